//! Case 3 beyond the paper: the evidence of the β-inflated N = 1 model class
//! against the N = 2 class (the combined estimator of `bayes::evidence`, the
//! one `diagnose` trusts), and `nanobeam diagnose` on the same data.
//! Which cases, how many TMCMC samples and the estimator's settings:
//! `paper/specs/evidence.yaml`.

use crate::bayes::control::Control;
use crate::bayes::evidence::estimate_replicated;
use crate::diagnose::evidence::multimodal_by_construction;
use crate::reproduce::cases::CaseOutcome;
use crate::reproduce::error::ReproduceError;
use crate::reproduce::reconstruction::Reconstruction;
use crate::reproduce::results::{CandidateResult, DiagnosisResult, EvidenceResult};
use crate::reproduce::specs::EvidenceSpec;

/// log evidence of each Case-3 model class on the same synthetic data, each
/// run keyed by its case's seed; the log Bayes factor says what the second
/// internal variable buys over absorbing the misfit into β. The estimator is
/// `bayes::evidence`'s: TMCMC checked by the MAP, the Laplace evidence and
/// importance sampling; the N = 2 posterior (two exchangeable relaxations) is
/// multimodal by construction and gets the global MAP search; a run that
/// missed the peak with no reliable importance evidence is replicated (both
/// classes are in contention: their Bayes factor is the result). `None` when
/// a case is absent or the estimator fails.
pub fn evidence_stage(spec: &EvidenceSpec, cases: &[CaseOutcome], quick: bool) -> Option<EvidenceResult> {
    let settings = spec.settings(quick);
    let one = |id: &str| -> Option<(f64, f64)> {
        let c = cases.iter().find(|c| c.spec.id == id)?;
        let multimodal = multimodal_by_construction(c.posterior.parameters());
        estimate_replicated(
            &c.posterior,
            &settings,
            c.spec.seed,
            multimodal,
            &[],
            f64::NEG_INFINITY,
            &Control::default(),
        )
        .ok()
        .map(|e| (e.log_evidence, e.log_evidence_se))
    };
    let (n1, n2) = rayon::join(|| one(&spec.n1_case), || one(&spec.n2_case));
    let ((z1, s1), (z2, s2)) = (n1?, n2?);
    Some(EvidenceResult {
        log_evidence_n1_beta: z1,
        log_evidence_n1_beta_se: s1,
        log_evidence_n2: z2,
        log_evidence_n2_se: s2,
        log_bayes_factor_n2_vs_n1_beta: z2 - z1,
        tmcmc_samples: settings.samples,
    })
}

/// `nanobeam diagnose` on the data of `spec.diagnose_case` (the same noisy
/// observations the β-inflated calibration saw; base model = the paper's
/// N = 1 beam with the Table-1 geometry): which cause it names and by how much.
pub fn diagnosis_stage(
    spec: &EvidenceSpec,
    cases: &[CaseOutcome],
    rec: &Reconstruction,
    quick: bool,
) -> Result<Option<DiagnosisResult>, ReproduceError> {
    use crate::diagnose::{diagnose, DiagnoseSettings};
    let Some(c) = cases.iter().find(|c| c.spec.id == spec.diagnose_case) else { return Ok(None) };
    let mut beam = rec.table_1.clone();
    beam.diameter_nm = c.spec.inverse_diameter_nm;
    beam.internal_variables = vec![];
    let file = crate::calibration::measured::MeasuredFile {
        beam,
        modes: c.observations.clone(),
        held_out_modes: vec![],
        mode_scans: vec![],
        parameters: None,
        sampler: None,
    };
    let data = crate::calibration::measured::MeasuredData::from_file(file)
        .map_err(|e| ReproduceError::Failure(format!("case 3 as measured data: {e}")))?;
    let settings = DiagnoseSettings {
        seed: Some(c.spec.seed),
        ..if quick { DiagnoseSettings::quick() } else { DiagnoseSettings::default() }
    };
    let d = diagnose(&data, &settings).map_err(|e| ReproduceError::Failure(format!("case 3 diagnosis: {e}")))?;
    let probability = |name: &str| d.candidates.iter().find(|k| k.extension == name).map(|k| k.probability);
    Ok(Some(DiagnosisResult {
        misfit_detected: d.misfit_detected,
        cause: d.cause.clone(),
        log_bayes_factor: d.gain.log_bayes_factor,
        baseline_beta_log_bayes_factor: d.baseline.log_bayes_factor,
        cause_probability: probability(&d.cause),
        rms_z_before: d.gain.rms_z_before,
        rms_z_after: d.gain.rms_z_after,
        candidates: d
            .candidates
            .iter()
            .map(|k| CandidateResult {
                extension: k.extension.clone(),
                log_bayes_factor: k.log_bayes_factor,
                probability: k.probability,
            })
            .collect(),
    }))
}
