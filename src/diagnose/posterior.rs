//! The posterior of one model class over its sampling coordinates u
//! (u = x, or u = ln x for log-uniform priors).
//!
//! Likelihood: eq. (26) with the diagonal Σεε of eq. (38), scaled by β² when
//! the class calibrates β² (eq. 41):
//! log L = −Σ_j [ (y_j − ŷ_j(θ))² / (2β²σ_j²) + ln(βσ_j) + ½ ln 2π ],
//! over the ω and ζ of every fitted mode.

use rand::RngCore;

use crate::bayes::prior::Prior;
use crate::bayes::Posterior;
use crate::beam::BeamSpec;
use crate::calibration::{ModeObservation, Target};

use super::classes::ClassParameters;

/// One scalar observable: mode r's ω or ζ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observable {
    pub mode: usize,
    pub quantity: Quantity,
    pub value: f64,
    pub sd: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    Omega,
    Zeta,
}

impl Quantity {
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Omega => "omega",
            Quantity::Zeta => "zeta",
        }
    }
}

/// The observables of a list of modes, ω first then ζ per mode (y of eq. 36).
pub fn observables(modes: &[ModeObservation]) -> Vec<Observable> {
    let mut out = Vec::with_capacity(2 * modes.len());
    for m in modes {
        out.push(Observable { mode: m.mode, quantity: Quantity::Omega, value: m.omega_rad_s, sd: m.omega_sd_rad_s });
        out.push(Observable { mode: m.mode, quantity: Quantity::Zeta, value: m.zeta, sd: m.zeta_sd });
    }
    out
}

/// Picks the observable's prediction out of the model's modal pairs.
pub fn predicted(obs: &Observable, modes: &[ModalPair]) -> f64 {
    let m = modes[obs.mode - 1];
    match obs.quantity {
        Quantity::Omega => m.omega_rad_s,
        Quantity::Zeta => m.zeta,
    }
}

/// One mode's predicted modal pair, eqs. (34)–(35).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalPair {
    pub omega_rad_s: f64,
    pub zeta: f64,
}

/// The first `n_modes` modal pairs of `beam` by `beam::modal` (the exact fast
/// path, or RQI on T(s) when a spring or a damped point mass couples the
/// modes), through this thread's reusable solver. `Err` when the model cannot
/// produce them (overdamped mode, invalid parameters).
pub fn predict(beam: &BeamSpec, n_modes: usize) -> Result<Vec<ModalPair>, String> {
    let r = crate::beam::modal(beam, n_modes).map_err(|e| e.to_string())?;
    if let Some(o) = r.overdamped.first() {
        return Err(format!("mode {} is overdamped", o.mode));
    }
    Ok(r.modes.iter().map(|m| ModalPair { omega_rad_s: m.omega_rad_s, zeta: m.zeta }).collect())
}

/// The posterior of a class given fitted observables.
#[derive(Debug, Clone)]
pub struct ClassPosterior {
    pub params: ClassParameters,
    pub beam: BeamSpec,
    pub fitted: Vec<Observable>,
    /// Number of modes the forward model computes (highest mode needed).
    pub n_modes: usize,
    beta_index: Option<usize>,
}

impl ClassPosterior {
    pub fn new(params: ClassParameters, beam: BeamSpec, fitted: Vec<Observable>, n_modes: usize) -> Self {
        let beta_index = params.set.params.iter().position(|p| p.target == Target::BetaSquared);
        Self { params, beam, fitted, n_modes, beta_index }
    }

    /// Physical parameters x from sampling coordinates u.
    pub fn to_physical(&self, u: &[f64]) -> Vec<f64> {
        u.iter().zip(&self.params.log_scale).map(|(&v, &l)| if l { v.exp() } else { v }).collect()
    }

    /// β² at u (1 when the class does not calibrate it).
    pub fn beta_squared(&self, u: &[f64]) -> f64 {
        self.beta_index.map_or(1.0, |i| u[i])
    }

    /// The beam at u.
    pub fn beam_at(&self, u: &[f64]) -> BeamSpec {
        self.params.set.apply(&self.beam, &self.to_physical(u))
    }

    /// Model predictions at u for modes 1..=n_modes.
    pub fn predict(&self, u: &[f64]) -> Result<Vec<ModalPair>, String> {
        predict(&self.beam_at(u), self.n_modes)
    }

    /// Gaussian log likelihood of `fitted` given predictions and β².
    pub fn log_likelihood_of(&self, modes: &[ModalPair], beta_squared: f64) -> f64 {
        let half_ln_2pi = 0.5 * (2.0 * std::f64::consts::PI).ln();
        self.fitted
            .iter()
            .map(|o| {
                let var = beta_squared * o.sd * o.sd;
                let r = o.value - predicted(o, modes);
                -0.5 * r * r / var - 0.5 * var.ln() - half_ln_2pi
            })
            .sum()
    }
}

impl Posterior for ClassPosterior {
    fn names(&self) -> Vec<String> {
        self.params.set.names()
    }

    fn log_prior(&self, u: &[f64]) -> f64 {
        let mut lp = 0.0;
        for ((p, &l), &v) in self.params.set.params.iter().zip(&self.params.log_scale).zip(u) {
            lp += match (l, &p.prior) {
                (true, Prior::LogUniform { lower, upper }) => {
                    if v >= lower.ln() && v <= upper.ln() {
                        -(upper / lower).ln().ln()
                    } else {
                        f64::NEG_INFINITY
                    }
                }
                _ => p.prior.ln_pdf(v),
            };
        }
        lp
    }

    fn log_likelihood(&self, u: &[f64]) -> f64 {
        match self.predict(u) {
            Ok(modes) => self.log_likelihood_of(&modes, self.beta_squared(u)),
            Err(_) => f64::NEG_INFINITY,
        }
    }

    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        self.params
            .set
            .params
            .iter()
            .zip(&self.params.log_scale)
            .map(|(p, &l)| {
                let x = p.prior.sample(rng);
                if l {
                    x.ln()
                } else {
                    x
                }
            })
            .collect()
    }
}
