//! `calibrate` as a library call: place the chains with a multi-start
//! optimum, run DRAM chains in parallel, summarise, find the MAP.

use serde::Serialize;

use crate::bayes::chains::{pooled_acceptance, run_chains};
use crate::bayes::dram::{ChainOutput, DramSettings};
use crate::bayes::map::{map_estimate, multi_start_optimum, MapResult};
use crate::bayes::rng::{stream, Purpose};
use crate::bayes::summary::{summarize, Summary};
use crate::bayes::{Cancelled, Control, Controlled, Posterior};
use crate::calibration::{BeamPosterior, MeasuredData};
use rand_distr::{Distribution, StandardNormal};

/// Caller-side options that do not change the numbers.
#[derive(Debug, Clone, Default)]
pub struct CalibrateOptions {
    /// Cancellation and progress ([`crate::bayes::control`]): the chains'
    /// states are reported as a phase of `chains × draws_per_chain` "draws";
    /// a cancelled calibration returns [`SamplingError::Cancelled`].
    pub control: Control,
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
    /// Why the result should be read with care (frozen chains, low
    /// acceptance, R̂/ESS); also printed on stderr and in the JSON.
    pub warnings: Vec<String>,
}

/// A run that cannot sample: `calibrate` exits 1 with this message.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SamplingError {
    /// No prior draw of the multi-start screen has a finite posterior.
    #[error(
        "no valid state: none of the {draws} prior draws gives a finite log posterior{detail} \
         (widen the priors or check the measured modes against the beam)"
    )]
    NoValidState { draws: usize, detail: String },
    /// Every chain stayed where it started.
    #[error(
        "the chains cannot sample: {reason} (give a proposal_sd between about 1e-3 and 1e-1 of each prior's \
         width, or check that the model is valid around the start)"
    )]
    Frozen { reason: String },
    /// The summaries are not finite numbers.
    #[error("the posterior summary is not finite for {name} (mean {mean}, sd {sd}): narrow its prior")]
    NonFinite { name: String, mean: f64, sd: f64 },
    /// A sampler setting outside its range (bad input: exit 2).
    #[error("{0}")]
    Settings(#[from] crate::error::InputError),
    /// The caller cancelled the run ([`CalibrateOptions::control`]).
    #[error("{0}")]
    Cancelled(#[from] Cancelled),
}

/// Least pooled acceptance (all DR stages) below which a run is reported
/// as nearly frozen: with ≥ 40 kept draws per chain (`MIN_KEPT_DRAWS`), 1 %
/// means < 1 move per 100 states, an ESS far below what the run size suggests.
const LOW_ACCEPTANCE: f64 = 0.01;
/// R̂ above which chains have not mixed (Vehtari et al. 2021 recommend 1.01
/// for final results; 1.1 is the classic threshold for "not converged").
const RHAT_WARN: f64 = 1.1;
/// Bulk/tail ESS below which intervals are unreliable (Vehtari et al. 2021: 100 per run).
const ESS_WARN: f64 = 100.0;

/// The JSON printed by `nanobeam calibrate --json`.
#[derive(Debug, Clone, Serialize)]
pub struct CalibrationJson<'a> {
    pub parameters: &'a [crate::bayes::summary::ParameterSummary],
    pub acceptance: &'a [f64],
    pub rejected_invalid: u64,
    pub log_posterior_map: f64,
    pub warnings: &'a [String],
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
            warnings: &self.warnings,
        }
    }
}

/// Calibrates the file's parameter set against its fitted modes.
pub fn calibrate(data: &MeasuredData, opts: &CalibrateOptions) -> Result<CalibrationResult, SamplingError> {
    let post = BeamPosterior::new(data, data.parameters.clone());
    let c0_sd: Vec<f64> = data.parameters.params.iter().map(|p| p.proposal_sd).collect();
    let mut result = calibrate_posterior(&post, &c0_sd, &data.sampler, opts).map_err(|e| match e {
        SamplingError::NoValidState { draws, .. } => {
            SamplingError::NoValidState { draws, detail: why_invalid(&post, data.sampler.seed) }
        }
        other => other,
    })?;
    result.warnings.extend(map_on_bound(&data.parameters.params, &result.map_theta));
    Ok(result)
}

/// How close to a bound of a uniform, log-uniform or asinh-uniform prior (a
/// fraction of the prior's width in the coordinate where it is uniform) the
/// MAP counts as on it: 0.1 %, for `calibrate` and `diagnose` alike
/// (Nelder–Mead pressed against a bound ends within a few 1e-6 of the width
/// of it; an interior optimum that close needs a posterior sd of the same
/// order sitting right at the edge).
pub const ON_BOUND_FRACTION: f64 = 1e-3;

/// A warning per parameter whose MAP lies on a bound of its prior: the data
/// ask for a value the prior excludes, so the posterior there is the prior's
/// edge, not the data's answer.
fn map_on_bound(params: &[crate::calibration::Parameter], map: &[f64]) -> Vec<String> {
    use crate::bayes::prior::Prior;
    params
        .iter()
        .zip(map)
        .filter_map(|(p, &x)| {
            let u: fn(f64, f64) -> f64 = match p.prior {
                Prior::Uniform { .. } => |x, _| x,
                Prior::LogUniform { .. } => |x, _| x.ln(),
                Prior::AsinhUniform { .. } => |x, s| (x / s).asinh(),
                _ => return None,
            };
            let scale = if let Prior::AsinhUniform { scale, .. } = p.prior { scale } else { 1.0 };
            let (lo, hi) = p.prior.support();
            let tol = ON_BOUND_FRACTION * (u(hi, scale) - u(lo, scale));
            [lo, hi].into_iter().find(|&b| (u(x, scale) - u(b, scale)).abs() <= tol).map(|b| {
                format!(
                    "{}: MAP {} on its prior bound {} (the data ask for a value the prior excludes; widen the prior \
                     or question the model)",
                    p.name,
                    crate::error::fmt_num(x),
                    crate::error::fmt_num(b)
                )
            })
        })
        .collect()
}

/// What the model says at the prior mean (or one prior draw): the reason a
/// state is invalid, for the error line.
fn why_invalid(post: &BeamPosterior, seed: u64) -> String {
    let params = post.parameters();
    let theta: Vec<f64> = match params.params.iter().map(|p| p.prior.mean()).collect::<Option<Vec<f64>>>() {
        Some(t) => t,
        None => post.sample_prior(&mut stream(seed, Purpose::ChainStart, [u64::MAX, 1])),
    };
    let beam = post.beam_at(&theta);
    let max_mode = post.max_mode();
    let at = |what: String| format!("; at the prior mean {what}");
    match crate::beam::modal(&beam, max_mode) {
        Err(e) => at(format!("the model fails: {e}")),
        Ok(r) => match r.overdamped.first() {
            Some(o) if post.fitted_modes().contains(&o.mode) => at(format!("measured mode {} is overdamped", o.mode)),
            _ => String::new(),
        },
    }
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
    sampler: &DramSettings,
    opts: &CalibrateOptions,
) -> Result<CalibrationResult, SamplingError> {
    sampler.validate(post.dim())?;
    let names = post.names();
    let control = &opts.control;
    // the optimisations before and after the chains poll the control at every
    // evaluation (`bayes::control::Controlled`) and are checked after
    let seen = Controlled::new(post, control);
    let optima = multi_start_optimum(&seen, c0_sd, sampler.multistart_points, sampler.chains.max(4), sampler.seed, 0);
    control.check()?;
    let Some(best) = optima.first().filter(|m| m.log_posterior.is_finite()).map(|m| m.theta.clone()) else {
        return Err(SamplingError::NoValidState { draws: sampler.multistart_points, detail: String::new() });
    };
    let starts = overdispersed_starts(&seen, c0_sd, &optima, sampler.chains, sampler.seed);
    control.check()?;

    control.start("draws", (sampler.chains * sampler.draws_per_chain) as u64);
    let chains = run_chains(post, sampler, c0_sd, &starts, sampler.seed, Some(control));
    control.finish();
    control.check()?;
    let mut chains = chains?;
    // exchangeable components in their canonical order (`Posterior::relabel`):
    // chains at one mode under swapped labels agree, and R̂ still shows
    // chains at different modes
    chains.iter_mut().flat_map(|c| c.draws.iter_mut()).for_each(|d| post.relabel(d));

    // borrowed post-burn-in draws (a copy of every state cost ~5 % of a calibrate)
    let kept: Vec<&[Vec<f64>]> = chains.iter().map(|c| &c.draws[sampler.burn_in..]).collect();
    let summary = summarize(&names, &kept);
    let warnings = sampling_health(&chains, &kept, &summary)?;

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
    let mut map = map_estimate(&seen, best_state, &scales, 4000);
    control.check()?;
    post.relabel(&mut map.theta);
    let summary = summary.with_map(&map.theta);

    Ok(CalibrationResult {
        names,
        acceptance: pooled_acceptance(&chains),
        rejected_invalid: chains.iter().map(|c| c.rejected_invalid).sum(),
        chains,
        burn_in: sampler.burn_in,
        summary,
        map_theta: map.theta,
        log_posterior_map: map.log_posterior,
        starts,
        warnings,
    })
}

/// Whether the chains sampled: an error when none moved (acceptance 0 or
/// every chain constant after burn-in) or a summary is not finite; warnings
/// for frozen chains among moving ones, low acceptance, R̂ and ESS.
fn sampling_health(
    chains: &[ChainOutput],
    kept: &[&[Vec<f64>]],
    summary: &Summary,
) -> Result<Vec<String>, SamplingError> {
    let accepted: u64 = chains.iter().flat_map(|c| &c.accepted).sum();
    let steps: u64 = chains.iter().map(|c| c.draws.len().saturating_sub(1) as u64).sum();
    let invalid: u64 = chains.iter().map(|c| c.rejected_invalid).sum();
    let proposed: u64 = chains.iter().flat_map(|c| &c.proposed).sum();
    if accepted == 0 {
        return Err(SamplingError::Frozen {
            reason: format!(
                "no proposal was accepted in {steps} steps ({invalid} of {proposed} proposals left the prior support \
                 or made the model fail)"
            ),
        });
    }
    let frozen: Vec<usize> = (0..kept.len()).filter(|&c| kept[c].windows(2).all(|w| w[0] == w[1])).collect();
    if frozen.len() == kept.len() {
        return Err(SamplingError::Frozen { reason: "every chain stayed constant after burn-in".into() });
    }
    for p in &summary.parameters {
        if !(p.mean.is_finite() && p.sd.is_finite()) {
            return Err(SamplingError::NonFinite { name: p.name.clone(), mean: p.mean, sd: p.sd });
        }
    }
    let mut warnings = Vec::new();
    if !frozen.is_empty() {
        warnings.push(format!("chains {frozen:?} stayed constant after burn-in (0-based)"));
    }
    let rate = accepted as f64 / steps.max(1) as f64;
    if rate < LOW_ACCEPTANCE {
        warnings
            .push(format!("acceptance {rate:.4} < {LOW_ACCEPTANCE}: proposal_sd likely far too large or too small"));
    }
    for p in &summary.parameters {
        if p.rhat.is_nan() || p.rhat > RHAT_WARN {
            warnings.push(format!("{}: R-hat {:.3} > {RHAT_WARN} (chains disagree; run longer)", p.name, p.rhat));
        }
        let ess = p.ess_bulk.min(p.ess_tail);
        if ess.is_nan() || ess < ESS_WARN {
            warnings.push(format!("{}: ESS {:.0} < {ESS_WARN} (run longer)", p.name, ess));
        }
    }
    Ok(warnings)
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

#[cfg(test)]
mod bound_tests {
    use super::*;
    use crate::bayes::prior::Prior;
    use crate::calibration::parameters::Target;

    fn param(prior: Prior) -> crate::calibration::Parameter {
        crate::calibration::Parameter { name: "omega_rad_s".into(), target: Target::Omega(0), prior, proposal_sd: 1.0 }
    }

    /// A MAP 1e-5 of the width from a bound (where Nelder–Mead stops against
    /// it) warns, naming the bound; one 1 % inside does not; the log-uniform
    /// width is measured in ln x (Ω's prior 1e3..1e13: 1e13·(1 − 1e-5) is on
    /// the bound, 1e13/1.3 is 1.1 % of the ln-width inside).
    #[test]
    fn map_on_a_prior_bound_warns_and_an_interior_one_does_not() {
        let uniform = param(Prior::Uniform { lower: 0.0, upper: 2.0 });
        let w = map_on_bound(std::slice::from_ref(&uniform), &[2.0 - 2e-5]);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(w[0].starts_with("omega_rad_s: MAP") && w[0].contains("prior bound 2"), "{w:?}");
        assert!(map_on_bound(&[uniform], &[1.98]).is_empty());
        let log = param(Prior::LogUniform { lower: 1e3, upper: 1e13 });
        assert_eq!(map_on_bound(std::slice::from_ref(&log), &[1e13 * (1.0 - 1e-5)]).len(), 1);
        assert!(map_on_bound(&[log], &[1e13 / 1.3]).is_empty());
    }
}
