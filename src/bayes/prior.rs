//! Prior densities with their supports.
//!
//! Written in YAML as an internally tagged map:
//! `{dist: uniform, lower, upper}`, `{dist: normal, mean, sd}`,
//! `{dist: inverse-gamma, shape, scale}` (pdf b^a/Γ(a) x^(−a−1) e^(−b/x);
//! Case 3 puts IG(9.5, 11.1) on β²), `{dist: log-uniform, lower, upper}`
//! (density ∝ 1/x on [lower, upper]), `{dist: asinh-uniform, lower, upper,
//! scale}` (uniform in asinh(x/scale): density ∝ 1/√(x² + scale²) on
//! [lower, upper], flat for |x| ≪ scale and log-uniform in |x| for
//! |x| ≫ scale, so one prior spans a signed quantity near 0 and decades of
//! it on one side; `diagnose`'s axial force from compression to the string
//! regime).

use rand::RngCore;
use rand_distr::{Distribution, Normal, Uniform};
use serde::{Deserialize, Serialize};
use statrs::function::gamma::ln_gamma;

use crate::error::InputError;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "dist", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Prior {
    Uniform { lower: f64, upper: f64 },
    Normal { mean: f64, sd: f64 },
    InverseGamma { shape: f64, scale: f64 },
    LogUniform { lower: f64, upper: f64 },
    AsinhUniform { lower: f64, upper: f64, scale: f64 },
}

/// asinh(lower/scale) and asinh(upper/scale): the support of an
/// [`Prior::AsinhUniform`] in its uniform coordinate.
fn asinh_bounds(lower: f64, upper: f64, scale: f64) -> (f64, f64) {
    ((lower / scale).asinh(), (upper / scale).asinh())
}

impl Prior {
    /// Checks the parameters; `field` names the prior in the error.
    pub fn validate(&self, field: &str) -> Result<(), InputError> {
        let finite = |name: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(InputError::new(format!("{field}.{name}"), v, "a finite number"))
            }
        };
        match *self {
            Prior::Uniform { lower, upper } => {
                finite("lower", lower)?;
                finite("upper", upper)?;
                if upper <= lower {
                    return Err(InputError::new(format!("{field}.upper"), upper, format!("> lower = {lower}")));
                }
            }
            Prior::Normal { mean, sd } => {
                finite("mean", mean)?;
                crate::error::positive(&format!("{field}.sd"), sd)?;
            }
            Prior::InverseGamma { shape, scale } => {
                crate::error::positive(&format!("{field}.shape"), shape)?;
                crate::error::positive(&format!("{field}.scale"), scale)?;
            }
            Prior::LogUniform { lower, upper } => {
                crate::error::positive(&format!("{field}.lower"), lower)?;
                finite("upper", upper)?;
                if upper <= lower {
                    return Err(InputError::new(format!("{field}.upper"), upper, format!("> lower = {lower}")));
                }
            }
            Prior::AsinhUniform { lower, upper, scale } => {
                finite("lower", lower)?;
                finite("upper", upper)?;
                crate::error::positive(&format!("{field}.scale"), scale)?;
                if upper <= lower {
                    return Err(InputError::new(format!("{field}.upper"), upper, format!("> lower = {lower}")));
                }
            }
        }
        Ok(())
    }

    /// Closed support [lo, hi] (±∞ where unbounded).
    pub fn support(&self) -> (f64, f64) {
        match *self {
            Prior::Uniform { lower, upper }
            | Prior::LogUniform { lower, upper }
            | Prior::AsinhUniform { lower, upper, .. } => (lower, upper),
            Prior::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Prior::InverseGamma { .. } => (0.0, f64::INFINITY),
        }
    }

    pub fn in_support(&self, x: f64) -> bool {
        let (lo, hi) = self.support();
        match self {
            Prior::InverseGamma { .. } => x > 0.0 && x.is_finite(),
            _ => x >= lo && x <= hi && x.is_finite(),
        }
    }

    /// log density, `NEG_INFINITY` outside the support.
    pub fn ln_pdf(&self, x: f64) -> f64 {
        if !self.in_support(x) {
            return f64::NEG_INFINITY;
        }
        match *self {
            Prior::Uniform { lower, upper } => -(upper - lower).ln(),
            Prior::Normal { mean, sd } => statrs::distribution::Continuous::ln_pdf(
                &statrs::distribution::Normal::new(mean, sd).expect("validated sd > 0"),
                x,
            ),
            Prior::InverseGamma { shape, scale } => {
                shape * scale.ln() - ln_gamma(shape) - (shape + 1.0) * x.ln() - scale / x
            }
            Prior::LogUniform { lower, upper } => -x.ln() - (upper / lower).ln().ln(),
            Prior::AsinhUniform { lower, upper, scale } => {
                let (a, b) = asinh_bounds(lower, upper, scale);
                -x.hypot(scale).ln() - (b - a).ln()
            }
        }
    }

    /// One draw.
    pub fn sample(&self, rng: &mut dyn RngCore) -> f64 {
        match *self {
            Prior::Uniform { lower, upper } => Uniform::new_inclusive(lower, upper).sample(rng),
            Prior::Normal { mean, sd } => Normal::new(mean, sd).expect("validated sd > 0").sample(rng),
            Prior::InverseGamma { shape, scale } => {
                // X ~ IG(a, b)  <=>  1/X ~ Gamma(shape a, rate b) = Gamma(a, scale 1/b).
                let g = rand_distr::Gamma::new(shape, 1.0 / scale).expect("validated shape, scale > 0");
                1.0 / g.sample(rng)
            }
            Prior::LogUniform { lower, upper } => {
                (Uniform::new_inclusive(lower.ln(), upper.ln()).sample(rng)).exp().clamp(lower, upper)
            }
            Prior::AsinhUniform { lower, upper, scale } => {
                let (a, b) = asinh_bounds(lower, upper, scale);
                (scale * Uniform::new_inclusive(a, b).sample(rng).sinh()).clamp(lower, upper)
            }
        }
    }

    /// Mean, where finite.
    pub fn mean(&self) -> Option<f64> {
        match *self {
            Prior::Uniform { lower, upper } => Some(0.5 * (lower + upper)),
            Prior::Normal { mean, .. } => Some(mean),
            Prior::InverseGamma { shape, scale } => (shape > 1.0).then(|| scale / (shape - 1.0)),
            Prior::LogUniform { lower, upper } => Some((upper - lower) / (upper / lower).ln()),
            // x = s·sinh u with u ~ U[a, b]: E x = s (cosh b − cosh a)/(b − a)
            Prior::AsinhUniform { lower, upper, scale } => {
                let (a, b) = asinh_bounds(lower, upper, scale);
                Some(scale * (b.cosh() - a.cosh()) / (b - a))
            }
        }
    }

    /// Standard deviation, where finite.
    pub fn sd(&self) -> Option<f64> {
        match *self {
            Prior::Uniform { lower, upper } => Some((upper - lower) / 12f64.sqrt()),
            Prior::Normal { sd, .. } => Some(sd),
            Prior::InverseGamma { shape, scale } => (shape > 2.0).then(|| scale / (shape - 1.0) / (shape - 2.0).sqrt()),
            Prior::LogUniform { lower, upper } => {
                let l = (upper / lower).ln();
                let m = (upper - lower) / l;
                let m2 = (upper * upper - lower * lower) / (2.0 * l);
                Some((m2 - m * m).max(0.0).sqrt())
            }
            // E x² = s² E sinh² u = s² (E cosh 2u − 1)/2, E cosh 2u = (sinh 2b − sinh 2a)/(2(b − a))
            Prior::AsinhUniform { lower, upper, scale } => {
                let (a, b) = asinh_bounds(lower, upper, scale);
                let m = scale * (b.cosh() - a.cosh()) / (b - a);
                let m2 = scale * scale * (((2.0 * b).sinh() - (2.0 * a).sinh()) / (2.0 * (b - a)) - 1.0) / 2.0;
                Some((m2 - m * m).max(0.0).sqrt())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// ∫ pdf = 1 by the trapezoidal rule on a fine grid: the error of the
    /// rule for these smooth densities is < 1e-6 with 200 001 points.
    #[test]
    fn densities_integrate_to_one() {
        let priors = [
            Prior::Uniform { lower: -1.0, upper: 3.0 },
            Prior::Normal { mean: 1.0, sd: 0.5 },
            Prior::InverseGamma { shape: 9.5, scale: 11.1 },
            Prior::LogUniform { lower: 1e-2, upper: 1e2 },
            Prior::AsinhUniform { lower: -0.5, upper: 50.0, scale: 1.0 },
        ];
        for p in priors {
            let (lo, hi) = match p {
                Prior::Normal { mean, sd } => (mean - 12.0 * sd, mean + 12.0 * sd),
                Prior::InverseGamma { .. } => (1e-6, 60.0),
                _ => p.support(),
            };
            let n = 200_000;
            let h = (hi - lo) / n as f64;
            let mut s = 0.0;
            for i in 0..=n {
                let x = lo + i as f64 * h;
                let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                s += w * p.ln_pdf(x).exp();
            }
            // LogUniform's 1/x peak at 1e-2 makes the trapezoid error ~h²·f''/12·width ≈ 2e-4.
            assert!((s * h - 1.0).abs() < 5e-4, "{p:?}: {}", s * h);
        }
    }

    /// Sample means within 5 standard errors (σ/√n) of the analytic mean.
    #[test]
    fn sample_moments_match() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        for p in [
            Prior::InverseGamma { shape: 9.5, scale: 11.1 },
            Prior::LogUniform { lower: 1.0, upper: 100.0 },
            Prior::AsinhUniform { lower: -0.5, upper: 50.0, scale: 1.0 },
        ] {
            let n = 100_000;
            let m: f64 = (0..n).map(|_| p.sample(&mut rng)).sum::<f64>() / n as f64;
            let se = p.sd().unwrap() / (n as f64).sqrt();
            assert!((m - p.mean().unwrap()).abs() < 5.0 * se, "{p:?}: {m}");
        }
    }

    #[test]
    fn validation_names_the_field() {
        let e = Prior::Uniform { lower: 2.0, upper: 1.0 }.validate("parameters.delta.prior").unwrap_err();
        assert_eq!(e.field, "parameters.delta.prior.upper");
        assert!(Prior::Normal { mean: 0.0, sd: -1.0 }.validate("p").is_err());
        assert!(Prior::LogUniform { lower: 0.0, upper: 1.0 }.validate("p").is_err());
        let e = Prior::AsinhUniform { lower: -1.0, upper: 1.0, scale: 0.0 }.validate("p").unwrap_err();
        assert_eq!(e.field, "p.scale");
        assert!(Prior::AsinhUniform { lower: 1.0, upper: 1.0, scale: 1.0 }.validate("p").is_err());
    }
}
