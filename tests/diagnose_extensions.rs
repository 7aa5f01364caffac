//! The field's extensions (issue 65) against a generator that shares no code
//! with `src/`: which verdicts `diagnose` gives on data with a foundation, a
//! loss factor, Kelvin–Voigt damping, a strain gradient (in the catalogue
//! since `strain-gradient` joined it; outside it when `tests/diagnose_extensions.md`
//! was measured), earlier kinds, and kinds that stay outside the catalogue
//! (a shallow arch, a Cole–Cole relaxation, a mass spread over a segment).
//!
//! Generator (closed form): a simply supported nonlocal Euler–Bernoulli
//! beam (L = 8 nm, d = 1 nm, E = 1 TPa, ρ = 2300 kg/m³, e0a = 1 nm, one
//! relaxation Δ = 0.45, Ω = 4e11 rad/s: the base model's truth). Every
//! effect here keeps the sine modes, so mode n (q = nπ/L) has the pole of
//!   s² + c s + a_n + λ_n (1 + iη) G(s) = 0,
//!   λ_n = EI q⁴ (1 + l²q²)/(ρA(1 + μq²)),  μ = (e0a)²,
//!   G(s) = 1 + Δ s/(s + Ω) + τ s + Δ_cc (sτ_cc)^α/(1 + (sτ_cc)^α),
//! with a_n = k/ρA (a Winkler foundation k, Eringen's operator on its
//! reaction) plus, for n = 1 only, EA h² q⁴/(2ρA(1 + μq²)) (a shallow
//! sinusoidal arch of rise h with immovable ends: the stretching its first
//! mode causes, by Galerkin on the sine; the higher sines are orthogonal to
//! the arch's curvature and stay as they are), c = C/ρA (viscous), l the
//! strain-gradient length (Lim, Zhang & Reddy's stiffening (1 + l²q²)),
//! τ the Kelvin–Voigt time, (Δ_cc, τ_cc, α) a Cole–Cole relaxation. The
//! root is found by Newton along a homotopy that switches the damping and
//! loss terms on in 40 steps from the elastic pair i√(a_n + λ_n) (each step
//! moves the root by ≲ 1/40 of its shift, well inside Newton's basin), and
//! checked by its residual. Noise as the hidden suites': ω 0.3 %, ζ 3 %.
//!
//! A mass spread over a segment [a, b] (ρ_s per length, local: it carries no
//! Eringen term) couples the sines, so λ_n there is the n-th eigenvalue of the
//! Galerkin pencil in the first [`GALERKIN_SINES`] sines: K_ij = δ_ij EI q_i⁴
//! L/2, M_ij = δ_ij ρA(1 + μq_i²) L/2 + ρ_s ∫_a^b sin q_i x sin q_j x dx
//! (closed-form integrals; nalgebra's symmetric eigen of L⁻¹KL⁻ᵀ, M = LLᵀ).
//! The relaxation multiplies all of K and nothing else is damped, so the
//! Galerkin modes stay uncoupled in s and each pole solves
//! s² + λ_n G(s) = 0 as above.

mod closed_form_records;

use closed_form_records::{data, file, observations};
use nanobeam::calibration::ModeObservation;
use nanobeam::diagnose::{diagnose, DiagnoseSettings, Diagnosis};
use num_complex::Complex64;

/// One truth: the base beam plus the effects (zero = absent).
#[derive(Debug, Clone, Copy, Default)]
struct Truth {
    /// k as a fraction of ρAλ₁ of the base beam's first mode.
    foundation: f64,
    eta: f64,
    /// ζ that Kelvin–Voigt damping alone gives mode 5: τ = 2ζ/ω₅.
    kv_zeta5: f64,
    /// Strain-gradient length l in nm.
    gradient_nm: f64,
    /// Arch rise h in nm.
    rise_nm: f64,
    /// Cole–Cole (Δ_cc, ω_cc = 1/τ_cc in rad/s, α).
    cole_cole: (f64, f64, f64),
    /// Viscous ζ₁ (C = 2ρAω₁ζ₁).
    viscous_zeta1: f64,
    /// Axial tension in units of EIπ²/L².
    tension: f64,
    /// A mass spread over a segment: (its mass over the beam's, a/L, b/L).
    segment: (f64, f64, f64),
}

/// Sines of the segment's Galerkin pencil. Converged for the study's modes
/// 1–5 to within 1e-4 relative in λ (twice as many sines move them by less,
/// `the_generator_reduces_to_known_limits`), far below the 0.6 % the ω noise
/// puts on λ.
const GALERKIN_SINES: usize = 60;

/// λ_n (n = 1..) of the beam with a mass spread over a segment (module doc).
fn segment_lambdas((ratio, a, b): (f64, f64, f64), n_max: usize, n: usize) -> Vec<f64> {
    let rho_a = RHO * area();
    let rho_s = ratio * rho_a * L / ((b - a) * L);
    let (xa, xb) = (a * L, b * L);
    let q = |i: usize| (i + 1) as f64 * std::f64::consts::PI / L;
    // ∫_a^b sin(pi x) sin(pj x) dx
    let integral = |i: usize, j: usize| -> f64 {
        let (p, r) = (q(i), q(j));
        if i == j {
            let f = |x: f64| x / 2.0 - (2.0 * p * x).sin() / (4.0 * p);
            f(xb) - f(xa)
        } else {
            let f = |x: f64| ((p - r) * x).sin() / (2.0 * (p - r)) - ((p + r) * x).sin() / (2.0 * (p + r));
            f(xb) - f(xa)
        }
    };
    let mut m = nalgebra::DMatrix::<f64>::zeros(n, n);
    let mut k = nalgebra::DMatrix::<f64>::zeros(n, n);
    for i in 0..n {
        k[(i, i)] = ei() * q(i).powi(4) * L / 2.0;
        for j in 0..n {
            m[(i, j)] = rho_s * integral(i, j);
        }
        m[(i, i)] += rho_a * (1.0 + (E0A * q(i)).powi(2)) * L / 2.0;
    }
    let chol = nalgebra::Cholesky::new(m).expect("a positive mass");
    let l_inv = chol.l().try_inverse().expect("invertible");
    let c = &l_inv * k * l_inv.transpose();
    let mut lambdas: Vec<f64> = nalgebra::SymmetricEigen::new(c).eigenvalues.iter().copied().collect();
    lambdas.sort_by(f64::total_cmp);
    lambdas.truncate(n_max);
    lambdas
}

const L: f64 = 8e-9;
const D: f64 = 1e-9;
const E: f64 = 1e12;
const RHO: f64 = 2300.0;
const E0A: f64 = 1e-9;
const DELTA: f64 = 0.45;
const OMEGA: f64 = 4e11;

fn area() -> f64 {
    std::f64::consts::PI * D * D / 4.0
}

fn ei() -> f64 {
    E * std::f64::consts::PI * D.powi(4) / 64.0
}

/// λ_n of the base beam (no gradient).
fn lambda_base(n: usize) -> f64 {
    let q = n as f64 * std::f64::consts::PI / L;
    ei() * q.powi(4) / (RHO * area() * (1.0 + (E0A * q).powi(2)))
}

impl Truth {
    /// (ω, ζ) of mode n (module doc).
    fn mode(&self, n: usize) -> (f64, f64) {
        let q = n as f64 * std::f64::consts::PI / L;
        let nonlocal = 1.0 + (E0A * q).powi(2);
        let rho_a = RHO * area();
        let lam = if self.segment.0 > 0.0 {
            segment_lambdas(self.segment, n, GALERKIN_SINES)[n - 1]
        } else {
            ei() * q.powi(4) * (1.0 + (self.gradient_nm * 1e-9 * q).powi(2)) / (rho_a * nonlocal)
                + self.tension * ei() * (std::f64::consts::PI / L).powi(2) * q * q / rho_a
        };
        let mut a = self.foundation * lambda_base(1);
        if n == 1 {
            let h = self.rise_nm * 1e-9;
            a += E * area() * h * h * q.powi(4) / (2.0 * rho_a * nonlocal);
        }
        let w1 = lambda_base(1).sqrt();
        let c = 2.0 * w1 * self.viscous_zeta1;
        let tau = 2.0 * self.kv_zeta5 / lambda_base(5).sqrt();
        let (dcc, wcc, alpha) = self.cole_cole;
        let g = |s: Complex64, t: f64| -> (Complex64, Complex64) {
            let mut g = Complex64::new(1.0, 0.0) + DELTA * s / (s + OMEGA);
            let mut dg = Complex64::new(DELTA * OMEGA, 0.0) / ((s + OMEGA) * (s + OMEGA));
            g += t * tau * s;
            dg += t * tau;
            if dcc > 0.0 {
                let x = (s / wcc).powf(alpha);
                let dx = alpha * x / s;
                g += t * dcc * x / (1.0 + x);
                dg += t * dcc * dx / ((1.0 + x) * (1.0 + x));
            }
            (g, dg)
        };
        let mut s = Complex64::new(0.0, (a + lam).sqrt());
        let steps = 40;
        for k in 1..=steps {
            let t = k as f64 / steps as f64;
            let lc = Complex64::new(lam, lam * self.eta * t);
            for _ in 0..50 {
                let (gv, dgv) = g(s, t);
                let f = s * s + t * c * s + a + lc * gv;
                let df = 2.0 * s + t * c + lc * dgv;
                let step = f / df;
                s -= step;
                if step.norm() <= 1e-15 * s.norm() {
                    break;
                }
            }
        }
        let (gv, _) = g(s, 1.0);
        let f = s * s + c * s + a + Complex64::new(lam, lam * self.eta) * gv;
        assert!(f.norm() <= 1e-10 * s.norm_sqr(), "root not converged: residual {f}");
        assert!(s.im > 0.0, "an oscillatory pole");
        (s.norm(), -s.re / s.norm())
    }

    fn observations(&self, modes: &[usize], seed: u64) -> Vec<ModeObservation> {
        observations(|n| self.mode(n), modes, seed)
    }
}

/// The grade of a verdict: `right` (the decided causes are the truth's, or
/// nothing decided for a kind outside the catalogue), `undecided` (nothing
/// decided where a cause was expected; the truth named or not), `wrong` (a
/// decided cause the truth does not hold: the worst outcome).
fn grade(d: &Diagnosis, expected: &[&str]) -> &'static str {
    let decided: Vec<&str> = d.decided_causes.iter().map(|s| s.as_str()).collect();
    if decided.iter().any(|c| !expected.contains(c)) {
        "wrong"
    } else if expected.is_empty() || (!decided.is_empty() && expected.iter().all(|c| decided.contains(c))) {
        "right"
    } else {
        "undecided"
    }
}

/// The kinds, the causes a right verdict decides (empty: outside the
/// catalogue, where `unexplained` or nothing decided is right).
fn kinds() -> Vec<(&'static str, Truth, Vec<&'static str>)> {
    let t = Truth::default();
    vec![
        ("substrate k = +1.0 λ₁", Truth { foundation: 1.0, ..t }, vec!["elastic-foundation"]),
        ("gate pull k = −0.3 λ₁", Truth { foundation: -0.3, ..t }, vec!["elastic-foundation"]),
        ("loss factor η = 0.02", Truth { eta: 0.02, ..t }, vec!["loss-factor"]),
        ("loss factor η = 0.1", Truth { eta: 0.1, ..t }, vec!["loss-factor"]),
        ("Kelvin–Voigt ζ₅ = 0.05", Truth { kv_zeta5: 0.05, ..t }, vec!["extra-relaxation"]),
        ("viscous ζ₁ = 0.02", Truth { viscous_zeta1: 0.02, ..t }, vec!["viscous-damping"]),
        ("tension 1.0 N_cr", Truth { tension: 1.0, ..t }, vec!["axial-force"]),
        ("strain gradient l = 0.4 nm", Truth { gradient_nm: 0.4, ..t }, vec!["strain-gradient"]),
        ("shallow arch h = 0.15 nm (outside)", Truth { rise_nm: 0.15, ..t }, vec![]),
        ("Cole–Cole α = 0.5 (outside)", Truth { cole_cole: (0.3, 2e12, 0.5), ..t }, vec![]),
        ("mass 0.3 ρAL over [0.15, 0.45] L (outside)", Truth { segment: (0.3, 0.15, 0.45), ..t }, vec![]),
    ]
}

/// The generator against itself: with no effect it is the base beam's cubic
/// (ω₁ of the local elastic beam at Δ = 0 is the textbook (π/L)²√(EI/ρA));
/// a loss factor alone gives ζ ≈ η/2 above the base's; a foundation adds
/// k/ρA to ω² of the elastic beam. (Checks of the generator's algebra.)
#[test]
fn the_generator_reduces_to_known_limits() {
    let base = Truth::default();
    let (w1, z1) = base.mode(1);
    assert!(w1 > lambda_base(1).sqrt() && z1 > 0.0 && z1 < 0.5);
    let lossy = Truth { eta: 0.1, ..base };
    for n in 1..=5 {
        let dz = lossy.mode(n).1 - base.mode(n).1;
        assert!((dz - 0.05).abs() < 0.02, "mode {n}: Δζ {dz}");
    }
    let arch = Truth { rise_nm: 0.3, ..base };
    assert!(arch.mode(1).0 > 1.05 * base.mode(1).0 && arch.mode(2) == base.mode(2));
    // a segment over the whole span is a uniform local mass ρ_s = 0.3ρA:
    // λ_n = EIq⁴/(ρA(1 + μq²) + ρ_s) exactly (the sines stay uncoupled)
    let whole = segment_lambdas((0.3, 0.0, 1.0), 5, GALERKIN_SINES);
    for (n, l) in whole.iter().enumerate() {
        let q = (n + 1) as f64 * std::f64::consts::PI / L;
        let rho_a = RHO * area();
        let exact = ei() * q.powi(4) / (rho_a * (1.0 + (E0A * q).powi(2)) + 0.3 * rho_a);
        assert!((l / exact - 1.0).abs() < 1e-12, "mode {}: {l:e} vs {exact:e}", n + 1);
    }
    // a vanishing segment is the base beam
    let none = segment_lambdas((1e-12, 0.2, 0.3), 5, GALERKIN_SINES);
    for (n, l) in none.iter().enumerate() {
        assert!((l / lambda_base(n + 1) - 1.0).abs() < 1e-10, "mode {}", n + 1);
    }
    // the study's segment: converged in the number of sines, and heavier
    // than the beam's own mass would make it (every mode lower)
    let study = (0.3, 0.15, 0.45);
    let (coarse, fine) = (segment_lambdas(study, 5, GALERKIN_SINES), segment_lambdas(study, 5, 2 * GALERKIN_SINES));
    for n in 0..5 {
        let moved = (coarse[n] / fine[n] - 1.0).abs();
        eprintln!(
            "segment mode {}: lambda moves {moved:e} from {GALERKIN_SINES} to {} sines",
            n + 1,
            2 * GALERKIN_SINES
        );
        assert!(moved < 1e-4 && fine[n] < lambda_base(n + 1), "mode {}: {moved:e}", n + 1);
    }
}

/// A loss factor is named `loss-factor`, and never a wrong cause decided.
#[test]
fn a_loss_factor_is_named_as_one() {
    let seed = 661;
    let truth = Truth { eta: 0.1, ..Truth::default() };
    let d = diagnose(&data(truth.observations(&[1, 2, 3, 4, 5], seed), seed), &DiagnoseSettings::quick())
        .expect("valid data");
    eprintln!("{} decided {:?} of {:?}", d.cause, d.decided_causes, d.causes);
    assert_ne!(grade(&d, &["loss-factor"]), "wrong", "{:?}", d.decided_causes);
    assert!(d.causes.iter().any(|c| c == "loss-factor"), "{:?}", d.causes);
}

/// The study (not in CI: ~10 diagnoses of 20–40 s): every kind on modes
/// 1–5, two noise seeds each; prints the confusion (`tests/diagnose_extensions.md`).
#[test]
#[ignore]
fn extension_study() {
    let settings = DiagnoseSettings::quick();
    let only: Option<usize> = std::env::var("KIND").ok().and_then(|k| k.parse().ok());
    for (i, (label, truth, expected)) in kinds().into_iter().enumerate() {
        if only.is_some_and(|k| k != i) {
            continue;
        }
        for rep in 0..2u64 {
            let seed = 700 + 10 * i as u64 + rep;
            let obs = truth.observations(&[1, 2, 3, 4, 5], seed);
            if let Ok(dir) = std::env::var("DUMP") {
                // the set as a measured-data file, for the CLI (old and new binaries)
                let yaml = serde_yaml::to_string(&file(obs.clone(), seed)).unwrap();
                std::fs::write(format!("{dir}/ext-{seed}.yaml"), yaml).unwrap();
            }
            let t0 = std::time::Instant::now();
            let d = diagnose(&data(obs, seed), &settings).expect("valid data");
            println!(
                "| {label} | {seed} | {} | {} | {} | {} | {} models, {} screened, {} solves | {:.1} s |",
                d.cause,
                d.causes.join(" + "),
                d.decided_causes.join(" + "),
                grade(&d, &expected),
                d.candidates.len(),
                d.screened.len(),
                d.forward_evaluations,
                t0.elapsed().as_secs_f64()
            );
        }
    }
}

/// A strain gradient on modes 1–5, seed 770: named `attached-mass`, decided
/// (`extension_study`) while the catalogue had no `strain-gradient`. The decided verdict names
/// its falsifying measurement; the truth's value of that observable, fed
/// back, must either lie inside the stated 95 % interval (then the verdict
/// may stand: the measurement cannot tell) or end the decision.
#[test]
#[ignore = "up to two diagnoses, the second of six modes: 80-151 s on 2 shared cores, too long for CI; measured \
            2026-12-07 with nine causes: attached-mass decided, falsified by omega_8 (truth 3.018e13 outside \
            [2.594e13, 2.729e13]), fed back: unexplained; with strain-gradient in the catalogue: strain-gradient, \
            undecided, so no falsifying measurement (80 s)"]
fn a_strain_gradient_verdict_meets_its_falsifying_measurement() {
    let seed = 770;
    let truth = Truth { gradient_nm: 0.4, ..Truth::default() };
    let settings = DiagnoseSettings::quick();
    let first = diagnose(&data(truth.observations(&[1, 2, 3, 4, 5], seed), seed), &settings).expect("valid data");
    eprintln!(
        "modes 1-5: {} decided {:?}; falsifying {:?}",
        first.cause, first.decided_causes, first.falsifying_measurement
    );
    if first.decided_causes.is_empty() {
        assert!(first.falsifying_measurement.is_none());
        return;
    }
    let f = first.falsifying_measurement.as_ref().expect("a decided verdict names its falsifying measurement");
    let (omega, zeta) = truth.mode(f.mode);
    let value = if f.quantity == "omega" { omega } else { zeta };
    let inside = f.interval_95[0] <= value && value <= f.interval_95[1];
    eprintln!("truth's {} of mode {}: {value:e}, interval {:?}: inside = {inside}", f.quantity, f.mode, f.interval_95);
    let mut modes: Vec<usize> = (1..=5).collect();
    modes.push(f.mode);
    let second = diagnose(&data(truth.observations(&modes, seed), seed), &settings).expect("valid data");
    eprintln!("with mode {}: {} decided {:?} of {:?}", f.mode, second.cause, second.decided_causes, second.causes);
    let still_decided = first.decided_causes.iter().all(|c| second.decided_causes.contains(c));
    if !inside {
        assert!(
            second.cause == "unexplained" || !still_decided,
            "the truth fell outside the interval, yet {:?} stays decided",
            first.decided_causes
        );
    }
}
