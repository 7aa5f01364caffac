//! What the secular paths share (`spring_spectrum`, `mass_blocks`,
//! `spring_mass`): the 2 × 2 wavenumber block's algebra (its pencil, both
//! eigenvalues, the partial-fraction residues), the blocks' spring-free
//! spectrum, and the one certified eigenvalue search: safeguarded Newton
//! whose root is accepted only when an exact inertia count brackets it.

use crate::beam::fast::axial_spectrum::Sym2;
use crate::beam::fast::jet::{Jet, Num};

/// The two eigenvalues of a block must differ by this (relative) for its
/// partial fractions: the residue divides by their difference, whose
/// rounding (~eps of the larger) is then ≤ 1e-8 of it; the blocks of a
/// uniform beam are ≥ 1e-2 apart (bending against rotation or shear), so
/// this only guards a degenerate pencil, which takes the block form.
pub(crate) const RESIDUE_GAP: f64 = 1e-8;

/// Safeguarded Newton on the real axis stops after a step ≤ EIGEN_TOL·λ.
pub(crate) const EIGEN_TOL: f64 = 1e-13;

pub(crate) const EIGEN_MAX_STEPS: usize = 100;

/// The count must be r − 1 at λ(1 − CERTIFY_GAP) and ≥ r at λ(1 + CERTIFY_GAP):
/// far above the eigenvalue's rounding (≲ 1e-12 relative, above), far below
/// any gap between two eigenvalues of a mesh a diagnosis fits (≥ 1e-2).
pub const CERTIFY_GAP: f64 = 1e-10;

/// One wavenumber block at (ẽ², ñ): M_j, K_j (relaxed), N_j (elastic), d_j
/// and σ_j = (−1)^j; a 1 × 1 block (j = 0, n_e) keeps its entry in `vv`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Block {
    pub(crate) m: Sym2,
    pub(crate) k: Sym2,
    pub(crate) n: Sym2,
    pub(crate) d: f64,
    pub(crate) sign: f64,
    pub(crate) single: bool,
}

impl Block {
    /// (B_uu or 1, det B) of B = pM + qK + N (module doc), with derivatives.
    pub(crate) fn parts<T: Num>(&self, p: Jet<T>, q: Jet<T>) -> (Jet<T>, Jet<T>) {
        let e = |m: f64, k: f64, n: f64| p.scale(m).add(q.scale(k)).add(Jet::c(n));
        let vv = e(self.m.vv, self.k.vv, self.n.vv);
        if self.single {
            return (Jet::c(1.0), vv);
        }
        let uu = e(self.m.uu, self.k.uu, self.n.uu);
        let uv = e(self.m.uv, self.k.uv, self.n.uv);
        (uu, uu.mul(vv).sub(uv.mul(uv)))
    }

    /// The block's real matrices S − λM with S = K + N.
    pub(crate) fn shifted(&self, lambda: f64) -> Sym2 {
        self.k.plus(1.0, self.n).plus(-lambda, self.m)
    }

    /// Both eigenvalues (low, high) of a 2 × 2 pencil (S, M), S = K + N: the
    /// roots of det M·μ² − (S_uu M_vv + S_vv M_uu − 2S_uv M_uv)μ + det S, the
    /// lower one as det S/(det M·high) (no cancellation); `None` when M is not
    /// positive definite or the roots are not real.
    pub(crate) fn eigenvalues(&self) -> Option<(f64, f64)> {
        let (s, m) = (self.k.plus(1.0, self.n), self.m);
        let a = m.uu * m.vv - m.uv * m.uv;
        let bb = s.uu * m.vv + s.vv * m.uu - 2.0 * s.uv * m.uv;
        let c = s.uu * s.vv - s.uv * s.uv;
        let disc = bb * bb - 4.0 * a * c;
        if !(a > 0.0 && disc >= 0.0) {
            return None;
        }
        let up = (bb + disc.sqrt()) / (2.0 * a);
        Some((c / (a * up), up))
    }

    /// The residue c = φ_v²/d of eigenvalue `mu` (one of
    /// [`Self::eigenvalues`], bitwise, or the 1 × 1 block's) in
    /// [B⁻¹]_vv/d = Σ c/(p + qμ) when N = 0 (module doc, "Partial
    /// fractions"); `None` when the block's two eigenvalues are too close for
    /// the split to be accurate.
    pub(crate) fn residue(&self, mu: f64) -> Option<f64> {
        if self.single {
            return Some(1.0 / (self.d * self.m.vv));
        }
        let (low, up) = self.eigenvalues()?;
        let other = if mu == low { up } else { low };
        if !((other - mu).abs() > RESIDUE_GAP * other.abs().max(mu.abs())) {
            return None;
        }
        let m = self.m;
        let c = (self.k.uu - mu * m.uu) / ((m.uu * m.vv - m.uv * m.uv) * (other - mu) * self.d);
        c.is_finite().then_some(c)
    }
}

/// Eigenvalue r0 + 1 of a secular path (this file's, `mass_blocks.rs`'s,
/// `spring_mass.rs`'s), certified: safeguarded Newton on the pole-free g
/// from `x` inside the bracket (a, b), every count narrowing the bracket, and
/// a root accepted only when the count is r0 just below it and > r0 just
/// above it (relative gap [`CERTIFY_GAP`]); `None` where the path declines.
/// `eval(x)` gives g(x) with its derivative and the count at x (`None` where
/// H is singular at x: x is then taken as the root and certified);
/// `count(x)` the count alone.
pub(crate) fn certified_eigenvalue(
    r0: usize,
    (mut a, mut b): (f64, f64),
    mut x: f64,
    eval: impl Fn(f64) -> (Jet<f64>, Option<usize>),
    count: impl Fn(f64) -> Option<usize>,
) -> Option<f64> {
    for _ in 0..EIGEN_MAX_STEPS {
        let (g, n) = eval(x);
        let exact = match n {
            Some(n) if n > r0 => {
                b = x;
                false
            }
            Some(_) => {
                a = x;
                false
            }
            None => true,
        };
        let newton = if exact { x } else { x - g.v / g.d };
        let inside = exact || (newton.is_finite() && newton > a && newton < b);
        // a converged step may land on the bracket's end: the count at x
        // itself (x at the root to rounding) may have set that end
        let on_bracket = newton.is_finite() && newton >= a && newton <= b;
        let converged = (inside || on_bracket) && (newton - x).abs() <= EIGEN_TOL * newton.abs();
        if converged || b - a <= 4.0 * f64::EPSILON * b {
            let lambda = if converged { newton } else { 0.5 * (a + b) };
            // a root of g is λ_r only if the count says so (it may be
            // another eigenvalue in the bracket): otherwise narrow and go on
            let below = count(lambda * (1.0 - CERTIFY_GAP))?;
            let above = count(lambda * (1.0 + CERTIFY_GAP))?;
            if below == r0 && above > r0 {
                return (lambda > 0.0).then_some(lambda);
            }
            if below > r0 {
                b = b.min(lambda * (1.0 - CERTIFY_GAP));
            } else {
                a = a.max(lambda * (1.0 + CERTIFY_GAP));
            }
            if !(a < b) {
                return None;
            }
            x = 0.5 * (a + b);
            continue;
        }
        x = if inside { newton } else { 0.5 * (a + b) };
    }
    None
}

/// The spring-free spectrum of `blocks` (both eigenvalues of every 2 × 2
/// pencil (K + N, M), the entry of every 1 × 1 one) with each eigenvalue's
/// block into `mu`, ascending; `false` when a 2 × 2 pencil has no real
/// eigenvalues (not positive definite in M).
pub(crate) fn block_spectrum(blocks: &[Block], mu: &mut Vec<(f64, usize)>) -> bool {
    mu.clear();
    for (idx, b) in blocks.iter().enumerate() {
        if b.single {
            mu.push(((b.k.vv + b.n.vv) / b.m.vv, idx));
            continue;
        }
        let Some((low, up)) = b.eigenvalues() else { return false };
        mu.push((low, idx));
        mu.push((up, idx));
    }
    mu.sort_by(|x, y| x.0.total_cmp(&y.0));
    true
}
