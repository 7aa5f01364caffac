//! Issue 69, defect 3: `identify` on a thermal-motion record must not move
//! when the samples do not — under a shift of the time origin, a common
//! scale of the displacements and a DC offset. Records and numbers:
//! `tests/invariance.md`.
//!
//! Generator (written here, not `src/`): a Langevin-like record, the sum of
//! three sampled damped oscillators, each a second-order autoregressive
//! process x_k = φ1 x_{k−1} + φ2 x_{k−2} + e_k with poles e^{(−ζω ± iω_d)Δt}
//! driven by seeded ChaCha8 Gaussian noise, plus a white floor, in two
//! independent columns, written as CSV text with Rust's shortest
//! round-trip form of every value (the file a script writes with `repr`).
//! The lines (300, 750, 1320 GHz; ζ = 0.05, 0.03, 0.02) sit in the lowest
//! quarter of a 5-THz Nyquist band, as an MD record's do.

use nanobeam::identify::data::Measurement;
use nanobeam::identify::{identify, IdentifySettings};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::f64::consts::PI;
use std::sync::OnceLock;

/// Sampling step (s): a short decimal, as an MD step times its output
/// interval is (`identify::step`).
const DT: f64 = 1e-13;
/// Samples per column: the narrowest line (1320 GHz, ζ = 0.03) is 79 GHz
/// wide at half power, and `thermal` picks segments of 1 024 samples
/// (bins of 9.8 GHz, 8 bins to the line): 15 segments per column at 50 %
/// overlap, 30 averages over the two columns.
const N: usize = 8192;
/// (f Hz, ζ) of the three lines.
const LINES: [(f64, f64); 3] = [(3.0e11, 0.08), (7.5e11, 0.05), (1.32e12, 0.03)];

/// The two displacement columns (m) of the record of `seed`.
fn columns(seed: u64) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let burn = 4000; // the slowest pole's r^4000 = e^{−0.05·2π·0.03·4000} < 1e-16
    (0..2)
        .map(|_| {
            let mut col = vec![0.0; N];
            for &(f, zeta) in &LINES {
                let w = 2.0 * PI * f;
                let r = (-zeta * w * DT).exp();
                let wd = w * (1.0 - zeta * zeta).sqrt();
                let (p1, p2) = (2.0 * r * (wd * DT).cos(), -r * r);
                let (mut a, mut b) = (0.0, 0.0);
                for k in 0..N + burn {
                    let e: f64 = StandardNormal.sample(&mut rng);
                    let x = p1 * a + p2 * b + 1e-12 * e;
                    (b, a) = (a, x);
                    if k >= burn {
                        col[k - burn] += x;
                    }
                }
            }
            for v in &mut col {
                let e: f64 = StandardNormal.sample(&mut rng);
                *v += 2e-12 * e;
            }
            col
        })
        .collect()
}

/// The record as CSV text: times t0 + k·Δt, displacements scale·x + offset.
fn csv(cols: &[Vec<f64>], t0: f64, scale: f64, offset: f64) -> String {
    let mut s = String::from("time_s,thermal_a_m,thermal_b_m\n");
    for k in 0..N {
        s.push_str(&format!("{:e}", t0 + k as f64 * DT));
        for c in cols {
            s.push_str(&format!(",{:e}", scale * c[k] + offset));
        }
        s.push('\n');
    }
    s
}

/// (ω, sd ω, ζ, sd ζ) of every reported mode.
type Modes = Vec<[f64; 4]>;

fn modes(text: &str) -> Modes {
    modes_of(&Measurement::from_csv(text).expect("a thermal record"))
}

fn modes_of(m: &Measurement) -> Modes {
    let id = identify(m, &IdentifySettings::default()).expect("identified");
    id.modes.iter().map(|m| [m.omega_rad_s, m.omega_sd_rad_s, m.zeta, m.zeta_sd]).collect()
}

/// The largest move of ω or ζ of any mode, in the reference's sd; infinite
/// when the modes found differ in number.
fn largest_move_sd(reference: &Modes, other: &Modes) -> f64 {
    if reference.len() != other.len() {
        return f64::INFINITY;
    }
    reference
        .iter()
        .zip(other)
        .map(|(a, b)| ((a[0] - b[0]).abs() / a[1]).max((a[2] - b[2]).abs() / a[3]))
        .fold(0.0, f64::max)
}

/// The unshifted, unscaled record of seed 7 and its modes, computed once
/// for every test of this file.
fn reference() -> &'static (Vec<Vec<f64>>, Modes) {
    static REFERENCE: OnceLock<(Vec<Vec<f64>>, Modes)> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let cols = columns(7);
        let modes = modes(&csv(&cols, 0.0, 1.0, 0.0));
        // the fit reports the 750 and 1320 GHz lines and keeps the broad
        // 300 GHz one as a background term (tests/invariance.md); the
        // invariances hold for whatever it reports
        assert!(modes.len() >= 2, "{modes:?}");
        (cols, modes)
    })
}

/// `cases` proptest cases, the same on every run, as CI needs
/// (`tests/beam_properties.rs` fixes its seed too).
fn fixed_seed(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x696e_7661_7269_616e),
        ..ProptestConfig::default()
    }
}

proptest! {
    // 4 cases: each is one `identify` (about 1 s in the test build)
    #![proptest_config(fixed_seed(4))]

    /// A time origin anywhere from −1 ns to +100 ns (the 2 ns,
    /// 20 ns and −0.175 ns among them; 100 ns is 120 record lengths) gives
    /// the same ω, ζ and sd bit for bit: the times enter only through the
    /// sampling step, which is canonical (`identify::step`). Before it the
    /// end-point step of a shifted record was a few ulps off and the fit's
    /// outcome moved (tests/invariance.md).
    #[test]
    fn a_shift_of_the_time_origin_changes_nothing(t0 in prop_oneof![-1e-9..1e-9f64, 1e-9..1e-7f64]) {
        let (cols, base) = reference();
        let shifted = modes(&csv(cols, t0, 1.0, 0.0));
        prop_assert_eq!(&shifted, base, "t0 = {:e}", t0);
    }

    /// A power-of-two scale of the displacements is exact in floating
    /// point, and so must the result be: ω, ζ and their sd bit for bit.
    #[test]
    fn a_power_of_two_scale_changes_nothing(j in -60i32..60) {
        let (cols, base) = reference();
        let scaled = modes(&csv(cols, 0.0, 2f64.powi(j), 0.0));
        prop_assert_eq!(&scaled, base, "scale 2^{}", j);
    }
}

/// A free decay (`time_s,displacement_m`): two damped modes (20 and 55 kHz,
/// ζ = 0.01, 0.02) sampled at 1 MHz for 2 ms, plus seeded white noise at
/// 10⁻³ of the first sample, written from time `t0`.
fn decay_csv(t0: f64) -> String {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let dt = 1e-6;
    let mut s = String::from("time_s,displacement_m\n");
    for k in 0..2000 {
        let t = k as f64 * dt;
        let y: f64 = [(2e4, 0.01, 1.0), (5.5e4, 0.02, 0.6)]
            .iter()
            .map(|&(f, z, a)| {
                let w = 2.0 * PI * f;
                a * (-z * w * t).exp() * (w * (1.0f64 - z * z).sqrt() * t).cos()
            })
            .sum();
        let e: f64 = StandardNormal.sample(&mut rng);
        s.push_str(&format!("{:e},{:e}\n", t0 + t, 1e-9 * (y + 1e-3 * e)));
    }
    s
}

/// The decay's modes, untouched, computed once.
fn decay_reference() -> &'static Modes {
    static REFERENCE: OnceLock<Modes> = OnceLock::new();
    REFERENCE.get_or_init(|| {
        let modes = modes(&decay_csv(0.0));
        assert!(modes.len() >= 2, "{modes:?}");
        modes
    })
}

proptest! {
    #![proptest_config(fixed_seed(3))]

    /// The free decay from a time origin of −1 s … +1 s (500 record lengths;
    /// the times still resolve the 1 µs step to 10⁻⁹ of it): ω, ζ and sd bit
    /// for bit. The decay's fit runs on sample indices; the step only turns
    /// its rates into rad/s, and before the canonical step a shifted
    /// record's ω differed in its last bits.
    #[test]
    fn a_free_decay_from_another_time_origin_is_the_same(t0 in -1.0..1.0f64) {
        prop_assert_eq!(&modes(&decay_csv(t0)), decay_reference(), "t0 = {:e}", t0);
    }
}

/// Time rounded to float32 (the case): the step stays 1e-13 s
/// within the column's resolution, and the result is bit for bit the same.
#[test]
fn times_rounded_to_float32_change_nothing() {
    let (cols, base) = reference();
    let text = csv(cols, 0.0, 1.0, 0.0);
    let mut single = String::new();
    for (i, line) in text.lines().enumerate() {
        if i == 0 {
            single.push_str(line);
        } else {
            let (t, rest) = line.split_once(',').expect("a row");
            let t: f64 = t.parse().expect("a time");
            single.push_str(&format!("{:e},{rest}", f64::from(t as f32)));
        }
        single.push('\n');
    }
    assert_eq!(&modes(&single), base);
}

proptest! {
    #![proptest_config(fixed_seed(4))]

    /// A common scale that is no power of two (1e-6 … 1e6) rounds every
    /// sample differently (a relative change of 1e-16): ω and ζ must move
    /// by less than 0.1 of their sd. 0.1 sd is the bar: a change
    /// of the data by rounding is 10⁻¹⁶ of a sample, and a well-posed fit
    /// moves its optimum by that order; the refinement's stopping rule
    /// (`refine::JOINT_FTOL`) leaves a parameter ≤ 0.004 sd from its optimum
    /// on a PSD of this size, 25 times under the bar.
    #[test]
    fn a_common_scale_moves_nothing_beyond_a_tenth_of_an_sd(e in -6.0..6.0f64) {
        let (cols, base) = reference();
        let scale = 10f64.powf(e) * 1.2345;
        let moved = largest_move_sd(base, &modes(&csv(cols, 0.0, scale, 0.0)));
        prop_assert!(moved < 0.1, "scale {:e}: {} sd", scale, moved);
    }

    /// A DC offset of up to 10 × the record's sd (the Welch estimate removes
    /// each segment's mean): the same bar and reason as the scale.
    #[test]
    fn a_dc_offset_moves_nothing_beyond_a_tenth_of_an_sd(d in -10.0..10.0f64) {
        let (cols, base) = reference();
        let sd = (cols[0].iter().map(|v| v * v).sum::<f64>() / N as f64).sqrt();
        let moved = largest_move_sd(base, &modes(&csv(cols, 0.0, 1.0, d * sd)));
        prop_assert!(moved < 0.1, "offset {:e} m: {} sd", d * sd, moved);
    }
}

/// `v` rounded to `bits` significant bits of its mantissa (of 52), half up.
fn round_to_bits(v: f64, bits: u32) -> f64 {
    let drop = 52 - bits;
    f64::from_bits((v.to_bits() + (1u64 << (drop - 1))) & !((1u64 << drop) - 1))
}

/// The cause of the two invariances above (open until the fit was made
/// insensitive to its input's last bits), as its own property: the
/// record's Welch PSD with every bin rounded to 20, 28 or 36 significant
/// bits (a relative change ≤ 2⁻²¹ = 4.8e-7, 2⁻²⁹, 2⁻³⁷) must give the same
/// modes within 0.1 sd. The bar: a bin of a Welch estimate of ν = 30
/// averages scatters by 1/√ν = 0.18 of its value, so rounding moves each
/// bin by ≤ 2.6e-6 of its own sd; the modes, weighted sums of the bins'
/// scatter whose total is 1 sd, move by that order, 10⁻⁵ of the bar
/// (plus the stopping rule's ≤ 0.004 sd, `a_common_scale_…` above).
/// A scale or an offset changes the PSD by 10⁻¹⁶ – 10⁻¹³ relative
/// (tests/invariance.md, measured on cc7): a fit that passes this passes
/// those. Before the well-conditioned LSCF (`identify::lscf`), 20 and 36
/// bits moved the modes by 196 sd (another set of modes); with it alone, 28
/// bits by 0.83 sd, until the pseudo-modes that fit no line were put back
/// above the band (`identify::select`): the fit's outcome was a function of
/// the data's last bits, which this test measures directly.
#[test]
fn the_psd_rounded_below_its_scatter_moves_nothing() {
    let (cols, base) = reference();
    let Measurement::Psd { omega_rad_s, psd_m2_s_per_rad } =
        Measurement::from_csv(&csv(cols, 0.0, 1.0, 0.0)).expect("a record")
    else {
        panic!("a thermal record gives a PSD");
    };
    let moves: Vec<(u32, f64)> = [20, 28, 36]
        .into_iter()
        .map(|bits| {
            let psd = psd_m2_s_per_rad.iter().map(|&v| round_to_bits(v, bits)).collect();
            let m = Measurement::Psd { omega_rad_s: omega_rad_s.clone(), psd_m2_s_per_rad: psd };
            (bits, largest_move_sd(base, &modes_of(&m)))
        })
        .collect();
    assert!(moves.iter().all(|&(_, moved)| moved < 0.1), "(bits, largest move in sd): {moves:?}");
}
