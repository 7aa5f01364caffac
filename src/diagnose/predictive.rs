//! The predictive engine: the predictions of observables at every posterior
//! draw of a model (the misfit tests, the gain, the next measurement).

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use crate::calibration::posterior::relative_amplitudes;
use crate::calibration::{MeasuredData, Observable, Quantity};

use super::evidence::ModelRun;
use super::ppc::{self, Check, Draws};

/// The leverage-corrected residual test ([`ppc::check_fitted`]) of every
/// fitted observable of `data` under `run`'s posterior.
pub fn fitted_checks(run: &ModelRun, data: &MeasuredData) -> Vec<Check> {
    fitted_checks_and_omnibus(run, data).0
}

/// [`fitted_checks`] and the omnibus check ([`ppc::omnibus`]) of the same
/// draws: what [`ppc::misfit_detected`] decides on.
pub fn fitted_checks_and_omnibus(run: &ModelRun, data: &MeasuredData) -> (Vec<Check>, ppc::Omnibus) {
    let fitted = data.fitted_observables();
    let draws = predictive(run, &fitted, data.max_mode(), &AtomicU64::new(0));
    (ppc::check_fitted(&fitted, &draws), ppc::omnibus(&fitted, &draws))
}

/// Predictions of `obs` at every posterior sample (failed samples dropped), and β² per sample.
/// One modal solve per posterior draw of `run`, added to `solves`. Relative
/// amplitudes among `obs` must be those of `run`'s fitted scans, in order
/// (as [`MeasuredData::fitted_observables`] lists them); their FRF
/// factorisations are not counted (they run only when scans are fitted).
pub(crate) fn predictive(run: &ModelRun, obs: &[Observable], max_mode: usize, solves: &AtomicU64) -> Draws {
    solves.fetch_add(run.draws.len() as u64, Ordering::Relaxed);
    let post = &run.posterior;
    let scans = post.inner().scans();
    let has_amplitudes = obs.iter().any(|o| o.quantity == Quantity::RelativeAmplitude);
    let rows: Vec<Option<(Vec<f64>, f64)>> = run
        .draws
        .par_iter()
        .map(|u| {
            let x = post.to_inner(u);
            let beam = post.inner().beam_at(&x);
            let modes = crate::beam::modal(&beam, max_mode).ok()?.modes;
            let omega_of = |n: usize| modes.iter().find(|m| m.mode == n).map(|m| m.omega_rad_s);
            let amplitudes = if has_amplitudes { relative_amplitudes(&beam, scans, omega_of)? } else { vec![] };
            let mut next_amplitude = amplitudes.into_iter();
            let row: Option<Vec<f64>> = obs
                .iter()
                .map(|o| match o.quantity {
                    Quantity::RelativeAmplitude => next_amplitude.next(),
                    _ => o.predicted(&modes),
                })
                .collect();
            Some((row?, post.inner().beta_at(&x).powi(2)))
        })
        .collect();
    let (predictions, beta_sq) = rows.into_iter().flatten().unzip();
    Draws { predictions, beta_sq }
}
