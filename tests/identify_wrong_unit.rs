//! Issue 69, defect 6: a record in the wrong time unit (picoseconds or
//! LAMMPS step numbers left in `time_s`) put its lines 12–15 decades below
//! the `--beam` model's modes, and `identify` numbered them 1, 2, … anyway
//! (exit 0). It must exit 2 naming the column and the decades.
//!
//! Data: a two-mode ring-down written here, ω = 9.3e11 and 3.8e12 rad/s
//! (modes 1 and 2 of the hardening suite's 8 nm beam, ζ = 0.02 and 0.01),
//! sampled at 20 points per period of the upper mode; the same samples
//! with the time written in picoseconds and in 1 fs steps.

use std::process::Command;

const BEAM: &str = "length_nm: 8.0\ndiameter_nm: 1.0\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300.0\nsupport: simply-supported\nelements: 20\n";

/// The ring-down with its times multiplied by `scale` (1 = seconds).
fn ring_down(scale: f64) -> String {
    let modes = [(9.3e11_f64, 0.02_f64, 1e-11_f64), (3.8e12, 0.01, 4e-12)];
    let dt = std::f64::consts::TAU / 3.8e12 / 20.0;
    let mut text = String::from("time_s,displacement_m\n");
    for i in 0..3000 {
        let t = i as f64 * dt;
        let x: f64 = modes.iter().map(|&(w, z, a)| a * (-z * w * t).exp() * (w * (1.0 - z * z).sqrt() * t).cos()).sum();
        text.push_str(&format!("{:e},{x:e}\n", t * scale));
    }
    text
}

/// (exit code, stderr) of `nanobeam identify REC --beam BEAM --first-mode 1`
/// (two modes fit modes 1, 2 and 1, 3 of the prior: the first is stated).
fn identify(record: &str) -> (i32, String) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("rec.csv"), record).unwrap();
    std::fs::write(dir.path().join("beam.yaml"), BEAM).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_nanobeam"))
        .args(["identify", "rec.csv", "--beam", "beam.yaml", "--first-mode", "1"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    (out.status.code().expect("exited"), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn a_time_column_in_another_unit_is_refused_with_the_decades() {
    // the control: in seconds, the two lines are numbered
    let (code, err) = identify(&ring_down(1.0));
    assert_eq!(code, 0, "{err}");
    // picoseconds: lines 12 decades low; 1 fs steps: 15
    for (scale, decades) in [(1e12, 12.0), (1e15, 15.0)] {
        let (code, err) = identify(&ring_down(scale));
        assert_eq!(code, 2, "{scale:e}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        let line = err.trim_end();
        assert!(line.len() <= 200, "{} chars: {line}", line.len());
        assert!(line.starts_with("invalid time_s = lines at "), "{line}");
        assert!(line.contains("a column in seconds"), "{line}");
        // the decades between the record's highest line and the lowest mode 1 of
        // the prior (about 0.1–0.3 below the nominal mode 1): within one of the scale's
        let shown: f64 = line.split("these are ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
        assert!((shown - decades).abs() < 1.0, "{shown} decades for a scale of {scale:e}: {line}");
    }
}
