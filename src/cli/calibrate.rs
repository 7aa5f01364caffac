//! `nanobeam calibrate MEASURED.yaml [--out DIR] [--json]`.

use std::path::PathBuf;

use clap::Args;

use crate::calibration::output::{summary_cells, write_calibration_files, SUMMARY_HEADERS};
use crate::calibration::{calibrate, CalibrateOptions};
use crate::cli::{read_measured, write_out, CliError};
use crate::error::InputError;
use crate::report::render::{check_out_dir, write_dir_atomically};
use crate::report::table::Table;
use crate::report::ReportError;

#[derive(Debug, Args)]
pub struct CalibrateArgs {
    /// Measured-data file (YAML): beam, modes, optional parameters and sampler.
    pub measured: PathBuf,
    /// Directory for chains.csv, summary.json and SVG plots (written atomically).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the summary as JSON on stdout.
    #[arg(long)]
    pub json: bool,
}

/// A bad `--out` (existing file, foreign non-empty directory, unwritable
/// parent) is bad input (exit 2); any other write failure is exit 1.
pub(crate) fn out_dir_error(dir: &std::path::Path, e: ReportError) -> CliError {
    match e {
        ReportError::OutPath { path, reason } => CliError::Input(InputError::new(
            "--out",
            path.display(),
            format!("a new path, an empty directory or a directory written by nanobeam; {reason}"),
        )),
        other => CliError::Failure(format!("cannot write {}: {other}", dir.display())),
    }
}

pub fn run(args: &CalibrateArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    let data = read_measured(&args.measured)?;
    if let Some(dir) = &args.out {
        check_out_dir(dir).map_err(|e| out_dir_error(dir, e))?;
    }
    let result = calibrate(&data, &CalibrateOptions { control: crate::cli::progress::TerminalBar::control() })?;
    for w in &result.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(dir) = &args.out {
        let posterior = crate::calibration::BeamPosterior::new(&data, data.parameters.clone());
        let ctx = crate::calibration::output::InferenceContext { posterior: &posterior, seed: data.sampler.seed };
        write_dir_atomically(dir, |tmp| write_calibration_files(tmp, &result, None, Some(&ctx)))
            .map_err(|e| out_dir_error(dir, e))?;
    }
    if args.json {
        let json = serde_json::to_string(&result.json()).expect("summary serialises");
        return write_out(out, &(json + "\n"));
    }
    let mut t = Table::new(std::iter::once("parameter").chain(SUMMARY_HEADERS));
    for p in &result.summary.parameters {
        t.push_row(std::iter::once(p.name.clone()).chain(summary_cells(p)));
    }
    let acc: Vec<String> = result.acceptance.iter().map(|a| format!("{a:.3}")).collect();
    let text = format!(
        "{}\nacceptance per DR stage: [{}]; rejected invalid proposals: {}; log posterior at MAP: {:.4}\n",
        t.to_markdown(),
        acc.join(", "),
        result.rejected_invalid,
        result.log_posterior_map
    );
    write_out(out, &text)
}
