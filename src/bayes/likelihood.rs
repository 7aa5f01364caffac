//! Gaussian likelihood with diagonal covariance, eqs. (26), (38), scaled by β²
//! as in eq. (41): Σ̃ = β² Σεε.

use statrs::distribution::{Continuous, Normal};

/// log L = −½ Σ r_k²/(β² σ_k²) − Σ ln(β σ_k) − (n/2) ln 2π with r = y − A(θ).
///
/// The normalising constant depends on β and is kept. A NaN prediction gives
/// NaN (samplers count it as a rejection).
pub fn gaussian_log_likelihood(observed: &[f64], predicted: &[f64], sd: &[f64], beta: f64) -> f64 {
    debug_assert_eq!(observed.len(), predicted.len());
    debug_assert_eq!(observed.len(), sd.len());
    observed
        .iter()
        .zip(predicted)
        .zip(sd)
        .map(|((&y, &p), &s)| match Normal::new(p, beta * s) {
            Ok(n) => n.ln_pdf(y),
            Err(_) => f64::NAN, // a NaN prediction (or sd): the sampler counts it as a rejection
        })
        .sum()
}

/// The same log-likelihood with the normalising constant −Σ ln σ_k − (n/2) ln 2π
/// computed once: a sampler evaluates it at every proposal, and
/// [`gaussian_log_likelihood`] (statrs' `ln_pdf`) takes one logarithm per
/// observation per call. Equal to it up to rounding (tested).
#[derive(Debug, Clone, PartialEq)]
pub struct DiagonalGaussian {
    observed: Vec<f64>,
    inv_sd: Vec<f64>,
    log_norm: f64,
}

impl DiagonalGaussian {
    pub fn new(observed: &[f64], sd: &[f64]) -> Self {
        debug_assert_eq!(observed.len(), sd.len());
        let n = observed.len() as f64;
        let log_norm = -sd.iter().map(|s| s.ln()).sum::<f64>() - 0.5 * n * (2.0 * std::f64::consts::PI).ln();
        Self { observed: observed.to_vec(), inv_sd: sd.iter().map(|s| 1.0 / s).collect(), log_norm }
    }

    /// log L = −½ Σ r_k²/(β² σ_k²) − n ln β + log_norm; NaN for a NaN
    /// prediction or β ≤ 0 (as statrs' `Normal::new` refuses).
    pub fn log_likelihood(&self, predicted: &[f64], beta: f64) -> f64 {
        debug_assert_eq!(predicted.len(), self.observed.len());
        if !(beta > 0.0 && beta.is_finite()) {
            return f64::NAN;
        }
        let ss: f64 = self
            .observed
            .iter()
            .zip(predicted)
            .zip(&self.inv_sd)
            .map(|((y, p), w)| {
                let z = (y - p) * w;
                z * z
            })
            .sum();
        let n = self.observed.len() as f64;
        let log_beta = if beta == 1.0 { 0.0 } else { beta.ln() };
        -0.5 * ss / (beta * beta) - n * log_beta + self.log_norm
    }
}

/// Standardised residuals (y − A(θ)) / σ.
pub fn standardized_residuals(observed: &[f64], predicted: &[f64], sd: &[f64]) -> Vec<f64> {
    observed.iter().zip(predicted).zip(sd).map(|((y, p), s)| (y - p) / s).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the density of independent normals written out directly.
    #[test]
    fn equals_product_of_normal_densities() {
        let y = [1.0, 2.0, 3.5];
        let p = [1.1, 1.7, 3.0];
        let s: [f64; 3] = [0.1, 0.2, 0.5];
        let beta = 1.7;
        let direct: f64 = (0..3)
            .map(|k| {
                let sd = beta * s[k];
                let z = (y[k] - p[k]) / sd;
                (-0.5 * z * z).exp() / (sd * (2.0 * std::f64::consts::PI).sqrt())
            })
            .product::<f64>()
            .ln();
        assert!((gaussian_log_likelihood(&y, &p, &s, beta) - direct).abs() < 1e-12);
        assert!(gaussian_log_likelihood(&y, &[f64::NAN, 0.0, 0.0], &s, 1.0).is_nan());
    }

    /// The precomputed form equals statrs' densities up to rounding: a sum of
    /// ~3n terms of size ≤ |log L| each rounded once (≤ 1e-15 relative), so
    /// 1e-13·max(1, |log L|) is a safe bound.
    #[test]
    fn diagonal_gaussian_equals_the_statrs_sum() {
        let y = [8.8e11, 2.9e12, 0.05, 0.016];
        let s = [2.6e9, 9e9, 0.0015, 0.0005];
        let g = DiagonalGaussian::new(&y, &s);
        for (k, beta) in [1.0, 0.3, 2.5, 4.0].into_iter().enumerate() {
            let p = [8.81e11 + 1e9 * k as f64, 2.95e12, 0.049, 0.0161 - 1e-4 * k as f64];
            let reference = gaussian_log_likelihood(&y, &p, &s, beta);
            let fast = g.log_likelihood(&p, beta);
            assert!((fast - reference).abs() <= 1e-13 * reference.abs().max(1.0), "{fast} vs {reference}");
        }
        assert!(g.log_likelihood(&[f64::NAN, 0.0, 0.0, 0.0], 1.0).is_nan());
        assert!(g.log_likelihood(&y, 0.0).is_nan());
    }
}
