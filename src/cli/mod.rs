//! The `nanobeam` command line: argument definitions and command bodies.
//! `main.rs` only parses and dispatches. Exit codes: 0 ok, 1 numerical
//! failure, 2 bad input (one line on stderr naming field, value and range).

pub mod calibrate;
pub mod campaign;
pub mod clap_error;
pub mod diagnose;
pub mod frf;
pub mod identify;
pub mod modal;
pub mod progress;

use std::path::Path;

use clap::{Parser, Subcommand};

use crate::bayes::BayesError;
use crate::beam::{BeamError, BeamSpec};
use crate::calibration::SamplingError;
use crate::diagnose::DiagnoseError;
use crate::error::InputError;
use crate::report::ReportError;

#[derive(Debug, Parser)]
#[command(
    name = "nanobeam",
    version,
    about = "Nonlocal viscoelastic Euler-Bernoulli nanobeams: forward model and calibration"
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// Every subcommand takes a value that starts with `-` as a (negative)
/// number (`--input-x-nm -0.0`, `--samples -1`), so the value is checked
/// and named with its flag instead of being taken for an unknown argument.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Natural frequencies and damping ratios (eqs. 34-35) of a beam.
    #[command(allow_negative_numbers = true)]
    Modal(modal::ModalArgs),
    /// Receptance between a point force and a point displacement.
    #[command(allow_negative_numbers = true)]
    Frf(frf::FrfArgs),
    /// Bayesian calibration (DRAM) against measured modal data.
    #[command(allow_negative_numbers = true)]
    Calibrate(calibrate::CalibrateArgs),
    /// Model diagnosis: misfit checks, candidate causes by evidence, gain.
    #[command(allow_negative_numbers = true)]
    Diagnose(diagnose::DiagnoseArgs),
    /// Modal identification of a measured sweep, spectrum or ring-down -> measured-data file.
    #[command(allow_negative_numbers = true)]
    Identify(identify::IdentifyArgs),
    /// Many records (a manifest CSV or a folder) through identify and diagnose -> one table (CSV).
    #[command(allow_negative_numbers = true)]
    Campaign(campaign::CampaignArgs),
}

/// A command failure. Every layer's error converts into it, and
/// [`CliError::exit_code`] is the one place where exit codes are decided:
/// 2 for bad input (the user can fix the file or flag), 1 for a numerical or
/// output failure on valid input.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Exit 2: one line naming the field, the value and the allowed range.
    #[error("{0}")]
    Input(#[from] InputError),
    /// Exit 1: the computation or the output failed.
    #[error("error: {0}")]
    Failure(String),
}

impl CliError {
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Input(_) => 2,
            CliError::Failure(_) => 1,
        }
    }
}

impl From<BeamError> for CliError {
    fn from(e: BeamError) -> Self {
        match e {
            BeamError::Input(i) => CliError::Input(i),
            BeamError::Numerical(m) => CliError::Failure(format!("numerical failure: {m}")),
        }
    }
}

impl From<DiagnoseError> for CliError {
    fn from(e: DiagnoseError) -> Self {
        match e {
            DiagnoseError::Input(i) => CliError::Input(i),
            DiagnoseError::Evidence { source: BayesError::Config(i), .. } => CliError::Input(i),
            other => CliError::Failure(other.to_string()),
        }
    }
}

impl From<SamplingError> for CliError {
    fn from(e: SamplingError) -> Self {
        match e {
            SamplingError::Settings(i) => CliError::Input(i),
            other => CliError::Failure(other.to_string()),
        }
    }
}

impl From<ReportError> for CliError {
    fn from(e: ReportError) -> Self {
        CliError::Failure(format!("cannot write output: {e}"))
    }
}

/// Runs one parsed command, writing its output to `out`.
pub fn run(cli: Cli, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    match cli.command {
        Command::Modal(args) => modal::run(&args, out),
        Command::Frf(args) => frf::run(&args, out),
        Command::Calibrate(args) => calibrate::run(&args, out),
        Command::Diagnose(args) => diagnose::run(&args, out),
        Command::Identify(args) => identify::run(&args, out),
        Command::Campaign(args) => campaign::run(&args, out),
    }
}

/// An error about the whole document names the file (`BEAM.yaml`) instead.
fn name_file(mut e: InputError, file: &str) -> InputError {
    if e.field == crate::error::TOP_LEVEL {
        e.field = file.to_string();
    }
    e
}

/// Reads and validates a beam YAML file.
pub fn read_beam(path: &Path) -> Result<BeamSpec, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::new("BEAM.yaml", path.display(), format!("a readable YAML file ({e})")))?;
    BeamSpec::from_yaml(&text).map_err(|e| CliError::Input(name_file(name_serde_value(e), "BEAM.yaml")))
}

/// serde reports unknown variants/fields inside its message; lift the
/// offending name into `value` and the expected set into `allowed` so the one
/// line reads `invalid support = hinged: allowed one of `simply-supported`, …`.
/// Public so that other front ends (the Python package) that parse YAML text
/// themselves print the CLI's line.
pub fn name_serde_value(mut e: InputError) -> InputError {
    for key in ["unknown variant `", "unknown field `"] {
        if let Some(start) = e.allowed.find(key) {
            let rest = &e.allowed[start + key.len()..];
            let Some(value) = rest.split('`').next().map(str::to_string) else { continue };
            let expected = rest
                .find("expected ")
                .map(|i| rest[i + "expected ".len()..].split(" at line").next().unwrap_or("").to_string())
                .unwrap_or_default();
            e.value = value;
            let expected = crate::error::clip_list(&expected, crate::error::LIST_CHARS);
            if key == "unknown field `" {
                e.allowed = format!("a known field: {expected}");
            } else {
                e.allowed = expected;
            }
        }
    }
    e
}

pub(crate) fn write_out(out: &mut dyn std::io::Write, text: &str) -> Result<(), CliError> {
    out.write_all(text.as_bytes()).map_err(|e| CliError::Failure(format!("cannot write output: {e}")))
}

/// Reads and validates a measured-data file.
pub fn read_measured(path: &Path) -> Result<crate::calibration::MeasuredData, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| InputError::new("MEASURED.yaml", path.display(), format!("a readable YAML file ({e})")))?;
    crate::calibration::MeasuredData::from_yaml(&text)
        .map_err(|e| CliError::Input(name_file(name_serde_value(e), "MEASURED.yaml")))
}
