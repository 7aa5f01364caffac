//! Transitional Markov chain Monte Carlo (Ching & Chen 2007, J. Eng. Mech.
//! 133(7)), the sampler Muto & Beck (2008) use for model-class selection: it
//! returns posterior samples and the log evidence log p(y) = log ∫ L(θ) π(θ) dθ.
//!
//! Algorithm (stages j = 0, 1, …, m with 0 = p_0 < p_1 < … < p_m = 1):
//! 1. draw N samples θ_i ~ π(θ) (the prior), compute ℓ_i = log L(θ_i);
//! 2. given p_j, pick p_{j+1} ∈ (p_j, 1] by bisection so the plausibility weights
//!    w_i = L(θ_i)^{p_{j+1} − p_j} have coefficient of variation
//!    std(w)/mean(w) (population std) equal to the target (1.0); take
//!    p_{j+1} = 1 if the CoV at p = 1 is already below the target;
//! 3. log-evidence increment S_j = log((1/N) Σ_i w_i), in log-sum-exp form
//!    S_j = Δp·ℓ_max + log((1/N) Σ exp(Δp(ℓ_i − ℓ_max))); log p(y) ≈ Σ_j S_j;
//! 4. resample N indices with probabilities w̄_i = w_i/Σw (multinomial);
//! 5. move every resampled θ by `mh_steps` Metropolis–Hastings steps targeting
//!    π_{j+1}(θ) ∝ π(θ) L(θ)^{p_{j+1}}, with Gaussian proposal covariance
//!    β²·Σ_w, Σ_w the w̄-weighted sample covariance of the stage-j samples
//!    (Ching & Chen's choice, β = 0.2). Optionally β is adapted between stages:
//!    β ← β·exp(a_j − a*) with a_j the stage's acceptance rate, a* the target
//!    (Betz, Papaioannou & Straub 2016 adapt a scale the same way);
//! 6. stop after the stage that reaches p = 1.
//!
//! Scale invariance: the proposal uses the full sample covariance, factorised as
//! Σ_w = D R Dᵀ with D = diag(sd) and R the correlation matrix (Cholesky of R,
//! not of Σ_w), so coordinates of wildly different magnitudes (Ω ~ 1e12 next to
//! Δ ~ 0.5) neither break the Cholesky factorisation nor the moves. Nothing else
//! in the algorithm depends on coordinate units.
//!
//! A run can also start from a population other than the prior's
//! ([`tmcmc_from`], [`Start`]: a sub-model's posterior, tempered from its
//! likelihood to this one's), with every step above on L/L_ref.
//!
//! Determinism: every random stream is a ChaCha8 generator keyed by
//! (seed, stage, sample index, purpose); the per-sample work runs in parallel
//! with rayon but each sample owns its stream and all reductions are done
//! sequentially in index order, so results are byte-identical for any thread count.
//!
//! Standard error of the log evidence (`log_evidence_se`): the delta-method
//! estimate Var(S_j) ≈ CoV_j²/N for N independent weights (Var(mean w)/mean(w)²),
//! summed over stages: se = sqrt(Σ_j CoV_j²/N). It is a lower bound in spirit:
//! the resampled, MH-moved samples are positively correlated, so the true
//! run-to-run spread is larger (measured in tests/bayes_tmcmc.rs: about 1.5× there).
//! The estimator of the evidence itself is consistent as N → ∞; log p̂ carries a
//! small negative bias ≈ −se²/2 (Jensen).

use rand::{Rng, RngCore};
use rand_distr::StandardNormal;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use super::error::BayesError;
use super::rng::{stream, Purpose};
use super::{Control, Posterior};
use crate::error::InputError;

/// Settings of [`tmcmc`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TmcmcConfig {
    /// Number of samples N carried through all stages.
    pub n_samples: usize,
    /// Target coefficient of variation of the plausibility weights (Ching & Chen: 1.0).
    pub target_cov: f64,
    /// Initial proposal scale β (proposal covariance β²Σ_w; Ching & Chen: 0.2).
    pub beta: f64,
    /// MH steps per sample per stage.
    pub mh_steps: usize,
    /// Adapt β between stages toward `target_acceptance`.
    pub adapt_beta: bool,
    /// Target MH acceptance rate for the adaptation.
    pub target_acceptance: f64,
    /// Safety stop: error if p has not reached 1 after this many stages.
    pub max_stages: usize,
    /// When set, the number of MH steps of the next stage adapts to the last
    /// acceptance rate a (Betz, Papaioannou & Straub 2016): the smallest L with
    /// (1 − a)^L ≤ 0.01 (a sample stays put with probability ≤ 1 %), clamped
    /// to [`mh_steps`, `max_mh_steps`]. `None`: always `mh_steps`.
    pub max_mh_steps: Option<usize>,
    /// Seed of all random streams.
    pub seed: u64,
}

impl Default for TmcmcConfig {
    fn default() -> Self {
        Self {
            n_samples: 2000,
            target_cov: 1.0,
            beta: 0.2,
            mh_steps: 5,
            adapt_beta: true,
            target_acceptance: 0.25,
            max_stages: 200,
            max_mh_steps: None,
            seed: 0,
        }
    }
}

impl TmcmcConfig {
    /// Checks every field, naming the offending one as `tmcmc.<field>`.
    pub fn validate(&self) -> Result<(), InputError> {
        if self.n_samples < 2 {
            return Err(InputError::new("tmcmc.n_samples", self.n_samples, ">= 2"));
        }
        if self.mh_steps < 1 {
            return Err(InputError::new("tmcmc.mh_steps", self.mh_steps, ">= 1"));
        }
        if let Some(max) = self.max_mh_steps {
            if max < self.mh_steps {
                return Err(InputError::new("tmcmc.max_mh_steps", max, format!(">= mh_steps = {}", self.mh_steps)));
            }
        }
        if self.max_stages < 1 {
            return Err(InputError::new("tmcmc.max_stages", self.max_stages, ">= 1"));
        }
        crate::error::positive("tmcmc.target_cov", self.target_cov)?;
        crate::error::positive("tmcmc.beta", self.beta)?;
        if !(self.target_acceptance > 0.0 && self.target_acceptance < 1.0) {
            return Err(InputError::new("tmcmc.target_acceptance", self.target_acceptance, "in (0, 1)"));
        }
        Ok(())
    }
}

/// Output of [`tmcmc`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TmcmcResult {
    /// Estimate of log p(y) = Σ_j S_j (natural log).
    pub log_evidence: f64,
    /// Delta-method standard error sqrt(Σ_j CoV_j²/N) of `log_evidence` (see module docs).
    pub log_evidence_se: f64,
    /// Final posterior samples, `samples[i]` = θ_i.
    pub samples: Vec<Vec<f64>>,
    /// log L(θ_i) of the final samples.
    pub log_likelihoods: Vec<f64>,
    /// Tempering exponents p_0 = 0, p_1, …, p_m = 1.
    pub stages: Vec<f64>,
    /// Log-evidence increments S_j, one per transition p_j → p_{j+1}.
    pub log_evidence_increments: Vec<f64>,
    /// MH acceptance rate of each transition's moves.
    pub acceptance: Vec<f64>,
    /// Proposal scale β used in each transition.
    pub beta: Vec<f64>,
}

fn finite_or_neg_inf(x: f64) -> f64 {
    if x.is_nan() {
        f64::NEG_INFINITY
    } else {
        x
    }
}

/// Runs TMCMC on `posterior` (uses only `sample_prior`, `log_prior`, `log_likelihood`).
pub fn tmcmc(posterior: &dyn Posterior, config: &TmcmcConfig) -> Result<TmcmcResult, BayesError> {
    tmcmc_controlled(posterior, config, &Control::default())
}

/// [`tmcmc`] that polls `control` before each stage and before each
/// sample's likelihood or moves within a stage ([`crate::bayes::control`]):
/// once cancelled, the remaining samples of the stage are skipped and
/// [`BayesError::Cancelled`] is returned. Not cancelled, the result is
/// [`tmcmc`]'s, bit for bit.
pub fn tmcmc_controlled(
    posterior: &dyn Posterior,
    config: &TmcmcConfig,
    control: &Control,
) -> Result<TmcmcResult, BayesError> {
    tmcmc_from(posterior, config, control, None)
}

/// ln L_ref(θ) of a [`Start`].
pub type Reference<'a> = &'a (dyn Fn(&[f64]) -> f64 + Sync);

/// Where [`tmcmc_from`] starts instead of the prior: a population drawn from
/// q₀(θ) = π(θ)·L_ref(θ)/Z_ref, the posterior of the same prior under a
/// reference likelihood L_ref whose evidence Z_ref is known (e.g. a
/// sub-model's posterior draws, with prior draws of the parameters this
/// posterior adds, when the sub-model's likelihood is L_ref read on the
/// shared parameters and the two priors agree on them).
///
/// The tempering then runs on the path π_p(θ) ∝ π(θ)·L_ref(θ)^(1−p)·L(θ)^p
/// from p = 0 (q₀) to p = 1 (the posterior), and every step of the module
/// doc holds with L replaced by L/L_ref: the plausibility weights are
/// (L/L_ref)^Δp, the Metropolis moves target π_p, and
/// ln Z = ln Z_ref + Σ_j S_j (the product of the stages' ratios
/// Z_{p_{j+1}}/Z_{p_j}, telescoping from Z_0 = Z_ref). Where L_ref is close
/// to L (a cause that the data barely need), two to five stages reach p = 1,
/// against 12–16 from the prior on the diagnoses measured
/// (`benches/README.md`); each move then costs one
/// evaluation of L_ref besides L's (none in the last stage, where its power
/// is 0).
pub struct Start<'a> {
    /// The population, `n_samples` vectors drawn from q₀.
    pub samples: Vec<Vec<f64>>,
    /// ln L_ref(θ).
    pub reference: Reference<'a>,
    /// ln Z_ref and its standard error (added in quadrature to the run's).
    pub log_evidence: f64,
    pub log_evidence_se: f64,
    /// The least ln L the start's best sample must reach to be taken
    /// (e.g. the best ln L found elsewhere less a posterior draw's plausible
    /// shortfall; −∞: no such check). The weights L/L_ref cannot see a peak
    /// of L that no start sample comes near: their spread is small where the
    /// whole start lies far from it.
    pub least_best_log_likelihood: f64,
}

/// [`tmcmc_controlled`] from `start` ([`Start`]) instead of the prior when
/// given and taken (its best sample reaches
/// [`Start::least_best_log_likelihood`] and its weights at Δp = 1 hold
/// [`START_MIN_ESS_FRACTION`]); `None`, or a start not taken, is
/// [`tmcmc_controlled`], bit for bit (the start's solves spent besides). A start population
/// of another size or dimension, or with a sample outside the prior's
/// support, is [`BayesError::BadPriorSample`] (a bug of the caller).
pub fn tmcmc_from(
    posterior: &dyn Posterior,
    config: &TmcmcConfig,
    control: &Control,
    start: Option<&Start>,
) -> Result<TmcmcResult, BayesError> {
    config.validate()?;
    let n = config.n_samples;
    let d = posterior.dim();
    let seed = config.seed;

    // Stage 0: prior samples, or the start's.
    let likelihoods = |samples: &[Vec<f64>], f: Reference| -> Result<Vec<f64>, BayesError> {
        let l = samples
            .par_iter()
            .map(|th| if control.is_cancelled() { f64::NEG_INFINITY } else { finite_or_neg_inf(f(th)) })
            .collect();
        control.check()?;
        Ok(l)
    };
    let prior_samples = || -> Vec<Vec<f64>> {
        (0..n)
            .into_par_iter()
            .map(|i| {
                let mut rng = stream(seed, Purpose::TmcmcPrior, [0, i as u64]);
                posterior.sample_prior(&mut rng as &mut dyn RngCore)
            })
            .collect()
    };
    let log_likelihood = |th: &[f64]| posterior.log_likelihood(th);
    let mut start = start;
    let mut from_start = None;
    if let Some(st) = start {
        if st.samples.len() != n {
            return Err(BayesError::BadPriorSample { index: st.samples.len(), got: d, expected: d });
        }
        // checked before any likelihood is spent on them
        if let Some(index) = st.samples.iter().position(|th| th.len() != d || !posterior.log_prior(th).is_finite()) {
            return Err(BayesError::BadPriorSample { index, got: st.samples[index].len(), expected: d });
        }
        let loglik = likelihoods(&st.samples, &log_likelihood)?;
        let logref = likelihoods(&st.samples, st.reference)?;
        let ratio: Vec<f64> = loglik.iter().zip(&logref).map(|(&l, &r)| log_ratio(l, r)).collect();
        let best = loglik.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if best >= st.least_best_log_likelihood && start_is_close(&ratio) {
            from_start = Some((st.samples.clone(), loglik, logref));
        } else {
            start = None;
        }
    }
    let prior = prior_samples();
    if let Some((index, s)) = prior.iter().enumerate().find(|(_, s)| s.len() != d) {
        return Err(BayesError::BadPriorSample { index, got: s.len(), expected: d });
    }
    let prior_sd = weighted_mean_cov(&prior, &vec![1.0 / n as f64; n]).1;
    // ln L_ref of each sample: 0 from the prior (L_ref ≡ 1, Z_ref = 1)
    let (mut samples, mut loglik, mut logref) = match from_start {
        Some(s) => s,
        None => {
            let loglik = likelihoods(&prior, &log_likelihood)?;
            (prior, loglik, vec![0.0; n])
        }
    };
    let mut logprior: Vec<f64> = samples.par_iter().map(|th| posterior.log_prior(th)).collect();

    let mut p = 0.0;
    let mut stages = vec![0.0];
    let mut increments = Vec::new();
    let mut acceptance = Vec::new();
    let mut betas = Vec::new();
    let mut se2 = start.map_or(0.0, |st| st.log_evidence_se * st.log_evidence_se);
    let mut beta = config.beta;
    // ln(L/L_ref) of each sample, the plausibility's exponent (ln L from the prior)
    let excess = |loglik: &[f64], logref: &[f64]| -> Vec<f64> {
        loglik.iter().zip(logref).map(|(&l, &r)| if start.is_some() { log_ratio(l, r) } else { l }).collect()
    };

    let mut steps = config.mh_steps;
    let mut stage = 0usize;
    while p < 1.0 {
        if stage >= config.max_stages {
            return Err(BayesError::TooManyStages { max_stages: config.max_stages, p });
        }
        stage += 1;
        control.check()?;
        let ex = excess(&loglik, &logref);
        let l_max = ex.iter().copied().filter(|x| !x.is_nan()).fold(f64::NEG_INFINITY, f64::max);
        if !l_max.is_finite() {
            return Err(BayesError::NoFiniteLikelihood { stage });
        }
        let ex: Vec<f64> = ex.into_iter().map(finite_or_neg_inf).collect();
        // Next exponent.
        let dp = next_increment(&ex, l_max, 1.0 - p, config.target_cov);
        let p_next = if dp >= 1.0 - p { 1.0 } else { p + dp };
        let dp = p_next - p;
        let w: Vec<f64> = ex.iter().map(|&l| (dp * (l - l_max)).exp()).collect();
        let sum_w: f64 = w.iter().sum();
        let mean_w = sum_w / n as f64;
        increments.push(dp * l_max + mean_w.ln());
        let var_w = w.iter().map(|x| (x - mean_w) * (x - mean_w)).sum::<f64>() / n as f64;
        se2 += var_w / (mean_w * mean_w) / n as f64;
        let wbar: Vec<f64> = w.iter().map(|x| x / sum_w).collect();

        // Proposal: β²Σ_w, Σ_w = D R D, Cholesky of R.
        let chol = proposal_factor(&samples, &wbar, &prior_sd);

        let idx = resample(seed, stage, &wbar);
        let population = Population { samples: &samples, logprior: &logprior, loglik: &loglik, logref: &logref };
        // the reference's power 1 − p is 0 in the last stage: its moves need no L_ref
        let reference = start.filter(|_| p_next < 1.0).map(|st| st.reference);
        let walk = Walk { chol: &chol, beta, p: p_next, steps, seed, stage, reference };
        let moved = mh_moves(posterior, &population, &idx, &walk, control);
        control.check()?;
        let accepted: usize = moved.iter().map(|m| m.4).sum();
        let rate = accepted as f64 / (n * steps) as f64;
        samples = Vec::with_capacity(n);
        logprior = Vec::with_capacity(n);
        loglik = Vec::with_capacity(n);
        logref = Vec::with_capacity(n);
        for (th, lp, ll, lr, _) in moved {
            samples.push(th);
            logprior.push(lp);
            loglik.push(ll);
            logref.push(lr);
        }
        acceptance.push(rate);
        betas.push(beta);
        if config.adapt_beta {
            beta *= (rate - config.target_acceptance).exp();
        }
        if let Some(max) = config.max_mh_steps {
            let wanted = if rate > 0.0 && rate < 1.0 {
                (0.01f64.ln() / (1.0 - rate).ln()).ceil() as usize
            } else {
                config.mh_steps
            };
            steps = wanted.clamp(config.mh_steps, max);
        }
        p = p_next;
        stages.push(p);
    }

    Ok(TmcmcResult {
        log_evidence: start.map_or(0.0, |st| st.log_evidence) + increments.iter().sum::<f64>(),
        log_evidence_se: se2.sqrt(),
        samples,
        log_likelihoods: loglik,
        stages,
        log_evidence_increments: increments,
        acceptance,
        beta: betas,
    })
}

/// The least Kish effective sample size, as a fraction of the samples, of
/// the plausibility weights L/L_ref of a [`Start`] population at the full
/// step Δp = 1 for the start to be taken: 0.02 (else [`tmcmc_from`] runs from
/// the prior). Why: the stage rule's CoV = 1 is an ESS of half the samples,
/// and a start whose weights at Δp = 1 lie further apart bridges two distant
/// posteriors geometrically, in more stages than the prior needs, each move
/// at two solves. Measured on hidden case 201 (a clean record, every
/// pair computed; `benches/README.md`): with no floor, a shear pair (shear
/// misfits there: its start's ESS fraction 0.0025) took 75 stages and 900
/// thousand solves against 73 thousand from the prior; the pairs' fractions
/// were 0.003–0.27, and the starts taken at 0.1, 0.02 and 0.005 took 2–3,
/// 2–5 and 2–10 stages, against 12–16 from the prior, for 1.85, 1.81 and
/// 1.85 million solves in all (2.02 from the prior).
pub const START_MIN_ESS_FRACTION: f64 = 0.02;

/// ln(L/L_ref) of a sample with ln L = `l`, ln L_ref = `r`: −∞ where L_ref = 0
/// (such a sample cannot come from q₀ and takes no weight).
fn log_ratio(l: f64, r: f64) -> f64 {
    if r.is_finite() {
        l - r
    } else {
        f64::NEG_INFINITY
    }
}

/// Whether a start whose samples have ln(L/L_ref) `ratio` is taken
/// ([`START_MIN_ESS_FRACTION`]).
fn start_is_close(ratio: &[f64]) -> bool {
    let max = ratio.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !max.is_finite() {
        return false;
    }
    let w: Vec<f64> = ratio.iter().map(|r| (r - max).exp()).collect();
    let (sum, sum2) = w.iter().fold((0.0, 0.0), |(a, b), x| (a + x, b + x * x));
    let ess = sum * sum / sum2;
    ess >= START_MIN_ESS_FRACTION * ratio.len() as f64
}

/// Coefficient of variation (population std / mean) of w_i = exp(dp(ℓ_i − ℓ_max)).
fn weight_cov(loglik: &[f64], l_max: f64, dp: f64) -> f64 {
    let n = loglik.len() as f64;
    let w: Vec<f64> = loglik.iter().map(|&l| (dp * (l - l_max)).exp()).collect();
    let m = w.iter().sum::<f64>() / n;
    let v = w.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n;
    v.sqrt() / m
}

/// Largest useful Δp ∈ (0, max_dp]: max_dp if CoV(max_dp) ≤ target, otherwise the
/// root of CoV(Δp) = target by bisection (CoV(0) = 0 and CoV grows with Δp).
/// 200 halvings of [0, max_dp] reach the f64 resolution of Δp.
fn next_increment(loglik: &[f64], l_max: f64, max_dp: f64, target: f64) -> f64 {
    if weight_cov(loglik, l_max, max_dp) <= target {
        return max_dp;
    }
    let (mut lo, mut hi) = (0.0, max_dp);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if weight_cov(loglik, l_max, mid) > target {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    // lo has CoV ≤ target; guard against a zero step when the bracket collapsed.
    if lo > 0.0 {
        lo
    } else {
        hi
    }
}

/// Multinomial resampling of the stage's normalised weights `wbar` (one
/// sequential stream per stage): the index of each new sample's parent.
fn resample(seed: u64, stage: usize, wbar: &[f64]) -> Vec<usize> {
    let n = wbar.len();
    let mut rs = stream(seed, Purpose::TmcmcResample, [stage as u64, 0]);
    let cdf: Vec<f64> = wbar
        .iter()
        .scan(0.0, |acc, x| {
            *acc += x;
            Some(*acc)
        })
        .collect();
    (0..n)
        .map(|_| {
            let u: f64 = rs.gen::<f64>() * cdf[n - 1];
            cdf.partition_point(|&c| c <= u).min(n - 1)
        })
        .collect()
}

/// The current population: samples with their log prior, log likelihood
/// and log reference likelihood ([`Start`]; 0 from the prior).
struct Population<'a> {
    samples: &'a [Vec<f64>],
    logprior: &'a [f64],
    loglik: &'a [f64],
    logref: &'a [f64],
}

/// One stage's random walk: proposal θ + β·L·z with L the Cholesky factor of
/// the weighted covariance, target π(θ)·L(θ)^p (times L_ref(θ)^(1−p) with a
/// `reference`), `steps` moves per sample.
struct Walk<'a> {
    chol: &'a [Vec<f64>],
    beta: f64,
    p: f64,
    steps: usize,
    seed: u64,
    stage: usize,
    reference: Option<Reference<'a>>,
}

/// Metropolis moves of every resampled parent `idx[i]`, in parallel, one
/// stream per sample: (θ, log prior, log likelihood, log reference
/// likelihood, accepted moves). A sample that finds `control` cancelled is
/// not moved (the caller discards the stage).
fn mh_moves(
    posterior: &dyn Posterior,
    pop: &Population,
    idx: &[usize],
    w: &Walk,
    control: &Control,
) -> Vec<(Vec<f64>, f64, f64, f64, usize)> {
    let d = posterior.dim();
    idx.par_iter()
        .enumerate()
        .map(|(i, &k)| {
            let mut rng = stream(w.seed, Purpose::TmcmcMove, [w.stage as u64, i as u64]);
            let mut th = pop.samples[k].clone();
            let (mut lp, mut ll, mut lr) = (pop.logprior[k], pop.loglik[k], pop.logref[k]);
            let mut acc = 0usize;
            if control.is_cancelled() {
                return (th, lp, ll, lr, acc);
            }
            let mut z = vec![0.0; d];
            for _ in 0..w.steps {
                for zi in z.iter_mut() {
                    *zi = rng.sample(StandardNormal);
                }
                let prop: Vec<f64> =
                    (0..d).map(|a| th[a] + w.beta * (0..=a).map(|b| w.chol[a][b] * z[b]).sum::<f64>()).collect();
                let lp_new = posterior.log_prior(&prop);
                let u: f64 = rng.gen();
                if !lp_new.is_finite() {
                    continue;
                }
                let ll_new = finite_or_neg_inf(posterior.log_likelihood(&prop));
                if ll_new == f64::NEG_INFINITY {
                    continue;
                }
                let (log_alpha, lr_new) = match w.reference {
                    None => (lp_new + w.p * ll_new - lp - w.p * ll, lr),
                    Some(reference) => {
                        let lr_new = finite_or_neg_inf(reference(&prop));
                        if lr_new == f64::NEG_INFINITY {
                            continue;
                        }
                        let q = 1.0 - w.p;
                        (lp_new + q * lr_new + w.p * ll_new - lp - q * lr - w.p * ll, lr_new)
                    }
                };
                if u.ln() < log_alpha {
                    th = prop;
                    lp = lp_new;
                    ll = ll_new;
                    lr = lr_new;
                    acc += 1;
                }
            }
            (th, lp, ll, lr, acc)
        })
        .collect()
}

/// Weighted mean and per-coordinate standard deviation (weights sum to 1).
fn weighted_mean_cov(samples: &[Vec<f64>], wbar: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let d = samples[0].len();
    let mut mu = vec![0.0; d];
    for (th, &w) in samples.iter().zip(wbar) {
        for a in 0..d {
            mu[a] += w * th[a];
        }
    }
    let mut sd = vec![0.0; d];
    for (th, &w) in samples.iter().zip(wbar) {
        for a in 0..d {
            sd[a] += w * (th[a] - mu[a]) * (th[a] - mu[a]);
        }
    }
    (mu, sd.into_iter().map(f64::sqrt).collect())
}

/// Lower-triangular L with L Lᵀ = Σ_w (weighted covariance), computed as D·chol(R).
/// A coordinate with zero weighted spread (degenerate population) falls back to
/// 1e-3 × its prior-sample standard deviation; a non-PD correlation matrix
/// (collinear samples) gets a diagonal jitter 1e-10, 1e-9, … until it factorises
/// (R + jitter·I is PD for jitter > 0 since R is PSD).
fn proposal_factor(samples: &[Vec<f64>], wbar: &[f64], prior_sd: &[f64]) -> Vec<Vec<f64>> {
    let d = samples[0].len();
    let (mu, mut sd) = weighted_mean_cov(samples, wbar);
    let mut r = vec![vec![0.0; d]; d];
    for (th, &w) in samples.iter().zip(wbar) {
        for a in 0..d {
            for b in 0..=a {
                r[a][b] += w * (th[a] - mu[a]) * (th[b] - mu[b]);
            }
        }
    }
    let degenerate: Vec<bool> = sd.iter().map(|&s| !(s > 0.0 && s.is_finite())).collect();
    for a in 0..d {
        for b in 0..=a {
            r[a][b] = if a == b {
                1.0
            } else if degenerate[a] || degenerate[b] {
                0.0
            } else {
                r[a][b] / (sd[a] * sd[b])
            };
            r[b][a] = r[a][b];
        }
    }
    for a in 0..d {
        if degenerate[a] {
            sd[a] = 1e-3 * prior_sd[a];
        }
    }
    let mut jitter = 0.0;
    let l = loop {
        let mut m = nalgebra::DMatrix::from_fn(d, d, |a, b| r[a][b]);
        for a in 0..d {
            m[(a, a)] += jitter;
        }
        if let Some(c) = nalgebra::Cholesky::new(m) {
            break c.l();
        }
        if jitter >= 1.0 {
            // Unreachable for a finite correlation matrix (R + I is PD); identity as a last resort.
            break nalgebra::DMatrix::identity(d, d);
        }
        jitter = if jitter == 0.0 { 1e-10 } else { jitter * 10.0 };
    };
    (0..d).map(|a| (0..d).map(|b| sd[a] * l[(a, b)]).collect()).collect()
}
