//! The MAP search of a diagnosed model (`diagnose::evidence`): started from
//! the MAP of a model with one cause fewer, it finds the narrow mode of a
//! relaxation + mass posterior that TMCMC and the global prior-draw search
//! both pass by.

mod synthetic;

use nanobeam::bayes::Posterior;
use nanobeam::diagnose::evidence::run_model;
use nanobeam::diagnose::{model_posterior, DiagnoseSettings, Model, ModelClass, NominalScales};
use synthetic::{generate_hidden, Hidden};

/// Largest shortfall of the MAP's log-likelihood below the exact fit that
/// still counts as having found the mode. Every prior of these models is
/// uniform in the sampling coordinates (the log of a log-uniform
/// parameter), so the MAP maximises the likelihood, and on noise-free data
/// the truth, inside the priors, fits every observable exactly: the MAP's
/// log-likelihood is at least the exact fit's, less what a stopped simplex
/// leaves (0.03 nats measured with this test's seeds). A missed mode falls short by
/// far more: with this test's seeds and no sub-model the MAP ends 8.8 nats
/// below (the diagnosis's seeds: 21.3), measured 2026-11-27. One nat
/// separates the two.
const FOUND_MODE_NATS: f64 = 1.0;

/// Hidden pair case 339 (a second relaxation and a point mass, 4 modes),
/// its noise-free data: the true pair's model started from the relaxation
/// model's MAP reaches the exact fit.
#[test]
fn relaxation_and_mass_model_started_from_the_relaxation_model_reaches_the_exact_fit() {
    let causes = [ModelClass::ExtraRelaxation, ModelClass::AttachedMass];
    let case = generate_hidden(339, &Hidden::causes(&causes));
    let data = case.noise_free_data();
    let scales = NominalScales::of(&data.beam, data.max_mode()).expect("the generated beam solves");
    let posterior =
        |m: &Model| model_posterior(m, &data.parameters, &data.beam, &data.modes, &data.mode_scans, &scales);
    let settings = DiagnoseSettings::quick();

    let sub = Model::with(&[ModelClass::ExtraRelaxation]);
    let sub_run = run_model(sub.clone(), posterior(&sub), &settings, 1, &[]).expect("the relaxation model runs");
    let pair = Model::with(&causes);
    let run = run_model(pair.clone(), posterior(&pair), &settings, 2, &[&sub_run]).expect("the pair model runs");

    // ln L of a zero residual: −Σ ln σ − (n/2) ln 2π over the ω and ζ of every mode
    let exact: f64 =
        data.modes.iter().map(|m| -(m.omega_sd_rad_s.ln() + m.zeta_sd.ln()) - (2.0 * std::f64::consts::PI).ln()).sum();
    let at_map = run.posterior.log_likelihood(&run.map);
    assert!(at_map >= exact - FOUND_MODE_NATS, "MAP log-likelihood {at_map:.2} against the exact fit's {exact:.2}");
}
