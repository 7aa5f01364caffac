//! `nanobeam diagnose MEASURED.yaml [--out DIR] [--json]`: misfit, cause,
//! extension and gain (see `crate::diagnose`).

use std::path::PathBuf;

use clap::Args;

use crate::cli::CliError;
use crate::diagnose::{cli::run_to, DiagnoseSettings};

#[derive(Debug, Args)]
pub struct DiagnoseArgs {
    /// Measured-data file (YAML): beam, at least 3 modes, optional held_out_modes, parameters, sampler (its seed is used).
    pub measured: PathBuf,
    /// Directory for report.md, diagnosis.json and SVG plots (written atomically).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print the diagnosis as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// TMCMC samples per stage per model class.
    #[arg(long, default_value_t = 1000)]
    pub samples: usize,
}

pub fn run(args: &DiagnoseArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    if let Some(dir) = &args.out {
        crate::report::render::check_out_dir(dir).map_err(|e| crate::cli::calibrate::out_dir_error(dir, e))?;
    }
    let settings = DiagnoseSettings { samples: args.samples, ..DiagnoseSettings::default() };
    run_to(&args.measured, args.out.as_deref(), args.json, &settings, out)
}
