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
//! reaction) plus N q²/ρA (an axial tension N, below) plus, for n = 1
//! only, EA h² q⁴/(2ρA(1 + μq²)) (a shallow sinusoidal arch of rise h
//! with immovable ends: the stretching its first
//! mode causes, by Galerkin on the sine; the higher sines are orthogonal to
//! the arch's curvature and stay as they are), c = C/ρA (viscous), l the
//! strain-gradient length (Lim, Zhang & Reddy's stiffening (1 + l²q²)),
//! τ the Kelvin–Voigt time, (Δ_cc, τ_cc, α) a Cole–Cole relaxation.
//!
//! The tension is elastic: an axial force is a geometric stiffness, not the
//! material's, so neither G(s) nor η touches it (as the catalogue's
//! `axial-force`: `beam::fe::model`'s K̃_N, outside the relaxation in
//! `beam::fast::axial_spectrum`'s T̃(s)). Eringen's operator acts on N w″ as
//! on the foundation's reaction (Reddy 2007, eq. (28)):
//!   ρA(1 − μ∂²)ẅ + EI(1 + iη)G(∂_t) w⁗ − N(1 − μ∂²)w″ + … = 0,
//! and on w = sin(qx) e^{st} this is
//!   ρA(1 + μq²)s² + EI(1 + iη)G(s) q⁴ + N q²(1 + μq²) + … = 0:
//! divided by ρA(1 + μq²) the nonlocal factor of the tension cancels,
//! N q²(1 + μq²)/(ρA(1 + μq²)) = N q²/ρA, a term of a_n. (Until 2026-12-07
//! the generator put it in λ_n, a tension that relaxed with the material;
//! `tests/diagnose_extensions.md`, "The oracle".)
//!
//! The root is found by Newton along a homotopy that switches the damping and
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
//!
//! The oracle (`oracle_fits`, issue 65 item 2): every candidate model of the
//! diagnosis fitted to each set by least squares, far harder than the
//! diagnosis's screening (prior draws, nested starts, Levenberg–Marquardt,
//! Nelder–Mead polishes, restarts), to tell which sets some catalogue model
//! other than the truth's explains within noise (the mimics), where
//! `undecided` or a catalogue name is the best any method could say.

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
    /// Axial tension in units of EIπ²/L² (N > 0 pulls). Elastic: N q²/ρA is
    /// a term of a_n (module doc), outside G(s) and η, as the catalogue's
    /// `axial-force`. Until 2026-12-07 it entered λ_n, so the relaxation and
    /// the loss factor scaled it (a tension relaxing with the material): the
    /// oracle measured χ² 1624 and 1658 of ten observables at the truth's own
    /// `axial-force` parameters on seeds 760 and 761 then, 7.0 and 12.5 with
    /// the tension in a_n (`tests/diagnose_extensions.md`, "The oracle").
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
        };
        let mut a = self.foundation * lambda_base(1);
        if self.tension != 0.0 {
            // elastic (geometric) stiffness, outside G(s) and η: N q²(1 + μq²)/(ρA(1 + μq²)) = N q²/ρA
            assert!(self.segment.0 == 0.0, "a tension on the sines only, not in the segment's pencil");
            a += self.tension * ei() * (std::f64::consts::PI / L).powi(2) * q * q / rho_a;
        }
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
        ("deep arch h = 0.5 nm (outside)", Truth { rise_nm: 0.5, ..t }, vec![]),
        ("mass 1.0 ρAL over [0.15, 0.45] L (outside)", Truth { segment: (1.0, 0.15, 0.45), ..t }, vec![]),
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
    // a tension is elastic, a term of a_n: on mode n it is the foundation of
    // the same k/ρA = N q²/ρA (the base always relaxes, Δ = 0.45, so the
    // undamped ω_n² = λ_n + N q²/ρA is no pole of the generator; this is)
    let tensioned = Truth { tension: 1.0, ..base };
    for n in 1..=5 {
        let q = n as f64 * std::f64::consts::PI / L;
        let a = ei() * (std::f64::consts::PI / L).powi(2) * q * q / (RHO * area());
        let (w, z) = tensioned.mode(n);
        let (wf, zf) = Truth { foundation: a / lambda_base(1), ..base }.mode(n);
        assert!(
            (w / wf - 1.0).abs() < 1e-12 && (z / zf - 1.0).abs() < 1e-9,
            "mode {n}: ({w:e}, {z}) vs ({wf:e}, {zf})"
        );
        assert!(w > base.mode(n).0 && z < base.mode(n).1, "mode {n}: stiffer and, undamped, less damped");
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
    falsify_and_feed_back(Truth { gradient_nm: 0.4, ..Truth::default() }, 770);
}

/// A mass of 1.0 ρAL spread over [0.15, 0.45] L (outside the catalogue),
/// seed 820: `attached-mass` + `elastic-foundation` decided on modes 1–5,
/// a pair the oracle finds within noise (χ² 8.67 on 4 dof): a mimic, so
/// only a measurement beyond the five modes can tell. The decided verdict's
/// falsifying measurement, fed back with the truth's value, must keep the
/// verdict only if the value lies inside its stated interval.
#[test]
#[ignore = "two diagnoses, the second of six modes: about a minute in release; run by hand, result in \
            tests/diagnose_extensions.md (the deep arch and the heavy segment)"]
fn a_segment_mass_verdict_meets_its_falsifying_measurement() {
    falsify_and_feed_back(Truth { segment: (1.0, 0.15, 0.45), ..Truth::default() }, 820);
}

/// The decided verdict on modes 1–5 of `truth` (noise `seed`) names its
/// falsifying measurement; the truth's value of that observable, fed back,
/// must either lie inside the stated 95 % interval (then the verdict may
/// stand: the measurement cannot tell) or end the decision.
fn falsify_and_feed_back(truth: Truth, seed: u64) {
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

// ---------------------------------------------------------------------------
// The oracle (issue 65, item 2): which sets can ANY model of the catalogue
// explain? A least-squares fit of every candidate model, optimised far
// harder than the diagnosis's screening, on the generator's data.

/// The diagnosis's verdict on each set, from the final table of
/// `tests/diagnose_extensions.md` (head 027ec67, release CLI; 760 and 761
/// regenerated with an elastic tension, `extension_study`, 2026-12-07):
/// seed → (cause, named, grade).
const DIAGNOSED: [(u64, &str, &str, &str); 26] = [
    (700, "elastic-foundation", "elastic-foundation", "right"),
    (701, "elastic-foundation", "elastic-foundation", "right"),
    (710, "elastic-foundation", "elastic-foundation", "undecided"),
    (711, "elastic-foundation", "elastic-foundation", "right"),
    (720, "loss-factor", "loss-factor", "undecided"),
    (721, "loss-factor", "loss-factor", "undecided"),
    (730, "loss-factor", "loss-factor", "right"),
    (731, "loss-factor", "loss-factor", "undecided"),
    (740, "extra-relaxation", "extra-relaxation", "right"),
    (741, "extra-relaxation", "extra-relaxation", "right"),
    (750, "none", "—", "undecided"),
    (751, "none", "—", "undecided"),
    (760, "axial-force", "axial-force", "undecided"),
    (761, "axial-force", "axial-force", "undecided"),
    (770, "strain-gradient", "strain-gradient", "undecided"),
    (771, "strain-gradient", "strain-gradient", "undecided"),
    (780, "elastic-foundation", "elastic-foundation", "right"),
    (781, "elastic-foundation", "elastic-foundation", "right"),
    (790, "extra-relaxation", "extra-relaxation", "right"),
    (791, "loss-factor", "loss-factor", "right"),
    (800, "multiple", "viscous-damping + axial-force", "right"),
    (801, "multiple", "viscous-damping + attached-mass", "right"),
    (810, "unexplained", "—", "right"),
    (811, "unexplained", "—", "right"),
    (820, "multiple", "attached-mass + elastic-foundation", "wrong"),
    (821, "unexplained", "—", "right"),
];

/// The oracle's budget per model (see [`oracle_fit`]): prior draws scored
/// by χ², and how many of the best are polished by Levenberg–Marquardt.
const ORACLE_DRAWS: usize = 1500;
const ORACLE_KEEP: usize = 10;
/// Prior draws of the parameters a model adds to each sub-model's best fit
/// (the nested starts), and how many of the best nested starts are polished.
const ORACLE_NESTED_DRAWS: usize = 300;
const ORACLE_NESTED_KEEP: usize = 6;
/// Random restarts around the best optimum (each a Levenberg–Marquardt run
/// from a perturbation of 0.1, then 0.02, of the box in every coordinate).
const ORACLE_RESTARTS: usize = 6;
/// Levenberg–Marquardt iterations per run (each p + 1 forward solves or more).
const LM_ITERS: usize = 200;
/// Forward-difference step of the Jacobian in box coordinates v ∈ [0, 1]:
/// 1e-6 of a box that spans ≥ ln(1e2) in a log coordinate moves a parameter
/// by ≥ 4.6e-6 relative, an ω by ~1e-6 relative = 3e-4 σ of the 0.3 % noise:
/// far above the forward solves' round-off (~1e-12 relative, 3e-10 σ), far
/// below the curvature scale of χ².
const LM_STEP: f64 = 1e-6;
/// Nelder–Mead iterations of each polish of the best optimum.
const NM_ITERS: u64 = 3000;

/// What "fits within noise" means for the oracle (`tests/diagnose_extensions.md`,
/// "The oracle"): χ² at or below the 95 % quantile of χ² with n − p degrees
/// of freedom (the test that a true model with p free parameters passes 95 %
/// of the time, for a model linear near its optimum), and no residual beyond
/// 3.5 σ (a true model's ten residuals all stay inside with probability
/// 0.9995^10 ≈ 0.995; it catches a misfit concentrated on one observable
/// that the sum dilutes when n − p is large).
const FIT_QUANTILE: f64 = 0.95;
const FIT_MAX_RESIDUAL: f64 = 3.5;

/// One catalogue model's least-squares problem in box coordinates
/// v ∈ [0, 1]^p: u = lo + v·(hi − lo), u the model's sampling coordinate (in
/// which every prior of the catalogue is uniform), x = g(u) the physical
/// parameters. Only the prior's support constrains the fit: the prior
/// density is flat there in u, so the oracle's optimum is the likelihood's
/// maximum over the model as the catalogue defines it. Two folds of
/// `model_posterior` are left out, neither of which changes the set of
/// predictions the model reaches: the end springs' κ₀ ≥ κ_L (the data are a
/// simply supported beam's ω and ζ, symmetric in the ends) and the 5 %
/// sliver of equal relaxation rates (which the model without the second
/// relaxation spans; kept out, as the posterior does, because the pole
/// solvers are slow there).
struct OracleProblem<'a> {
    post: &'a nanobeam::diagnose::ClassPosterior,
    lo: Vec<f64>,
    hi: Vec<f64>,
    names: Vec<String>,
    /// θ indices of the relaxation rates Ωᵢ.
    rates: Vec<usize>,
    evaluations: std::sync::atomic::AtomicU64,
}

impl<'a> OracleProblem<'a> {
    fn new(post: &'a nanobeam::diagnose::ClassPosterior) -> Self {
        let params = &post.inner().parameters().params;
        let (lo, hi): (Vec<f64>, Vec<f64>) = params
            .iter()
            .zip(post.coordinates())
            .map(|(p, c)| {
                let (a, b) = p.prior.support();
                (c.to_u(a), c.to_u(b))
            })
            .unzip();
        assert!(lo.iter().chain(&hi).all(|u| u.is_finite()), "a prior without a bounded support");
        let names: Vec<String> = params.iter().map(|p| p.name.clone()).collect();
        let rates = names.iter().enumerate().filter(|(_, n)| n.starts_with("omega")).map(|(i, _)| i).collect();
        Self { post, lo, hi, names, rates, evaluations: std::sync::atomic::AtomicU64::new(0) }
    }

    fn dim(&self) -> usize {
        self.lo.len()
    }

    /// Physical parameters at v.
    fn x(&self, v: &[f64]) -> Vec<f64> {
        let u: Vec<f64> = v.iter().zip(self.lo.iter().zip(&self.hi)).map(|(v, (l, h))| l + v * (h - l)).collect();
        self.post.to_inner(&u)
    }

    /// v of physical parameters x (inside the box).
    fn v(&self, x: &[f64]) -> Vec<f64> {
        let u = self.post.from_inner(x);
        // clamped: a bound's x may round to just outside the box
        u.iter().zip(self.lo.iter().zip(&self.hi)).map(|(u, (l, h))| ((u - l) / (h - l)).clamp(0.0, 1.0)).collect()
    }

    /// Standardised residuals (prediction − observation)/σ at v, in the
    /// likelihood's order (ω of every mode, then ζ), by the forward solve
    /// the likelihood itself makes; `None` outside the box or where the
    /// model has no likelihood (an invalid or buckled beam, a mode missing).
    fn residuals(&self, v: &[f64]) -> Option<Vec<f64>> {
        self.evaluations.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        if v.iter().any(|v| !(0.0..=1.0).contains(v)) {
            return None;
        }
        let x = self.x(v);
        for (k, &i) in self.rates.iter().enumerate() {
            for &j in &self.rates[k + 1..] {
                if (x[i] / x[j]).ln().abs() <= nanobeam::diagnose::DISTINCT_RELAXATIONS {
                    return None;
                }
            }
        }
        let inner = self.post.inner();
        let beam = inner.beam_at(&x);
        let mut y = vec![0.0; inner.observed().len()];
        match nanobeam::beam::modal_observables(&beam, inner.fitted_modes(), inner.max_mode(), &mut y) {
            Ok(true) => {}
            _ => return None,
        }
        let r: Vec<f64> = y.iter().zip(inner.observed()).zip(inner.sd()).map(|((p, o), s)| (p - o) / s).collect();
        r.iter().all(|r| r.is_finite()).then_some(r)
    }

    fn chi2(&self, v: &[f64]) -> f64 {
        self.residuals(v).map_or(f64::INFINITY, |r| r.iter().map(|r| r * r).sum())
    }
}

/// The problem as a posterior for `bayes::map`'s Nelder–Mead: flat on the
/// box, log L = −χ²/2.
impl nanobeam::bayes::Posterior for OracleProblem<'_> {
    fn names(&self) -> Vec<String> {
        self.names.clone()
    }
    fn log_prior(&self, v: &[f64]) -> f64 {
        if v.iter().all(|v| (0.0..=1.0).contains(v)) {
            0.0
        } else {
            f64::NEG_INFINITY
        }
    }
    fn log_likelihood(&self, v: &[f64]) -> f64 {
        -0.5 * self.chi2(v)
    }
    fn sample_prior(&self, rng: &mut dyn rand::RngCore) -> Vec<f64> {
        use rand::Rng;
        (0..self.dim()).map(|_| rng.gen::<f64>()).collect()
    }
}

/// Levenberg–Marquardt from v0 on the box (steps projected onto it;
/// Marquardt's diagonal scaling; forward differences of [`LM_STEP`], taken
/// inward at a face). Returns the best v and its χ² (∞ when v0 has none).
fn levenberg_marquardt(pr: &OracleProblem, v0: &[f64]) -> (Vec<f64>, f64) {
    use nalgebra::{DMatrix, DVector};
    let Some(mut r) = pr.residuals(v0) else { return (v0.to_vec(), f64::INFINITY) };
    let (n, p) = (r.len(), pr.dim());
    let mut v = v0.to_vec();
    let mut chi2: f64 = r.iter().map(|r| r * r).sum();
    let mut lambda = 1e-2;
    let mut stalls = 0;
    for _ in 0..LM_ITERS {
        let mut jac = DMatrix::<f64>::zeros(n, p);
        for k in 0..p {
            let h = if v[k] + LM_STEP <= 1.0 { LM_STEP } else { -LM_STEP };
            let mut w = v.clone();
            w[k] += h;
            let col = pr.residuals(&w).map(|rw| (rw, h)).or_else(|| {
                w[k] = v[k] - h;
                pr.residuals(&w).map(|rw| (rw, -h))
            });
            if let Some((rw, h)) = col {
                for i in 0..n {
                    jac[(i, k)] = (rw[i] - r[i]) / h;
                }
            }
        }
        let a = jac.tr_mul(&jac);
        let g = jac.tr_mul(&DVector::from_column_slice(&r));
        let floor = 1e-12 * a.diagonal().max().max(1e-300);
        let mut step = None;
        for _ in 0..16 {
            let mut m = a.clone();
            for k in 0..p {
                m[(k, k)] += lambda * a[(k, k)].max(floor);
            }
            if let Some(c) = m.cholesky() {
                let d = c.solve(&(-&g));
                let w: Vec<f64> = v.iter().zip(d.iter()).map(|(x, d)| (x + d).clamp(0.0, 1.0)).collect();
                if let Some(rw) = pr.residuals(&w) {
                    let c2: f64 = rw.iter().map(|r| r * r).sum();
                    if c2 < chi2 {
                        step = Some((w, rw, c2));
                        lambda = (lambda / 3.0).max(1e-9);
                        break;
                    }
                }
            }
            lambda *= 4.0;
        }
        let Some((w, rw, c2)) = step else { break };
        let gain = chi2 - c2;
        (v, r, chi2) = (w, rw, c2);
        stalls = if gain < 1e-9 * chi2.max(1.0) { stalls + 1 } else { 0 };
        if stalls >= 3 {
            break;
        }
    }
    (v, chi2)
}

/// LM, then Nelder–Mead (`bayes::map`) at simplex steps 0.05 and 0.005 of
/// the box, each followed by LM again: the polish of one optimum.
fn polish(pr: &OracleProblem, v0: &[f64]) -> (Vec<f64>, f64) {
    let (mut v, mut chi2) = levenberg_marquardt(pr, v0);
    for scale in [0.05, 0.005] {
        let nm = nanobeam::bayes::map::map_estimate(pr, &v, &vec![scale; pr.dim()], NM_ITERS);
        let (w, c) = levenberg_marquardt(pr, &nm.theta);
        if c < chi2 {
            (v, chi2) = (w, c);
        }
    }
    (v, chi2)
}

/// The oracle's fit of one model.
#[derive(Debug, Clone)]
struct OracleFit {
    model: nanobeam::diagnose::Model,
    names: Vec<String>,
    /// Physical parameters at the optimum.
    x: Vec<f64>,
    chi2: f64,
    /// Observables n and parameters p.
    n: usize,
    p: usize,
    max_residual: f64,
    evaluations: u64,
}

impl OracleFit {
    fn dof(&self) -> usize {
        self.n - self.p
    }

    /// P(χ²_{n−p} ≥ χ²): the goodness of fit.
    fn p_value(&self) -> f64 {
        use statrs::distribution::{ChiSquared, ContinuousCDF};
        ChiSquared::new(self.dof() as f64).unwrap().sf(self.chi2)
    }

    /// Fits within noise ([`FIT_QUANTILE`], [`FIT_MAX_RESIDUAL`]).
    fn fits(&self) -> bool {
        use statrs::distribution::{ChiSquared, ContinuousCDF};
        let q = ChiSquared::new(self.dof() as f64).unwrap().inverse_cdf(FIT_QUANTILE);
        self.chi2 <= q && self.max_residual <= FIT_MAX_RESIDUAL
    }
}

/// The oracle's least-squares fit of `model` ([`OracleProblem`]): the best
/// of [`ORACLE_DRAWS`] prior draws and of the nested starts (each sub-model's
/// best fit with [`ORACLE_NESTED_DRAWS`] prior draws, and the corners and
/// middle of the box, of the parameters the model adds) polished by LM, the
/// best of those by [`polish`], then [`ORACLE_RESTARTS`] LM restarts around
/// it at two scales, and the winner polished again.
fn oracle_fit(
    model: &nanobeam::diagnose::Model,
    data: &nanobeam::calibration::MeasuredData,
    sub_fits: &[&OracleFit],
    seed: u64,
) -> OracleFit {
    use rand::Rng;
    use rayon::prelude::*;
    let scales = nanobeam::diagnose::NominalScales::of(&data.beam, data.max_mode()).expect("nominal scales");
    let post = nanobeam::diagnose::model_posterior(
        model,
        &data.parameters,
        &data.beam,
        &data.modes,
        &data.mode_scans,
        &scales,
    );
    let pr = OracleProblem::new(&post);
    let p = pr.dim();
    use rand::SeedableRng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let draw = |rng: &mut rand_chacha::ChaCha8Rng| (0..p).map(|_| rng.gen::<f64>()).collect::<Vec<f64>>();
    let best_of = |starts: Vec<Vec<f64>>, keep: usize| -> Vec<Vec<f64>> {
        let mut scored: Vec<(f64, Vec<f64>)> = starts.into_par_iter().map(|v| (pr.chi2(&v), v)).collect();
        scored.retain(|(c, _)| c.is_finite());
        scored.sort_by(|a, b| a.0.total_cmp(&b.0));
        scored.into_iter().take(keep).map(|(_, v)| v).collect()
    };
    let mut starts = best_of((0..ORACLE_DRAWS).map(|_| draw(&mut rng)).collect(), ORACLE_KEEP);
    for sub in sub_fits {
        // the sub-model's optimum in this model's box, the added parameters at the box's middle
        let shared: Vec<Option<usize>> = pr.names.iter().map(|n| sub.names.iter().position(|m| m == n)).collect();
        let mut x_mid = pr.x(&vec![0.5; p]);
        for (x, j) in x_mid.iter_mut().zip(&shared) {
            if let Some(j) = j {
                *x = sub.x[*j];
            }
        }
        let from_sub = pr.v(&x_mid);
        let added: Vec<usize> = (0..p).filter(|&i| shared[i].is_none()).collect();
        let fill = |values: &[f64]| {
            let mut v = from_sub.clone();
            for (&i, &x) in added.iter().zip(values) {
                v[i] = x;
            }
            v
        };
        let mut nested: Vec<Vec<f64>> = (0..ORACLE_NESTED_DRAWS).map(|_| fill(&draw(&mut rng))).collect();
        // the corners and middle of the added parameters' box (where their null values lie)
        let levels = [0.0, 0.5, 1.0];
        for code in 0..levels.len().pow(added.len() as u32) {
            let values: Vec<f64> = (0..added.len()).map(|k| levels[code / 3usize.pow(k as u32) % 3]).collect();
            nested.push(fill(&values));
        }
        starts.extend(best_of(nested, ORACLE_NESTED_KEEP));
    }
    let runs: Vec<(Vec<f64>, f64)> = starts.par_iter().map(|v| levenberg_marquardt(&pr, v)).collect();
    let (v, chi2) = runs.into_iter().min_by(|a, b| a.1.total_cmp(&b.1)).unwrap_or((vec![0.5; p], f64::INFINITY));
    let (mut v, mut chi2) = if chi2.is_finite() { polish(&pr, &v) } else { (v, chi2) };
    if chi2.is_finite() {
        for scale in [0.1, 0.02] {
            let around: Vec<Vec<f64>> = (0..ORACLE_RESTARTS)
                .map(|_| v.iter().map(|x| (x + scale * (2.0 * rng.gen::<f64>() - 1.0)).clamp(0.0, 1.0)).collect())
                .collect();
            let runs: Vec<(Vec<f64>, f64)> = around.par_iter().map(|w| levenberg_marquardt(&pr, w)).collect();
            if let Some((w, c)) = runs.into_iter().min_by(|a, b| a.1.total_cmp(&b.1)) {
                if c < chi2 {
                    (v, chi2) = polish(&pr, &w);
                }
            }
        }
    }
    let r = pr.residuals(&v);
    let max_residual = r.as_ref().map_or(f64::INFINITY, |r| r.iter().fold(0.0, |m, r| m.max(r.abs())));
    if let Some(r) = &r {
        // the χ² is the likelihood's: −2(ln L − ln L at zero residual)
        use nanobeam::bayes::Posterior;
        let n = r.len() as f64;
        let ln_l0 =
            -post.inner().sd().iter().map(|s| s.ln()).sum::<f64>() - 0.5 * n * (2.0 * std::f64::consts::PI).ln();
        let from_likelihood = -2.0 * (post.inner().log_likelihood(&pr.x(&v)) - ln_l0);
        assert!((from_likelihood - chi2).abs() <= 1e-6 * chi2.max(1.0), "{from_likelihood} vs {chi2}");
    }
    OracleFit {
        model: model.clone(),
        names: pr.names.clone(),
        x: pr.x(&v),
        chi2,
        n: post.inner().observed().len(),
        p,
        max_residual,
        evaluations: pr.evaluations.load(std::sync::atomic::Ordering::Relaxed),
    }
}

/// Every candidate model of `data` (`Model::candidates` at the diagnosis's
/// two causes) fitted by the oracle, the base first, then the singles, then
/// the pairs (each layer in parallel; a model's nested starts come from its
/// sub-models with one cause fewer).
fn oracle_all(data: &nanobeam::calibration::MeasuredData, seed: u64) -> Vec<OracleFit> {
    use rayon::prelude::*;
    let models = nanobeam::diagnose::Model::candidates(2, data.beam.support, &data.parameters);
    let mut fits: Vec<OracleFit> = Vec::new();
    for k in 0..=2 {
        let layer: Vec<(usize, &nanobeam::diagnose::Model)> =
            models.iter().enumerate().filter(|(_, m)| m.causes().len() == k).collect();
        let new: Vec<OracleFit> = layer
            .par_iter()
            .map(|(i, m)| {
                let subs: Vec<&OracleFit> = m
                    .causes()
                    .iter()
                    .filter_map(|&c| {
                        let sub = m.without(c);
                        fits.iter().find(|f| f.model == sub)
                    })
                    .collect();
                oracle_fit(m, data, &subs, seed.wrapping_mul(1000).wrapping_add(*i as u64))
            })
            .collect();
        fits.extend(new);
    }
    fits
}

/// The columns of `oracle_fits`' table.
const ORACLE_HEADER: &str = "| kind | seed | diagnose: cause (named) | grade | oracle best | χ²/dof | max \
                             \\|r\\|/σ | truth's own model: χ²/dof | best rival | χ²/dof | max \\|r\\|/σ | \
                             rivals within noise | mimic | forward solves |\n\
                             |---|---:|---|---|---|---:|---:|---|---|---:|---:|---:|---|---:|\n";

/// The truth's own parameters in the order of `names` (its own model's),
/// where that model holds the truth exactly (`None` otherwise: the
/// Kelvin–Voigt kind, which `extra-relaxation` only approaches).
fn truth_point(truth: &Truth, names: &[String]) -> Option<Vec<f64>> {
    let rho_a = RHO * area();
    names
        .iter()
        .map(|n| match n.as_str() {
            "nonlocal_e0a_nm" => Some(E0A * 1e9),
            "delta" => Some(DELTA),
            "omega_rad_s" => Some(OMEGA),
            "elastic_foundation_n_m2" => Some(truth.foundation * rho_a * lambda_base(1)),
            "loss_factor" => Some(truth.eta),
            "viscous_damping_n_s_m2" => Some(2.0 * rho_a * lambda_base(1).sqrt() * truth.viscous_zeta1),
            "axial_force_n" => Some(truth.tension * ei() * (std::f64::consts::PI / L).powi(2)),
            "strain_gradient_length_nm" => Some(truth.gradient_nm),
            _ => None,
        })
        .collect()
}

/// χ² of `model` at the truth's own parameters ([`truth_point`]).
fn chi2_at_truth(
    truth: &Truth,
    model: &nanobeam::diagnose::Model,
    d: &nanobeam::calibration::MeasuredData,
) -> Option<f64> {
    let scales = nanobeam::diagnose::NominalScales::of(&d.beam, d.max_mode()).ok()?;
    let post = nanobeam::diagnose::model_posterior(model, &d.parameters, &d.beam, &d.modes, &d.mode_scans, &scales);
    let pr = OracleProblem::new(&post);
    truth_point(truth, &pr.names).map(|x| pr.chi2(&pr.v(&x)))
}

/// Whether `fit`'s model holds every cause of the truth's (`expected`; empty
/// outside the catalogue, where no model does).
fn holds_truth(fit: &OracleFit, expected: &[&str]) -> bool {
    !expected.is_empty() && expected.iter().all(|e| fit.model.causes().iter().any(|c| c.name() == *e))
}

/// The oracle's optimiser on one set whose truth its catalogue holds: seed
/// 730 (loss factor η = 0.1), model `loss-factor` (p = 4 of n = 10).
/// The truth's own parameters (e0a = 1 nm, Δ = 0.45, Ω = 4e11 rad/s,
/// η = 0.1) are a point of the model, so the least-squares optimum can be
/// no worse than their χ²; a search that stops short of it fails. And if the
/// model is the truth's (the generator's sine modes against the beam's own
/// solver), its minimum χ² is χ²_{n−p}: above the 99.9 % quantile
/// (22.46 at 6 degrees of freedom) with probability 1e-3 only. Measured
/// 2026-12-07: χ² 2.18 against 7.08 at the truth, 7 800 forward solves,
/// 0.03 s (`tests/diagnose_extensions.md`, "The oracle").
#[test]
fn the_oracle_fits_the_truths_own_model() {
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    let seed = 730;
    let truth = Truth { eta: 0.1, ..Truth::default() };
    let d = data(truth.observations(&[1, 2, 3, 4, 5], seed), seed);
    let model = nanobeam::diagnose::Model::from_name("loss-factor").unwrap();
    let base = oracle_fit(&nanobeam::diagnose::Model::BASE, &d, &[], 1);
    let fit = oracle_fit(&model, &d, &[&base], 2);
    let scales = nanobeam::diagnose::NominalScales::of(&d.beam, 5).unwrap();
    let post = nanobeam::diagnose::model_posterior(&model, &d.parameters, &d.beam, &d.modes, &[], &scales);
    let pr = OracleProblem::new(&post);
    assert_eq!(pr.names, ["nonlocal_e0a_nm", "delta", "omega_rad_s", "loss_factor"]);
    let at_truth = pr.chi2(&pr.v(&[E0A * 1e9, DELTA, OMEGA, 0.1]));
    assert_eq!(Some(at_truth), chi2_at_truth(&truth, &model, &d));
    let q = ChiSquared::new(fit.dof() as f64).unwrap().inverse_cdf(0.999);
    eprintln!(
        "loss-factor on 730: χ² {:.3} (at the truth {at_truth:.3}, 99.9 % quantile {q:.2}), base {:.1}, {} + {} solves",
        fit.chi2, base.chi2, base.evaluations, fit.evaluations
    );
    assert!(fit.chi2 <= at_truth + 1e-9, "the optimum {} is worse than the truth's point {at_truth}", fit.chi2);
    assert!(fit.chi2 <= q, "χ² {} above the 99.9 % quantile {q} of χ²_{}", fit.chi2, fit.dof());
}

/// The oracle on every set (not in CI: 55 models per set, 1.3–2.5 M forward
/// solves and 40–70 s per set, 91–129 s per kind in the test profile on 2
/// shared cores). `KIND=i` runs one kind; `ORACLE_SEED=k` draws the
/// optimiser's starts from another stream (a check that the minima are
/// found again); `ORACLE_OUT=path` writes the table, the confusion matrix
/// and each set's rivals within noise there, and every model's fit
/// (χ², n, p, max |r|, parameters) to `path.tsv`. Prints the per-set table,
/// then the confusion matrix of the kinds run, split by mimic (a set is a
/// mimic when a model without the truth's causes, any model for a kind
/// outside the catalogue, fits within noise: [`OracleFit::fits`]).
#[test]
#[ignore]
fn oracle_fits() {
    let only: Option<usize> = std::env::var("KIND").ok().and_then(|k| k.parse().ok());
    // ORACLE_SEED=k: the optimiser's draws from another stream (a check of its reach: the same minima?)
    let restart_seed: u64 = std::env::var("ORACLE_SEED").ok().and_then(|k| k.parse().ok()).unwrap_or(0) * 100_000;
    let mut out = String::new();
    let mut details = String::new();
    let mut tsv = String::from("seed\tmodel\tchi2\tn\tp\tmax_r\tfits\tsolves\tparameters\n");
    let mut confusion: Vec<(String, bool, &str)> = Vec::new();
    out.push_str(ORACLE_HEADER);
    for (i, (label, truth, expected)) in kinds().into_iter().enumerate() {
        if only.is_some_and(|k| k != i) {
            continue;
        }
        for rep in 0..2u64 {
            let seed = 700 + 10 * i as u64 + rep;
            let d = data(truth.observations(&[1, 2, 3, 4, 5], seed), seed);
            let t0 = std::time::Instant::now();
            let mut fits = oracle_all(&d, seed + restart_seed);
            let wall = t0.elapsed().as_secs_f64();
            fits.sort_by(|a, b| b.p_value().total_cmp(&a.p_value()));
            let own_model = (!expected.is_empty())
                .then(|| nanobeam::diagnose::Model::from_name(&expected.join("+")).expect("catalogue names"));
            let own = fits.iter().find(|f| Some(&f.model) == own_model.as_ref());
            let best = &fits[0];
            let rivals: Vec<&OracleFit> = fits.iter().filter(|f| !holds_truth(f, &expected)).collect();
            let fitting: Vec<&OracleFit> = rivals.iter().copied().filter(|f| f.fits()).collect();
            let mimic = !fitting.is_empty();
            let (_, cause, named, grade) = DIAGNOSED.iter().find(|s| s.0 == seed).copied().expect("a diagnosed set");
            let row = format!(
                "| {label} | {seed} | {cause} ({named}) | {grade} | {} | {:.2}/{} | {:.2} | {} | {} | {:.2}/{} | {:.2} | {} | {} | {} |\n",
                best.model.name(),
                best.chi2,
                best.dof(),
                best.max_residual,
                own.map_or("—".to_string(), |f| {
                    let at = chi2_at_truth(&truth, &f.model, &d).map_or(String::new(), |c| format!(" (at θ_true {c:.2})"));
                    format!("{:.2}/{}, max {:.2}{at}", f.chi2, f.dof(), f.max_residual)
                }),
                rivals[0].model.name(),
                rivals[0].chi2,
                rivals[0].dof(),
                rivals[0].max_residual,
                fitting.len(),
                if mimic { "**yes**" } else { "no" },
                fits.iter().map(|f| f.evaluations).sum::<u64>(),
            );
            print!("{row}");
            out.push_str(&row);
            details.push_str(&format!(
                "- {seed} ({label}, {wall:.0} s): rivals within noise: {}\n",
                fitting
                    .iter()
                    .map(|f| format!("{} ({:.2}/{})", f.model.name(), f.chi2, f.dof()))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
            for f in &fits {
                let params = f.names.iter().zip(&f.x).map(|(n, x)| format!("{n}={x:.5e}")).collect::<Vec<_>>();
                tsv.push_str(&format!(
                    "{seed}\t{}\t{:.4}\t{}\t{}\t{:.3}\t{}\t{}\t{}\n",
                    f.model.name(),
                    f.chi2,
                    f.n,
                    f.p,
                    f.max_residual,
                    f.fits(),
                    f.evaluations,
                    params.join(" ")
                ));
            }
            confusion.push((label.to_string(), mimic, grade));
        }
    }
    let mut matrix = String::from(
        "\n| kind | mimic: right / undecided / wrong | not mimic: right / undecided / wrong |\n|---|---|---|\n",
    );
    let mut labels: Vec<&String> = confusion.iter().map(|c| &c.0).collect();
    labels.dedup();
    for label in labels {
        let count =
            |mimic: bool, g: &str| confusion.iter().filter(|c| &c.0 == label && c.1 == mimic && c.2 == g).count();
        matrix.push_str(&format!(
            "| {label} | {} / {} / {} | {} / {} / {} |\n",
            count(true, "right"),
            count(true, "undecided"),
            count(true, "wrong"),
            count(false, "right"),
            count(false, "undecided"),
            count(false, "wrong")
        ));
    }
    print!("{matrix}\n{details}");
    if let Ok(path) = std::env::var("ORACLE_OUT") {
        std::fs::write(&path, format!("{out}{matrix}\n{details}")).expect("ORACLE_OUT writable");
        std::fs::write(format!("{path}.tsv"), tsv).expect("ORACLE_OUT.tsv writable");
    }
}
