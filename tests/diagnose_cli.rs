//! Bad input and the output directory of `diagnose`.

use nanobeam::calibration::MeasuredData;
use nanobeam::diagnose::{cli, diagnose, synthetic, DiagnoseSettings};

fn yaml_with(modes: &str) -> String {
    format!(
        "beam: {{ length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, support: simply-supported, elements: 20 }}\nmodes:\n{modes}"
    )
}

const M1: &str = "  - { mode: 1, omega_rad_s: 8.3e11, omega_sd_rad_s: 2.5e9, zeta: 0.07, zeta_sd: 0.002 }\n";
const M2: &str = "  - { mode: 2, omega_rad_s: 2.9e12, omega_sd_rad_s: 9e9, zeta: 0.05, zeta_sd: 0.0015 }\n";
const M3: &str = "  - { mode: 3, omega_rad_s: 5.3e12, omega_sd_rad_s: 1.6e10, zeta: 0.03, zeta_sd: 0.001 }\n";

#[test]
fn fewer_than_three_modes_is_an_input_error_naming_modes() {
    let data = MeasuredData::from_yaml(&yaml_with(&format!("{M1}{M2}"))).unwrap();
    let e = diagnose(&data, &DiagnoseSettings::quick()).unwrap_err();
    assert_eq!(e.field, "modes");
}

#[test]
fn bad_fields_are_named() {
    let neg = M3.replace("zeta_sd: 0.001", "zeta_sd: -0.001");
    let e = MeasuredData::from_yaml(&yaml_with(&format!("{M1}{M2}{neg}"))).unwrap_err();
    assert_eq!(e.field, "modes[2].zeta_sd");
    let e = MeasuredData::from_yaml(&yaml_with(&format!("{M1}{M2}{M2}"))).unwrap_err();
    assert_eq!(e.field, "modes[2].mode");
    let pm = yaml_with(&format!("{M1}{M2}{M3}"))
        .replace("elements: 20 }", "elements: 20, point_mass: { mass_kg: 1e-24, x_nm: 9.0 } }");
    let e = MeasuredData::from_yaml(&pm).unwrap_err();
    assert_eq!(e.field, "beam.point_mass.x_nm");
}

#[test]
fn cli_exits_2_and_leaves_out_dir_untouched_on_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("m.yaml");
    std::fs::write(&input, yaml_with(&format!("{M1}{M2}"))).unwrap();
    let out = dir.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("sentinel"), "x").unwrap();
    assert_eq!(cli::run(&input, Some(&out), true, &DiagnoseSettings::quick()), 2);
    assert_eq!(std::fs::read_to_string(out.join("sentinel")).unwrap(), "x");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2, "no temporary directory left behind");
}

#[test]
fn report_directory_is_written_and_json_is_shaped() {
    let case = synthetic::generate(3, Some(nanobeam::diagnose::ModelClass::ExtraRelaxation));
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("m.yaml");
    std::fs::write(&input, serde_yaml::to_string(&case.file).unwrap()).unwrap();
    let out = dir.path().join("out");
    assert_eq!(cli::run(&input, Some(&out), false, &DiagnoseSettings::quick()), 0);
    for f in ["report.md", "diagnosis.json", "residuals.svg", "probabilities.svg", "posterior.svg"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("diagnosis.json")).unwrap()).unwrap();
    for key in ["misfit_detected", "misfit", "candidates", "cause", "gain"] {
        assert!(v.get(key).is_some(), "{key} missing");
    }
    let c = &v["candidates"][0];
    for key in ["extension", "log_evidence", "log_evidence_laplace", "log_bayes_factor", "probability", "posterior"] {
        assert!(c.get(key).is_some(), "candidate.{key} missing");
    }
    assert!(["omega", "zeta"].contains(&v["misfit"][0]["quantity"].as_str().unwrap()));
}
