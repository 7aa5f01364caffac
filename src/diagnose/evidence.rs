//! Evidence of one model: TMCMC (`bayes::tmcmc`, Ching & Chen 2007 with the
//! proposal scale and chain length adapted as in Betz et al. 2016), then the
//! MAP from the best sample (`bayes::map`) and the Laplace evidence there
//! (`bayes::laplace`) as a cross-check.

use crate::bayes::laplace::laplace_log_evidence_with_step;
use crate::bayes::map::map_estimate;
use crate::bayes::posterior::Counted;
use crate::bayes::tmcmc::{tmcmc, TmcmcConfig, TmcmcResult};
use crate::bayes::{BayesError, Posterior};

use super::classes::Model;
use super::{ClassPosterior, DiagnoseSettings};

/// Everything computed for one model (kept for the report's plots).
#[derive(Debug, Clone)]
pub struct ModelRun {
    pub model: Model,
    pub posterior: ClassPosterior,
    pub tmcmc: TmcmcResult,
    /// The MAP in sampling coordinates.
    pub map: Vec<f64>,
    /// `None` when the MAP sits on a prior boundary or the Hessian is not positive definite.
    pub log_evidence_laplace: Option<f64>,
    /// Forward-model solves of TMCMC, the MAP and the Laplace Hessian together.
    pub forward_evaluations: u64,
}

/// Runs TMCMC, the MAP and the Laplace evidence of `posterior` with the master seed `seed`.
pub fn run_model(
    model: Model,
    posterior: ClassPosterior,
    s: &DiagnoseSettings,
    seed: u64,
) -> Result<ModelRun, BayesError> {
    let d = posterior.dim();
    let config = TmcmcConfig {
        n_samples: s.samples,
        mh_steps: s.mh_steps,
        // optimal random-walk scale for a d-dimensional Gaussian target
        // (Gelman, Roberts & Gilks 1996), steered towards its 0.234 acceptance
        beta: 2.38 / (d as f64).sqrt(),
        target_acceptance: 0.234,
        adapt_beta: true,
        max_mh_steps: Some(5 * s.mh_steps),
        seed,
        ..TmcmcConfig::default()
    };
    let counted = Counted::new(&posterior);
    let t = tmcmc(&counted, &config)?;
    let sd = sample_sd(&t.samples, d);
    let best = t
        .samples
        .iter()
        .zip(&t.log_likelihoods)
        .map(|(u, &l)| (u, l + posterior.log_prior(u)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(u, _)| u.clone())
        .ok_or(BayesError::NoFiniteLikelihood { stage: t.stages.len() })?;
    // initial simplex: half a posterior sd per coordinate
    let half_sd: Vec<f64> = sd.iter().zip(&best).map(|(s, b)| (0.5 * s).max(1e-12 * b.abs().max(1e-300))).collect();
    let map = map_estimate(&counted, &best, &half_sd, s.map_iters).theta;
    // FD step 0.05 sd: the O(h²) truncation error is ≈ 0.25 % of the curvature
    // of a near-Gaussian posterior, while the forward model's round-off
    // (~1e-12 relative) stays negligible against the h²-sized differences.
    let log_evidence_laplace = laplace_log_evidence_with_step(&counted, &map, &sd, 0.05).ok().map(|l| l.log_evidence);
    let forward_evaluations = counted.count();
    Ok(ModelRun { model, posterior, tmcmc: t, map, log_evidence_laplace, forward_evaluations })
}

/// Per-coordinate sd of equally weighted samples (TMCMC's final population is resampled).
fn sample_sd(samples: &[Vec<f64>], d: usize) -> Vec<f64> {
    (0..d)
        .map(|k| {
            let v: Vec<f64> = samples.iter().map(|s| s[k]).collect();
            crate::bayes::summary::describe(&v).1
        })
        .collect()
}
