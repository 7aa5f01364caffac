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

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Level of the Breusch–Pagan test that switches to the sandwich covariance.
pub const DOUBT_LEVEL: f64 = 0.01;

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
}
