//! `cargo xtask reproduce [--out DIR] [--quick] [--check | --bless]`: a thin
//! driver over `nanobeam::reproduce` (rust-analyzer's xtask convention).
//!
//! `--check` compares the run with `golden/reproduce-{quick,full}.json`
//! (`nanobeam::reproduce::check`): exit 1 and a list of drifts in units of
//! their Monte Carlo error; a missing or malformed golden file is exit 2.
//! `--bless` writes the golden file from the run.

use std::path::PathBuf;
use std::time::Instant;

use clap::{Parser, Subcommand};
use nanobeam::reproduce::check::{compare, golden_of, load_golden};
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
        /// Short chains and fewer noise replicates (what the test suite uses).
        #[arg(long)]
        quick: bool,
        /// Compare with the committed golden results; exit 1 on drift.
        #[arg(long, conflicts_with = "bless")]
        check: bool,
        /// Write the golden results of this run (after a reviewed, intended change).
        #[arg(long)]
        bless: bool,
    },
}

fn main() {
    let Cli { command: Command::Reproduce { out, quick, check, bless } } = Cli::parse();
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().expect("xtask lives in the repository").to_path_buf();
    let golden_path = root.join("golden").join(if quick { "reproduce-quick.json" } else { "reproduce-full.json" });
    // Read the golden file first: a bad one must not cost a run.
    let golden = if check {
        match load_golden(&golden_path, quick) {
            Ok(g) => Some(g),
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        }
    } else {
        None
    };
    let command_line =
        std::iter::once("cargo xtask".to_string()).chain(std::env::args().skip(1)).collect::<Vec<_>>().join(" ");
    let t = Instant::now();
    let summary = match run(&Options { root, out: out.clone(), quick, command_line }) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(match e {
                ReproduceError::Input(_) => 2,
                ReproduceError::Failure(_) => 1,
            });
        }
    };
    for (stage, s) in &summary.timings {
        eprintln!("{stage:>24}: {s:7.2} s");
    }
    let count = |sym: &str| summary.verdicts.iter().filter(|v| v.status.symbol() == sym).count();
    eprintln!(
        "wrote {} in {:.1} s; audit: {} ✓, {} ≈, {} ✗ of {}",
        out.join("report.md").display(),
        t.elapsed().as_secs_f64(),
        count("✓"),
        count("≈"),
        count("✗"),
        summary.verdicts.len()
    );
    let mine = golden_of(&summary.typed);
    if bless {
        std::fs::write(&golden_path, mine.to_json()).unwrap_or_else(|e| {
            eprintln!("{}: {e}", golden_path.display());
            std::process::exit(1);
        });
        eprintln!("wrote {}", golden_path.display());
    }
    if let Some(g) = golden {
        let drifts = compare(&mine, &g);
        if drifts.is_empty() {
            eprintln!(
                "check: no drift against {} ({} quantities, {} verdicts)",
                golden_path.display(),
                g.quantities.len(),
                g.verdicts.len()
            );
        } else {
            eprintln!("check: {} drift(s) against {}:", drifts.len(), golden_path.display());
            for d in &drifts {
                eprintln!("  {d}");
            }
            std::process::exit(1);
        }
    }
}
