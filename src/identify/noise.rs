//! The noise model fitted with the modes: which variance the residuals of
//! a record have, and the covariance of the modal parameters that follows.
//!
//! Candidates (complex, magnitude and time records; a PSD's noise is the
//! Welch bin's Gamma law, relative by construction, see `refine`):
//! - uniform, σ² = a²;
//! - additive + signal-proportional, σ²_i = a² + b²|ŷ_i|² (ŷ the fitted
//!   model at point i), what drive-level and gain fluctuations on top of a
//!   sensor floor give in a lock-in sweep.
//!
//! The second is fitted by maximum likelihood on the residuals (Gaussian,
//! the variance profiled out: for c = b²/a², â²(c) = mean r²/(1 + c|ŷ|²)),
//! and chosen by the BIC (one extra parameter: it wins when the doubled
//! log-likelihood gain exceeds ln m). The modes are then refitted by weighted
//! least squares (weights 1/√(1 + c|ŷ|²), iterated, since ŷ moves with the
//! fit), so ω and ζ get their sd from the weighted fit.
//!
//! Where the chosen model itself is in doubt, the covariance is the
//! sandwich (Huber–White) one, (J̃ᵀJ̃)⁻¹ J̃ᵀ diag(r̃²) J̃ (J̃ᵀJ̃)⁻¹ with the
//! weighted residuals r̃ and Jacobian J̃, which stays consistent whatever the
//! variance law. "In doubt" is a Breusch–Pagan score test (T. S. Breusch &
//! A. R. Pagan, Econometrica 47, 1979) of the standardised squared residuals
//! against ln|ŷ|², m·R² > χ²₁(1 − [`DOUBT_LEVEL`]): variance still trending
//! with the signal after the weighting.
//!
//! Magnitude records are Gaussian only where the signal stands clear of
//! zero. A lab's magnitude of a complex noisy sweep is Rician, |H + ε|; a
//! magnitude with real noise added is folded at zero, |(|H| + e)|. Both
//! depart from N(|H|, σ²) where |H| is within a few σ of zero, near an
//! antiresonance or a node: at |H| = 0 the Rician law has mean 1.25σ and sd
//! 0.66σ, the folded law mean 0.80σ and sd 0.60σ. Such samples bias the
//! fitted background, and their scatter, other than σ, trends with |ŷ|
//! and fires the Breusch–Pagan test on an additive record (60 of 100 folded
//! records, against 5 of 100 of their unfolded twins; tests/identify_coverage.md).
//! The fit keeps every sample (near zero their laws differ, and either
//! would need its own likelihood), but the noise variance and the doubt
//! test come from the samples whose fitted |ŷ_i| stands at least
//! [`MAGNITUDE_FLOOR_SD`] noise sd above zero, where both laws are the
//! Gaussian the covariance assumes.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Level of the Breusch–Pagan test that switches to the sandwich covariance.
pub const DOUBT_LEVEL: f64 = 0.01;

/// How many noise sd a magnitude sample's fitted |ŷ| must stand above zero
/// to count in the noise variance and the doubt test (see the module doc;
/// every sample is fitted). Above K = 3 the two laws are Gaussian
/// but for terms the least squares can carry:
/// - folded: |A + e| differs from A + e only when e < −A, with probability
///   Φ(−K) = 1.3e-3 at the threshold, less above it;
/// - Rician: for A ≫ σ, |A + ε| ≈ A + σ²/(2A) with sd σ, so the mean shifts by
///   at most σ/(2K) = 0.17σ at the threshold, and by 0.025σ at the 20σ a
///   visible resonance stands.
///
/// The samples below it lie where |H| is small: they hold little of a
/// mode's ω and ζ, which come from the samples around its peak.
pub const MAGNITUDE_FLOOR_SD: f64 = 3.0;

/// The noise model reported with an identification.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NoiseModel {
    /// `uniform`, `additive_plus_proportional` or `welch_gamma` (PSD).
    pub kind: &'static str,
    /// a: the sd of the additive part, in the record's units (m/N per
    /// component, m/N or m); PSD: the relative sd 1/√ν̂ of a bin.
    pub additive_sd: f64,
    /// b: the sd proportional to the signal, as a fraction of |ŷ| (0 when uniform).
    pub proportional_fraction: f64,
    /// 2·(ln L_proportional − ln L_uniform) on the first fit's residuals
    /// (the BIC picks the proportional model when it exceeds ln m).
    pub likelihood_ratio: f64,
    /// `model` (σ̂²(J̃ᵀJ̃)⁻¹) or `sandwich` (the noise model in doubt).
    pub covariance: &'static str,
    /// Breusch–Pagan statistic m·R² of the final standardised residuals (χ²₁ under the model).
    pub breusch_pagan: f64,
    /// Magnitude records: the samples whose fitted |ŷ| stands less than
    /// [`MAGNITUDE_FLOOR_SD`] noise sd above zero, left out of the noise
    /// variance and the Breusch–Pagan test (0 for other kinds).
    pub samples_below_floor: usize,
}

/// Which samples of a magnitude record stand above the floor: |ŷ_i| ≥ K·σ_i
/// with σ²_i = a²(1 + c|ŷ_i|²), K = [`MAGNITUDE_FLOOR_SD`], for the squared
/// fitted levels `s2`, the additive variance `a2` and c = b²/a².
pub fn above_the_floor(s2: &[f64], a2: f64, c: f64) -> Vec<bool> {
    let k2 = MAGNITUDE_FLOOR_SD * MAGNITUDE_FLOOR_SD;
    s2.iter().map(|&s| s >= k2 * a2 * (1.0 + c * s)).collect()
}

/// Rounds of [`variance_above_the_floor`]'s fixed point (the floor moves with â).
const FLOOR_ROUNDS: usize = 4;

/// The additive variance a² of a magnitude record from the samples above
/// its floor alone, with the mask: for weighted residuals `r` (sd a where
/// the model holds) and Jacobian `j` of the fit, E Σ_{i∈S} r²_i =
/// a²(|S| − Σ_{i∈S} h_ii) with h_ii the leverages of the hat matrix
/// J(JᵀJ)⁺Jᵀ (the p fitted parameters take their share of each sample's
/// variance). S depends on â, so the two are iterated from `a2` (the
/// estimate from all samples). `None` when every sample stands above the
/// floor, or when too few do (the proportional part alone reaches |ŷ|/K,
/// b ≥ 1/K: no sample is Gaussian, and the estimate from all stands).
pub fn variance_above_the_floor(
    r: &DVector<f64>,
    j: &DMatrix<f64>,
    s2: &[f64],
    a2: f64,
    c: f64,
) -> Option<(Vec<bool>, f64)> {
    let (_, leverage) = crate::identify::covariance::leverages(j)?;
    let variance = |keep: &[bool]| -> Option<f64> {
        let (mut rss, mut dof) = (0.0, 0.0);
        for (i, _) in keep.iter().enumerate().filter(|(_, &k)| k) {
            rss += r[i] * r[i];
            dof += 1.0 - leverage[i];
        }
        (dof >= 1.0 && rss > 0.0).then_some(rss / dof)
    };
    let mut keep = above_the_floor(s2, a2, c);
    for _ in 0..FLOOR_ROUNDS {
        let next = above_the_floor(s2, variance(&keep)?, c);
        if next == keep {
            break;
        }
        keep = next;
    }
    if keep.iter().all(|&k| k) {
        return None;
    }
    let a2 = variance(&keep)?;
    let kept = keep.iter().filter(|&&k| k).count();
    (kept > j.ncols() + 1).then_some((keep, a2))
}

/// The profile log-likelihood (constant dropped) of σ²_i = a²(1 + c·s²_i)
/// for squared residuals `r2` at squared signal levels `s2`, and â².
fn profile(r2: &[f64], s2: &[f64], c: f64) -> (f64, f64) {
    let m = r2.len() as f64;
    let a2 = r2.iter().zip(s2).map(|(r, s)| r / (1.0 + c * s)).sum::<f64>() / m;
    let logdet: f64 = s2.iter().map(|s| (c * s).ln_1p()).sum();
    (-0.5 * (logdet + m * a2.max(f64::MIN_POSITIVE).ln() + m), a2)
}

/// Maximum-likelihood c = b²/a² ≥ 0 (a log grid over 16 decades of c·max s²,
/// then golden-section search in ln c around the best grid point), with its
/// log-likelihood and that of c = 0.
pub fn fit_variance(r2: &[f64], s2: &[f64]) -> (f64, f64, f64) {
    let smax = s2.iter().copied().fold(f64::MIN_POSITIVE, f64::max);
    let (l0, _) = profile(r2, s2, 0.0);
    let grid: Vec<f64> = (0..=64).map(|k| 10f64.powf(-4.0 + 0.25 * k as f64) / smax).collect();
    let (mut best, mut lbest) = (0.0, l0);
    let mut at = None;
    for (k, &c) in grid.iter().enumerate() {
        let (l, _) = profile(r2, s2, c);
        if l > lbest {
            (best, lbest, at) = (c, l, Some(k));
        }
    }
    if let Some(k) = at {
        let (mut lo, mut hi) = (grid[k.saturating_sub(1)].ln(), grid[(k + 1).min(grid.len() - 1)].ln());
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if profile(r2, s2, x1.exp()).0 > profile(r2, s2, x2.exp()).0 {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        let c = (0.5 * (lo + hi)).exp();
        let (l, _) = profile(r2, s2, c);
        if l > lbest {
            (best, lbest) = (c, l);
        }
    }
    (best, lbest, l0)
}

/// â² at c.
pub fn additive_var(r2: &[f64], s2: &[f64], c: f64) -> f64 {
    profile(r2, s2, c).1
}

/// Breusch–Pagan m·R² of u_i = r̃²_i/mean(r̃²) on ln s²_i (with intercept).
pub fn breusch_pagan(r2w: &[f64], s2: &[f64]) -> f64 {
    let m = r2w.len() as f64;
    let mean = r2w.iter().sum::<f64>() / m;
    if !(mean > 0.0) {
        return 0.0;
    }
    let floor = s2.iter().copied().fold(f64::MIN_POSITIVE, f64::max) * 1e-12;
    let z: Vec<f64> = s2.iter().map(|s| (s + floor).ln()).collect();
    let u: Vec<f64> = r2w.iter().map(|r| r / mean).collect();
    let (zm, um) = (z.iter().sum::<f64>() / m, u.iter().sum::<f64>() / m);
    let (mut szz, mut szu, mut suu) = (0.0, 0.0, 0.0);
    for (a, b) in z.iter().zip(&u) {
        szz += (a - zm) * (a - zm);
        szu += (a - zm) * (b - um);
        suu += (b - um) * (b - um);
    }
    if !(szz > 0.0 && suu > 0.0) {
        return 0.0;
    }
    m * szu * szu / (szz * suu)
}

/// The sandwich covariance from weighted residuals `r` and Jacobian `j`,
/// with `bread` = (J̃ᵀJ̃)⁺.
pub fn sandwich(r: &DVector<f64>, j: &DMatrix<f64>, bread: &DMatrix<f64>) -> DMatrix<f64> {
    let mut scaled = j.clone();
    for (i, mut row) in scaled.row_iter_mut().enumerate() {
        row *= r[i];
    }
    let meat = scaled.transpose() * &scaled;
    bread * meat * bread
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Residuals drawn deterministically with variance a²(1 + c s²) (a
    /// fixed ±1 pattern times the sd, whose mean square is exactly 1 over
    /// each block): the ML c must come back close and win the BIC.
    #[test]
    fn proportional_variance_is_recovered() {
        let s2: Vec<f64> = (0..2000).map(|i| (1.0 + (i % 50) as f64).powi(2)).collect();
        let c_true = 4.0;
        let r2: Vec<f64> = s2.iter().map(|s| 1e-6 * (1.0 + c_true * s)).collect();
        let (c, l, l0) = fit_variance(&r2, &s2);
        assert!((c / c_true - 1.0).abs() < 1e-3, "c = {c}");
        assert!(2.0 * (l - l0) > (2000f64).ln());
        // uniform residuals: c = 0 stays best
        let flat = vec![1e-6; 2000];
        let (c, l, l0) = fit_variance(&flat, &s2);
        assert!(2.0 * (l - l0) < 1e-9, "c = {c}");
    }

    /// Magnitudes of a signal with many samples near zero, A_i = 10a|sin 3πx_i|,
    /// made as a lab would, Rician |A + ε| (ε complex, sd a per component),
    /// and folded |A + e|, fitted by one scale factor. Above the floor the
    /// estimate is unbiased for a²: over 200 records its mean is within 0.02
    /// of a² (a record's relative sd is about √(2/m_kept) ≈ 0.08, so the
    /// mean's is 0.006, and the Rician's σ²/(2A) shift of samples just above
    /// the floor adds at most (1/(2K))² ≈ 0.03 of a² on a few of them). The
    /// folded law's estimate from all samples is off by more than that.
    #[test]
    fn the_variance_above_the_floor_is_the_gaussian_one() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, StandardNormal};
        let (m, a) = (400, 1.0e-3);
        let shape: Vec<f64> =
            (0..m).map(|i| 10.0 * a * (3.0 * std::f64::consts::PI * i as f64 / m as f64).sin().abs()).collect();
        for rician in [true, false] {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(42 + u64::from(rician));
            let (mut floor_mean, mut all_mean) = (0.0, 0.0);
            let reps = 200;
            for _ in 0..reps {
                let y: Vec<f64> = shape
                    .iter()
                    .map(|&v| {
                        let (e1, e2): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
                        if rician {
                            (v + a * e1).hypot(a * e2)
                        } else {
                            (v + a * e1).abs()
                        }
                    })
                    .collect();
                let theta =
                    y.iter().zip(&shape).map(|(y, s)| y * s).sum::<f64>() / shape.iter().map(|s| s * s).sum::<f64>();
                let r = DVector::from_iterator(m, y.iter().zip(&shape).map(|(y, s)| theta * s - y));
                let j = DMatrix::from_iterator(m, 1, shape.iter().copied());
                let s2: Vec<f64> = shape.iter().map(|s| (theta * s).powi(2)).collect();
                let all = r.norm_squared() / (m - 1) as f64;
                let (keep, a2) = variance_above_the_floor(&r, &j, &s2, all, 0.0).expect("samples below the floor");
                assert!(keep.iter().filter(|&&k| !k).count() > m / 20);
                floor_mean += a2 / (a * a) / reps as f64;
                all_mean += all / (a * a) / reps as f64;
            }
            assert!((floor_mean - 1.0).abs() < 0.02, "rician {rician}: above the floor {floor_mean}");
            // the folded law's samples near zero scatter less than a
            // (E(|A + e| − A)² = 0.6a² at A = a/2); the Rician's more at
            // A = 0 (2a²) and less beside it, which here nearly cancel
            if !rician {
                assert!(all_mean < 0.98, "folded: all samples {all_mean}");
            }
        }
    }
}
