//! The seeded YAML specs of `paper/specs/`, the only inputs of `reproduce`
//! besides `paper/published.yaml`. Every spec requires `seed` and rejects
//! unknown fields; errors name the file and the field.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::beam::Support;
use crate::calibration::{DramSettings, ParameterSet};
use crate::error::{positive, InputError};

/// A spec that failed to load: file + field.
#[derive(Debug, Clone)]
pub struct SpecError {
    pub file: PathBuf,
    pub error: InputError,
}

impl std::fmt::Display for SpecError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.file.display(), self.error)
    }
}

impl std::error::Error for SpecError {}

/// The fixed beam assumptions and search ranges of the reconstruction.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReconstructionSpec {
    pub seed: u64,
    /// Standard SWCNT constants held fixed (only EI/(ρA L⁴) and e0a/L are identifiable).
    pub diameter_nm: f64,
    pub youngs_modulus_pa: f64,
    pub density_kg_m3: f64,
    pub support: Support,
    pub elements: usize,
    /// Search priors (uniform) of the Table 1/4 fit: length_nm, nonlocal_e0a_nm, delta, omega_rad_s.
    pub table_1_4_parameters: serde_yaml::Mapping,
    /// Search priors of the Table 9 (N̄ = 2) fit, with the Table 1 beam.
    pub table_9_parameters: serde_yaml::Mapping,
    pub multistart_points: usize,
}

/// Table 2 and Figures 1–3.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForwardSpec {
    pub seed: u64,
    /// Modes tabulated and mapped (paper: 3).
    pub modes: usize,
    /// Δ of the parametric maps (Table 3 is lost: the reconstructed Table 4 Δ is used when `null`).
    #[serde(default)]
    pub delta: Option<f64>,
    pub e0a_nm: Axis,
    pub omega_rad_s: Axis,
}

/// A grid axis (log-spaced when `log`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    pub from: f64,
    pub to: f64,
    pub points: usize,
    pub quick_points: usize,
    #[serde(default)]
    pub log: bool,
}

impl Axis {
    pub fn values(&self, quick: bool) -> Vec<f64> {
        let n = if quick { self.quick_points } else { self.points };
        let (a, b) = if self.log { (self.from.ln(), self.to.ln()) } else { (self.from, self.to) };
        (0..n)
            .map(|i| {
                let v = a + (b - a) * i as f64 / (n - 1) as f64;
                if self.log {
                    v.exp()
                } else {
                    v
                }
            })
            .collect()
    }

    fn validate(&self, field: &str) -> Result<(), InputError> {
        if !(self.from.is_finite() && self.to.is_finite() && self.to > self.from && self.from >= 0.0) {
            return Err(InputError::new(
                format!("{field}.to"),
                self.to,
                format!("finite, > from = {} >= 0", self.from),
            ));
        }
        if self.log {
            positive(&format!("{field}.from"), self.from)?;
        }
        for (n, v) in [("points", self.points), ("quick_points", self.quick_points)] {
            if !(2..=400).contains(&v) {
                return Err(InputError::new(format!("{field}.{n}"), v, "2..=400"));
            }
        }
        Ok(())
    }
}

/// Which reconstructed truth generates a case's synthetic data.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Truth {
    /// Table 1 + Table 4 (N = 1), reference values Table 5.
    Table4,
    /// Table 1 + Table 9 (N̄ = 2), reference values Table 10.
    Table9,
}

/// One calibration case (1A–1C, 2A–2C, 3).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseSpec {
    /// The file it was loaded from (set by [`Specs::load`]).
    #[serde(skip)]
    pub file: PathBuf,
    pub seed: u64,
    pub id: String,
    pub title: String,
    pub truth: Truth,
    /// Covariance set of published.yaml whose σ's are the noise (eq. 37–38).
    pub covariance_set: String,
    /// Nominal diameter d0 of the inverse model, nm.
    pub inverse_diameter_nm: f64,
    /// Parameters and priors (the measured-data file's format).
    pub parameters: serde_yaml::Mapping,
    /// Internal variables of the inverse model's base beam: the start of every
    /// parameter the set does not calibrate, and of those it does before the
    /// multi-start (§4.2: Δ = 0.5, Ω = 1e12 rad/s).
    pub inverse_internal_variables: Vec<crate::beam::InternalVariable>,
    pub sampler: DramSettings,
    pub quick_sampler: DramSettings,
}

/// Figure 14: FRF of the Case-3 reference vs the calibrated N = 1 model.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrfSpec {
    pub seed: u64,
    /// The calibration case whose posterior is propagated.
    pub case: String,
    /// Excitation and response positions as fractions of L (the paper's "0.45 nm" and "0.85 nm").
    pub input_x_fraction: f64,
    pub output_x_fraction: f64,
    pub from_ghz: f64,
    pub to_ghz: f64,
    pub points: usize,
    pub quick_points: usize,
    /// Posterior draws propagated (the envelope is their 0.5–99.5 % band).
    pub posterior_draws: usize,
    pub quick_posterior_draws: usize,
}

/// The audit's noise replicates (`audit.yaml`). The noise of replicate r of a
/// case is keyed by that case's own seed, `stream(case.seed, MeasurementNoise,
/// [0, r])`, so this spec carries no seed of its own.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AuditSpec {
    /// Noise replicates per case in the full run (issue 14: ≥ 100).
    pub replicates: usize,
    /// Noise replicates per case in `--quick`.
    pub quick_replicates: usize,
}

/// One table of calibration cases and its figures (`tables.yaml`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseTable {
    /// File stem, e.g. `table-7`.
    pub table: String,
    /// Case ids, in row order.
    pub cases: Vec<String>,
    /// Trace (`<figure>a`) and marginal (`<figure>b`) figures of one parameter across the cases.
    #[serde(default)]
    pub parameter_figures: Vec<ParameterFigure>,
    /// File stem of the pair plots (one per case, suffixed by the case id when there are several).
    pub pair_figure: String,
    /// What the report says above the table.
    pub caption: String,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParameterFigure {
    pub figure: String,
    pub parameter: String,
}

/// The paper's grouping of cases into tables (`tables.yaml`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TablesSpec {
    pub tables: Vec<CaseTable>,
}

/// Case-3 evidence and diagnosis (`evidence.yaml`). The TMCMC runs are keyed
/// by the seeds of the cases they evaluate.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EvidenceSpec {
    /// The paper's β-inflated N = 1 case.
    pub n1_case: String,
    /// The N = 2 case on the same data.
    pub n2_case: String,
    /// TMCMC samples per stage (full, quick).
    pub tmcmc_samples: usize,
    pub quick_tmcmc_samples: usize,
    /// MH steps per TMCMC stage and MAP iterations of the evidence estimator
    /// (`bayes::evidence::EvidenceSettings`).
    pub mh_steps: usize,
    pub map_iters: u64,
    /// Case whose data `diagnose` examines.
    pub diagnose_case: String,
}

/// Every spec, loaded and validated.
#[derive(Debug, Clone)]
pub struct Specs {
    pub reconstruction: ReconstructionSpec,
    pub forward: ForwardSpec,
    pub cases: Vec<CaseSpec>,
    pub frf: FrfSpec,
    pub audit: AuditSpec,
    pub tables: TablesSpec,
    pub evidence: EvidenceSpec,
    /// Every file read, in load order (for the provenance block).
    pub files: Vec<PathBuf>,
}

fn load<T: serde::de::DeserializeOwned>(path: &Path) -> Result<T, SpecError> {
    let wrap = |error: InputError| SpecError { file: path.to_path_buf(), error };
    let text = std::fs::read_to_string(path)
        .map_err(|e| wrap(InputError::new("<file>", path.display(), format!("a readable file ({e})"))))?;
    crate::error::parse_yaml(&text).map_err(wrap)
}

impl Specs {
    /// Loads `dir/{reconstruction,forward,figure-14,case-*,audit,tables,evidence}.yaml` and validates all.
    pub fn load(dir: &Path) -> Result<Self, SpecError> {
        let reconstruction: ReconstructionSpec = load(&dir.join("reconstruction.yaml"))?;
        let forward: ForwardSpec = load(&dir.join("forward.yaml"))?;
        let frf: FrfSpec = load(&dir.join("figure-14.yaml"))?;
        let mut case_files: Vec<PathBuf> = std::fs::read_dir(dir)
            .map_err(|e| SpecError {
                file: dir.to_path_buf(),
                error: InputError::new("<dir>", dir.display(), e.to_string()),
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.file_name().and_then(|n| n.to_str()).is_some_and(|n| n.starts_with("case-") && n.ends_with(".yaml"))
            })
            .collect();
        case_files.sort();
        let mut cases = Vec::new();
        for f in &case_files {
            let mut c: CaseSpec = load(f)?;
            c.file = f.clone();
            c.validate().map_err(|error| SpecError { file: f.clone(), error })?;
            cases.push(c);
        }
        let file = |n: &str| dir.join(n);
        reconstruction.validate().map_err(|error| SpecError { file: file("reconstruction.yaml"), error })?;
        forward.validate().map_err(|error| SpecError { file: file("forward.yaml"), error })?;
        frf.validate(&cases).map_err(|error| SpecError { file: file("figure-14.yaml"), error })?;
        let audit: AuditSpec = load(&file("audit.yaml"))?;
        audit.validate().map_err(|error| SpecError { file: file("audit.yaml"), error })?;
        let tables: TablesSpec = load(&file("tables.yaml"))?;
        tables.validate(&cases).map_err(|error| SpecError { file: file("tables.yaml"), error })?;
        let evidence: EvidenceSpec = load(&file("evidence.yaml"))?;
        evidence.validate(&cases).map_err(|error| SpecError { file: file("evidence.yaml"), error })?;
        let mut files: Vec<PathBuf> =
            ["reconstruction.yaml", "forward.yaml", "figure-14.yaml"].iter().map(|n| file(n)).collect();
        files.extend(case_files);
        files.extend(["audit.yaml", "tables.yaml", "evidence.yaml"].iter().map(|n| file(n)));
        Ok(Specs { reconstruction, forward, cases, frf, audit, tables, evidence, files })
    }
}

impl ReconstructionSpec {
    fn validate(&self) -> Result<(), InputError> {
        positive("diameter_nm", self.diameter_nm)?;
        positive("youngs_modulus_pa", self.youngs_modulus_pa)?;
        positive("density_kg_m3", self.density_kg_m3)?;
        if self.elements == 0 {
            return Err(InputError::new("elements", 0, ">= 1"));
        }
        ParameterSet::from_mapping(&self.table_1_4_parameters).map_err(|e| e.within("table_1_4_parameters"))?;
        ParameterSet::from_mapping(&self.table_9_parameters).map_err(|e| e.within("table_9_parameters"))?;
        if self.multistart_points == 0 {
            return Err(InputError::new("multistart_points", 0, ">= 1"));
        }
        Ok(())
    }
}

impl ForwardSpec {
    fn validate(&self) -> Result<(), InputError> {
        if !(1..=10).contains(&self.modes) {
            return Err(InputError::new("modes", self.modes, "1..=10"));
        }
        if let Some(d) = self.delta {
            crate::error::non_negative("delta", d)?;
        }
        self.e0a_nm.validate("e0a_nm")?;
        self.omega_rad_s.validate("omega_rad_s")
    }
}

impl CaseSpec {
    fn validate(&self) -> Result<(), InputError> {
        positive("inverse_diameter_nm", self.inverse_diameter_nm)?;
        for (i, v) in self.inverse_internal_variables.iter().enumerate() {
            crate::error::non_negative(&format!("inverse_internal_variables[{i}].delta"), v.delta)?;
            positive(&format!("inverse_internal_variables[{i}].omega_rad_s"), v.omega_rad_s)?;
        }
        let params = ParameterSet::from_mapping(&self.parameters)?;
        for p in &params.params {
            crate::calibration::parameters::check_physical(&p.prior, &format!("parameters.{}", p.name))?;
        }
        self.sampler.validate(params.len()).map_err(|e| rename(e, "sampler"))?;
        self.quick_sampler.validate(params.len()).map_err(|e| rename(e, "quick_sampler"))
    }
}

fn rename(mut e: InputError, section: &str) -> InputError {
    e.field = e.field.replacen("sampler", section, 1);
    e
}

impl FrfSpec {
    fn validate(&self, cases: &[CaseSpec]) -> Result<(), InputError> {
        if !cases.iter().any(|c| c.id == self.case) {
            return Err(InputError::new("case", &self.case, "the id of a case-*.yaml spec"));
        }
        for (n, x) in [("input_x_fraction", self.input_x_fraction), ("output_x_fraction", self.output_x_fraction)] {
            if !(x.is_finite() && (0.0..=1.0).contains(&x)) {
                return Err(InputError::new(n, x, "0..=1 (fraction of the length)"));
            }
        }
        positive("from_ghz", self.from_ghz)?;
        if self.to_ghz.partial_cmp(&self.from_ghz) != Some(std::cmp::Ordering::Greater) {
            return Err(InputError::new("to_ghz", self.to_ghz, format!("> from_ghz = {}", self.from_ghz)));
        }
        if self.points < 2 || self.quick_points < 2 || self.posterior_draws == 0 || self.quick_posterior_draws == 0 {
            return Err(InputError::new("points", self.points, ">= 2 (and draws >= 1)"));
        }
        Ok(())
    }
}

fn known_case(cases: &[CaseSpec], field: &str, id: &str) -> Result<(), InputError> {
    if cases.iter().any(|c| c.id == id) {
        Ok(())
    } else {
        Err(InputError::new(field, id, "the id of a case-*.yaml spec"))
    }
}

impl AuditSpec {
    fn validate(&self) -> Result<(), InputError> {
        if !(100..=100_000).contains(&self.replicates) {
            return Err(InputError::new("replicates", self.replicates, "100..=100000 (issue 14: R >= 100)"));
        }
        if !(10..=self.replicates).contains(&self.quick_replicates) {
            return Err(InputError::new(
                "quick_replicates",
                self.quick_replicates,
                format!("10..={} (at most replicates)", self.replicates),
            ));
        }
        Ok(())
    }
}

impl TablesSpec {
    fn validate(&self, cases: &[CaseSpec]) -> Result<(), InputError> {
        for (i, t) in self.tables.iter().enumerate() {
            if t.cases.is_empty() {
                return Err(InputError::new(format!("tables[{i}].cases"), "[]", "at least one case id"));
            }
            for (j, id) in t.cases.iter().enumerate() {
                known_case(cases, &format!("tables[{i}].cases[{j}]"), id)?;
            }
        }
        Ok(())
    }
}

impl EvidenceSpec {
    /// The evidence estimator's settings of a full or `quick` run.
    pub fn settings(&self, quick: bool) -> crate::bayes::evidence::EvidenceSettings {
        crate::bayes::evidence::EvidenceSettings {
            samples: if quick { self.quick_tmcmc_samples } else { self.tmcmc_samples },
            mh_steps: self.mh_steps,
            map_iters: self.map_iters,
        }
    }

    fn validate(&self, cases: &[CaseSpec]) -> Result<(), InputError> {
        known_case(cases, "n1_case", &self.n1_case)?;
        known_case(cases, "n2_case", &self.n2_case)?;
        known_case(cases, "diagnose_case", &self.diagnose_case)?;
        for (n, v) in [("tmcmc_samples", self.tmcmc_samples), ("quick_tmcmc_samples", self.quick_tmcmc_samples)] {
            if !(50..=100_000).contains(&v) {
                return Err(InputError::new(n, v, "50..=100000"));
            }
        }
        self.settings(false).validate()
    }
}
