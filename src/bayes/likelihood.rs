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
}
