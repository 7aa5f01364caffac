//! The error type of the statistics layer.

use crate::error::InputError;

/// Why a sampler, optimiser or evidence estimate could not deliver.
///
/// [`BayesError::Config`] is bad input (a setting outside its range: fix the
/// setting); every other variant is a numerical failure on a valid problem
/// (the posterior is degenerate, or the method's assumptions do not hold:
/// change the model, the priors or the method).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BayesError {
    /// A setting outside its documented range.
    #[error("{0}")]
    Config(#[from] InputError),
    /// TMCMC: every sample of a stage has log L = −∞ or NaN (the data are impossible under every prior draw).
    #[error("TMCMC stage {stage}: no sample has a finite log-likelihood (no prior draw can explain the data)")]
    NoFiniteLikelihood { stage: usize },
    /// TMCMC: the tempering did not reach p = 1 (likelihood too peaked for the stage budget).
    #[error("TMCMC did not reach p = 1 within {max_stages} stages (p = {p}); raise max_stages or n_samples")]
    TooManyStages { max_stages: usize, p: f64 },
    /// TMCMC: the posterior's prior draw has the wrong length (a bug in the posterior).
    #[error("TMCMC: prior sample {index} has dimension {got}, expected {expected}")]
    BadPriorSample { index: usize, got: usize, expected: usize },
    /// Laplace: θ*, the scales and the posterior disagree in dimension.
    #[error("Laplace: dimension mismatch (theta has {theta}, scales {scales}, posterior {posterior})")]
    Dimension { theta: usize, scales: usize, posterior: usize },
    /// Laplace: a finite-difference scale that is not positive and finite.
    #[error("Laplace: scale of parameter {index} is {value}; must be > 0 and finite")]
    BadScale { index: usize, value: f64 },
    /// Laplace: log π is not finite next to θ* (θ* on or near the prior's boundary).
    #[error("Laplace: log posterior is not finite at a finite-difference point near θ* (parameter {index}); θ* on or near the prior's boundary?")]
    NonFinite { index: usize },
    /// Laplace: θ* is not a strict local maximum.
    #[error("Laplace: Hessian of −log posterior is not positive definite at θ* (smallest eigenvalue of the standardised Hessian {min_eigenvalue:e}); θ* is not a strict local maximum")]
    NotPositiveDefinite { min_eigenvalue: f64 },
    /// Importance sampling: the centre, the population and the posterior disagree in
    /// dimension, or the population is too small to estimate its covariance.
    #[error("importance sampling: centre has dimension {center}, posterior {posterior}; population of {population} needs >= {needed} samples of that dimension")]
    ImportancePopulation { center: usize, posterior: usize, population: usize, needed: usize },
    /// Importance sampling: a proposal covariance (Laplace's or the population's) is not positive definite.
    #[error(
        "importance sampling: the {which} covariance is not positive definite (smallest eigenvalue {min_eigenvalue:e})"
    )]
    ImportanceCovariance { which: &'static str, min_eigenvalue: f64 },
    /// Importance sampling: no draw has a finite log posterior.
    #[error("importance sampling: none of {draws} draws has a finite log posterior")]
    ImportanceNoFiniteDraw { draws: usize },
    /// The caller cancelled the run ([`crate::bayes::Control::cancel`]).
    #[error("{0}")]
    Cancelled(#[from] crate::bayes::Cancelled),
}

impl BayesError {
    /// `true` for bad settings (exit 2), `false` for a numerical failure (exit 1).
    pub fn is_input(&self) -> bool {
        matches!(self, BayesError::Config(_))
    }
}
