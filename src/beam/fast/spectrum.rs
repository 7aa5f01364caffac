//! Certified Chebyshev interpolants of the lowest eigenvalues of the
//! Euler–Bernoulli pencil K̃φ = λ̃(M̃₀ + ẽ²M̃₁)φ as functions of t = ẽ² = (e0a/L)²
//! (the forward model at its physical limit: an eigenvalue for the cost of a
//! polynomial evaluation).
//!
//! # Why an interpolant can be exact to round-off
//! In the decoupled model only e0a changes the pencil; the section and the
//! material scale λ = ω_ref²·λ̃ (`model.rs`). So λ̃_r depends on one variable
//! per mesh and support. Its reciprocal μ_r(t) = 1/λ̃_r(t) is the r-th largest
//! eigenvalue of the symmetric *linear* family K̃^{-½}(M̃₀ + tM̃₁)K̃^{-½}, hence
//! analytic in t wherever it is simple (Kato, *Perturbation Theory for Linear
//! Operators*, II §1), with branch points only where two eigenvalues meet off the
//! real axis. For the continuum simply supported beam it is even linear:
//! λ_r = (rπ)⁴/(1 + t(rπ)²) (Eringen's nonlocal beam), μ_r = (1 + t r²π²)/(rπ)⁴;
//! the FE pencil is a small perturbation of that, so the Chebyshev coefficients
//! of μ_r fall to round-off after a few terms (Trefethen, *Approximation Theory
//! and Approximation Practice*, Thm 8.2: geometric decay for analytic functions).
//!
//! # Layout
//! t ∈ [0, T₀) is piece 0 and [T₀·2^(p−1), T₀·2^p) is piece p (dyadic: μ_r changes by
//! less than a factor 2 on a piece, so an absolute Chebyshev error is a relative
//! one), up to t = T₀·2^(PIECES−1) = 128 ≥ (`MAX_E_TILDE`)² = 100. Each (mesh, mode,
//! piece) interpolant is built on first use from direct solves at Chebyshev
//! points of that piece only, so it is a function of (elements, support, mode,
//! piece) alone: which e0a were evaluated before cannot change a bit of it.
//!
//! # Certification (computed, never assumed)
//! For degree n = 8, 16, 32, 64 the interpolant p_n through the n + 1
//! Chebyshev–Lobatto points is compared with the direct banded solve at the n
//! points of the next level it did not use (the Chebyshev points of the first
//! kind, midway in angle between its nodes, where its error peaks), and the
//! degree-2n coefficients beyond n estimate its truncation error (a Chebyshev
//! series' truncation error is at most the sum of the dropped |c_k|):
//!   certificate = max( max |p_n − μ|/|μ| at the check points , 2·Σ_{k>n}|c_k| / min|μ| ).
//! The lowest n with certificate ≤ 5e-13 (half of [`CERTIFIED_TOL`] = 1e-12,
//! see [`ACCEPT_TOL`]) is kept with its
//! certificate; if none qualifies (or a direct solve fails), that (mode, piece)
//! is marked uncertified and the caller uses the direct solve there.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use crate::beam::fe::model::UnitMesh;
use crate::beam::solve::eigen::lowest_eigenpairs;
use crate::beam::spec::Support;

/// Largest certified relative error of an interpolated eigenvalue.
pub const CERTIFIED_TOL: f64 = 1e-12;

/// What a certificate must reach to be kept: half of [`CERTIFIED_TOL`]. The
/// check points and the tail sum estimate the maximum error; the factor 2
/// covers an estimate that is low between check points (for an analytic
/// function the error of a degree-n interpolant between its nodes stays within a
/// small factor of its value at the first-kind points; Trefethen, ATAP, ch. 7–8).
/// Measured: at 4000 random points of 20-element meshes the largest error is
/// 3.4e-13 (`tests/beam_fast_path.rs`). A tenth would not be reachable
/// everywhere: the tail sum adds the direct solve's own ~1e-15 noise over up to
/// 64 coefficients.
const ACCEPT_TOL: f64 = 0.5 * CERTIFIED_TOL;

/// Width of piece 0, [0, T₀) in t = ẽ²: 2⁻¹⁰ (e0a/L < 0.031).
const T0: f64 = 1.0 / 1024.0;
/// Pieces 0..PIECES cover t < T₀·2^(PIECES−1) = 128 (validation: t ≤ 100).
pub const PIECES: usize = 18;
/// Chebyshev–Lobatto levels tried; the finest grid used is 2·64 = 128 intervals.
const LEVELS: [usize; 4] = [8, 16, 32, 64];
const FINEST: usize = 128;

/// One certified interpolant: μ(t) = Σ c_k T_k(x), x = (2t − lo − hi)/(hi − lo).
#[derive(Debug, Clone, PartialEq)]
pub struct Chebyshev {
    lo: f64,
    hi: f64,
    coef: Vec<f64>,
    certificate: Certificate,
}

/// What was measured when an interpolant was certified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Certificate {
    /// Physical mode number (1-based).
    pub mode: usize,
    /// Piece index and its t = (e0a/L)² range [t_lo, t_hi).
    pub piece: usize,
    pub t_lo: f64,
    pub t_hi: f64,
    /// Degree of the kept interpolant.
    pub degree: usize,
    /// Largest relative difference from the direct solve at the check points.
    pub check_error: f64,
    /// 2·Σ_{k>n}|c_k| / min|μ| from the next level's coefficients.
    pub tail_bound: f64,
}

impl Certificate {
    /// The certified relative error bound: max(check error, tail bound).
    pub fn bound(&self) -> f64 {
        self.check_error.max(self.tail_bound)
    }
}

impl Chebyshev {
    /// μ(t) by Clenshaw's recurrence (backward stable: error ≤ a few eps·Σ|c_k|).
    #[inline]
    fn mu(&self, t: f64) -> f64 {
        let x = (2.0 * t - self.lo - self.hi) / (self.hi - self.lo);
        let (mut b1, mut b2) = (0.0, 0.0);
        for &c in self.coef[1..].iter().rev() {
            let b0 = 2.0 * x * b1 - b2 + c;
            b2 = b1;
            b1 = b0;
        }
        x * b1 - b2 + self.coef[0]
    }
}

/// The piece of t (see the module doc), or `None` beyond the last piece.
pub fn piece_of(t: f64) -> Option<usize> {
    if !(t >= 0.0) {
        return None;
    }
    if t < T0 {
        return Some(0);
    }
    // t/T₀ ∈ [2^e, 2^(e+1)) → piece e + 1 (T₀ is a power of two: exact)
    let e = (((t / T0).to_bits() >> 52) & 0x7ff) as usize - 1023;
    (e + 1 < PIECES).then_some(e + 1)
}

/// [t_lo, t_hi) of piece p.
pub fn piece_range(p: usize) -> (f64, f64) {
    if p == 0 {
        (0.0, T0)
    } else {
        let lo = T0 * (1u64 << (p - 1)) as f64;
        (lo, 2.0 * lo)
    }
}

/// μ_r = 1/λ̃_r of the lowest `count` eigenvalues at t by the direct banded solve
/// (Newton–Maehly from scratch, a pure function of (mesh, t); the first r values
/// do not depend on `count`: the eigenvalues are found in order, each from the
/// previous ones only).
fn direct_mu(mesh: &UnitMesh, t: f64, count: usize) -> Option<Vec<f64>> {
    let m = mesh.m0.plus_scaled(t, &mesh.m1);
    let pairs = lowest_eigenpairs(&mesh.k, &m, count, &mut Vec::new(), &|x| mesh.stiffness_form(x, 0.0)).ok()?;
    pairs.iter().map(|p| (p.lambda.is_finite() && p.lambda > 0.0).then(|| 1.0 / p.lambda)).collect()
}

/// Chebyshev coefficients of the degree-n interpolant through the Lobatto values
/// f_j = f(cos(πj/n)), j = 0..=n (a DCT-I: c_k = (2/n)Σ″ f_j cos(πjk/n), ends
/// halved). Hand-written: n ≤ 128 and O(n²) is nothing next to one eigen-solve,
/// and no listed crate provides a DCT-I. The 2n distinct cosines are computed
/// once per call (the same expressions, so the same bits): the table builds
/// call this for every mode, level and DOF, and n² cosines a call were 8 % of
/// a 5-mode diagnosis's CPU (`benches/README.md`).
pub(crate) fn lobatto_coefficients(f: &[f64]) -> Vec<f64> {
    let n = f.len() - 1;
    // jk mod 2n keeps the cosine argument small (exact integer reduction)
    let cos: Vec<f64> = (0..2 * n).map(|m| (std::f64::consts::PI * m as f64 / n as f64).cos()).collect();
    (0..=n)
        .map(|k| {
            let mut s = 0.0;
            for (j, &fj) in f.iter().enumerate() {
                let w = if j == 0 || j == n { 0.5 } else { 1.0 };
                s += w * fj * cos[(j * k) % (2 * n)];
            }
            let c = 2.0 * s / n as f64;
            if k == 0 || k == n {
                0.5 * c
            } else {
                c
            }
        })
        .collect()
}

/// Direct values at the finest Lobatto grid of one piece, solved on demand.
struct Nodes<'a> {
    mesh: &'a UnitMesh,
    lo: f64,
    hi: f64,
    count: usize,
    values: Vec<Option<Vec<f64>>>,
    failed: bool,
}

impl Nodes<'_> {
    fn t(&self, j: usize) -> f64 {
        let x = (std::f64::consts::PI * j as f64 / FINEST as f64).cos();
        0.5 * (self.lo + self.hi) + 0.5 * (self.hi - self.lo) * x
    }

    /// μ of `mode` at the level-n Lobatto nodes (n divides FINEST), or `None`
    /// when a direct solve failed.
    fn level(&mut self, n: usize, mode: usize) -> Option<Vec<f64>> {
        let step = FINEST / n;
        let mut out = Vec::with_capacity(n + 1);
        for j in (0..=FINEST).step_by(step) {
            if self.values[j].is_none() && !self.failed {
                let t = self.t(j);
                self.values[j] = direct_mu(self.mesh, t, self.count);
                self.failed = self.values[j].is_none();
            }
            out.push(self.values[j].as_ref()?[mode - 1]);
        }
        Some(out)
    }
}

/// Builds and certifies the interpolants of modes `modes` on piece `piece`
/// (see the module doc); `None` for a (mode, piece) that cannot be certified.
pub fn build_piece(mesh: &UnitMesh, piece: usize, modes: std::ops::RangeInclusive<usize>) -> Vec<Option<Chebyshev>> {
    let (lo, hi) = piece_range(piece);
    let count = *modes.end();
    let mut nodes = Nodes { mesh, lo, hi, count, values: vec![None; FINEST + 1], failed: false };
    modes.map(|mode| certify(&mut nodes, piece, mode)).collect()
}

fn certify(nodes: &mut Nodes<'_>, piece: usize, mode: usize) -> Option<Chebyshev> {
    for n in LEVELS {
        let fine = nodes.level(2 * n, mode)?;
        let coarse: Vec<f64> = fine.iter().step_by(2).copied().collect();
        let coef = lobatto_coefficients(&coarse);
        let candidate = Chebyshev {
            lo: nodes.lo,
            hi: nodes.hi,
            coef,
            certificate: Certificate {
                mode,
                piece,
                t_lo: nodes.lo,
                t_hi: nodes.hi,
                degree: n,
                check_error: 0.0,
                tail_bound: 0.0,
            },
        };
        let mut check_error = 0.0f64;
        for j in (1..=2 * n).step_by(2) {
            let t = nodes.t(j * FINEST / (2 * n));
            check_error = check_error.max((candidate.mu(t) - fine[j]).abs() / fine[j].abs());
        }
        let fine_coef = lobatto_coefficients(&fine);
        let min_abs = fine.iter().fold(f64::INFINITY, |a, v| a.min(v.abs()));
        let tail_bound = 2.0 * fine_coef[n + 1..].iter().map(|c| c.abs()).sum::<f64>() / min_abs;
        if check_error <= ACCEPT_TOL && tail_bound <= ACCEPT_TOL {
            let mut kept = candidate;
            kept.certificate.check_error = check_error;
            kept.certificate.tail_bound = tail_bound;
            return Some(kept);
        }
    }
    None
}

/// Shared by every solver of the process: keyed by (elements, support, mode,
/// piece), a pure function of its key, so sharing it across threads changes
/// how fast a result comes, never its bits.
type Key = (usize, Support, usize, usize);
type Entry = Arc<Option<Chebyshev>>;

fn global() -> &'static Mutex<HashMap<Key, Entry>> {
    static CACHE: OnceLock<Mutex<HashMap<Key, Entry>>> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// The interpolants of one Euler–Bernoulli mesh seen by one solver: a local
/// index `[mode − 1][piece]` in front of the process-wide cache.
#[derive(Debug, Default, Clone)]
pub struct SpectrumTable {
    local: Vec<[Option<Entry>; PIECES]>,
}

impl SpectrumTable {
    /// λ̃_1..λ̃_n at t = ẽ² into `out` (length n) from certified interpolants,
    /// building missing pieces; `false` when t is beyond the last piece or a
    /// needed (mode, piece) is uncertified (the caller then solves directly).
    pub fn lambdas(&mut self, mesh: &UnitMesh, t: f64, out: &mut [f64]) -> bool {
        // interpolated in ẽ² alone: the strain-gradient pencil has l̃² too
        if mesh.gradient.is_some() {
            return false;
        }
        let Some(p) = piece_of(t) else { return false };
        let n = out.len();
        if self.local.len() < n || self.local[..n].iter().any(|row| row[p].is_none()) {
            self.fill(mesh, p, n);
        }
        for (r, slot) in out.iter_mut().enumerate() {
            match self.local[r][p].as_deref() {
                Some(Some(cheb)) => *slot = 1.0 / cheb.mu(t),
                _ => return false,
            }
        }
        true
    }

    /// Fills the local rows 1..=n of piece p from the global cache, building
    /// (outside the lock) whatever is missing there too.
    fn fill(&mut self, mesh: &UnitMesh, p: usize, n: usize) {
        if self.local.len() < n {
            self.local.resize_with(n, Default::default);
        }
        let key = |r: usize| (mesh.elements, mesh.support, r, p);
        let missing: Vec<usize> = {
            let cache = global().lock().unwrap_or_else(|e| e.into_inner());
            (1..=n).filter(|&r| !cache.contains_key(&key(r))).collect()
        };
        if let Some(&first) = missing.first() {
            let built = build_piece(mesh, p, first..=n);
            let mut cache = global().lock().unwrap_or_else(|e| e.into_inner());
            for (r, cheb) in (first..=n).zip(built) {
                // an entry another thread inserted meanwhile is the same bits
                cache.entry(key(r)).or_insert_with(|| Arc::new(cheb));
            }
        }
        let cache = global().lock().unwrap_or_else(|e| e.into_inner());
        for r in 1..=n {
            self.local[r - 1][p] = cache.get(&key(r)).cloned();
        }
    }
}

/// The certificate of every (mode, piece) interpolant of an Euler–Bernoulli
/// mesh covering t = (e0a/L)² ∈ [0, t_max] for modes 1..=modes (building them if
/// needed); `None` entries are pieces that could not be certified (the solver
/// uses the direct solve there).
pub fn certificates(elements: usize, support: Support, modes: usize, t_max: f64) -> Vec<Option<Certificate>> {
    let mesh = UnitMesh::new(elements, support);
    let mut table = SpectrumTable::default();
    let last = piece_of(t_max).unwrap_or(PIECES - 1);
    let mut out = Vec::new();
    for p in 0..=last {
        table.fill(&mesh, p, modes);
        for r in 0..modes {
            out.push(table.local[r][p].as_deref().and_then(|c| c.as_ref()).map(|c| c.certificate));
        }
    }
    out
}

/// λ̃_1..λ̃_count of the Euler–Bernoulli pencil at ẽ = e0a/L from the certified
/// interpolants (`None` beyond the interpolated range or where a piece is not
/// certified): the values [`crate::beam::ModalSolver`] uses, exposed for tests.
pub fn interpolated_eigenvalues(elements: usize, support: Support, e_tilde: f64, count: usize) -> Option<Vec<f64>> {
    let mesh = UnitMesh::new(elements, support);
    let mut out = vec![0.0; count];
    SpectrumTable::default().lambdas(&mesh, e_tilde * e_tilde, &mut out).then_some(out)
}

/// The same eigenvalues by the direct banded solve the interpolants are
/// certified against (`None` if it fails).
pub fn direct_eigenvalues(elements: usize, support: Support, e_tilde: f64, count: usize) -> Option<Vec<f64>> {
    let mesh = UnitMesh::new(elements, support);
    direct_mu(&mesh, e_tilde * e_tilde, count).map(|mu| mu.iter().map(|m| 1.0 / m).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pieces_tile_the_range() {
        assert_eq!(piece_of(0.0), Some(0));
        assert_eq!(piece_of(T0 * 0.999), Some(0));
        assert_eq!(piece_of(T0), Some(1));
        for p in 1..PIECES {
            let (lo, hi) = piece_range(p);
            assert_eq!(piece_of(lo), Some(p));
            assert_eq!(piece_of(0.5 * (lo + hi)), Some(p));
            assert_eq!(piece_of(hi * (1.0 - f64::EPSILON)), Some(p));
        }
        assert_eq!(piece_of(piece_range(PIECES - 1).1), None);
        assert!(piece_range(PIECES - 1).1 >= crate::beam::spec::MAX_E_TILDE.powi(2));
        assert_eq!(piece_of(-1.0), None);
        assert_eq!(piece_of(f64::NAN), None);
    }

    #[test]
    fn chebyshev_interpolation_reproduces_a_polynomial() {
        // degree ≤ n is interpolated exactly (up to rounding in the DCT: ~n·eps)
        let n = 8;
        let f: Vec<f64> = (0..=n)
            .map(|j| {
                let x = (std::f64::consts::PI * j as f64 / n as f64).cos();
                1.0 + 0.5 * x - 0.25 * x.powi(3) + 0.125 * x.powi(7)
            })
            .collect();
        let coef = lobatto_coefficients(&f);
        let cheb = Chebyshev {
            lo: -1.0,
            hi: 1.0,
            coef,
            certificate: Certificate {
                mode: 1,
                piece: 0,
                t_lo: -1.0,
                t_hi: 1.0,
                degree: n,
                check_error: 0.0,
                tail_bound: 0.0,
            },
        };
        for i in 0..=50 {
            let x = -1.0 + 2.0 * i as f64 / 50.0;
            let exact = 1.0 + 0.5 * x - 0.25 * x.powi(3) + 0.125 * x.powi(7);
            // 9 coefficients, each with ~9 rounded products: 1e-14 is > 50 eps
            assert!((cheb.mu(x) - exact).abs() <= 1e-14, "{x}");
        }
    }

    /// The interpolant of mode r does not depend on how many modes were built
    /// with it (the order of the direct solve): the history invariant.
    #[test]
    fn a_mode_interpolant_does_not_depend_on_the_mode_count() {
        let mesh = UnitMesh::new(12, Support::ClampedFree);
        for p in [0, 5] {
            let three = build_piece(&mesh, p, 1..=3);
            let six = build_piece(&mesh, p, 1..=6);
            let from_two = build_piece(&mesh, p, 2..=3);
            assert_eq!(three[..], six[..3]);
            assert_eq!(three[1..], from_two[..]);
            assert!(three.iter().all(|c| c.is_some()), "piece {p} not certified");
        }
    }
}
