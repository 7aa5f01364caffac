//! The scaled model of one beam: the scalars of the nondimensional scaling
//! (`model`'s module doc) and the matrices every pole and FRF solver reads.
//!
//! # The Winkler foundation
//! A foundation of modulus k (N/m²) loads the beam with the reaction
//! p = −k w per length. Eringen's differential law, (1 − μ∂ₓ²)σ = E ε with
//! μ = (e0a)², turns the equilibrium M″ = ρA ẅ + C ẇ − p into the nonlocal
//! beam equation
//!   EI w⁗ + (1 − μ∂ₓ²)(ρA ẅ + C ẇ + k w) = 0
//! (Eringen's operator acts on every distributed transverse load, the
//! reaction as the inertia and the damping). Its weak form adds to the
//! stiffness k·(∫w v dx + μ∫w′v′ dx): k times the translational nonlocal
//! mass form, i.e. k̃_f·M̃_beam with k̃_f = kL⁴/EI in the scaled units
//! (M̃_beam is ρA's form divided by ρA L). The foundation is elastic: it is
//! not multiplied by the relaxation factor G(s). Where M̃_beam = M̃ (no point
//! mass, no rotary inertia) and D̃ ∝ M̃, every family of `modal.rs` becomes
//! s² + c̃s + k̃_f + λG(s) = 0, so the undamped elastic beam has
//! ω² = ω₀² + k/ρA for every mode and support. Simply supported, continuum:
//! ω² = (EI α⁴/(1 + μα²) + k)/ρA, α = rπ/L (tested in
//! `tests/beam_foundation.rs`). A Pasternak shear layer G_p adds −G_p w″,
//! whose form is that of a tension N = G_p: the axial force carries it.
//!
//! # The strain gradient
//! Nonlocal strain-gradient elasticity (Lim, Zhang & Reddy, "A higher-order
//! nonlocal elasticity and strain gradient theory and its applications in
//! wave propagation", J. Mech. Phys. Solids 78 (2015) 298–313) adds to
//! Eringen's law a gradient of the strain with a material length l:
//! (1 − μ∂ₓ²)σ = E(1 − l²∂ₓ²)ε. The bending moment of the Euler–Bernoulli
//! beam follows, (1 − μ∂ₓ²)M = −EI(w″ − l²w⁗), and with M″ = ρA ẅ + C ẇ − p
//! the beam equation is of sixth order:
//!   EI(w⁗ − l²w⁽⁶⁾) + (1 − μ∂ₓ²)(ρA ẅ + C ẇ + k w) = 0.
//! Its weak form adds EI l²∫w‴v‴ dx to the stiffness: K̃ = K̃₂ + l̃²K̃₃ with
//! l̃ = l/L and K̃₃ = Σ∫N‴N‴ᵀ dx̃ in the scaled units. The energy needs w‴ in
//! L², i.e. C²-continuous elements: the quintic Hermite element with
//! (w, w′, w″) per node (`model::GradientMesh`). The internal variables relax
//! the modulus, E → E·G(s), and l is a length of the same material, so G(s)
//! multiplies the whole K̃ (both terms): D̃ ∝ M̃ and the one K̃ of the
//! families are kept, and every family of `modal.rs` stays exact with λ the
//! eigenvalues of (K̃₂ + l̃²K̃₃, M̃). The axial force and the foundation are
//! external loads, untouched by l.
//!
//! Boundary conditions. Integrating the stiffness by parts leaves, at each
//! end, v·(shear force), v′·EI(w″ − l²w⁗) and v″·EI l²w‴: each end needs one
//! of (w or the force), (w′ or EI(w″ − l²w⁗)), (w″ or l²w‴). The literature
//! differs on the third pair; taken here:
//! - pinned end (simply supported, the pinned end of clamped–pinned):
//!   w = 0 and w″ = 0 essential (w″ a nodal DOF, removed); the natural
//!   condition on v′ then gives w⁗ = 0. The set w = w″ = w⁗ = 0 is the one
//!   under which the sine modes are exact, so the simply supported beam has
//!   the closed form of the NSGT literature,
//!   ω² = EI q⁴(1 + l²q²)/(ρA(1 + (e0a)²q²)), q = rπ/L
//!   (Lim et al.'s dispersion relation at the wavenumbers the supports
//!   admit; tested in `tests/beam_strain_gradient.rs`).
//! - pinned end with a rotational spring k_r: w = 0 essential, w″ free, so
//!   the natural conditions EI(w″ − l²w⁗) = ±k_r w′ (the spring's moment)
//!   and l²EI w‴ = 0 hold. Keeping w″ = 0 there would leave the spring's
//!   moment to the higher-order term alone and, as l → 0, put a boundary
//!   layer of width ~l where the classical beam has EI w″ = ±k_r w′: the C²
//!   mesh then missed the classical spring beam by O(h) (measured, SS,
//!   k_r L/EI = 10, l = 1e-5 nm: 1.1 %, 0.56 %, 0.28 % in ω₁ on 10, 20,
//!   40 elements), so a strain gradient with a spring did not contain the
//!   spring alone. With w″ free the l → 0 limit is the classical spring
//!   condition (tested); the price is that the pinned end's condition jumps
//!   between k_r = 0 (w″ = 0) and k_r > 0 (w″ free) at a given l.
//! - clamped end: w = w′ = 0 essential, w″ free, so the natural condition
//!   l²EI w‴ = 0 (no higher-order moment) holds. A clamp constrains
//!   deflection and rotation; also fixing w″ = 0 would make the support hold
//!   the curvature (a "higher-order clamp" no experiment controls) and put a
//!   boundary layer of width ~l into w″ at the end. The natural condition is
//!   the variationally consistent one and needs nothing of the support
//!   beyond a classical clamp; as l → 0 the classical clamp is recovered.
//! - free end: all three natural.
//!
//! Shear deformation with a strain gradient is refused (`BeamSpec::validate`):
//! a Timoshenko strain-gradient beam carries gradients of both the bending
//! and the shear strain (a second length and other higher-order conditions),
//! a different theory from the one implemented here.

use std::borrow::Cow;

use crate::beam::fe::model::{add_point_mass, shear_params, PencilParams, UnitMesh};
use crate::beam::linalg::band::SymBand;
use crate::beam::spec::BeamSpec;

/// The scaled model of one beam: everything the pole and FRF solvers need.
#[derive(Debug, Clone)]
pub struct ScaledModel<'a> {
    pub mesh: &'a UnitMesh,
    /// K̃ (beam, relaxed).
    /// (The mesh's own matrix for Euler–Bernoulli; K̃ = k + g̃·ks for Timoshenko.)
    pub k: Cow<'a, SymBand>,
    /// g̃ = κGAL²/EI (0 for Euler–Bernoulli).
    pub shear: f64,
    /// l̃² = (l/L)², the strain gradient (0 = none; K̃ = k + l̃²·k3 on the C²
    /// mesh, module doc).
    pub gradient: f64,
    /// Point mass μ̃ and N(x̃₀) (reduced DOFs).
    pub point_mass: Option<(f64, Vec<f64>)>,
    /// M̃ including the point mass.
    pub m: SymBand,
    /// The damping shape: the viscous damping matrix is c̃ times this. It is
    /// the translational nonlocal mass of the beam (A5): M̃ of the beam alone
    /// for Euler–Bernoulli, without the rotary inertia for Timoshenko.
    pub m_beam: SymBand,
    /// K̃_N = ñ(G̃₀ + ẽ²G̃₁), the axial-force stiffness (elastic, not relaxed).
    pub k_axial: Option<SymBand>,
    /// ñ = NL²/EI.
    pub axial: f64,
    /// k̃_f = kL⁴/EI, the Winkler foundation (elastic, not relaxed); its
    /// stiffness matrix is k̃_f·M̃_beam (module doc).
    pub foundation: f64,
    /// The hysteretic loss factor η: the relaxed stiffness is G(s)·(1 + iη)·K̃
    /// in the upper half plane ([`Self::relaxation`]).
    pub loss: f64,
    /// True for a Timoshenko beam (rotary inertia: D̃ ∝ M̃ only if c̃ = 0).
    pub has_rotary: bool,
    /// k̃_r at x = 0 and at x = L (0 = no spring; a value on an end whose
    /// rotation the support fixes acts on nothing: `spring_dofs`).
    pub spring: [f64; 2],
    pub spring_dofs: [Option<usize>; 2],
    pub c: f64,
    /// Active internal variables (Δᵢ > 0) as (Δᵢ, Ω̃ᵢ).
    pub ivs: Vec<(f64, f64)>,
    /// All internal variables, including Δᵢ = 0 (state-space dimension).
    pub ivs_all: Vec<(f64, f64)>,
    pub has_point_mass: bool,
    /// x̃ of the point mass (0 without one).
    pub point_mass_x: f64,
    pub omega_ref: f64,
    /// L³/(EI) in m/N: converts T̃⁻¹ to SI receptance.
    pub compliance: f64,
    pub e_tilde: f64,
}

/// G(s) = 1 + Σ Δᵢ s/(s + Ωᵢ) and G′(s) = Σ Δᵢ Ωᵢ/(s + Ωᵢ)² of the internal
/// variables `ivs` = (Δᵢ, Ωᵢ) (any consistent units of s and Ωᵢ): what
/// [`ScaledModel::relaxation`] and the families' loss-factor continuation
/// (`solve::family`) evaluate.
pub fn relaxation_factor(
    s: num_complex::Complex64,
    ivs: &[(f64, f64)],
) -> (num_complex::Complex64, num_complex::Complex64) {
    let mut g = num_complex::Complex64::new(1.0, 0.0);
    let mut dg = num_complex::Complex64::new(0.0, 0.0);
    for &(d, w) in ivs {
        let den = s + w;
        g += d * s / den;
        dg += d * w / (den * den);
    }
    (g, dg)
}

/// The scalars of the nondimensional scaling (module doc), without any matrix:
/// what [`ScaledModel::new`] and the interpolated fast path of `modal.rs` share.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scaling {
    /// L in m.
    pub l: f64,
    pub ei: f64,
    pub rho_a: f64,
    /// ω_ref = √(EI/ρA)/L².
    pub omega_ref: f64,
    /// ẽ = e0a/L.
    pub e_tilde: f64,
    /// c̃ = C/(ρA ω_ref).
    pub c: f64,
    /// k̃_r = k_r L/EI at x = 0 and at x = L.
    pub spring: [f64; 2],
    /// ñ = NL²/EI.
    pub axial: f64,
    /// k̃_f = kL⁴/EI.
    pub foundation: f64,
    /// l̃² = (l/L)², the strain-gradient length scale (0 = none).
    pub gradient: f64,
}

impl Scaling {
    pub fn new(beam: &BeamSpec) -> Self {
        let l = beam.length_nm * 1e-9;
        let ei = beam.youngs_modulus_pa * beam.inertia_m4();
        let rho_a = beam.density_kg_m3 * beam.area_m2();
        let omega_ref = (ei / rho_a).sqrt() / (l * l);
        Scaling {
            l,
            ei,
            rho_a,
            omega_ref,
            e_tilde: beam.nonlocal_e0a_nm / beam.length_nm,
            c: beam.viscous_damping_n_s_m2 / (rho_a * omega_ref),
            spring: beam.support_rotational_stiffness_at_ends_n_m_rad().map(|k| k * l / ei),
            axial: beam.axial_force_n * l * l / ei,
            foundation: beam.elastic_foundation_n_m2 * l * l * l * l / ei,
            gradient: {
                let lt = beam.strain_gradient_length_nm / beam.length_nm;
                lt * lt
            },
        }
    }
}

impl<'a> ScaledModel<'a> {
    pub fn new(beam: &BeamSpec, mesh: &'a UnitMesh) -> Self {
        let Scaling { l, ei, rho_a, omega_ref, e_tilde, c, spring, axial, foundation, gradient } = Scaling::new(beam);
        // l̃² acts only on the C² mesh `UnitMesh::for_beam` builds for it
        let gradient = if mesh.gradient.is_some() { gradient } else { 0.0 };
        let shear = shear_params(beam).map_or(0.0, |(g, _)| g);
        let m_all = mesh.m0.plus_scaled(e_tilde * e_tilde, &mesh.m1);
        let m_beam = match &mesh.shear {
            Some(sh) => sh.mt0.plus_scaled(e_tilde * e_tilde, &sh.mt1),
            None => m_all.clone(),
        };
        let mut m = m_all;
        let k_axial = (axial != 0.0).then(|| mesh.geometric(axial, e_tilde));
        let mut point_mass = None;
        if let Some(pm) = &beam.point_mass {
            let mu = pm.mass_kg / (rho_a * l);
            let nv = mesh.shape_vector(pm.x_nm / beam.length_nm);
            add_point_mass(&mut m, mu, &nv);
            point_mass = Some((mu, nv));
        }
        let ivs_all: Vec<(f64, f64)> =
            beam.internal_variables.iter().map(|iv| (iv.delta, iv.omega_rad_s / omega_ref)).collect();
        Self {
            mesh,
            k: match (&mesh.shear, &mesh.gradient) {
                (Some(_), _) => Cow::Owned(mesh.stiffness(shear)),
                (None, Some(gm)) => Cow::Owned(mesh.k.plus_scaled(gradient, &gm.k3)),
                (None, None) => Cow::Borrowed(&mesh.k),
            },
            shear,
            gradient,
            point_mass,
            m,
            m_beam,
            k_axial,
            axial,
            foundation,
            loss: beam.loss_factor,
            has_rotary: mesh.shear.is_some(),
            spring,
            spring_dofs: mesh.spring_dofs,
            c,
            ivs: ivs_all.iter().copied().filter(|&(d, _)| d > 0.0).collect(),
            ivs_all,
            has_point_mass: beam.point_mass.is_some(),
            point_mass_x: beam.point_mass.as_ref().map_or(0.0, |p| p.x_nm / beam.length_nm),
            omega_ref,
            compliance: l * l * l / ei,
            e_tilde,
        }
    }

    pub fn n(&self) -> usize {
        self.k.n
    }

    /// The parameters of this model's undamped relaxed pencil.
    pub fn pencil_params(&self) -> PencilParams {
        PencilParams {
            e_tilde: self.e_tilde,
            point_mass: self.point_mass.as_ref().map(|(mu, _)| (*mu, self.point_mass_x)),
            spring: std::array::from_fn(|e| if self.spring_dofs[e].is_some() { self.spring[e] } else { 0.0 }),
            axial: self.axial,
            shear: self.shear,
            gradient: self.gradient,
        }
    }

    pub fn has_spring(&self) -> bool {
        self.springs().next().is_some()
    }

    /// (reduced DOF, k̃_r) of each support spring that acts ([`UnitMesh::springs`]).
    pub fn springs(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.spring_dofs.iter().zip(&self.spring).filter_map(|(d, &k)| d.filter(|_| k > 0.0).map(|i| (i, k)))
    }

    /// k̃_r on reduced DOF `i` (0 where no spring acts).
    pub fn spring_at(&self, i: usize) -> f64 {
        self.springs().find(|&(d, _)| d == i).map_or(0.0, |(_, k)| k)
    }

    /// True when the pencil decouples exactly (proof in `modal.rs`): no spring,
    /// no axial force (both are elastic stiffness not ∝ the relaxed K̃), and
    /// D̃ ∝ M̃: no point mass and no rotary inertia unless C = 0; a foundation
    /// only where M̃_beam = M̃ (no point mass, no rotary inertia): then its
    /// k̃_f M̃_beam = k̃_f M̃ adds k̃_f to every family's constant term.
    pub fn decouples(&self) -> bool {
        let mass_is_beam = !(self.has_point_mass || self.has_rotary);
        !self.has_spring()
            && self.k_axial.is_none()
            && (mass_is_beam || self.c == 0.0)
            && (mass_is_beam || self.foundation == 0.0)
    }

    /// K̃ + K̃_spring + K̃_N: the stiffness of the pencil whose eigenpairs the
    /// cache keys on [`PencilParams`] (the foundation is left out: it is not
    /// among those parameters; [`Self::forms`] and [`Self::unrelaxed_entry`]
    /// carry it).
    pub fn k_total(&self) -> SymBand {
        let mut k = self.k.as_ref().clone();
        for (i, ks) in self.springs() {
            k.add(i, i, ks);
        }
        if let Some(ka) = &self.k_axial {
            k = k.plus_scaled(1.0, ka);
        }
        k
    }

    /// The entry (i, j) of the unrelaxed elastic stiffness K̃_spring + K̃_N + k̃_f M̃_beam.
    pub fn unrelaxed_entry(&self, i: usize, j: usize) -> f64 {
        let ks = if i == j { self.spring_at(i) } else { 0.0 };
        let kf = if self.foundation != 0.0 { self.foundation * self.m_beam.get(i, j) } else { 0.0 };
        ks + self.k_axial.as_ref().map_or(0.0, |ka| ka.get(i, j)) + kf
    }

    /// Bilinear forms of x: (xᵀK̃x, xᵀM̃x, xᵀM̃_beam x, xᵀ(K̃_spring + K̃_N + k̃_f M̃_beam)x),
    /// the first three (and the axial and foundation parts of the last) from
    /// element energies (see [`UnitMesh::energy_forms`]).
    pub fn forms<T>(&self, x: &[T]) -> (T, T, T, T)
    where
        T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        let e2 = self.e_tilde * self.e_tilde;
        let (mut k, mut m, mb, k_n) = if self.mesh.shear.is_none() && self.k_axial.is_none() {
            let [k, m0, m1] = self.mesh.energy_forms(x);
            let mb = m0 + m1 * e2;
            (k, mb, mb, T::default())
        } else {
            let [k, m0, m1, mt0, mt1, g0, g1] = self.mesh.energy_forms_ext(x, self.shear);
            (k, m0 + m1 * e2, mt0 + mt1 * e2, (g0 + g1 * e2) * self.axial)
        };
        if self.gradient != 0.0 {
            k = k + self.mesh.gradient_form(x) * self.gradient;
        }
        if let Some((mu, nv)) = &self.point_mass {
            let mut w = T::default();
            for (a, b) in nv.iter().zip(x) {
                if *a != 0.0 {
                    w = w + *b * *a;
                }
            }
            m = m + w * w * *mu;
        }
        let mut ks = k_n + mb * self.foundation;
        for (i, k) in self.springs() {
            ks = ks + x[i] * x[i] * k;
        }
        (k, m, mb, ks)
    }

    /// Relaxation factor G(s̃) = 1 + Σ Δᵢ s̃/(s̃ + Ω̃ᵢ) (Laplace transform of eq. 8
    /// times s, eq. 9) and its derivative Σ Δᵢ Ω̃ᵢ/(s̃ + Ω̃ᵢ)², both times
    /// (1 + iη) with a loss factor η: the hysteretic modulus of positive
    /// frequencies, valid in the upper half plane where the oscillatory poles
    /// are taken (their conjugates are the negative frequencies').
    pub fn relaxation(&self, s: num_complex::Complex64) -> (num_complex::Complex64, num_complex::Complex64) {
        let (g, dg) = relaxation_factor(s, &self.ivs);
        if self.loss != 0.0 {
            let h = num_complex::Complex64::new(1.0, self.loss);
            return (g * h, dg * h);
        }
        (g, dg)
    }
}
