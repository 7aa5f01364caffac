//! The InferenceData file of a calibration has the structure ArviZ's
//! `from_netcdf` reads (checked here by reading it back with the pure-Rust
//! netcdf-reader, so CI needs no Python): groups, dimensions, variables,
//! shapes, values and attributes.

use nanobeam::calibration::output::{inference_data, InferenceContext};
use nanobeam::calibration::{calibrate, BeamPosterior, CalibrateOptions, MeasuredData, ModeScan, ScanPoint};
use nanobeam::report::inference_data::{Group, InferenceData, Variable};
use netcdf_reader::NcFile;

fn measured() -> MeasuredData {
    let yaml = r#"
beam: { length_nm: 8.12, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0,
        support: simply-supported, elements: 12 }
modes:
  - { mode: 1, omega_rad_s: 8.38e11, omega_sd_rad_s: 2.5e9, zeta: 0.0712, zeta_sd: 0.0021 }
  - { mode: 2, omega_rad_s: 3.0e12, omega_sd_rad_s: 9.0e9, zeta: 0.05, zeta_sd: 0.0015 }
sampler: { draws_per_chain: 1200, burn_in: 200, nonadaptive_draws: 300, adaptation_start: 300,
           covariance_skip: 100, chains: 4, seed: 7, multistart_points: 32 }
"#;
    MeasuredData::from_yaml(yaml).expect("valid measured data")
}

/// Row-major values of an n-d array.
fn flat<A: IntoIterator<Item = f64> + Clone>(a: &A) -> Vec<f64> {
    a.clone().into_iter().collect()
}

#[test]
fn calibration_inference_data_has_the_arviz_groups() {
    let data = measured();
    let result = calibrate(&data, &CalibrateOptions::default()).expect("calibrates");
    let post = BeamPosterior::new(&data, data.parameters.clone());
    let idata = inference_data(&result, &InferenceContext { posterior: &post, seed: 7 });
    let bytes = idata.to_netcdf().unwrap();
    let file = NcFile::from_bytes(&bytes).unwrap();
    let root = file.root_group().unwrap();
    let (chains, draws) = (4u64, 1000u64);
    let posterior = root.group("posterior").expect("posterior group");
    assert_eq!(posterior.dimension("chain").unwrap().size, chains);
    assert_eq!(posterior.dimension("draw").unwrap().size, draws);
    for (k, name) in result.names.iter().enumerate() {
        let v = posterior.variable(name).unwrap_or_else(|| panic!("posterior/{name}"));
        assert_eq!(v.shape(), vec![chains, draws]);
        let values = file.read_variable_as_f64(&format!("posterior/{name}")).unwrap();
        // Chain 2, draw 5 is state burn_in + 5 of chain 2 (no thinning at 1000 kept draws).
        assert_eq!(flat(&values)[2 * draws as usize + 5], result.chains[2].draws[result.burn_in + 5][k]);
    }
    let stats = root.group("sample_stats").unwrap();
    assert_eq!(stats.variable("lp").unwrap().shape(), vec![chains, draws]);
    assert_eq!(stats.variable("acceptance_rate_per_dr_stage").unwrap().shape(), vec![chains, 2]);
    let ll = root.group("log_likelihood").unwrap();
    let obs = root.group("observed_data").unwrap();
    for name in ["omega_rad_s", "zeta"] {
        assert_eq!(ll.variable(name).unwrap().shape(), vec![chains, draws, 2]);
        assert_eq!(obs.variable(name).unwrap().shape(), vec![2]);
    }
    // The pointwise terms sum to the log likelihood: lp − log prior at a draw.
    let ll_w = file.read_variable_as_f64("log_likelihood/omega_rad_s").unwrap();
    let ll_z = file.read_variable_as_f64("log_likelihood/zeta").unwrap();
    let theta = &result.chains[1].draws[result.burn_in + 10];
    let at = |a: &[f64], m: usize| a[(draws as usize + 10) * 2 + m];
    let (ll_w, ll_z) = (flat(&ll_w), flat(&ll_z));
    let sum: f64 = (0..2).map(|m| at(&ll_w, m) + at(&ll_z, m)).sum();
    use nanobeam::bayes::Posterior;
    let direct = post.log_likelihood(theta);
    assert!((sum - direct).abs() <= 1e-9 * direct.abs().max(1.0), "{sum} vs {direct}");
    let prior = root.group("prior").unwrap();
    assert_eq!(prior.variable(&result.names[0]).unwrap().shape(), vec![1, 1000]);
    for g in ["posterior", "sample_stats", "log_likelihood", "observed_data", "prior"] {
        let group = root.group(g).unwrap();
        assert!(group.attribute("nanobeam_version").is_some(), "{g} lacks nanobeam_version");
        assert!(group.attribute("seed").is_some(), "{g} lacks seed");
    }
}

#[test]
fn a_variable_whose_values_do_not_fill_its_dimensions_is_an_error() {
    let bad = InferenceData {
        groups: vec![Group {
            name: "posterior".into(),
            variables: vec![Variable {
                name: "x".into(),
                dims: vec![("chain".into(), 2), ("draw".into(), 3)],
                values: vec![0.0; 5],
            }],
            attributes: vec![],
        }],
        attributes: vec![],
    };
    let err = bad.to_netcdf().unwrap_err().to_string();
    assert!(err.contains("posterior/x"), "{err}");
}

/// A fitted mode scan adds `relative_amplitude` over a `scan_point`
/// dimension to `log_likelihood` and `observed_data`, and the pointwise terms
/// of all three variables still sum to the posterior's log likelihood (the
/// scan's terms are in it, in the file's order).
#[test]
fn a_fitted_mode_scan_is_a_pointwise_variable_of_its_own() {
    let mut data = measured();
    // mode 1 of a simply supported beam driven near one end: ≈ sin(πx/L) over its largest point
    let points: Vec<ScanPoint> = [(2.03, 0.707), (4.06, 1.0), (6.09, 0.707)]
        .iter()
        .map(|&(x_nm, a)| ScanPoint { x_nm, relative_amplitude: a, relative_amplitude_sd: 0.02 })
        .collect();
    data.mode_scans = vec![ModeScan { mode: 1, drive_x_nm: 7.9, points }];
    let result = calibrate(&data, &CalibrateOptions::default()).expect("calibrates");
    let post = BeamPosterior::new(&data, data.parameters.clone());
    let bytes = inference_data(&result, &InferenceContext { posterior: &post, seed: 7 }).to_netcdf().unwrap();
    let file = NcFile::from_bytes(&bytes).unwrap();
    let root = file.root_group().unwrap();
    let draws = 1000usize;
    let ll = root.group("log_likelihood").unwrap();
    assert_eq!(ll.variable("relative_amplitude").unwrap().shape(), vec![4, draws as u64, 3]);
    let observed = flat(&file.read_variable_as_f64("observed_data/relative_amplitude").unwrap());
    assert_eq!(observed, vec![0.707, 1.0, 0.707]);
    let read = |name: &str| flat(&file.read_variable_as_f64(&format!("log_likelihood/{name}")).unwrap());
    let (w, z, a) = (read("omega_rad_s"), read("zeta"), read("relative_amplitude"));
    let (chain, draw) = (3, 17);
    let row = chain * draws + draw;
    let sum: f64 =
        (0..2).map(|m| w[row * 2 + m] + z[row * 2 + m]).sum::<f64>() + (0..3).map(|k| a[row * 3 + k]).sum::<f64>();
    use nanobeam::bayes::Posterior;
    let direct = post.log_likelihood(&result.chains[chain].draws[result.burn_in + draw]);
    assert!(direct.is_finite());
    assert!((sum - direct).abs() <= 1e-9 * direct.abs().max(1.0), "{sum} vs {direct}");
}
