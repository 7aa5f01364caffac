//! Issue 11 (CLI): one-line messages with the full field path, value and
//! range; sampler, prior and mode-number bounds; runs that cannot sample.

use std::process::{Command, Output};

const BEAM: &str = "length_nm: 8.0\ndiameter_nm: 1.0\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300.0\nsupport: simply-supported\nelements: 20\n";

mod common_hardening;
use common_hardening::MEASURED;

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nanobeam")).args(args).output().unwrap()
}

/// Runs `cmd` on `text`; returns (exit code, the single stderr line).
fn one(cmd: &str, text: &str, extra: &[&str]) -> (i32, String) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("in.yaml");
    std::fs::write(&p, text).unwrap();
    let mut args = vec![cmd, p.to_str().unwrap()];
    args.extend_from_slice(extra);
    let out = run(&args);
    let err = String::from_utf8(out.stderr).unwrap();
    let code = out.status.code().expect("exited normally");
    if code != 0 {
        assert_eq!(err.lines().count(), 1, "not one line: {err:?}");
    }
    (code, err.trim_end().to_string())
}

fn bad(cmd: &str, text: &str, field: &str) -> String {
    let (code, line) = one(cmd, text, &[]);
    assert_eq!(code, 2, "{line}");
    assert!(line.starts_with(&format!("invalid {field} = ")), "expected field {field}: {line}");
    assert!(!line.contains("(see message)"), "{line}");
    // serde's location suffix is dropped where the field path says it all
    assert!(field == "BEAM.yaml" || !line.contains(" at line "), "{line}");
    line
}

#[test]
fn serde_errors_name_the_full_path_the_value_and_the_range() {
    let l = bad("modal", &BEAM.replace("2300.0", "1e400"), "density_kg_m3");
    assert!(l.contains("= 1e400") && l.contains("finite") && !l.contains("invalid type"), "{l}");
    let l = bad("modal", &BEAM.replace("20\n", "-3\n"), "elements");
    assert!(l.contains("= -3"), "{l}");
    bad("modal", &format!("{BEAM}internal_variables: [{{delta: 1}}]\n"), "internal_variables[0].omega_rad_s");
    bad(
        "modal",
        &format!("{BEAM}internal_variables: [{{delta: 1, omega_rad_s: x}}]\n"),
        "internal_variables[0].omega_rad_s",
    );
    bad("modal", &format!("{BEAM}length_nm: 9\n"), "length_nm");
    // the whole document is named by its file (issue 69: `<document>` was an internal name)
    bad("modal", "[1, 2]\n", "BEAM.yaml");
    bad("modal", "{\n", "BEAM.yaml");
    // an alias bomb (1e9 expanded nodes) inside a field that takes any mapping is named as one
    let mut bomb = String::from("parameters:\n  a0: &a0 [1,1,1,1,1,1,1,1,1,1]\n");
    for i in 1..9 {
        bomb += &format!("  a{i}: &a{i} [{}]\n", vec![format!("*a{}", i - 1); 10].join(","));
    }
    let (code, line) = one("calibrate", &format!("{MEASURED}{bomb}"), &[]);
    assert_eq!(code, 2, "{line}");
    assert!(line.contains("alias"), "{line}");
    let (code, line) = one("modal", &format!("x: &x {{ a: 1 }}\n{}", BEAM), &[]);
    assert_eq!(code, 2, "{line}");
    // nested parameter entries keep every level of the path
    let l = bad(
        "calibrate",
        &format!("{MEASURED}parameters: {{ delta: {{ prior: {{ dist: uniform, lower: 0, upper: 1, mean: 3 }} }} }}\n"),
        "parameters.delta.prior.mean",
    );
    assert!(l.contains("= mean: allowed a known field"), "{l}");
    bad(
        "calibrate",
        &format!("{MEASURED}parameters: {{ delta: {{ prior: {{ dist: uniform, lower: 0, upper: 1 }}, mean: 3 }} }}\n"),
        "parameters.delta.mean",
    );
    bad("calibrate", &MEASURED.replace("zeta_sd: 0.0005", "zeta_sd: -1"), "modes[1].zeta_sd");
}

fn bad_measured(edit: impl Fn(&str) -> String, field: &str) -> String {
    bad("calibrate", &edit(MEASURED), field)
}

#[test]
fn sampler_settings_that_cannot_work_are_refused() {
    let s = |from: &'static str, to: &'static str| move |m: &str| m.replace(from, to);
    bad_measured(s("chains: 2", "chains: 1"), "sampler.chains");
    bad_measured(s("draws_per_chain: 1000", "draws_per_chain: 1000000000000"), "sampler.draws_per_chain");
    bad_measured(s("draws_per_chain: 1000", "draws_per_chain: 1e12"), "sampler.draws_per_chain");
    bad_measured(s("draws_per_chain: 1000, burn_in: 200", "draws_per_chain: 1, burn_in: 0"), "sampler.draws_per_chain");
    bad_measured(s("nonadaptive_draws: 300", "nonadaptive_draws: 3000"), "sampler.nonadaptive_draws");
    bad_measured(s("adaptation_start: 300", "adaptation_start: 3000"), "sampler.adaptation_start");
    let param = |entry: &'static str| move |m: &str| format!("{m}parameters: {{ delta: {entry} }}\n");
    for sd in ["1e-200", "1e200"] {
        let entry: &'static str = Box::leak(
            format!("{{ prior: {{ dist: uniform, lower: 0, upper: 1 }}, proposal_sd: {sd} }}").into_boxed_str(),
        );
        let l = bad_measured(param(entry), "parameters.delta.proposal_sd");
        assert!(l.contains(sd), "{l}");
    }
    bad_measured(param("{ prior: { dist: uniform, lower: 0, upper: 1e-300 } }"), "parameters.delta.prior.upper");
    bad_measured(param("{ prior: { dist: uniform, lower: 0, upper: 1.7e308 } }"), "parameters.delta.prior.upper");
}

#[test]
fn measured_modes_must_exist_in_the_model() {
    // a 20-element simply supported beam has 40 free DOFs: physical modes 1..=40
    bad_measured(|m| m.replace("mode: 2,", "mode: 41,"), "modes[1].mode");
    bad_measured(|m| m.replace("mode: 2,", "mode: 1000000000,"), "modes[1].mode");
    bad_measured(
        |m| {
            format!("{m}held_out_modes: [{{ mode: 1, omega_rad_s: 1e12, omega_sd_rad_s: 1e9, zeta: 0.1, zeta_sd: 0.01 }}]\n")
        },
        "held_out_modes[0].mode",
    );
}

/// Modes are numbered by frequency: ω falling with the mode number, or two
/// modes at one ω, are a misnumbered table (issue 69, defect 9: `diagnose`
/// accepted both), refused naming the later mode's ω.
#[test]
fn a_mode_table_out_of_frequency_order_is_refused() {
    let l = bad_measured(|m| m.replace("omega_rad_s: 3.8e12", "omega_rad_s: 9.0e11"), "modes[1].omega_rad_s");
    assert!(l.contains("(mode 1's omega_rad_s)"), "{l}");
    bad_measured(|m| m.replace("omega_rad_s: 3.8e12", "omega_rad_s: 9.3e11"), "modes[1].omega_rad_s");
    // across fitted and held-out modes: a held-out mode 3 below mode 2
    bad_measured(
        |m| {
            format!("{m}held_out_modes: [{{ mode: 3, omega_rad_s: 2e12, omega_sd_rad_s: 1e9, zeta: 0.1, zeta_sd: 0.01 }}]\n")
        },
        "held_out_modes[0].omega_rad_s",
    );
    // the diagnosis reads the same file
    let three = MEASURED.replace(
        "zeta_sd: 0.0005 }
",
        "zeta_sd: 0.0005 }
  - { mode: 3, omega_rad_s: 8.0e12, omega_sd_rad_s: 2.4e10, zeta: 0.01, zeta_sd: 0.0003 }
",
    );
    let (code, line) = one("diagnose", &three.replace("omega_rad_s: 3.8e12", "omega_rad_s: 9.0e11"), &[]);
    assert_eq!(code, 2, "{line}");
    assert!(line.starts_with("invalid modes[1].omega_rad_s = "), "{line}");
}

/// Mode scans (`mode_scans`, what `diagnose` suggests as a shape
/// measurement) get the same treatment: each bad field named with its value
/// and range.
#[test]
fn bad_mode_scans_are_named() {
    let scan = |mode: &'static str, drive: &'static str, points: &str| {
        let points = points.to_string();
        move |m: &str| format!("{m}mode_scans: [{{ mode: {mode}, drive_x_nm: {drive}, points: [{points}] }}]\n")
    };
    let p = |x: f64, a: f64, sd: f64| format!("{{ x_nm: {x}, relative_amplitude: {a}, relative_amplitude_sd: {sd} }}");
    let two = format!("{}, {}", p(2.0, 0.7, 0.01), p(4.0, 1.0, 0.01));
    // a scan is taken at a fitted mode's resonance
    let l = bad_measured(scan("3", "7.8", &two), "mode_scans[0].mode");
    assert!(l.contains("= 3") && l.contains("listed in `modes` (1, 2)"), "{l}");
    let l = bad_measured(scan("2", "9.0", &two), "mode_scans[0].drive_x_nm");
    assert!(l.contains("= 9") && l.contains("length_nm = 8"), "{l}");
    bad_measured(scan("2", "0.0", &two), "mode_scans[0].drive_x_nm");
    bad_measured(scan("2", "7.8", &p(2.0, 0.7, 0.01)), "mode_scans[0].points");
    bad_measured(
        scan("2", "7.8", &format!("{}, {}", p(4.0, 0.7, 0.01), p(2.0, 1.0, 0.01))),
        "mode_scans[0].points[1].x_nm",
    );
    bad_measured(
        scan("2", "7.8", &format!("{}, {}", p(2.0, 0.7, 0.01), p(8.0, 1.0, 0.01))),
        "mode_scans[0].points[1].x_nm",
    );
    let l = bad_measured(
        scan("2", "7.8", &format!("{}, {}", p(2.0, -0.1, 0.01), p(4.0, 1.0, 0.01))),
        "mode_scans[0].points[0].relative_amplitude",
    );
    assert!(l.contains("= -0.1") && l.contains("<= 2"), "{l}");
    bad_measured(
        scan("2", "7.8", &format!("{}, {}", p(2.0, 0.7, 0.0), p(4.0, 1.0, 0.01))),
        "mode_scans[0].points[0].relative_amplitude_sd",
    );
    bad_measured(
        |m| format!("{m}mode_scans: [{{ mode: 2, drive_x_nm: 7.8, points: [], gain: 1 }}]\n"),
        "mode_scans[0].gain",
    );
    let twice = |m: &str| {
        let one = format!("{{ mode: 2, drive_x_nm: 7.8, points: [{}, {}] }}", p(2.0, 0.7, 0.01), p(4.0, 1.0, 0.01));
        format!("{m}mode_scans: [{one}, {one}]\n")
    };
    bad_measured(twice, "mode_scans[1].mode");
}

#[test]
fn a_run_without_any_valid_state_is_exit_1_saying_why() {
    // mode 1 is overdamped for every e0a in the prior (c̃ ≈ 55)
    let text = MEASURED.replace("elements: 20 }", "elements: 20, viscous_damping_n_s_m2: 1.0e-2 }")
        + "parameters: { nonlocal_e0a_nm: { prior: { dist: uniform, lower: 0.0, upper: 0.1 } } }\n";
    let (code, line) = one("calibrate", &text, &[]);
    assert_eq!(code, 1, "{line}");
    assert!(line.contains("no valid state") && line.contains("mode 1 is overdamped"), "{line}");
}

#[test]
fn modal_prints_an_overdamped_mode_under_its_number() {
    let beam = format!("{BEAM}viscous_damping_n_s_m2: 1.0e-2\n");
    let (code, _) = one("modal", &beam, &[]);
    assert_eq!(code, 0);
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("b.yaml");
    std::fs::write(&p, &beam).unwrap();
    let text = String::from_utf8(run(&["modal", p.to_str().unwrap()]).stdout).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).take(3).collect();
    assert!(rows[0].trim_start().starts_with("1  overdamped"), "{text}");
    assert!(rows[1].trim_start().starts_with("2 ") && rows[2].trim_start().starts_with("3 "), "{text}");
    let v: serde_json::Value = serde_json::from_slice(&run(&["modal", p.to_str().unwrap(), "--json"]).stdout).unwrap();
    assert_eq!(v["overdamped_modes"][0]["mode"], 1);
    assert_eq!(v["modes"][0]["mode"], 2);
    let (code, line) = one("modal", &beam, &["--modes", "41"]);
    assert_eq!(code, 2);
    assert!(line.starts_with("invalid --modes = 41: allowed 1..=40"), "{line}");
}

#[test]
fn frf_ranges_are_checked_before_computing() {
    let frf = |from: &str, to: &str, points: &str| {
        one(
            "frf",
            BEAM,
            &[
                "--input-x-nm",
                "2",
                "--output-x-nm",
                "4",
                "--from-rad-s",
                from,
                "--to-rad-s",
                to,
                "--points",
                points,
                "--log",
            ],
        )
    };
    let (code, line) = frf("1e-300", "1e308", "3");
    assert_eq!(code, 2);
    assert!(line.starts_with("invalid --to-rad-s = 1e308") && !line.contains("resonance"), "{line}");
    let (code, line) = frf("1e11", "1e13", "100000000");
    assert_eq!(code, 2);
    assert!(line.starts_with("invalid --points = 100000000"), "{line}");
    let (code, _) = frf("1e-300", "1e30", "5");
    assert_eq!(code, 0);
}

#[test]
fn clap_errors_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("b.yaml");
    std::fs::write(&p, BEAM).unwrap();
    let p = p.to_str().unwrap();
    for (args, start) in [
        (
            vec![
                "frf",
                p,
                "--input-x-nm",
                "1",
                "--output-x-nm",
                "1",
                "--from-rad-s",
                "1",
                "--to-rad-s",
                "2",
                "--points",
                "x",
            ],
            "invalid --points = x",
        ),
        (vec!["frf", p], "invalid --input-x-nm"),
        (vec!["bogus"], "invalid command = bogus"),
        (vec![], "invalid command = '': allowed one of: "),
        // issue 69: the argument as written in the value slot, not "(unknown argument)"
        (vec!["modal", p, "--foo"], "invalid argument = --foo: "),
    ] {
        let out = run(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with(start), "{err}");
    }
    assert_eq!(run(&["--help"]).status.code(), Some(0));
}
