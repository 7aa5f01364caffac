//! Evidence of one model: the combined estimator of `bayes::evidence` (TMCMC,
//! the importance check, the MAP searches, the Laplace evidence, replicates)
//! run on the model's posterior with the diagnosis's settings. What the
//! diagnosis adds is what the estimator cannot know: which posteriors are
//! multimodal by construction ([`multimodal_by_construction`]), the MAPs of
//! a model's sub-models (one cause fewer) for the nested MAP search, and,
//! in `search`, the bar a flagged model must reach to be replicated.

use crate::bayes::evidence::{self, AtOptimum, Evidence, EvidenceSettings, SubModelMap};
use crate::bayes::posterior::Counted;
use crate::bayes::rng::{stream, Purpose};
use crate::bayes::tmcmc::Start;
use crate::bayes::{BayesError, Posterior};
use crate::calibration::{ParameterSet, Target};

use super::classes::ClassPosterior;
use super::classes::Model;
use super::settings::DiagnoseSettings;

pub use crate::bayes::evidence::LAPLACE_DISAGREEMENT_NATS;

/// Everything computed for one model (kept for the report's plots): the
/// model, its posterior, and its [`Evidence`], whose fields read through
/// (`run.log_evidence`, `run.draws`, …: the posterior draws the predictive
/// checks, summaries and plots use, in sampling coordinates).
#[derive(Debug, Clone)]
pub struct ModelRun {
    pub model: Model,
    pub posterior: ClassPosterior,
    pub evidence: Evidence,
}

impl std::ops::Deref for ModelRun {
    type Target = Evidence;

    fn deref(&self) -> &Evidence {
        &self.evidence
    }
}

impl ModelRun {
    fn new(model: Model, posterior: ClassPosterior, evidence: Evidence) -> Self {
        ModelRun { model, posterior, evidence }
    }

    /// The model, its posterior and its [`Evidence`], apart.
    fn split(self) -> (Model, ClassPosterior, Evidence) {
        (self.model, self.posterior, self.evidence)
    }

    /// The importance evidence is the model's evidence (its ESS ≥ [`evidence::IMPORTANCE_MIN_ESS`]).
    pub fn importance_reliable(&self) -> bool {
        evidence::importance_reliable(self.importance.as_ref())
    }

    /// The estimator's replication rule ([`Evidence::needs_replicates`]) at `bar`.
    pub fn needs_replicates(&self, bar: f64) -> bool {
        evidence::needs_replicates(self.missed_peak, self.importance.as_ref(), self.log_evidence_laplace, bar)
    }
}

/// The estimator's settings of a diagnosis: its TMCMC samples, MH steps and
/// MAP iterations (validated with the diagnosis's settings, to the same ranges).
pub fn evidence_settings(s: &DiagnoseSettings) -> EvidenceSettings {
    EvidenceSettings { samples: s.samples, mh_steps: s.mh_steps, map_iters: s.map_iters }
}

/// Runs the combined estimator on `posterior` with the master seed `seed`.
/// `sub_models` are runs of models with one cause fewer (any, or none): on a
/// posterior multimodal by construction the MAP search also starts from each
/// of their MAPs.
pub fn run_model(
    model: Model,
    posterior: ClassPosterior,
    s: &DiagnoseSettings,
    seed: u64,
    sub_models: &[&ModelRun],
) -> Result<ModelRun, BayesError> {
    run_model_from(model, posterior, s, seed, sub_models, None)
}

/// [`run_model`] whose TMCMC run starts from the posterior of `start`'s
/// sub-model, one whose prior this model's agrees with on their shared
/// parameters (the caller's rule, `search`), instead of the prior, when its
/// best sample comes within [`evidence::missed_peak_nats`] of `start`'s ln L
/// (the best log-likelihood of this model found elsewhere: its screening
/// search's)
/// ([`crate::bayes::tmcmc::tmcmc_from`]): the population pairs `start`'s posterior draws (cycled)
/// for the shared parameters, by name, with prior draws (stream `(seed,
/// NestedStart, [0, 0])`) for the ones this model adds, which is a draw of
/// q₀ ∝ π·L_start when the prior factorises so; the tempering runs from
/// L_start to this model's likelihood, each move evaluating both (counted in
/// the forward solves). A population the prior refuses (no such agreement)
/// falls back to [`run_model`].
///
/// Why: from the prior TMCMC spends 12–16 stages of 400 samples × up to 15
/// moves (40–70 thousand solves) rediscovering the sub-model's posterior,
/// which the search has already sampled; where the added cause changes
/// little, two to five stages from it reach this posterior
/// (`benches/README.md`). What the
/// start cannot see is a mode of this posterior that the sub-model's
/// posterior and the added parameters' prior both miss; the global and
/// nested MAP searches of a posterior multimodal by construction, the
/// importance evidence at the MAP and the missed-peak flag
/// (`bayes::evidence`) are kept as they were for that.
pub fn run_model_from(
    model: Model,
    posterior: ClassPosterior,
    s: &DiagnoseSettings,
    seed: u64,
    sub_models: &[&ModelRun],
    start: Option<(&ModelRun, f64)>,
) -> Result<ModelRun, BayesError> {
    let names: Vec<Vec<String>> = sub_models.iter().map(|r| r.posterior.names()).collect();
    let subs: Vec<SubModelMap<'_>> =
        sub_models.iter().zip(&names).map(|(r, names)| SubModelMap { names, map: &r.map }).collect();
    let multimodal = multimodal_by_construction(posterior.inner().parameters());
    let settings = evidence_settings(s);
    let Some((sub, peak)) = start.filter(|(r, _)| !r.draws.is_empty()) else {
        let e = evidence::estimate(&posterior, &settings, seed, multimodal, &subs, &s.control)?;
        return Ok(ModelRun::new(model, posterior, e));
    };
    let own = posterior.names();
    let sub_names = sub.posterior.names();
    // where each of the sub-model's parameters sits in this model's
    let Some(at): Option<Vec<usize>> = sub_names.iter().map(|n| own.iter().position(|m| m == n)).collect() else {
        let e = evidence::estimate(&posterior, &settings, seed, multimodal, &subs, &s.control)?;
        return Ok(ModelRun::new(model, posterior, e));
    };
    let mut rng = stream(seed, Purpose::NestedStart, [0, 0]);
    let samples: Vec<Vec<f64>> = (0..s.samples)
        .map(|j| {
            let mut theta = posterior.sample_prior(&mut rng);
            let draw = &sub.draws[j % sub.draws.len()];
            for (k, &i) in at.iter().enumerate() {
                theta[i] = draw[k];
            }
            theta
        })
        .collect();
    let counted = Counted::new(&sub.posterior);
    let reference = |theta: &[f64]| {
        let a: Vec<f64> = at.iter().map(|&i| theta[i]).collect();
        counted.log_likelihood(&a)
    };
    let start = Start {
        samples,
        reference: &reference,
        log_evidence: sub.log_evidence,
        log_evidence_se: sub.log_evidence_se,
        least_best_log_likelihood: peak - evidence::missed_peak_nats(own.len(), s.samples),
    };
    match evidence::estimate_from(&posterior, &settings, seed, multimodal, &subs, Some(&start), &s.control) {
        Ok(mut e) => {
            e.forward_evaluations += counted.count();
            Ok(ModelRun::new(model, posterior, e))
        }
        Err(BayesError::BadPriorSample { .. }) => {
            let mut e = evidence::estimate(&posterior, &settings, seed, multimodal, &subs, &s.control)?;
            e.forward_evaluations += counted.count();
            Ok(ModelRun::new(model, posterior, e))
        }
        Err(other) => Err(other),
    }
}

/// How far below the best of a model's sub-models another sub-model's
/// evidence may lie and still give points to the population of
/// [`run_from_optimum`]: 10 nats. The population's kernels share one
/// covariance (Silverman's rule on the whole population, `bayes::importance`),
/// so draws of a sub-model that misfits by far sit far from this posterior
/// and widen every kernel until the density covers nothing; a sub-model
/// 10 nats behind holds e⁻¹⁰ of the mass its better sibling does, too little
/// for the estimate to need its region.
pub const POPULATION_SUB_NATS: f64 = 10.0;

/// The evidence of a model that adds causes to fitted sub-models, by
/// importance sampling from an optimum found by its screening search
/// (`optimum`, `scales`: [`super::screen::Bound::optimum`]) without TMCMC
/// ([`evidence::estimate_at_optimum`]); `Ok(Err(solves))` when that
/// evidence is not reliable (the caller runs [`run_model`]) or `sub_models`
/// is empty. The population of the proposal's kernel density: `samples`
/// points shared out among the sub-models within [`POPULATION_SUB_NATS`] of
/// the best one, each a sub-model's posterior draw
/// (cycled) for the parameters both share, by name, and a prior draw (stream
/// `(seed, ImportancePopulation, [k, 0])` for the k-th sub-model) for the
/// ones this model adds.
///
/// Why that population: where an added cause is not needed, this posterior
/// is the sub-model's posterior times the prior of the added parameters
/// over the range where they change nothing, which the population covers;
/// where it is needed, the Student-t at the optimum covers the peak. The
/// caller keeps posteriors multimodal by construction on [`run_model`].
pub fn run_from_optimum(
    model: Model,
    posterior: ClassPosterior,
    s: &DiagnoseSettings,
    seed: u64,
    (optimum, scales): (&[f64], &[f64]),
    sub_models: &[&ModelRun],
) -> Result<Result<ModelRun, u64>, BayesError> {
    // the sub-models that can hold this posterior's bulk: within
    // POPULATION_SUB_NATS of the best one (a sub-model far behind sits where
    // this posterior has no mass, and its draws would only widen the kernels)
    let best = sub_models.iter().map(|r| r.log_evidence).fold(f64::NEG_INFINITY, f64::max);
    let sub_models: Vec<&ModelRun> =
        sub_models.iter().copied().filter(|r| r.log_evidence >= best - POPULATION_SUB_NATS).collect();
    if sub_models.is_empty() {
        return Ok(Err(0));
    }
    let names = posterior.names();
    let k_subs = sub_models.len();
    let mut population = Vec::with_capacity(s.samples);
    for (k, sub) in sub_models.iter().enumerate() {
        let sub_names = sub.posterior.names();
        let shared: Vec<Option<usize>> = names.iter().map(|n| sub_names.iter().position(|m| m == n)).collect();
        let mut rng = stream(seed, Purpose::ImportancePopulation, [k as u64, 0]);
        let n = s.samples / k_subs + usize::from(k < s.samples % k_subs);
        if sub.draws.is_empty() {
            return Ok(Err(0));
        }
        for j in 0..n {
            let draw = &sub.draws[j % sub.draws.len()];
            let prior = posterior.sample_prior(&mut rng);
            population.push(shared.iter().zip(prior).map(|(i, x)| i.map_or(x, |i| draw[i])).collect());
        }
    }
    match evidence::estimate_at_optimum(
        &posterior,
        &evidence_settings(s),
        seed,
        optimum,
        scales,
        &population,
        &s.control,
    )? {
        AtOptimum::Reliable(e) => Ok(Ok(ModelRun::new(model, posterior, *e))),
        AtOptimum::Unreliable { forward_evaluations } => Ok(Err(forward_evaluations)),
    }
}

/// `run` with [`evidence::EVIDENCE_REPLICATES`] TMCMC runs in all
/// ([`evidence::replicate`]). The search calls it for the models whose first
/// run missed the peak and whose Laplace evidence puts them in contention
/// ([`Evidence::needs_replicates`]).
pub fn replicate(run: ModelRun, s: &DiagnoseSettings) -> Result<ModelRun, BayesError> {
    let (model, posterior, e) = run.split();
    let e = evidence::replicate(e, &posterior, &evidence_settings(s), &s.control)?;
    Ok(ModelRun::new(model, posterior, e))
}

/// The posterior of these parameters has several modes by construction: two or more relaxations
/// (exchangeable up to labels, each Ω on either side of a resonance) or a
/// point mass (its position on either side of a node of each mode): the
/// posteriors on which TMCMC was seen to miss the peak. Only these get the
/// global and nested MAP searches of `bayes::evidence`, which keeps their
/// cost off the other models, most of them Timoshenko models whose solves
/// cost 3–10× the others'. Whether the others ever need them was not measured.
pub fn multimodal_by_construction(parameters: &ParameterSet) -> bool {
    let params = &parameters.params;
    let relaxations = params.iter().filter(|p| matches!(p.target, Target::Omega(_))).count();
    relaxations >= 2 || params.iter().any(|p| p.target == Target::PointMassXnm)
}
