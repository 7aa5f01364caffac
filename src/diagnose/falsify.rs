//! The measurement that would falsify a decided verdict.
//!
//! A decided cause is decided among the models the search compared: no
//! alternative within the margin explains the data without it. A model
//! outside the catalogue (an elastic foundation, a loss factor, a slack
//! tube, …) may explain the same modes as well, and the data in hand cannot
//! say so. What can is a new observable on which the selected model commits
//! to a value its rivals do not share: measured outside the selected model's
//! predictive interval, the verdict is falsified, whatever the truth is.
//!
//! **The rivals.** The strongest explanations the search built apart from
//! the selection: the runner-up (the best visited model, by evidence, that
//! does not hold every selected cause) and the best [`MAX_EXTENDED_RIVALS`]
//! visited models that hold the selected causes and one more, each among the
//! best [`MAX_TESTED_RIVALS`] of its kind (the verdict
//! plus an effect the data did not ask for). Models that misfit are no
//! rivals (the data already rule them out), unless no model that lacks a
//! selected cause fits: then the best of those stands in as the runner-up,
//! to show where the selection commits.
//!
//! **The observable.** Each unmeasured ω and ζ of modes ≤
//! [`next::MAX_MODE`](super::next::MAX_MODE), as in [`super::next`]: the
//! selected model's posterior predictive mean m and variance v, a rival's
//! m_r and v_r, the measurement's sd σ (the fitted modes' median relative
//! sd times the prediction) and the separation s_r = |m − m_r| / √(σ² + (v +
//! v_r)/2). The suggestion maximises Σ_r min(s_r, [`SEPARATION_CAP_SD`]): a
//! rival separated by 3 sd is ruled out by the measurement and gains nothing
//! from more, so the observable that rules out the most rivals at once wins,
//! and ties go to the larger smallest separation. The suggestion states the
//! selected model's prediction with its 95 % interval m ± 1.96√(v + σ²)
//! (predictive and measurement noise, Gaussian): a value outside it
//! falsifies the verdict at the 5 % level. Fed back as a fitted mode, the
//! measurement then either keeps the verdict, or turns it into another
//! name or `unexplained` (`tests/diagnose_falsify.rs`).

use std::sync::atomic::AtomicU64;

use serde::Serialize;

use super::evidence::ModelRun;
use super::next::{mean_var, relative_sds, MAX_MODE};
use super::ppc::Draws;
use crate::calibration::{MeasuredData, Observable, Quantity};

/// Visited models with the selected causes and one more that are asked as
/// rivals (the best by evidence).
pub const MAX_EXTENDED_RIVALS: usize = 2;

/// Candidates of each kind (lacking a selected cause; the selection plus
/// one cause) whose misfit is tested, best first: a test costs the model's
/// predictive draws, and a rival beyond the fourth by evidence adds little.
pub const MAX_TESTED_RIVALS: usize = 4;

/// A rival separated by this many combined sds is ruled out by the
/// measurement: separations beyond it gain nothing (module doc).
pub const SEPARATION_CAP_SD: f64 = 3.0;

/// z of a two-sided 95 % interval.
const Z95: f64 = 1.959_963_984_540_054;

/// One rival's prediction of the suggested observable.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RivalPrediction {
    pub model: String,
    /// Its posterior predictive mean (rad/s for ω).
    pub predicted: f64,
    /// |m − m_r| / √(σ² + (v + v_r)/2), module doc.
    pub separation_sd: f64,
}

/// The unmeasured observable that would falsify the selected model
/// (module doc).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct FalsifyingMeasurement {
    pub mode: usize,
    /// `omega` or `zeta`.
    pub quantity: &'static str,
    /// The selected model.
    pub model: String,
    /// Its posterior predictive mean (rad/s for ω).
    pub predicted: f64,
    /// Its 95 % interval for a measured value: predictive and measurement
    /// noise. A value outside falsifies the verdict.
    pub interval_95: [f64; 2],
    /// The assumed measurement sd (the fitted modes' median relative sd).
    pub measurement_sd: f64,
    /// The rivals it was chosen against, with their predictions.
    pub rivals: Vec<RivalPrediction>,
}

/// The falsifying measurement of `selected` against `rivals` (module doc),
/// `own` being `selected`'s [`unmeasured_draws`](super::next::unmeasured_draws); `None` when no rival's
/// predictions compute. The forward solves of the rivals' predictive draws
/// are added to `solves`.
pub fn falsifying_measurement(
    data: &MeasuredData,
    selected: &ModelRun,
    (candidates, own): &(Vec<Observable>, Draws),
    rivals: &[&ModelRun],
    solves: &AtomicU64,
) -> Option<FalsifyingMeasurement> {
    if rivals.is_empty() {
        return None;
    }
    let (rel_omega, rel_zeta) = relative_sds(data);
    let moments = |d: &Draws| -> Vec<(f64, f64)> {
        (0..candidates.len()).map(|j| mean_var(d.predictions.iter().map(|p| p[j]))).collect()
    };
    let predict = |run: &ModelRun| {
        let d = super::predictive::predictive(run, candidates, MAX_MODE, solves);
        (!d.predictions.is_empty()).then(|| moments(&d))
    };
    let own = moments(own);
    let theirs: Vec<(&ModelRun, Vec<(f64, f64)>)> = rivals.iter().filter_map(|r| Some((*r, predict(r)?))).collect();
    if theirs.is_empty() {
        return None;
    }
    let scored = candidates.iter().enumerate().filter_map(|(j, o)| {
        let (m, v) = own[j];
        let rel = if o.quantity == Quantity::Omega { rel_omega } else { rel_zeta };
        let sd = rel * m.abs();
        let rivals: Vec<RivalPrediction> = theirs
            .iter()
            .map(|(r, p)| {
                let (mr, vr) = p[j];
                RivalPrediction {
                    model: r.model.name(),
                    predicted: mr,
                    separation_sd: (m - mr).abs() / (sd * sd + 0.5 * (v + vr)).sqrt(),
                }
            })
            .collect();
        if !(m.is_finite() && v.is_finite() && rivals.iter().all(|r| r.separation_sd.is_finite())) {
            return None;
        }
        let key = rank(&rivals);
        let half = Z95 * (v + sd * sd).sqrt();
        let suggestion = FalsifyingMeasurement {
            mode: o.mode,
            quantity: o.quantity.name(),
            model: selected.model.name(),
            predicted: m,
            interval_95: [m - half, m + half],
            measurement_sd: sd,
            rivals,
        };
        Some((key, suggestion))
    });
    // the first of equal scores wins (candidates in mode order): deterministic
    scored
        .fold(None, |best: Option<((f64, f64), FalsifyingMeasurement)>, (key, s)| match &best {
            Some((k, _)) if !(key.0 > k.0 || (key.0 == k.0 && key.1 > k.1)) => best,
            _ => Some((key, s)),
        })
        .map(|(_, s)| s)
}

/// (Σ_r min(s_r, cap), min_r s_r): the suggestion's order, larger first
/// (module doc).
fn rank(rivals: &[RivalPrediction]) -> (f64, f64) {
    let score = rivals.iter().map(|r| r.separation_sd.min(SEPARATION_CAP_SD)).sum();
    let least = rivals.iter().map(|r| r.separation_sd).fold(f64::INFINITY, f64::min);
    (score, least)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rivals(s: &[f64]) -> Vec<RivalPrediction> {
        s.iter().map(|&separation_sd| RivalPrediction { model: "m".into(), predicted: 0.0, separation_sd }).collect()
    }

    /// The cap: a rival beyond 3 sd adds exactly the cap, so two rivals at 2
    /// sd outrank one at 10 sd and one at 0; equal sums go to the larger
    /// least separation.
    #[test]
    fn the_rank_prefers_ruling_out_more_rivals() {
        assert!(rank(&rivals(&[2.0, 2.0])) > rank(&rivals(&[10.0, 0.0])));
        assert_eq!(rank(&rivals(&[10.0])).0, SEPARATION_CAP_SD);
        assert!(rank(&rivals(&[1.5, 1.5])) > rank(&rivals(&[3.0, 0.0])));
    }
}
