//! The measurement that would decide between two models the data cannot
//! separate: the unmeasured observable (mode ≤ [`MAX_MODE`], ω or ζ) whose
//! posterior predictive distributions under the two models differ most, in
//! units of the expected measurement sd.
//!
//! For observable q, model k's predictive has mean m_k and variance v_k over
//! its posterior samples; a new measurement adds noise of sd σ_q, taken as the
//! median relative sd of the fitted modes' ω (or ζ) times the predicted value.
//! The separation is |m_a − m_b| / √(σ_q² + (v_a + v_b)/2): the number of
//! combined sds between the two predictions. Measuring the observable with the
//! largest separation is the most informative single addition to the data.

use std::sync::atomic::AtomicU64;

use serde::Serialize;

use crate::calibration::{MeasuredData, Observable, Quantity};

use super::evidence::ModelRun;

/// Highest mode number considered for a new measurement.
pub const MAX_MODE: usize = 8;

/// Smallest separation worth suggesting: an observable whose predictions
/// differ by s combined sds moves the log evidence of the pair by ≈ s²/2 when
/// measured, so below 1 sd (≤ 0.5 nats) no single measurement is expected to
/// decide; then there is no suggestion (`null`), and the alternatives stand:
/// the pair cannot be separated by ω or ζ of modes up to [`MAX_MODE`].
pub const MIN_SEPARATION_SD: f64 = 1.0;

/// The suggested next measurement.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct NextMeasurement {
    pub mode: usize,
    pub quantity: &'static str,
    /// The two models it would separate (selected first).
    pub between: [String; 2],
    /// Predictive means under the two models (rad/s for ω).
    pub predicted: [f64; 2],
    /// The assumed measurement sd (relative sds of the fitted modes, median).
    pub measurement_sd: f64,
    /// |m_a − m_b| / √(σ² + (v_a + v_b)/2).
    pub separation_sd: f64,
}

/// The best unmeasured observable to separate `a` from the first of
/// `rivals` (in their order) that some observable predicted by both
/// separates by [`MIN_SEPARATION_SD`]; `a`'s predictive draws are computed
/// once. The forward solves of the predictive draws are added to `solves`.
pub fn next_measurement<'r>(
    data: &MeasuredData,
    a: &ModelRun,
    rivals: impl IntoIterator<Item = &'r ModelRun>,
    solves: &AtomicU64,
) -> Option<NextMeasurement> {
    let measured: Vec<usize> = data.modes.iter().chain(&data.held_out_modes).map(|m| m.mode).collect();
    let rel = |f: fn(&crate::calibration::ModeObservation) -> f64| {
        let mut r: Vec<f64> = data.modes.iter().map(f).collect();
        r.sort_by(f64::total_cmp);
        r[r.len() / 2]
    };
    let rel_omega = rel(|m| m.omega_sd_rad_s / m.omega_rad_s);
    let rel_zeta = rel(|m| m.zeta_sd / m.zeta.abs().max(f64::MIN_POSITIVE));
    let candidates: Vec<Observable> = (1..=MAX_MODE)
        .filter(|m| !measured.contains(m))
        .flat_map(|mode| {
            [Quantity::Omega, Quantity::Zeta].map(|quantity| Observable { mode, quantity, value: 0.0, sd: 0.0 })
        })
        .collect();
    if candidates.is_empty() {
        return None;
    }
    let da = super::predictive(a, &candidates, MAX_MODE, solves);
    if da.predictions.is_empty() {
        return None;
    }
    rivals.into_iter().find_map(|b| {
        let db = super::predictive(b, &candidates, MAX_MODE, solves);
        if db.predictions.is_empty() {
            return None;
        }
        candidates
            .iter()
            .enumerate()
            .map(|(j, o)| {
                let (ma, va) = mean_var(da.predictions.iter().map(|p| p[j]));
                let (mb, vb) = mean_var(db.predictions.iter().map(|p| p[j]));
                let rel = if o.quantity == Quantity::Omega { rel_omega } else { rel_zeta };
                let sd = rel * 0.5 * (ma.abs() + mb.abs());
                let separation = (ma - mb).abs() / (sd * sd + 0.5 * (va + vb)).sqrt();
                NextMeasurement {
                    mode: o.mode,
                    quantity: o.quantity.name(),
                    between: [a.model.name(), b.model.name()],
                    predicted: [ma, mb],
                    measurement_sd: sd,
                    separation_sd: separation,
                }
            })
            .filter(|n| n.separation_sd.is_finite())
            .max_by(|x, y| x.separation_sd.total_cmp(&y.separation_sd))
            .filter(|n| n.separation_sd >= MIN_SEPARATION_SD)
    })
}

fn mean_var(x: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = x.clone().count() as f64;
    let m = x.clone().sum::<f64>() / n;
    (m, x.map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0))
}
