//! `cargo xtask reproduce [--out DIR] [--quick]`: a thin driver over
//! `nanobeam::reproduce::pipeline` (rust-analyzer's xtask convention).

use std::path::PathBuf;
use std::time::Instant;

use clap::{Parser, Subcommand};
use nanobeam::reproduce::pipeline::{run, Options, ReproduceError};

#[derive(Parser)]
#[command(name = "xtask", about = "Project automation for nanobeam")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Regenerate every table and figure of the paper, audit them, render report.md.
    Reproduce {
        /// Output directory (replaced atomically).
        #[arg(long, default_value = "target/reproduce")]
        out: PathBuf,
        /// Short chains (what the test suite uses).
        #[arg(long)]
        quick: bool,
    },
}

fn main() {
    let Cli { command: Command::Reproduce { out, quick } } = Cli::parse();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let t = Instant::now();
    match run(&Options { root, out: out.clone(), quick }) {
        Ok(summary) => {
            for (stage, s) in &summary.timings {
                eprintln!("{stage:>24}: {s:7.2} s");
            }
            let failed = summary.verdicts.iter().filter(|v| !v.pass).count();
            eprintln!(
                "wrote {} in {:.1} s; audit: {} of {} checks pass",
                out.join("report.md").display(),
                t.elapsed().as_secs_f64(),
                summary.verdicts.len() - failed,
                summary.verdicts.len()
            );
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(match e {
                ReproduceError::Input(_) => 2,
                ReproduceError::Failure(_) => 1,
            });
        }
    }
}
