//! Identified modes → a measured-data file (`nanobeam identify`'s output,
//! read unchanged by `calibrate` and `diagnose`).
//!
//! # Physical mode numbers
//! The measured-data file refers to physical modes (1-based, by |s|, eq. 34),
//! but a record only shows resonances. The identified modes, sorted by
//! frequency, are matched to the modes the `--beam` model predicts (its
//! first K + 4, K identified) by the order-preserving one-to-one assignment
//! m₁ < m₂ < … < m_K that minimises Σᵢ (ln ωᵢ − ln ω̂_{mᵢ})² (dynamic
//! programming). Order preservation is physics: modes keep their order under
//! the model's error; skipping a predicted mode is allowed (a mode with a
//! node at the force or the sensor is absent from the record).
//!
//! **Ambiguity.** The nominal beam may lack effects (nonlocality, the
//! relaxation stiffening) that move frequencies by tens of percent, so
//! closeness alone can mislead. A numbering is refused as ambiguous when the
//! best assignment with a *different lowest mode number* is nearly as good:
//! its RMS log-misfit exceeds the best one's by less than
//! [`AMBIGUITY_MARGIN`] (0.1 in ln ω ≈ 10 % in frequency, the scale of the
//! effects a nominal beam leaves out). The user then states the lowest
//! mode's number (`--first-mode N`), which fixes m₁ = N; the rest follows
//! from the same assignment.

use crate::beam::{modal, BeamSpec};
use crate::calibration::measured::{MeasuredData, MeasuredFile, ModeObservation};
use crate::error::InputError;

/// Minimum RMS log-misfit advantage of the chosen numbering over the best
/// numbering with another lowest mode (see the module doc).
pub const AMBIGUITY_MARGIN: f64 = 0.1;
/// Predicted modes beyond the identified count that the assignment may use.
pub const EXTRA_PREDICTED: usize = 4;

/// Physical mode numbers for identified frequencies (sorted ascending).
pub fn number_modes(
    beam: &BeamSpec,
    omegas_rad_s: &[f64],
    first_mode: Option<usize>,
) -> Result<Vec<usize>, InputError> {
    let k = omegas_rad_s.len();
    if first_mode == Some(0) {
        return Err(InputError::new("--first-mode", 0, ">= 1 (mode numbers are 1-based)"));
    }
    let n_pred = k + EXTRA_PREDICTED + first_mode.unwrap_or(1) - 1;
    let predicted = modal(beam, n_pred).map_err(|e| {
        InputError::new(
            "--beam",
            format!("{n_pred} predicted modes"),
            format!("a beam whose first modes compute ({e})"),
        )
    })?;
    let logs: Vec<f64> = predicted.modes.iter().map(|m| m.omega_rad_s.ln()).collect();
    let ids: Vec<f64> = omegas_rad_s.iter().map(|w| w.ln()).collect();
    let rms = |c: f64| (c / k as f64).sqrt();
    let best = |first: Option<usize>| assign(&ids, &logs, first);
    if let Some(f) = first_mode {
        return best(Some(f - 1)).map(|(_, m)| m.into_iter().map(|j| j + 1).collect()).ok_or_else(|| {
            InputError::new(
                "--first-mode",
                f,
                format!("<= {} (the beam model's modes above it must hold the rest)", logs.len() - k + 1),
            )
        });
    }
    let (cost, modes) =
        best(None).ok_or_else(|| InputError::new("--beam", "(no assignment)", "a beam model with enough modes"))?;
    let runner_up = (0..logs.len())
        .filter(|&f| f != modes[0])
        .filter_map(|f| best(Some(f)).map(|(c, _)| c))
        .fold(f64::INFINITY, f64::min);
    if rms(runner_up) - rms(cost) < AMBIGUITY_MARGIN {
        return Err(InputError::new(
            "--first-mode",
            "(not given)",
            format!(
                "a value: numbering the lowest identified mode ({:.4e} rad/s) as mode {} or another mode fits the --beam model almost equally (RMS ln-misfit {:.3} vs {:.3}); state its physical number",
                omegas_rad_s[0],
                modes[0] + 1,
                rms(cost),
                rms(runner_up)
            ),
        ));
    }
    Ok(modes.into_iter().map(|j| j + 1).collect())
}

/// Order-preserving one-to-one assignment of `ids` to `preds` minimising the
/// squared distance, optionally with the first one fixed to `first`.
/// Returns (cost, 0-based predicted indices).
fn assign(ids: &[f64], preds: &[f64], first: Option<usize>) -> Option<(f64, Vec<usize>)> {
    let (k, n) = (ids.len(), preds.len());
    if k == 0 || k > n {
        return None;
    }
    let inf = f64::INFINITY;
    let mut cost = vec![vec![inf; n]; k];
    let mut from = vec![vec![usize::MAX; n]; k];
    for j in 0..n {
        if first.is_none_or(|f| f == j) {
            cost[0][j] = (ids[0] - preds[j]).powi(2);
        }
    }
    for i in 1..k {
        let (mut best, mut arg) = (inf, usize::MAX);
        for j in 1..n {
            if cost[i - 1][j - 1] < best {
                best = cost[i - 1][j - 1];
                arg = j - 1;
            }
            if best < inf {
                cost[i][j] = best + (ids[i] - preds[j]).powi(2);
                from[i][j] = arg;
            }
        }
    }
    let (mut j, total) = cost[k - 1].iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).map(|(j, &c)| (j, c))?;
    if !total.is_finite() {
        return None;
    }
    let mut out = vec![0; k];
    for i in (0..k).rev() {
        out[i] = j;
        j = from[i][j];
    }
    Some((total, out))
}

/// The measured-data file of identified modes on `beam`, validated as
/// `calibrate` and `diagnose` will read it.
pub fn measured_file(beam: BeamSpec, modes: Vec<ModeObservation>) -> Result<MeasuredFile, InputError> {
    let file =
        MeasuredFile { beam, modes, held_out_modes: vec![], mode_scans: vec![], parameters: None, sampler: None };
    MeasuredData::from_file(file.clone())?;
    Ok(file)
}

/// YAML text of a measured-data file, with a header comment.
pub fn to_yaml(file: &MeasuredFile, comment: &str) -> String {
    let body = serde_yaml::to_string(file).expect("plain data serialises");
    let mut out: String = comment.lines().map(|l| format!("# {l}\n")).collect();
    out.push_str(&body);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assignment_is_order_preserving_and_may_skip() {
        let preds: Vec<f64> = [1.0f64, 4.0, 9.0, 16.0, 25.0].iter().map(|v| v.ln()).collect();
        let ids: Vec<f64> = [1.05f64, 8.7, 15.0].iter().map(|v| v.ln()).collect();
        assert_eq!(assign(&ids, &preds, None).unwrap().1, vec![0, 2, 3]);
        assert_eq!(assign(&ids, &preds, Some(1)).unwrap().1, vec![1, 2, 3]);
        assert!(assign(&ids, &preds, Some(4)).is_none());
    }
}
