//! The measured-data file: the input of `nanobeam calibrate` and `nanobeam diagnose`.
//!
//! ```yaml
//! beam: { ...BeamSpec: the nominal, known part... }
//! modes:                 # any number >= 1, mode numbers 1-based
//!   - { mode: 1, omega_rad_s: 8.38e11, omega_sd_rad_s: 2.5e9, zeta: 0.0712, zeta_sd: 0.0021 }
//! held_out_modes: []     # optional, same format, never used for fitting
//! mode_scans:            # optional: deflection scans at a mode's resonance (fitted)
//!   - mode: 2
//!     drive_x_nm: 7.8
//!     points:            # >= 2 readout points, 0 < x_nm < length_nm, ascending
//!       - { x_nm: 0.4, relative_amplitude: 0.3129, relative_amplitude_sd: 0.002 }
//!       - { x_nm: 2.0, relative_amplitude: 1.0, relative_amplitude_sd: 0.002 }
//! parameters: { ... }    # optional; default = the paper's N = 1 set
//! sampler: { ... }       # optional; default = the paper's §4.2 settings, 4 chains, fixed seed
//! ```

use serde::{Deserialize, Serialize};

use crate::bayes::dram::DramSettings;
use crate::beam::spec::{RAW_MAX, RAW_MIN};
use crate::beam::{self, BeamSpec};
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

/// A scan of the readout point along the beam while a point force at
/// `drive_x_nm` drives mode `mode` at its resonance: at each point the
/// deflection amplitude |H(ω_n; drive, x)| relative to the largest among the
/// scan's points (dimensionless; a noisy reading may exceed 1). This is what
/// `diagnose` suggests when no ω or ζ separates two explanations
/// (`shape_measurement`, a scan of its grid). The model value at θ is the
/// same ratio computed at the model's own ω_n
/// ([`crate::calibration::posterior::relative_amplitudes`]); the readings
/// are taken as independent Gaussians with the listed sds. Normalising by
/// the largest point correlates the readings a little (the largest one is 1
/// by construction); at sds far below the amplitudes that is second order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModeScan {
    /// 1-based mode number whose resonance the scan is taken at.
    pub mode: usize,
    pub drive_x_nm: f64,
    pub points: Vec<ScanPoint>,
}

/// One readout point of a [`ModeScan`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScanPoint {
    pub x_nm: f64,
    pub relative_amplitude: f64,
    pub relative_amplitude_sd: f64,
}

/// Largest relative amplitude a reading may have: the ratio to the largest
/// listed reading is ≤ 1 without noise; a generous bound for noisy readings
/// that still rejects a column of raw amplitudes in m/N.
pub const MAX_RELATIVE_AMPLITUDE: f64 = 2.0;

/// The file as written.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasuredFile {
    pub beam: BeamSpec,
    pub modes: Vec<ModeObservation>,
    #[serde(default)]
    pub held_out_modes: Vec<ModeObservation>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub mode_scans: Vec<ModeScan>,
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
    /// Fitted beside `modes` ([`ModeScan`]).
    pub mode_scans: Vec<ModeScan>,
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
        validate_order(&file.modes, &file.held_out_modes)?;
        validate_scans(&file.mode_scans, &file.modes, &file.beam)?;
        let parameters = match &file.parameters {
            Some(map) => ParameterSet::from_mapping(map)?,
            None => ParameterSet::paper_n1(),
        };
        parameters.check_against_beam(&file.beam)?;
        let sampler = file.sampler.clone().unwrap_or_default();
        sampler.validate(parameters.len())?;
        Ok(Self {
            beam: file.beam,
            modes: file.modes,
            held_out_modes: file.held_out_modes,
            mode_scans: file.mode_scans,
            parameters,
            sampler,
        })
    }

    /// Highest mode number among fitted and held-out modes (a scan's mode is a fitted one).
    pub fn max_mode(&self) -> usize {
        self.modes.iter().chain(&self.held_out_modes).map(|m| m.mode).max().unwrap_or(1)
    }

    /// Every fitted observable in the likelihood's order: the modes' ω and
    /// ζ (eq. 36), then each scan's points.
    pub fn fitted_observables(&self) -> Vec<Observable> {
        let mut obs = observables(&self.modes);
        obs.extend(scan_observables(&self.mode_scans));
        obs
    }
}

/// Scans need a fitted mode (the scan is taken at its resonance, and the
/// likelihood reads its ω from the fast modal path), a drive point and at
/// least two readout points inside the beam, ascending (one point is 1 by
/// definition, so not all are 0), with readings in
/// 0..=[`MAX_RELATIVE_AMPLITUDE`] and sds in RAW_MIN..=1; one scan per mode.
/// "Inside" is 0 < x < L, and x = L too on a cantilever (its free end moves,
/// while a force at a supported end moves nothing); at most 4 readout points
/// per element.
fn validate_scans(scans: &[ModeScan], modes: &[ModeObservation], beam: &BeamSpec) -> Result<(), InputError> {
    let length_nm = beam.length_nm;
    // a cantilever's end x = L is free: it moves, so it may be driven and read
    let free_end = beam.support == crate::beam::Support::ClampedFree;
    let inside = |x: f64| x.is_finite() && x > 0.0 && (x < length_nm || (free_end && x == length_nm));
    let upper = if free_end {
        format!("x <= length_nm = {length_nm} (free end)")
    } else {
        format!("x < length_nm = {length_nm}")
    };
    let max_points = max_scan_points(beam);
    let mut seen = std::collections::BTreeSet::new();
    for (i, s) in scans.iter().enumerate() {
        let f = |name: &str| format!("mode_scans[{i}].{name}");
        if !modes.iter().any(|m| m.mode == s.mode) {
            let listed: Vec<String> = modes.iter().map(|m| m.mode.to_string()).collect();
            return Err(InputError::new(
                f("mode"),
                s.mode,
                format!("a mode listed in `modes` ({})", listed.join(", ")),
            ));
        }
        if !seen.insert(s.mode) {
            return Err(InputError::new(f("mode"), s.mode, "one scan per mode"));
        }
        // not at a supported end: a force there moves nothing
        if !inside(s.drive_x_nm) {
            return Err(InputError::new(f("drive_x_nm"), fmt_num(s.drive_x_nm), format!("0 < {upper}")));
        }
        if s.points.len() > max_points {
            return Err(InputError::new(
                f("points"),
                format!("{} points", s.points.len()),
                format!(
                    "at most {max_points} (4 per element of the beam's {} elements: its deflection is one cubic per element, which 4 readings fix; more only average noise, which the sds state)",
                    beam.elements
                ),
            ));
        }
        if s.points.len() < 2 {
            return Err(InputError::new(
                f("points"),
                format!("{} point(s)", s.points.len()),
                "at least 2 (amplitudes are relative to the largest)",
            ));
        }
        let mut last = 0.0;
        for (k, p) in s.points.iter().enumerate() {
            let g = |name: &str| format!("mode_scans[{i}].points[{k}].{name}");
            if !(inside(p.x_nm) && p.x_nm > last) {
                return Err(InputError::new(
                    g("x_nm"),
                    fmt_num(p.x_nm),
                    format!("{} < {upper} (ascending, inside the beam)", fmt_num(last)),
                ));
            }
            last = p.x_nm;
            if !(p.relative_amplitude.is_finite() && (0.0..=MAX_RELATIVE_AMPLITUDE).contains(&p.relative_amplitude)) {
                return Err(InputError::new(
                    g("relative_amplitude"),
                    fmt_num(p.relative_amplitude),
                    format!("0 <= relative_amplitude <= {MAX_RELATIVE_AMPLITUDE} (relative to the scan's largest)"),
                ));
            }
            if !(p.relative_amplitude_sd.is_finite() && (RAW_MIN..=1.0).contains(&p.relative_amplitude_sd)) {
                return Err(InputError::new(
                    g("relative_amplitude_sd"),
                    fmt_num(p.relative_amplitude_sd),
                    format!("{RAW_MIN:e} <= relative_amplitude_sd <= 1"),
                ));
            }
        }
        if s.points.iter().all(|p| p.relative_amplitude == 0.0) {
            return Err(InputError::new(
                f("points"),
                "every relative_amplitude 0",
                "a scan with a nonzero reading (amplitudes are relative to the largest, which is 1)",
            ));
        }
    }
    Ok(())
}

/// Most readout points of one scan: 4 per element (see `validate_scans`).
fn max_scan_points(beam: &BeamSpec) -> usize {
    4 * beam.elements
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

/// Physical modes are numbered by |s| (eq. 34), and a beam's flexural
/// eigenvalues in one plane are simple (a Sturm–Liouville problem), so over
/// the fitted and held-out modes together ω must rise strictly with the mode
/// number: a table where it falls or repeats is misnumbered or mistyped. The
/// later mode of the first pair out of order is named.
fn validate_order(modes: &[ModeObservation], held_out: &[ModeObservation]) -> Result<(), InputError> {
    let mut all: Vec<(usize, String, f64)> = modes
        .iter()
        .enumerate()
        .map(|(i, m)| (m.mode, format!("modes[{i}].omega_rad_s"), m.omega_rad_s))
        .chain(
            held_out
                .iter()
                .enumerate()
                .map(|(i, m)| (m.mode, format!("held_out_modes[{i}].omega_rad_s"), m.omega_rad_s)),
        )
        .collect();
    all.sort_by_key(|m| m.0);
    for w in all.windows(2) {
        let ((lower, _, w_lower), (mode, field, omega)) = (&w[0], &w[1]);
        if omega <= w_lower {
            return Err(InputError::new(
                field.clone(),
                fmt_num(*omega),
                format!(
                    "> {} (mode {lower}'s omega_rad_s): modes are numbered by frequency, so mode {mode} lies above mode {lower}",
                    fmt_num(*w_lower)
                ),
            ));
        }
    }
    Ok(())
}

/// Which modal quantity an observable is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    Omega,
    Zeta,
    /// A mode scan's relative amplitude at one point ([`ModeScan`]).
    RelativeAmplitude,
}

impl Quantity {
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Omega => "omega",
            Quantity::Zeta => "zeta",
            Quantity::RelativeAmplitude => "relative_amplitude",
        }
    }
}

/// One scalar entry of y (eq. 36): mode `mode`'s ω (rad/s) or ζ, or a scan's
/// relative amplitude at `x_nm`, with its measurement sd in the same unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observable {
    pub mode: usize,
    pub quantity: Quantity,
    /// The readout point of a relative amplitude (`None` for ω and ζ).
    pub x_nm: Option<f64>,
    pub value: f64,
    pub sd: f64,
}

impl Observable {
    /// This observable's model value among `modes` (1-based numbering), if
    /// computed; `None` for a relative amplitude too, which needs its whole
    /// scan ([`relative_amplitudes`](crate::calibration::posterior::relative_amplitudes)).
    pub fn predicted(&self, modes: &[beam::Mode]) -> Option<f64> {
        let m = modes.get(self.mode.checked_sub(1)?)?;
        match self.quantity {
            Quantity::Omega => Some(m.omega_rad_s),
            Quantity::Zeta => Some(m.zeta),
            Quantity::RelativeAmplitude => None,
        }
    }
}

/// The observables of `scans`' points, scan by scan, in the file's order.
pub fn scan_observables(scans: &[ModeScan]) -> Vec<Observable> {
    scans
        .iter()
        .flat_map(|s| {
            s.points.iter().map(|p| Observable {
                mode: s.mode,
                quantity: Quantity::RelativeAmplitude,
                x_nm: Some(p.x_nm),
                value: p.relative_amplitude,
                sd: p.relative_amplitude_sd,
            })
        })
        .collect()
}

/// The observables of a list of modes stacked as in eq. (36): every ω, then every ζ.
pub fn observables(obs: &[ModeObservation]) -> Vec<Observable> {
    let omega = obs.iter().map(|m| Observable {
        mode: m.mode,
        quantity: Quantity::Omega,
        x_nm: None,
        value: m.omega_rad_s,
        sd: m.omega_sd_rad_s,
    });
    let zeta = obs.iter().map(|m| Observable {
        mode: m.mode,
        quantity: Quantity::Zeta,
        x_nm: None,
        value: m.zeta,
        sd: m.zeta_sd,
    });
    omega.chain(zeta).collect()
}
