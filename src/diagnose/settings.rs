//! The knobs of a diagnosis and why one could not be made.

use crate::bayes::{BayesError, Cancelled, Control};
use crate::error::InputError;
use crate::report::ReportError;

/// Knobs of a diagnosis (defaults documented on each field).
#[derive(Debug, Clone, PartialEq)]
pub struct DiagnoseSettings {
    /// TMCMC samples per stage (default 1000).
    pub samples: usize,
    /// Metropolis steps per sample and stage (default 4).
    pub mh_steps: usize,
    /// Master seed (default: the file's `sampler.seed`).
    pub seed: Option<u64>,
    /// Family-wise level of the misfit test (default 0.01).
    pub family_alpha: f64,
    /// ln B threshold to add a cause (default 3).
    pub log_bayes_factor_threshold: f64,
    /// A model within this many nats of the selected one is an alternative (default 3:
    /// the data do not prefer either "strongly").
    pub alternative_margin: f64,
    /// Most causes of every model the search compares (default 2: with 8–10
    /// observables and the base's 3 parameters, a third cause leaves ≤ 3
    /// degrees of freedom, where any flexible enough combination fits and
    /// "explained" stops meaning much). On records of at least
    /// `search::EXTENSION_OBSERVABLES` observables a selected pair is also
    /// extended by one cause (`search::extension`).
    pub max_causes: usize,
    /// Nelder–Mead iterations for the MAP (default 400).
    pub map_iters: u64,
    /// Cancellation and progress (default: neither; [`crate::bayes::control`]).
    /// Progress counts the models whose evidence is done ("models"); a
    /// cancelled diagnosis returns [`DiagnoseError::Cancelled`]. Changes no
    /// number, so it never distinguishes two settings (`==`).
    pub control: Control,
}

impl Default for DiagnoseSettings {
    fn default() -> Self {
        Self {
            samples: 1000,
            mh_steps: 4,
            seed: None,
            family_alpha: 0.01,
            log_bayes_factor_threshold: 3.0,
            alternative_margin: 3.0,
            max_causes: 2,
            map_iters: 400,
            control: Control::default(),
        }
    }
}

impl DiagnoseSettings {
    /// Upper bound of `samples`: 1e5 samples × ≈ 20 stages × 4 steps is ≈ 1e7
    /// forward evaluations per model (minutes); memory stays ≈ 1e5 × d × 8 B.
    pub const MAX_SAMPLES: usize = 100_000;
    /// Lower bound: the stage covariance of a 5-parameter model needs ≫ 5 samples.
    pub const MIN_SAMPLES: usize = 50;
    /// Upper bound of `max_causes`: 3 makes 112 triples of the 10 causes (120
    /// less the 8 that hold both shear-deformation and strain-gradient), each
    /// screened by its evidence bound; a fourth cause would leave a 5-mode
    /// record no degrees of freedom.
    pub const MAX_CAUSES: usize = 3;

    /// The settings the hidden-effect suite validates its accuracy targets
    /// at, and `nanobeam diagnose`'s default: 400 samples, 3 steps, 250 MAP
    /// iterations (about a third of [`Default`]'s forward solves).
    pub fn quick() -> Self {
        Self { samples: 400, mh_steps: 3, map_iters: 250, ..Self::default() }
    }

    /// Checks every knob against its range (flag names as the CLI spells them).
    pub fn validate(&self) -> Result<(), InputError> {
        if !(Self::MIN_SAMPLES..=Self::MAX_SAMPLES).contains(&self.samples) {
            return Err(InputError::new(
                "--samples",
                self.samples,
                format!("{}..={}", Self::MIN_SAMPLES, Self::MAX_SAMPLES),
            ));
        }
        if !(1..=Self::MAX_CAUSES).contains(&self.max_causes) {
            return Err(InputError::new("--max-causes", self.max_causes, format!("1..={}", Self::MAX_CAUSES)));
        }
        if !(1..=100).contains(&self.mh_steps) {
            return Err(InputError::new("mh_steps", self.mh_steps, "1..=100"));
        }
        if !(self.family_alpha > 0.0 && self.family_alpha < 1.0) {
            return Err(InputError::new("family_alpha", self.family_alpha, "0 < alpha < 1"));
        }
        for (name, v) in [
            ("log_bayes_factor_threshold", self.log_bayes_factor_threshold),
            ("alternative_margin", self.alternative_margin),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(InputError::new(name, v, ">= 0 (finite)"));
            }
        }
        Ok(())
    }
}

/// Why a diagnosis could not be made.
#[derive(Debug, thiserror::Error)]
pub enum DiagnoseError {
    /// The measured data or a setting is outside its range: fix the file or flag.
    #[error("{0}")]
    Input(#[from] InputError),
    /// A model's evidence could not be computed (TMCMC failed): the data are
    /// impossible under that model's priors, or the sampler budget is too small.
    #[error("model `{model}`: {source}")]
    Evidence { model: String, source: BayesError },
    /// The report directory could not be written.
    #[error("{0}")]
    Report(#[from] ReportError),
    /// The caller cancelled the run ([`DiagnoseSettings::control`]).
    #[error("{0}")]
    Cancelled(#[from] Cancelled),
}
