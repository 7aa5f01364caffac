//! `calibrate` as a library call: place the chains with a multi-start
//! optimum, run DRAM chains in parallel, summarise, find the MAP.

use std::io::IsTerminal;

use serde::Serialize;

use crate::bayes::chains::{pooled_acceptance, run_chains};
use crate::bayes::dram::{ChainOutput, DramSettings};
use crate::bayes::map::{map_estimate, multi_start_optimum};
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
/// Chains start at the best multi-start optimum, each displaced by one C0
/// step drawn from its own stream (kept only if the log posterior stays
/// finite), so split-R̂ across chains can reveal a second mode the chains
/// find on their own; the starting optimum itself is reported.
pub fn calibrate_posterior(
    post: &dyn Posterior,
    c0_sd: &[f64],
    sampler: &SamplerSpec,
    opts: &CalibrateOptions,
) -> CalibrationResult {
    let names = post.names();
    let settings = dram_settings(sampler);
    let optima = multi_start_optimum(post, c0_sd, sampler.multistart_points, 4, sampler.seed, 0);
    let best = optima.first().map(|m| m.theta.clone()).unwrap_or_else(|| {
        let mut rng = stream(sampler.seed, Purpose::ChainStart, [u64::MAX, 0]);
        post.sample_prior(&mut rng)
    });
    let starts: Vec<Vec<f64>> = (0..sampler.chains)
        .map(|c| {
            let mut rng = stream(sampler.seed, Purpose::ChainStart, [c as u64, 0]);
            for _ in 0..100 {
                let cand: Vec<f64> = best
                    .iter()
                    .zip(c0_sd)
                    .map(|(x, s)| x + s * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, &mut rng))
                    .collect();
                if post.log_posterior(&cand).is_finite() {
                    return cand;
                }
            }
            best.clone()
        })
        .collect();

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
