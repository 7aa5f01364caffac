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
//!
//! When no ω or ζ separates them, a measurement of another kind may: the
//! shape of a measured mode ([`shape_measurement`]). A support spring and an
//! axial force both shift mode n's ω² by ∝ 1/n² relative at leading order,
//! so no modal table tells them apart, but the tension leaves a simply
//! supported beam's mode shapes exactly sinusoidal while the spring bends
//! them near the supports (by a few per cent of the peak amplitude at a
//! higher mode: `tests/diagnose_hidden.md`, "Case histories"). The observable is what a scan of the readout point along
//! the beam at the mode's resonance gives: the amplitude |H(ω_n; x_drive, x)|
//! ([`crate::beam::frf_points`]) relative to the largest on the scan grid. Its measurement sd depends on the instrument, which the data
//! do not say, so the suggestion gives the largest sd at which the
//! measurement still decides (moves ln B by the decision threshold). The
//! scan goes back in as `mode_scans` data
//! ([`crate::calibration::ModeScan`], [`ShapeMeasurement::scan_on`]) and is
//! fitted like the modes; a scanned mode is not suggested again. Hidden case
//! 104 (a tension, the spring 0.36 nats behind it): with the truth's scan of
//! mode 4 on this grid at ±0.0073, the spring falls 29.7 nats behind.

use std::sync::atomic::AtomicU64;

use serde::Serialize;

use rayon::prelude::*;

use crate::beam::{frf_points, modal, BeamSpec};
use crate::calibration::posterior::relative_to_peak;
use crate::calibration::{MeasuredData, ModeScan, Observable, Quantity, ScanPoint};

use super::evidence::ModelRun;
use super::ppc::Draws;

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

/// The unmeasured observables ([`unmeasured_observables`]) with `run`'s
/// predictive draws of them: computed once for the selected model and read by
/// both [`next_measurement`] and `falsify::falsifying_measurement`. `None`
/// when nothing is unmeasured or no draw computes. The forward solves are
/// added to `solves`.
pub(super) fn unmeasured_draws(
    data: &MeasuredData,
    run: &ModelRun,
    solves: &AtomicU64,
) -> Option<(Vec<Observable>, Draws)> {
    let candidates = unmeasured_observables(data);
    if candidates.is_empty() {
        return None;
    }
    let draws = super::predictive::predictive(run, &candidates, MAX_MODE, solves);
    (!draws.predictions.is_empty()).then_some((candidates, draws))
}

/// The best unmeasured observable to separate `a` from the first of
/// `rivals` (in their order) that some observable predicted by both
/// separates by [`MIN_SEPARATION_SD`]; `own` is `a`'s [`unmeasured_draws`].
/// The forward solves of the rivals' predictive draws are added to `solves`.
pub fn next_measurement<'r>(
    data: &MeasuredData,
    a: &ModelRun,
    (candidates, da): &(Vec<Observable>, Draws),
    rivals: impl IntoIterator<Item = &'r ModelRun>,
    solves: &AtomicU64,
) -> Option<NextMeasurement> {
    let (rel_omega, rel_zeta) = relative_sds(data);
    rivals.into_iter().find_map(|b| {
        let db = super::predictive::predictive(b, candidates, MAX_MODE, solves);
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

/// The median relative sd of the fitted modes' ω and of their ζ: the
/// assumed noise of a new measurement, relative to its predicted value.
pub(super) fn relative_sds(data: &MeasuredData) -> (f64, f64) {
    let rel = |f: fn(&crate::calibration::ModeObservation) -> f64| {
        let mut r: Vec<f64> = data.modes.iter().map(f).collect();
        r.sort_by(f64::total_cmp);
        r[r.len() / 2]
    };
    (rel(|m| m.omega_sd_rad_s / m.omega_rad_s), rel(|m| m.zeta_sd / m.zeta.abs().max(f64::MIN_POSITIVE)))
}

/// ω and ζ of every mode ≤ [`MAX_MODE`] the file neither fits nor holds out.
pub(super) fn unmeasured_observables(data: &MeasuredData) -> Vec<Observable> {
    let measured: Vec<usize> = data.modes.iter().chain(&data.held_out_modes).map(|m| m.mode).collect();
    (1..=MAX_MODE)
        .filter(|m| !measured.contains(m))
        .flat_map(|mode| {
            [Quantity::Omega, Quantity::Zeta].map(|quantity| Observable {
                mode,
                quantity,
                x_nm: None,
                value: 0.0,
                sd: 0.0,
            })
        })
        .collect()
}

/// Points of the readout scan: x = k·L/[`SHAPE_GRID`], k = 1 … SHAPE_GRID − 1
/// (0.4 nm apart on the paper's 8 nm tube).
pub const SHAPE_GRID: usize = 20;

/// Drive point of the predicted scans as a fraction of L: 39/40, near the end
/// x = L that is pinned or free for every support but clamped–clamped, off
/// the scan grid; a uniform beam has no node of a mode ≤ [`MAX_MODE`] there
/// (the normalisation by the largest amplitude removes the drive's own
/// amplitude, so only a node would matter).
pub const SHAPE_DRIVE_FRACTION: f64 = 39.0 / 40.0;

/// The smallest decisive measurement sd a shape suggestion may ask for, as a
/// fraction of the peak amplitude: a tenth of a per cent. A stated
/// assumption, not a derived bound: a scan of a nanotube's deflection is not
/// expected to resolve less, and below it differences reach numerical noise
/// (without the floor a suggestion can be the point of largest amplitude,
/// 1 under both models by definition, "decisive" at an sd of 0; see
/// `tests/diagnose_hidden.md`, "Case histories").
pub const MIN_SHAPE_SD: f64 = 1e-3;

/// A mode-shape measurement that would separate two models no ω or ζ
/// separates (module doc).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ShapeMeasurement {
    /// The mode whose resonance the scan is taken at (a measured one).
    pub mode: usize,
    /// The readout point where the two predictions differ most usefully.
    pub position_x_nm: f64,
    /// The drive point the predictions assume.
    pub drive_x_nm: f64,
    /// The two models it would separate (selected first).
    pub between: [String; 2],
    /// Predictive means of the amplitude at `position_x_nm` relative to the
    /// largest on the scan grid (dimensionless), under the two models (a
    /// model with a folded mass position over each draw and its mirror
    /// image, see `shape_draws`).
    pub predicted_relative_amplitude: [f64; 2],
    /// Their posterior predictive sds.
    pub predictive_sd: [f64; 2],
    /// The largest measurement sd of the relative amplitude at which the
    /// measurement is expected to move ln B between the two by the decision
    /// threshold T: Δ²/(2(σ² + v̄)) ≥ T, so σ = √(Δ²/(2T) − v̄), v̄ the mean
    /// predictive variance.
    pub decisive_measurement_sd: f64,
}

impl ShapeMeasurement {
    /// The suggested observable of `beam` (its resonance scan at this mode
    /// and point, [`resonance_scan`]): what the measurement would read on a
    /// beam known exactly, e.g. a synthetic truth.
    pub fn value_of(&self, beam: &BeamSpec) -> Option<f64> {
        let xs = scan_points(beam.length_nm);
        let k = xs.iter().position(|&x| x == self.position_x_nm)?;
        resonance_scan(beam, self.mode, self.drive_x_nm, &xs).map(|s| s[(self.mode - 1) * xs.len() + k])
    }

    /// The suggested scan as `mode_scans` data ([`ModeScan`]): `beam`'s
    /// relative amplitudes at every point of the scan grid, each read with sd
    /// `sd`, noise-free (what the scan would read on a beam known exactly,
    /// e.g. a synthetic truth; the caller adds the instrument's noise).
    pub fn scan_on(&self, beam: &BeamSpec, sd: f64) -> Option<ModeScan> {
        let xs = scan_points(beam.length_nm);
        let all = resonance_scan(beam, self.mode, self.drive_x_nm, &xs)?;
        let row = &all[(self.mode - 1) * xs.len()..];
        let points = xs
            .iter()
            .zip(row)
            .map(|(&x_nm, &a)| ScanPoint { x_nm, relative_amplitude: a, relative_amplitude_sd: sd })
            .collect();
        Some(ModeScan { mode: self.mode, drive_x_nm: self.drive_x_nm, points })
    }

    /// The expected ln B of the first model over the second when a beam whose
    /// true relative amplitude is `value` is measured with sd `sd`: ln B of a
    /// reading y is the ratio of the two Gaussian predictives N(y; m_k, s_k² +
    /// sd²) (the approximation the decisive sd assumes), and over y ~
    /// N(`value`, `sd`²), E[(y − m)²] = (value − m)² + sd², so no random draw
    /// decides it.
    pub fn expected_log_bayes_factor(&self, value: f64, sd: f64) -> f64 {
        let expected_log_density = |m: f64, s: f64| {
            let v = s * s + sd * sd;
            -0.5 * ((value - m).powi(2) + sd * sd) / v - 0.5 * v.ln()
        };
        let [ma, mb] = self.predicted_relative_amplitude;
        let [sa, sb] = self.predictive_sd;
        expected_log_density(ma, sa) - expected_log_density(mb, sb)
    }
}

/// The mode shape that best separates `a` from the first of `rivals` (in
/// their order) for which some measured mode's scan point gives a decisive
/// sd ([`ShapeMeasurement::decisive_measurement_sd`], threshold
/// `decisive_nats`) of at least [`MIN_SHAPE_SD`]: the point with the largest
/// such sd. Forward solves (a
/// modal solve and one FRF factorisation per mode, per posterior draw) are
/// added to `solves`.
pub fn shape_measurement<'r>(
    data: &MeasuredData,
    a: &ModelRun,
    rivals: impl IntoIterator<Item = &'r ModelRun>,
    decisive_nats: f64,
    solves: &AtomicU64,
) -> Option<ShapeMeasurement> {
    let modes = data.max_mode().min(MAX_MODE);
    // a measured mode not already scanned
    let measured: Vec<usize> = data
        .modes
        .iter()
        .chain(&data.held_out_modes)
        .map(|m| m.mode)
        .filter(|n| !data.mode_scans.iter().any(|s| s.mode == *n))
        .collect();
    let length_nm = data.beam.length_nm;
    let xs = scan_points(length_nm);
    let drive = SHAPE_DRIVE_FRACTION * length_nm;
    let da = shape_draws(a, data, modes, drive, &xs, solves);
    if da.is_empty() {
        return None;
    }
    rivals.into_iter().find_map(|b| {
        let db = shape_draws(b, data, modes, drive, &xs, solves);
        if db.is_empty() {
            return None;
        }
        (0..modes * xs.len())
            .filter(|j| measured.contains(&(j / xs.len() + 1)))
            .map(|j| {
                let (ma, va) = mean_var(da.iter().map(|p| p[j]));
                let (mb, vb) = mean_var(db.iter().map(|p| p[j]));
                let sd2 = (ma - mb).powi(2) / (2.0 * decisive_nats) - 0.5 * (va + vb);
                (j, ma, va, mb, vb, sd2)
            })
            .filter(|t| t.5 >= MIN_SHAPE_SD * MIN_SHAPE_SD && t.5.is_finite())
            .max_by(|x, y| x.5.total_cmp(&y.5))
            .map(|(j, ma, va, mb, vb, sd2)| ShapeMeasurement {
                mode: j / xs.len() + 1,
                position_x_nm: xs[j % xs.len()],
                drive_x_nm: drive,
                between: [a.model.name(), b.model.name()],
                predicted_relative_amplitude: [ma, mb],
                predictive_sd: [va.sqrt(), vb.sqrt()],
                decisive_measurement_sd: sd2.sqrt(),
            })
    })
}

/// Per posterior draw of `run` (in order; draws whose [`resonance_scan`]
/// fails are left out): the scans of modes 1..=`modes`. When the model's
/// posterior is folded onto one of two mirror images (the mass position
/// onto the left half, or the stiffer end spring onto x = 0:
/// [`super::classes::folds_mirror_image`]) each draw is followed by its
/// mirror image's scan: the predictive of the unfolded posterior, an equal
/// mixture of the two. Without it the prediction is that of a mass on the
/// left only, wrong by the mirror's difference for a mass on the right, and
/// a scan suggested from it can decide for the wrong model
/// (`tests/diagnose_hidden.md`, "Case histories").
fn shape_draws(
    run: &ModelRun,
    data: &MeasuredData,
    modes: usize,
    drive_nm: f64,
    xs: &[f64],
    solves: &AtomicU64,
) -> Vec<Vec<f64>> {
    let images = if super::classes::folds_mirror_image(&run.model, &data.beam, &data.mode_scans) { 2 } else { 1 };
    solves.fetch_add((images * run.draws.len() * (1 + modes)) as u64, std::sync::atomic::Ordering::Relaxed);
    let post = &run.posterior;
    let rows: Vec<Vec<Option<Vec<f64>>>> = run
        .draws
        .par_iter()
        .map(|u| {
            let beam = post.inner().beam_at(&post.to_inner(u));
            let mut scans = vec![resonance_scan(&beam, modes, drive_nm, xs)];
            if images == 2 {
                scans.push(resonance_scan(&beam.mirror_image(), modes, drive_nm, xs));
            }
            scans
        })
        .collect();
    rows.into_iter().flatten().flatten().collect()
}

/// The scan points of a beam of length `length_nm`: x = k·L/[`SHAPE_GRID`], k = 1 … SHAPE_GRID − 1.
pub fn scan_points(length_nm: f64) -> Vec<f64> {
    (1..SHAPE_GRID).map(|k| k as f64 * length_nm / SHAPE_GRID as f64).collect()
}

/// The resonance scans of `beam`'s modes 1..=`modes`, mode-major: at ω_n,
/// |H(ω_n; drive, x_k)| / max_k |H(ω_n; drive, x_k)| over the points `xs`;
/// `None` when the model cannot be solved or a mode ≤ `modes` is overdamped.
pub fn resonance_scan(beam: &BeamSpec, modes: usize, drive_nm: f64, xs: &[f64]) -> Option<Vec<f64>> {
    let found = modal(beam, modes).ok()?.modes;
    let omegas: Vec<f64> =
        (1..=modes).map(|n| found.iter().find(|m| m.mode == n).map(|m| m.omega_rad_s)).collect::<Option<_>>()?;
    let h = frf_points(beam, drive_nm, xs, &omegas).ok()?;
    let mut row = Vec::with_capacity(modes * xs.len());
    for scan in &h {
        row.extend(relative_to_peak(scan)?);
    }
    Some(row)
}

pub(super) fn mean_var(x: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = x.clone().count() as f64;
    let m = x.clone().sum::<f64>() / n;
    (m, x.map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::{InternalVariable, PointMass};

    /// Why the predictive of a folded mass position needs the mirror image
    /// ([`shape_draws`]): on a simply supported beam a mass at 0.3 L and one
    /// at 0.7 L give the same ω and ζ (both at mesh nodes of a uniform mesh,
    /// so the two discrete models are exact mirror images and differ only by
    /// the eigensolver's rounding, measured ≤ 9e-15 relative; 1e-9 leaves a
    /// wide margin over double-precision rounding on 40 DOFs), while their
    /// resonance scans differ far beyond the smallest sd a suggestion may ask
    /// for (by up to 0.52 of the peak).
    #[test]
    fn a_mirrored_mass_has_the_same_modes_and_a_different_scan() {
        let mut beam =
            crate::beam::BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, crate::beam::Support::SimplySupported, 20);
        beam.internal_variables = vec![InternalVariable { delta: 0.05, omega_rad_s: 1e12 }];
        let mass_kg = 0.1 * beam.density_kg_m3 * beam.area_m2() * beam.length_nm * 1e-9;
        beam.point_mass = Some(PointMass { mass_kg, x_nm: 0.3 * beam.length_nm });
        let mirror = beam.mirror_image();
        assert!((mirror.point_mass.unwrap().x_nm - 0.7 * beam.length_nm).abs() < 1e-12);
        let (a, b) = (modal(&beam, 5).unwrap().modes, modal(&mirror, 5).unwrap().modes);
        for (p, q) in a.iter().zip(&b) {
            assert_eq!(p.mode, q.mode);
            assert!((p.omega_rad_s / q.omega_rad_s - 1.0).abs() < 1e-9, "mode {}", p.mode);
            assert!((p.zeta / q.zeta - 1.0).abs() < 1e-9, "mode {}", p.mode);
        }
        let xs = scan_points(beam.length_nm);
        let drive = SHAPE_DRIVE_FRACTION * beam.length_nm;
        let (sa, sb) = (resonance_scan(&beam, 5, drive, &xs).unwrap(), resonance_scan(&mirror, 5, drive, &xs).unwrap());
        let largest = sa.iter().zip(&sb).map(|(p, q)| (p - q).abs()).fold(0.0, f64::max);
        assert!(largest > 10.0 * MIN_SHAPE_SD, "largest scan difference {largest}");
    }
}
