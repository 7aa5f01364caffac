//! The exact fast path of the axial force on a uniform simply supported
//! Euler–Bernoulli mesh (issue 41): the pencil splits into one 2 × 2 block per
//! wavenumber, so the coupled model decouples into one scalar family per mode.
//!
//! # Why it is exact (the derivation)
//! With an axial force the dynamic stiffness of the Euler–Bernoulli mesh is
//!   T̃(s) = s(s + c̃)(m₀ + ẽ²m₁) + G(s)k + ñ(m₁ + ẽ²k),  G(s) = 1 + Σᵢ Δᵢ s/(s + Ωᵢ)
//! (`modal.rs`, `model.rs`: K̃_N = ñ(G̃₀ + ẽ²G̃₁) with G̃₀ = m₁, G̃₁ = k, and
//! D̃ = c̃M̃ without a point mass). m₁ enters with two different scalars, so
//! no eigenbasis of one pencil diagonalises T̃(s) in general (`shear_spectrum.rs`).
//! On the uniform simply supported mesh it does split: every element matrix
//! A ∈ {k, m₀, m₁} is the same on every element and mirror symmetric
//! (A₀₀ = A₂₂, A₁₁ = A₃₃, A₀₁ = −A₂₃, A₀₃ = −A₂₁ in the local order
//! w_a, θ̃_a, w_b, θ̃_b), and the supports remove exactly the w DOFs where
//! sin(jπx̃) vanishes. So for a wavenumber j the two vectors
//!   u_j: w_i = sin(jπ i/n_e), θ̃_i = 0;   v_j: w_i = 0, θ̃_i = cos(jπ i/n_e)
//! (nodes i = 0..n_e, n_e elements) span a subspace that W⁻¹A maps into
//! itself, with W the identity except ½ on the two end rotations (whose rows
//! collect one element instead of two). Summing the element contributions
//! (Σₑ sin²aₑ = Σₑ cos²aₑ = n_e/2, Σₑ sin aₑ sin aₑ₊₁ = Σₑ cos aₑ cos aₑ₊₁ = (n_e/2)cos φ,
//! Σₑ sin aₑ₊₁ cos aₑ = −Σₑ sin aₑ cos aₑ₊₁ = (n_e/2) sin φ, aₑ = eφ, φ = jπ/n_e,
//! 0 < j < n_e) gives the block of W⁻¹A in the basis (u_j, v_j), symmetric:
//!   A_uu = A₀₀ + A₂₂ + 2A₀₂cos φ = (A₀₀ + A₂₂ + 2A₀₂) − 4A₀₂ sin²(φ/2),
//!   A_vv = A₁₁ + A₃₃ + 2A₁₃cos φ,   A_uv = (A₁₂ − A₀₃) sin φ.
//! (The first is written with sin²(φ/2) because A₀₀ + A₂₂ + 2A₀₂ is 0 for k
//! and m₁, rigid translation, and the cos φ form would cancel to O(φ²).)
//! j = 0 and j = n_e leave only v_j (1 × 1 blocks, θ̃ constant or alternating):
//! with the n_e − 1 blocks of size 2 that is 2n_e vectors, the whole reduced
//! space, and the vectors of different j are W-orthogonal. Hence
//!   det T̃(s) ∝ Π_j det T_j(s),  T_j(s) = s(s + c̃)M_j + G(s)K_j + N_j,
//! M_j = m₀_j + ẽ²m₁_j, K_j = k_j, N_j = ñ(m₁_j + ẽ²k_j), for any damping,
//! any internal variables and any force. A Winkler foundation adds k̃_f M̃
//! (`fe::scaling`), elastic like the force, which the same basis splits into
//! k̃_f M_j: it joins N_j = ñ(m₁_j + ẽ²k_j) + k̃_f M_j, here and in the paths
//! built on these blocks (`spring_spectrum.rs`, `mass_blocks.rs`; checked
//! against the coupled reference in `tests/beam_foundation_blocks.rs`).
//! That the subspaces are invariant is
//! not assumed: [`AxialBlocks::new`] computes the residual ‖A U_j − W U_j B_j‖
//! of every block on the assembled mesh and disables the path if any exceeds
//! [`INVARIANCE_TOL`]. Clamped and free ends break the mirror (residuals of
//! order 1); the Timoshenko mesh has its own element (not built here).
//!
//! # Modes and poles
//! Physical mode r is the r-th eigenpair of the undamped relaxed pencil
//! (K̃ + K̃_N, M̃) (`modal_result.rs`); here its eigenvalues are those of the
//! 2 × 2 pencils (K_j + N_j, M_j) and the 1 × 1 ones, in closed form. Mode r
//! must be the lower eigenvalue of some block j (the bending branch; the upper
//! one and the 1 × 1 blocks are the mesh's rotation modes, above the bending
//! modes a diagnosis fits; this is checked on every call): when that fails, or an eigenvalue is not
//! positive (at or beyond buckling), the path declines and the reference runs.
//! Family r's poles are roots of the entire function
//!   E_j(s) = det( s(s + c̃)P(s)M_j + Q(s)K_j + P(s)N_j ),  P = Πᵢ(s + Ωᵢ), Q = G·P,
//! found by Newton from the same starts the coupled reference uses: the roots
//! of the one-term family s² + c̃s + a + bG(s) = 0 with a = xᵀN_jx/xᵀM_jx,
//! b = xᵀK_jx/xᵀM_jx, x the block's lower eigenvector (`coupled.rs`,
//! `family_approximations`), and the same acceptance tests (a root within
//! half its start's modulus, no two starts on one pole, a complex start not
//! on the real axis). Only the oscillatory poles are solved here: when every
//! pole is asked for and a family has real (relaxation) starts, the path
//! declines (see [`AxialBlocks::family_roots`]). The other roots of E_j (the rotation branch) lie
//! beyond that neighbourhood for the modes a diagnosis fits; a start that
//! reached one would fail the half-modulus test and the reference would run.
//!
//! # A hysteretic loss factor
//! A loss factor η multiplies the relaxed stiffness alone: G(s)K̃ becomes
//! G(s)(1 + iη)K̃ in the upper half plane (`ScaledModel::relaxation`), the
//! force and the foundation staying elastic. The basis above splits K̃ and
//! nothing else, so the factorisation holds with Q = (1 + iη)G·P in E_j, and
//! the secular paths built on these blocks take (1 + iη)G(s) in place of
//! G(s) ([`Modulus`]). The starts are the reference's: the oscillatory root
//! of the one-term family s² + c̃s + a + b(1 + iη)G(s) = 0
//! (`hysteretic_family_roots_into`); there are no real poles to ask for, as
//! in the reference (`coupled::general_path`). Checked against the coupled
//! reference in `tests/beam_loss_factor_blocks.rs`.
//!
//! # Accuracy
//! The block entries are a few rounded operations on the element entries.
//! The bending eigenvalue is the Schur complement K_uu − K_uv²/K_vv ∝ sin⁴(φ/2),
//! formed from terms ∝ sin²(φ/2): a relative rounding of ~eps/sin²(φ/2)
//! (≈ 4e-14 at j = 1, n_e = 20; ≈ 1.5e-13 at n_e = 40), the same order as the
//! Rayleigh quotients of the reference (`eigen.rs`, ~1e-14). Newton stops when
//! its step is ≤ [`NEWTON_TOL`]·|s|: convergence is quadratic, so the root is
//! then at the rounding floor.

use num_complex::Complex64;

use crate::beam::fast::jet::Modulus;
use crate::beam::fe::element;
use crate::beam::fe::model::UnitMesh;
use crate::beam::solve::family::{hysteretic_family_roots_into, Roots, REAL_TOL};
use crate::beam::spec::Support;

/// Largest residual ‖W⁻¹A U_j − U_j B_j‖∞ / ‖W⁻¹A‖-scale accepted for the
/// invariance of the wavenumber subspaces: the residual is a sum of ≤ 8
/// rounded products of entries of size ‖A‖ per row, so ~1e-15 relative when
/// the subspaces are invariant and of order 1 when they are not (clamped or
/// free ends); 1e-12 separates the two with margin.
pub const INVARIANCE_TOL: f64 = 1e-12;
/// Newton stops after a step ≤ NEWTON_TOL·|s| (the error after it is
/// ≈ C·NEWTON_TOL² with C = |E″/2E′|·|s| of order 1 at a simple pole:
/// round-off).
const NEWTON_TOL: f64 = 1e-10;
const NEWTON_MAX_STEPS: usize = 40;

/// A symmetric 2 × 2 block (uu, uv, vv).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Sym2 {
    pub(crate) uu: f64,
    pub(crate) uv: f64,
    pub(crate) vv: f64,
}

impl Sym2 {
    pub(crate) fn plus(self, c: f64, o: Sym2) -> Sym2 {
        Sym2 { uu: self.uu + c * o.uu, uv: self.uv + c * o.uv, vv: self.vv + c * o.vv }
    }
    pub(crate) fn scaled(self, c: f64) -> Sym2 {
        Sym2 { uu: c * self.uu, uv: c * self.uv, vv: c * self.vv }
    }
    pub(crate) fn form(self, x: [f64; 2]) -> f64 {
        self.uu * x[0] * x[0] + 2.0 * self.uv * x[0] * x[1] + self.vv * x[1] * x[1]
    }
}

/// The blocks (k_j, m₀_j, m₁_j) of one simply supported Euler–Bernoulli mesh,
/// j = 1..n_e − 1, and the 1 × 1 rotation blocks j = 0, n_e.
#[derive(Debug, Clone, PartialEq)]
pub struct AxialBlocks {
    pub(crate) elements: usize,
    /// (k, m₀, m₁) of block j = 1..n_e − 1 (index j − 1).
    pub(crate) blocks: Vec<[Sym2; 3]>,
    /// (k, m₀, m₁) of v_0 and v_{n_e}.
    pub(crate) rotation: [[f64; 3]; 2],
}

/// The block of one element matrix at φ = jπ/n_e (module doc).
fn block(a: &element::Mat4, phi: f64) -> Sym2 {
    let s2 = (0.5 * phi).sin().powi(2);
    Sym2 {
        uu: (a[0][0] + a[2][2] + 2.0 * a[0][2]) - 4.0 * a[0][2] * s2,
        uv: (a[1][2] - a[0][3]) * phi.sin(),
        vv: a[1][1] + a[3][3] + 2.0 * a[1][3] * phi.cos(),
    }
}

impl AxialBlocks {
    /// The blocks of `mesh`, or `None` when the mesh is not a uniform simply
    /// supported Euler–Bernoulli one or a block fails the invariance check.
    pub fn new(mesh: &UnitMesh) -> Option<Self> {
        // the blocks are the cubic Hermite element's: no Timoshenko, no C² (strain-gradient) mesh
        if mesh.support != Support::SimplySupported
            || mesh.shear.is_some()
            || mesh.gradient.is_some()
            || mesh.elements < 2
        {
            return None;
        }
        let ne = mesh.elements;
        let h = 1.0 / ne as f64;
        let mats = [element::curvature_integral(h), element::mass_integral(h), element::slope_integral(h)];
        let pi = std::f64::consts::PI;
        let blocks: Vec<[Sym2; 3]> =
            (1..ne).map(|j| mats.each_ref().map(|a| block(a, pi * j as f64 / ne as f64))).collect();
        let rotation = [0.0, pi].map(|phi| mats.each_ref().map(|a| block(a, phi).vv));
        let out = AxialBlocks { elements: ne, blocks, rotation };
        (out.invariance_residual(mesh) <= INVARIANCE_TOL).then_some(out)
    }

    /// max over j and A ∈ {k, m₀, m₁} of ‖A U_j − W U_j B_j‖∞ / (max |A|·‖U_j‖∞):
    /// ~1e-15 when the wavenumber subspaces are invariant (module doc).
    pub fn invariance_residual(&self, mesh: &UnitMesh) -> f64 {
        let ne = self.elements;
        let n = mesh.n();
        let mats = [&mesh.k, &mesh.m0, &mesh.m1];
        let scale: [f64; 3] = mats.map(|m| m.data.iter().fold(0.0_f64, |a, v| a.max(v.abs())));
        let mut worst = 0.0_f64;
        let mut y = Vec::new();
        for j in 0..=ne {
            let phi = std::f64::consts::PI * j as f64 / ne as f64;
            let (u, v) = self.basis(mesh, phi);
            let w: Vec<f64> = (0..n)
                .map(|i| if Some(i) == mesh.spring_dofs[0] || Some(i) == mesh.spring_dofs[1] { 0.5 } else { 1.0 })
                .collect();
            for (a, mat) in mats.iter().enumerate() {
                let (buu, buv, bvv) = if j == 0 || j == ne {
                    (0.0, 0.0, self.rotation[usize::from(j == ne)][a])
                } else {
                    let b = self.blocks[j - 1][a];
                    (b.uu, b.uv, b.vv)
                };
                // A u = W(u·B_uu + v·B_uv), A v = W(u·B_uv + v·B_vv)
                for (x, (cu, cv)) in [(&u, (buu, buv)), (&v, (buv, bvv))] {
                    mat.mul_vec_into(x, &mut y);
                    for i in 0..n {
                        let r = y[i] - w[i] * (u[i] * cu + v[i] * cv);
                        worst = worst.max(r.abs() / scale[a]);
                    }
                }
            }
        }
        worst
    }

    /// u_j and v_j as reduced DOF vectors of `mesh` (u = 0 at j = 0, n_e).
    fn basis(&self, mesh: &UnitMesh, phi: f64) -> (Vec<f64>, Vec<f64>) {
        let n = mesh.n();
        let (mut u, mut v) = (vec![0.0; n], vec![0.0; n]);
        for node in 0..=self.elements {
            let a = phi * node as f64;
            if let Some(i) = mesh.dof_map[2 * node] {
                u[i] = a.sin();
            }
            if let Some(i) = mesh.dof_map[2 * node + 1] {
                v[i] = a.cos();
            }
        }
        (u, v)
    }

    /// The bending eigenvalues (lower eigenvalue of block j of (K + N, M)),
    /// j = 1..n_e − 1, and their eigenvectors, for t = ẽ² and ñ; `None` unless
    /// the lowest `n_modes` eigenvalues of the whole pencil are bending ones,
    /// all positive. Sorted ascending: entry r is physical mode r + 1.
    fn bending(&self, t: f64, axial: f64, foundation: f64, n_modes: usize, out: &mut Vec<Bending>) -> Option<()> {
        out.clear();
        if n_modes > self.blocks.len() {
            return None;
        }
        let mut floor = f64::INFINITY;
        for rot in &self.rotation {
            let (k, m0, m1) = (rot[0], rot[1], rot[2]);
            floor = floor.min((k + axial * (m1 + t * k)) / (m0 + t * m1) + foundation);
        }
        for (j, [k, m0, m1]) in self.blocks.iter().enumerate() {
            let m = m0.plus(t, *m1);
            let nn = m1.plus(t, *k).scaled(axial).plus(foundation, m);
            let s = k.plus(1.0, nn);
            // det(S − λM) = aλ² − bλ + c
            let a = m.uu * m.vv - m.uv * m.uv;
            let b = s.uu * m.vv + s.vv * m.uu - 2.0 * s.uv * m.uv;
            let c = s.uu * s.vv - s.uv * s.uv;
            let disc = b * b - 4.0 * a * c;
            if !(a > 0.0 && disc >= 0.0) {
                return None;
            }
            let up = (b + disc.sqrt()) / (2.0 * a);
            let low = c / (a * up);
            floor = floor.min(up);
            // eigenvector of the lower eigenvalue from the better-scaled row
            let r1 = [-(s.uv - low * m.uv), s.uu - low * m.uu];
            let r2 = [s.vv - low * m.vv, -(s.uv - low * m.uv)];
            let x = if r1[0].abs() + r1[1].abs() >= r2[0].abs() + r2[1].abs() { r1 } else { r2 };
            out.push(Bending { lambda: low, j, x, m, k: *k, n: nn });
        }
        out.sort_by(|a, b| a.lambda.total_cmp(&b.lambda));
        out.truncate(n_modes);
        let ok =
            out.iter().all(|b| b.lambda > 0.0 && b.lambda.is_finite()) && out.last().is_some_and(|b| b.lambda < floor);
        ok.then_some(())
    }

    /// The lowest `n_modes` eigenvalues of the undamped relaxed pencil
    /// (K̃ + K̃_N, M̃) at t = ẽ² and ñ, from the blocks; `None` where the path
    /// declines (see the module doc).
    pub fn eigenvalues(&self, t: f64, axial: f64, foundation: f64, n_modes: usize) -> Option<Vec<f64>> {
        let mut b = Vec::new();
        self.bending(t, axial, foundation, n_modes, &mut b)?;
        Some(b.iter().map(|b| b.lambda).collect())
    }

    /// The poles of families 1..=n_modes (scaled units) into `roots`: every
    /// pole when `all`, else the oscillatory pairs only (the real starts are
    /// skipped, as the coupled reference's `Poles::Oscillatory` does).
    /// `false` when the path declines or a root search fails its tests (the
    /// caller then runs the reference).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn family_roots(
        &self,
        t: f64,
        axial: f64,
        foundation: f64,
        c: f64,
        modulus: Modulus,
        n_modes: usize,
        all: bool,
        scratch: &mut Vec<Bending>,
        roots: &mut Vec<Roots>,
    ) -> bool {
        if self.bending(t, axial, foundation, n_modes, scratch).is_none() {
            return false;
        }
        roots.resize(n_modes, Roots::default());
        let mut found: [Complex64; 64] = [Complex64::new(0.0, 0.0); 64];
        let mut nfound = 0;
        let mut starts = Roots::default();
        for (b, out) in scratch.iter().zip(roots.iter_mut()) {
            let mm = b.m.form(b.x);
            let (a1, b1) = (b.n.form(b.x) / mm, b.k.form(b.x) / mm);
            if hysteretic_family_roots_into(a1, b1, c, modulus.ivs, modulus.loss, &mut starts).is_err() {
                return false;
            }
            // Real poles are left to the reference: every family has one near
            // −Ωᵢ/(1 + Δᵢ) and so does the rotation branch of its own block
            // (6.6e-7 relative apart on one random beam of the property test,
            // where the nearest root of E_j was the wrong one), so which root a start belongs to is decided by the
            // eigenvector, as the reference's RQI does, not by the nearest root of E_j.
            if all && starts.iter().any(|s| s.im == 0.0) {
                return false;
            }
            let mut fam = Roots::default();
            // real starts never reach here (they end the path above), so
            // every start is an oscillatory pair's
            for &s0 in starts.iter().filter(|s| s.im > 0.0) {
                let Some(s) = newton(b, c, modulus, s0) else { return false };
                if !accept_pair(s0, s, &mut found, &mut nfound, &mut fam) {
                    return false;
                }
            }
            *out = fam;
        }
        true
    }
}

/// One bending eigenpair of a block and the block's matrices at (t, ñ).
#[derive(Debug, Clone, Copy)]
pub struct Bending {
    lambda: f64,
    /// Block index (wavenumber j − 1).
    #[allow(dead_code)]
    j: usize,
    x: [f64; 2],
    m: Sym2,
    k: Sym2,
    n: Sym2,
}

/// A complex value with its derivative in s.
#[derive(Debug, Clone, Copy)]
struct Jet {
    v: Complex64,
    d: Complex64,
}

impl Jet {
    fn c(v: f64) -> Jet {
        Jet { v: Complex64::new(v, 0.0), d: Complex64::new(0.0, 0.0) }
    }
    fn mul(self, o: Jet) -> Jet {
        Jet { v: self.v * o.v, d: self.d * o.v + self.v * o.d }
    }
    fn add(self, o: Jet) -> Jet {
        Jet { v: self.v + o.v, d: self.d + o.d }
    }
    fn scale(self, c: f64) -> Jet {
        Jet { v: self.v * c, d: self.d * c }
    }
}

/// E_j(s) and E_j′(s) (module doc).
fn family_function(b: &Bending, c: f64, modulus: Modulus, s: Complex64) -> Jet {
    let ivs = modulus.ivs;
    let sj = Jet { v: s, d: Complex64::new(1.0, 0.0) };
    // P = Πᵢ(s + Ωᵢ); Q = P + Σᵢ Δᵢ s Π_{k≠i}(s + Ωₖ) = G·P
    let mut p = Jet::c(1.0);
    for &(_, om) in ivs {
        p = p.mul(sj.add(Jet::c(om)));
    }
    let mut q = p;
    for (i, &(d, _)) in ivs.iter().enumerate() {
        let mut term = sj.scale(d);
        for (k, &(_, om)) in ivs.iter().enumerate() {
            if k != i {
                term = term.mul(sj.add(Jet::c(om)));
            }
        }
        q = q.add(term);
    }
    if modulus.loss != 0.0 {
        // the hysteretic modulus G(s)(1 + iη) (`jet::Modulus`): Q = G·P times (1 + iη)
        let h = Complex64::new(1.0, modulus.loss);
        q = Jet { v: q.v * h, d: q.d * h };
    }
    let pp = sj.mul(sj.add(Jet::c(c))).mul(p);
    let entry = |m: f64, k: f64, n: f64| pp.scale(m).add(q.scale(k)).add(p.scale(n));
    let auu = entry(b.m.uu, b.k.uu, b.n.uu);
    let auv = entry(b.m.uv, b.k.uv, b.n.uv);
    let avv = entry(b.m.vv, b.k.vv, b.n.vv);
    let det = auu.mul(avv);
    let off = auv.mul(auv);
    Jet { v: det.v - off.v, d: det.d - off.d }
}

/// The coupled reference's acceptance of the root `s` Newton reached from the
/// oscillatory start `s0` (`coupled.rs`): within half the start's modulus, no
/// root already found within 1e-8·|s| (two starts on one pole), room left in
/// `found`, and off the real axis. An accepted root joins `found` and `fam`
/// as the pair (s, s̄) with Im s > 0; `false` ends the fast path.
pub(crate) fn accept_pair(
    s0: Complex64,
    s: Complex64,
    found: &mut [Complex64],
    nfound: &mut usize,
    fam: &mut Roots,
) -> bool {
    let n = *nfound;
    if (s - s0).norm() > 0.5 * s0.norm()
        || found[..n].iter().any(|f| (s - f).norm() <= 1e-8 * s.norm())
        || n + 2 > found.len()
        || s.im.abs() <= REAL_TOL * s.norm()
    {
        return false;
    }
    let s = Complex64::new(s.re, s.im.abs());
    found[n] = s;
    found[n + 1] = s.conj();
    *nfound = n + 2;
    fam.push(s);
    fam.push(s.conj());
    true
}

/// A family's oscillatory poles: Newton's iteration ([`newton_from`] with
/// `step`) from each of its starts with Im s > 0, each root accepted by
/// [`accept_pair`]; `None` when a start fails either (the block and
/// continuum paths then decline).
pub(crate) fn oscillatory_pairs(
    starts: &Roots,
    mut step: impl FnMut(Complex64) -> Complex64,
    found: &mut [Complex64],
    nfound: &mut usize,
) -> Option<Roots> {
    let mut fam = Roots::default();
    for &s0 in starts.iter().filter(|s| s.im > 0.0) {
        let s = newton_from(s0, &mut step)?;
        if !accept_pair(s0, s, found, nfound, &mut fam) {
            return None;
        }
    }
    Some(fam)
}

/// The families 1..=n_modes of a secular path (`spring_spectrum.rs`,
/// `mass_blocks.rs`) into `roots`. `family(r0)` gives family r0 + 1's
/// one-term forms (a, b, damping) and what its Newton step needs (the
/// removed blocks); its starts come from `hysteretic_family_roots_into`
/// with `modulus`'s loss factor (the coupled reference's starts), the path
/// declines on a real start when `all` (real poles are left to the
/// reference), and its oscillatory pairs come from [`oscillatory_pairs`]
/// with `step(context, s)`. `false` when any part declines.
pub(crate) fn secular_families<R>(
    n_modes: usize,
    all: bool,
    modulus: Modulus,
    roots: &mut Vec<Roots>,
    mut family: impl FnMut(usize) -> Option<((f64, f64, f64), R)>,
    mut step: impl FnMut(&R, Complex64) -> Complex64,
) -> bool {
    if n_modes == 0 {
        return false;
    }
    roots.resize(n_modes, Roots::default());
    let mut found: [Complex64; 64] = [Complex64::new(0.0, 0.0); 64];
    let mut nfound = 0;
    let mut starts = Roots::default();
    for (r0, out) in roots.iter_mut().enumerate().take(n_modes) {
        let Some(((a1, b1, damping), context)) = family(r0) else { return false };
        if hysteretic_family_roots_into(a1, b1, damping, modulus.ivs, modulus.loss, &mut starts).is_err() {
            return false;
        }
        if all && starts.iter().any(|s| s.im == 0.0) {
            return false;
        }
        let Some(fam) = oscillatory_pairs(&starts, |s| step(&context, s), &mut found, &mut nfound) else {
            return false;
        };
        *out = fam;
    }
    true
}

/// Newton on E_j from `s0`; `None` without convergence.
fn newton(b: &Bending, c: f64, modulus: Modulus, s0: Complex64) -> Option<Complex64> {
    newton_from(s0, |s| {
        let e = family_function(b, c, modulus, s);
        e.v / e.d
    })
}

/// Newton's iteration s ← s − step(s) from `s0`, stopped after a step
/// ≤ [`NEWTON_TOL`]·|s| (then the root), or `None` on a non-finite step or
/// after [`NEWTON_MAX_STEPS`]: the one stopping rule of the block paths
/// (this file's determinants and `spring_spectrum.rs`'s secular function).
pub(crate) fn newton_from(s0: Complex64, mut step: impl FnMut(Complex64) -> Complex64) -> Option<Complex64> {
    let mut s = s0;
    for _ in 0..NEWTON_MAX_STEPS {
        let ds = step(s);
        if !(ds.re.is_finite() && ds.im.is_finite()) {
            return None;
        }
        s -= ds;
        if ds.norm() <= NEWTON_TOL * s.norm() {
            return Some(s);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    //! Data: the assembled mesh matrices of `model.rs` (another code path
    //! than the element sums of [`block`]) and `eigen.rs`'s solve of the
    //! whole assembled pencil.
    use super::*;
    use crate::beam::fe::model::PencilParams;
    use crate::beam::solve::eigen::lowest_eigenpairs;

    /// The invariance the path rests on holds on simply supported meshes
    /// (residual at rounding) and fails on clamped–clamped (order 1), so the
    /// check in [`AxialBlocks::new`] can fail.
    #[test]
    fn wavenumber_subspaces_are_invariant_only_when_simply_supported() {
        for ne in [2, 5, 20, 40] {
            let ss = UnitMesh::new(ne, Support::SimplySupported);
            let blocks = AxialBlocks::new(&ss).expect("simply supported");
            // rounding: measured 1.6e-14 at 40 elements; the accepted INVARIANCE_TOL
            assert!(blocks.invariance_residual(&ss) <= INVARIANCE_TOL, "{ne}: {}", blocks.invariance_residual(&ss));
            let cc = UnitMesh::new(ne, Support::ClampedClamped);
            assert!(AxialBlocks::new(&cc).is_none());
            if ne >= 5 {
                assert!(blocks.invariance_residual(&cc) > 1e-3, "{ne}: {}", blocks.invariance_residual(&cc));
            }
        }
    }

    /// The block eigenvalues are the lowest eigenvalues of the assembled
    /// pencil (K̃ + K̃_N, M̃): within 1e-12 relative (the direct solve's
    /// Rayleigh-quotient rounding, `modal.rs`'s refinement test) times the
    /// compression gain (1 + r)/(1 − r) ≤ 3 at r = ½.
    #[test]
    fn block_eigenvalues_are_the_assembled_pencils() {
        let mesh = UnitMesh::new(20, Support::SimplySupported);
        let blocks = AxialBlocks::new(&mesh).unwrap();
        let ncr = std::f64::consts::PI.powi(2);
        for (e, ratio) in [(0.0, 1.0), (0.1, 20.0), (0.25, -0.5), (0.05, 100.0), (0.2, 0.0)] {
            let t = e * e;
            // the scaled force as a multiple of the local Euler load π² (ñ = NL²/EI)
            let axial = ratio * ncr / (1.0 + t * ncr);
            let fast = blocks.eigenvalues(t, axial, 0.0, 6).unwrap();
            let p = PencilParams { e_tilde: e, point_mass: None, spring: [0.0; 2], axial, shear: 0.0, gradient: 0.0 };
            let (k, m) = mesh.pencil(&p);
            let direct = lowest_eigenpairs(&k, &m, 6, &mut Vec::new(), &|x| mesh.pencil_stiffness(&p, x)).unwrap();
            for (f, d) in fast.iter().zip(&direct) {
                assert!((f - d.lambda).abs() <= 3e-12 * d.lambda, "ẽ {e} N/N_E {ratio}: {f} vs {}", d.lambda);
            }
        }
    }
}
