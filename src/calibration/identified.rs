//! Identified modes → a measured-data file (`nanobeam identify`'s output,
//! read unchanged by `calibrate` and `diagnose`).
//!
//! # Physical mode numbers
//! The measured-data file refers to physical modes (1-based, by |s|, eq. 34),
//! but a record only shows resonances. The identified modes, sorted by
//! frequency, are matched to the modes the `--beam` model predicts (its
//! first K + 4, K identified) by the order-preserving one-to-one assignment
//! m₁ < m₂ < … < m_K that minimises Σᵢ d(ln ωᵢ, band_{mᵢ})² (dynamic
//! programming). Order preservation is physics: modes keep their order under
//! the model's error; skipping a predicted mode is allowed (a mode with a
//! node at the force or the sensor is absent from the record).
//!
//! **The bands.** The nominal beam is uncertain where calibration will free
//! it: e0a over its prior range ([`E0A_RANGE_NM`], the default prior of
//! `calibration::parameters::ParameterSet::paper_n1`, widened to hold the
//! file's own e0a). Nonlocality softens each mode monotonically in e0a, so
//! mode j's predicted frequency lies in the band [ω_j(e0a_max), ω_j(e0a_min)];
//! d is the distance of ln ωᵢ from that band (0 inside). A short beam's
//! higher modes can move by a factor of two over the range, so bands
//! overlap: a frequency inside two bands fits both numbers.
//!
//! **Ambiguity.** The nominal beam may also lack effects (shear, the
//! relaxation stiffening) that move frequencies by tens of percent, so
//! closeness alone can mislead. For every identified mode i, the best
//! assignment that gives it a *different number* than the best one is
//! computed; when its RMS log-misfit exceeds the best one's by less than
//! [`AMBIGUITY_MARGIN`] (0.1 in ln ω ≈ 10 % in frequency, the scale of the
//! effects a nominal beam leaves out) the numbering is refused as
//! ambiguous, naming the mode and both numbers; likewise for the whole
//! numbering shifted to another lowest mode. An alternative that skips more
//! predicted modes than the best one does not count (a skip needs a node at
//! the force or the sensor; with the bands of a short beam every mode could
//! otherwise be renumbered into a gap at no cost). `--first-mode N` states
//! the lowest mode's number; the others are then N + 1, N + 2, … (no
//! skipped mode) when each lies within [`AMBIGUITY_MARGIN`] of its band,
//! otherwise the best assignment from N, which must itself be unambiguous.
//!
//! Modes are numbered against every mode the record holds clearly, never
//! against a chosen subset (`--modes K`): a subset that leaves a mode out
//! would otherwise be renumbered into the gap.

use crate::beam::{modal, BeamSpec};
use crate::calibration::measured::{MeasuredData, MeasuredFile, ModeObservation};
use crate::error::InputError;

/// Minimum RMS log-misfit advantage of the chosen numbering over the best
/// numbering that changes any one mode's number (see the module doc).
pub const AMBIGUITY_MARGIN: f64 = 0.1;
/// Predicted modes beyond the identified count that the assignment may use.
pub const EXTRA_PREDICTED: usize = 4;
/// The e0a range (nm) the numbering considers: the default prior's.
pub const E0A_RANGE_NM: (f64, f64) = (0.0, 2.0);

/// Predicted ln-frequency bands [lo, hi] of the first `n` modes of `beam`
/// over its e0a range.
fn predicted_bands(beam: &BeamSpec, n: usize) -> Result<Vec<(f64, f64)>, InputError> {
    let lo = E0A_RANGE_NM.0.min(beam.nonlocal_e0a_nm);
    let hi = E0A_RANGE_NM.1.max(beam.nonlocal_e0a_nm);
    let mut sets = Vec::new();
    for e0a in [lo, hi] {
        let b = BeamSpec { nonlocal_e0a_nm: e0a, ..beam.clone() };
        let predicted = modal(&b, n).map_err(|e| {
            InputError::new(
                "--beam",
                format!("{n} predicted modes at e0a = {e0a} nm"),
                format!("a beam whose first modes compute over e0a in [{lo}, {hi}] nm ({e})"),
            )
        })?;
        let mut logs: Vec<f64> = predicted.modes.iter().map(|m| m.omega_rad_s.ln()).collect();
        logs.sort_by(f64::total_cmp);
        sets.push(logs);
    }
    let m = sets[0].len().min(sets[1].len());
    Ok((0..m).map(|j| (sets[0][j].min(sets[1][j]), sets[0][j].max(sets[1][j]))).collect())
}

/// Distance of `x` from the band `b` (0 inside).
fn band_distance(x: f64, b: (f64, f64)) -> f64 {
    if x < b.0 {
        b.0 - x
    } else if x > b.1 {
        x - b.1
    } else {
        0.0
    }
}

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
    if k == 0 {
        return Err(InputError::new("modes", "none identified", "at least one identified mode to number"));
    }
    let n_pred = k + EXTRA_PREDICTED + first_mode.unwrap_or(1) - 1;
    let bands = predicted_bands(beam, n_pred)?;
    let ids: Vec<f64> = omegas_rad_s.iter().map(|w| w.ln()).collect();
    let cost: Vec<Vec<f64>> =
        ids.iter().map(|&x| bands.iter().map(|&b| band_distance(x, b).powi(2)).collect()).collect();
    let rms = |c: f64| (c / k as f64).sqrt();
    let range = format!(
        "e0a in [{}, {}] nm",
        E0A_RANGE_NM.0.min(beam.nonlocal_e0a_nm),
        E0A_RANGE_NM.1.max(beam.nonlocal_e0a_nm)
    );
    if let Some(f) = first_mode {
        let too_high = || {
            InputError::new(
                "--first-mode",
                f,
                format!(
                    "<= {} (the beam model's modes above it must hold the rest)",
                    bands.len().saturating_sub(k) + 1
                ),
            )
        };
        if f - 1 + k > bands.len() {
            return Err(too_high());
        }
        // consecutive from N when every mode lies within the margin of its band
        let consecutive: Vec<usize> = (0..k).map(|i| f - 1 + i).collect();
        if consecutive.iter().enumerate().all(|(i, &j)| cost[i][j].sqrt() < AMBIGUITY_MARGIN) {
            return Ok(consecutive.into_iter().map(|j| j + 1).collect());
        }
        let (c, modes) = assign(&cost, Some(f - 1), None).ok_or_else(too_high)?;
        check_unique(&cost, c, &modes, Some(f - 1), omegas_rad_s, &range, rms)?;
        return Ok(modes.into_iter().map(|j| j + 1).collect());
    }
    let (c, modes) = assign(&cost, None, None).ok_or_else(|| {
        InputError::new("--beam", format!("{} predicted modes", bands.len()), "a beam model with enough modes")
    })?;
    check_unique(&cost, c, &modes, None, omegas_rad_s, &range, rms)?;
    Ok(modes.into_iter().map(|j| j + 1).collect())
}

/// Refuses the numbering `modes` (cost `c`) when changing any one mode's
/// number costs less than [`AMBIGUITY_MARGIN`] in RMS ln ω.
fn check_unique(
    cost: &[Vec<f64>],
    c: f64,
    modes: &[usize],
    first: Option<usize>,
    omegas_rad_s: &[f64],
    range: &str,
    rms: impl Fn(f64) -> f64,
) -> Result<(), InputError> {
    let skips = |m: &[usize]| m.windows(2).map(|w| w[1] - w[0] - 1).sum::<usize>();
    let n = cost.first().map_or(0, Vec::len);
    // the numbering shifted as a whole (the old lowest-mode check), and the
    // best numbering that changes mode i's number without skipping more
    // predicted modes (a skip needs a node at the force or the sensor: an
    // alternative that needs more of them is not preferred to one that fits)
    let mut alternatives: Vec<(f64, Vec<usize>, usize)> = Vec::new();
    if first.is_none() {
        for f in (0..n).filter(|&f| f != modes[0]) {
            if let Some((c2, other)) = assign(cost, Some(f), None) {
                if skips(&other) <= skips(modes) {
                    alternatives.push((c2, other, 0));
                }
            }
        }
    }
    for (i, &j) in modes.iter().enumerate() {
        if first.is_some() && i == 0 {
            continue;
        }
        if let Some((c2, other)) = assign(cost, first, Some((i, j))) {
            if skips(&other) <= skips(modes) {
                alternatives.push((c2, other, i));
            }
        }
    }
    for (c2, other, i) in alternatives {
        let j = modes[i];
        if rms(c2) - rms(c) < AMBIGUITY_MARGIN {
            let advice = if i == 0 && first.is_none() {
                "state the lowest identified mode's physical number"
            } else {
                "state the lowest identified mode's physical number; the others are then numbered consecutively from it where the --beam model allows"
            };
            return Err(InputError::new(
                "--first-mode",
                if first.is_some() { "(given)".to_string() } else { "(not given)".to_string() },
                format!(
                    "a numbering the --beam model decides: the identified mode at {:.4e} rad/s fits mode {} or mode {} of the --beam model over {range} (RMS ln-misfit {:.3} vs {:.3}, margin {AMBIGUITY_MARGIN}); {advice}",
                    omegas_rad_s[i],
                    j + 1,
                    other[i] + 1,
                    rms(c),
                    rms(c2)
                ),
            ));
        }
    }
    Ok(())
}

/// Order-preserving one-to-one assignment of identified modes (rows of
/// `cost`) to predicted modes (columns) minimising the summed cost,
/// optionally with the first one fixed to `first` and one cell `(i, j)`
/// forbidden. Returns (cost, 0-based predicted indices).
fn assign(cost: &[Vec<f64>], first: Option<usize>, forbid: Option<(usize, usize)>) -> Option<(f64, Vec<usize>)> {
    let k = cost.len();
    let n = cost.first().map_or(0, Vec::len);
    if k == 0 || k > n {
        return None;
    }
    let inf = f64::INFINITY;
    let c = |i: usize, j: usize| if forbid == Some((i, j)) { inf } else { cost[i][j] };
    let mut acc = vec![vec![inf; n]; k];
    let mut from = vec![vec![usize::MAX; n]; k];
    for (j, a) in acc[0].iter_mut().enumerate() {
        if first.is_none_or(|f| f == j) {
            *a = c(0, j);
        }
    }
    for i in 1..k {
        let (mut best, mut arg) = (inf, usize::MAX);
        for j in 1..n {
            if acc[i - 1][j - 1] < best {
                best = acc[i - 1][j - 1];
                arg = j - 1;
            }
            if best < inf {
                acc[i][j] = best + c(i, j);
                from[i][j] = arg;
            }
        }
    }
    let (mut j, total) = acc[k - 1].iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).map(|(j, &c)| (j, c))?;
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

    /// ln-distance cost of ids against point bands.
    fn costs(ids: &[f64], preds: &[f64]) -> Vec<Vec<f64>> {
        ids.iter().map(|i| preds.iter().map(|p| (i.ln() - p.ln()).powi(2)).collect()).collect()
    }

    #[test]
    fn assignment_is_order_preserving_and_may_skip() {
        let preds = [1.0f64, 4.0, 9.0, 16.0, 25.0];
        let c = costs(&[1.05, 8.7, 15.0], &preds);
        assert_eq!(assign(&c, None, None).unwrap().1, vec![0, 2, 3]);
        assert_eq!(assign(&c, Some(1), None).unwrap().1, vec![1, 2, 3]);
        assert!(assign(&c, Some(4), None).is_none());
        // forbidding the best cell of mode 2 moves it to its next best number
        assert_eq!(assign(&c, None, Some((1, 2))).unwrap().1, vec![0, 1, 3]);
    }
}
