//! The typed results of a reproduction: every stage returns one of these
//! structs, and `results.json` is their single serialisation.

use serde::{Serialize, Serializer};

use crate::bayes::summary::ParameterSummary;
use crate::calibration::ModeObservation;
use crate::reproduce::reconstruction::{Fit, Reconstruction};
use crate::reproduce::verdict::Verdict;

/// Rounds to `sig` significant digits.
pub fn round_sig(x: f64, sig: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let e = x.abs().log10().floor() as i32;
    let f = 10f64.powi(sig - 1 - e);
    (x * f).round() / f
}

/// Exact or closed-form numbers (printed references, their intervals, mode
/// frequencies of a fixed beam): 6 significant digits, stable against
/// last-bit differences.
pub fn r6(x: f64) -> f64 {
    round_sig(x, 6)
}

/// Fitted numbers: 5 significant digits. The Nelder–Mead fit stops when the
/// spread of −log L over its simplex is < 1e-12, which resolves a parameter
/// only to ~√(2e-12/curvature): the flattest direction (Ω of the σ-fit) moved
/// by 2.4e-6 relative when the forward model's round-off changed. Five digits
/// (half-step 5e-6 … 5e-5) sit above that and stay ≥ 10× below the σ-level
/// resolution of the fit (0.3 % frequency noise on three modes determines L,
/// the best-resolved parameter since ω ∝ L⁻², only to ≈ 0.1 %).
pub fn r5(x: f64) -> f64 {
    round_sig(x, 5)
}

/// Everything a run computed (`results.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Results {
    pub quick: bool,
    pub reconstruction: ReconstructionResult,
    pub table_2: Vec<Table2Row>,
    pub cases: Vec<CaseResult>,
    pub figure_14: Figure14Result,
    pub case_3_evidence: Option<EvidenceResult>,
    pub case_3_diagnosis: Option<DiagnosisResult>,
    pub replicates: Vec<ReplicateCount>,
    pub audit: Vec<Verdict>,
    pub timings_s: Timings,
    pub provenance: Provenance,
}

/// Wall time per stage, in run order (serialised as an ordered JSON object).
#[derive(Debug, Clone, Default)]
pub struct Timings(pub Vec<(String, f64)>);

impl Serialize for Timings {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Table1 {
    pub length_nm: f64,
    pub diameter_nm: f64,
    pub youngs_modulus_pa: f64,
    pub density_kg_m3: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct FitValueResult {
    pub mode: usize,
    pub quantity: String,
    pub reference: f64,
    pub interval: [f64; 2],
    pub reproduced: f64,
    pub residual_sigma: f64,
    pub within_rounding: bool,
}

#[derive(Debug, Clone, Serialize)]
pub struct FitResult {
    pub parameters: std::collections::BTreeMap<String, f64>,
    pub chi2: f64,
    pub runner_up_chi2: Option<f64>,
    pub weighting: crate::reproduce::reconstruction::Weighting,
    pub all_within_rounding: bool,
    pub values: Vec<FitValueResult>,
}

impl FitResult {
    /// Rounded for a stable snapshot (see [`r5`], [`r6`]).
    pub fn new(f: &Fit) -> Self {
        FitResult {
            parameters: f.parameters.iter().map(|(n, v)| (n.clone(), r5(*v))).collect(),
            chi2: r5(f.chi2),
            runner_up_chi2: f.runner_up_chi2.map(r5),
            weighting: f.weighting,
            all_within_rounding: f.all_within_rounding(),
            values: f
                .values
                .iter()
                .map(|v| FitValueResult {
                    mode: v.mode,
                    quantity: v.quantity.to_string(),
                    reference: r6(v.reference),
                    interval: [r6(v.interval[0]), r6(v.interval[1])],
                    reproduced: r5(v.reproduced),
                    residual_sigma: (v.residual_sigma * 1000.0).round() / 1000.0,
                    within_rounding: v.within_rounding,
                })
                .collect(),
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct ReconstructionResult {
    pub table_1: Table1,
    pub table_4_fit: FitResult,
    pub table_9_fit: FitResult,
    pub table_4_sigma_fit: FitResult,
    pub table_9_sigma_fit: FitResult,
}

impl ReconstructionResult {
    pub fn new(rec: &Reconstruction) -> Self {
        ReconstructionResult {
            table_1: Table1 {
                length_nm: r5(rec.table_1.length_nm),
                diameter_nm: rec.table_1.diameter_nm,
                youngs_modulus_pa: rec.table_1.youngs_modulus_pa,
                density_kg_m3: rec.table_1.density_kg_m3,
            },
            table_4_fit: FitResult::new(&rec.fit_table_4),
            table_9_fit: FitResult::new(&rec.fit_table_9),
            table_4_sigma_fit: FitResult::new(&rec.sigma_fit_table_4),
            table_9_sigma_fit: FitResult::new(&rec.sigma_fit_table_9),
        }
    }
}

#[derive(Debug, Clone, Serialize)]
pub struct Table2Row {
    pub mode: usize,
    pub omega_rad_s: f64,
    pub f_ghz: f64,
}

/// One parameter of a calibration case.
#[derive(Debug, Clone, Serialize)]
pub struct CaseParameter {
    #[serde(flatten)]
    pub summary: ParameterSummary,
    /// The true value (absent where the truth has no counterpart, e.g. β).
    pub exact: Option<f64>,
    /// Monte Carlo standard error of the mean, sd/√ESS_bulk.
    pub mcse_mean: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct CaseResult {
    pub id: String,
    pub title: String,
    /// The spec file and seed that produced it.
    pub spec_file: String,
    pub seed: u64,
    pub parameters: Vec<CaseParameter>,
    pub correlation: Vec<Vec<f64>>,
    pub acceptance: Vec<f64>,
    pub rejected_invalid: u64,
    pub log_posterior_map: f64,
    pub seconds: f64,
    pub observations: Vec<ModeObservation>,
}

#[derive(Debug, Clone, Serialize)]
pub struct Figure14Result {
    pub mode_4_ghz: f64,
    pub coverage_to_mode_4: f64,
    pub draws: usize,
    pub points: usize,
    pub log10_rms_error_to_mode_4_n1: f64,
    pub log10_rms_error_to_mode_4_n2: Option<f64>,
    pub coverage_to_mode_4_n2: Option<f64>,
}

#[derive(Debug, Clone, Serialize)]
pub struct EvidenceResult {
    pub log_evidence_n1_beta: f64,
    pub log_evidence_n1_beta_se: f64,
    pub log_evidence_n2: f64,
    pub log_evidence_n2_se: f64,
    pub log_bayes_factor_n2_vs_n1_beta: f64,
    pub tmcmc_samples: usize,
}

#[derive(Debug, Clone, Serialize)]
pub struct CandidateResult {
    pub extension: String,
    pub log_bayes_factor: f64,
    pub probability: f64,
}

#[derive(Debug, Clone, Serialize)]
pub struct DiagnosisResult {
    pub misfit_detected: bool,
    pub cause: String,
    pub log_bayes_factor: f64,
    pub baseline_beta_log_bayes_factor: f64,
    pub cause_probability: Option<f64>,
    pub rms_z_before: f64,
    pub rms_z_after: f64,
    pub candidates: Vec<CandidateResult>,
}

/// How many noise replicates of a case were fitted, and the Laplace-relative
/// shape of its DRAM posterior they use.
#[derive(Debug, Clone, Serialize)]
pub struct ReplicateCount {
    pub case: String,
    pub replicates: usize,
    pub failed: usize,
    pub shape: crate::reproduce::replicates::Shape,
}

/// Where the numbers came from.
#[derive(Debug, Clone, Serialize)]
pub struct Provenance {
    pub nanobeam_version: String,
    /// `git rev-parse HEAD` of the repository root, when git is available.
    pub git_commit: Option<String>,
    /// Whether the work tree had uncommitted changes (`git status --porcelain`).
    pub git_dirty: Option<bool>,
    /// SHA-256 of every input file, relative path → hex digest.
    pub inputs_sha256: Vec<(String, String)>,
    pub command_line: String,
}
