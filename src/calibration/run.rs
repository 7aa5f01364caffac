//! `calibrate` as a library call: place the chains with a multi-start
//! optimum, run DRAM chains in parallel, summarise, find the MAP.

use std::io::IsTerminal;

use serde::Serialize;

use crate::bayes::chains::{pooled_acceptance, run_chains};
use crate::bayes::dram::{ChainOutput, DramSettings};
use crate::bayes::map::{map_estimate, multi_start_optimum, MapResult};
use crate::bayes::rng::{stream, Purpose};
use crate::bayes::summary::{summarize, Summary};
use crate::bayes::Posterior;
use crate::calibration::{BeamPosterior, MeasuredData, SamplerSpec};
use rand_distr::{Distribution, StandardNormal};

/// Caller-side options that do not change the numbers.
#[derive(Debug, Clone, Copy, Default)]
pub struct CalibrateOptions {
    /// Show a progress bar on stderr (only drawn when stderr is a terminal).
    pub progress: bool,
}

/// Everything a calibration produced.
#[derive(Debug, Clone)]
pub struct CalibrationResult {
    pub names: Vec<String>,
    /// Full chains, burn-in included.
    pub chains: Vec<ChainOutput>,
    pub burn_in: usize,
    /// Summary of the post-burn-in draws, with the MAP filled in.
    pub summary: Summary,
    /// Pooled fraction of steps accepted at each DR stage.
    pub acceptance: Vec<f64>,
    pub rejected_invalid: u64,
    pub map_theta: Vec<f64>,
    pub log_posterior_map: f64,
    /// Where each chain started.
    pub starts: Vec<Vec<f64>>,
}

/// The JSON printed by `nanobeam calibrate --json`.
#[derive(Debug, Clone, Serialize)]
pub struct CalibrationJson<'a> {
    pub parameters: &'a [crate::bayes::summary::ParameterSummary],
    pub acceptance: &'a [f64],
    pub rejected_invalid: u64,
    pub log_posterior_map: f64,
}

impl CalibrationResult {
    /// Post-burn-in draws: chain → draw → θ.
    pub fn kept_draws(&self) -> Vec<Vec<Vec<f64>>> {
        self.chains.iter().map(|c| c.draws[self.burn_in..].to_vec()).collect()
    }

    pub fn json(&self) -> CalibrationJson<'_> {
        CalibrationJson {
            parameters: &self.summary.parameters,
            acceptance: &self.acceptance,
            rejected_invalid: self.rejected_invalid,
            log_posterior_map: self.log_posterior_map,
        }
    }
}

/// DRAM settings of a sampler section.
pub fn dram_settings(s: &SamplerSpec) -> DramSettings {
    DramSettings {
        draws: s.draws_per_chain,
        burn_in: s.burn_in,
        nonadapt_n0: s.nonadaptive_draws,
        adapt_start: s.adaptation_start,
        cov_skip: s.covariance_skip,
        dr_gammas: s.dr_shrink_factors.clone(),
        ..DramSettings::default()
    }
}

/// Calibrates the file's parameter set against its fitted modes.
pub fn calibrate(data: &MeasuredData, opts: &CalibrateOptions) -> CalibrationResult {
    let post = BeamPosterior::new(data, data.parameters.clone());
    let c0_sd: Vec<f64> = data.parameters.params.iter().map(|p| p.proposal_sd).collect();
    calibrate_posterior(&post, &c0_sd, &data.sampler, opts)
}

/// Any posterior: the beam-agnostic core of [`calibrate`].
///
/// Chains start from overdispersed points ([`overdispersed_starts`]): distinct
/// multi-start optima first, then prior draws carried to their local optimum,
/// so split-R̂ can reveal a mode the best optimum alone would miss
/// (Gelman & Rubin 1992, §2: starts "overdispersed with respect to the target").
pub fn calibrate_posterior(
    post: &dyn Posterior,
    c0_sd: &[f64],
    sampler: &SamplerSpec,
    opts: &CalibrateOptions,
) -> CalibrationResult {
    let names = post.names();
    let settings = dram_settings(sampler);
    let optima = multi_start_optimum(post, c0_sd, sampler.multistart_points, sampler.chains.max(4), sampler.seed, 0);
    let starts = overdispersed_starts(post, c0_sd, &optima, sampler.chains, sampler.seed);
    let best = optima.first().map(|m| m.theta.clone()).unwrap_or_else(|| starts[0].clone());

    let total = (sampler.chains * sampler.draws_per_chain) as u64;
    let bar = (opts.progress && std::io::stderr().is_terminal()).then(|| {
        let pb = indicatif::ProgressBar::new(total);
        pb.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} draws ({eta})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        pb
    });
    let tick = |n: usize| {
        if let Some(pb) = &bar {
            pb.inc(n as u64);
        }
    };
    let chains = run_chains(post, &settings, c0_sd, &starts, sampler.seed, Some(&tick));
    if let Some(pb) = &bar {
        pb.finish_and_clear();
    }

    let kept: Vec<Vec<Vec<f64>>> = chains.iter().map(|c| c.draws[sampler.burn_in..].to_vec()).collect();
    let summary = summarize(&names, &kept);

    // MAP: Nelder–Mead from the best sampled state, simplex scaled by the posterior sd.
    let (best_state, _) = chains
        .iter()
        .flat_map(|c| c.draws.iter().zip(&c.log_posterior))
        .fold((&best, f64::NEG_INFINITY), |acc, (d, &lp)| if lp > acc.1 { (d, lp) } else { acc });
    let scales: Vec<f64> = summary
        .parameters
        .iter()
        .zip(c0_sd)
        .map(|(p, s)| if p.sd.is_finite() && p.sd > 0.0 { p.sd } else { *s })
        .collect();
    let map = map_estimate(post, best_state, &scales, 4000);
    let summary = summary.with_map(&map.theta);

    CalibrationResult {
        names,
        acceptance: pooled_acceptance(&chains),
        rejected_invalid: chains.iter().map(|c| c.rejected_invalid).sum(),
        chains,
        burn_in: sampler.burn_in,
        summary,
        map_theta: map.theta,
        log_posterior_map: map.log_posterior,
        starts,
    }
}

/// Ten proposal steps: two optima closer than this in every coordinate (in
/// units of the C0 proposal sd) are one optimum. The Nelder–Mead polish stops
/// at a simplex spread of 1e-12 in −log π, far inside one step, so two polishes
/// of one mode agree to well under a step; distinct modes of interest (Ω on
/// either side of a resonance) lie orders of magnitude more steps apart.
const DISTINCT_STEPS: f64 = 10.0;

fn distinct(a: &[f64], b: &[f64], c0_sd: &[f64]) -> bool {
    a.iter().zip(b).zip(c0_sd).any(|((x, y), s)| (x - y).abs() > DISTINCT_STEPS * s)
}

/// One C0 step from `centre` drawn from `rng`, kept only if the log posterior
/// stays finite (100 tries, else `centre`).
fn jitter(post: &dyn Posterior, centre: &[f64], c0_sd: &[f64], rng: &mut dyn rand::RngCore) -> Vec<f64> {
    for _ in 0..100 {
        let cand: Vec<f64> = centre
            .iter()
            .zip(c0_sd)
            .map(|(x, s)| x + s * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, rng))
            .collect();
        if post.log_posterior(&cand).is_finite() {
            return cand;
        }
    }
    centre.to_vec()
}

/// The old placement, kept for comparison: every chain one C0 step from the
/// best optimum (stream `(seed, ChainStart, [c, 0])`). Chains placed this way
/// agree with each other even when the optimum missed a mode.
pub fn single_start(post: &dyn Posterior, c0_sd: &[f64], best: &[f64], chains: usize, seed: u64) -> Vec<Vec<f64>> {
    (0..chains)
        .map(|c| {
            let mut rng = stream(seed, Purpose::ChainStart, [c as u64, 0]);
            jitter(post, best, c0_sd, &mut rng)
        })
        .collect()
}

/// Overdispersed chain starts. Chain c starts at the c-th *distinct* optimum of
/// `optima` (sorted best first, distinct = more than [`DISTINCT_STEPS`] proposal
/// steps apart); once those are used up, at a prior draw from the stream
/// `(seed, ChainStart, [c, 0])` polished by Nelder–Mead to its local optimum
/// (a raw prior draw can lie far out in a tail that C0-sized steps would take
/// longer than the burn-in to leave). Every start is then
/// displaced by one C0 step from the same stream, so no two chains share a point.
pub fn overdispersed_starts(
    post: &dyn Posterior,
    c0_sd: &[f64],
    optima: &[MapResult],
    chains: usize,
    seed: u64,
) -> Vec<Vec<f64>> {
    let mut modes: Vec<&[f64]> = Vec::new();
    for m in optima.iter().filter(|m| m.log_posterior.is_finite()) {
        if modes.iter().all(|x| distinct(x, &m.theta, c0_sd)) {
            modes.push(&m.theta);
        }
    }
    (0..chains)
        .map(|c| {
            let mut rng = stream(seed, Purpose::ChainStart, [c as u64, 0]);
            let centre = match modes.get(c) {
                Some(m) => m.to_vec(),
                None => {
                    let draw = (0..100)
                        .map(|_| post.sample_prior(&mut rng))
                        .find(|t| post.log_posterior(t).is_finite())
                        .unwrap_or_else(|| post.sample_prior(&mut rng));
                    let first = map_estimate(post, &draw, c0_sd, 2000);
                    let small: Vec<f64> = c0_sd.iter().map(|s| s * 0.1).collect();
                    map_estimate(post, &first.theta, &small, 2000).theta
                }
            };
            jitter(post, &centre, c0_sd, &mut rng)
        })
        .collect()
}
