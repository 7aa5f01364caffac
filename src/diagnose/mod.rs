//! `nanobeam diagnose`: show what the model gets wrong, name every cause
//! present, extend the model, measure the gain — or say that nothing it has
//! explains the data (the step §4.3 of the paper names: Muto & Beck's
//! evidence-based model-class selection, done automatically).
//!
//! 1. **Misfit.** The base model (the file's parameters, default the paper's
//!    N = 1 set; C = 0, ideal supports, nominal geometry) is calibrated by
//!    TMCMC; every observable (ω_r, ζ_r) gets a leverage-corrected residual
//!    test ([`ppc`]). Misfit is detected when some p-value falls below the Šidák
//!    level 1 − (1 − α_FW)^(1/J) (family-wise α_FW = 1 % over J observables).
//! 2. **Search.** Every model of at most [`DiagnoseSettings::max_causes`]
//!    causes (22 at the default two: the base, six singles, fifteen pairs;
//!    16 on a clamped–clamped or clamped–free beam, where no rotation is
//!    left for a support spring, [`ModelClass::acts_on`]) gets its
//!    evidence ([`evidence`]), in one parallel batch per number of causes
//!    (a multimodal model's MAP search also starts from its sub-models'
//!    MAPs). A cause
//!    earns its place in a model when the model's ln B against the same
//!    model without it is ≥ 3 ("strong" on the Kass–Raftery scale, B ≥ 20,
//!    and more than ten times the TMCMC log-evidence spread between seeds,
//!    ≈ 0.1–0.3, of a run that finds the posterior's peak; a run that misses
//!    it is detected and replicated, [`evidence`]). A model is selectable
//!    when each of its causes earns its place; among those, more causes
//!    replace fewer only when their best model beats the selection by 3 nats
//!    as well (parsimony), and a selection that misfits yields to the most
//!    probable selectable model within
//!    [`DiagnoseSettings::alternative_margin`] of it that fits ([`search`]).
//!    Every model and not a greedy path: a pair whose causes are each masked
//!    alone is never reached by extending the leading singles.
//!    The β-inflated base of eq. (41) is computed beside it as a baseline.
//! 3. **Verdict.** The misfit test is run again on the selected
//!    model: a cause is only named when its model no longer misfits; otherwise
//!    the verdict is `unexplained`, with the best partial explanation beside
//!    it. `none` when no misfit is detected and no cause wins.
//! 4. **Gain.** ln B, RMS standardized residual before/after and, with
//!    `held_out_modes`, the joint predictive log score and 95 % coverage of
//!    both models on the held-out modes.
//! 5. **Undecided.** Models within [`DiagnoseSettings::alternative_margin`]
//!    nats of the selected one are listed as alternatives. Each is put to the
//!    misfit test too: one that fails it is listed but is no explanation.
//!    The next measurement is the unmeasured observable whose predictions
//!    under the selected model and an alternative that fits differ most
//!    ([`next::next_measurement`]); the alternative is the closest rival (one
//!    that is not the selected causes plus more; then the nested ones) that
//!    some such observable separates by [`next::MIN_SEPARATION_SD`]; when
//!    none does, the scan of a measured mode's shape that would
//!    ([`next::shape_measurement`]). The
//!    named causes that every alternative that fits contains too are the
//!    decided ones ([`decided_causes`]); the others are a best guess.

pub mod classes;
pub mod evidence;
pub mod next;
pub mod ppc;
pub mod report;
pub mod synthetic;

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use rayon::prelude::*;
use serde::Serialize;

use crate::bayes::importance::ImportanceEvidence;
use crate::bayes::prior::Prior;
use crate::bayes::rng::{child_seed, Purpose};
use crate::bayes::transform::Reparameterized;
use crate::bayes::{BayesError, Posterior};
use crate::beam::BeamSpec;
use crate::calibration::posterior::relative_amplitudes;
use crate::calibration::{
    observables, BeamPosterior, MeasuredData, ModeObservation, ModeScan, Observable, ParameterSet, Quantity,
};
use crate::error::InputError;
use crate::report::ReportError;

use classes::model_parameters;
pub use classes::NominalScales;
pub use classes::{Model, ModelClass};
pub use evidence::ModelRun;
use ppc::{Check, Draws};

/// The posterior of one model in its sampling coordinates (log-uniform priors sampled in ln x).
pub type ClassPosterior = Reparameterized<BeamPosterior>;

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
    /// ln B threshold to add a cause (default 3).
    pub log_bayes_factor_threshold: f64,
    /// A model within this many nats of the selected one is an alternative (default 3:
    /// the data do not prefer either "strongly").
    pub alternative_margin: f64,
    /// Most causes the search adds (default 2: with 8–12 observables and the
    /// base's 3 parameters, a third cause leaves ≤ 3 degrees of freedom, where
    /// any flexible enough combination fits and "explained" stops meaning much).
    pub max_causes: usize,
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
            alternative_margin: 3.0,
            max_causes: 2,
            map_iters: 400,
        }
    }
}

impl DiagnoseSettings {
    /// Upper bound of `samples`: 1e5 samples × ≈ 20 stages × 4 steps is ≈ 1e7
    /// forward evaluations per model (minutes); memory stays ≈ 1e5 × d × 8 B.
    pub const MAX_SAMPLES: usize = 100_000;
    /// Lower bound: the stage covariance of a 5-parameter model needs ≫ 5 samples.
    pub const MIN_SAMPLES: usize = 50;

    /// The settings the hidden-effect suite validates its accuracy targets
    /// at, and `nanobeam diagnose`'s default: 400 samples, 3 steps, 250 MAP
    /// iterations (about a third of [`Default`]'s forward solves).
    pub fn quick() -> Self {
        Self { samples: 400, mh_steps: 3, map_iters: 250, ..Self::default() }
    }

    /// Checks every knob against its range (flag names as the CLI spells them).
    pub fn validate(&self) -> Result<(), InputError> {
        if !(Self::MIN_SAMPLES..=Self::MAX_SAMPLES).contains(&self.samples) {
            return Err(InputError::new(
                "--samples",
                self.samples,
                format!("{}..={}", Self::MIN_SAMPLES, Self::MAX_SAMPLES),
            ));
        }
        if !(1..=100).contains(&self.mh_steps) {
            return Err(InputError::new("mh_steps", self.mh_steps, "1..=100"));
        }
        if !(self.family_alpha > 0.0 && self.family_alpha < 1.0) {
            return Err(InputError::new("family_alpha", self.family_alpha, "0 < alpha < 1"));
        }
        for (name, v) in [
            ("log_bayes_factor_threshold", self.log_bayes_factor_threshold),
            ("alternative_margin", self.alternative_margin),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(InputError::new(name, v, ">= 0 (finite)"));
            }
        }
        Ok(())
    }
}

/// Why a diagnosis could not be made.
#[derive(Debug, thiserror::Error)]
pub enum DiagnoseError {
    /// The measured data or a setting is outside its range: fix the file or flag.
    #[error("{0}")]
    Input(#[from] InputError),
    /// A model's evidence could not be computed (TMCMC failed): the data are
    /// impossible under that model's priors, or the sampler budget is too small.
    #[error("model `{model}`: {source}")]
    Evidence { model: String, source: BayesError },
    /// The report directory could not be written.
    #[error("{0}")]
    Report(#[from] ReportError),
}

/// Posterior summary of one parameter (physical units).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Summary {
    pub mean: f64,
    pub sd: f64,
    pub ci95: [f64; 2],
}

/// One evaluated model in the output.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Candidate {
    /// The model's name: `base`, a cause, causes joined by `+`, or `baseline-beta`.
    pub extension: String,
    pub causes: Vec<String>,
    pub log_evidence: f64,
    /// Standard error of `log_evidence`: Ching & Chen's stage estimator for
    /// one TMCMC run, the replicates' spread when there were several, the
    /// weights' when the importance evidence replaced them.
    pub log_evidence_se: f64,
    /// ln Ẑ of every TMCMC run: one, or `evidence::EVIDENCE_REPLICATES` when
    /// the first run missed the posterior's peak (`log_evidence` combines them,
    /// or is `log_evidence_importance` when that one is reliable).
    pub log_evidence_runs: Vec<f64>,
    /// Importance-sampling evidence (`evidence` module doc; `null` when its
    /// proposal could not be built); it is `log_evidence` when its `ess` ≥
    /// `evidence::IMPORTANCE_MIN_ESS`.
    pub log_evidence_importance: Option<ImportanceEvidence>,
    /// Which estimate `log_evidence` is: `importance` or `tmcmc`.
    pub log_evidence_method: String,
    /// `null` when the MAP sits on a prior boundary or the Hessian is not positive definite.
    pub log_evidence_laplace: Option<f64>,
    /// Laplace and `log_evidence` disagree by more than
    /// [`LAPLACE_DISAGREEMENT_NATS`]: the posterior is far from Gaussian.
    pub laplace_disagrees: bool,
    pub log_bayes_factor: f64,
    /// Posterior model probability among the extended models evaluated (equal prior
    /// probabilities); for the baseline, its probability had it been compared with the base alone.
    pub probability: f64,
    /// Forward-model solves spent on this model (TMCMC, MAP, Laplace, importance draws).
    pub forward_evaluations: u64,
    pub posterior: BTreeMap<String, Summary>,
    /// Cause parameters whose MAP lies on the stronger-effect bound of their
    /// prior range ([`on_prior_bound`]).
    pub map_on_prior_bound: Vec<BoundHit>,
    /// The model has a point mass on supports that mirror each other and the
    /// data have no mode scan, so the modes fix its position only up to the
    /// mirror image about midspan: the prior on `point_mass_x_nm` is folded
    /// onto the left half ([`classes::folds_mass_position`]) and a mass at
    /// L − x fits the data equally well.
    pub point_mass_x_mirror_ambiguous: bool,
}

/// A parameter whose MAP lies on a bound of its prior range.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BoundHit {
    pub parameter: String,
    /// The MAP value and the bound, in the parameter's physical units.
    pub map: f64,
    pub bound: f64,
}

/// How close to a bound of a uniform or log-uniform prior (as a fraction of
/// the prior's width in sampling coordinates) a MAP counts as on it: 0.1 %.
/// Nelder–Mead pressed against a bound ends within its simplex tolerance of
/// it (local-defect case 404: κ = 0.3000016 on the bound 0.3, 2e-6 of the
/// width), while an interior optimum this close to a bound needs a
/// posterior sd of the same 0.1 % order sitting right at the edge.
pub const ON_BOUND_FRACTION: f64 = 1e-3;

/// The cause parameters of `r`'s model whose MAP is on the bound of its
/// prior range where the effect is strongest
/// ([`classes::stronger_effect_ends`]). A cause that earned its place only by
/// asking for more than its class's physical range allows is a sign that
/// the effect lies outside the catalogue (or that the range is too narrow):
/// local-defect case 404 is fitted by a mass and shear deformation with
/// κ = 0.3000016 on the bound 0.3. The base model's own parameters (e0a, Δ,
/// Ω) are not causes and are not judged. The report says so; the verdict is
/// not changed. On the 41-case hidden suite (2026-11-25) this flags no
/// true cause; counting both ends and the base parameters, it had flagged
/// 4 of 4 shear singles, 3 of 8 pairs and a clean case.
pub fn on_prior_bound(r: &ModelRun) -> Vec<BoundHit> {
    let params = &r.posterior.inner().parameters().params;
    let causes: usize = r.model.causes().iter().map(|c| c.parameter_count()).sum();
    let first = params.len() - causes;
    bound_hits(&params[first..], &r.posterior.log_scale()[first..], &r.map[first..])
}

/// The parameters whose value `map` (sampling coordinates: ln x where
/// `log_scale`) lies within [`ON_BOUND_FRACTION`] of a stronger-effect bound
/// of a uniform or log-uniform prior.
fn bound_hits(params: &[crate::calibration::Parameter], log_scale: &[bool], map: &[f64]) -> Vec<BoundHit> {
    params
        .iter()
        .zip(log_scale)
        .zip(map)
        .filter_map(|((p, &log), &u)| {
            if !matches!(p.prior, Prior::Uniform { .. } | Prior::LogUniform { .. }) {
                return None;
            }
            let (lo, hi) = p.prior.support();
            let t = |x: f64| if log { x.ln() } else { x };
            let tol = ON_BOUND_FRACTION * (t(hi) - t(lo));
            let phys = if log { u.exp() } else { u };
            [lo, hi]
                .into_iter()
                .zip(classes::stronger_effect_ends(p.target))
                .find(|&(b, strong)| strong && (u - t(b)).abs() <= tol)
                .map(|(bound, _)| BoundHit { parameter: p.name.clone(), map: phys, bound })
        })
        .collect()
}

/// Two relaxations closer than this in |ln(Ωᵢ/Ωⱼ)| are one (see
/// `BeamPosterior::with_distinct_relaxations`): 5 %, which removes ≈ 2·0.05/5.8
/// ≈ 2 % of the extra relaxation's prior (its Ω spans ln(9ω_n/ω₁) ≈ 5.8 nats
/// for 5 modes), i.e. ≤ 0.02 nats of log evidence, far below the ln B ≥ 3 threshold.
pub const DISTINCT_RELAXATIONS: f64 = 0.05;

/// Laplace vs TMCMC log-evidence gap that flags a non-Gaussian posterior.
pub const LAPLACE_DISAGREEMENT_NATS: f64 = 1.0;

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
    /// The model assessed: the selected one, else the most probable candidate.
    pub extension: String,
    pub log_bayes_factor: f64,
    pub rms_z_before: f64,
    pub rms_z_after: f64,
    /// The posterior predictive checks under the extended model.
    pub misfit_after: Vec<Check>,
    pub held_out: Option<HeldOut>,
}

/// A model the data cannot separate from the selected one.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Alternative {
    pub extension: String,
    /// ln Z(selected) − ln Z(alternative), below the margin. Negative for a
    /// model with more causes whose evidence exceeds the selected one's by
    /// less than the ln B threshold a cause must gain to be added (step 2).
    pub log_bayes_factor_gap: f64,
    /// The alternative fails the misfit test on the fitted data: its
    /// evidence is close, but some observable rejects it at the family-wise
    /// level, so it is no explanation. It neither undecides a cause
    /// ([`decided_causes`]) nor is the rival of the next measurement.
    pub misfits: bool,
}

impl Alternative {
    /// The β baseline: noise larger than the stated sds, not a cause.
    pub fn is_noise(&self) -> bool {
        self.extension == Model::Baseline.name()
    }
}

/// Decision thresholds actually used.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Thresholds {
    pub family_alpha: f64,
    pub per_test_alpha_sidak: f64,
    pub log_bayes_factor: f64,
    pub alternative_margin: f64,
}

/// The diagnosis (the `--json` output).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Diagnosis {
    pub misfit_detected: bool,
    pub misfit: Vec<Check>,
    /// Every extended model the search evaluated, in the order visited.
    pub candidates: Vec<Candidate>,
    /// The causes of the selected model, ordered by evidence gain (empty when unexplained).
    pub causes: Vec<String>,
    /// `none`, a cause's name, `multiple`, or `unexplained`.
    pub cause: String,
    /// `false` when the selected model still misfits (the cause is then `unexplained`).
    pub explained: bool,
    /// The causes of `causes` that every model in `alternatives` contains as
    /// well: no model within the alternative margin explains the data
    /// without them ([`decided_causes`]). The rest of `causes` is the
    /// evidence's best guess, not a decision. Empty when unexplained.
    pub decided_causes: Vec<String>,
    /// The causes of the best model found, even when it does not explain the data.
    pub best_partial_explanation: Vec<String>,
    pub gain: Gain,
    pub alternatives: Vec<Alternative>,
    pub next_measurement: Option<next::NextMeasurement>,
    /// When no ω or ζ separates the selection from an alternative that fits:
    /// the scan of a measured mode's shape that would (`null` otherwise, or
    /// when no shape separates them either).
    pub shape_measurement: Option<next::ShapeMeasurement>,
    pub base: Candidate,
    pub baseline: Candidate,
    pub thresholds: Thresholds,
    /// Forward-model solves of the whole diagnosis: every model visited and
    /// the baseline, and the posterior predictive draws of the misfit tests,
    /// the gain and the next measurement.
    pub forward_evaluations: u64,
}

/// A diagnosis with the per-model runs behind it.
#[derive(Debug, Clone)]
pub struct DiagnosisRun {
    pub diagnosis: Diagnosis,
    pub runs: Vec<ModelRun>,
}

impl DiagnosisRun {
    /// The run of `model` (every model in the diagnosis ran).
    pub fn run_of(&self, model: &Model) -> Option<&ModelRun> {
        self.runs.iter().find(|r| &r.model == model)
    }
}

/// Runs the diagnosis of `data`.
pub fn diagnose(data: &MeasuredData, settings: &DiagnoseSettings) -> Result<Diagnosis, DiagnoseError> {
    diagnose_run(data, settings).map(|r| r.diagnosis)
}

/// What every model of one diagnosis shares.
struct Problem<'a> {
    data: &'a MeasuredData,
    settings: &'a DiagnoseSettings,
    scales: NominalScales,
    seed: u64,
    /// Forward solves of the posterior predictive draws (the misfit tests,
    /// the gain, the next measurement): one modal solve per posterior draw
    /// and model, counted into the diagnosis's `forward_evaluations`.
    predictive_solves: AtomicU64,
    /// Each model's misfit verdict ([`misfits`]) by name, computed once: the
    /// search's fallback and the alternatives' screening can ask for the same
    /// model, at one predictive solve per posterior draw each time.
    misfit_verdicts: Mutex<BTreeMap<String, bool>>,
}

/// The posterior of `model` given the fitted `modes` and `scans` of a beam whose known part is `beam`.
pub fn model_posterior(
    model: &Model,
    parameters: &ParameterSet,
    beam: &BeamSpec,
    modes: &[ModeObservation],
    scans: &[ModeScan],
    scales: &NominalScales,
) -> ClassPosterior {
    let p = model_parameters(model, parameters, beam, scans, scales);
    let posterior =
        BeamPosterior::from_parts(beam, modes, p.set).with_scans(scans).with_distinct_relaxations(DISTINCT_RELAXATIONS);
    Reparameterized::new(posterior, p.log_scale)
}

impl Problem<'_> {
    fn posterior(&self, model: &Model) -> ClassPosterior {
        let d = self.data;
        model_posterior(model, &d.parameters, &d.beam, &d.modes, &d.mode_scans, &self.scales)
    }

    /// Evidence of every model in `models` (in parallel; each keyed by the
    /// model's identity); a multimodal model's MAP search also starts from
    /// the MAPs of its sub-models (one cause fewer) among the runs `done`
    /// ([`evidence::run_model`]). A model whose first TMCMC run missed the
    /// peak, and whose importance evidence is not reliable enough to stand
    /// in for it, is replicated ([`evidence::replicate`]) when it is in
    /// contention: its Laplace evidence within the alternative margin of the
    /// best evidence of `done` and the batch, the β baseline left out (it
    /// is never a cause). One far behind cannot change a decision and keeps
    /// its single run (flagged in the output by one entry in
    /// `log_evidence_runs`): on a foreign effect, where every pair is tried,
    /// replicating every flagged model took one case from 85 s to 690 s.
    fn run(&self, models: Vec<Model>, done: &[ModelRun]) -> Result<Vec<ModelRun>, DiagnoseError> {
        fn err(m: &Model) -> impl FnOnce(BayesError) -> DiagnoseError {
            let model = m.name();
            move |source| DiagnoseError::Evidence { model, source }
        }
        let runs: Vec<ModelRun> = models
            .into_par_iter()
            .map(|m| {
                let seed = child_seed(self.seed, Purpose::ModelClass, [model_key(&m), 0]);
                let subs: Vec<&ModelRun> =
                    m.causes().iter().filter_map(|&c| done.iter().find(|r| r.model == m.without(c))).collect();
                evidence::run_model(m.clone(), self.posterior(&m), self.settings, seed, &subs).map_err(err(&m))
            })
            .collect::<Result<_, _>>()?;
        // the β baseline is never a cause: a misfit it absorbs as noise must not
        // lift the bar a candidate's evidence is judged in contention against
        let best = runs
            .iter()
            .chain(done)
            .filter(|r| r.model != Model::Baseline)
            .map(|r| r.log_evidence)
            .fold(f64::NEG_INFINITY, f64::max);
        let margin = self.settings.alternative_margin;
        runs.into_par_iter()
            .map(|r| match r.log_evidence_laplace {
                Some(l) if r.missed_peak && !r.importance_reliable() && l >= best - margin => {
                    let m = r.model.clone();
                    evidence::replicate(r, self.settings).map_err(err(&m))
                }
                _ => Ok(r),
            })
            .collect()
    }
}

/// A stable key of a model for its random streams: the bit set of its causes
/// (bit k = `ModelClass::CAUSES[k]`), or `u64::MAX` for the baseline.
fn model_key(m: &Model) -> u64 {
    match m {
        Model::Baseline => u64::MAX,
        Model::Extended(c) => {
            c.iter().map(|c| 1u64 << ModelClass::CAUSES.iter().position(|k| k == c).unwrap_or(63)).sum()
        }
    }
}

/// [`diagnose`] keeping the per-model runs.
pub fn diagnose_run(data: &MeasuredData, settings: &DiagnoseSettings) -> Result<DiagnosisRun, DiagnoseError> {
    settings.validate()?;
    if data.modes.len() < 3 {
        return Err(InputError::new(
            "modes",
            format!("{} mode(s)", data.modes.len()),
            "at least 3 fitted modes (a diagnosis compares models with up to 7 parameters)",
        )
        .into());
    }
    let n_modes = data.max_mode();
    let scales = NominalScales::of(&data.beam, n_modes).map_err(|e| {
        InputError::new("modes", format!("highest mode {n_modes}"), format!("modes the beam model can compute ({e})"))
    })?;
    let problem = Problem {
        data,
        settings,
        scales,
        seed: settings.seed.unwrap_or(data.sampler.seed),
        predictive_solves: AtomicU64::new(0),
        misfit_verdicts: Mutex::new(BTreeMap::new()),
    };

    let mut runs = problem.run(vec![Model::BASE, Model::Baseline], &[])?;
    let search = search(&problem, &mut runs)?;
    let decide = Decision::new(&problem, &runs, &search);
    let diagnosis = decide.diagnosis(&problem, &runs, &search)?;
    Ok(DiagnosisRun { diagnosis, runs })
}

/// The model the search selected and the models it compared.
struct Search {
    /// The base, then the selected model's causes added in the order of
    /// their evidence gain (at each step the sub-model of highest evidence),
    /// ending with the selected model.
    path: Vec<Model>,
    /// Every model compared, in the order of [`Model::candidates`] (the base first).
    visited: Vec<Model>,
}

/// Evidence-based selection over every model of at most `max_causes`
/// causes (module doc, step 2), run in one batch per number of causes:
/// 1. a cause earns its place in a model when ln Z(model) − ln Z(model
///    without it) ≥ the threshold; only models whose every cause earns its
///    place are selectable (the base always is);
/// 2. parsimony: the best selectable model of k causes replaces the
///    selection of fewer causes only when it beats it by the threshold too;
/// 3. when that selection misfits, it yields to the most probable
///    selectable model within the alternative margin of it that fits.
///
/// Why every model and not a greedy path: forward selection only extends
/// the singles near the best single, so a pair whose causes are each masked
/// alone is never run, and the verdict can be `unexplained` while a
/// catalogue pair fits (hidden case 335: relaxation + tension, its pair
/// never run). Why rules 2 and 3, measured on the 73 hidden cases
/// (2026-11-25) with the evidences and misfit flags of this batch: rule 1
/// alone named a spring as viscous damping + tension (case 120: that pair
/// lies 1.0 nats above the spring, each of its causes 3.7–33 nats above its
/// singles) and took singles to 22/24; rules 1 and 2 keep that spring but
/// say `unexplained` on case 335, where the best single (shear) misfits and
/// the true pair fits 0.2 nats above it. All three: singles 23/24, pairs
/// 23/40 (forward selection: 22/40). The cost is every pair's evidence (22
/// models at two causes against the 10–17 the path visited), in one
/// parallel batch per number of causes, the singles first, so that each
/// multimodal model's MAP search can start from its sub-models' MAPs.
fn search(problem: &Problem, runs: &mut Vec<ModelRun>) -> Result<Search, DiagnoseError> {
    let threshold = problem.settings.log_bayes_factor_threshold;
    let margin = problem.settings.alternative_margin;
    let models = Model::candidates(problem.settings.max_causes, problem.data.beam.support);
    for k in 1..=problem.settings.max_causes {
        let batch: Vec<Model> = models.iter().filter(|m| m.causes().len() == k).cloned().collect();
        let done = problem.run(batch, runs)?;
        runs.extend(done);
    }
    let runs: &[ModelRun] = runs;
    let z = |m: &Model| log_evidence_of(runs, m);
    let selectable = |m: &&Model| m.causes().iter().all(|&c| z(m) - z(&m.without(c)) >= threshold);
    let most_probable = |a: &&Model, b: &&Model| z(a).total_cmp(&z(b));
    let mut selected = Model::BASE;
    for k in 1..=problem.settings.max_causes {
        let best = models.iter().filter(|m| m.causes().len() == k).filter(selectable).max_by(most_probable);
        if let Some(best) = best.filter(|b| z(b) - z(&selected) >= threshold) {
            selected = best.clone();
        }
    }
    let run = |m: &Model| runs.iter().find(|r| &r.model == m).expect("every model ran");
    if misfits(problem, run(&selected)) {
        let floor = z(&selected) - margin;
        let fitting = models
            .iter()
            .filter(|m| z(m) >= floor)
            .filter(selectable)
            .filter(|m| !misfits(problem, run(m)))
            .max_by(most_probable);
        if let Some(m) = fitting {
            selected = m.clone();
        }
    }
    // the path records the order of evidence gain: from the selected model
    // down, drop at each step the cause whose removal costs least
    let mut path = vec![selected];
    while let Some(last) = path.last().filter(|m| !m.causes().is_empty()) {
        let parent = last
            .causes()
            .iter()
            .map(|&c| last.without(c))
            .max_by(|a, b| z(a).total_cmp(&z(b)))
            .expect("a model with causes has a parent");
        path.push(parent);
    }
    path.reverse();
    Ok(Search { path, visited: models })
}

/// Does `run`'s model fail the misfit test on the fitted data? (Once per model: [`Problem::misfit_verdicts`].)
fn misfits(problem: &Problem, run: &ModelRun) -> bool {
    let name = run.model.name();
    if let Some(&v) = problem.misfit_verdicts.lock().expect("no panic holds the lock").get(&name) {
        return v;
    }
    let fitted = problem.data.fitted_observables();
    let draws = predictive(run, &fitted, problem.data.max_mode(), &problem.predictive_solves);
    let checks = ppc::check_fitted(&fitted, &draws);
    let per_test = ppc::sidak_level(problem.settings.family_alpha, checks.len());
    let v = checks.iter().any(|c| c.ppp < per_test);
    problem.misfit_verdicts.lock().expect("no panic holds the lock").insert(name, v);
    v
}

/// ln Z of `m` among `runs` (−∞ when it has not run).
fn log_evidence_of(runs: &[ModelRun], m: &Model) -> f64 {
    runs.iter().find(|r| &r.model == m).map_or(f64::NEG_INFINITY, |r| r.log_evidence)
}

/// The leverage-corrected residual test ([`ppc::check_fitted`]) of every
/// fitted observable of `data` under `run`'s posterior.
pub fn fitted_checks(run: &ModelRun, data: &MeasuredData) -> Vec<Check> {
    let fitted = data.fitted_observables();
    ppc::check_fitted(&fitted, &predictive(run, &fitted, data.max_mode(), &AtomicU64::new(0)))
}

/// The checks and the verdict (module doc, step 3).
struct Decision {
    selected: Model,
    draws_base: Draws,
    draws_selected: Draws,
    fitted: Vec<Observable>,
    held: Vec<Observable>,
}

impl Decision {
    fn new(problem: &Problem, runs: &[ModelRun], search: &Search) -> Self {
        let fitted = problem.data.fitted_observables();
        let held = observables(&problem.data.held_out_modes);
        let all: Vec<Observable> = fitted.iter().chain(&held).copied().collect();
        let run = |m: &Model| runs.iter().find(|r| &r.model == m).expect("every visited model ran");
        let selected = search.path.last().expect("path starts with the base").clone();
        // the gain is assessed for the selected model, else for the most probable candidate
        let assessed = if selected == Model::BASE {
            search
                .visited
                .iter()
                .skip(1)
                .max_by(|a, b| run(a).log_evidence.total_cmp(&run(b).log_evidence))
                .cloned()
                .unwrap_or(Model::BASE)
        } else {
            selected
        };
        let max_mode = problem.data.max_mode();
        Self {
            draws_base: predictive(run(&Model::BASE), &all, max_mode, &problem.predictive_solves),
            draws_selected: predictive(run(&assessed), &all, max_mode, &problem.predictive_solves),
            selected: assessed,
            fitted,
            held,
        }
    }

    fn diagnosis(&self, problem: &Problem, runs: &[ModelRun], search: &Search) -> Result<Diagnosis, DiagnoseError> {
        let s = problem.settings;
        let run = |m: &Model| runs.iter().find(|r| &r.model == m).expect("every visited model ran");
        let z_base = run(&Model::BASE).log_evidence;
        let nf = self.fitted.len();
        let per_test = ppc::sidak_level(s.family_alpha, nf);
        let misfit = ppc::check_fitted(&self.fitted, &self.draws_base);
        let misfit_after = ppc::check_fitted(&self.fitted, &self.draws_selected);
        let flags = |c: &[Check]| c.iter().any(|c| c.ppp < per_test);
        let misfit_detected = flags(&misfit);

        let selected = search.path.last().expect("path starts with the base");
        let causes: Vec<String> = selected.causes_in_order(&search.path);
        // misfit_after belongs to the selected model whenever one was selected
        let explained = if selected == &Model::BASE { !misfit_detected } else { !flags(&misfit_after) };
        let cause = match (explained, causes.len()) {
            (false, _) => "unexplained".to_string(),
            (true, 0) => "none".to_string(),
            (true, 1) => causes[0].clone(),
            (true, _) => "multiple".to_string(),
        };

        // probabilities over the visited extended models, equal prior probabilities
        let z_max = search.visited.iter().map(|m| run(m).log_evidence).fold(f64::NEG_INFINITY, f64::max);
        let norm: f64 = search.visited.iter().map(|m| (run(m).log_evidence - z_max).exp()).sum();
        let prob = |r: &ModelRun| (r.log_evidence - z_max).exp() / norm;
        let candidate = |r: &ModelRun, p: f64| candidate(r, z_base, p, problem.data);
        let candidates: Vec<Candidate> =
            search.visited.iter().skip(1).map(|m| candidate(run(m), prob(run(m)))).collect();
        let baseline_run = run(&Model::Baseline);
        let lb = baseline_run.log_evidence - z_base;

        let z_sel = run(selected).log_evidence;
        // The β baseline is an alternative too, though never a cause: noise
        // larger than the stated sds explaining the misfit about as well as
        // the selected causes (a clean set whose noise is twice its stated
        // sds was named viscous-damping 0.5 nats ahead of it, 2026-11-27). It
        // lacks every cause, so within the margin it undecides them all
        // ([`decided_causes`]); no ω or ζ is asked to separate it (`rivals`).
        let mut alternatives: Vec<Alternative> = if selected == &Model::BASE {
            vec![]
        } else {
            search
                .visited
                .iter()
                .chain([&Model::Baseline])
                .filter(|m| *m != selected && z_sel - run(m).log_evidence < s.alternative_margin)
                .map(|m| Alternative {
                    extension: m.name(),
                    log_bayes_factor_gap: z_sel - run(m).log_evidence,
                    misfits: misfits(problem, run(m)),
                })
                .collect()
        };
        alternatives.sort_by(|a, b| a.log_bayes_factor_gap.total_cmp(&b.log_bayes_factor_gap));
        // The alternatives a measurement could rule out, in the order asked:
        // the rival explanations (not the selected causes plus more) first,
        // closest first: a nested model within the margin only says "perhaps
        // X as well", which its Occam factor already weighed; which cause it
        // is comes first. An alternative that misfits is already rejected by
        // the data. The suggestion separates the selection from the first of
        // them some unmeasured ω or ζ separates by MIN_SEPARATION_SD: when the
        // closest rival cannot be separated so (a spring and a tension both
        // move mode n smoothly in n), a farther one often can (hidden pair
        // 307: spring + mass against relaxation + mass), and ruling it out is
        // still a decision the data could not make.
        let nested = |a: &&Alternative| {
            let m = Model::from_name(&a.extension).expect("names of visited models parse");
            selected.causes().iter().all(|c| m.causes().contains(c))
        };
        let fitting = alternatives.iter().filter(|a| !a.misfits && !a.is_noise());
        let asked = fitting.clone().filter(|a| !nested(a)).chain(fitting.filter(nested));
        let rivals: Vec<&ModelRun> =
            asked.map(|a| run(search.visited.iter().find(|m| m.name() == a.extension).expect("visited"))).collect();
        let solves = &problem.predictive_solves;
        let next_measurement = next::next_measurement(problem.data, run(selected), rivals.iter().copied(), solves);
        // no ω or ζ decides: a mode shape may (next.rs, module doc)
        let shape_measurement = match next_measurement {
            None => next::shape_measurement(
                problem.data,
                run(selected),
                rivals.iter().copied(),
                s.log_bayes_factor_threshold,
                solves,
            ),
            Some(_) => None,
        };

        let decided_causes = if explained { decided_causes(&causes, &alternatives) } else { vec![] };
        let gain = Gain {
            extension: self.selected.name(),
            log_bayes_factor: run(&self.selected).log_evidence - z_base,
            rms_z_before: ppc::rms_z(&misfit),
            rms_z_after: ppc::rms_z(&misfit_after),
            misfit_after,
            held_out: self.held_out(problem.data),
        };
        Ok(Diagnosis {
            misfit_detected,
            misfit,
            candidates,
            causes: if explained { causes.clone() } else { vec![] },
            cause,
            explained,
            decided_causes,
            best_partial_explanation: causes,
            gain,
            alternatives,
            next_measurement,
            shape_measurement,
            base: candidate(run(&Model::BASE), prob(run(&Model::BASE))),
            baseline: candidate(baseline_run, 1.0 / (1.0 + (-lb).exp())),
            thresholds: Thresholds {
                family_alpha: s.family_alpha,
                per_test_alpha_sidak: per_test,
                log_bayes_factor: s.log_bayes_factor_threshold,
                alternative_margin: s.alternative_margin,
            },
            forward_evaluations: runs.iter().map(|r| r.forward_evaluations).sum::<u64>()
                + problem.predictive_solves.load(Ordering::Relaxed),
        })
    }

    /// Held-out predictive log score and 95 % coverage, base vs assessed model.
    fn held_out(&self, data: &MeasuredData) -> Option<HeldOut> {
        if self.held.is_empty() {
            return None;
        }
        let nf = self.fitted.len();
        let score = |d: &Draws| {
            let per_sample: Vec<f64> = d
                .predictions
                .iter()
                .zip(&d.beta_sq)
                .map(|(row, &b2)| {
                    let one = Draws { predictions: vec![row.clone()], beta_sq: vec![b2] };
                    ppc::check(&self.held, &one, nf).iter().map(|p| p.log_density).sum::<f64>()
                })
                .collect();
            ppc::log_mean_exp(&per_sample)
        };
        let coverage = |d: &Draws| {
            let c = ppc::check(&self.held, d, nf);
            c.iter().filter(|p| p.in_95).count() as f64 / c.len() as f64
        };
        let mut modes: Vec<usize> = data.held_out_modes.iter().map(|m| m.mode).collect();
        modes.sort_unstable();
        Some(HeldOut {
            modes,
            log_score_before: score(&self.draws_base),
            log_score_after: score(&self.draws_selected),
            coverage95_before: coverage(&self.draws_base),
            coverage95_after: coverage(&self.draws_selected),
        })
    }
}

/// The causes of `causes` (in their order) that every alternative's model
/// that fits contains too (the β baseline, noise larger than stated,
/// contains none). A cause missing from some such model within the
/// alternative margin is not decided: the data explain themselves about as
/// well without it (a near-tie of two pairs that share one cause leaves that
/// one; a single cause with a rival single leaves none). A superset of the
/// selected model (the selection plus a cause the Occam factor weighed
/// against) removes nothing, and neither does an alternative that misfits
/// (the data reject it). On the 73-case hidden suite of 2026-11-26 no
/// decided cause was false in 72 cases (26 of them decided none, computed
/// from the logged verdicts and alternatives before misfitting alternatives
/// were screened; 25 with them screened, at 9bd7092); the exception, case
/// 310 (tension + mass, viscous damping preferred by 5.8 nats with both
/// evidences reliable), is a wrong name no margin of this size would have
/// flagged.
pub fn decided_causes(causes: &[String], alternatives: &[Alternative]) -> Vec<String> {
    let models: Vec<Model> = alternatives
        .iter()
        .filter(|a| !a.misfits)
        .map(|a| Model::from_name(&a.extension).expect("alternatives name visited models"))
        .collect();
    causes
        .iter()
        .filter(|name| {
            let c = ModelClass::from_name(name).expect("causes are class names");
            models.iter().all(|m| m.causes().contains(&c))
        })
        .cloned()
        .collect()
}

impl Model {
    /// This model's causes in the order the search added them.
    fn causes_in_order(&self, path: &[Model]) -> Vec<String> {
        path.windows(2)
            .filter_map(|w| w[1].causes().iter().find(|c| !w[0].causes().contains(c)))
            .filter(|c| self.causes().contains(c))
            .map(|c| c.name().to_string())
            .collect()
    }
}

fn candidate(r: &ModelRun, z_base: f64, probability: f64, data: &MeasuredData) -> Candidate {
    let z = r.log_evidence;
    Candidate {
        extension: r.model.name(),
        causes: r.model.causes().iter().map(|c| c.name().to_string()).collect(),
        log_evidence: z,
        log_evidence_se: r.log_evidence_se,
        log_evidence_runs: r.log_evidence_runs.clone(),
        log_evidence_importance: r.importance.clone(),
        log_evidence_method: if r.importance_reliable() { "importance" } else { "tmcmc" }.to_string(),
        log_evidence_laplace: r.log_evidence_laplace,
        laplace_disagrees: r.log_evidence_laplace.is_some_and(|l| (l - z).abs() > LAPLACE_DISAGREEMENT_NATS),
        log_bayes_factor: z - z_base,
        probability,
        forward_evaluations: r.forward_evaluations,
        posterior: summaries(r),
        map_on_prior_bound: on_prior_bound(r),
        point_mass_x_mirror_ambiguous: classes::folds_mass_position(&r.model, &data.beam, &data.mode_scans),
    }
}

/// Predictions of `obs` at every posterior sample (failed samples dropped), and β² per sample.
/// One modal solve per posterior draw of `run`, added to `solves`. Relative
/// amplitudes among `obs` must be those of `run`'s fitted scans, in order
/// (as [`MeasuredData::fitted_observables`] lists them); their FRF
/// factorisations are not counted (they run only when scans are fitted).
pub(crate) fn predictive(run: &ModelRun, obs: &[Observable], max_mode: usize, solves: &AtomicU64) -> Draws {
    solves.fetch_add(run.draws.len() as u64, Ordering::Relaxed);
    let post = &run.posterior;
    let scans = post.inner().scans();
    let has_amplitudes = obs.iter().any(|o| o.quantity == Quantity::RelativeAmplitude);
    let rows: Vec<Option<(Vec<f64>, f64)>> = run
        .draws
        .par_iter()
        .map(|u| {
            let x = post.to_inner(u);
            let beam = post.inner().beam_at(&x);
            let modes = crate::beam::modal(&beam, max_mode).ok()?.modes;
            let omega_of = |n: usize| modes.iter().find(|m| m.mode == n).map(|m| m.omega_rad_s);
            let amplitudes = if has_amplitudes { relative_amplitudes(&beam, scans, omega_of)? } else { vec![] };
            let mut next_amplitude = amplitudes.into_iter();
            let row: Option<Vec<f64>> = obs
                .iter()
                .map(|o| match o.quantity {
                    Quantity::RelativeAmplitude => next_amplitude.next(),
                    _ => o.predicted(&modes),
                })
                .collect();
            Some((row?, post.inner().beta_at(&x).powi(2)))
        })
        .collect();
    let (predictions, beta_sq) = rows.into_iter().flatten().unzip();
    Draws { predictions, beta_sq }
}

/// Mean, sd and central 95 % interval of every parameter in physical units.
fn summaries(r: &ModelRun) -> BTreeMap<String, Summary> {
    let phys: Vec<Vec<f64>> = r.draws.iter().map(|u| r.posterior.to_inner(u)).collect();
    r.posterior
        .names()
        .into_iter()
        .enumerate()
        .map(|(k, name)| {
            let v: Vec<f64> = phys.iter().map(|p| p[k]).collect();
            let (mean, sd, ci95) = crate::bayes::summary::describe(&v);
            (name, Summary { mean, sd, ci95 })
        })
        .collect()
}

/// The observations of `modes` as the file lists them (for the report).
pub(crate) fn mode_list(modes: &[ModeObservation]) -> String {
    modes.iter().map(|m| m.mode.to_string()).collect::<Vec<_>>().join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::calibration::{Parameter, Target};

    fn param(name: &str, prior: Prior) -> Parameter {
        Parameter { name: name.into(), target: Target::from_name(name).unwrap(), prior, proposal_sd: 0.01 }
    }

    /// A cause is decided when every alternative that fits has it: a rival
    /// pair that shares one cause leaves that one, a rival single leaves
    /// none, a superset of the selection or a misfitting alternative removes
    /// nothing, no alternative keeps all.
    #[test]
    fn decided_causes_are_those_every_alternative_shares() {
        let alt = |name: &str| Alternative { extension: name.into(), log_bayes_factor_gap: 1.0, misfits: false };
        let causes: Vec<String> = vec!["extra-relaxation".into(), "axial-force".into()];
        let rival_pair = [alt("extra-relaxation+support-rotational-stiffness")];
        assert_eq!(decided_causes(&causes, &rival_pair), vec!["extra-relaxation".to_string()]);
        let superset = [alt("extra-relaxation+axial-force+attached-mass")];
        assert_eq!(decided_causes(&causes, &superset), causes);
        assert_eq!(decided_causes(&causes, &[]), causes);
        let with_single = [rival_pair[0].clone(), alt("axial-force")];
        assert!(decided_causes(&causes, &with_single).is_empty());
        assert!(decided_causes(&causes, &[alt("base")]).is_empty());
        // an alternative the data reject undecides nothing
        let rejected = Alternative { misfits: true, ..alt("axial-force") };
        assert_eq!(decided_causes(&causes, &[rejected]), causes);
        // noise larger than stated explains the data without any cause
        let noise = alt("baseline-beta");
        assert!(noise.is_noise() && !rival_pair[0].is_noise());
        assert!(decided_causes(&causes, &[noise]).is_empty());
    }

    /// On a stronger-effect bound within 0.1 % of the prior's width (in ln x
    /// for a log-uniform prior); interior values, weak ends and priors
    /// without a bounded range are not flagged.
    #[test]
    fn bound_hits_flag_maps_on_the_edge_of_a_prior_range() {
        let params = [
            param("shear_coefficient", Prior::Uniform { lower: 0.3, upper: 1.0 }),
            param("support_rotational_stiffness_n_m_rad", Prior::LogUniform { lower: 1e-2, upper: 1e2 }),
            param("point_mass_x_nm", Prior::Uniform { lower: 0.0, upper: 4.0 }),
            param("nonlocal_e0a_nm", Prior::Normal { mean: 1.0, sd: 0.1 }),
        ];
        let log = [false, true, false, false];
        // case 404's κ; ln k 1e-4 below ln 1e2 (width ln 1e4 = 9.2, so 1.1e-5 of it); x at 2 nm; e0a far out
        let hits = bound_hits(&params, &log, &[0.3000016, 1e2f64.ln() - 1e-4, 2.0, 5.0]);
        assert_eq!(hits.len(), 2);
        assert_eq!((hits[0].parameter.as_str(), hits[0].bound), ("shear_coefficient", 0.3));
        assert!((hits[1].map / 1e2 - 1.0).abs() < 2e-4 && hits[1].bound == 1e2);
        // 0.2 % of the width inside: not on the bound
        assert!(bound_hits(&params[..1], &log[..1], &[0.3 + 0.002 * 0.7]).is_empty());
        // the weak ends (κ = 1: least shear; k_r at 1e-2: nearly pinned) and a
        // position (no stronger end) are not flagged
        assert!(bound_hits(&params[..1], &log[..1], &[1.0 - 1e-6]).is_empty());
        assert!(bound_hits(&params[1..2], &log[1..2], &[1e-2f64.ln() + 1e-6]).is_empty());
        assert!(bound_hits(&params[2..3], &log[2..3], &[0.003]).is_empty());
    }
}
