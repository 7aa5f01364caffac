//! `nanobeam diagnose MEASURED.yaml [--out DIR] [--json]` as a library call
//! the CLI wires up: returns the process exit code (0 ok, 2 bad input, 1 other failure).

use std::io::Write;
use std::path::Path;

use crate::calibration::MeasuredData;

use super::{diagnose_run, report, DiagnoseSettings};

/// Runs the command. Bad input prints one line naming the field and returns 2;
/// DIR is only replaced when everything succeeded.
pub fn run(measured: &Path, out: Option<&Path>, json: bool, settings: &DiagnoseSettings) -> i32 {
    let text = match std::fs::read_to_string(measured) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: cannot read {}: {e}", measured.display());
            return 2;
        }
    };
    let data = match MeasuredData::from_yaml(&text) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let t0 = std::time::Instant::now();
    let run = match diagnose_run(&data, settings) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    let elapsed = t0.elapsed();
    if let Some(dir) = out {
        if let Err(e) = report::write_report(dir, &run, &data, settings) {
            eprintln!("error: {e}");
            return 1;
        }
    }
    let d = &run.diagnosis;
    let mut stdout = std::io::stdout().lock();
    let written = if json {
        serde_json::to_string_pretty(d).map_err(std::io::Error::other).and_then(|s| writeln!(stdout, "{s}"))
    } else {
        writeln!(
            stdout,
            "misfit detected: {}\ncause: {}\nln B ({} vs base): {:.2}\nRMS z: {:.2} -> {:.2}\n({:.1} s)",
            d.misfit_detected,
            d.cause,
            d.gain.extension,
            d.gain.log_bayes_factor,
            d.gain.rms_z_before,
            d.gain.rms_z_after,
            elapsed.as_secs_f64()
        )
    };
    if written.is_err() {
        return 1;
    }
    0
}
