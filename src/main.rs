//! The `nanobeam` command line: argument parsing only; bodies live in `nanobeam::cli`.

use std::path::PathBuf;

use clap::{Parser, Subcommand};
use nanobeam::cli;

#[derive(Parser)]
#[command(name = "nanobeam", version, about = "Nonlocal viscoelastic Euler-Bernoulli nanobeams: modal analysis, FRF, Bayesian calibration, diagnosis")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Calibrate a model against measured modal data with DRAM.
    Calibrate {
        /// Measured-data file (YAML).
        measured: PathBuf,
        /// Directory for chains.csv, summary.json and plots (written atomically).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Print JSON on stdout.
        #[arg(long)]
        json: bool,
    },
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Calibrate { measured, out, json } => cli::calibrate::run(&measured, out.as_deref(), json),
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}
