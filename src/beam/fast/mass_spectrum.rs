//! The exact fast path of the Euler–Bernoulli beam with a point mass and no
//! viscous damping (`attached-mass`, issue 41): the lowest eigenvalues of
//! (K̃, M̃ + μ̃NNᵀ) from a secular equation over the *whole* spectrum of the
//! beam's own pencil (K̃, M̃), whose eigenpairs are certified Chebyshev
//! interpolants in t = ẽ² as in `spectrum.rs`.
//!
//! # How the point mass enters (`model.rs`)
//! `ScaledModel::new` adds μ̃NNᵀ to M̃ = M̃₀ + ẽ²M̃₁, μ̃ = m/(ρAL), with N = N(x̃)
//! the plain interpolation vector of the deflection at x̃ (`UnitMesh::shape_vector`:
//! w(x̃) = Nᵀq; Eringen's operator is not applied to the point mass's inertia,
//! only to the beam's own, through M̃₁). The mass is not in the damping
//! (D̃ = c̃M̃_beam) and not in the stiffness. With C = 0 and no spring or axial
//! force the model decouples (`modal.rs`: D̃ = 0 ∝ M̃), so its poles are the
//! family roots of s² + λ̃_r G(s) = 0 with λ̃_r the eigenvalues of the real
//! symmetric pencil (K̃, M̃ + μ̃NNᵀ). Only those eigenvalues are new here.
//!
//! # The secular equation (exact for the FE model)
//! Let (ν_j, ψ_j), j = 1..n, be the eigenpairs of M̃ψ = νK̃ψ, K̃-orthonormal
//! (ΨᵀK̃Ψ = I, ΨᵀM̃Ψ = diag ν, ν_j = 1/λ̃_j, ν₁ > ν₂ > … > ν_n > 0: beam spectra
//! are simple). The perturbed problem (M̃ + μ̃NNᵀ)x = νK̃x in the basis Ψ,
//! with w = ΨᵀN, is (diag ν + μ̃wwᵀ)y = νy, a symmetric rank-one update
//! (Golub, SIAM Rev. 15 (1973) 318; Bunch, Nielsen, Sorensen, Numer. Math. 31
//! (1978) 31). For ν ≠ ν_j its eigenvalues are exactly the roots of
//!   F(ν) = Σ_{j=1..n} w_j²/(ν − ν_j) − 1/μ̃ = 0,
//! and F′ = −Σ w_j²/(ν − ν_j)² < 0: F falls from +∞ to −∞ between consecutive
//! poles with w_j ≠ 0, so each such interval (ν_j, ν_{j−1}) holds exactly one
//! root, and the top one lies in (ν₁, ν₁ + μ̃Σw_j²] (there F ≤ Σw_j²/(ν − ν₁) − 1/μ̃).
//! A mode with w_j = 0 (the mass on its node) keeps ν_j exactly and drops
//! out of F. Adding mass raises every ν (lowers every λ̃), interlacing
//! ν_j < ν′_j < ν_{j−1}. With φ_j the M̃-orthonormal eigenvectors (what is
//! interpolated), ψ_j = φ_j√ν_j and w_j² = ν_j u_j², u_j = φ_jᵀN = φ_j(x̃) the
//! mode shape at the mass.
//!
//! The sum runs over all n eigenpairs: no truncation. A truncated sum with a
//! residual-flexibility tail Σ_{j>m} w_j²/(ν − ν_j) = Σ_k T_k/ν^{k+1},
//! T_k = Σ_{j>m} w_j²ν_j^k, was considered and rejected: T_k is what is left
//! of the static moments Nᵀ(K̃⁻¹M̃)^kK̃⁻¹N after subtracting the m kept modes, a
//! cancellation that amplifies the kept modes' 1e-12 interpolation error by
//! (ν₁/ν_{m+1})^k·S₀/T₀ (≈ 1e4·3e3 for m = 10 and k = 1 on a simply
//! supported beam), while the series' ratio ν_{m+1}/ν₅ ≈ 0.04 needs several
//! terms for 1e-12. The whole spectrum of a 20-element mesh is 36–40
//! eigenpairs, and a root costs O(n) per Newton step.
//!
//! # What is interpolated, and why that is exact to round-off
//! Only t = ẽ² changes (K̃, M̃) on a mesh. ν_j(t) and φ_j(t) are analytic in t
//! (a real symmetric pencil analytic in one real parameter has analytic
//! eigenvalues and eigenvectors: Rellich, *Perturbation Theory of Eigenvalue
//! Problems*, 1969, ch. 1; Kato, *Perturbation Theory for Linear Operators*,
//! II §6), so every entry of φ_j is a Chebyshev series converging
//! geometrically on a t-piece of `spectrum.rs` (dyadic, μ changes by less than
//! a factor 2 on one). x̃ and μ̃ are not interpolated at all: u_j = Σ_a N_a(x̃)·φ_j,a
//! over the ≤ 4 DOFs of the element holding x̃, with the FE shape functions
//! themselves, and μ̃ enters F only as 1/μ̃. So the only approximation is in t.
//!
//! # Data, sign and certification (computed, never assumed)
//! At each Chebyshev–Lobatto node of a piece the whole pencil is solved
//! densely (Cholesky of M̃, `nalgebra::SymmetricEigen` of L⁻¹K̃L⁻ᵀ, sorted),
//! then each pair is refined to the accuracy of the direct banded path: the
//! Rayleigh quotient of the dense vector (element-energy numerator,
//! `UnitMesh::stiffness_form`) as the shift of one step of inverse iteration
//! (`eigen::eigenvector`, M̃-normalised), and the quotient of the refined
//! vector. The sign of φ_j is fixed at every node by the entry of largest
//! modulus at the piece's midpoint node (made positive), which makes φ_j(t)
//! continuous on the piece as long as that entry does not change sign there;
//! if it did, the interpolant would not certify. Each data point is a pure
//! function of (mesh, t), so each interpolant is a function of (elements,
//! support, piece) alone.
//! For degree n = 8, 16, 32, 64 each mode is checked as in `spectrum.rs`:
//! the interpolant through the n + 1 Lobatto nodes against the data at the n
//! first-kind points between them, and the next level's coefficients beyond n:
//!   ε_ν = max(max |p_n − ν|/|ν| at the checks, 2Σ_{k>n}|c_k|/min|ν|),
//!   e_φ,a = max(max |p_n − φ_a| at the checks, 2Σ_{k>n}|c_k|) per entry a, e_φ = max_a e_φ,a.
//! The lowest degree with ε_ν ≤ 5e-13 and e_φ ≤ 5e-13·max|φ| is kept, else
//! the degree with the smallest certificate; a mode whose best certificate is
//! above 1e-9 makes the piece uncertified (direct path). The stored bounds
//! are 2ε_ν and every 2e_φ,a (the factor 2 of `spectrum.rs`'s `ACCEPT_TOL`: the error
//! between check points stays within a small factor of its value there).
//!
//! # A bound per evaluation
//! Every evaluation bounds its own error to first order in the data errors:
//! with δν_j = 2ε_ν,j ν_j (+ rounding) and δu_j = Σ_a|N_a|·2e_φ,j,a (each entry's own
//! certificate),
//!   δ(w_j²) ≤ ν_j(2|u_j|δu_j + δu_j²) + u_j²δν_j,
//!   δF(ν*) ≤ Σ_j [δ(w_j²)/|ν* − ν_j| + w_j²δν_j/(ν* − ν_j)²] + 4n·eps·(Σ_j w_j²/|ν* − ν_j| + 1/μ̃),
//!   |δν*|/ν* ≤ δF/(|F′(ν*)|·ν*) + 4·eps (the root finder's stop),
//! the last term of δF covering the rounding of F's terms. The solver takes
//! this path only when every requested eigenvalue's bound is within
//! [`MASS_CERTIFIED_TOL`]; otherwise it solves directly. What is not in the
//! bound is the data's own error against the exact FE pencil (Rayleigh
//! quotients from element energies, ~1e-14 relative, `eigen.rs`).
//!
//! # The root finder
//! Root k is sought as ν* = ν_p + τ, p the k-th pole with w_p ≠ 0, τ in the
//! bracket (0, gap) on which F changes sign once; Newton on
//! h(τ) = τF = w_p² + τ(R(τ) − 1/μ̃) (R the other poles' terms, differences
//! ν_p − ν_j formed once), which has no pole at τ = 0, keeps the bracket by the
//! sign of h and bisects when a step leaves it; it stops when a step is below
//! 4·eps·τ. The start is the one-pole estimate τ₀ = w_p²/(1/μ̃ − R(0)).
//!
//! # What is not built here
//! Timoshenko + point mass (C = 0) is the same equation with the Timoshenko
//! eigenpairs over (t, 1/g̃) (`shear_spectrum.rs`'s cells, ~100 DOFs: ~100²
//! interpolated vector entries per cell, 100 dense 100 × 100 solves per
//! node). With C > 0 the mass is outside the damping and the poles are the
//! roots in s of 1 + s²μ̃Σ_j u_j²/(s² + c̃s + λ̃_jG(s)) (`shear_spectrum.rs`'s
//! derivation), a complex secular equation over the same interpolated data.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::beam::fast::spectrum::{lobatto_coefficients, piece_of, piece_range, PIECES};
use crate::beam::fe::element;
use crate::beam::fe::model::{PencilParams, UnitMesh};
use crate::beam::solve::eigen::{eigenvector, lowest_eigenpairs};
use crate::beam::spec::Support;

/// Largest relative error bound of an eigenvalue the solver accepts from this
/// path (see "A bound per evaluation"). Why 1e-10 and not the 1e-12 of the
/// interpolated eigenvalues: the bound is dominated by the eigenvector
/// entries, which the data carry only to ~eps·λ_max/λ_j of the mode's scale
/// (inverse iteration solves a system whose rounding is eps·‖K̃ − σM̃‖, and
/// λ_max/λ₁ ~ 1e6 on a 20-element mesh; a Rayleigh quotient squares a
/// vector's error, a secular root does not), and it sums worst cases over
/// all n modes. Measured over the `attached-mass` prior on the four 20-element
/// meshes: 2e-12–3e-10, the largest on the clamped–pinned one (whose
/// evaluations above the tolerance take the direct path). What it costs the
/// consumer: a relative error ε in λ̃ moves ω by ≤ ε (|d ln s/d ln λ̃| ≤ 1,
/// `tests/beam_fast_path.rs`), a Gaussian log-likelihood term by
/// ≤ z·ε/σ_rel = 5·1e-10/0.003 ≈ 2e-7 nats at z = 5 and the hidden suite's
/// 0.3 % sd, five orders below the evidence's Monte Carlo error.
pub const MASS_CERTIFIED_TOL: f64 = 1e-10;
/// Certificate a mode's interpolant aims at (half of what `spectrum.rs` keeps).
const ACCEPT_TOL: f64 = 5e-13;
/// A mode whose best certificate is worse than this leaves its piece uncertified.
const KEEP_TOL: f64 = 1e-9;
/// Degrees tried and the finest Lobatto grid (2·64 intervals), as in `spectrum.rs`.
const LEVELS: [usize; 4] = [8, 16, 32, 64];
const FINEST: usize = 128;
/// Meshes with more reduced DOFs take the direct path: a piece costs FINEST + 1
/// dense solves of order n and n² interpolated entries (a 20-element
/// Euler–Bernoulli mesh has 36–40).
pub const MAX_DOFS: usize = 80;

/// One mode on one piece: ν(t) and every entry of φ(t), of one degree.
#[derive(Debug, Clone, PartialEq)]
struct ModeInterpolant {
    degree: usize,
    nu: Vec<f64>,
    /// Entry a's coefficients at `phi[a·(degree + 1)..]`.
    phi: Vec<f64>,
    /// Certified relative error of ν and absolute error of each entry of φ
    /// (2× the certificates: module doc).
    nu_err: f64,
    phi_err: Vec<f64>,
}

/// Every mode of one mesh on one t-piece.
#[derive(Debug, Clone, PartialEq)]
struct Piece {
    lo: f64,
    hi: f64,
    modes: Vec<ModeInterpolant>,
}

/// T_0(y)..T_{len−1}(y) by the three-term recurrence (on [−1, 1] its
/// rounding grows like k·eps, ≤ 65 eps here). The series of a piece are then
/// dot products with these values: independent multiply–adds instead of
/// Clenshaw's serial recurrence, whose latency was most of an evaluation
/// (n(1 + 4) series of one mode set each).
fn chebyshev_values(y: f64, out: &mut [f64]) {
    let mut prev = 1.0;
    let mut cur = y;
    for (k, slot) in out.iter_mut().enumerate() {
        *slot = match k {
            0 => 1.0,
            1 => y,
            _ => {
                let next = 2.0 * y * cur - prev;
                prev = cur;
                cur = next;
                next
            }
        };
    }
}

/// Σ c_k T_k(y) with `tk` from [`chebyshev_values`].
#[inline]
fn series(coef: &[f64], tk: &[f64]) -> f64 {
    coef.iter().zip(tk).map(|(c, t)| c * t).sum()
}

/// The whole spectrum of (K̃, M̃₀ + tM̃₁): ν_j = 1/λ̃_j descending and the
/// M̃-orthonormal φ_j (module doc, "Data"); `None` if a solve fails.
fn direct_all(mesh: &UnitMesh, t: f64) -> Option<Spectrum> {
    let m = mesh.m0.plus_scaled(t, &mesh.m1);
    let n = mesh.n();
    let chol = nalgebra::Cholesky::new(m.to_dense())?;
    let l = chol.l();
    let linv = l.clone().try_inverse()?;
    let c = &linv * mesh.k.to_dense() * linv.transpose();
    let c = (&c + c.transpose()) * 0.5;
    let eig = nalgebra::SymmetricEigen::new(c);
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let lt_inv = linv.transpose();
    let mut nus = Vec::with_capacity(n);
    let mut phis = Vec::with_capacity(n);
    let quotient = |x: &[f64]| mesh.stiffness_form(x, 0.0) / m.bilinear(x, x);
    for &j in &order {
        let dense: Vec<f64> = (&lt_inv * eig.eigenvectors.column(j)).iter().copied().collect();
        let shift = quotient(&dense);
        let phi = eigenvector(&mesh.k, &m, shift).ok()?;
        let lambda = quotient(&phi);
        if !(lambda.is_finite() && lambda > 0.0) {
            return None;
        }
        nus.push(1.0 / lambda);
        phis.push(phi);
    }
    // strictly descending ν: distinct eigenvalues, none lost to the refinement
    nus.windows(2).all(|w| w[0] > w[1]).then_some((nus, phis))
}

/// The whole spectrum at one t: ν_j descending and the φ_j.
type Spectrum = (Vec<f64>, Vec<Vec<f64>>);

/// Data at the finest Lobatto grid of one piece, solved on demand and
/// sign-aligned to the midpoint node.
struct Nodes<'a> {
    mesh: &'a UnitMesh,
    lo: f64,
    hi: f64,
    values: Vec<Option<Spectrum>>,
    /// Per mode, the entry made positive at every node.
    anchor: Vec<usize>,
}

impl Nodes<'_> {
    fn t(&self, j: usize) -> f64 {
        let x = (std::f64::consts::PI * j as f64 / FINEST as f64).cos();
        0.5 * (self.lo + self.hi) + 0.5 * (self.hi - self.lo) * x
    }

    fn node(&mut self, j: usize) -> Option<&Spectrum> {
        if self.values[j].is_none() {
            let (nus, mut phis) = direct_all(self.mesh, self.t(j))?;
            if self.anchor.is_empty() {
                // the midpoint node is solved first (see `build_piece`)
                self.anchor = phis
                    .iter()
                    .map(|p| (0..p.len()).max_by(|&a, &b| p[a].abs().total_cmp(&p[b].abs())).unwrap_or(0))
                    .collect();
            }
            for (p, &a) in phis.iter_mut().zip(&self.anchor) {
                if p[a] < 0.0 {
                    p.iter_mut().for_each(|v| *v = -*v);
                }
            }
            self.values[j] = Some((nus, phis));
        }
        self.values[j].as_ref()
    }

    /// ν_mode and φ_mode at the level-n Lobatto nodes (n divides FINEST).
    fn level(&mut self, n: usize, mode: usize) -> Option<Spectrum> {
        let (mut nu, mut phi) = (Vec::with_capacity(n + 1), Vec::with_capacity(n + 1));
        for j in (0..=FINEST).step_by(FINEST / n) {
            let (nus, phis) = self.node(j)?;
            nu.push(nus[mode]);
            phi.push(phis[mode].clone());
        }
        Some((nu, phi))
    }
}

/// max |p_n − f| at the level-2n check points and 2Σ_{k>n}|c_k| of `fine`
/// (values at the 2n + 1 Lobatto nodes), with p_n's coefficients.
fn check(fine: &[f64]) -> (Vec<f64>, f64, f64) {
    let n = (fine.len() - 1) / 2;
    let coarse: Vec<f64> = fine.iter().step_by(2).copied().collect();
    let coef = lobatto_coefficients(&coarse);
    let mut worst = 0.0f64;
    let mut tk = vec![0.0; n + 1];
    for j in (1..=2 * n).step_by(2) {
        let x = (std::f64::consts::PI * j as f64 / (2 * n) as f64).cos();
        chebyshev_values(x, &mut tk);
        worst = worst.max((series(&coef, &tk) - fine[j]).abs());
    }
    let tail = 2.0 * lobatto_coefficients(fine)[n + 1..].iter().map(|c| c.abs()).sum::<f64>();
    (coef, worst, tail)
}

/// Certifies one mode (module doc): the kept interpolant, or `None`.
fn certify(nodes: &mut Nodes<'_>, mode: usize) -> Option<ModeInterpolant> {
    let mut best: Option<(f64, ModeInterpolant)> = None;
    for n in LEVELS {
        let (nu, phi) = nodes.level(2 * n, mode)?;
        let (nu_coef, nu_check, nu_tail) = check(&nu);
        let min_nu = nu.iter().fold(f64::INFINITY, |a, v| a.min(v.abs()));
        let nu_cert = nu_check.max(nu_tail) / min_nu;
        let dofs = phi[0].len();
        let scale = phi.iter().flatten().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut phi_coef = Vec::with_capacity(dofs * (n + 1));
        let mut phi_err = Vec::with_capacity(dofs);
        for a in 0..dofs {
            let entry: Vec<f64> = phi.iter().map(|p| p[a]).collect();
            let (coef, worst, tail) = check(&entry);
            phi_err.push(2.0 * worst.max(tail));
            phi_coef.extend(coef);
        }
        let phi_cert = 0.5 * phi_err.iter().fold(0.0f64, |a, &v| a.max(v));
        let relative = nu_cert.max(phi_cert / scale);
        let kept = ModeInterpolant { degree: n, nu: nu_coef, phi: phi_coef, nu_err: 2.0 * nu_cert, phi_err };
        if relative <= ACCEPT_TOL {
            return Some(kept);
        }
        if best.as_ref().is_none_or(|(b, _)| relative < *b) {
            best = Some((relative, kept));
        }
    }
    best.filter(|(r, _)| *r <= KEEP_TOL).map(|(_, m)| m)
}

/// Builds the interpolants of every mode of `mesh` on piece `piece`; `None`
/// when a mode cannot be certified or a solve fails.
fn build_piece(mesh: &UnitMesh, piece: usize) -> Option<Piece> {
    if mesh.shear.is_some() || mesh.gradient.is_some() || mesh.n() > MAX_DOFS {
        return None;
    }
    let (lo, hi) = piece_range(piece);
    let mut nodes = Nodes { mesh, lo, hi, values: vec![None; FINEST + 1], anchor: Vec::new() };
    nodes.node(FINEST / 2)?;
    let modes = (0..mesh.n()).map(|j| certify(&mut nodes, j)).collect::<Option<Vec<_>>>()?;
    Some(Piece { lo, hi, modes })
}

/// Shared by every solver of the process: keyed by (elements, support,
/// piece), a pure function of its key (as `spectrum.rs`'s cache).
type Key = (usize, Support, usize);
type Entry = Arc<Option<Piece>>;

fn global() -> &'static Mutex<HashMap<Key, Entry>> {
    static CACHE: OnceLock<Mutex<HashMap<Key, Entry>>> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The lowest eigenvalues of (K̃, M̃ + μ̃NNᵀ) of one Euler–Bernoulli mesh for
/// one solver: a local index of pieces in front of the process-wide cache,
/// and the buffers of an evaluation.
///
/// Contract: [`Self::lambdas`] returns `true` only when every eigenvalue it
/// wrote carries a first-order error bound ≤ [`MASS_CERTIFIED_TOL`] relative
/// against the FE pencil's (module doc); its output is a function of (mesh,
/// t, μ̃, x̃, count) alone, whatever the table saw before.
#[derive(Debug, Default, Clone)]
pub struct MassSpectrumTable {
    local: Vec<Option<Entry>>,
    nu: Vec<f64>,
    w2: Vec<f64>,
    dw2: Vec<f64>,
    dnu: Vec<f64>,
    diff: Vec<f64>,
    wx: Vec<f64>,
    found: Vec<(f64, f64)>,
}

impl MassSpectrumTable {
    /// λ̃_1..λ̃_count of (K̃, M̃ + μ̃NN(x̃)ᵀ) at t = ẽ² into `out`, and their
    /// relative error bounds into `bounds` (both of length count); `false`
    /// when the path does not apply (Timoshenko or too large a mesh, t beyond
    /// the pieces, an uncertified piece, μ̃ not positive, a bound above
    /// [`MASS_CERTIFIED_TOL`]): the caller then solves directly.
    pub fn lambdas(&mut self, mesh: &UnitMesh, t: f64, mu: f64, x: f64, out: &mut [f64], bounds: &mut [f64]) -> bool {
        let count = out.len();
        if mesh.shear.is_some()
            || mesh.gradient.is_some()
            || mesh.n() > MAX_DOFS
            || count > mesh.n()
            || !(mu > 0.0 && mu.is_finite())
        {
            return false;
        }
        let Some(p) = piece_of(t) else { return false };
        if self.local.len() < PIECES {
            self.local.resize(PIECES, None);
        }
        if self.local[p].is_none() {
            self.local[p] = Some(fetch(mesh, p));
        }
        let entry = self.local[p].clone().expect("just set");
        let Some(piece) = entry.as_ref() else { return false };
        if !(0.0..=1.0).contains(&x) {
            return false;
        }
        self.evaluate(mesh, piece, t, x);
        self.roots(mu, count, out, bounds)
    }

    /// ν_j, w_j² and their error bounds at (t, x̃).
    fn evaluate(&mut self, mesh: &UnitMesh, piece: &Piece, t: f64, xt: f64) {
        // the element and shape values of `UnitMesh::shape_vector` (its `locate`)
        let ne = mesh.elements;
        let e = ((xt * ne as f64).floor() as usize).min(ne - 1);
        let h = 1.0 / ne as f64;
        let shape = element::shape(h, xt - e as f64 / ne as f64);
        // an eliminated DOF reads row 0 with weight 0
        let mut dofs = [(0usize, 0.0f64); 4];
        for ((slot, a), &na) in dofs.iter_mut().zip(0..).zip(&shape) {
            if let Some(i) = mesh.dof_map[2 * e + a] {
                *slot = (i, na);
            }
        }
        let y = (2.0 * t - piece.lo - piece.hi) / (piece.hi - piece.lo);
        let mut tk = [0.0; LEVELS[LEVELS.len() - 1] + 1];
        chebyshev_values(y, &mut tk);
        let n = piece.modes.len();
        for v in [&mut self.nu, &mut self.w2, &mut self.dw2, &mut self.dnu] {
            v.clear();
            v.reserve(n);
        }
        for m in &piece.modes {
            let d = m.degree + 1;
            let row = |a: usize| &m.phi[dofs[a].0 * d..(dofs[a].0 + 1) * d];
            // five independent sums in one pass over k
            let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
            let mut acc = [0.0f64; 5];
            for k in 0..d {
                let t = tk[k];
                acc[0] += m.nu[k] * t;
                acc[1] += r0[k] * t;
                acc[2] += r1[k] * t;
                acc[3] += r2[k] * t;
                acc[4] += r3[k] * t;
            }
            let nu = acc[0];
            let u = dofs[0].1 * acc[1] + dofs[1].1 * acc[2] + dofs[2].1 * acc[3] + dofs[3].1 * acc[4];
            let du: f64 = dofs.iter().map(|&(i, na)| na.abs() * m.phi_err[i]).sum();
            let dnu = (m.nu_err + 2.0 * f64::EPSILON) * nu;
            self.nu.push(nu);
            self.w2.push(nu * u * u);
            self.dw2.push(nu * (2.0 * u.abs() * du + du * du) + u * u * dnu);
            self.dnu.push(dnu);
        }
    }

    /// The secular roots (module doc) into `out` (λ̃, ascending) and `bounds`.
    fn roots(&mut self, mu: f64, count: usize, out: &mut [f64], bounds: &mut [f64]) -> bool {
        let n = self.nu.len();
        let inv_mu = 1.0 / mu;
        let total: f64 = self.w2.iter().sum();
        self.found.clear();
        // poles with w_j = 0 keep their ν_j (error: the interpolant's)
        for j in 0..n.min(count) {
            if self.w2[j] == 0.0 {
                self.found.push((self.nu[j], self.dnu[j] / self.nu[j]));
            }
        }
        let mut upper = f64::NAN;
        let mut roots = 0;
        for p in 0..n {
            if roots == count {
                break;
            }
            if self.w2[p] == 0.0 {
                continue;
            }
            let gap = if upper.is_nan() { mu * total } else { upper - self.nu[p] };
            upper = self.nu[p];
            let Some(root) = self.root(p, gap, inv_mu) else { return false };
            self.found.push(root);
            roots += 1;
        }
        if self.found.len() < count {
            return false;
        }
        // descending ν = ascending λ̃
        self.found.sort_by(|a, b| b.0.total_cmp(&a.0));
        for ((slot, bound), &(nu, err)) in out.iter_mut().zip(bounds.iter_mut()).zip(&self.found) {
            *slot = 1.0 / nu;
            *bound = err;
        }
        bounds[..count].iter().all(|&b| b <= MASS_CERTIFIED_TOL)
    }

    /// The root ν* = ν_p + τ, τ ∈ (0, gap), and its relative error bound.
    fn root(&mut self, p: usize, gap: f64, inv_mu: f64) -> Option<(f64, f64)> {
        let (nu, w2) = (&self.nu, &self.w2);
        let (nu_p, w2_p) = (nu[p], w2[p]);
        // differences ν_p − ν_j and the weights without pole p (its term is
        // w_p²/τ, kept apart; a zero weight there removes it from the sums)
        self.diff.clear();
        self.diff.extend(nu.iter().map(|v| nu_p - v));
        self.wx.clear();
        self.wx.extend_from_slice(w2);
        self.wx[p] = 0.0;
        let (diff, wx) = (&self.diff, &self.wx);
        // h(τ) = w_p² + τ(R(τ) − 1/μ̃) and h′ = R − 1/μ̃ + τR′
        let h = |tau: f64| {
            let (r, dr) = sums(diff, wx, tau);
            (w2_p + tau * (r - inv_mu), r - inv_mu - tau * dr)
        };
        let (mut lo, mut hi) = (0.0, gap);
        let (h0, dh0) = h(0.0);
        let first = -h0 / dh0;
        let mut tau = if first > 0.0 && first < hi { first } else { 0.5 * hi };
        let mut done = false;
        for _ in 0..200 {
            let (v, dv) = h(tau);
            if v == 0.0 {
                done = true;
                break;
            }
            if v > 0.0 {
                lo = tau;
            } else {
                hi = tau;
            }
            let mut next = tau - v / dv;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            let step = (next - tau).abs();
            tau = next;
            if step <= 4.0 * f64::EPSILON * tau || hi - lo <= 4.0 * f64::EPSILON * tau {
                done = true;
                break;
            }
        }
        if !(done && tau > 0.0 && tau.is_finite()) {
            return None;
        }
        let root = nu_p + tau;
        // the first-order bound of the module doc
        let (mut slope, mut df, mut size) = (0.0, 0.0, inv_mu);
        for j in 0..nu.len() {
            let x = if j == p { tau } else { diff[j] + tau };
            let (a, q) = (x.abs(), 1.0 / (x * x));
            slope += w2[j] * q;
            df += self.dw2[j] / a + w2[j] * self.dnu[j] * q;
            size += w2[j] / a;
        }
        df += 4.0 * nu.len() as f64 * f64::EPSILON * size;
        let bound = df / (slope * root) + 4.0 * f64::EPSILON;
        bound.is_finite().then_some((root, bound))
    }
}

/// (Σ_j w_j/(d_j + τ), Σ_j w_j/(d_j + τ)²) in four interleaved lanes: the
/// divisions are independent, so they pipeline (and vectorise) instead of
/// waiting on one running sum; this is most of a root's cost.
#[inline]
fn sums(diff: &[f64], w: &[f64], tau: f64) -> (f64, f64) {
    let (mut r, mut dr) = ([0.0f64; 4], [0.0f64; 4]);
    let (dc, wc) = (diff.chunks_exact(4), w.chunks_exact(4));
    let (d_rest, w_rest) = (dc.remainder(), wc.remainder());
    for (d, w) in dc.zip(wc) {
        for l in 0..4 {
            let q = 1.0 / (d[l] + tau);
            r[l] += w[l] * q;
            dr[l] += w[l] * q * q;
        }
    }
    let (mut r_sum, mut dr_sum) = ((r[0] + r[1]) + (r[2] + r[3]), (dr[0] + dr[1]) + (dr[2] + dr[3]));
    for (d, w) in d_rest.iter().zip(w_rest) {
        let q = 1.0 / (d + tau);
        r_sum += w * q;
        dr_sum += w * q * q;
    }
    (r_sum, dr_sum)
}

/// The piece from the process-wide cache, built (outside the lock) if missing.
fn fetch(mesh: &UnitMesh, p: usize) -> Entry {
    let key = (mesh.elements, mesh.support, p);
    if let Some(e) = global().lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
        return e.clone();
    }
    let built = Arc::new(build_piece(mesh, p));
    // an entry another thread inserted meanwhile is the same bits
    global().lock().unwrap_or_else(|e| e.into_inner()).entry(key).or_insert(built).clone()
}

/// λ̃_1..λ̃_count of the Euler–Bernoulli pencil with a point mass μ̃ = m/(ρAL)
/// at x̃ = x/L, ẽ = e0a/L, from the secular equation over the interpolated
/// spectrum, with each value's relative error bound; `None` where the solver
/// would take the direct path. The values [`crate::beam::ModalSolver`] uses,
/// exposed for tests.
pub fn point_mass_eigenvalues(
    elements: usize,
    support: Support,
    e_tilde: f64,
    mu: f64,
    x: f64,
    count: usize,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let mesh = UnitMesh::new(elements, support);
    let (mut out, mut bounds) = (vec![0.0; count], vec![0.0; count]);
    MassSpectrumTable::default()
        .lambdas(&mesh, e_tilde * e_tilde, mu, x, &mut out, &mut bounds)
        .then_some((out, bounds))
}

/// The same eigenvalues by the direct banded solve of the assembled pencil
/// (K̃, M̃ + μ̃NNᵀ) (Newton–Maehly, `eigen.rs`): the reference this path replaces.
pub fn point_mass_direct_eigenvalues(
    elements: usize,
    support: Support,
    e_tilde: f64,
    mu: f64,
    x: f64,
    count: usize,
) -> Option<Vec<f64>> {
    let mesh = UnitMesh::new(elements, support);
    let params =
        PencilParams { e_tilde, point_mass: Some((mu, x)), spring: [0.0; 2], axial: 0.0, shear: 0.0, gradient: 0.0 };
    let (k, m) = mesh.pencil(&params);
    let pairs = lowest_eigenpairs(&k, &m, count, &mut Vec::new(), &|v| mesh.pencil_stiffness(&params, v)).ok()?;
    Some(pairs.iter().map(|p| p.lambda).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The secular roots of a pencil whose whole spectrum is known in closed
    /// form: a diagonal (K, M) = (diag λ, I) with a rank-one mass, against
    /// nalgebra's dense symmetric eigenvalues of diag ν + μ̃wwᵀ.
    #[test]
    fn secular_roots_match_a_dense_rank_one_update() {
        let nu: Vec<f64> = (1..=12).map(|j| 1.0 / (j as f64).powi(4)).collect();
        for (mu, seed) in [(1e-3, 0.3), (0.1, 0.7), (1.0, 0.45), (10.0, 0.9)] {
            let u: Vec<f64> = (1..=12).map(|j| (seed * j as f64 * 2.1).sin() * 1.4).collect();
            let mut table = MassSpectrumTable {
                nu: nu.clone(),
                w2: nu.iter().zip(&u).map(|(v, u)| v * u * u).collect(),
                dw2: vec![0.0; 12],
                dnu: vec![0.0; 12],
                ..Default::default()
            };
            let (mut out, mut bounds) = (vec![0.0; 6], vec![0.0; 6]);
            assert!(table.roots(mu, 6, &mut out, &mut bounds));
            let w = nalgebra::DVector::from_iterator(12, table.w2.iter().map(|v| v.sqrt()));
            let a =
                nalgebra::DMatrix::from_diagonal(&nalgebra::DVector::from_vec(nu.clone())) + &w * w.transpose() * mu;
            let mut eig: Vec<f64> = nalgebra::SymmetricEigen::new(a).eigenvalues.iter().copied().collect();
            eig.sort_by(|a, b| b.total_cmp(a));
            for (got, want) in out.iter().zip(&eig) {
                // dense: absolute error ~ n·eps·‖A‖ ≤ 12·2.2e-16·(1 + 12·1.96·μ̃)
                // against ν ≥ ν₆ = 7.7e-4: relative ≤ 1e-9 for μ̃ ≤ 10
                let tol = 1e-9;
                assert!(((1.0 / got) - want).abs() <= tol * want, "μ̃ {mu}: {} vs {want}", 1.0 / got);
            }
        }
    }
}
