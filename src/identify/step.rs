//! The sampling step of a uniformly sampled record, the same whatever the
//! time origin and the precision the times were written with (issue 69).
//!
//! The step from the end points, (t_last − t₀)/(n − 1), carries the rounding
//! of both times: a record shifted to start at 2 ns or 20 ns, or with its
//! time column rounded to float32, gives a step a few ulps (float32: 10⁻⁸
//! relative) away from the unshifted record's. The fit works on scaled units
//! in which the step enters through these bits, and its outcome moved by up
//! to 4 sd of ζ with them (tests/invariance.md). Every step within the
//! record's own resolution is equally consistent with its times, so the step
//! used is a canonical one among them: the value with the fewest significant
//! decimal digits, of the step or of the rate 1/step (a DAQ's 48 kHz, whose
//! step is no short decimal), within the resolution of the end-point step.
//! Sampling steps are set as short decimals (an MD time step times the
//! output interval, a converter's rate), so the canonical step is the one
//! the record was sampled with, the same for every origin and rounding of
//! the times that keeps it inside the resolution. A step whose decimals run
//! to the resolution stays the end-point step.

/// Resolution of the end-point step of times `t` (n ≥ 2, increasing, finite
/// span): how far the true step may lie from it. With time errors e_k
/// (rounding in the file, the parse), the end-point step is off by
/// (e_last − e₀)/(n − 1); the errors show in the deviations
/// d_k = (t_k − t₀) − k·step from the grid, d_k = e_k − e₀ − k(e_last − e₀)/(n − 1),
/// so |e_last − e₀| ≤ 2·max|d| + 2·max|e| ≲ 4·max|d| when the errors are as
/// large somewhere inside the record as at its ends (rounding errors are:
/// over thousands of samples some come within a fraction of their bound).
/// Each d_k is itself computed with an error up to 2ε·max|t| (two
/// subtractions of numbers up to max|t|), and the division by n − 1 adds
/// ε·step; 4ε·max|t| and 2ε·step cover them twice.
fn resolution(t: &[f64], step: f64) -> f64 {
    let n = t.len();
    let m = (n - 1) as f64;
    let deviation = t.iter().enumerate().map(|(k, &tk)| ((tk - t[0]) - k as f64 * step).abs()).fold(0.0, f64::max);
    let largest = t[0].abs().max(t[n - 1].abs());
    (4.0 * deviation + 4.0 * f64::EPSILON * largest) / m + 2.0 * f64::EPSILON * step
}

/// The value with the fewest significant decimal digits within `tol` of
/// `x` (> 0), and that count (17 digits always give `x` itself back).
fn shortest_decimal(x: f64, tol: f64) -> (f64, usize) {
    for digits in 1..=16 {
        let candidate: f64 = format!("{:.*e}", digits - 1, x).parse().unwrap_or(x);
        if (candidate - x).abs() <= tol {
            return (candidate, digits);
        }
    }
    (x, 17)
}

/// The sampling step (s) of uniform times `t` (at least two, increasing,
/// with a finite span: the caller's checks; see the module doc): the
/// end-point step made canonical within its resolution. Fewer than two
/// times give 0.
pub fn sampling_step(t: &[f64]) -> f64 {
    let n = t.len();
    if n < 2 {
        return 0.0;
    }
    let step = (t[n - 1] - t[0]) / (n - 1) as f64;
    if !(step > 0.0 && step.is_finite()) {
        return step;
    }
    let tol = resolution(t, step);
    let (by_step, step_digits) = shortest_decimal(step, tol);
    // the rate 1/step, known to the same relative resolution
    let rate = 1.0 / step;
    let (by_rate, rate_digits) = shortest_decimal(rate, rate * tol / step);
    let from_rate = 1.0 / by_rate;
    if rate_digits < step_digits && (from_rate - step).abs() <= tol {
        from_rate
    } else {
        by_step
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The times of an MD record (20 fs, written as `%.6e`) give 2e-14 s
    /// exactly, shifted by 2 ns, by 20 ns or rounded to float32 alike; a
    /// 48 kHz record gives 1/48000 s shifted or not; a step of no short
    /// decimal stays the end-point step.
    #[test]
    fn the_step_is_the_same_for_every_origin_and_rounding() {
        let n = 17_503;
        let written: Vec<f64> = (0..n).map(|k| format!("{:.6e}", k as f64 * 2e-14).parse().unwrap()).collect();
        assert_eq!(sampling_step(&written), 2e-14);
        for shift in [2e-9, 2e-8, -0.175e-9] {
            let shifted: Vec<f64> = written.iter().map(|t| t + shift).collect();
            if shift > 0.0 {
                // the end-point step of these two is a few ulps off
                assert_ne!((shifted[n - 1] - shifted[0]) / (n - 1) as f64, 2e-14, "shift {shift:e}");
            }
            assert_eq!(sampling_step(&shifted), 2e-14, "shift {shift:e}");
        }
        let single: Vec<f64> = written.iter().map(|&t| f64::from(t as f32)).collect();
        assert_eq!(sampling_step(&single), 2e-14);
        let audio: Vec<f64> = (0..48_000).map(|k| 3.7 + k as f64 / 48_000.0).collect();
        assert_eq!(sampling_step(&audio), 1.0 / 48_000.0);
        let odd = std::f64::consts::PI * 1e-6;
        let t: Vec<f64> = (0..1000).map(|k| k as f64 * odd).collect();
        let raw = t[999] / 999.0;
        assert!((sampling_step(&t) - raw).abs() <= 1e-14 * raw, "{} vs {raw}", sampling_step(&t));
        assert_eq!(sampling_step(&[1.0]), 0.0);
    }
}
