//! Issue 44 (hardening, round two), inputs with derived bounds: the tension
//! and the shear coefficient through their scaled groups (ñ = NL²/EI,
//! g̃ = κGAL²/EI), short numbers in messages, mode-scan positions on a
//! cantilever's free end, all-zero scans and size limits. The files are
//! written by hand here; the expected limits are recomputed from the
//! closed forms EI = Eπd⁴/64 and AL²/I = 16(L/d)², not read from the code.

use std::process::Command;

const BEAM: &str = "length_nm: 8.0\ndiameter_nm: 1.0\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300.0\nsupport: simply-supported\nelements: 20\n";

/// (exit code, single stderr line) of `nanobeam cmd FILE extra…` on `text`.
fn one(cmd: &str, name: &str, text: &str, extra: &[&str]) -> (i32, String) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    let mut args = vec![cmd, p.to_str().unwrap()];
    args.extend_from_slice(extra);
    let out = Command::new(env!("CARGO_BIN_EXE_nanobeam")).args(&args).output().unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    let code = out.status.code().expect("exited normally");
    if code != 0 {
        assert_eq!(err.lines().count(), 1, "not one line: {err:?}");
    }
    (code, err.trim_end().to_string())
}

/// EI/L² of BEAM in newtons: E·πd⁴/64/L².
fn n_unit() -> f64 {
    1e12 * std::f64::consts::PI * 1e-36 / 64.0 / 64e-18
}

#[test]
fn tension_is_bounded_by_its_scaled_value() {
    // defect 8: 1e30 N gave exit 0 with ζ = −0.95; 1e300 N exit 1
    for n in ["1.0e30", "1.0e300"] {
        let (code, line) = one("modal", "b.yaml", &format!("{BEAM}axial_force_n: {n}\n"), &[]);
        assert_eq!(code, 2, "{line}");
        assert!(line.starts_with("invalid axial_force_n = 1e"), "{line}");
        let limit = 1e8 * n_unit();
        let shown: f64 = line.split("allowed <= ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
        // the same product in another order: equal to a few ulps
        assert!((shown / limit - 1.0).abs() < 1e-14, "limit {limit:e}: {line}");
    }
    // just inside the limit, with damping: finite modes, ζ > 0
    let inside = format!(
        "{BEAM}internal_variables: [{{delta: 0.4, omega_rad_s: 4.5e11}}]\naxial_force_n: {:e}\n",
        0.99e8 * n_unit()
    );
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("b.yaml"), inside).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_nanobeam"))
        .args(["modal", dir.path().join("b.yaml").to_str().unwrap(), "--modes", "2", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for m in v["modes"].as_array().unwrap() {
        assert!(m["zeta"].as_f64().unwrap() > 0.0, "{m}");
    }
}

#[test]
fn shear_coefficient_is_bounded_by_the_scaled_shear_stiffness() {
    // defect 8: 1e-300 took 9 s and exited 1 "non-positive family stiffness"
    let sd = |k: &str| format!("{BEAM}shear_deformation: {{poisson_ratio: 0.3, shear_coefficient: {k}}}\n");
    let (code, line) = one("modal", "b.yaml", &sd("1e-300"), &[]);
    assert_eq!(code, 2, "{line}");
    // g̃ = κ/(2(1+ν))·16(L/d)² = κ·512/1.3; g̃ >= 0.1 ⇔ κ >= 0.1·1.3/512
    let lo = 0.1 * 1.3 / 512.0;
    assert!(line.starts_with("invalid shear_deformation.shear_coefficient = 1e-300: allowed "), "{line}");
    let shown: f64 = line.split("allowed ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
    assert!((shown / lo - 1.0).abs() < 1e-12, "{shown:e} vs {lo:e}: {line}");
    assert_eq!(one("modal", "b.yaml", &sd("0.85"), &[]).0, 0);
}

#[test]
fn numbers_in_messages_are_short() {
    // user-hostile 4: a 301-digit shear_coefficient, a force as 0.0000000…: past the buckling
    // load (≈ −π²EI/L² = −7.6e-9 N) so refused
    let (_, line) = one(
        "modal",
        "b.yaml",
        &format!("{BEAM}shear_deformation: {{poisson_ratio: 0.3, shear_coefficient: 1e300}}\n"),
        &[],
    );
    assert!(line.contains("= 1e300:"), "{line}");
    let (code, line) = one("modal", "b.yaml", &format!("{BEAM}axial_force_n: -0.000000010200537342999999\n"), &[]);
    assert_eq!(code, 2, "{line}");
    assert!(line.starts_with("invalid axial_force_n = -1.0200537343e-8: "), "{line}");
}

fn measured_with_scan(support: &str, drive: &str, points: &str) -> String {
    format!(
        "beam: {{ length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, support: {support}, elements: 20 }}
modes:
  - {{ mode: 1, omega_rad_s: 3.0e11, omega_sd_rad_s: 3e9, zeta: 0.06, zeta_sd: 0.002 }}
  - {{ mode: 2, omega_rad_s: 1.9e12, omega_sd_rad_s: 2e10, zeta: 0.02, zeta_sd: 0.001 }}
  - {{ mode: 3, omega_rad_s: 5.3e12, omega_sd_rad_s: 5e10, zeta: 0.01, zeta_sd: 0.001 }}
mode_scans:
  - {{ mode: 1, drive_x_nm: {drive}, points: [{points}] }}
"
    )
}

/// Runs `diagnose` with an output dir that is a file, so a valid file stops
/// at the --out check (exit 2 on --out) without computing.
fn scan_check(text: &str) -> (i32, String) {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("file");
    std::fs::write(&f, "x").unwrap();
    let (code, line) = one("calibrate", "m.yaml", text, &["--out", f.to_str().unwrap()]);
    (code, line)
}

#[test]
fn a_cantilevers_free_end_may_be_driven_and_read_and_an_all_zero_scan_is_refused() {
    // user-hostile 6 and 7
    let pts = "{ x_nm: 4.0, relative_amplitude: 0.3, relative_amplitude_sd: 0.01 }, { x_nm: 8.0, relative_amplitude: 1.0, relative_amplitude_sd: 0.01 }";
    let (_, line) = scan_check(&measured_with_scan("clamped-free", "8.0", pts));
    assert!(line.starts_with("invalid --out"), "the file passes its checks: {line}");
    let (code, line) = scan_check(&measured_with_scan("simply-supported", "8.0", pts));
    assert_eq!(code, 2);
    assert!(line.starts_with("invalid mode_scans[0].drive_x_nm = 8: allowed 0 < x < length_nm"), "{line}");
    let zeros = "{ x_nm: 2.0, relative_amplitude: 0.0, relative_amplitude_sd: 0.01 }, { x_nm: 4.0, relative_amplitude: 0.0, relative_amplitude_sd: 0.01 }";
    let (code, line) = scan_check(&measured_with_scan("clamped-free", "8.0", zeros));
    assert_eq!(code, 2);
    assert!(line.starts_with("invalid mode_scans[0].points = every relative_amplitude 0"), "{line}");
}

#[test]
fn sizes_are_refused_up_front() {
    // user-hostile 8: a scan of 1e5 points ran for minutes; identify held 1e6 rows in 1.1 GB
    let many: Vec<String> = (1..=81)
        .map(|i| format!("{{ x_nm: {:e}, relative_amplitude: 0.5, relative_amplitude_sd: 0.01 }}", i as f64 * 0.095))
        .collect();
    let (code, line) = scan_check(&measured_with_scan("clamped-free", "8.0", &many.join(", ")));
    assert_eq!(code, 2);
    // 4 readings per element of the 20-element beam
    assert!(line.starts_with("invalid mode_scans[0].points = 81 points: allowed at most 80 "), "{line}");
    let mut csv = String::from("omega_rad_s,h_abs_m_per_n\n");
    for i in 0..200_001 {
        csv += &format!("{},1e-9\n", i + 1);
    }
    let started = std::time::Instant::now();
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("beam.yaml"), BEAM).unwrap();
    std::fs::write(dir.path().join("d.csv"), &csv).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_nanobeam"))
        .args(["identify", "d.csv", "--beam", "beam.yaml"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let line = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2), "{line}");
    assert!(line.starts_with("invalid rows = more than 200000: "), "{line}");
    assert!(started.elapsed().as_secs_f64() < 30.0);
}
