//! Noise replicates of the synthetic reference data: the sampling distribution
//! of every noise-dependent audit statistic.
//!
//! The paper's synthetic data carry one unknown noise draw ε ~ N(0, Σ) (eq. 37);
//! ours carry another. Replicate r of a case draws its noise from the stream
//! `stream(case_seed, Purpose::MeasurementNoise, [0, r])` (replicate 0 is the
//! case's own data, the one the DRAM chains saw).
//!
//! Inference per replicate is MAP + Laplace (`bayes::map`, `bayes::laplace`)
//! with the *shape* of the full DRAM posterior transported from replicate 0:
//! on replicate 0 both exist, and each parameter's DRAM mean, sd and 95 %
//! interval endpoints are expressed as offsets from the Laplace MAP in units of
//! the Laplace sd, `mean = MAP + a·s_L`, `sd = b·s_L`, `CI = MAP + [l, h]·s_L`.
//! Replicate r keeps (a, b, l, h) and moves MAP and s_L. Exact when the
//! posterior shape in standardised coordinates does not depend on the noise
//! draw (a Gaussian posterior of a linear model); `tests/reproduce_replicates.rs`
//! measures the error against full DRAM on fresh replicates and states the bound.

use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use serde::Serialize;

use crate::bayes::laplace::laplace_log_evidence;
use crate::bayes::map::map_estimate;
use crate::bayes::rng::{stream, Purpose};
use crate::bayes::summary::ParameterSummary;
use crate::beam::{self, BeamSpec};
use crate::calibration::{BeamPosterior, CalibrationResult, ModeObservation};
use crate::reproduce::reconstruction::ghz_to_rad_s;
use crate::reproduce::reference::CovarianceSet;

/// Which noise a set of observations carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Noise {
    /// Replicate r: ε from `stream(seed, MeasurementNoise, [0, r])`.
    Replicate(u64),
    /// ε = 0: the noise-free reference values (the deterministic part of a bias).
    None,
}

/// Synthetic measured data y = y0 + ε, ε ~ N(0, Σ) (eq. 37), σ = √Σ printed.
pub fn synthetic_observations(
    truth: &BeamSpec,
    cs: &CovarianceSet,
    seed: u64,
    noise: Noise,
) -> Result<Vec<ModeObservation>, beam::BeamError> {
    let y0 = beam::modal(truth, cs.sigma_omega_omega_diag_ghz2.len())?;
    let r = match noise {
        Noise::Replicate(r) => r,
        Noise::None => 0,
    };
    let mut rng = stream(seed, Purpose::MeasurementNoise, [0, r]);
    let mut eps = || -> f64 {
        let e: f64 = StandardNormal.sample(&mut rng);
        if noise == Noise::None {
            0.0
        } else {
            e
        }
    };
    Ok(y0
        .modes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let sw = cs.sigma_omega_omega_diag_ghz2[i].sqrt() * ghz_to_rad_s(1.0);
            let sz = (cs.sigma_zeta_zeta_diag_1e_minus_6[i] * 1e-6).sqrt();
            let (ew, ez) = (eps(), eps());
            ModeObservation {
                mode: i + 1,
                omega_rad_s: m.omega_rad_s + sw * ew,
                omega_sd_rad_s: sw,
                zeta: m.zeta + sz * ez,
                zeta_sd: sz,
            }
        })
        .collect())
}

/// A Laplace fit: the MAP and the inverse Hessian of −log π(θ | y) there.
#[derive(Debug, Clone)]
pub struct LaplaceFit {
    pub map: Vec<f64>,
    pub covariance: Vec<Vec<f64>>,
}

impl LaplaceFit {
    pub fn sd(&self) -> Vec<f64> {
        (0..self.map.len()).map(|k| self.covariance[k][k].sqrt()).collect()
    }
}

/// MAP by Nelder–Mead from `start` (simplex one `scales` step, then a tenth of
/// it, as `bayes::map::multi_start_optimum` polishes), then the Laplace
/// covariance with finite-difference steps 1e-4·`scales` (`bayes::laplace`).
/// `None` when the Hessian is not positive definite or not finite (θ* at a
/// prior bound): that replicate is counted as failed, never guessed.
pub fn laplace_fit(post: &BeamPosterior, start: &[f64], scales: &[f64]) -> Option<LaplaceFit> {
    let first = map_estimate(post, start, scales, 1500);
    let small: Vec<f64> = scales.iter().map(|s| 0.1 * s).collect();
    let map = map_estimate(post, &first.theta, &small, 1500);
    let lap = laplace_log_evidence(post, &map.theta, scales).ok()?;
    Some(LaplaceFit { map: map.theta, covariance: lap.covariance })
}

/// Posterior summary of one replicate (the statistics the audit needs).
#[derive(Debug, Clone, Serialize)]
pub struct ReplicateSummary {
    pub mean: Vec<f64>,
    pub sd: Vec<f64>,
    pub ci95: Vec<[f64; 2]>,
    pub correlation: Vec<Vec<f64>>,
}

/// DRAM shape relative to Laplace, per parameter, in Laplace-sd units (module doc).
#[derive(Debug, Clone, Serialize)]
pub struct Shape {
    /// (DRAM mean − MAP)/s_L.
    pub mean_offset: Vec<f64>,
    /// DRAM sd / s_L.
    pub sd_ratio: Vec<f64>,
    /// (DRAM CI95 endpoints − MAP)/s_L.
    pub ci95_offset: Vec<[f64; 2]>,
}

impl Shape {
    /// The shape of `dram` relative to `lap` (both on replicate 0).
    pub fn measure(dram: &[ParameterSummary], lap: &LaplaceFit) -> Self {
        let s = lap.sd();
        Self {
            mean_offset: dram.iter().enumerate().map(|(k, p)| (p.mean - lap.map[k]) / s[k]).collect(),
            sd_ratio: dram.iter().enumerate().map(|(k, p)| p.sd / s[k]).collect(),
            ci95_offset: dram
                .iter()
                .enumerate()
                .map(|(k, p)| [(p.ci95[0] - lap.map[k]) / s[k], (p.ci95[1] - lap.map[k]) / s[k]])
                .collect(),
        }
    }

    /// The summary of a replicate whose Laplace fit is `lap`.
    pub fn apply(&self, lap: &LaplaceFit) -> ReplicateSummary {
        let s = lap.sd();
        let d = s.len();
        ReplicateSummary {
            mean: (0..d).map(|k| lap.map[k] + self.mean_offset[k] * s[k]).collect(),
            sd: (0..d).map(|k| self.sd_ratio[k] * s[k]).collect(),
            ci95: (0..d)
                .map(|k| [lap.map[k] + self.ci95_offset[k][0] * s[k], lap.map[k] + self.ci95_offset[k][1] * s[k]])
                .collect(),
            correlation: (0..d).map(|i| (0..d).map(|j| lap.covariance[i][j] / (s[i] * s[j])).collect()).collect(),
        }
    }
}

/// What one case needs to be replicated.
pub struct ReplicateInput<'a> {
    pub id: &'a str,
    pub seed: u64,
    pub truth: &'a BeamSpec,
    pub covariance_set: &'a CovarianceSet,
    /// The inverse model's base beam and parameter set (as in the DRAM run).
    pub posterior: &'a BeamPosterior,
    pub dram: &'a CalibrationResult,
}

/// The replicate distribution of one case.
#[derive(Debug, Clone, Serialize)]
pub struct CaseReplicates {
    pub id: String,
    pub names: Vec<String>,
    /// Laplace-relative shape of the DRAM posterior on replicate 0.
    pub shape: Shape,
    /// Summary of replicates 0..R (`None`: MAP/Laplace failed on that draw).
    pub replicates: Vec<Option<ReplicateSummary>>,
    /// Summary on the noise-free data (the deterministic part of every bias).
    pub noise_free: Option<ReplicateSummary>,
}

impl CaseReplicates {
    pub fn failed(&self) -> usize {
        self.replicates.iter().filter(|r| r.is_none()).count()
    }
}

/// One replicate's data → its transported summary.
fn one(input: &ReplicateInput, shape: &Shape, noise: Noise, scales: &[f64]) -> Option<ReplicateSummary> {
    let obs = synthetic_observations(input.truth, input.covariance_set, input.seed, noise).ok()?;
    let post = BeamPosterior::from_parts(input.posterior.base_beam(), &obs, input.posterior.parameters().clone());
    laplace_fit(&post, &input.dram.map_theta, scales).map(|lap| shape.apply(&lap))
}

/// Replicates 0..`count` of every case and their noise-free fits, in parallel
/// over (case, replicate) and gathered in that fixed order. `None` for a case
/// whose replicate-0 Laplace fit fails (its shape cannot be measured).
pub fn replicate_cases(inputs: &[ReplicateInput], count: usize) -> Vec<Option<CaseReplicates>> {
    let scales_of = |i: &ReplicateInput| -> Vec<f64> {
        i.dram.summary.parameters.iter().map(|p| if p.sd.is_finite() && p.sd > 0.0 { p.sd } else { 1.0 }).collect()
    };
    let shapes: Vec<Option<Shape>> = inputs
        .par_iter()
        .map(|i| {
            let lap = laplace_fit(i.posterior, &i.dram.map_theta, &scales_of(i))?;
            Some(Shape::measure(&i.dram.summary.parameters, &lap))
        })
        .collect();
    let jobs: Vec<(usize, Noise)> = (0..inputs.len())
        .filter(|&c| shapes[c].is_some())
        .flat_map(|c| (0..count as u64).map(Noise::Replicate).chain([Noise::None]).map(move |n| (c, n)))
        .collect();
    let results: Vec<Option<ReplicateSummary>> = jobs
        .par_iter()
        .map(|&(c, n)| one(&inputs[c], shapes[c].as_ref().expect("filtered"), n, &scales_of(&inputs[c])))
        .collect();
    let mut it = results.into_iter();
    inputs
        .iter()
        .zip(shapes)
        .map(|(input, shape)| {
            let shape = shape?;
            let replicates: Vec<Option<ReplicateSummary>> = it.by_ref().take(count).collect();
            let noise_free = it.next().flatten();
            Some(CaseReplicates {
                id: input.id.to_string(),
                names: input.dram.names.clone(),
                shape,
                replicates,
                noise_free,
            })
        })
        .collect()
}
