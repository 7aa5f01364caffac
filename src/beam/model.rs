//! Assembly, supports and the nondimensional scaling of the FE model.
//!
//! # Scaling (why and how)
//! In SI the rotation-DOF entries are ~le² ≈ 1e-19 times the translation
//! entries and normwise eigensolvers lose the low modes. We therefore work in
//! the dimensionless coordinate x̃ = x/L (so h̃ = 1/elements, ẽ = e0a/L), with the
//! DOFs (w [m], θ̃ = dw/dx̃) and the dimensionless time t̃ = ω_ref t,
//! ω_ref = √(EI/ρA)/L². Energies then read
//! ½EI∫w''² dx = (EI/L³)·½ qᵀK̃q,  ½ρA∫ẇ² dx = (EI/L³)·½ q̇ᵀM̃q̇ (dots in t̃), with
//! K̃ = Σ∫N''N''ᵀ dx̃, M̃ = Σ(∫NNᵀ + ẽ²∫N'N'ᵀ) dx̃ (A4, A6), and the extensions
//! k̃_r = k_r L/EI (rotational spring, ½k_rθ² = ½k_rθ̃²/L²) and μ̃ = m/(ρAL)
//! (point mass, ½mẇ² = (EI/L³)·½μ̃ (dw/dt̃)²). Viscous damping (A5): De = (C/ρA)Me,
//! so D̃ = c̃ M̃_beam with c̃ = C/(ρA ω_ref). The SI dynamic stiffness is
//! T(s) = (EI/L³)·T̃(s/ω_ref), poles are s = ω_ref·s̃ and eigenvalues λ = ω_ref²·λ̃.
//! The whole transformation is a congruence with a diagonal DOF scaling plus a
//! time scaling, so poles are unchanged up to the factor ω_ref.
//!
//! # Supports (DOF elimination)
//! Node i has DOFs (w: 2i, θ: 2i+1). Simply supported removes w₀, w_L; clamped–
//! clamped w₀, θ₀, w_L, θ_L; clamped–free w₀, θ₀; clamped–pinned w₀, θ₀, w_L.
//! Removing rows/columns keeps the half-bandwidth ≤ 3.
//! The rotational spring acts on every *remaining* rotation at a supported end
//! (both ends for simply supported, x = L for clamped–pinned); it is elastic
//! only (not multiplied by the relaxation factor 1 + ΣΔᵢ s/(s+Ωᵢ)).

use crate::beam::band::SymBand;
use crate::beam::element;
use crate::beam::spec::{BeamSpec, Support};
use crate::beam::BeamError;
use crate::error::InputError;

/// Unit assembled integrals of a uniform mesh (depend only on elements and support).
#[derive(Debug, Clone, PartialEq)]
pub struct UnitMesh {
    pub elements: usize,
    pub support: Support,
    /// Global DOF -> reduced DOF (None if eliminated by a support).
    pub dof_map: Vec<Option<usize>>,
    /// Σ∫N''N''ᵀ dx̃.
    pub k: SymBand,
    /// Σ∫NNᵀ dx̃.
    pub m0: SymBand,
    /// Σ∫N'N'ᵀ dx̃.
    pub m1: SymBand,
    /// Reduced indices of rotations carrying a support spring.
    pub spring_dofs: Vec<usize>,
    /// (weight, N, N', N'') at the 4 Gauss points of one element (uniform mesh).
    gauss: [(f64, [f64; 4], [f64; 4], [f64; 4]); 4],
    /// N''(0) and N''(h̃) of one element (w'' is linear on an element).
    curvature_ends: [[f64; 4]; 2],
}

const GX: [f64; 4] =
    [-0.861_136_311_594_052_6, -0.339_981_043_584_856_3, 0.339_981_043_584_856_3, 0.861_136_311_594_052_6];
const GW: [f64; 4] =
    [0.347_854_845_137_453_8, 0.652_145_154_862_546_1, 0.652_145_154_862_546_1, 0.347_854_845_137_453_8];

impl UnitMesh {
    pub fn new(elements: usize, support: Support) -> Self {
        let ndof = 2 * (elements + 1);
        let last = elements;
        let removed: Vec<usize> = match support {
            Support::SimplySupported => vec![0, 2 * last],
            Support::ClampedClamped => vec![0, 1, 2 * last, 2 * last + 1],
            Support::ClampedFree => vec![0, 1],
            Support::ClampedPinned => vec![0, 1, 2 * last],
        };
        let mut dof_map = vec![None; ndof];
        let mut next = 0;
        for (g, slot) in dof_map.iter_mut().enumerate() {
            if !removed.contains(&g) {
                *slot = Some(next);
                next += 1;
            }
        }
        let n = next;
        let h = 1.0 / elements as f64;
        let (ke, me, se) = (element::curvature_integral(h), element::mass_integral(h), element::slope_integral(h));
        let (mut k, mut m0, mut m1) = (SymBand::zeros(n), SymBand::zeros(n), SymBand::zeros(n));
        for e in 0..elements {
            for a in 0..4 {
                let Some(i) = dof_map[2 * e + a] else { continue };
                for b in 0..=a {
                    let Some(j) = dof_map[2 * e + b] else { continue };
                    k.add(i, j, ke[a][b]);
                    m0.add(i, j, me[a][b]);
                    m1.add(i, j, se[a][b]);
                }
            }
        }
        let spring_global: Vec<usize> = match support {
            Support::SimplySupported => vec![1, 2 * last + 1],
            Support::ClampedPinned => vec![2 * last + 1],
            Support::ClampedClamped | Support::ClampedFree => vec![],
        };
        let spring_dofs = spring_global.iter().filter_map(|&g| dof_map[g]).collect();
        let gauss = std::array::from_fn(|g| {
            let xl = 0.5 * h * (1.0 + GX[g]);
            (0.5 * h * GW[g], element::shape(h, xl), element::shape_d(h, xl), element::shape_dd(h, xl))
        });
        let curvature_ends = [element::shape_dd(h, 0.0), element::shape_dd(h, h)];
        Self { elements, support, dof_map, k, m0, m1, spring_dofs, gauss, curvature_ends }
    }

    pub fn n(&self) -> usize {
        self.k.n
    }

    /// (element, local x̃ within it) for x̃ ∈ [0, 1]; the last element owns x̃ = 1.
    fn locate(&self, xt: f64) -> (usize, f64) {
        let ne = self.elements;
        let e = ((xt * ne as f64).floor() as usize).min(ne - 1);
        (e, xt - e as f64 / ne as f64)
    }

    /// The bilinear (not Hermitian) energy forms of a DOF vector x, element by
    /// element with 4-point Gauss (exact to degree 7 ≥ 6):
    /// [∫(w'')², ∫w², ∫(w')²] over x̃ ∈ [0, 1], w = Nᵀx.
    /// Computing xᵀKx as Σ∫(w'')² instead of from the assembled K avoids the
    /// cancellation between entries of size 12/h̃³ that limits xᵀKx to
    /// ~eps·λ_max absolute accuracy; here only the ~1/(π²h̃²) cancellation
    /// inside w'' remains, so Rayleigh quotients are accurate to ~1e-14.
    pub fn energy_forms<T>(&self, x: &[T]) -> [T; 3]
    where
        T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        let mut out = [T::default(); 3];
        for e in 0..self.elements {
            let mut q = [T::default(); 4];
            for (a, qa) in q.iter_mut().enumerate() {
                if let Some(i) = self.dof_map[2 * e + a] {
                    *qa = x[i];
                }
            }
            for (wt, n, d, dd) in &self.gauss {
                let dot = |f: &[f64; 4]| q[0] * f[0] + q[1] * f[1] + q[2] * f[2] + q[3] * f[3];
                let (w, w1, w2) = (dot(n), dot(d), dot(dd));
                out[0] = out[0] + w2 * w2 * *wt;
                out[1] = out[1] + w * w * *wt;
                out[2] = out[2] + w1 * w1 * *wt;
            }
        }
        out
    }

    /// xᵀK̃x = ∫₀¹ (w'')² dx̃ element by element in closed form: w'' is linear
    /// on an element, so with a, b its end values ∫ (w'')² = h̃(a² + ab + b²)/3.
    /// Same accuracy argument as [`Self::energy_forms`] (no cancellation
    /// between assembled entries; a² + ab + b² ≥ (a² + b²)/2 has none either),
    /// at a tenth of its cost: this is the numerator of every Rayleigh quotient.
    pub fn stiffness_form(&self, x: &[f64]) -> f64 {
        let h = 1.0 / self.elements as f64;
        let [n0, n1] = &self.curvature_ends;
        let mut sum = 0.0;
        for e in 0..self.elements {
            let (mut a, mut b) = (0.0, 0.0);
            for k in 0..4 {
                if let Some(i) = self.dof_map[2 * e + k] {
                    a += n0[k] * x[i];
                    b += n1[k] * x[i];
                }
            }
            sum += a * a + a * b + b * b;
        }
        sum * h / 3.0
    }

    /// Interpolation vector N(x̃) in reduced DOFs (w = Nᵀq).
    pub fn shape_vector(&self, xt: f64) -> Vec<f64> {
        let h = 1.0 / self.elements as f64;
        let (e, xl) = self.locate(xt);
        let n = element::shape(h, xl);
        let mut v = vec![0.0; self.n()];
        for a in 0..4 {
            if let Some(i) = self.dof_map[2 * e + a] {
                v[i] += n[a];
            }
        }
        v
    }

    /// Nodal load of a unit point force at x̃ (A7): N(x̃₀) − ẽ²N''(x̃₀). N'' jumps
    /// at nodes; at an interior node the two adjacent elements each take half of
    /// the δ (the symmetric choice; it is the limit of averaging x̃₀ → node±).
    pub fn load_vector(&self, xt: f64, e_tilde: f64) -> Vec<f64> {
        let ne = self.elements;
        let h = 1.0 / ne as f64;
        let mut v = vec![0.0; self.n()];
        let scaled = xt * ne as f64;
        let node = scaled.round();
        let at_interior_node = (scaled - node).abs() <= 1e-12 * ne as f64 && node > 0.0 && node < ne as f64;
        let parts: Vec<(usize, f64, f64)> = if at_interior_node {
            let k = node as usize;
            vec![(k - 1, h, 0.5), (k, 0.0, 0.5)]
        } else {
            let (e, xl) = self.locate(xt);
            vec![(e, xl, 1.0)]
        };
        for (e, xl, w) in parts {
            let p = element::point_load(h, xl, e_tilde);
            for a in 0..4 {
                if let Some(i) = self.dof_map[2 * e + a] {
                    v[i] += w * p[a];
                }
            }
        }
        v
    }
}

/// What the undamped relaxed pencil (K̃ + K̃_spring, M̃) depends on, for a
/// given mesh: not E, ρ, d, C, Δ, Ω (they only scale time and enter the
/// family polynomials).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PencilParams {
    /// ẽ = e0a/L.
    pub e_tilde: f64,
    /// (μ̃, x̃) of the point mass, if any.
    pub point_mass: Option<(f64, f64)>,
    /// k̃_r on the spring DOFs (0 = none).
    pub spring: f64,
}

/// Grid of [`PencilParams::snapped`]: steps in ẽ², ln μ̃, x̃ and ln k̃_r.
/// Measured on a simply supported 20-element mesh at cell corners (half a
/// step off in every coordinate), the sine of the angle between the grid's
/// and the pencil's eigenvectors (modes 1–6) is ≤ 4e-3 for ẽ and the spring,
/// and ≤ 0.11 for a point mass of a third of the beam's mass: RQI converges
/// cubically from there in 2–4 steps, and a start that slides to a
/// neighbouring eigenpair fails the inertia certification and is re-solved
/// from scratch. Coarse enough that a TMCMC population of a 2-parameter
/// pencil class fits in the cache (`GRID_CACHE`) once it leaves the prior.
const GRID_E2: f64 = 1e-3;
const GRID_LN: f64 = 0.25;
const GRID_X: f64 = 0.05;

impl PencilParams {
    /// Bitwise identity.
    pub fn bits(&self) -> [u64; 4] {
        let (mu, x) = self.point_mass.unwrap_or((0.0, 0.0));
        [self.e_tilde.to_bits(), mu.to_bits(), x.to_bits(), self.spring.to_bits()]
    }

    /// The nearest grid point: a pencil whose eigenpairs serve as RQI starts
    /// for every pencil in its cell. A function of `self` alone, so a solve
    /// that starts from it is a pure function of its input (bitwise
    /// reproducible whatever else the solver has seen).
    pub fn snapped(&self) -> Self {
        let ln_snap = |v: f64| ((v.ln() / GRID_LN).round() * GRID_LN).exp();
        let e2 = (self.e_tilde * self.e_tilde / GRID_E2).round() * GRID_E2;
        PencilParams {
            e_tilde: e2.sqrt(),
            point_mass: self.point_mass.map(|(mu, x)| (ln_snap(mu), ((x / GRID_X).round() * GRID_X).clamp(0.0, 1.0))),
            spring: if self.spring > 0.0 { ln_snap(self.spring) } else { 0.0 },
        }
    }
}

impl UnitMesh {
    /// (K̃ + K̃_spring, M̃) for these parameters.
    pub fn pencil(&self, p: &PencilParams) -> (SymBand, SymBand) {
        let mut k = self.k.clone();
        if p.spring > 0.0 {
            for &i in &self.spring_dofs {
                k.add(i, i, p.spring);
            }
        }
        let mut m = self.m0.plus_scaled(p.e_tilde * p.e_tilde, &self.m1);
        if let Some((mu, x)) = p.point_mass {
            add_point_mass(&mut m, mu, &self.shape_vector(x));
        }
        (k, m)
    }

    /// xᵀ(K̃ + K̃_spring)x with the beam part from [`Self::stiffness_form`]:
    /// the numerator of the pencil's Rayleigh quotients (the denominator
    /// xᵀM̃x has no such cancellation: M̃ ≻ 0 with a modest condition number).
    pub fn pencil_stiffness(&self, spring: f64, x: &[f64]) -> f64 {
        let ks: f64 = if spring > 0.0 { self.spring_dofs.iter().map(|&i| spring * x[i] * x[i]).sum() } else { 0.0 };
        self.stiffness_form(x) + ks
    }
}

/// M̃ += μ̃ N Nᵀ (a point mass with interpolation vector N).
fn add_point_mass(m: &mut SymBand, mu: f64, nv: &[f64]) {
    let nz: Vec<usize> = (0..nv.len()).filter(|&i| nv[i] != 0.0).collect();
    for &i in &nz {
        for &j in &nz {
            if j <= i {
                m.add(i, j, mu * nv[i] * nv[j]);
            }
        }
    }
}

/// The scaled model of one beam: everything the pole and FRF solvers need.
#[derive(Debug, Clone)]
pub struct ScaledModel<'a> {
    pub mesh: &'a UnitMesh,
    /// K̃ (beam, relaxed).
    pub k: &'a SymBand,
    /// Point mass μ̃ and N(x̃₀) (reduced DOFs).
    pub point_mass: Option<(f64, Vec<f64>)>,
    /// M̃ including the point mass.
    pub m: SymBand,
    /// M̃ of the beam alone (the viscous damping is c̃ times this).
    pub m_beam: SymBand,
    /// k̃_r on each spring DOF (0 = no spring).
    pub spring: f64,
    pub spring_dofs: Vec<usize>,
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

impl<'a> ScaledModel<'a> {
    pub fn new(beam: &BeamSpec, mesh: &'a UnitMesh) -> Self {
        let l = beam.length_nm * 1e-9;
        let ei = beam.youngs_modulus_pa * beam.inertia_m4();
        let rho_a = beam.density_kg_m3 * beam.area_m2();
        let omega_ref = (ei / rho_a).sqrt() / (l * l);
        let e_tilde = beam.nonlocal_e0a_nm / beam.length_nm;
        let m_beam = mesh.m0.plus_scaled(e_tilde * e_tilde, &mesh.m1);
        let mut m = m_beam.clone();
        let mut point_mass = None;
        if let Some(pm) = &beam.point_mass {
            let mu = pm.mass_kg / (rho_a * l);
            let nv = mesh.shape_vector(pm.x_nm / beam.length_nm);
            add_point_mass(&mut m, mu, &nv);
            point_mass = Some((mu, nv));
        }
        let spring = beam.support_rotational_stiffness_n_m_rad * l / ei;
        let ivs_all: Vec<(f64, f64)> =
            beam.internal_variables.iter().map(|iv| (iv.delta, iv.omega_rad_s / omega_ref)).collect();
        Self {
            mesh,
            k: &mesh.k,
            point_mass,
            m,
            m_beam,
            spring,
            spring_dofs: mesh.spring_dofs.clone(),
            c: beam.viscous_damping_n_s_m2 / (rho_a * omega_ref),
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
            spring: if self.has_spring() { self.spring } else { 0.0 },
        }
    }

    pub fn has_spring(&self) -> bool {
        self.spring > 0.0 && !self.spring_dofs.is_empty()
    }

    /// True when the pencil decouples exactly (proof in `modal.rs`): no spring,
    /// and no point mass unless C = 0.
    pub fn decouples(&self) -> bool {
        !self.has_spring() && (!self.has_point_mass || self.c == 0.0)
    }

    /// K̃ + K̃_spring (the elastic stiffness of the undamped, relaxed pencil).
    pub fn k_total(&self) -> SymBand {
        let mut k = self.k.clone();
        if self.has_spring() {
            for &i in &self.spring_dofs {
                k.add(i, i, self.spring);
            }
        }
        k
    }

    /// Bilinear forms of x: (xᵀK̃x, xᵀM̃x, xᵀM̃_beam x, xᵀK̃_spring x), the
    /// first three from element energies (see [`UnitMesh::energy_forms`]).
    pub fn forms<T>(&self, x: &[T]) -> (T, T, T, T)
    where
        T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        let [k, m0, m1] = self.mesh.energy_forms(x);
        let mb = m0 + m1 * (self.e_tilde * self.e_tilde);
        let mut m = mb;
        if let Some((mu, nv)) = &self.point_mass {
            let mut w = T::default();
            for (a, b) in nv.iter().zip(x) {
                if *a != 0.0 {
                    w = w + *b * *a;
                }
            }
            m = m + w * w * *mu;
        }
        let mut ks = T::default();
        if self.has_spring() {
            for &i in &self.spring_dofs {
                ks = ks + x[i] * x[i] * self.spring;
            }
        }
        (k, m, mb, ks)
    }

    /// Relaxation factor G(s̃) = 1 + Σ Δᵢ s̃/(s̃ + Ω̃ᵢ) (Laplace transform of eq. 8
    /// times s, eq. 9) and its derivative Σ Δᵢ Ω̃ᵢ/(s̃ + Ω̃ᵢ)².
    pub fn relaxation(&self, s: num_complex::Complex64) -> (num_complex::Complex64, num_complex::Complex64) {
        let mut g = num_complex::Complex64::new(1.0, 0.0);
        let mut dg = num_complex::Complex64::new(0.0, 0.0);
        for &(d, w) in &self.ivs {
            let den = s + w;
            g += d * s / den;
            dg += d * w / (den * den);
        }
        (g, dg)
    }
}

/// Checks a position along the beam (nm) against [0, L].
pub fn check_position(field: &str, x_nm: f64, length_nm: f64) -> Result<f64, BeamError> {
    if x_nm.is_finite() && (0.0..=length_nm).contains(&x_nm) {
        Ok(x_nm / length_nm)
    } else {
        Err(InputError::new(field, x_nm, format!("0 <= x <= length_nm = {length_nm}")).into())
    }
}
