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
//!    causes (55 at the default two: the base, ten singles, forty-four pairs,
//!    the forty-five less shear-deformation + strain-gradient, which the beam
//!    does not combine; 45 on a clamped–clamped or clamped–free beam, where
//!    no rotation is left for a support spring, [`ModelClass::acts_on`]; 45
//!    and 36 when the file's parameters already sample the section,
//!    [`ModelClass::free_in`]) gets its
//!    evidence ([`evidence`]), in one parallel batch per number of causes
//!    (a multimodal model's MAP search also starts from its sub-models'
//!    MAPs); a model of the most causes is left uncomputed when its evidence
//!    bound, its best likelihood found from its sub-models' MAPs, shows that
//!    it can change no decision ([`screen`]; listed as screened). Every
//!    model with causes gets that search first: one not multimodal by
//!    construction takes its evidence by importance sampling from the
//!    search's optimum when that estimate is reliable, without TMCMC
//!    ([`evidence::run_from_optimum`]), and one whose bound lies
//!    [`screen::HOPELESS_NATS`] below every evidence a decision could need
//!    runs TMCMC at a quarter of the samples. A cause
//!    earns its place in a model when the model's ln B against the same
//!    model without it is ≥ 3 ("strong" on the Kass–Raftery scale, B ≥ 20,
//!    and more than ten times the TMCMC log-evidence spread between seeds,
//!    ≈ 0.1–0.3, of a run that finds the posterior's peak; a run that misses
//!    it is detected and replicated, [`evidence`]). A model is selectable
//!    when each of its causes earns its place; among those, more causes
//!    replace fewer only when their best model beats the selection by 3 nats
//!    as well (parsimony), and a selection that misfits yields to the most
//!    probable selectable model within
//!    [`DiagnoseSettings::alternative_margin`] of it that fits ([`search::search`]).
//!    On records of many modes a selected pair is extended by one cause more
//!    (`search::extension`), and the selection made again.
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
//!    that one is not the closest (the closest then), or none is separated
//!    (any), the scan of a measured mode's shape that would
//!    ([`next::shape_measurement`]). The
//!    named causes that every alternative that fits contains too are the
//!    decided ones ([`decided_causes`]); the others are a best guess.
//!
//! # Files
//! `mod.rs` (module doc: the procedure; the entry points `diagnose`, `diagnose_run`; re-exports),
//! `settings` (`DiagnoseSettings`, `DiagnoseError`), `classes` (the priors of the ten causes, `section-mismatch`
//! among them, each with its out-of-catalogue first-order mimic if one is known
//! (`first_order_mimic`, in `model`), `Model` = base + causes or the β baseline (`model`), priors,
//! `model_posterior`; the mirror-image folds in `mirror`, the section reading in `section_reading`),
//! `evidence` (`ModelRun`: `bayes::evidence` per model with the diagnosis's settings; which
//! posteriors are multimodal by construction and get the global and nested MAP searches, the sub-
//! models' MAPs), `search` (evidence of every model of at most two causes (`--max-causes`) that act
//! on the beam's support, run in one batch per number of causes; on records of ≥ 12 fitted
//! observables a selected pair's extensions by one cause; selection), `screen` (the top layer's
//! evidence bounds from a MAP search at the sub-models' MAPs: ln Z ≤ ln L_max, and the Laplace
//! evidence with a measured margin; the rule that leaves a model uncomputed only when its bound
//! cannot change a decision), `verdict` (misfit of the selection, alternatives, next measurement,
//! gain), `diagnosis` (the result types, `decided_causes`, `decide`: the decided causes and, for
//! every other named cause, why not), `predictive` (predictions at every posterior draw), `ppc`
//! (leverage-corrected residual tests of fitted observables, predictive checks of held-out ones),
//! `next` (the measurement that would decide: an unmeasured ω or ζ, else a measured mode's shape
//! scan through `beam::frf_points`, which goes back in as `mode_scans` data), `report` (Markdown +
//! figures through `report`, and the CLI's text summary); error type `DiagnoseError`. The posterior
//! is `calibration::BeamPosterior` seen through `bayes::transform`

pub mod classes;
mod diagnosis;
pub mod evidence;
pub mod falsify;
pub mod mirror;
pub mod model;
pub mod next;
pub mod ppc;
mod predictive;
pub mod report;
pub mod screen;
mod search;
pub mod section_reading;
mod settings;
mod verdict;

use std::collections::BTreeMap;
use std::sync::atomic::AtomicU64;
use std::sync::Mutex;

use crate::calibration::MeasuredData;
use crate::error::InputError;

pub use classes::{model_posterior, ClassPosterior, Model, ModelClass, NominalScales, DISTINCT_RELAXATIONS};
pub use diagnosis::{
    decide, decided_causes, on_prior_bound, Alternative, BoundHit, Candidate, Diagnosis, DiagnosisRun, Gain, HeldOut,
    Summary, Thresholds, Undecided, ON_BOUND_FRACTION,
};
pub use evidence::{ModelRun, LAPLACE_DISAGREEMENT_NATS};
pub use predictive::{fitted_checks, fitted_checks_and_omnibus};
pub use settings::{DiagnoseError, DiagnoseSettings};

use search::{search, Problem};
use verdict::Decision;

/// Runs the diagnosis of `data`.
pub fn diagnose(data: &MeasuredData, settings: &DiagnoseSettings) -> Result<Diagnosis, DiagnoseError> {
    diagnose_run(data, settings).map(|r| r.diagnosis)
}

/// Issue 69, defect 12: a compression the nominal beam carries but the base
/// model's prior does not. The nonlocal buckling load of a simply supported
/// beam, N_cr = −EIα₁²/(1 + (e0a·α₁)²), falls as e0a grows, so a force
/// valid at the file's e0a (0.9999 of the local Euler load) buckles every
/// draw but those of e0a ≈ 0, and TMCMC's first stage found no finite
/// likelihood (exit 1). Refused before any sampling: the force must stay
/// above the buckling load at the largest e0a the base prior reaches (its
/// support's upper end; mean + 4 sd for a normal prior, as
/// `calibration::parameters` bounds it), so every draw of the base is a
/// stable beam. A base prior that samples the axial force itself sets the
/// force of every draw, and one without e0a leaves the file's own beam,
/// which `MeasuredData` has already checked.
fn check_base_prior_stable(data: &MeasuredData) -> Result<(), InputError> {
    use crate::bayes::prior::Prior;
    use crate::calibration::parameters::Target;
    let params = &data.parameters.params;
    if data.beam.axial_force_n >= 0.0 || params.iter().any(|p| p.target == Target::AxialForce) {
        return Ok(());
    }
    let Some(e0a) = params.iter().find(|p| p.target == Target::NonlocalE0a) else {
        return Ok(());
    };
    let e0a_max = match e0a.prior {
        Prior::Normal { mean, sd } => mean + 4.0 * sd,
        ref prior => prior.support().1,
    };
    let mut widest = data.beam.clone();
    widest.nonlocal_e0a_nm = e0a_max;
    match crate::beam::buckling_load_n(&widest) {
        Ok(n_cr) if data.beam.axial_force_n <= n_cr => Err(InputError::new(
            "axial_force_n",
            crate::error::fmt_num(data.beam.axial_force_n),
            format!(
                "> {} N, the buckling load at e0a = {} nm, the largest the base prior (parameters.{}) reaches",
                crate::error::fmt_num(float_short(n_cr)),
                crate::error::fmt_num(e0a_max),
                e0a.name
            ),
        )),
        _ => Ok(()),
    }
}

/// `x` to 6 significant digits (a bound in a message, not a value as written).
fn float_short(x: f64) -> f64 {
    format!("{x:.5e}").parse().unwrap_or(x)
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
    check_base_prior_stable(data)?;
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
        not_evaluable: Mutex::new(vec![]),
    };

    // progress: the base, the β baseline and every candidate but the base
    let control = &settings.control;
    let models = Model::candidates(settings.max_causes, data.beam.support, &data.parameters).len() + 1;
    control.start("models", models as u64);
    let searched = problem.run(vec![Model::BASE, Model::Baseline], &[]).and_then(|mut runs| {
        let search = search(&problem, &mut runs)?;
        Ok((runs, search))
    });
    control.finish();
    let (runs, search) = searched?;
    control.check()?;
    let decide = Decision::new(&problem, &runs, &search);
    let diagnosis = decide.diagnosis(&problem, &runs, &search)?;
    control.check()?;
    Ok(DiagnosisRun { diagnosis, runs })
}
