//! Assembly, supports and the nondimensional scaling of the FE model.
//!
//! # Scaling (why and how)
//! In SI the rotation-DOF entries are ~le² ≈ 1e-19 times the translation
//! entries and normwise eigensolvers lose the low modes. We therefore work in
//! the dimensionless coordinate x̃ = x/L (so h̃ = 1/elements, ẽ = e0a/L), with the
//! DOFs (w in m, θ̃ = dw/dx̃) and the dimensionless time t̃ = ω_ref t,
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
//! The rotational springs act on the *remaining* rotation at a supported end
//! (both ends for simply supported, x = L for clamped–pinned), each end its
//! own stiffness (`BeamSpec::support_rotational_stiffness_at_ends_n_m_rad`);
//! they are elastic only (not multiplied by the relaxation factor
//! 1 + ΣΔᵢ s/(s+Ωᵢ)).

use crate::beam::error::BeamError;
use crate::beam::fe::element;
use crate::beam::linalg::band::SymBand;
use crate::beam::spec::{BeamSpec, Support};
use crate::error::InputError;

/// At which ends (x = 0, x = L) of `beam` a rotational spring acts on a
/// rotation the support leaves free (what the C² mesh's pinned ends depend on).
fn sprung_ends(beam: &BeamSpec) -> [bool; 2] {
    let free = spring_rotations(beam.support, 0, 1);
    let k = beam.support_rotational_stiffness_at_ends_n_m_rad();
    [free[0].is_some() && k[0] > 0.0, free[1].is_some() && k[1] > 0.0]
}

/// (weight, N, N′, N″) at one Gauss point of an Euler–Bernoulli element.
type GaussPoint = (f64, [f64; 4], [f64; 4], [f64; 4]);

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
    /// Reduced index of the rotation a support leaves free at x = 0 and at
    /// x = L (where a support spring acts), `None` where the support fixes
    /// it (clamped) or there is no support (free end).
    pub spring_dofs: [Option<usize>; 2],
    /// Σ∫N_w′N_w′ᵀ dx̃ and Σ∫N_w″N_w″ᵀ dx̃: the axial-force (geometric) stiffness
    /// K̃_N = ñ(G̃₀ + ẽ²G̃₁) (for Euler–Bernoulli these are `m1` and `k`).
    pub g0: SymBand,
    pub g1: SymBand,
    /// Timoshenko data (shear deformation and rotary inertia); `None` = Euler–Bernoulli.
    pub shear: Option<ShearMesh>,
    /// The C² Euler–Bernoulli mesh of a strain-gradient beam (l > 0); `None`
    /// = the cubic Hermite mesh (or Timoshenko). Exclusive with `shear`.
    pub gradient: Option<GradientMesh>,
    /// (weight, N, N', N'') at the 4 Gauss points of one element (uniform mesh).
    gauss: [GaussPoint; 4],
    /// N''(0) and N''(h̃) of one element (w'' is linear on an element).
    curvature_ends: [[f64; 4]; 2],
}

const GX: [f64; 4] =
    [-0.861_136_311_594_052_6, -0.339_981_043_584_856_3, 0.339_981_043_584_856_3, 0.861_136_311_594_052_6];
const GW: [f64; 4] =
    [0.347_854_845_137_453_8, 0.652_145_154_862_546_1, 0.652_145_154_862_546_1, 0.347_854_845_137_453_8];

/// The cubic element's data at the [`GX`] Gauss points of an element of
/// length `h`: weight, and the shape functions with their first and second
/// derivatives (the C¹ mesh's, which the C² mesh carries too).
fn cubic_gauss(h: f64) -> [GaussPoint; 4] {
    std::array::from_fn(|g| {
        let xl = 0.5 * h * (1.0 + GX[g]);
        (0.5 * h * GW[g], element::shape(h, xl), element::shape_d(h, xl), element::shape_dd(h, xl))
    })
}

/// The Timoshenko part of a [`UnitMesh`] (`element::timoshenko_point`: the
/// bending–shear split element with a quintic Hermite bending part and a
/// cubic Hermite shear part; five DOFs per node (w, θ, χ, s, γ), half-bandwidth
/// 9; frequencies converge at O(h⁸) in bending, O(h⁶) in the shear part,
/// measured in `tests/beam_axial_shear.rs`). The mesh's `k`, `m0`, `m1` are
/// k = Σ∫θ′θ′ᵀ (bending only), m0 = Σ∫(wwᵀ + r̃²θθᵀ), m1 = Σ∫(w′w′ᵀ + r̃²θ′θ′ᵀ);
/// the beam's stiffness is K̃ = k + g̃·`ks`, ks = Σ∫γγᵀ, with the shear
/// stiffness g̃ a pencil parameter ([`PencilParams::shear`]), not part of the
/// mesh: a calibration or a diagnosis that moves κ then keeps the mesh and
/// its eigenpair caches (each new g̃ used to cost a new mesh and scratch
/// eigensolves, ~2.3× a fixed-κ chain step). The external viscous damping
/// acts on the translational part only.
/// Supports: w = 0 at a supported end, θ = 0 at a clamped one (section
/// rotation); the curvature χ = θ′ is never constrained (EIθ′ = 0 at a
/// pinned or free end is the natural moment condition; at a clamped end the
/// moment is free); s₀ = 0 fixes the split's gauge (a uniform shift of w_s
/// against w_b changes neither w nor θ nor γ).
#[derive(Debug, Clone, PartialEq)]
pub struct ShearMesh {
    /// r̃² = I/(AL²) (rotary inertia relative to ρAL).
    pub r2: f64,
    /// Σ∫γγᵀ: the shear stiffness per unit g̃.
    pub ks: SymBand,
    /// Σ∫wwᵀ and Σ∫w′w′ᵀ (translational mass: the damping shape).
    pub mt0: SymBand,
    pub mt1: SymBand,
    /// (weight, fields) at the 6 Gauss points of one element (exact for the
    /// degree-≤ 10 products of its fields).
    gauss: [(f64, element::TimoshenkoPoint); 6],
}

/// The C² part of a [`UnitMesh`] for a strain-gradient beam
/// (`element::gradient_element`: quintic Hermite, DOFs (w, θ = w′, χ = w″) per
/// node, half-bandwidth 5). The mesh's `k`, `m0`, `m1`, `g0`, `g1` are the
/// Euler–Bernoulli ones, ∫w″², ∫w², ∫w′², ∫w′², ∫w″², on this space; the
/// beam's stiffness is K̃ = k + l̃²·`k3`, k3 = Σ∫w‴w‴ᵀ, with l̃² = (l/L)² a
/// pencil parameter ([`PencilParams::gradient`]), not part of the mesh (so a
/// calibration or diagnosis that moves l keeps the mesh and its caches).
/// Supports (the higher-order conditions of `fe::scaling`'s module doc):
/// w = 0 at a supported end, θ = 0 at a clamped one, χ = 0 at a pinned one
/// without a rotational spring (simply supported, the pinned end of
/// clamped–pinned); χ is free at a clamped or free end and at a pinned end
/// with a spring (there the natural condition l²EI w‴ = 0 holds).
/// Rayleigh–Ritz: the l² energy is an H³ seminorm, quintic elements
/// approximate a smooth mode's w‴ to O(h³), so eigenvalues converge at
/// O(h⁶) (O(h⁸) as l → 0, the H² part), measured in
/// `tests/beam_strain_gradient.rs`.
#[derive(Debug, Clone, PartialEq)]
pub struct GradientMesh {
    /// Σ∫N‴N‴ᵀ dx̃: the strain-gradient stiffness per unit l̃².
    pub k3: SymBand,
    /// (weight, [N, N′, N″, N‴]) at the 6 Gauss points of one element (exact
    /// for the degree-≤ 10 products of its fields).
    gauss: [(f64, [[f64; GRADIENT_DOFS]; 4]); 6],
    /// Whether a rotational spring acts at x = 0 and at x = L (a pinned end
    /// with a spring keeps w″ free: `fe::scaling`'s module doc).
    pub sprung: [bool; 2],
}

/// DOFs per node and per element of the C² mesh.
const GRADIENT_DPN: usize = element::GRADIENT_DPN;
const GRADIENT_DOFS: usize = element::GRADIENT_DOFS;

/// DOFs per node of the Timoshenko mesh.
const SHEAR_DPN: usize = element::TIMOSHENKO_DPN;
/// DOFs per Timoshenko element.
const SHEAR_DOFS: usize = element::TIMOSHENKO_DOFS;

/// (g̃, r̃²) of a beam with shear deformation: g̃ = κGAL²/EI = (κG/E)·AL²/I
/// and r̃² = I/(AL²) (solid circle: AL²/I = 16L²/d²).
pub fn shear_params(beam: &BeamSpec) -> Option<(f64, f64)> {
    beam.shear_deformation.map(|sd| {
        let l2_over_r2 = beam.area_m2() * (beam.length_nm * 1e-9).powi(2) / beam.inertia_m4();
        (sd.shear_to_youngs() * l2_over_r2, 1.0 / l2_over_r2)
    })
}

impl UnitMesh {
    /// The mesh of a beam: Euler–Bernoulli (C² when it has a strain-gradient
    /// length l > 0), or Timoshenko with its (g̃, r̃²) (`BeamSpec::validate`
    /// refuses shear with l > 0; were both set, the Timoshenko mesh is built).
    pub fn for_beam(beam: &BeamSpec) -> Self {
        if beam.shear_deformation.is_none() && beam.strain_gradient_length_nm > 0.0 {
            return Self::with_gradient(beam.elements, beam.support, sprung_ends(beam));
        }
        Self::with_shear(beam.elements, beam.support, shear_params(beam))
    }

    /// True when this mesh is the one [`Self::for_beam`] would build (bitwise;
    /// g̃ and l̃ are pencil parameters and do not enter).
    pub fn matches(&self, beam: &BeamSpec) -> bool {
        let mine = self.shear.as_ref().map(|s| s.r2.to_bits());
        let theirs = shear_params(beam).map(|(_, r2)| r2.to_bits());
        let gradient =
            (beam.shear_deformation.is_none() && beam.strain_gradient_length_nm > 0.0).then(|| sprung_ends(beam));
        self.elements == beam.elements
            && self.support == beam.support
            && mine == theirs
            && self.gradient.as_ref().map(|g| g.sprung) == gradient
    }

    /// The C² Euler–Bernoulli mesh of a strain-gradient beam ([`GradientMesh`]);
    /// `sprung` says at which ends (x = 0, x = L) a rotational spring acts, so
    /// that a pinned end there keeps its curvature free.
    pub fn with_gradient(elements: usize, support: Support, sprung: [bool; 2]) -> Self {
        let last = elements;
        let node = |i: usize, d: usize| GRADIENT_DPN * i + d;
        // a pinned end fixes w and, without a spring, the curvature
        let pinned = |i: usize, end: usize| {
            if sprung[end] {
                vec![node(i, 0)]
            } else {
                vec![node(i, 0), node(i, 2)]
            }
        };
        let removed = match support {
            Support::SimplySupported => [pinned(0, 0), pinned(last, 1)].concat(),
            Support::ClampedClamped => vec![node(0, 0), node(0, 1), node(last, 0), node(last, 1)],
            Support::ClampedFree => vec![node(0, 0), node(0, 1)],
            Support::ClampedPinned => [vec![node(0, 0), node(0, 1)], pinned(last, 1)].concat(),
        };
        let mut next = 0;
        let dof_map: Vec<Option<usize>> = (0..GRADIENT_DPN * (elements + 1))
            .map(|gl| {
                (!removed.contains(&gl)).then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect();
        let n = next;
        let h = 1.0 / elements as f64;
        let ge = element::gradient_element(h);
        // an element couples DOFs at most 2·3 − 1 = 5 apart
        let kd = 2 * GRADIENT_DPN - 1;
        let mut out: [SymBand; 4] = std::array::from_fn(|_| SymBand::zeros_kd(n, kd));
        let mats = [&ge.curvature, &ge.mass, &ge.slope, &ge.gradient];
        for e in 0..elements {
            for a in 0..GRADIENT_DOFS {
                let Some(i) = dof_map[GRADIENT_DPN * e + a] else { continue };
                for b in 0..=a {
                    let Some(j) = dof_map[GRADIENT_DPN * e + b] else { continue };
                    for (band, mat) in out.iter_mut().zip(&mats) {
                        band.add(i, j, mat[a][b]);
                    }
                }
            }
        }
        let [k, m0, m1, k3] = out;
        let spring_dofs = spring_rotations(support, node(0, 1), node(last, 1)).map(|g| g.and_then(|g| dof_map[g]));
        let gauss = std::array::from_fn(|g| {
            let xl = 0.5 * h * (1.0 + element::GAUSS6_X[g]);
            let [n, d, dd] = element::quintic_shape(h, xl);
            (0.5 * h * element::GAUSS6_W[g], [n, d, dd, element::quintic_shape_ddd(h, xl)])
        });
        // the cubic element's Gauss data (unused on this mesh: every function
        // that reads them branches on `gradient` first)
        let cubic_gauss = cubic_gauss(h);
        let (g0, g1) = (m1.clone(), k.clone());
        Self {
            elements,
            support,
            dof_map,
            k,
            m0,
            m1,
            g0,
            g1,
            shear: None,
            gradient: Some(GradientMesh { k3, gauss, sprung }),
            spring_dofs,
            gauss: cubic_gauss,
            curvature_ends: [element::shape_dd(h, 0.0), element::shape_dd(h, h)],
        }
    }

    /// The element's 6 DOF values of a C² mesh vector (0 where a support removed one).
    fn gradient_dofs<T: Copy + Default>(&self, x: &[T], e: usize) -> [T; GRADIENT_DOFS] {
        std::array::from_fn(|a| self.dof_map[GRADIENT_DPN * e + a].map_or(T::default(), |i| x[i]))
    }

    /// [∫(w″)², ∫w², ∫(w′)², ∫(w‴)²] of a C² mesh vector, element by element
    /// with 6-point Gauss (exact for the degree-≤ 10 integrands; the same
    /// accuracy argument as [`Self::energy_forms`]).
    fn gradient_forms<T>(&self, gm: &GradientMesh, x: &[T]) -> [T; 4]
    where
        T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        let mut out = [T::default(); 4];
        for e in 0..self.elements {
            let q = self.gradient_dofs(x, e);
            for (wt, [n, d, dd, ddd]) in &gm.gauss {
                let dot = |f: &[f64; GRADIENT_DOFS]| (0..GRADIENT_DOFS).fold(T::default(), |acc, a| acc + q[a] * f[a]);
                let (w, w1, w2, w3) = (dot(n), dot(d), dot(dd), dot(ddd));
                out[0] = out[0] + w2 * w2 * *wt;
                out[1] = out[1] + w * w * *wt;
                out[2] = out[2] + w1 * w1 * *wt;
                out[3] = out[3] + w3 * w3 * *wt;
            }
        }
        out
    }

    /// ∫₀¹ (w‴)² dx̃ of a DOF vector: xᵀK̃₃x, the strain-gradient energy per
    /// unit l̃² (0 on a mesh without a strain gradient).
    pub fn gradient_form<T>(&self, x: &[T]) -> T
    where
        T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        self.gradient.as_ref().map_or(T::default(), |gm| self.gradient_forms(gm, x)[3])
    }

    /// Timoshenko mesh with rotary inertia r̃² (`shear_params`), or
    /// Euler–Bernoulli for `None`.
    pub fn with_shear(elements: usize, support: Support, shear: Option<(f64, f64)>) -> Self {
        let Some((_, r2)) = shear else { return Self::new(elements, support) };
        let mut mesh = Self::new(elements, support);
        let last = elements;
        let node = |i: usize, d: usize| SHEAR_DPN * i + d;
        // s₀ (the gauge); supports act on w (0) and θ (1), never on χ (2)
        let mut removed = vec![node(0, 3)];
        removed.extend(match support {
            Support::SimplySupported => vec![node(0, 0), node(last, 0)],
            Support::ClampedClamped => vec![node(0, 0), node(0, 1), node(last, 0), node(last, 1)],
            Support::ClampedFree => vec![node(0, 0), node(0, 1)],
            Support::ClampedPinned => vec![node(0, 0), node(0, 1), node(last, 0)],
        });
        let mut next = 0;
        mesh.dof_map = (0..SHEAR_DPN * (elements + 1))
            .map(|gl| {
                (!removed.contains(&gl)).then(|| {
                    next += 1;
                    next - 1
                })
            })
            .collect();
        let spring_global = spring_rotations(support, node(0, 1), node(last, 1));
        mesh.spring_dofs = spring_global.map(|g| g.and_then(|gl| mesh.dof_map[gl]));
        let h = 1.0 / elements as f64;
        let te = element::timoshenko_element(h);
        let comb = |a: &element::Mat10, c: f64, b: &element::Mat10| -> element::Mat10 {
            std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] + c * b[i][j]))
        };
        let [k, ks, m0, m1, mt0, mt1, g1] = mesh.assemble_shear(
            next,
            [
                te.bending,
                te.shear,
                comb(&te.mass_w0, r2, &te.mass_t0),
                comb(&te.mass_w1, r2, &te.bending),
                te.mass_w0,
                te.mass_w1,
                te.geometric_1,
            ],
        );
        mesh.gauss_shear_init(h, r2, ks, mt0, mt1);
        mesh.g0 = mesh.shear.as_ref().expect("just set").mt1.clone();
        mesh.g1 = g1;
        mesh.k = k;
        mesh.m0 = m0;
        mesh.m1 = m1;
        mesh
    }

    fn gauss_shear_init(&mut self, h: f64, r2: f64, ks: SymBand, mt0: SymBand, mt1: SymBand) {
        let gauss = std::array::from_fn(|i| {
            let xl = 0.5 * h * (1.0 + element::GAUSS6_X[i]);
            (0.5 * h * element::GAUSS6_W[i], element::timoshenko_point(h, xl))
        });
        self.shear = Some(ShearMesh { r2, ks, mt0, mt1, gauss });
    }

    /// Assembles 10×10 Timoshenko element matrices over the mesh (n reduced
    /// DOFs; an element couples DOFs at most 2·5 − 1 = 9 apart).
    fn assemble_shear<const K: usize>(&self, n: usize, mats: [element::Mat10; K]) -> [SymBand; K] {
        let mut out: [SymBand; K] = std::array::from_fn(|_| SymBand::zeros_kd(n, 2 * SHEAR_DPN - 1));
        for e in 0..self.elements {
            for a in 0..SHEAR_DOFS {
                let Some(i) = self.dof_map[SHEAR_DPN * e + a] else { continue };
                for b in 0..=a {
                    let Some(j) = self.dof_map[SHEAR_DPN * e + b] else { continue };
                    for (band, mat) in out.iter_mut().zip(&mats) {
                        band.add(i, j, mat[a][b]);
                    }
                }
            }
        }
        out
    }

    /// v += w·coef scattered from element `e`'s local DOFs to reduced DOFs
    /// (10 coefficients for Timoshenko, 4 for Euler–Bernoulli).
    fn scatter(&self, e: usize, coef: &[f64], w: f64, v: &mut [f64]) {
        let dpn = if self.shear.is_some() {
            SHEAR_DPN
        } else if self.gradient.is_some() {
            GRADIENT_DPN
        } else {
            2
        };
        for (a, c) in coef.iter().enumerate() {
            if let Some(i) = self.dof_map[dpn * e + a] {
                v[i] += w * c;
            }
        }
    }

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
        let spring_dofs = spring_rotations(support, 1, 2 * last + 1).map(|g| g.and_then(|g| dof_map[g]));
        let gauss = cubic_gauss(h);
        let curvature_ends = [element::shape_dd(h, 0.0), element::shape_dd(h, h)];
        let (g0, g1) = (m1.clone(), k.clone());
        Self {
            elements,
            support,
            dof_map,
            k,
            m0,
            m1,
            g0,
            g1,
            shear: None,
            gradient: None,
            spring_dofs,
            gauss,
            curvature_ends,
        }
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
        if let Some(gm) = &self.gradient {
            let [k, m0, m1, _] = self.gradient_forms(gm, x);
            return [k, m0, m1];
        }
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

    /// Every form a model needs, element by element (same accuracy argument
    /// as [`Self::energy_forms`]; 4-point Gauss for Euler–Bernoulli, 6-point
    /// for the Timoshenko mesh, exact for its degree-≤ 10 integrands):
    /// [k, m0, m1, mt0, mt1, g0, g1] =
    /// xᵀK̃x, xᵀM̃₀x, xᵀM̃₁x (M̃ = M̃₀ + ẽ²M̃₁), the translational parts of M̃₀, M̃₁
    /// (the damping shape) and xᵀG̃₀x = ∫(w′)², xᵀG̃₁x = ∫(w″)² (axial force).
    /// Euler–Bernoulli: k = g1 = ∫(w″)², m0 = mt0 = ∫w², m1 = mt1 = g0 = ∫(w′)².
    /// Timoshenko with shear stiffness `g` = g̃ (ignored for Euler–Bernoulli):
    /// k = ∫(θ′)² + g̃∫γ², m0 = ∫w² + r̃²∫θ², m1 = ∫(w′)² + r̃²∫(θ′)².
    pub fn energy_forms_ext<T>(&self, x: &[T], g: f64) -> [T; 7]
    where
        T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<Output = T> + std::ops::Mul<f64, Output = T>,
    {
        let Some(sh) = &self.shear else {
            let [k, m0, m1] = self.energy_forms(x);
            return [k, m0, m1, m0, m1, m1, k];
        };
        let mut out = [T::default(); 7];
        for e in 0..self.elements {
            let mut q = [T::default(); SHEAR_DOFS];
            for (a, qa) in q.iter_mut().enumerate() {
                if let Some(i) = self.dof_map[SHEAR_DPN * e + a] {
                    *qa = x[i];
                }
            }
            for (wt, p) in &sh.gauss {
                let dot = |f: &element::TimoshenkoRow| (0..SHEAR_DOFS).fold(T::default(), |acc, a| acc + q[a] * f[a]);
                let (w, w1, w2) = (dot(&p.w), dot(&p.dw), dot(&p.ddw));
                let (t, t1, gam) = (dot(&p.rot), dot(&p.drot), dot(&p.shear));
                out[0] = out[0] + (t1 * t1 + gam * gam * g) * *wt;
                out[1] = out[1] + t * t * *wt;
                out[2] = out[2] + t1 * t1 * *wt;
                out[3] = out[3] + w * w * *wt;
                out[4] = out[4] + w1 * w1 * *wt;
                out[6] = out[6] + w2 * w2 * *wt;
            }
        }
        // out[1], out[2] hold the rotary parts so far
        out[1] = out[3] + out[1] * sh.r2;
        out[2] = out[4] + out[2] * sh.r2;
        out[5] = out[4];
        out
    }

    /// xᵀK̃x = ∫₀¹ (w'')² dx̃ element by element in closed form: w'' is linear
    /// on an element, so with a, b its end values ∫ (w'')² = h̃(a² + ab + b²)/3.
    /// Same accuracy argument as [`Self::energy_forms`] (no cancellation
    /// between assembled entries; a² + ab + b² ≥ (a² + b²)/2 has none either),
    /// at a tenth of its cost: this is the numerator of every Rayleigh quotient.
    /// Timoshenko: ∫(θ′)² + g̃∫γ² with `g` = g̃ (ignored for Euler–Bernoulli).
    pub fn stiffness_form(&self, x: &[f64], g: f64) -> f64 {
        if let Some(sh) = &self.shear {
            return self.timoshenko_stiffness_form(sh, x, g);
        }
        if let Some(gm) = &self.gradient {
            return self.gradient_forms(gm, x)[0];
        }
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

    /// ∫(θ′)² + g̃∫γ² of a Timoshenko DOF vector: the first entry of
    /// [`Self::energy_forms_ext`] (the same Gauss sums in the same order, so
    /// the same bits) without the four fields it does not need (it is the
    /// numerator of every RQI step on a Timoshenko pencil: ~20 % of a
    /// coupled shear model's solve time when all six were formed).
    fn timoshenko_stiffness_form(&self, sh: &ShearMesh, x: &[f64], g: f64) -> f64 {
        let mut sum = 0.0;
        for e in 0..self.elements {
            let mut q = [0.0; SHEAR_DOFS];
            for (a, qa) in q.iter_mut().enumerate() {
                if let Some(i) = self.dof_map[SHEAR_DPN * e + a] {
                    *qa = x[i];
                }
            }
            for (wt, p) in &sh.gauss {
                let dot = |f: &element::TimoshenkoRow| (0..SHEAR_DOFS).fold(0.0, |acc, a| acc + q[a] * f[a]);
                let (t1, gam) = (dot(&p.drot), dot(&p.shear));
                sum += (t1 * t1 + gam * gam * g) * *wt;
            }
        }
        sum
    }

    /// Interpolation vector N(x̃) in reduced DOFs (w = Nᵀq).
    pub fn shape_vector(&self, xt: f64) -> Vec<f64> {
        let h = 1.0 / self.elements as f64;
        let (e, xl) = self.locate(xt);
        if self.shear.is_some() {
            let mut v = vec![0.0; self.n()];
            self.scatter(e, &element::timoshenko_point(h, xl).w, 1.0, &mut v);
            return v;
        }
        if self.gradient.is_some() {
            let mut v = vec![0.0; self.n()];
            self.scatter(e, &element::quintic_shape(h, xl)[0], 1.0, &mut v);
            return v;
        }
        let n = element::shape(h, xl);
        let mut v = vec![0.0; self.n()];
        self.scatter(e, &n, 1.0, &mut v);
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
            if self.shear.is_some() {
                // (A7) with the Timoshenko deflection: N_w − ẽ²N_w″
                let t = element::timoshenko_point(h, xl);
                let p: element::TimoshenkoRow = std::array::from_fn(|a| t.w[a] - e_tilde * e_tilde * t.ddw[a]);
                self.scatter(e, &p, w, &mut v);
                continue;
            }
            if self.gradient.is_some() {
                // (A7) on the C² element: N − ẽ²N″
                let [n, _, dd] = element::quintic_shape(h, xl);
                let p: [f64; GRADIENT_DOFS] = std::array::from_fn(|a| n[a] - e_tilde * e_tilde * dd[a]);
                self.scatter(e, &p, w, &mut v);
                continue;
            }
            let p = element::point_load(h, xl, e_tilde);
            self.scatter(e, &p, w, &mut v);
        }
        v
    }
}

/// The global rotation DOFs (`theta_0` at x = 0, `theta_l` at x = L) that
/// `support` leaves free at a supported end: where a support spring acts.
fn spring_rotations(support: Support, theta_0: usize, theta_l: usize) -> [Option<usize>; 2] {
    match support {
        Support::SimplySupported => [Some(theta_0), Some(theta_l)],
        Support::ClampedPinned => [None, Some(theta_l)],
        Support::ClampedClamped | Support::ClampedFree => [None, None],
    }
}

/// What the undamped relaxed pencil (K̃ + K̃_spring, M̃) depends on, for a
/// given mesh: not E, ρ, C, Δ, Ω (they only scale time and enter the
/// family polynomials); d and L only through the Timoshenko mesh's r̃² and g̃.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PencilParams {
    /// ẽ = e0a/L.
    pub e_tilde: f64,
    /// (μ̃, x̃) of the point mass, if any.
    pub point_mass: Option<(f64, f64)>,
    /// k̃_r at x = 0 and at x = L (0 = none), on `UnitMesh::spring_dofs`.
    pub spring: [f64; 2],
    /// ñ = NL²/EI, the axial force (0 = none).
    pub axial: f64,
    /// g̃ = κGAL²/EI, the shear stiffness of a Timoshenko mesh (0 for Euler–Bernoulli).
    pub shear: f64,
    /// l̃² = (l/L)², the strain gradient of a C² mesh (0 = none).
    pub gradient: f64,
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
/// Step of ñ = NL²/EI on the grid (the simply supported buckling load is
/// ñ = −π²(1 + …) ≈ −10; a step of 0.25 moves λ₁ ≈ π⁴ + ñπ² by ≲ 2.5 %).
/// Snapped towards 0, so a compressed grid pencil is never past buckling
/// when the pencil itself is not.
const GRID_N: f64 = 0.25;
/// Step of ln g̃ on the grid. g̃ = κ(G/E)·16(L/d)² is ≈ 100–450 for the
/// paper's L/d ≈ 8 and κ ∈ [0.3, 1], and mode r's shear share of its
/// compliance is ≈ (rπ)²/g̃: a step of 0.1 (10 % in g̃) moves it by ≲ 10 %
/// of itself, as the other steps move their parameters' share.
const GRID_LN_SHEAR: f64 = 0.1;
/// Step of ln l̃² on the grid: mode r's strain-gradient share of its
/// stiffness is l̃²(rπ)²/(1 + l̃²(rπ)²) ≤ 1, so a step of 0.1 (10 % in l̃²)
/// moves λ_r by ≲ 10 %, as [`GRID_LN_SHEAR`] moves the shear share.
const GRID_LN_GRADIENT: f64 = 0.1;

impl PencilParams {
    /// Bitwise identity.
    pub fn bits(&self) -> [u64; 8] {
        let (mu, x) = self.point_mass.unwrap_or((0.0, 0.0));
        [
            self.e_tilde.to_bits(),
            mu.to_bits(),
            x.to_bits(),
            self.spring[0].to_bits(),
            self.spring[1].to_bits(),
            self.axial.to_bits(),
            self.shear.to_bits(),
            self.gradient.to_bits(),
        ]
    }

    /// The same pencil without its extensions (spring, point mass, axial
    /// force): ẽ, g̃ and l̃² only.
    pub fn plain(&self) -> Self {
        PencilParams {
            e_tilde: self.e_tilde,
            point_mass: None,
            spring: [0.0; 2],
            axial: 0.0,
            shear: self.shear,
            gradient: self.gradient,
        }
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
            spring: self.spring.map(|k| if k > 0.0 { ln_snap(k) } else { 0.0 }),
            axial: (self.axial / GRID_N).trunc() * GRID_N,
            shear: if self.shear > 0.0 {
                ((self.shear.ln() / GRID_LN_SHEAR).round() * GRID_LN_SHEAR).exp()
            } else {
                0.0
            },
            gradient: if self.gradient > 0.0 {
                ((self.gradient.ln() / GRID_LN_GRADIENT).round() * GRID_LN_GRADIENT).exp()
            } else {
                0.0
            },
        }
    }
}

impl UnitMesh {
    /// (reduced DOF, k̃_r) of each spring of `spring` (k̃_r at x = 0 and x = L)
    /// that acts: positive, on a rotation the support leaves free.
    pub fn springs<'a>(&'a self, spring: &'a [f64; 2]) -> impl Iterator<Item = (usize, f64)> + 'a {
        self.spring_dofs.iter().zip(spring).filter_map(|(d, &k)| d.filter(|_| k > 0.0).map(|i| (i, k)))
    }

    /// (K̃ + K̃_spring, M̃) for these parameters.
    pub fn pencil(&self, p: &PencilParams) -> (SymBand, SymBand) {
        let mut k = self.stiffness(p.shear);
        if let Some(gm) = self.gradient.as_ref().filter(|_| p.gradient != 0.0) {
            k = k.plus_scaled(p.gradient, &gm.k3);
        }
        for (i, ks) in self.springs(&p.spring) {
            k.add(i, i, ks);
        }
        if p.axial != 0.0 {
            k = k.plus_scaled(1.0, &self.geometric(p.axial, p.e_tilde));
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
    pub fn pencil_stiffness(&self, p: &PencilParams, x: &[f64]) -> f64 {
        let ks: f64 = self.springs(&p.spring).map(|(i, k)| k * x[i] * x[i]).sum();
        if let Some(gm) = self.gradient.as_ref().filter(|_| p.gradient != 0.0) {
            // ∫w″² + l̃²∫w‴² (+ ñ(∫w′² + ẽ²∫w″²)) in one pass over the elements
            let [k2, _, g0, k3] = self.gradient_forms(gm, x);
            let k_n = if p.axial != 0.0 { p.axial * (g0 + p.e_tilde * p.e_tilde * k2) } else { 0.0 };
            return k2 + p.gradient * k3 + ks + k_n;
        }
        if p.axial != 0.0 {
            let f = self.energy_forms_ext(x, p.shear);
            return f[0] + ks + p.axial * (f[5] + p.e_tilde * p.e_tilde * f[6]);
        }
        self.stiffness_form(x, p.shear) + ks
    }

    /// K̃ of the beam (relaxed, no extension): `k`, plus g̃·Σ∫γγᵀ on a
    /// Timoshenko mesh (`g` = g̃, ignored for Euler–Bernoulli).
    pub fn stiffness(&self, g: f64) -> SymBand {
        match &self.shear {
            Some(sh) => self.k.plus_scaled(g, &sh.ks),
            None => self.k.clone(),
        }
    }

    /// K̃_N = ñ(G̃₀ + ẽ²G̃₁): the axial force N·(∫N′N′ᵀ + (e0a)²∫N″N″ᵀ) with
    /// Eringen's operator acting on the axial-force term, N w″ → (1 − (e0a)²∂²)N w″
    /// (Reddy, "Nonlocal theories for bending, buckling and vibration of beams",
    /// Int. J. Eng. Sci. 45 (2007) 288–307, eq. (28)), in units of EI/L³.
    pub fn geometric(&self, axial: f64, e_tilde: f64) -> SymBand {
        let mut g = self.g0.plus_scaled(e_tilde * e_tilde, &self.g1);
        g.data.iter_mut().for_each(|v| *v *= axial);
        g
    }
}

/// M̃ += μ̃ N Nᵀ (a point mass with interpolation vector N).
pub(crate) fn add_point_mass(m: &mut SymBand, mu: f64, nv: &[f64]) {
    let nz: Vec<usize> = (0..nv.len()).filter(|&i| nv[i] != 0.0).collect();
    for &i in &nz {
        for &j in &nz {
            if j <= i {
                m.add(i, j, mu * nv[i] * nv[j]);
            }
        }
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
