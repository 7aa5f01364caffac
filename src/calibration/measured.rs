//! The measured-data file: the input of `nanobeam calibrate` and `nanobeam diagnose`.
//!
//! ```yaml
//! beam: { ...BeamSpec: the nominal, known part... }
//! modes:                 # any number >= 1, mode numbers 1-based
//!   - { mode: 1, omega_rad_s: 8.38e11, omega_sd_rad_s: 2.5e9, zeta: 0.0712, zeta_sd: 0.0021 }
//! held_out_modes: []     # optional, same format, never used for fitting
//! parameters: { ... }    # optional; default = the paper's N = 1 set
//! sampler: { ... }       # optional; default = the paper's §4.2 settings, 4 chains, fixed seed
//! ```

use serde::{Deserialize, Serialize};

use crate::bayes::dram::DramSettings;
use crate::beam::spec::{RAW_MAX, RAW_MIN};
use crate::beam::BeamSpec;
use crate::calibration::parameters::ParameterSet;
use crate::error::{fmt_num, InputError};

/// One measured mode: natural frequency and damping ratio with their
/// measurement standard deviations (the diagonal of Σεε, eq. 38).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModeObservation {
    /// 1-based mode number (modes sorted by |s|, eq. 34).
    pub mode: usize,
    pub omega_rad_s: f64,
    pub omega_sd_rad_s: f64,
    pub zeta: f64,
    pub zeta_sd: f64,
}

/// The file as written.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasuredFile {
    pub beam: BeamSpec,
    pub modes: Vec<ModeObservation>,
    #[serde(default)]
    pub held_out_modes: Vec<ModeObservation>,
    #[serde(default)]
    pub parameters: Option<serde_yaml::Mapping>,
    #[serde(default)]
    pub sampler: Option<DramSettings>,
}

/// A validated measured-data file, with the parameter set resolved.
#[derive(Debug, Clone)]
pub struct MeasuredData {
    pub beam: BeamSpec,
    pub modes: Vec<ModeObservation>,
    pub held_out_modes: Vec<ModeObservation>,
    pub parameters: ParameterSet,
    pub sampler: DramSettings,
}

impl MeasuredData {
    /// Parses and validates a measured-data file (unknown fields rejected).
    pub fn from_yaml(text: &str) -> Result<Self, InputError> {
        let file: MeasuredFile = crate::error::parse_yaml(text)?;
        Self::from_file(file)
    }

    pub fn from_file(file: MeasuredFile) -> Result<Self, InputError> {
        file.beam.validate().map_err(|e| e.within("beam"))?;
        if file.modes.is_empty() {
            return Err(InputError::new("modes", "[]", "at least one mode"));
        }
        let dofs = file.beam.free_dofs();
        validate_modes("modes", &file.modes, dofs)?;
        validate_modes("held_out_modes", &file.held_out_modes, dofs)?;
        for (i, h) in file.held_out_modes.iter().enumerate() {
            if file.modes.iter().any(|m| m.mode == h.mode) {
                return Err(InputError::new(
                    format!("held_out_modes[{i}].mode"),
                    h.mode,
                    "a mode not already listed in `modes`",
                ));
            }
        }
        let parameters = match &file.parameters {
            Some(map) => ParameterSet::from_mapping(map)?,
            None => ParameterSet::paper_n1(),
        };
        parameters.check_against_beam(&file.beam)?;
        let sampler = file.sampler.clone().unwrap_or_default();
        sampler.validate(parameters.len())?;
        Ok(Self { beam: file.beam, modes: file.modes, held_out_modes: file.held_out_modes, parameters, sampler })
    }

    /// Highest mode number among fitted and held-out modes.
    pub fn max_mode(&self) -> usize {
        self.modes.iter().chain(&self.held_out_modes).map(|m| m.mode).max().unwrap_or(1)
    }
}

/// Mode numbers 1..=dofs (the beam model has as many physical modes as free
/// DOFs), each listed once (across the list), positive sds and finite values.
fn validate_modes(field: &str, modes: &[ModeObservation], dofs: usize) -> Result<(), InputError> {
    let mut seen = std::collections::BTreeSet::new();
    for (i, m) in modes.iter().enumerate() {
        let f = |name: &str| format!("{field}[{i}].{name}");
        if m.mode == 0 || m.mode > dofs {
            return Err(InputError::new(
                f("mode"),
                m.mode,
                format!("1..={dofs} (1-based physical modes; the beam's mesh has {dofs} free DOFs)"),
            ));
        }
        if !seen.insert(m.mode) {
            return Err(InputError::new(f("mode"), m.mode, "each mode listed once"));
        }
        // the window of every dimensional input (beam::spec::RAW_MIN..=RAW_MAX):
        // residuals (ω − ω_model)/sd then stay within 1e60, their squares normal
        for (name, v) in [("omega_rad_s", m.omega_rad_s), ("omega_sd_rad_s", m.omega_sd_rad_s)] {
            if !(v.is_finite() && (RAW_MIN..=RAW_MAX).contains(&v)) {
                return Err(InputError::new(f(name), fmt_num(v), format!("{RAW_MIN:e} <= x <= {RAW_MAX:e}")));
            }
        }
        if !(m.zeta.is_finite() && m.zeta > 0.0 && m.zeta < 1.0) {
            return Err(InputError::new(f("zeta"), fmt_num(m.zeta), "0 < zeta < 1 (underdamped mode)"));
        }
        if !(m.zeta_sd.is_finite() && (RAW_MIN..=1.0).contains(&m.zeta_sd)) {
            return Err(InputError::new(f("zeta_sd"), fmt_num(m.zeta_sd), format!("{RAW_MIN:e} <= zeta_sd <= 1")));
        }
    }
    Ok(())
}
