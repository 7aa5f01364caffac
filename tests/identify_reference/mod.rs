//! An independent generator of the four record kinds `identify` reads:
//! closed-form modal sums of an Euler–Bernoulli beam with analytic mode
//! shapes. It does NOT use the crate's beam module (nor any crate code but
//! the RNG streams), so a test built on it checks `identify` against what its
//! author did not write.
//!
//! Beam (unit length, unit mass per length, modal frequencies scaled to
//! `omega_1`): the mode shapes and eigenvalues β_n L of
//! - simply supported: φ_n = sin(nπx), β_n = nπ;
//! - clamped–clamped: cos β cosh β = 1, φ = cosh βx − cos βx − s(sinh βx − sin βx),
//!   s = (cosh β − cos β)/(sinh β − sin β);
//! - cantilever (clamped at 0, free at 1): cos β cosh β = −1, same φ with
//!   s = (sinh β − sin β)/(cosh β + cos β)
//!
//! (the characteristic equations and shapes of any vibration text, e.g.
//! Meirovitch, *Fundamentals of Vibrations*, §8.6), ω_n ∝ β_n². The roots are
//! found here by bisection; the modal masses ∫φ² by Simpson's rule.
//!
//! H(ω) = Σ_n φ_n(x_in)φ_n(x_out) / (M_n(ω_n² − ω² + 2iζ_nω_nω)) + B/(iω + γ):
//! the modes plus one real (relaxation) pole −γ, which is not a mode.
//! The impulse response is its inverse transform,
//! h(t) = Σ_n φφ/M_n · e^{−ζ_nω_n t} sin(ω_d,n t)/ω_d,n + B e^{−γt}, sampled
//! behind an ideal anti-alias filter (modes above the cut-off removed,
//! those below untouched).

#![allow(dead_code)]

use std::f64::consts::PI;

use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::identify::Measurement;
use num_complex::Complex64;
use rand::Rng;
use rand_distr::{Distribution, Gamma, StandardNormal};

/// The three supports with closed-form shapes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Support {
    SimplySupported,
    ClampedClamped,
    Cantilever,
}

/// β_n L of mode n ≥ 1.
pub fn beta(support: Support, n: usize) -> f64 {
    let nf = n as f64;
    let (g, lo, hi): (fn(f64) -> f64, f64, f64) = match support {
        Support::SimplySupported => return nf * PI,
        // cos β − 1/cosh β changes sign once on [nπ, (n+1)π]
        Support::ClampedClamped => (|b: f64| b.cos() - 1.0 / b.cosh(), nf * PI, (nf + 1.0) * PI),
        // cos β + 1/cosh β changes sign once on [(n−1)π, nπ]
        Support::Cantilever => (|b: f64| b.cos() + 1.0 / b.cosh(), (nf - 1.0) * PI, nf * PI),
    };
    let (mut a, mut b) = (lo + 1e-12, hi - 1e-12);
    let ga = g(a);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if (g(m) > 0.0) == (ga > 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// Mode shape n at x ∈ [0, 1].
pub fn shape(support: Support, n: usize, x: f64) -> f64 {
    let b = beta(support, n);
    match support {
        Support::SimplySupported => (b * x).sin(),
        Support::ClampedClamped | Support::Cantilever => {
            let s = if support == Support::ClampedClamped {
                (b.cosh() - b.cos()) / (b.sinh() - b.sin())
            } else {
                (b.sinh() - b.sin()) / (b.cosh() + b.cos())
            };
            (b * x).cosh() - (b * x).cos() - s * ((b * x).sinh() - (b * x).sin())
        }
    }
}

/// ∫₀¹ φ_n² dx by Simpson's rule on 2 000 intervals (error ~ β⁴h⁴/180 < 1e-9 for n ≤ 8).
pub fn modal_mass(support: Support, n: usize) -> f64 {
    let k = 2000;
    let h = 1.0 / k as f64;
    let f = |i: usize| shape(support, n, i as f64 * h).powi(2);
    let mut s = f(0) + f(k);
    for i in 1..k {
        s += if i % 2 == 1 { 4.0 } else { 2.0 } * f(i);
    }
    s * h / 3.0
}

/// One true mode: natural frequency (rad/s), ζ, modal participation
/// φ(x_in)φ(x_out)/M (m/N·(rad/s)² in the scaled units below).
#[derive(Debug, Clone, Copy)]
pub struct TrueMode {
    pub omega: f64,
    pub zeta: f64,
    pub gain: f64,
}

impl TrueMode {
    pub fn pole(&self) -> Complex64 {
        Complex64::new(-self.zeta * self.omega, self.omega * (1.0 - self.zeta * self.zeta).sqrt())
    }
    /// Its own contribution to H.
    pub fn h(&self, w: f64) -> Complex64 {
        self.gain / Complex64::new(self.omega * self.omega - w * w, 2.0 * self.zeta * self.omega * w)
    }
}

/// A beam with sensor positions: its modes and relaxation pole.
#[derive(Debug, Clone)]
pub struct Beam {
    pub modes: Vec<TrueMode>,
    /// Relaxation pole −γ (rad/s) and its residue B (m/N·rad/s).
    pub gamma: f64,
    pub b: f64,
}

/// Damping ratios of modes 1…8: different for every mode, 0.4–2 %.
const ZETA: [f64; 8] = [0.012, 0.006, 0.009, 0.015, 0.02, 0.01, 0.012, 0.015];

impl Beam {
    /// `n_modes` modes of `support`, mode 1 at `omega_1`, driven at `x_in`
    /// and observed at `x_out` (fractions of L), with a relaxation pole at
    /// γ = 0.3ω₁ whose static compliance is `relax` times mode 1's static
    /// compliance at the antinode.
    pub fn new(support: Support, n_modes: usize, omega_1: f64, x_in: f64, x_out: f64, relax: f64) -> Self {
        let b1 = beta(support, 1);
        let modes = (1..=n_modes)
            .map(|n| {
                let omega = omega_1 * (beta(support, n) / b1).powi(2);
                let gain = shape(support, n, x_in) * shape(support, n, x_out) / modal_mass(support, n);
                // scale so that gains are m/N with ω in rad/s: a 1e-9 m/N static mode 1
                TrueMode { omega, zeta: ZETA[n - 1], gain: gain * 1e-9 * omega_1 * omega_1 }
            })
            .collect();
        let gamma = 0.3 * omega_1;
        Beam { modes, gamma, b: relax * 1e-9 * gamma }
    }

    pub fn h(&self, w: f64) -> Complex64 {
        self.modes.iter().map(|m| m.h(w)).sum::<Complex64>() + self.b / Complex64::new(self.gamma, w)
    }

    /// Impulse response (m/(N·s)) at t, modes with ω < `cutoff` only.
    pub fn impulse(&self, t: f64, cutoff: f64) -> f64 {
        let modes: f64 = self
            .modes
            .iter()
            .filter(|m| m.omega < cutoff)
            .map(|m| {
                let p = m.pole();
                m.gain * (p.re * t).exp() * (p.im * t).sin() / p.im
            })
            .sum();
        modes + self.b * (-self.gamma * t).exp()
    }
}

/// The two noise kinds of the issue.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Noise {
    /// sd = `fraction` of the record's peak, the same everywhere.
    Additive { fraction: f64 },
    /// σ² = a² + b²|signal|², a = `floor`·peak.
    Proportional { floor: f64, b: f64 },
}

impl Noise {
    /// Standard deviation at a point where the clean signal is `s`, for a record whose peak is `peak`.
    pub fn sd(&self, s: f64, peak: f64) -> f64 {
        match *self {
            Noise::Additive { fraction } => fraction * peak,
            Noise::Proportional { floor, b } => ((floor * peak).powi(2) + (b * s).powi(2)).sqrt(),
        }
    }
}

/// The record kinds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    Complex,
    Magnitude,
    Psd,
    Time,
    /// A magnitude record made as a lock-in's R channel makes it: the
    /// magnitude of the complex sweep's noisy response, |H + ε| (Rician),
    /// with ε as in [`Kind::Complex`]. [`Kind::Magnitude`] adds real noise
    /// to |H| and folds it at zero, |(|H| + e)|.
    Rician,
}

/// A generated record and what it holds.
pub struct Record {
    pub data: Measurement,
    /// The true modes a lab would call visible: ≥ 20 noise sd above the
    /// floor at resonance and ≥ 3 samples in the half-power band.
    pub visible: Vec<TrueMode>,
    pub beam: Beam,
}

/// `n` log-spaced frequencies over [lo, hi].
pub fn log_grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n).map(|i| (lo.ln() + (hi / lo).ln() * i as f64 / (n - 1) as f64).exp()).collect()
}

/// Averages of the Welch PSDs.
pub const NU: f64 = 20.0;

/// Makes a record of `kind` of the beam with noise `noise`, seed keyed by
/// `[tag, seed]`. Frequency records: 1 500 log-spaced points from 0.5ω₁ to
/// 1.15× the highest in-band mode (`band_modes`); PSD: `NU`-average Welch
/// bins of |H|²S_F (white force) plus, for additive noise, a white sensor
/// floor of `fraction`·peak; ring-down: 4 000 samples at 8× the highest
/// in-band frequency behind an anti-alias filter at 0.8 Nyquist.
pub fn record(beam: Beam, kind: Kind, noise: Noise, band_modes: usize, tag: u64, seed: u64) -> Record {
    let points = if kind == Kind::Time { 4000 } else { 1500 };
    record_with(beam, kind, noise, band_modes, points, tag, seed)
}

/// [`record`] with `points` frequency samples (ring-downs: samples) instead of 1 500 (4 000).
pub fn record_with(
    beam: Beam,
    kind: Kind,
    noise: Noise,
    band_modes: usize,
    points: usize,
    tag: u64,
    seed: u64,
) -> Record {
    let mut rng = stream(42, Purpose::MeasurementNoise, [tag, seed]);
    let top = beam.modes[band_modes - 1].omega;
    let mut normal = || -> f64 { StandardNormal.sample(&mut rng) };
    let lo = 0.5 * beam.modes[0].omega;
    let hi = 1.15 * top;
    match kind {
        Kind::Complex | Kind::Magnitude | Kind::Psd | Kind::Rician => {
            let w = log_grid(lo, hi, points);
            let h: Vec<Complex64> = w.iter().map(|&w| beam.h(w)).collect();
            let peak = h.iter().map(|v| v.norm()).fold(0.0, f64::max);
            let spacing = |wc: f64, half: f64| w.iter().filter(|&&x| (x - wc).abs() <= half).count();
            let psd_floor = match noise {
                Noise::Additive { fraction } => (fraction * peak).powi(2),
                Noise::Proportional { .. } => 0.0,
            };
            let data = match kind {
                Kind::Complex => {
                    let y = h
                        .iter()
                        .map(|v| {
                            let sd = noise.sd(v.norm(), peak);
                            v + Complex64::new(sd * normal(), sd * normal())
                        })
                        .collect();
                    Measurement::Complex { omega_rad_s: w.clone(), h_m_per_n: y }
                }
                Kind::Magnitude => {
                    let y = h.iter().map(|v| (v.norm() + noise.sd(v.norm(), peak) * normal()).abs()).collect();
                    Measurement::Magnitude { omega_rad_s: w.clone(), h_abs_m_per_n: y }
                }
                Kind::Rician => {
                    let y = h
                        .iter()
                        .map(|v| {
                            let sd = noise.sd(v.norm(), peak);
                            (v + Complex64::new(sd * normal(), sd * normal())).norm()
                        })
                        .collect();
                    Measurement::Magnitude { omega_rad_s: w.clone(), h_abs_m_per_n: y }
                }
                _ => {
                    let gamma = Gamma::new(NU, 1.0 / NU).unwrap();
                    let floor = psd_floor;
                    let mut g = stream(42, Purpose::MeasurementNoise, [tag + 1, seed]);
                    let y = h.iter().map(|v| (v.norm_sqr() + floor) * gamma.sample(&mut g)).collect();
                    Measurement::Psd { omega_rad_s: w.clone(), psd_m2_s_per_rad: y }
                }
            };
            let visible = beam
                .modes
                .iter()
                .filter(|m| m.omega <= hi)
                .filter(|m| {
                    let s = m.h(m.omega).norm();
                    let (height, sd) = if kind == Kind::Psd {
                        // a PSD's floor at the resonance: everything but this
                        // mode (other modes, relaxation, sensor floor); its
                        // bins scatter by 1/√ν of their level
                        let rest = (beam.h(m.omega) - m.h(m.omega)).norm_sqr() + psd_floor;
                        (s * s, rest / NU.sqrt())
                    } else {
                        (s, noise.sd(s, peak))
                    };
                    height >= 20.0 * sd && spacing(m.omega, m.zeta * m.omega) >= 3
                })
                .copied()
                .collect();
            Record { data, visible, beam }
        }
        Kind::Time => {
            let nyquist = 8.0 * top / 2.0;
            let dt = PI / nyquist;
            let cutoff = 0.8 * nyquist;
            let n = points;
            let clean: Vec<f64> = (0..n).map(|k| beam.impulse(k as f64 * dt, cutoff)).collect();
            let peak = clean.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let y = clean.iter().map(|&v| v + noise.sd(v, peak) * normal()).collect();
            let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
            // visible: initial amplitude ≥ 20 sd of the floor, it lives
            // ≥ 3 samples (a decay rate resolved), and its own signal stands
            // ≥ 20 noise sd high in the matched-filter sense,
            // √Σ_k (y_r(t_k)/σ(t_k))² ≥ 20 with σ(t_k) the generator's noise sd
            // at sample k: the residue SNR a fit at the true poles gets for
            // this mode. Under proportional noise the noise at early times is
            // 1 % of the whole signal, so a weak high mode can start 20 sd
            // above the floor a and still drown (measured: such modes, matched-
            // filter SNR 0.3–5, came out 10–48 sd off in a fit started at the
            // true poles with the true weights; tests/identify_coverage.md).
            let matched = |m: &TrueMode| -> f64 {
                let (p, a) = (m.pole(), m.gain / m.pole().im);
                (0..n)
                    .map(|k| {
                        let t = k as f64 * dt;
                        let (v, sd) = (a * (p.re * t).exp() * (p.im * t).sin(), noise.sd(clean[k], peak));
                        // a noise-free sample holds any nonzero signal exactly
                        if sd > 0.0 {
                            (v / sd).powi(2)
                        } else if v == 0.0 {
                            0.0
                        } else {
                            f64::INFINITY
                        }
                    })
                    .sum::<f64>()
                    .sqrt()
            };
            let visible = beam
                .modes
                .iter()
                .filter(|m| m.omega < cutoff)
                .filter(|m| {
                    let amp = (m.gain / m.pole().im).abs();
                    let sd = noise.sd(0.0, peak);
                    amp >= 20.0 * sd && 1.0 / (m.zeta * m.omega) >= 3.0 * dt && matched(m) >= 20.0
                })
                .copied()
                .collect();
            Record { data: Measurement::Time { time_s: t, displacement_m: y }, visible, beam }
        }
    }
}

/// Random sensor positions in (0.02, 0.98) L: anywhere, nodes included.
pub fn positions(tag: u64, seed: u64) -> (f64, f64) {
    let mut rng = stream(42, Purpose::MeasurementNoise, [tag + 7, seed]);
    (rng.gen_range(0.02..0.98), rng.gen_range(0.02..0.98))
}
