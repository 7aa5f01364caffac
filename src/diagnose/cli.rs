//! `nanobeam diagnose MEASURED.yaml [--out DIR] [--json]` as a library call
//! (the clap wiring is `src/cli/diagnose.rs`).

use std::io::Write;
use std::path::Path;

use crate::cli::{read_measured, CliError};

use super::{diagnose_run, report, DiagnoseSettings};

/// Runs the command, writing the summary (or the JSON) to `out`. Bad input is
/// `CliError::Input` (exit 2) naming the field; DIR is only replaced when
/// everything succeeded.
pub fn run_to(
    measured: &Path,
    dir: Option<&Path>,
    json: bool,
    settings: &DiagnoseSettings,
    out: &mut dyn Write,
) -> Result<(), CliError> {
    let data = read_measured(measured)?;
    let t0 = std::time::Instant::now();
    let run = diagnose_run(&data, settings)?;
    let elapsed = t0.elapsed();
    if let Some(dir) = dir {
        report::write_report(dir, &run, &data, settings).map_err(CliError::Failure)?;
    }
    let d = &run.diagnosis;
    let text = if json {
        serde_json::to_string_pretty(d).expect("diagnosis serialises") + "\n"
    } else {
        format!(
            "misfit detected: {}\ncause: {}\nln B ({} vs base): {:.2}\nRMS z: {:.2} -> {:.2}\n({:.1} s)\n",
            d.misfit_detected,
            d.cause,
            d.gain.extension,
            d.gain.log_bayes_factor,
            d.gain.rms_z_before,
            d.gain.rms_z_after,
            elapsed.as_secs_f64()
        )
    };
    out.write_all(text.as_bytes()).map_err(|e| CliError::Failure(format!("cannot write output: {e}")))
}

/// [`run_to`] on stdout, returning the process exit code (0, 1 or 2).
pub fn run(measured: &Path, dir: Option<&Path>, json: bool, settings: &DiagnoseSettings) -> i32 {
    let stdout = std::io::stdout();
    let mut lock = stdout.lock();
    match run_to(measured, dir, json, settings, &mut lock) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("{e}");
            e.exit_code()
        }
    }
}
