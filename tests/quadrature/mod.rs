//! Gauss–Legendre quadrature on [0, 1], written in the tests (not `src/`'s
//! element quadrature) for the Ritz references of the strain-gradient suites
//! (`beam_strain_gradient`, `beam_gradient_blocks`).

use std::f64::consts::PI;

/// Gauss–Legendre nodes and weights on [0, 1] (n points, Newton on Pₙ).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut t = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 0.0;
            for _ in 0..100 {
                let (mut p0, mut p1) = (1.0, t);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * t * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n as f64 * (t * p1 - p0) / (t * t - 1.0);
                let step = p1 / dp;
                t -= step;
                if step.abs() < 1e-16 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - t * t) * dp * dp);
            (0.5 * (1.0 + t), 0.5 * w)
        })
        .collect()
}
