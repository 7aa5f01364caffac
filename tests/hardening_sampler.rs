//! Issue 11 (sampler): no panic when C0 underflows; a run that cannot
//! sample is an error, not "ESS 8000".

use nanobeam::bayes::chains::chain_rng;
use nanobeam::bayes::dram::{run_chain, DramSettings};
use nanobeam::bayes::Posterior;
use nanobeam::calibration::{calibrate_posterior, CalibrateOptions, SamplingError};
use rand::{Rng, RngCore};

/// Standard normal in d dimensions.
struct Gauss(usize);

impl Posterior for Gauss {
    fn names(&self) -> Vec<String> {
        (0..self.0).map(|i| format!("x{i}")).collect()
    }
    fn dim(&self) -> usize {
        self.0
    }
    fn log_prior(&self, _: &[f64]) -> f64 {
        0.0
    }
    fn log_likelihood(&self, t: &[f64]) -> f64 {
        -0.5 * t.iter().map(|x| x * x).sum::<f64>()
    }
    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        (0..self.0).map(|_| rng.gen_range(-1.0..1.0)).collect()
    }
}

/// A valid 300-state chain (adaptation from state 100).
fn short_chain() -> DramSettings {
    DramSettings {
        draws_per_chain: 300,
        burn_in: 10,
        nonadaptive_draws: 100,
        adaptation_start: 100,
        covariance_skip: 50,
        ..Default::default()
    }
}

#[test]
fn an_underflowing_proposal_covariance_does_not_panic() {
    let s = short_chain();
    // sd² = 1e-400 underflows to 0: C0 = diag(sd²) is not factorisable
    let out =
        run_chain(&Gauss(2), &s, &[1e-200, 1e-200], &[0.5, 0.5], &mut chain_rng(1, 0), None).expect("valid settings");
    assert_eq!(out.draws.len(), 300);
    assert!(out.draws.iter().flatten().all(|x| x.is_finite()));
}

/// `run_chain` is public: it checks its settings and inputs itself instead
/// of assuming a caller did, and names the offending field.
#[test]
fn run_chain_rejects_bad_settings_and_inputs_by_name() {
    let good = short_chain();
    let run = |s: &DramSettings, c0: &[f64], start: &[f64]| {
        run_chain(&Gauss(start.len()), s, c0, start, &mut chain_rng(1, 0), None).map(|_| ()).unwrap_err().field
    };
    let bad_burn = DramSettings { burn_in: 300, ..good.clone() };
    assert_eq!(run(&bad_burn, &[0.1, 0.1], &[0.5, 0.5]), "sampler.draws_per_chain");
    let bad_gamma = DramSettings { dr_shrink_factors: vec![0.0], ..good.clone() };
    assert_eq!(run(&bad_gamma, &[0.1, 0.1], &[0.5, 0.5]), "sampler.dr_shrink_factors[0]");
    assert_eq!(run(&good, &[0.1], &[0.5, 0.5]), "c0_sd");
    assert_eq!(run(&good, &[0.1, -1.0], &[0.5, 0.5]), "c0_sd[1]");
    assert_eq!(run(&good, &[0.1, 0.1], &[0.5, f64::NAN]), "start[1]");
    assert_eq!(run(&good, &[], &[]), "start");
}

/// Finite only on the lattice k/1024 of [0, 1]: a random-walk proposal never
/// lands on it, so no chain can move.
struct Lattice;

impl Posterior for Lattice {
    fn names(&self) -> Vec<String> {
        vec!["x".into()]
    }
    fn dim(&self) -> usize {
        1
    }
    fn log_prior(&self, t: &[f64]) -> f64 {
        let k = t[0] * 1024.0;
        if (0.0..=1.0).contains(&t[0]) && k == k.round() {
            0.0
        } else {
            f64::NEG_INFINITY
        }
    }
    fn log_likelihood(&self, _: &[f64]) -> f64 {
        0.0
    }
    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        vec![rng.gen_range(0..=1024) as f64 / 1024.0]
    }
}

fn small() -> DramSettings {
    DramSettings {
        draws_per_chain: 400,
        burn_in: 100,
        nonadaptive_draws: 200,
        adaptation_start: 200,
        covariance_skip: 100,
        chains: 2,
        multistart_points: 8,
        ..DramSettings::default()
    }
}

#[test]
fn frozen_chains_are_an_error_not_a_converged_result() {
    let r = calibrate_posterior(&Lattice, &[0.013], &small(), &CalibrateOptions::default());
    assert!(matches!(r, Err(SamplingError::Frozen { .. })), "{r:?}");
}

/// −∞ everywhere.
struct Nowhere;

impl Posterior for Nowhere {
    fn names(&self) -> Vec<String> {
        vec!["x".into()]
    }
    fn dim(&self) -> usize {
        1
    }
    fn log_prior(&self, _: &[f64]) -> f64 {
        f64::NEG_INFINITY
    }
    fn log_likelihood(&self, _: &[f64]) -> f64 {
        0.0
    }
    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        vec![rng.gen()]
    }
}

#[test]
fn no_valid_state_is_an_error() {
    let r = calibrate_posterior(&Nowhere, &[0.01], &small(), &CalibrateOptions::default());
    assert!(matches!(r, Err(SamplingError::NoValidState { draws: 8, .. })), "{r:?}");
}

#[test]
fn a_healthy_run_has_no_warnings_and_they_reach_the_json() {
    let mut s = small();
    s.draws_per_chain = 4000;
    s.burn_in = 500;
    s.chains = 4;
    let r = calibrate_posterior(&Gauss(2), &[0.5, 0.5], &s, &CalibrateOptions::default()).unwrap();
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let json = serde_json::to_value(r.json()).unwrap();
    assert_eq!(json["warnings"], serde_json::json!([]));
    assert_eq!(nanobeam::calibration::output::summary_json(&r)["warnings"], serde_json::json!([]));
}

#[test]
fn a_doubtful_run_warns_and_says_so_in_the_json() {
    // 2 chains of 40 kept draws with a step 1e-3 of the posterior's scale:
    // nothing mixes, R-hat and ESS are flagged but the numbers are finite
    let mut s = small();
    s.draws_per_chain = 140;
    s.nonadaptive_draws = 139;
    s.adaptation_start = 139;
    s.covariance_skip = 100;
    let r = calibrate_posterior(&Gauss(1), &[1e-3], &s, &CalibrateOptions::default()).unwrap();
    assert!(r.warnings.iter().any(|w| w.contains("ESS")), "{:?}", r.warnings);
    let json = serde_json::to_value(r.json()).unwrap();
    assert_eq!(json["warnings"].as_array().unwrap().len(), r.warnings.len());
}
