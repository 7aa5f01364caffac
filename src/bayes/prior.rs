//! TEMPORARY stand-in written on branch `diagnose` so the crate compiles before
//! the bayes helper's `prior` lands; on merge the real module replaces this file.
//! Priors: uniform, normal, inverse-gamma, log-uniform.

use rand::RngCore;
use rand_distr::{Distribution, Gamma, Normal, Uniform};
use serde::{Deserialize, Serialize};

use crate::error::InputError;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "dist", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Prior {
    Uniform { lower: f64, upper: f64 },
    Normal { mean: f64, sd: f64 },
    InverseGamma { shape: f64, scale: f64 },
    LogUniform { lower: f64, upper: f64 },
}

impl Prior {
    pub fn validate(&self, field: &str) -> Result<(), InputError> {
        let ok = match *self {
            Prior::Uniform { lower, upper } => lower.is_finite() && upper.is_finite() && lower < upper,
            Prior::Normal { mean, sd } => mean.is_finite() && sd.is_finite() && sd > 0.0,
            Prior::InverseGamma { shape, scale } => shape > 0.0 && scale > 0.0 && shape.is_finite() && scale.is_finite(),
            Prior::LogUniform { lower, upper } => lower > 0.0 && upper.is_finite() && lower < upper,
        };
        if ok {
            Ok(())
        } else {
            Err(InputError::new(field, format!("{self:?}"), "a proper prior"))
        }
    }

    pub fn support(&self) -> (f64, f64) {
        match *self {
            Prior::Uniform { lower, upper } | Prior::LogUniform { lower, upper } => (lower, upper),
            Prior::Normal { .. } => (f64::NEG_INFINITY, f64::INFINITY),
            Prior::InverseGamma { .. } => (0.0, f64::INFINITY),
        }
    }

    pub fn sd(&self) -> Option<f64> {
        match *self {
            Prior::Uniform { lower, upper } => Some((upper - lower) / 12f64.sqrt()),
            Prior::Normal { sd, .. } => Some(sd),
            Prior::InverseGamma { shape, scale } => (shape > 2.0).then(|| scale / (shape - 1.0) / (shape - 2.0).sqrt()),
            Prior::LogUniform { .. } => None,
        }
    }

    pub fn ln_pdf(&self, x: f64) -> f64 {
        match *self {
            Prior::Uniform { lower, upper } => {
                if x >= lower && x <= upper { -(upper - lower).ln() } else { f64::NEG_INFINITY }
            }
            Prior::Normal { mean, sd } => {
                let z = (x - mean) / sd;
                -0.5 * z * z - sd.ln() - 0.5 * (2.0 * std::f64::consts::PI).ln()
            }
            Prior::InverseGamma { shape, scale } => {
                if x > 0.0 {
                    shape * scale.ln() - statrs::function::gamma::ln_gamma(shape) - (shape + 1.0) * x.ln() - scale / x
                } else {
                    f64::NEG_INFINITY
                }
            }
            Prior::LogUniform { lower, upper } => {
                if x >= lower && x <= upper { -x.ln() - (upper / lower).ln() } else { f64::NEG_INFINITY }
            }
        }
    }

    pub fn sample(&self, rng: &mut dyn RngCore) -> f64 {
        match *self {
            Prior::Uniform { lower, upper } => Uniform::new_inclusive(lower, upper).sample(rng),
            Prior::Normal { mean, sd } => Normal::new(mean, sd).expect("valid").sample(rng),
            Prior::InverseGamma { shape, scale } => 1.0 / Gamma::new(shape, 1.0 / scale).expect("valid").sample(rng),
            Prior::LogUniform { lower, upper } => Uniform::new_inclusive(lower.ln(), upper.ln()).sample(rng).exp(),
        }
    }
}
