//! CLI contract of `nanobeam modal` / `nanobeam frf`: JSON shape on stdout,
//! exit code 2 and exactly one stderr line for bad input.

use std::process::Command;

const GOOD: &str = "length_nm: 8\ndiameter_nm: 1\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300\nsupport: simply-supported\nelements: 20\nnonlocal_e0a_nm: 0.5\nviscous_damping_n_s_m2: 1.0e-5\ninternal_variables:\n  - {delta: 0.1, omega_rad_s: 1.0e11}\n";

fn write(dir: &tempfile::TempDir, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_nanobeam")).args(args).output().unwrap()
}

#[test]
fn modal_json_has_exactly_the_documented_shape() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "b.yaml", GOOD);
    let out = run(&["modal", p.to_str().unwrap(), "--json", "--modes", "4"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("stdout is one JSON document");
    let obj = v.as_object().unwrap();
    assert_eq!(obj.keys().collect::<Vec<_>>(), vec!["modes"]);
    let modes = obj["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 4);
    for (i, m) in modes.iter().enumerate() {
        let m = m.as_object().unwrap();
        let mut keys: Vec<_> = m.keys().map(String::as_str).collect();
        keys.sort();
        assert_eq!(keys, ["mode", "omega_rad_s", "pole_im_rad_s", "pole_re_rad_s", "zeta"]);
        assert_eq!(m["mode"].as_u64().unwrap() as usize, i + 1);
        let (re, im) = (m["pole_re_rad_s"].as_f64().unwrap(), m["pole_im_rad_s"].as_f64().unwrap());
        let w = m["omega_rad_s"].as_f64().unwrap();
        // eq. (34)-(35) restated on the serialised numbers (round-trip exact to 1 ulp)
        assert!((w - re.hypot(im)).abs() <= 1e-15 * w * 4.0);
        assert!((m["zeta"].as_f64().unwrap() + re / w).abs() <= 1e-15);
        assert!(im > 0.0);
    }
    // default --modes 3 and the readable table
    let out = run(&["modal", p.to_str().unwrap()]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("omega [rad/s]") && text.contains("f [GHz]") && text.contains("zeta"));
    assert!(text.contains("real poles"));
    assert_eq!(text.lines().filter(|l| l.trim_start().starts_with(|c: char| c.is_ascii_digit())).count(), 3);
}

#[test]
fn frf_json_has_the_documented_shape() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "b.yaml", GOOD);
    let out = run(&[
        "frf",
        p.to_str().unwrap(),
        "--input-x-nm",
        "2",
        "--output-x-nm",
        "4",
        "--from-rad-s",
        "1e11",
        "--to-rad-s",
        "1e13",
        "--points",
        "5",
        "--log",
        "--json",
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let pts = v["points"].as_array().unwrap();
    assert_eq!(pts.len(), 5);
    let first = pts[0]["omega_rad_s"].as_f64().unwrap();
    let last = pts[4]["omega_rad_s"].as_f64().unwrap();
    // log grid end points: exp(ln a) is exact to a couple of ulps
    assert!((first / 1e11 - 1.0).abs() < 1e-14 && (last / 1e13 - 1.0).abs() < 1e-14);
    for p in pts {
        let mut keys: Vec<_> = p.as_object().unwrap().keys().map(String::as_str).collect();
        keys.sort();
        assert_eq!(keys, ["im_m_per_n", "magnitude_m_per_n", "omega_rad_s", "phase_rad", "re_m_per_n"]);
    }
}

/// Bad input: exit code 2, nothing on stdout, one line on stderr naming the
/// field, the value and the allowed range.
#[test]
fn bad_input_exits_2_with_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let cases: Vec<(String, &str, &str)> = vec![
        (GOOD.replace("length_nm: 8", "length_nm: -8"), "length_nm", "-8"),
        (GOOD.replace("diameter_nm: 1", "diameter_nm: 0"), "diameter_nm", "0"),
        (GOOD.replace("youngs_modulus_pa: 1.0e12", "youngs_modulus_pa: -1"), "youngs_modulus_pa", "-1"),
        (GOOD.replace("density_kg_m3: 2300", "density_kg_m3: 0"), "density_kg_m3", "0"),
        (GOOD.replace("elements: 20", "elements: 0"), "elements", "0"),
        (GOOD.replace("nonlocal_e0a_nm: 0.5", "nonlocal_e0a_nm: -0.5"), "nonlocal_e0a_nm", "-0.5"),
        (GOOD.replace("delta: 0.1", "delta: -0.1"), "internal_variables[0].delta", "-0.1"),
        (GOOD.replace("omega_rad_s: 1.0e11", "omega_rad_s: 0"), "internal_variables[0].omega_rad_s", "0"),
        (GOOD.replace("viscous_damping_n_s_m2: 1.0e-5", "viscous_damping_n_s_m2: -1"), "viscous_damping_n_s_m2", "-1"),
        (GOOD.replace("simply-supported", "hinged"), "support", "hinged"),
        (format!("{GOOD}colour: red\n"), "colour", "colour"),
    ];
    for (i, (yaml, field, value)) in cases.iter().enumerate() {
        let p = write(&dir, &format!("bad{i}.yaml"), yaml);
        let out = run(&["modal", p.to_str().unwrap(), "--json"]);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "case {field}: {err}");
        assert!(out.stdout.is_empty());
        assert_eq!(err.lines().count(), 1, "case {field}: {err:?}");
        assert!(err.contains(&format!("invalid {field} = {value}")), "case {field}: {err}");
        assert!(err.contains("allowed"), "case {field}: {err}");
    }
    let out = run(&["modal", dir.path().join("missing.yaml").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(String::from_utf8(out.stderr).unwrap().lines().count(), 1);
    // out-of-range position in frf
    let p = write(&dir, "ok.yaml", GOOD);
    let out = run(&[
        "frf",
        p.to_str().unwrap(),
        "--input-x-nm",
        "9",
        "--output-x-nm",
        "4",
        "--from-rad-s",
        "1",
        "--to-rad-s",
        "2",
        "--points",
        "2",
    ]);
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(err.starts_with("invalid input_x_nm = 9") && err.lines().count() == 1, "{err}");
    let out = run(&[
        "frf",
        p.to_str().unwrap(),
        "--input-x-nm",
        "1",
        "--output-x-nm",
        "4",
        "--from-rad-s",
        "-1",
        "--to-rad-s",
        "2",
        "--points",
        "2",
    ]);
    assert_eq!(out.status.code(), Some(2));
}
