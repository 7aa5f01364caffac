//! A decided verdict names the measurement that would falsify it
//! (`diagnose::falsify`), and feeding that measurement back works: on a
//! truth outside the catalogue, a decided wrong name either stays within its
//! own predictive interval (the measurement cannot tell) or the new
//! diagnosis no longer decides it.
//!
//! Generator of the data (closed form, no code of `src/`): a simply
//! supported Eringen-nonlocal Euler–Bernoulli beam on a Winkler foundation of
//! modulus k, one internal variable (Δ, Ω), no viscous damping. Eringen's
//! law acts on every distributed transverse load, the foundation's reaction
//! as the inertia, so on the sine mode of wavenumber q = nπ/L
//!   EI·G(s)·q⁴ W = (1 + (e0a q)²)(−ρA s² − k) W,  G(s) = 1 + Δ s/(s + Ω),
//! and with λ_n = EI q⁴/(ρA(1 + (e0a q)²)) and κ = k/ρA the poles of mode n
//! are the roots of the cubic
//!   s³ + Ω s² + (κ + λ_n(1 + Δ)) s + (κ + λ_n)Ω = 0
//! (its complex pair is the mode: ω = |s|, ζ = −Re s/|s|). A gate's
//! electrostatic pull is a negative k (a softening that is the same for every
//! mode). Before the catalogue held `elastic-foundation` (issue 65) it looked
//! like a compression on modes 1–5 and was named `axial-force`, decided; the
//! falsification test below was written for that case and still runs it.
//! With the class, every foundation of `explore_foundations` is named
//! `elastic-foundation` (`tests/diagnose_falsify.md`).

mod closed_form_records;

use closed_form_records::{data, observations};
use nalgebra::Matrix3;
use nanobeam::calibration::ModeObservation;
use nanobeam::diagnose::{diagnose, DiagnoseSettings, Diagnosis};

/// The truth: the nominal beam of the file (L = 8 nm, d = 1 nm, E = 1 TPa,
/// ρ = 2300 kg/m³) with e0a, one relaxation and a foundation κ = k/ρA as a
/// fraction of the first mode's λ₁ (negative: a gate's pull).
struct Truth {
    e0a_nm: f64,
    delta: f64,
    omega_rad_s: f64,
    kappa_over_lambda1: f64,
}

impl Truth {
    /// (ω, ζ) of mode n by the closed form (module doc).
    fn mode(&self, n: usize) -> (f64, f64) {
        let (l, d, e, rho) = (8e-9, 1e-9, 1e12, 2300.0);
        let area = std::f64::consts::PI * d * d / 4.0;
        let inertia = std::f64::consts::PI * d.powi(4) / 64.0;
        let lambda = |n: usize| {
            let q = n as f64 * std::f64::consts::PI / l;
            e * inertia * q.powi(4) / (rho * area * (1.0 + (self.e0a_nm * 1e-9 * q).powi(2)))
        };
        let kappa = self.kappa_over_lambda1 * lambda(1);
        let (ln, w) = (lambda(n), self.omega_rad_s);
        // in x = s/√λ_n (every coefficient of order 1), the companion
        // matrix's eigenvalue polished by Newton on the cubic
        let r = ln.sqrt();
        let (a, b, c) = (w / r, (kappa + ln * (1.0 + self.delta)) / ln, (kappa + ln) * w / (ln * r));
        let companion = Matrix3::new(0.0, 0.0, -c, 1.0, 0.0, -b, 0.0, 1.0, -a);
        let mut x = companion
            .complex_eigenvalues()
            .iter()
            .copied()
            .find(|x| x.im > 0.0)
            .expect("a lightly damped mode has a complex pair");
        for _ in 0..4 {
            x -= (((x + a) * x + b) * x + c) / ((3.0 * x + 2.0 * a) * x + b);
        }
        let s = x * r;
        (s.norm(), -s.re / s.norm())
    }

    /// Measured modes `modes` with the suites' sds, noise drawn from `seed`.
    fn observations(&self, modes: &[usize], seed: u64) -> Vec<ModeObservation> {
        observations(|n| self.mode(n), modes, seed)
    }
}

fn summary(d: &Diagnosis) -> String {
    format!("cause {} (decided: {:?}, of {:?})", d.cause, d.decided_causes, d.causes)
}

/// The closed form against itself at Δ = κ = 0: the local elastic beam's
/// ω₁ = (π/L)²√(EI/ρA), and ζ = 0. (A check of the generator's algebra, not
/// of the crate.)
#[test]
fn the_generator_reduces_to_the_textbook_beam() {
    let t = Truth { e0a_nm: 0.0, delta: 0.0, omega_rad_s: 1e12, kappa_over_lambda1: 0.0 };
    let (w1, z1) = t.mode(1);
    let (l, d): (f64, f64) = (8e-9, 1e-9);
    let textbook = (std::f64::consts::PI / l).powi(2) * (1e12 * d * d / 16.0 / 2300.0).sqrt();
    assert!((w1 / textbook - 1.0).abs() < 1e-12, "{w1} vs {textbook}");
    assert!(z1.abs() < 1e-12);
    // a foundation adds κ to every ω² of the elastic beam: ω₂² − ω₁² is unchanged
    let f = Truth { kappa_over_lambda1: -0.3, ..t };
    let gap = |t: &Truth| t.mode(2).0.powi(2) - t.mode(1).0.powi(2);
    assert!((gap(&f) / gap(&t) - 1.0).abs() < 1e-9);
}

/// A gate's pull (κ = −0.3 λ₁) on modes 1–5, noise seed 651: named
/// `axial-force`, decided, before the catalogue held the foundation; now
/// `elastic-foundation`, undecided (`explore_foundations`). Whatever the diagnosis
/// decides, it names a falsifying measurement for it; the truth's value of
/// that observable, fed back as a measured mode, either lies inside the
/// stated 95 % interval and the verdict stands, or it ends the decision
/// (`unexplained`, or the causes decided before no longer all decided).
#[test]
fn a_gate_pull_verdict_is_falsified_by_its_own_suggestion() {
    let seed = 651;
    let truth = Truth { e0a_nm: 1.0, delta: 0.45, omega_rad_s: 4e11, kappa_over_lambda1: -0.3 };
    let settings = DiagnoseSettings::quick();
    let first = diagnose(&data(truth.observations(&[1, 2, 3, 4, 5], seed), seed), &settings).expect("valid data");
    eprintln!("modes 1-5: {}; falsifying: {:?}", summary(&first), first.falsifying_measurement);
    if first.decided_causes.is_empty() {
        assert!(first.falsifying_measurement.is_none(), "nothing decided, nothing to falsify");
        return;
    }
    let f = first.falsifying_measurement.as_ref().expect("a decided verdict names its falsifying measurement");
    assert!(f.mode > 5 && !f.rivals.is_empty(), "{f:?}");
    assert!(f.interval_95[0] < f.predicted && f.predicted < f.interval_95[1], "{f:?}");
    let (omega, zeta) = truth.mode(f.mode);
    let value = if f.quantity == "omega" { omega } else { zeta };
    let inside = f.interval_95[0] <= value && value <= f.interval_95[1];
    eprintln!("truth's {} of mode {}: {value:e}, interval {:?}: inside = {inside}", f.quantity, f.mode, f.interval_95);
    let mut modes: Vec<usize> = (1..=5).collect();
    modes.push(f.mode);
    let second = diagnose(&data(truth.observations(&modes, seed), seed), &settings).expect("valid data");
    eprintln!("modes 1-5 and {}: {}", f.mode, summary(&second));
    let still_decided = first.decided_causes.iter().all(|c| second.decided_causes.contains(c));
    if inside {
        // the measurement agrees with the verdict: it stands (measured
        // without the foundation class: the gate's pull mimics a compression
        // through mode 8 once e0a and the relaxation adjust, so ω₇ landed
        // inside the interval and `axial-force` stayed decided:
        // tests/diagnose_falsify.md)
        assert!(still_decided, "a measurement inside the interval changed the verdict: {}", summary(&second));
    } else {
        assert!(
            second.cause == "unexplained" || !still_decided,
            "the measurement fell outside the interval, yet {:?} stays decided: {}",
            first.decided_causes,
            summary(&second)
        );
    }
}

/// Exploration (not in CI): the verdicts on foundations of several signs
/// and sizes, modes 1–5.
#[test]
#[ignore]
fn explore_foundations() {
    let settings = DiagnoseSettings::quick();
    for (i, k) in [-0.15, -0.3, 0.5, 2.0, -0.5, 1.0].into_iter().enumerate() {
        let seed = 650 + i as u64;
        let truth = Truth { e0a_nm: 1.0, delta: 0.45, omega_rad_s: 4e11, kappa_over_lambda1: k };
        let d = diagnose(&data(truth.observations(&[1, 2, 3, 4, 5], seed), seed), &settings).expect("valid data");
        eprintln!("kappa {k}: {}; falsifying {:?}", summary(&d), d.falsifying_measurement);
    }
}
