//! `nanobeam diagnose MEASURED.yaml [--out DIR] [--json] [--samples N] [--quick]`:
//! misfit, causes, extension and gain (see `crate::diagnose`).

use std::path::PathBuf;

use clap::Args;

use crate::cli::{read_measured, write_out, CliError};
use crate::diagnose::{diagnose_run, report, DiagnoseSettings};

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
    /// TMCMC samples per stage per model [default: 1000, or 400 with --quick].
    #[arg(long)]
    pub samples: Option<usize>,
    /// The settings the hidden-effect test suite validates its accuracy targets at
    /// (400 samples, 3 MH steps per stage, 250 MAP iterations) instead of the
    /// defaults (1000, 4, 400): about 2.5 times fewer forward solves.
    #[arg(long)]
    pub quick: bool,
}

/// Runs the command: the summary (or the JSON) goes to `out`; DIR is only
/// replaced when everything succeeded.
pub fn run(args: &DiagnoseArgs, out: &mut dyn std::io::Write) -> Result<(), CliError> {
    if let Some(dir) = &args.out {
        crate::report::render::check_out_dir(dir).map_err(|e| crate::cli::calibrate::out_dir_error(dir, e))?;
    }
    let mut settings = if args.quick { DiagnoseSettings::quick() } else { DiagnoseSettings::default() };
    if let Some(samples) = args.samples {
        settings.samples = samples;
    }
    settings.validate()?;
    let data = read_measured(&args.measured)?;
    let started = std::time::Instant::now();
    let run = diagnose_run(&data, &settings)?;
    // the timing summary goes to stderr: wall time is not part of the (deterministic) result
    eprintln!(
        "diagnosis: {} models, {} forward evaluations, {:.1} s",
        run.runs.len(),
        run.diagnosis.forward_evaluations,
        started.elapsed().as_secs_f64()
    );
    // per model: where the time went (models run concurrently on the
    // threads, so the elapsed times overlap and sum to more than the wall)
    for r in &run.runs {
        eprintln!("  {:<48} {:>8} evaluations {:>7.1} s", r.model.name(), r.forward_evaluations, r.elapsed_s);
    }
    if let Some(dir) = &args.out {
        report::write_report(dir, &run, &data, &settings)?;
    }
    let d = &run.diagnosis;
    let text = if args.json {
        serde_json::to_string_pretty(d).expect("plain data") + "\n"
    } else {
        let mut t = format!(
            "misfit detected: {}\ncause: {}\nexplained: {}\nln B ({} vs base): {:.2}\nRMS z: {:.2} -> {:.2}\n",
            d.misfit_detected,
            d.cause,
            d.explained,
            d.gain.extension,
            d.gain.log_bayes_factor,
            d.gain.rms_z_before,
            d.gain.rms_z_after,
        );
        for a in &d.alternatives {
            t += &format!("alternative: {} (ln B gap {:.2})\n", a.extension, a.log_bayes_factor_gap);
        }
        if let Some(n) = &d.next_measurement {
            t += &format!("next measurement: {} of mode {} ({:.1} sd apart)\n", n.quantity, n.mode, n.separation_sd);
        }
        t
    };
    write_out(out, &text)
}
