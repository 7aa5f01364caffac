//! The record in the fit's scaled units: abscissa over the band's top, data over its scale.

use num_complex::Complex64;

use super::data::Measurement;
use super::refine::{FitKind, Stop};
use super::REACH;

/// The record in scaled units, with the scales.
pub(super) struct Scaled {
    pub(super) kind: FitKind,
    pub(super) x: Vec<f64>,
    pub(super) y: Vec<Complex64>,
    /// abscissa → rad/s (frequency) or scaled time → s.
    pub(super) x_ref: f64,
    /// data scale (PSD: scale of the PSD itself).
    pub(super) y_ref: f64,
    pub(super) band: (f64, f64),
    /// The caller's stop request, handed to every fit ([`Stop`]).
    pub(super) stop: Stop,
}

pub(super) fn scale(m: &Measurement, stop: &Stop) -> Scaled {
    let stop = stop.clone();
    let c = |v: f64| Complex64::new(v, 0.0);
    let (kind, x, y, x_ref, band) = match m {
        Measurement::Complex { omega_rad_s, h_m_per_n } => {
            (FitKind::Complex, omega_rad_s.clone(), h_m_per_n.clone(), 0.0, (0.0, 0.0))
        }
        Measurement::Magnitude { omega_rad_s, h_abs_m_per_n } => {
            (FitKind::Magnitude, omega_rad_s.clone(), h_abs_m_per_n.iter().map(|&v| c(v)).collect(), 0.0, (0.0, 0.0))
        }
        Measurement::Psd { omega_rad_s, psd_m2_s_per_rad } => {
            (FitKind::Psd, omega_rad_s.clone(), psd_m2_s_per_rad.iter().map(|&v| c(v)).collect(), 0.0, (0.0, 0.0))
        }
        Measurement::Time { time_s, displacement_m } => {
            let n = time_s.len();
            // the canonical step: the same bits for every time origin (`step`)
            let dt = super::step::sampling_step(time_s);
            // t̃ = π t/Δt: the Nyquist frequency is 1 in the scaled units.
            let x = (0..n).map(|k| std::f64::consts::PI * k as f64).collect();
            (FitKind::Time, x, displacement_m.iter().map(|&v| c(v)).collect(), dt / std::f64::consts::PI, (0.0, 1.0))
        }
    };
    let y_ref = y.iter().map(|v| v.norm()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
    let y = y.iter().map(|v| v / y_ref).collect();
    if kind == FitKind::Time {
        return Scaled { kind, x, y, x_ref, y_ref, band, stop };
    }
    // ω̃ = ω/(REACH·ω_max): the initial estimator represents poles up to
    // REACH·ω_max, so a mode just above the band is fitted as a background mode
    // instead of being forced into the residual terms.
    let w_ref = REACH * x.last().copied().unwrap_or(1.0);
    let xs: Vec<f64> = x.iter().map(|w| w / w_ref).collect();
    let band = (xs[0], 1.0 / REACH);
    Scaled { kind, x: xs, y, x_ref: w_ref, y_ref, band, stop }
}
