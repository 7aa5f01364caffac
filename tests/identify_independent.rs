//! `identify` on records generated WITHOUT the project's beam code: closed-form
//! sums of modes with arbitrary complex residues, log-spaced sweeps, a Welch
//! PSD with a known number of averages, a ring-down of damped cosines, in the
//! units a lab uses (pm/N-sized receptances, kHz modes), written as CSV the
//! way real files come (CRLF line endings, spaces around fields, a trailing
//! newline) and read back through `Measurement::from_csv`.

use std::f64::consts::PI;

use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::identify::{identify, IdentifiedMode, IdentifySettings, Measurement};
use num_complex::Complex64;
use rand_distr::{Distribution, Gamma, StandardNormal};

/// (natural frequency rad/s, ζ, complex residue) of a MEMS-like resonator:
/// modes at 10, 27 and 51 kHz in the band, one at 90 kHz above it.
fn modes() -> Vec<(f64, f64, Complex64)> {
    vec![
        (2.0 * PI * 10.0e3, 0.010, Complex64::from_polar(2.0e-9, -1.2)),
        (2.0 * PI * 27.0e3, 0.004, Complex64::from_polar(0.6e-9, 2.0)),
        (2.0 * PI * 51.0e3, 0.020, Complex64::from_polar(3.0e-9, 0.4)),
        (2.0 * PI * 90.0e3, 0.015, Complex64::from_polar(5.0e-9, -2.5)),
    ]
}

fn pole(w: f64, z: f64) -> Complex64 {
    Complex64::new(-z * w, w * (1.0 - z * z).sqrt())
}

/// H(ω) = Σ A_k/(iω − p_k) + Ā_k/(iω − p̄_k), in m/N.
fn receptance(w: f64) -> Complex64 {
    let s = Complex64::new(0.0, w);
    modes().iter().map(|&(wn, z, a)| a / (s - pole(wn, z)) + a.conj() / (s - pole(wn, z).conj())).sum()
}

/// `n` log-spaced frequencies from 5 to 70 kHz (rad/s): a different number
/// of points per resonance for every mode.
fn log_sweep(n: usize) -> Vec<f64> {
    let (lo, hi) = ((2.0 * PI * 5.0e3f64).ln(), (2.0 * PI * 70.0e3f64).ln());
    (0..n).map(|i| (lo + (hi - lo) * i as f64 / (n - 1) as f64).exp()).collect()
}

/// A CSV as a lab PC writes it: CRLF, spaces around fields, trailing newline.
fn lab_csv(header: &str, rows: impl Iterator<Item = Vec<f64>>) -> String {
    let mut s = format!("{}\r\n", header.replace(',', " , "));
    for r in rows {
        let fields: Vec<String> = r.iter().map(|v| format!(" {v:e} ")).collect();
        s.push_str(&fields.join(","));
        s.push_str("\r\n");
    }
    s
}

/// The first three true modes, each within `k` of its reported sd.
fn check(found: &[IdentifiedMode], k: f64, what: &str) {
    let mut found = found.to_vec();
    found.sort_by(|a, b| a.omega_rad_s.total_cmp(&b.omega_rad_s));
    for m in &found {
        println!(
            "{what}: omega {:e} ± {:.2e}, zeta {:.5} ± {:.2e}",
            m.omega_rad_s, m.omega_sd_rad_s, m.zeta, m.zeta_sd
        );
    }
    assert_eq!(found.len(), 3, "{what}: the three in-band modes");
    for (m, &(w, z, _)) in found.iter().zip(&modes()) {
        assert!((m.omega_rad_s - w).abs() <= k * m.omega_sd_rad_s, "{what}: omega {:e} vs {w:e}", m.omega_rad_s);
        assert!((m.zeta - z).abs() <= k * m.zeta_sd, "{what}: zeta {} vs {z}", m.zeta);
    }
}

#[test]
fn noise_free_log_sweep_gives_the_closed_form_modes() {
    let w = log_sweep(3000);
    let csv = lab_csv(
        "omega_rad_s,h_re_m_per_n,h_im_m_per_n",
        w.iter().map(|&w| {
            let h = receptance(w);
            vec![w, h.re, h.im]
        }),
    );
    let id = identify(&Measurement::from_csv(&csv).unwrap(), &IdentifySettings::default()).unwrap();
    assert_eq!(id.modes.len(), 3);
    for (m, &(w, z, _)) in id.modes.iter().zip(&modes()) {
        let (ew, ez) = ((m.omega_rad_s - w).abs() / w, (m.zeta - z).abs() / z);
        println!("omega rel err {ew:.2e}, zeta rel err {ez:.2e}");
        // The model class holds the record exactly (modes + out-of-band
        // poles), so only the CSV's printing (`{:e}`: shortest round-trip,
        // exact) and the optimiser's tolerance (1e-14) limit it: 1e-6 is the
        // issue's bar, measured far below.
        assert!(ew < 1e-6 && ez < 1e-6, "omega {ew:e}, zeta {ez:e}");
    }
}

#[test]
fn noisy_log_sweep_in_pm_per_n_recovers_the_modes_within_their_sd() {
    let w = log_sweep(2500);
    let peak = w.iter().map(|&w| receptance(w).norm()).fold(0.0, f64::max);
    let sd = 5e-3 * peak;
    let mut rng = stream(12, Purpose::MeasurementNoise, [1210, 0]);
    let csv = lab_csv(
        "omega_rad_s,h_re_m_per_n,h_im_m_per_n",
        w.iter().map(|&w| {
            let h = receptance(w);
            let (a, b): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
            vec![w, h.re + sd * a, h.im + sd * b]
        }),
    );
    let id = identify(&Measurement::from_csv(&csv).unwrap(), &IdentifySettings::default()).unwrap();
    // 3 sd: a two-sided miss has probability 0.27 % per number
    check(&id.modes, 3.0, "log sweep");
}

#[test]
fn welch_psd_with_known_averages_recovers_the_modes_and_the_averages() {
    // linear grid 5–70 kHz, 4000 bins; ν = 16 averaged periodograms of the
    // response to a white force of S_F = 1e-6 N²s/rad: bin = |H|²S_F·Gamma(16, 1/16)
    const NU: f64 = 16.0;
    let n = 4000;
    let (lo, hi) = (2.0 * PI * 5.0e3, 2.0 * PI * 70.0e3);
    let w: Vec<f64> = (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect();
    let gamma = Gamma::new(NU, 1.0 / NU).unwrap();
    let mut rng = stream(12, Purpose::MeasurementNoise, [1211, 0]);
    let csv = lab_csv(
        "omega_rad_s,psd_m2_s_per_rad",
        w.iter().map(|&w| vec![w, receptance(w).norm_sqr() * 1e-6 * gamma.sample(&mut rng)]),
    );
    let id = identify(&Measurement::from_csv(&csv).unwrap(), &IdentifySettings::default()).unwrap();
    // 1/ν̂ = Σ(u−1)²/(m−p): relative sd of (u−1)² is sqrt((2 + 6/ν)/m)
    // (Gamma moments E(u−1)⁴ = 3/ν² + 6/ν³) = 0.024 for m = 4000, so ν̂ = 16 ± 0.4;
    // 4 sd = ±1.6.
    for m in &id.background_modes {
        println!("welch background: omega {:e}, zeta {:.5}, snr {:.1}", m.omega_rad_s, m.zeta, m.amplitude_snr);
    }
    println!("welch real poles {:?}", id.real_poles_rad_s);
    let nu = 1.0 / (id.noise_sd * id.noise_sd);
    println!("estimated averages {nu:.2}");
    assert!((nu - NU).abs() < 1.6, "averages {nu}");
    check(&id.modes, 3.0, "welch psd");
}

#[test]
fn ring_down_of_damped_cosines_recovers_the_modes_within_their_sd() {
    // y(t) = Σ 2|A_k| e^{−ζ_kω_k t} cos(ω_d,k t + arg A_k), the impulse
    // response of the same modes (mode 4 left out: a lab's anti-alias filter
    // at 80 kHz removes it), sampled at 200 kHz for 10 ms, noise 0.2 % of the
    // first sample's scale.
    let dt = 5e-6;
    let n = 2000;
    let y: Vec<f64> = (0..n)
        .map(|k| {
            let t = k as f64 * dt;
            modes()[..3]
                .iter()
                .map(|&(w, z, a)| {
                    let p = pole(w, z);
                    2.0 * a.norm() * (p.re * t).exp() * (p.im * t + a.arg()).cos()
                })
                .sum::<f64>()
        })
        .collect();
    let sd = 2e-3 * y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut rng = stream(12, Purpose::MeasurementNoise, [1212, 0]);
    let csv = lab_csv(
        "time_s,displacement_m",
        y.iter().enumerate().map(|(k, &v)| {
            let e: f64 = StandardNormal.sample(&mut rng);
            vec![k as f64 * dt, v + sd * e]
        }),
    );
    let id = identify(&Measurement::from_csv(&csv).unwrap(), &IdentifySettings::default()).unwrap();
    for m in &id.background_modes {
        println!("ring-down background: omega {:e}, zeta {:.5}, snr {:.1}", m.omega_rad_s, m.zeta, m.amplitude_snr);
    }
    check(&id.modes, 3.0, "ring-down");
}
