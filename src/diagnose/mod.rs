//! `nanobeam diagnose`: show what the model gets wrong, name the cause,
//! extend the model, measure the gain (the step §4.3 of the paper names:
//! Muto & Beck's evidence-based model-class selection, done automatically).
//!
//! 1. **Misfit.** The base class (the file's parameters, default the paper's
//!    N = 1 set; C = 0, ideal supports, nominal geometry) is calibrated by
//!    TMCMC; every observable (ω_r, ζ_r) gets a posterior predictive check
//!    ([`ppc`]): standardized residual z and two-sided p-value. Misfit is
//!    detected when some p-value falls below the Šidák level
//!    1 − (1 − 0.01)^(1/J) (family-wise 1 % over the J observables).
//! 2. **Candidates.** Four model classes extend the base, one cause each
//!    ([`classes`]); the β-inflated base of eq. (41) is computed as a baseline.
//! 3. **Evidence.** log π(y|M) by TMCMC, cross-checked by Laplace at the MAP
//!    (`bayes::{tmcmc, map, laplace}`); class probabilities with equal prior probabilities over
//!    {base, causes}. The cause is the most probable class when
//!    ln B = ln Z_class − ln Z_base ≥ 3: "strong" on the Kass–Raftery scale
//!    (B ≥ 20), and more than ten times the TMCMC log-evidence spread measured
//!    between seeds (≈ 0.1–0.3 at the default settings, see the report). `none`
//!    when no misfit is detected and no class wins, `unexplained` when misfit
//!    is detected and no class wins.
//! 4. **Gain.** ln B, RMS standardized residual before/after and, with
//!    `held_out_modes`, the joint predictive log score and 95 % coverage of
//!    both models on the held-out modes.

pub mod classes;
pub mod cli;
pub mod posterior;
pub mod ppc;
pub mod report;
pub mod synthetic;

use std::collections::BTreeMap;

use rayon::prelude::*;
use serde::Serialize;

use crate::calibration::MeasuredData;
use crate::error::InputError;

use crate::bayes::laplace::laplace_log_evidence_with_step;
use crate::bayes::map::map_estimate;
use crate::bayes::rng::{child_seed, Purpose};
use crate::bayes::tmcmc::{tmcmc, TmcmcConfig, TmcmcError, TmcmcResult};
pub use classes::ModelClass;
use classes::{class_parameters, NominalScales};
use posterior::{observables, predicted, ClassPosterior, Observable};
use ppc::Check;

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
    /// ln B threshold to name a cause (default 3).
    pub log_bayes_factor_threshold: f64,
    /// Nelder–Mead iterations for the MAP (default 400).
    pub map_iters: u64,
}

impl Default for DiagnoseSettings {
    fn default() -> Self {
        Self {
            samples: 1000,
            mh_steps: 4,
            seed: None,
            family_alpha: 0.01,
            log_bayes_factor_threshold: 3.0,
            map_iters: 400,
        }
    }
}

impl DiagnoseSettings {
    /// Short runs for tests: 400 samples, 3 steps.
    pub fn quick() -> Self {
        Self { samples: 400, mh_steps: 3, map_iters: 250, ..Self::default() }
    }
}

/// Posterior summary of one parameter (physical units).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Summary {
    pub mean: f64,
    pub sd: f64,
    pub ci95: [f64; 2],
}

/// One model class in the output.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Candidate {
    pub extension: String,
    pub log_evidence: f64,
    /// `null` when the MAP sits on a prior boundary or the Hessian is not positive definite.
    pub log_evidence_laplace: Option<f64>,
    pub log_bayes_factor: f64,
    /// Posterior class probability among {base, causes}; for the baseline, its
    /// probability had it been compared with the base alone.
    pub probability: f64,
    pub posterior: BTreeMap<String, Summary>,
}

/// Held-out predictive comparison.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct HeldOut {
    pub modes: Vec<usize>,
    /// ln p(y_held_out | y, M) of the base and the extended model (joint over the held-out observables).
    pub log_score_before: f64,
    pub log_score_after: f64,
    /// Fraction of held-out observables inside the central 95 % predictive interval.
    pub coverage95_before: f64,
    pub coverage95_after: f64,
}

/// What the extension buys.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Gain {
    /// The class assessed: the cause, else the most probable candidate.
    pub extension: String,
    pub log_bayes_factor: f64,
    pub rms_z_before: f64,
    pub rms_z_after: f64,
    /// The posterior predictive checks under the extended model.
    pub misfit_after: Vec<Check>,
    pub held_out: Option<HeldOut>,
}

/// Decision thresholds actually used.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Thresholds {
    pub family_alpha: f64,
    pub per_test_alpha_sidak: f64,
    pub log_bayes_factor: f64,
}

/// The diagnosis (the `--json` output).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Diagnosis {
    pub misfit_detected: bool,
    pub misfit: Vec<Check>,
    pub candidates: Vec<Candidate>,
    pub cause: String,
    pub gain: Gain,
    pub base: Candidate,
    pub baseline: Candidate,
    pub thresholds: Thresholds,
}

/// Everything computed for one class (kept for the report's plots).
#[derive(Debug, Clone)]
pub struct ClassRun {
    pub class: ModelClass,
    pub posterior: ClassPosterior,
    pub tmcmc: TmcmcResult,
    pub map: Vec<f64>,
    pub log_evidence_laplace: Option<f64>,
}

/// A diagnosis with the per-class runs behind it.
#[derive(Debug, Clone)]
pub struct DiagnosisRun {
    pub diagnosis: Diagnosis,
    pub runs: Vec<ClassRun>,
}

/// Runs the diagnosis of `data`.
pub fn diagnose(data: &MeasuredData, settings: &DiagnoseSettings) -> Result<Diagnosis, InputError> {
    diagnose_run(data, settings).map(|r| r.diagnosis)
}

/// [`diagnose`] keeping the per-class runs.
pub fn diagnose_run(data: &MeasuredData, settings: &DiagnoseSettings) -> Result<DiagnosisRun, InputError> {
    if data.modes.len() < 3 {
        return Err(InputError::new(
            "modes",
            format!("{} mode(s)", data.modes.len()),
            "at least 3 fitted modes (a diagnosis compares classes with up to 5 parameters)",
        ));
    }
    let n_modes = data.max_mode();
    let scales = NominalScales::of(&data.beam, n_modes).map_err(|e| {
        InputError::new("modes", format!("highest mode {n_modes}"), format!("modes the beam model can compute ({e})"))
    })?;
    let fitted = observables(&data.modes);
    let held = observables(&data.held_out_modes);
    let seed = settings.seed.unwrap_or(data.sampler.seed);
    let classes: Vec<ModelClass> =
        [ModelClass::Base, ModelClass::Baseline].into_iter().chain(ModelClass::CAUSES).collect();

    let runs: Vec<ClassRun> = classes
        .par_iter()
        .enumerate()
        .map(|(k, &class)| {
            let params = class_parameters(class, &data.parameters, &data.beam, &scales);
            let post = ClassPosterior::new(params, data.beam.clone(), fitted.clone(), n_modes);
            run_class(class, post, settings, child_seed(seed, Purpose::ModelClass, [k as u64, 0]))
        })
        .collect::<Result<_, _>>()
        .map_err(|e| InputError::new("modes", e, "data every model class can be evaluated on (TMCMC failed)"))?;
    let run_of = |c: ModelClass| runs.iter().find(|r| r.class == c).expect("every class ran");
    let base = run_of(ModelClass::Base);
    let z_base = base.tmcmc.log_evidence;

    // class probabilities over {base, causes}, equal prior probabilities
    let compared: Vec<&ClassRun> = std::iter::once(base).chain(ModelClass::CAUSES.iter().map(|&c| run_of(c))).collect();
    let z_max = compared.iter().map(|r| r.tmcmc.log_evidence).fold(f64::NEG_INFINITY, f64::max);
    let norm: f64 = compared.iter().map(|r| (r.tmcmc.log_evidence - z_max).exp()).sum();
    let prob = |r: &ClassRun| (r.tmcmc.log_evidence - z_max).exp() / norm;

    let candidate = |r: &ClassRun, p: f64| Candidate {
        extension: r.class.name().to_string(),
        log_evidence: r.tmcmc.log_evidence,
        log_evidence_laplace: r.log_evidence_laplace,
        log_bayes_factor: r.tmcmc.log_evidence - z_base,
        probability: p,
        posterior: summaries(&r.posterior, &r.tmcmc.samples),
    };
    let candidates: Vec<Candidate> =
        ModelClass::CAUSES.iter().map(|&c| candidate(run_of(c), prob(run_of(c)))).collect();
    let baseline_run = run_of(ModelClass::Baseline);
    let lb = baseline_run.tmcmc.log_evidence - z_base;
    let baseline = candidate(baseline_run, 1.0 / (1.0 + (-lb).exp()));
    let base_c = candidate(base, prob(base));

    // misfit of the base model
    let all_obs: Vec<Observable> = fitted.iter().chain(&held).cloned().collect();
    let base_pred = predictive(base, &all_obs);
    let nf = fitted.len();
    let base_checks = ppc::check(&fitted, &base_pred.0, &base_pred.1);
    let per_test = ppc::sidak_level(settings.family_alpha, nf);
    let misfit_detected = base_checks.iter().any(|c| c.check.ppp < per_test);

    // cause
    let best = ModelClass::CAUSES
        .iter()
        .map(|&c| run_of(c))
        .max_by(|a, b| a.tmcmc.log_evidence.total_cmp(&b.tmcmc.log_evidence))
        .expect("four causes");
    let best_lbf = best.tmcmc.log_evidence - z_base;
    let cause = if best_lbf >= settings.log_bayes_factor_threshold {
        best.class.name().to_string()
    } else if misfit_detected {
        "unexplained".to_string()
    } else {
        "none".to_string()
    };

    // gain of the best class
    let best_pred = predictive(best, &all_obs);
    let best_checks = ppc::check(&fitted, &best_pred.0, &best_pred.1);
    let held_out = (!held.is_empty()).then(|| {
        let score = |pred: &(Vec<Vec<f64>>, Vec<f64>)| {
            let (p, b2) = pred;
            let terms: Vec<f64> = p
                .iter()
                .zip(b2)
                .map(|(row, &b)| {
                    held.iter()
                        .enumerate()
                        .map(|(j, o)| {
                            let sd = o.sd * b.sqrt();
                            let x = (row[nf + j] - o.value) / sd;
                            -0.5 * x * x - sd.ln() - 0.5 * (2.0 * std::f64::consts::PI).ln()
                        })
                        .sum::<f64>()
                })
                .collect();
            let m = terms.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
            m + (terms.iter().map(|t| (t - m).exp()).sum::<f64>() / terms.len() as f64).ln()
        };
        let coverage = |pred: &(Vec<Vec<f64>>, Vec<f64>)| {
            let shifted: Vec<Vec<f64>> = pred.0.iter().map(|r| r[nf..].to_vec()).collect();
            let c = ppc::check(&held, &shifted, &pred.1);
            c.iter().filter(|p| p.in_95).count() as f64 / c.len() as f64
        };
        let mut modes: Vec<usize> = data.held_out_modes.iter().map(|m| m.mode).collect();
        modes.sort_unstable();
        HeldOut {
            modes,
            log_score_before: score(&base_pred),
            log_score_after: score(&best_pred),
            coverage95_before: coverage(&base_pred),
            coverage95_after: coverage(&best_pred),
        }
    });
    let misfit: Vec<Check> = base_checks.iter().map(|c| c.check).collect();
    let misfit_after: Vec<Check> = best_checks.iter().map(|c| c.check).collect();
    let gain = Gain {
        extension: best.class.name().to_string(),
        log_bayes_factor: best_lbf,
        rms_z_before: ppc::rms_z(&misfit),
        rms_z_after: ppc::rms_z(&misfit_after),
        misfit_after,
        held_out,
    };
    let diagnosis = Diagnosis {
        misfit_detected,
        misfit,
        candidates,
        cause,
        gain,
        base: base_c,
        baseline,
        thresholds: Thresholds {
            family_alpha: settings.family_alpha,
            per_test_alpha_sidak: per_test,
            log_bayes_factor: settings.log_bayes_factor_threshold,
        },
    };
    Ok(DiagnosisRun { diagnosis, runs })
}

/// TMCMC (`bayes::tmcmc`, Ching & Chen 2007 with the proposal scale and
/// chain length adapted as in Betz et al. 2016), then the MAP from the best
/// sample (`bayes::map`) and the Laplace evidence there (`bayes::laplace`).
fn run_class(class: ModelClass, post: ClassPosterior, s: &DiagnoseSettings, seed: u64) -> Result<ClassRun, TmcmcError> {
    use crate::bayes::Posterior;
    let d = post.dim();
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
    let t = tmcmc(&post, &config)?;
    let (_, sd) = moments(&t.samples, d);
    let best = t
        .samples
        .iter()
        .zip(&t.log_likelihoods)
        .map(|(u, &l)| (u, l + post.log_prior(u)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(u, _)| u.clone())
        .expect("samples");
    // initial simplex: half a posterior sd per coordinate
    let half_sd: Vec<f64> = sd.iter().zip(&best).map(|(s, b)| (0.5 * s).max(1e-12 * b.abs().max(1e-300))).collect();
    let map = map_estimate(&post, &best, &half_sd, s.map_iters).theta;
    // FD step 0.05 sd: the O(h²) truncation error is ≈ 0.25 % of the curvature
    // of a near-Gaussian posterior, while the forward model's round-off
    // (~1e-12 relative) stays negligible against the h²-sized differences.
    let log_evidence_laplace = laplace_log_evidence_with_step(&post, &map, &sd, 0.05).ok().map(|l| l.log_evidence);
    Ok(ClassRun { class, posterior: post, tmcmc: t, map, log_evidence_laplace })
}

fn moments(samples: &[Vec<f64>], d: usize) -> (Vec<f64>, Vec<f64>) {
    let n = samples.len() as f64;
    let mean: Vec<f64> = (0..d).map(|k| samples.iter().map(|s| s[k]).sum::<f64>() / n).collect();
    let sd = (0..d)
        .map(|k| (samples.iter().map(|s| (s[k] - mean[k]).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt())
        .collect();
    (mean, sd)
}

/// Predictions of `obs` at every posterior sample, and β² per sample.
fn predictive(run: &ClassRun, obs: &[Observable]) -> (Vec<Vec<f64>>, Vec<f64>) {
    let rows: Vec<Option<(Vec<f64>, f64)>> = run
        .tmcmc
        .samples
        .par_iter()
        .map(|u| {
            let modes = run.posterior.predict(u).ok()?;
            Some((obs.iter().map(|o| predicted(o, &modes)).collect(), run.posterior.beta_squared(u)))
        })
        .collect();
    rows.into_iter().flatten().unzip()
}

/// Mean, sd and central 95 % interval of every parameter in physical units.
fn summaries(post: &ClassPosterior, samples: &[Vec<f64>]) -> BTreeMap<String, Summary> {
    let phys: Vec<Vec<f64>> = samples.iter().map(|u| post.to_physical(u)).collect();
    let d = post.params.set.len();
    let (mean, sd) = moments(&phys, d);
    post.params
        .set
        .names()
        .into_iter()
        .enumerate()
        .map(|(k, name)| {
            let mut v: Vec<f64> = phys.iter().map(|p| p[k]).collect();
            v.sort_by(f64::total_cmp);
            let q = |f: f64| v[((f * (v.len() - 1) as f64).round() as usize).min(v.len() - 1)];
            (name, Summary { mean: mean[k], sd: sd[k], ci95: [q(0.025), q(0.975)] })
        })
        .collect()
}
