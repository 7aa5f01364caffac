//! The evidence of one posterior, estimated so that a run that missed the
//! posterior's peak is seen and corrected: TMCMC (`bayes::tmcmc`, Ching & Chen
//! 2007 with the proposal scale and chain length adapted as in Betz et al.
//! 2016), the MAP from the best sample (`bayes::map`), the Laplace evidence
//! there (`bayes::laplace`), and the evidence by importance sampling
//! (`bayes::importance`) from a mixture built at that MAP.
//!
//! # Why several estimators
//! TMCMC can miss the peak region of a posterior with several narrow modes
//! (exchangeable components, a parameter on either side of a symmetry): its
//! final population then sits below the peak and its ln Ẑ falls short, by
//! far more than the stage estimator's standard error says. The MAP search
//! from the population's best sample shows the shortfall: when the MAP lies
//! further above the best sample than [`missed_peak_nats`] allows and the
//! Laplace evidence at the MAP exceeds TMCMC's by more than
//! [`LAPLACE_DISAGREEMENT_NATS`], the run is flagged ([`Evidence::missed_peak`]).
//! A flagged run can be [`replicate`]d: [`EVIDENCE_REPLICATES`] runs in all,
//! their evidences combined ([`combine`]) with a standard error from their
//! spread. Which flagged runs are worth the cost is the caller's rule
//! ([`Evidence::needs_replicates`]: in contention by its Laplace evidence).
//!
//! Replicates alone do not settle it: the combined ln Ẑ of such a posterior
//! still spreads over seeds. So the evidence is also estimated by importance
//! sampling from a mixture of a Student-t at the MAP (Laplace covariance) and
//! a kernel density of the TMCMC population (all runs' populations pooled for
//! a replicated posterior): unbiased whatever the population missed, as long
//! as the t covers the peak, with a standard error that the weights measure.
//! It is the evidence when its effective sample size is at least
//! [`IMPORTANCE_MIN_ESS`] (with more draws when the first batch falls short
//! by a factor more draws make up: [`importance_draws_for`]); a flagged
//! posterior whose importance evidence is that reliable is not replicated.
//! Long TMCMC runs can still drop a little of a multimodal posterior's mass,
//! which is the shortfall this estimator avoids.
//!
//! The importance evidence is only as good as the MAP its t component sits
//! at, and its ESS cannot see a mode that neither component reaches. So a
//! posterior the caller knows to be multimodal by construction also gets a
//! global MAP search from prior draws ([`global_map`]) and a search from the
//! MAPs of its sub-models ([`nested_map`]), the Laplace covariance is retried
//! at finer steps when the population's scale steps out of a narrow mode
//! ([`laplace_at`]), and when the population lies below the MAP by more than
//! [`missed_peak_nats`] and the importance evidence is reliable, the posterior
//! draws are resampled from the importance draws ([`posterior_draws`]) instead
//! of TMCMC's population at the wrong mode.
//!
//! The measurements behind every constant here are in the record
//! `tests/evidence.md`.

use statrs::distribution::{ChiSquared, ContinuousCDF};

use crate::bayes::control::{Control, Controlled};
use crate::bayes::importance::{
    evidence_from_log_weights, pareto_k, pareto_k_threshold, sample_covariance, Defended, ImportanceEvidence,
    MixtureProposal, Proposal,
};
use crate::bayes::laplace::{laplace_log_evidence_with_step, LaplaceEvidence};
use crate::bayes::map::{map_estimate, multi_start_from, polish_best, MapResult};
use crate::bayes::posterior::Counted;
use crate::bayes::rng::{child_seed, Purpose};
use crate::bayes::tmcmc::{tmcmc_controlled, tmcmc_from, Start, TmcmcConfig, TmcmcResult};
use crate::bayes::{BayesError, Posterior};
use crate::error::InputError;

/// Laplace vs TMCMC log-evidence gap that flags a non-Gaussian posterior.
pub const LAPLACE_DISAGREEMENT_NATS: f64 = 1.0;

/// Settings of the combined estimator ([`estimate`], [`replicate`]).
///
/// Contract: `samples` in [`Self::MIN_SAMPLES`]..=[`Self::MAX_SAMPLES`] (TMCMC
/// samples per stage; also sets the importance draws,
/// [`IMPORTANCE_DRAWS_PER_SAMPLE`] per sample, and the posterior draws
/// resampled from them), `mh_steps` in 1..=100 (MH steps per stage; the
/// adaptive chain length goes up to 5 × that), `map_iters` any (Nelder–Mead
/// iterations of every MAP search; the simplex stops earlier when it
/// converges). [`Self::validate`] checks it, and so do [`estimate`] and
/// [`replicate`] themselves, so no run starts on settings outside it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EvidenceSettings {
    pub samples: usize,
    pub mh_steps: usize,
    pub map_iters: u64,
}

impl EvidenceSettings {
    /// Upper bound of `samples`: 1e5 samples × ≈ 20 stages × 4 steps is ≈ 1e7
    /// forward solves per run.
    pub const MAX_SAMPLES: usize = 100_000;
    /// Lower bound of `samples`: the stage covariance of a 5–7-parameter
    /// posterior needs ≫ 7 samples.
    pub const MIN_SAMPLES: usize = 50;

    /// Checks every field against the contract (field names as spelled here).
    pub fn validate(&self) -> Result<(), InputError> {
        if !(Self::MIN_SAMPLES..=Self::MAX_SAMPLES).contains(&self.samples) {
            return Err(InputError::new(
                "samples",
                self.samples,
                format!("{}..={}", Self::MIN_SAMPLES, Self::MAX_SAMPLES),
            ));
        }
        if !(1..=100).contains(&self.mh_steps) {
            return Err(InputError::new("mh_steps", self.mh_steps, "1..=100"));
        }
        Ok(())
    }

    /// The TMCMC settings of a `d`-dimensional posterior with master seed `seed`.
    fn tmcmc_config(&self, d: usize, seed: u64) -> TmcmcConfig {
        TmcmcConfig {
            n_samples: self.samples,
            mh_steps: self.mh_steps,
            // optimal random-walk scale for a d-dimensional Gaussian target
            // (Gelman, Roberts & Gilks 1996), steered towards its 0.234 acceptance
            beta: 2.38 / (d as f64).sqrt(),
            target_acceptance: 0.234,
            adapt_beta: true,
            max_mh_steps: Some(5 * self.mh_steps),
            seed,
            ..TmcmcConfig::default()
        }
    }
}

/// The evidence of one posterior and everything computed for it.
#[derive(Debug, Clone)]
pub struct Evidence {
    /// ln Z: the importance evidence when reliable
    /// ([`Evidence::importance_reliable`]), TMCMC's otherwise.
    pub log_evidence: f64,
    /// Standard error of `log_evidence`.
    pub log_evidence_se: f64,
    /// The TMCMC result; with several runs, their combined evidence and the
    /// population of the run that came closest to the peak ([`combine`]);
    /// `None` for an evidence estimated from an optimum without TMCMC
    /// ([`estimate_at_optimum`]).
    pub tmcmc: Option<TmcmcResult>,
    /// ln Ẑ of each TMCMC run (one unless replicated; none from [`estimate_at_optimum`]).
    pub log_evidence_runs: Vec<f64>,
    /// Posterior draws (the posterior's coordinates): TMCMC's final
    /// population, or, when that population lies below the MAP by more than
    /// [`missed_peak_nats`] and the importance evidence is reliable, a
    /// resample of the importance draws ([`posterior_draws`]).
    pub draws: Vec<Vec<f64>>,
    /// The MAP.
    pub map: Vec<f64>,
    /// `None` when the MAP sits on a prior boundary or the Hessian is not positive definite.
    pub log_evidence_laplace: Option<f64>,
    /// The first TMCMC run ended below the posterior's peak (module doc).
    pub missed_peak: bool,
    /// The importance-sampling evidence (`None` when its proposal could not
    /// be built); when its ESS ≥ [`IMPORTANCE_MIN_ESS`] it is the evidence.
    pub importance: Option<ImportanceEvidence>,
    /// The master seed of the random streams.
    pub seed: u64,
    /// Adapted proposals the importance evidence took before its last batch
    /// ([`estimate_at_optimum`]; 0 elsewhere).
    pub importance_rounds: usize,
    /// Forward-model solves of TMCMC, the MAP searches, the Laplace Hessian
    /// and the importance draws together.
    pub forward_evaluations: u64,
    /// Wall time (s), replicates included: a timing summary, never part of
    /// a (deterministic) result.
    pub elapsed_s: f64,
}

impl Evidence {
    /// The importance evidence is the evidence (its ESS ≥ [`IMPORTANCE_MIN_ESS`]).
    pub fn importance_reliable(&self) -> bool {
        importance_reliable(self.importance.as_ref())
    }

    /// The replication rule: a run that missed the peak, whose importance
    /// evidence is not reliable enough to stand in for it, and whose Laplace
    /// evidence reaches `bar` (the caller's "in contention": e.g. the best
    /// evidence of the models compared less a margin; `f64::NEG_INFINITY`
    /// for any). A run far behind cannot change a decision and keeps its
    /// single run.
    pub fn needs_replicates(&self, bar: f64) -> bool {
        needs_replicates(self.missed_peak, self.importance.as_ref(), self.log_evidence_laplace, bar)
    }
}

/// An importance evidence reliable enough to be the evidence (ESS ≥ [`IMPORTANCE_MIN_ESS`]).
pub fn importance_reliable(importance: Option<&ImportanceEvidence>) -> bool {
    importance.is_some_and(|is| is.ess >= IMPORTANCE_MIN_ESS)
}

/// The replication rule of [`Evidence::needs_replicates`] on its inputs, for
/// callers that keep an [`Evidence`]'s fields in a record of their own.
pub fn needs_replicates(
    missed_peak: bool,
    importance: Option<&ImportanceEvidence>,
    log_evidence_laplace: Option<f64>,
    bar: f64,
) -> bool {
    missed_peak && !importance_reliable(importance) && log_evidence_laplace.is_some_and(|l| l >= bar)
}

/// The MAP of a sub-model (one with fewer parameters) for the nested MAP
/// search ([`nested_map`]): its parameter names and its MAP in the same order.
#[derive(Debug, Clone, Copy)]
pub struct SubModelMap<'a> {
    pub names: &'a [String],
    pub map: &'a [f64],
}

/// The evidence of `posterior` with master seed `seed`: TMCMC, the MAP, the
/// Laplace evidence and the importance evidence (module doc). With
/// `multimodal` (a posterior multimodal by construction, which the caller
/// knows and this module cannot) the MAP search also runs from prior draws
/// ([`global_map`]) and from each of `sub_models`' MAPs ([`nested_map`]).
/// `control` is polled by TMCMC, before and after the MAP searches, the
/// Laplace evidence and the importance evidence, and within them at every
/// likelihood evaluation (they see the posterior through
/// [`Controlled`]): a cancelled run returns `BayesError::Cancelled` within a
/// forward solve per thread; one never cancelled gives the same bits as
/// without it.
pub fn estimate<P: Posterior>(
    posterior: &P,
    s: &EvidenceSettings,
    seed: u64,
    multimodal: bool,
    sub_models: &[SubModelMap<'_>],
    control: &Control,
) -> Result<Evidence, BayesError> {
    estimate_from(posterior, s, seed, multimodal, sub_models, None, control)
}

/// [`estimate`] whose TMCMC run starts from `start` ([`tmcmc_from`]: a
/// sub-model's posterior, with the tempering from its likelihood to this
/// one's) instead of the prior when given; `None` is [`estimate`]. The
/// reference likelihood's evaluations are the caller's to count.
pub fn estimate_from<P: Posterior>(
    posterior: &P,
    s: &EvidenceSettings,
    seed: u64,
    multimodal: bool,
    sub_models: &[SubModelMap<'_>],
    start: Option<&Start>,
    control: &Control,
) -> Result<Evidence, BayesError> {
    s.validate()?;
    let started = std::time::Instant::now();
    let d = posterior.dim();
    let counted_tmcmc = Counted::new(posterior);
    let t = tmcmc_from(&counted_tmcmc, &s.tmcmc_config(d, seed), control, start)?;
    // the searches and batches below poll the control at every evaluation
    let counted = Controlled::new(&counted_tmcmc, control);
    let mut map = map_from_best(&counted, &t, s)?;
    // the searches that posteriors multimodal by construction get, with
    // simplex steps one population sd per axis
    control.check()?;
    if multimodal {
        let sd = sample_sd(&t.samples, d);
        let searches = [global_map(&counted, &sd, s, seed), nested_map(&counted, &sd, s, seed, sub_models)];
        for m in searches.into_iter().flatten() {
            if m.log_posterior > map.log_posterior {
                map = m;
            }
        }
    }
    control.check()?;
    let laplace = laplace_at(&counted, &map.theta, &t);
    control.check()?;
    let log_evidence_laplace = laplace.as_ref().map(|l| l.log_evidence);
    // a final population whose best sample lies further below the MAP than a
    // posterior draw plausibly does, and whose evidence falls short of the
    // Laplace evidence at that MAP, missed the peak region's mass (module
    // doc). Both signs are needed: a high but narrow spike the MAP climbs (a
    // mass at a node) has a small Laplace evidence, and Laplace alone is off
    // on any non-Gaussian posterior.
    let shortfall = map.log_posterior - best_sample(&t, posterior)?.1;
    let population_missed = shortfall > missed_peak_nats(d, s.samples);
    let missed_peak =
        population_missed && log_evidence_laplace.is_some_and(|l| l - t.log_evidence > LAPLACE_DISAGREEMENT_NATS);
    let log_evidence_runs = vec![t.log_evidence];
    control.check()?;
    let (importance, resampled) =
        importance_at(&counted, &map.theta, laplace.as_ref(), &t.samples, s, seed, [0, 0], population_missed);
    control.check()?;
    let (log_evidence, log_evidence_se) = chosen(&t, importance.as_ref());
    let forward_evaluations = counted_tmcmc.count();
    Ok(Evidence {
        log_evidence,
        log_evidence_se,
        log_evidence_runs,
        draws: posterior_draws(&t, resampled),
        tmcmc: Some(t),
        map: map.theta,
        log_evidence_laplace,
        missed_peak,
        importance,
        seed,
        importance_rounds: 0,
        forward_evaluations,
        elapsed_s: started.elapsed().as_secs_f64(),
    })
}

/// What [`estimate_at_optimum`] found: the evidence, or the solves it spent
/// on finding that its importance evidence is not reliable.
#[derive(Debug, Clone)]
pub enum AtOptimum {
    /// The importance evidence is reliable (ESS ≥ [`IMPORTANCE_MIN_ESS`]): it is the evidence.
    Reliable(Box<Evidence>),
    /// It is not: the caller runs [`estimate`], which costs these solves more.
    Unreliable { forward_evaluations: u64 },
}

/// The evidence of `posterior` by importance sampling alone, from an
/// optimum found elsewhere (`optimum`, with scales `scales` per coordinate,
/// e.g. a posterior sd), unless a global MAP search (stream `(seed,
/// GlobalMapSearch, [0, 0])`) climbs [`MISSED_MODE_NATS`] above it (then
/// [`AtOptimum::Unreliable`]): the Laplace evidence at `optimum` (FD steps 0.05,
/// then 0.01 and 0.002 of `scales`, as [`estimate`]'s), and the importance
/// evidence from the mixture of a Student-t there (the Laplace covariance)
/// and a kernel density of `population` (≥ d + 2 points that cover the
/// posterior's bulk: e.g. a sub-model's posterior draws with prior draws of
/// the parameters this posterior adds), [`IMPORTANCE_DRAWS_PER_SAMPLE`] ×
/// samples draws and more up to [`IMPORTANCE_MAX_DRAW_FACTOR`] × as in
/// [`estimate`] (stream `(seed, ImportanceDraw, [2, 0])`). When that batch
/// falls short of [`IMPORTANCE_MIN_ESS`], up to [`IMPORTANCE_ADAPT_ROUNDS`]
/// more batches follow (streams `[2, r]`), each from a proposal of the same
/// form built from the batch before it ([`adapt`]: its weighted moments and
/// a resample of its draws, or, below [`adapt_min_ess`], its elite); the
/// last batch alone is the estimate. When its ESS reaches
/// [`IMPORTANCE_MIN_ESS`] it is the evidence, the posterior draws are
/// min(samples, ⌊ESS⌋) resampled from its weighted draws, and no TMCMC runs;
/// otherwise [`AtOptimum::Unreliable`].
///
/// An adapted batch must also pass PSIS's Pareto k̂ ([`pareto_k`]): an
/// adapted proposal is narrower than the first, and on a curved ridge
/// (`tests/bayes_tmcmc.rs`) one round reached ESS 160 with ln Ẑ 0.26 nats
/// (3.4 se) below the exact value and k̂ = 0.89, above the 0.69 threshold at
/// that size: the ESS and se measure the draws, k̂ the tail they did not
/// reach. The first batch is held to the ESS alone, as [`estimate`]'s is.
///
/// Why the last batch alone: given the batches before it, its proposal is
/// fixed and its Ẑ unbiased, with its own ESS and se; pooling the batches
/// would need the deterministic-mixture weights of AMIS (Cornuet et al.
/// 2012), whose estimator is consistent but not unbiased, to gain a factor
/// below 1.5 on draws that cost a few per cent of a TMCMC run. Why adapt at
/// all: the first proposal misses where the screening optimum's Laplace
/// covariance is not the posterior's (the Hessian not positive definite at
/// a parameter that does nothing, a curved ridge between a cause and e0a);
/// on the ten CI cases of the hidden suite most failed first batches had
/// ESS 1–14 of 1 600, and with adaptation the models whose evidence came
/// from the optimum alone went from 133 to 196 of the 399 computed
/// (`benches/README.md`, "The importance evidence from an optimum, adapted").
///
/// Why: [`estimate`] already takes the importance evidence as the evidence
/// whenever it is reliable; TMCMC there contributes the population the
/// mixture's kernel density covers and the MAP search's start, at 10–20 ×
/// the solves of the importance draws (a 5-mode diagnosis: 40–70 thousand
/// solves a model against 2–13 thousand). A caller that has an optimum and a
/// population already (a model that adds a cause to a fitted sub-model)
/// needs only the draws. The estimate is unbiased whatever the proposal
/// (self-normalised weights), and its se is ≈ 1/√ESS; what the ESS cannot
/// see is a mode neither component reaches, the blind spot [`estimate`]'s
/// importance evidence shares. So a posterior multimodal by construction is
/// not for this estimator: the caller runs [`estimate`] with its global and
/// nested searches.
#[allow(clippy::too_many_arguments)]
pub fn estimate_at_optimum<P: Posterior>(
    posterior: &P,
    s: &EvidenceSettings,
    seed: u64,
    optimum: &[f64],
    scales: &[f64],
    population: &[Vec<f64>],
    control: &Control,
) -> Result<AtOptimum, BayesError> {
    s.validate()?;
    let started = std::time::Instant::now();
    let counted_all = Counted::new(posterior);
    let counted = Controlled::new(&counted_all, control);
    control.check()?;
    // a peak the optimum's own search did not reach ([`MISSED_MODE_NATS`]):
    // the global search against the optimum polished where it is
    let at = counted.log_posterior(optimum);
    let local = polish_best(&counted, scales, vec![optimum.to_vec()], 1, s.map_iters)
        .into_iter()
        .next()
        .map_or(at, |m| m.log_posterior.max(at));
    if global_map(&counted, scales, s, seed).is_some_and(|g| g.log_posterior > local + MISSED_MODE_NATS) {
        control.check()?;
        return Ok(AtOptimum::Unreliable { forward_evaluations: counted_all.count() });
    }
    control.check()?;
    let laplace =
        [0.05, 0.01, 0.002].into_iter().find_map(|h| laplace_log_evidence_with_step(&counted, optimum, scales, h).ok());
    control.check()?;
    let Ok(proposal) =
        MixtureProposal::new(counted.dim(), optimum, laplace.as_ref().map(|l| l.covariance.as_slice()), population)
    else {
        return Ok(AtOptimum::Unreliable { forward_evaluations: counted_all.count() });
    };
    let mut batch = Batch::draw(&counted, &proposal, s, child_seed(seed, Purpose::ImportanceDraw, [2, 0]));
    control.check()?;
    // adaptation (doc): each round's proposal from the last round's weighted
    // draws, kept defensive by the first proposal; only the last round's
    // draws enter the estimate
    fn defended<'a>(base: &'a MixtureProposal<'a>, (centre, cov, population): &'a Adapted) -> Option<Defended<'a>> {
        MixtureProposal::new(centre.len(), centre, Some(cov), population).ok().map(|inner| Defended { base, inner })
    }
    let mut adapted: Option<Adapted> = None;
    let mut rounds = 0;
    for round in 1..=IMPORTANCE_ADAPT_ROUNDS as u64 {
        let Some(last) = batch.as_ref().filter(|b| !b.trusted(round > 1)) else {
            break;
        };
        let next = match &adapted {
            Some(a) => defended(&proposal, a).and_then(|p| adapt(&p, last, s.samples, counted.dim())),
            None => adapt(&proposal, last, s.samples, counted.dim()),
        };
        let Some(next) = next else { break };
        let Some(p) = defended(&proposal, &next) else { break };
        let next_batch = Batch::draw(&counted, &p, s, child_seed(seed, Purpose::ImportanceDraw, [2, round]));
        control.check()?;
        batch = next_batch;
        adapted = Some(next);
        rounds = round as usize;
    }
    let forward_evaluations = counted_all.count();
    let Some(b) = batch.filter(|b| b.trusted(rounds > 0)) else {
        return Ok(AtOptimum::Unreliable { forward_evaluations });
    };
    let draws = match &adapted {
        Some(a) => defended(&proposal, a).map(|p| b.resampled(&p, s)).unwrap_or_default(),
        None => b.resampled(&proposal, s),
    };
    if draws.is_empty() {
        return Ok(AtOptimum::Unreliable { forward_evaluations });
    }
    Ok(AtOptimum::Reliable(Box::new(Evidence {
        log_evidence: b.is.log_evidence,
        log_evidence_se: b.is.log_evidence_se,
        tmcmc: None,
        log_evidence_runs: vec![],
        draws,
        map: optimum.to_vec(),
        log_evidence_laplace: laplace.map(|l| l.log_evidence),
        missed_peak: false,
        importance: Some(b.is),
        seed,
        importance_rounds: rounds,
        forward_evaluations,
        elapsed_s: started.elapsed().as_secs_f64(),
    })))
}

/// How far above the optimum given to [`estimate_at_optimum`] (polished
/// where it is: an optimum short of its own peak is no missed mode) a global
/// MAP search ([`global_map`], from prior draws) must climb for that optimum
/// to be taken as a local one, and the evidence left to [`estimate`]: 1 nat.
///
/// Why: the importance evidence from an optimum cannot see a mode that
/// neither its t at the optimum nor its kernels (a sub-model's draws with
/// prior draws of the added parameters) reach, and its ESS and Pareto k̂
/// then look healthy. Audited against the TMCMC path on 30 records
/// (`tests/evidence.md`, "The evidence from an optimum, audited"): the
/// shear-deformation single of 8 records sat at the sub-model's e0a,
/// 9–156 nats below the evidence TMCMC found at the mode where shear and
/// e0a trade (e0a ≈ 0.3–0.4 nm against the base's 0.6), and the pair of
/// viscous damping and axial force 9.3 nats below on one record; the guard
/// sends all of them to TMCMC and changes none of the 30 verdicts. The
/// search costs at most 2000 + 8 · 2 · `map_iters` solves and the polish
/// 2 · `map_iters`, a fraction of the TMCMC run it saves or calls for.
pub const MISSED_MODE_NATS: f64 = 1.0;

/// An adapted proposal's centre, covariance and kernel population ([`adapt`]).
type Adapted = (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>);

/// The inputs of the next adapted proposal (centre, covariance, kernel
/// population) from a batch of `proposal`'s draws that was not reliable:
/// with ESS ≥ [`adapt_min_ess`], the batch's weighted moments and `samples`
/// draws resampled by weight (population Monte Carlo, Cappé et al. 2004);
/// below it, too few draws carry the weight for moments, so the elite of
/// the cross-entropy method instead: the [`elite_count`] draws of largest
/// weight, their mean, their (unweighted) covariance and themselves, wider
/// than the posterior where the proposal was, which the next batch's
/// weights then correct. `None` when no weight is finite.
fn adapt(proposal: &dyn Proposal, batch: &Batch, samples: usize, d: usize) -> Option<Adapted> {
    if batch.is.ess >= adapt_min_ess(d) {
        let (centre, cov) = proposal.weighted_moments(&batch.log_w, batch.seed)?;
        return Some((centre, cov, proposal.resample(&batch.log_w, samples, batch.seed)));
    }
    let mut order: Vec<usize> = (0..batch.log_w.len()).filter(|&i| batch.log_w[i].is_finite()).collect();
    let k = elite_count(d, batch.log_w.len());
    if order.len() < k {
        return None;
    }
    order.sort_by(|&a, &b| batch.log_w[b].total_cmp(&batch.log_w[a]).then(a.cmp(&b)));
    let elite: Vec<Vec<f64>> = order[..k].iter().map(|&i| proposal.draw(i, batch.seed)).collect();
    let mean: Vec<f64> = (0..d).map(|j| elite.iter().map(|x| x[j]).sum::<f64>() / k as f64).collect();
    let cov = sample_covariance(&elite);
    let cov = (0..d).map(|i| (0..d).map(|j| cov[(i, j)]).collect()).collect();
    Some((mean, cov, elite))
}

/// The elite of [`adapt`]'s cross-entropy step: the larger of 4(d + 2) and a
/// twentieth of the batch (the usual elite fraction of the cross-entropy
/// method is 1–10 %), enough distinct draws for a kernel density in d
/// dimensions.
fn elite_count(d: usize, draws: usize) -> usize {
    (4 * (d + 2)).max(draws / 20)
}

/// Adaptation rounds of [`estimate_at_optimum`] when its first batch is not
/// reliable: 2. See [`adapt_min_ess`] for when a round is tried.
pub const IMPORTANCE_ADAPT_ROUNDS: usize = 2;

/// The least ESS of a batch from which [`estimate_at_optimum`] adapts its
/// proposal: 2(d + 2). The next proposal's t component takes the batch's
/// weighted covariance and its kernel density a resample of its draws; with
/// fewer than d + 2 effective draws that covariance is not positive definite
/// (the resample has too few distinct points), and twice that keeps the
/// moments from resting on one or two heavy draws.
fn adapt_min_ess(d: usize) -> f64 {
    2.0 * (d as f64 + 2.0)
}

/// [`estimate`], then [`replicate`] when [`Evidence::needs_replicates`] at
/// `bar`: the whole estimator for one posterior on its own.
pub fn estimate_replicated<P: Posterior>(
    posterior: &P,
    s: &EvidenceSettings,
    seed: u64,
    multimodal: bool,
    sub_models: &[SubModelMap<'_>],
    bar: f64,
    control: &Control,
) -> Result<Evidence, BayesError> {
    let run = estimate(posterior, s, seed, multimodal, sub_models, control)?;
    if run.needs_replicates(bar) {
        replicate(run, posterior, s, control)
    } else {
        Ok(run)
    }
}

/// The importance evidence (module doc) at the MAP `map` with the Laplace
/// covariance there (the population's when Laplace failed), drawing
/// [`IMPORTANCE_DRAWS_PER_SAMPLE`] × samples, and more when that falls short
/// of [`IMPORTANCE_MIN_ESS`] by a factor more draws can make up
/// ([`importance_draws_for`]); `None` when it cannot be built (a singular
/// population covariance). With `resample`, and when the estimate is
/// reliable (ESS ≥ [`IMPORTANCE_MIN_ESS`]), also min(samples, ⌊ESS⌋)
/// posterior draws resampled from its weighted draws (empty otherwise).
#[allow(clippy::too_many_arguments)]
fn importance_at(
    counted: &dyn Posterior,
    map: &[f64],
    laplace: Option<&LaplaceEvidence>,
    population: &[Vec<f64>],
    s: &EvidenceSettings,
    seed: u64,
    stream: [u64; 2],
    resample: bool,
) -> (Option<ImportanceEvidence>, Vec<Vec<f64>>) {
    let Ok(proposal) = MixtureProposal::new(counted.dim(), map, laplace.map(|l| l.covariance.as_slice()), population)
    else {
        return (None, vec![]);
    };
    match Batch::draw(counted, &proposal, s, child_seed(seed, Purpose::ImportanceDraw, stream)) {
        Some(b) => {
            let draws = if resample { b.resampled(&proposal, s) } else { vec![] };
            (Some(b.is), draws)
        }
        None => (None, vec![]),
    }
}

/// One batch of importance draws from a proposal: the estimate, the log
/// weights, and the seed of their streams (draw i is a function of (seed, i)).
struct Batch {
    is: ImportanceEvidence,
    log_w: Vec<f64>,
    seed: u64,
}

impl Batch {
    /// [`IMPORTANCE_DRAWS_PER_SAMPLE`] × samples draws of `proposal`, and
    /// more when that falls short of [`IMPORTANCE_MIN_ESS`] by a factor more
    /// draws can make up ([`importance_draws_for`]); `None` when no weight is finite.
    fn draw(counted: &dyn Posterior, proposal: &dyn Proposal, s: &EvidenceSettings, seed: u64) -> Option<Self> {
        let base = IMPORTANCE_DRAWS_PER_SAMPLE * s.samples;
        let mut log_w = proposal.log_weights(counted, 0..base, seed);
        let first = evidence_from_log_weights(&log_w).ok()?;
        let is = match importance_draws_for(&first, base) {
            // draws base..more extend the first batch (draw i depends on i alone)
            Some(more) => {
                log_w.extend(proposal.log_weights(counted, base..more, seed));
                evidence_from_log_weights(&log_w).unwrap_or(first)
            }
            None => first,
        };
        Some(Self { is, log_w, seed })
    }

    fn reliable(&self) -> bool {
        self.is.ess >= IMPORTANCE_MIN_ESS
    }

    /// Reliable, and for a batch of an adapted proposal also a Pareto k̂ of
    /// its weights within [`pareto_k_threshold`] ([`estimate_at_optimum`]'s doc).
    fn trusted(&self, adapted: bool) -> bool {
        self.reliable() && (!adapted || pareto_k(&self.log_w) <= pareto_k_threshold(self.log_w.len()))
    }

    /// min(samples, ⌊ESS⌋) posterior draws resampled by weight when the
    /// estimate is reliable, none otherwise.
    fn resampled(&self, proposal: &dyn Proposal, s: &EvidenceSettings) -> Vec<Vec<f64>> {
        if self.reliable() {
            proposal.resample(&self.log_w, s.samples.min(self.is.ess.floor() as usize), self.seed)
        } else {
            vec![]
        }
    }
}

/// The draws of a posterior ([`Evidence::draws`]): `resampled` (importance
/// draws resampled by weight, non-empty only when TMCMC's population missed
/// the MAP and the importance evidence is reliable), else TMCMC's final
/// population.
///
/// Why: a caller that judges a model by its posterior draws (predictive
/// checks) would call a model that contains the truth a misfit when a short
/// TMCMC run ended in a secondary mode. The importance evidence, whose
/// proposal has a t component at the MAP, is then the evidence; its
/// resampled draws are the posterior it estimates.
fn posterior_draws(t: &TmcmcResult, resampled: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    if resampled.is_empty() {
        t.samples.clone()
    } else {
        resampled
    }
}

/// Prior points screened by the global MAP search ([`global_map`]) and how
/// many of the best are polished: 2000 and 8, at most 2000 + 8 · 2 ·
/// `map_iters` solves plus the polishes' simplex set-up, a small fraction of
/// a TMCMC run; fewer found the global mode less often, more cost twice as
/// much for little more (`tests/evidence.md`).
pub const GLOBAL_SEARCH_POINTS: usize = 2000;
pub const GLOBAL_SEARCH_KEEP: usize = 8;

/// The best optimum of a multi-start Nelder–Mead search from the
/// [`GLOBAL_SEARCH_KEEP`] best of [`GLOBAL_SEARCH_POINTS`] prior draws
/// (stream `(seed, GlobalMapSearch, [0, 0])`), simplex steps `sd`; `None`
/// when no prior draw has a finite posterior. Run on posteriors multimodal
/// by construction only ([`estimate`]'s `multimodal`).
///
/// Why, beside the MAP from the population's best sample: on a posterior
/// with a narrow global mode that TMCMC's annealing passes by, the
/// population's best sample climbs to a local one.
fn global_map(counted: &dyn Posterior, sd: &[f64], s: &EvidenceSettings, seed: u64) -> Option<MapResult> {
    let rng = crate::bayes::rng::stream(seed, Purpose::GlobalMapSearch, [0, 0]);
    multi_start_from(counted, sd, GLOBAL_SEARCH_POINTS, GLOBAL_SEARCH_KEEP, rng, s.map_iters).into_iter().next()
}

/// Prior draws of the added parameters screened per sub-model by the nested
/// MAP search ([`nested_map`]), and how many of the best are polished: 500
/// and 2. The added parameters number one or two, so 500 draws put about
/// 22 per axis on a grid's worth of them; the cost is in the polishes
/// (≈ 650 solves each), so two (`tests/evidence.md`).
pub const NESTED_SEARCH_POINTS: usize = 500;
pub const NESTED_SEARCH_KEEP: usize = 2;

/// The best MAP found from the MAPs of `sub_models`: each sub-model's MAP
/// fills the parameters the two posteriors share (matched by name),
/// [`NESTED_SEARCH_POINTS`] prior draws fill the ones this posterior adds
/// (stream `(seed, NestedMapSearch, [k, 0])` for the k-th sub-model), and the
/// [`NESTED_SEARCH_KEEP`] best are polished with simplex steps `sd`. `None`
/// without sub-models. Run, like [`global_map`], on posteriors multimodal by
/// construction only.
///
/// Why: a model that adds a cause to a fitting sub-model usually peaks near
/// that sub-model's MAP in the shared parameters, with the added ones
/// wherever they explain the rest, and one or two added parameters are
/// searched far more densely than all of them by [`global_map`]'s prior
/// draws.
fn nested_map(
    counted: &dyn Posterior,
    sd: &[f64],
    s: &EvidenceSettings,
    seed: u64,
    sub_models: &[SubModelMap<'_>],
) -> Option<MapResult> {
    let names = counted.names();
    sub_models
        .iter()
        .enumerate()
        .filter_map(|(k, sub)| {
            let shared: Vec<Option<f64>> =
                names.iter().map(|n| sub.names.iter().position(|m| m == n).map(|j| sub.map[j])).collect();
            let mut rng = crate::bayes::rng::stream(seed, Purpose::NestedMapSearch, [k as u64, 0]);
            let starts: Vec<Vec<f64>> = (0..NESTED_SEARCH_POINTS)
                .map(|_| {
                    let draw = counted.sample_prior(&mut rng);
                    shared.iter().zip(draw).map(|(fixed, x)| fixed.unwrap_or(x)).collect()
                })
                .collect();
            polish_best(counted, sd, starts, NESTED_SEARCH_KEEP, s.map_iters).into_iter().next()
        })
        .max_by(|a, b| a.log_posterior.total_cmp(&b.log_posterior))
}

/// Importance draws that bring an estimate of ESS `is.ess` from `base`
/// draws up to [`IMPORTANCE_MIN_ESS`]: the ESS of self-normalised weights
/// grows in proportion to the draws, so n = base · 1.25 · MIN_ESS / ESS
/// (25 % for the ESS estimate's own scatter); `None` when the estimate is
/// reliable already or would need more than [`IMPORTANCE_MAX_DRAW_FACTOR`] ×
/// base (a proposal that misses a mode: more draws do not help it).
///
/// Why: a short TMCMC run's evidence of a 5–6-parameter posterior can be off
/// by several nats while its se says 0.2, and an error that size decides
/// between two confounded models. More draws do not remove every bias (a
/// proposal built from a short run's population can miss some of the mass,
/// which the ESS cannot see), but they make a reliable estimate of what it
/// covers.
fn importance_draws_for(is: &ImportanceEvidence, base: usize) -> Option<usize> {
    if is.ess >= IMPORTANCE_MIN_ESS || !(is.ess > 0.0) {
        return None;
    }
    let n = (base as f64 * 1.25 * IMPORTANCE_MIN_ESS / is.ess).ceil();
    (n <= (IMPORTANCE_MAX_DRAW_FACTOR * base) as f64).then_some(n as usize)
}

/// The evidence and its se: the importance estimate when reliable, TMCMC's otherwise.
fn chosen(t: &TmcmcResult, importance: Option<&ImportanceEvidence>) -> (f64, f64) {
    match importance.filter(|is| is.ess >= IMPORTANCE_MIN_ESS) {
        Some(is) => (is.log_evidence, is.log_evidence_se),
        None => (t.log_evidence, t.log_evidence_se),
    }
}

/// `run` (of `posterior`, computed by [`estimate`]) with [`EVIDENCE_REPLICATES`]
/// TMCMC runs in all, combined ([`combine`]); the MAP and Laplace evidence
/// are redone when the kept population holds a better point than the MAP.
/// Callers use it for the runs [`Evidence::needs_replicates`] names.
pub fn replicate<P: Posterior>(
    run: Evidence,
    posterior: &P,
    s: &EvidenceSettings,
    control: &Control,
) -> Result<Evidence, BayesError> {
    s.validate()?;
    let started = std::time::Instant::now();
    let Evidence { tmcmc: first, mut map, seed, .. } = run;
    let d = posterior.dim();
    let counted_tmcmc = Counted::new(posterior);
    // an evidence from an optimum has no TMCMC run yet: its first is run here
    let first = match first {
        Some(t) => t,
        None => tmcmc_controlled(&counted_tmcmc, &s.tmcmc_config(d, seed), control)?,
    };
    let mut runs = vec![first];
    for r in 1..EVIDENCE_REPLICATES {
        let seed = child_seed(seed, Purpose::EvidenceReplicate, [r as u64, 0]);
        runs.push(tmcmc_controlled(&counted_tmcmc, &s.tmcmc_config(d, seed), control)?);
    }
    // the searches and batches below poll the control at every evaluation
    let counted = Controlled::new(&counted_tmcmc, control);
    let log_evidence_runs: Vec<f64> = runs.iter().map(|t| t.log_evidence).collect();
    let pooled: Vec<Vec<f64>> = runs.iter().flat_map(|t| t.samples.iter().cloned()).collect();
    let t = combine(runs, posterior)?;
    if best_sample(&t, posterior)?.1 > posterior.log_posterior(&map) {
        map = map_from_best(&counted, &t, s)?.theta;
    }
    control.check()?;
    // redone at the final MAP with the kept population's scales; its
    // covariance shapes the importance proposal's t component
    let laplace = laplace_at(&counted, &map, &t);
    control.check()?;
    let log_evidence_laplace = laplace.as_ref().map(|l| l.log_evidence);
    let shortfall = posterior.log_posterior(&map) - best_sample(&t, posterior)?.1;
    let population_missed = shortfall > missed_peak_nats(d, s.samples);
    let (importance, resampled) =
        importance_at(&counted, &map, laplace.as_ref(), &pooled, s, seed, [1, 0], population_missed);
    control.check()?;
    let (log_evidence, log_evidence_se) = chosen(&t, importance.as_ref());
    Ok(Evidence {
        log_evidence,
        log_evidence_se,
        log_evidence_runs,
        draws: posterior_draws(&t, resampled),
        tmcmc: Some(t),
        map,
        log_evidence_laplace,
        missed_peak: true,
        importance,
        seed,
        importance_rounds: 0,
        forward_evaluations: run.forward_evaluations + counted_tmcmc.count(),
        elapsed_s: run.elapsed_s + started.elapsed().as_secs_f64(),
    })
}

/// Importance draws per TMCMC sample: 4, a few per cent of a TMCMC run's
/// solves, against the three replicate runs a reliable estimate saves.
pub const IMPORTANCE_DRAWS_PER_SAMPLE: usize = 4;

/// The most importance draws, as a multiple of the first batch, spent on
/// reaching [`IMPORTANCE_MIN_ESS`]: 8 × the first batch, a quarter of a
/// TMCMC run, against the 3 more runs of [`replicate`] it can save. An ESS
/// below 100/8 · 1.25 ≈ 16 is not extended.
pub const IMPORTANCE_MAX_DRAW_FACTOR: usize = 8;

/// Least effective sample size at which the importance evidence replaces
/// TMCMC's. The weights' coefficient of variation is cv ≈ √(n/ESS − 1), so
/// se(ln Ẑ) = cv/√n ≈ 1/√ESS: ESS ≥ 100 keeps the se ≲ 0.1 nats, a thirtieth
/// of a 3-nat decision margin, and the se estimate itself stable.
pub const IMPORTANCE_MIN_ESS: f64 = 100.0;

/// TMCMC runs of a posterior when the first missed the peak: this one and
/// `EVIDENCE_REPLICATES − 1` more. The spread of ln Ẑ between seeds on such
/// posteriors is many times what the stage estimator says, so one run is not
/// enough; four bound the cost at 4× for the runs the caller replicates.
pub const EVIDENCE_REPLICATES: usize = 4;

/// The largest shortfall, in nats, of the best of `n` posterior draws below
/// the peak of a `d`-dimensional near-Gaussian posterior that is not a sign
/// of a missed peak: 2·(log π(θ̂) − log π(θ_i)) ~ χ²_d, so the best of n
/// falls short by more than g with probability P(χ²_d > 2g)^n; g is set
/// where that is 1e-3. (d = 7, n = 400: 0.74 nats; d = 6, n = 50: 1.24.)
pub fn missed_peak_nats(d: usize, n: usize) -> f64 {
    let q = 1.0 - 1e-3f64.powf(1.0 / n as f64);
    ChiSquared::new(d as f64).map_or(f64::INFINITY, |c| 0.5 * c.inverse_cdf(q))
}

/// The best sample of a population and its log posterior.
fn best_sample(t: &TmcmcResult, posterior: &dyn Posterior) -> Result<(Vec<f64>, f64), BayesError> {
    t.samples
        .iter()
        .zip(&t.log_likelihoods)
        .map(|(u, &l)| (u, l + posterior.log_prior(u)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(u, l)| (u.clone(), l))
        .ok_or(BayesError::NoFiniteLikelihood { stage: t.stages.len() })
}

/// The Laplace evidence at `map` (`None` when the MAP sits on a prior
/// boundary or the Hessian is not positive definite). FD step 0.05 sd: the
/// O(h²) truncation error is ≈ 0.25 % of the curvature of a near-Gaussian
/// posterior, while the forward model's round-off (~1e-12 relative) stays
/// negligible against the h²-sized differences.
///
/// When that fails, steps 0.01 and 0.002 sd are tried: a population that
/// missed the MAP's mode has an sd far wider than that mode, and 0.05 of it
/// steps out of the mode (or out of the prior's support); the truncation
/// error falls with h², so the finer steps agree where both succeed.
fn laplace_at(counted: &dyn Posterior, map: &[f64], t: &TmcmcResult) -> Option<LaplaceEvidence> {
    let sd = sample_sd(&t.samples, map.len());
    [0.05, 0.01, 0.002].into_iter().find_map(|h| laplace_log_evidence_with_step(counted, map, &sd, h).ok())
}

/// The MAP by Nelder–Mead from the best sample of `t`, initial simplex half
/// a posterior sd per coordinate.
fn map_from_best(counted: &dyn Posterior, t: &TmcmcResult, s: &EvidenceSettings) -> Result<MapResult, BayesError> {
    let (best, _) = best_sample(t, counted)?;
    let sd = sample_sd(&t.samples, best.len());
    let half_sd: Vec<f64> = sd.iter().zip(&best).map(|(s, b)| (0.5 * s).max(1e-12 * b.abs().max(1e-300))).collect();
    Ok(map_estimate(counted, &best, &half_sd, s.map_iters))
}

/// One evidence from replicate runs: ln of the mean of the Ẑ_r (each run's
/// Ẑ estimates Z without bias — the SMC normalising-constant property — so
/// their mean does too, while a mean of ln Ẑ would carry each run's
/// shortfall), with the delta-method standard error sd(Ẑ_r)/(√R·mean Ẑ),
/// never below the largest stage estimate over √R. The population kept for
/// the posterior draws is that of the run whose best sample is highest (the
/// one that found the peak). `runs` holds at least two runs.
fn combine(runs: Vec<TmcmcResult>, posterior: &dyn Posterior) -> Result<TmcmcResult, BayesError> {
    let lz: Vec<f64> = runs.iter().map(|t| t.log_evidence).collect();
    let se_stage = runs.iter().map(|t| t.log_evidence_se).fold(0.0, f64::max);
    let (log_evidence, log_evidence_se) = mean_log_evidence(&lz, se_stage);
    let mut keep = 0;
    let mut keep_peak = f64::NEG_INFINITY;
    for (k, t) in runs.iter().enumerate() {
        let peak = best_sample(t, posterior)?.1;
        if peak > keep_peak {
            (keep, keep_peak) = (k, peak);
        }
    }
    let mut t = runs.into_iter().nth(keep).expect("keep < runs");
    t.log_evidence = log_evidence;
    t.log_evidence_se = log_evidence_se;
    Ok(t)
}

/// ln of the mean of exp(`lz`) and its delta-method standard error
/// sd(Ẑ_r)/(√R·mean Ẑ), at least `se_stage`/√R (R ≥ 2 runs, each with a
/// stage-estimator error ≤ `se_stage`).
fn mean_log_evidence(lz: &[f64], se_stage: f64) -> (f64, f64) {
    let r = lz.len() as f64;
    let top = lz.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let z: Vec<f64> = lz.iter().map(|l| (l - top).exp()).collect();
    let mean = z.iter().sum::<f64>() / r;
    let var = z.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (r - 1.0);
    (top + mean.ln(), ((var / r).sqrt() / mean).max(se_stage / r.sqrt()))
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::Distribution;

    #[test]
    fn importance_draws_grow_to_the_ess_target_within_the_cap() {
        let is = |ess: f64| ImportanceEvidence { log_evidence: 0.0, log_evidence_se: 0.0, ess, draws: 1600 };
        // ESS 50 of 1600: 1600 · 1.25 · 100/50 = 4000 draws
        assert_eq!(importance_draws_for(&is(50.0), 1600), Some(4000));
        // reliable already, or beyond 8× (ESS < 15.6), or no weight at all: as it is
        assert_eq!(importance_draws_for(&is(100.0), 1600), None);
        assert_eq!(importance_draws_for(&is(15.0), 1600), None);
        assert_eq!(importance_draws_for(&is(0.0), 1600), None);
        assert_eq!(importance_draws_for(&is(f64::NAN), 1600), None);
        assert_eq!(importance_draws_for(&is(20.0), 1600), Some(10000));
    }

    #[test]
    fn replicate_evidences_average_in_z_not_in_log_z() {
        // Ẑ = 1 and 3: mean 2, sd √2, se √2/(√2·2) = 0.5
        let (lz, se) = mean_log_evidence(&[0.0, 3f64.ln()], 0.1);
        assert!((lz - 2f64.ln()).abs() < 1e-15, "{lz}");
        assert!((se - 0.5).abs() < 1e-15, "{se}");
        // identical runs: the stage estimate, shrunk by √R, is the floor
        let (lz, se) = mean_log_evidence(&[-7.0; 4], 0.2);
        assert!((lz + 7.0).abs() < 1e-15 && (se - 0.1).abs() < 1e-15, "{lz} {se}");
    }

    /// The shortfall of the best of n Gaussian-posterior draws exceeds the
    /// bound with probability 1e-3: over 20 000 simulated populations about
    /// 20 exceed it (Poisson, sd 4.5); outside 20 ± 5 sd the bound is wrong.
    #[test]
    fn missed_peak_bound_is_exceeded_at_its_stated_rate() {
        let (d, n, trials) = (6usize, 50usize, 20_000usize);
        let g = missed_peak_nats(d, n);
        let chi = rand_distr::ChiSquared::new(d as f64).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(13);
        let exceed = (0..trials)
            .filter(|_| (0..n).map(|_| 0.5 * chi.sample(&mut rng)).fold(f64::INFINITY, f64::min) > g)
            .count();
        let expected = 1e-3 * trials as f64;
        assert!((exceed as f64 - expected).abs() < 5.0 * expected.sqrt(), "{exceed} exceedances, expected {expected}");
        // the figures the doc quotes
        assert!((missed_peak_nats(7, 400) - 0.74).abs() < 0.01, "{}", missed_peak_nats(7, 400));
        assert!((missed_peak_nats(6, 50) - 1.24).abs() < 0.01, "{}", missed_peak_nats(6, 50));
    }
}
