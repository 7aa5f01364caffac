//! Physical mode numbering (`calibration::identified::number_modes`) on
//! frequencies this crate's beam models did not make.
//!
//! Generators of the data:
//! - **LAMMPS** (`data/md/`, Tersoff carbon, a (5,5) tube clamped at both
//!   ends, Langevin bath): the frequencies are what `nanobeam identify` found
//!   in the committed records `cc7.langevin.csv.gz` and `cc11.langevin.csv.gz`
//!   (`tests/identify_md.md`), every flexural line of each. The truth of
//!   their numbers is the record's own: consecutive lines of one tube, no
//!   peak between them in the PSD (the figures of `docs/md.md`).
//! - **`tests/thermal_langevin_study/gen.py`** (numpy: modal coordinates in a
//!   Langevin bath, Euler–Bernoulli shapes, eleven lines at the frequencies
//!   `F_GHZ` below): seeds 2, 5 and 7, on which `identify` misses one line in
//!   the noise of its neighbours. The frequencies are what `identify` found;
//!   the truth of their numbers is gen.py's.
//!
//! - **A closed-form generator in this file** (no `src/` code; its doc is
//!   at `relaxed` and `elastic` below): continuum nonlocal Euler–Bernoulli
//!   beams, simply supported and clamped–clamped, with the N = 1 relaxation
//!   between any two modes, e0a and the section factor drawn over the
//!   prior, random missing modes and σ = 1e-3 noise (issue 67;
//!   `tests/identify_numbering.md` records its confusion).
//!
//! The nominal beams of the MD records are the records' own files,
//! `data/md/tube-cc*.yaml`, untouched: the nominal Euler–Bernoulli beam is
//! 1.2–2.2× too stiff for modes 3–11, which is what the numbering must survive.
//!
//! What a numbering may do with a record it cannot number is refuse it (an
//! ambiguity, naming the mode); what it must never do is return wrong numbers.

use nanobeam::beam::BeamSpec;
use nanobeam::calibration::identified::{number_modes, number_modes_checked, number_modes_with_sd};

/// cc7 (L = 7.39 nm), modes 1..6, rad/s.
const CC7_RAD_S: [f64; 6] = [1.937107e12, 4.730263e12, 8.279720e12, 1.226079e13, 1.642419e13, 2.079731e13];
/// cc11 (L = 11.40 nm), modes 1..11, rad/s.
const CC11_RAD_S: [f64; 11] = [
    8.364620e11,
    2.214603e12,
    4.090229e12,
    6.322220e12,
    8.798912e12,
    1.145767e13,
    1.415816e13,
    1.696211e13,
    1.976439e13,
    2.256258e13,
    2.538519e13,
];
/// gen.py's line frequencies (GHz), its `f_ghz`: modes 1..11.
const F_GHZ: [f64; 11] = [133.1, 352.5, 651.0, 1006.2, 1400.4, 1823.5, 2253.3, 2699.6, 3145.6, 3590.9, 4040.2];

fn beam(path: &str) -> BeamSpec {
    BeamSpec::from_yaml(&std::fs::read_to_string(path).expect("committed beam file")).expect("valid beam file")
}

/// Physical numbers of the lines kept when `dropped` (0-based) are left out.
fn kept(all: &[f64], dropped: &[usize]) -> (Vec<f64>, Vec<usize>) {
    (0..all.len()).filter(|i| !dropped.contains(i)).map(|i| (all[i], i + 1)).unzip()
}

#[test]
fn the_md_records_are_numbered_consecutively_from_one() {
    for (path, omegas) in [("data/md/tube-cc7.yaml", &CC7_RAD_S[..]), ("data/md/tube-cc11.yaml", &CC11_RAD_S[..])] {
        let numbers = number_modes(&beam(path), omegas, None).expect("numbered");
        assert_eq!(numbers, (1..=omegas.len()).collect::<Vec<_>>(), "{path}");
    }
}

#[test]
fn a_missed_line_in_gen_py_records_leaves_a_gap() {
    let cc11 = beam("data/md/tube-cc11.yaml");
    // (seed, the line identify missed, the frequencies it found in rad/s).
    let cases: [(u32, usize, [f64; 10]); 3] = [
        (
            2,
            8,
            [
                8.477168e11,
                2.224115e12,
                4.063664e12,
                6.291475e12,
                8.753025e12,
                1.142340e13,
                1.407462e13,
                1.982191e13,
                2.256241e13,
                2.539603e13,
            ],
        ),
        (
            5,
            8,
            [
                8.328577e11,
                2.184061e12,
                4.055711e12,
                6.271450e12,
                8.820676e12,
                1.144252e13,
                1.414450e13,
                1.974333e13,
                2.257981e13,
                2.534739e13,
            ],
        ),
        (
            7,
            7,
            [
                8.406732e11,
                2.223634e12,
                4.058511e12,
                6.303466e12,
                8.794478e12,
                1.148472e13,
                1.699013e13,
                1.975592e13,
                2.257005e13,
                2.539287e13,
            ],
        ),
    ];
    for (seed, missed, found) in cases {
        let truth: Vec<usize> = (1..=11).filter(|&m| m != missed).collect();
        // The found lines are gen.py's own within the PSD's resolution: the
        // truth above is the nearest line's number.
        for (w, &m) in found.iter().zip(&truth) {
            let f_ghz = w / (2.0 * std::f64::consts::PI) / 1e9;
            assert!((f_ghz / F_GHZ[m - 1] - 1.0).abs() < 0.02, "seed {seed}: {f_ghz} GHz is not line {m}");
        }
        let numbers = number_modes(&cc11, &found, None).expect("numbered");
        assert_eq!(numbers, truth, "seed {seed}");
    }
}

#[test]
fn an_md_record_missing_one_line_is_never_numbered_wrong() {
    let mut right = 0;
    for (path, omegas) in [("data/md/tube-cc7.yaml", &CC7_RAD_S[..]), ("data/md/tube-cc11.yaml", &CC11_RAD_S[..])] {
        let spec = beam(path);
        for drop in 0..omegas.len() {
            let (found, truth) = kept(omegas, &[drop]);
            match number_modes(&spec, &found, None) {
                Ok(numbers) => {
                    assert_eq!(numbers, truth, "{path} without mode {}", drop + 1);
                    right += 1;
                }
                Err(e) => {
                    let message = e.to_string();
                    eprintln!("{path} without mode {}: refused: {message}", drop + 1);
                    // The ambiguity refusal names both numbers of a mode.
                    assert!(message.contains("fit both modes"), "{path} without mode {}: {message}", drop + 1);
                }
            }
        }
    }
    eprintln!("MD subsets without one line: {right} of 17 numbered right, the rest refused");
    // Refusing every subset would pass the loop above; the family must still
    // number the records whose gap shows.
    assert!(right >= RIGHT_AT_LEAST, "numbered {right} of 17 subsets");
}

/// A floor on the subsets numbered (not refused) above. Measured with the
/// numbering over the whole prior: 15 of the 17, cc7 without its mode 4 or 5
/// refused (`tests/identify_md.md`, round 7); the per-mode e0a bands it
/// replaced numbered 4 right and 9 wrong. Any change that refuses one more
/// of these records is a change to look at.
const RIGHT_AT_LEAST: usize = 15;

// ---------------------------------------------------------------------------
// Beams of the whole prior, from a closed-form generator (issue 67).
//
// Generator: the continuum nonlocal Euler–Bernoulli beam in closed form, no
// `src/` code. Eringen's model puts the nonlocality on the inertia:
// EI w'''' = ρAω² (w − μ w''), μ = e0a². Simply supported: ω_e,n² =
// (EI/ρA) k⁴/(1 + μk²), k = nπ/L. Clamped–clamped: w = e^{βx} gives
// EI β⁴ + ρAω²μ β² − ρAω² = 0, β² = α² > 0 or −γ² < 0, and w = w' = 0 at both
// ends gives 1 − cosh αL cos γL + (α² − γ²)/(2αγ) sinh αL sin γL = 0, solved
// by a scan and bisection in ω. The relaxation E(1 + δ s/(s + Ω)) scales the
// whole stiffness, so each elastic mode's pole solves
// s³ + Ω s² + ω_e²(1 + δ) s + ω_e² Ω = 0, here by nalgebra's eigenvalues
// of its companion matrix (the crate's numbering solves it by bisection on
// the real root). The section factor f multiplies EI/ρA.
// ---------------------------------------------------------------------------

use nalgebra::Matrix3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// |s| of the oscillatory pole of an elastic mode ω_e under (δ, Ω).
fn relaxed(omega_e: f64, delta: f64, omega: f64) -> f64 {
    // companion matrix of s³ + a s² + b s + c, in units of ω_e
    let (a, b, c) = (omega / omega_e, 1.0 + delta, omega / omega_e);
    let m = Matrix3::new(0.0, 0.0, -c, 1.0, 0.0, -b, 0.0, 1.0, -a);
    let roots = m.complex_eigenvalues();
    let pair = roots.iter().max_by(|x, y| x.im.abs().total_cmp(&y.im.abs())).expect("three roots");
    assert!(pair.im.abs() > 0.0, "overdamped mode at delta {delta}, Omega/omega_e {a}");
    omega_e * pair.norm()
}

/// The first `n` elastic ω of a continuum nonlocal EB beam (rad/s).
fn elastic(cc: bool, l: f64, ei_over_rho_a: f64, mu: f64, n: usize) -> Vec<f64> {
    if !cc {
        return (1..=n)
            .map(|j| {
                let k = j as f64 * std::f64::consts::PI / l;
                (ei_over_rho_a * k.powi(4) / (1.0 + mu * k * k)).sqrt()
            })
            .collect();
    }
    let det = |w: f64| {
        // β² roots of β⁴ + (w²μ/c) β² − w²/c = 0, c = EI/ρA
        let (p, q) = (w * w * mu / ei_over_rho_a, w * w / ei_over_rho_a);
        let disc = (p * p + 4.0 * q).sqrt();
        let (alpha, gamma) = ((0.5 * (-p + disc)).sqrt(), (0.5 * (p + disc)).sqrt());
        // divided by cosh αL to stay finite
        let (al, gl) = (alpha * l, gamma * l);
        1.0 / al.cosh() - gl.cos() + (alpha * alpha - gamma * gamma) / (2.0 * alpha * gamma) * al.tanh() * gl.sin()
    };
    // the local first root is 4.730²·√c/L²; scan well below it upwards
    let w1 = 4.730_f64.powi(2) * ei_over_rho_a.sqrt() / (l * l);
    let (mut out, mut w, dw) = (Vec::new(), 0.05 * w1, 0.01 * w1);
    let mut f = det(w);
    while out.len() < n {
        let (w2, f2) = (w + dw, det(w + dw));
        if f.signum() != f2.signum() {
            let (mut lo, mut hi, mut flo) = (w, w2, f);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                let fm = det(mid);
                if fm.signum() == flo.signum() {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            out.push(0.5 * (lo + hi));
        }
        w = w2;
        f = f2;
    }
    out
}

/// Confusion of the numbering over `count` generated records.
#[derive(Debug, Default)]
struct Confusion {
    right: usize,
    refused: usize,
    wrong: usize,
}

/// Relative sd of the identified ω the records carry: 1e-3, the σ the MD
/// records' lines have (docs/md.md) and above a sweep's.
const SIGMA: f64 = 1e-3;

fn confusion(count: usize, seed: u64) -> Confusion {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Confusion::default();
    for record in 0..count {
        let cc = rng.gen_bool(0.5);
        let l_nm = rng.gen_range(8.0..20.0);
        let d_nm: f64 = rng.gen_range(0.8..1.6);
        let (e, rho) = (1.0e12, 2300.0);
        // solid circle: I/A = d²/16
        let ei_rho_a = e / rho * (d_nm * 1e-9).powi(2) / 16.0;
        let f = rng.gen_range(2.0 / 3.0..1.5);
        let e0a: f64 = rng.gen_range(0.0..2.0);
        let delta = rng.gen_range(0.0..1.0);
        let modes = 8;
        let w_el = elastic(cc, l_nm * 1e-9, f * ei_rho_a, (e0a * 1e-9).powi(2), modes);
        // the relaxation between two modes (g, g + 1), inside the prior (Ω ≤ 1e13)
        let gaps: Vec<usize> = (0..modes - 1).filter(|&g| (w_el[g] * w_el[g + 1]).sqrt() <= 1e13).collect();
        let omega = match gaps.len() {
            0 => rng.gen_range(0.0..1e13),
            n => {
                let g = gaps[rng.gen_range(0..n)];
                (w_el[g] * w_el[g + 1]).sqrt()
            }
        };
        let truth: Vec<f64> = w_el.iter().map(|&w| relaxed(w, delta, omega)).collect();
        // random missing modes: mode 1 with probability 0.3, the others 0.2;
        // at least 3 kept
        let mut kept: Vec<usize> = (0..modes).filter(|&j| rng.gen_bool(if j == 0 { 0.7 } else { 0.8 })).collect();
        if kept.len() < 3 {
            kept = (0..modes).collect();
        }
        let omegas: Vec<f64> = kept
            .iter()
            .map(|&j| {
                let z: f64 = rng.sample(rand_distr::StandardNormal);
                truth[j] * (1.0 + SIGMA * z)
            })
            .collect();
        let numbers: Vec<usize> = kept.iter().map(|j| j + 1).collect();
        let support = if cc { "clamped-clamped" } else { "simply-supported" };
        let spec = format!(
            "length_nm: {l_nm}\ndiameter_nm: {d_nm}\nyoungs_modulus_pa: {e}\ndensity_kg_m3: {rho}\nsupport: {support}\nelements: 40\n"
        );
        let beam = BeamSpec::from_yaml(&spec).expect("valid nominal beam");
        // the sds identify would report with these frequencies
        let sds: Vec<f64> = omegas.iter().map(|w| SIGMA * w).collect();
        match number_modes_with_sd(&beam, &omegas, Some(&sds), None).map(|n| n.numbers) {
            Ok(n) if n == numbers => out.right += 1,
            Ok(n) => {
                eprintln!("record {record} ({support}, L {l_nm:.2} nm, d {d_nm:.2} nm, f {f:.3}, e0a {e0a:.2}, delta {delta:.2}, Omega {omega:.3e}): numbered {n:?}, truth {numbers:?}");
                out.wrong += 1;
            }
            Err(e) => {
                let message = e.to_string();
                assert!(message.starts_with("invalid --first-mode = '': allowed"), "{message}");
                out.refused += 1;
            }
        }
    }
    out
}

/// CI's share: 40 records. Wrong must be 0; the floor on the right ones is
/// what keeps a numbering that refuses everything from passing.
#[test]
fn beams_of_the_whole_prior_are_never_numbered_wrong() {
    let c = confusion(40, 67);
    eprintln!("{c:?}");
    assert_eq!(c.wrong, 0, "{c:?}");
    assert!(c.right >= RIGHT_OF_40, "{c:?}");
}

/// Right numberings of the 40 CI records, a floor (measured when written:
/// see tests/identify_numbering.md).
const RIGHT_OF_40: usize = 30;

/// The larger count (tests/identify_numbering.md records its result):
/// `cargo test --test identify_numbering -- --ignored --nocapture`.
#[test]
#[ignore]
fn beams_of_the_whole_prior_300_records() {
    let c = confusion(300, 6767);
    eprintln!("{c:?}");
    assert_eq!(c.wrong, 0, "{c:?}");
}

/// The first case: a simply supported beam whose relaxation lies
/// between modes 1 and 2 (δ = 0.13: the modes above Ω stiffer by about 6 %),
/// modes 1-6 found. Numbered 1-6 without `--first-mode`; `--first-mode 1`
/// (the truth) is taken without a warning; `--first-mode 2` is never taken
/// silently: refused with the value as written, or taken with a warning.
#[test]
fn a_relaxation_between_modes_1_and_2_is_numbered_and_first_mode_is_checked() {
    let (l_nm, d_nm, e, rho, e0a) = (10.0, 1.0, 1.0e12, 2300.0, 0.5);
    let ei_rho_a = e / rho * (d_nm * 1e-9f64).powi(2) / 16.0;
    let w_el = elastic(false, l_nm * 1e-9, ei_rho_a, (e0a * 1e-9f64).powi(2), 6);
    let omega = (w_el[0] * w_el[1]).sqrt();
    let found: Vec<f64> = w_el.iter().map(|&w| relaxed(w, 0.13, omega)).collect();
    let spec = format!(
        "length_nm: {l_nm}\ndiameter_nm: {d_nm}\nyoungs_modulus_pa: {e}\ndensity_kg_m3: {rho}\nsupport: simply-supported\nelements: 40\n"
    );
    let beam = BeamSpec::from_yaml(&spec).unwrap();
    assert_eq!(number_modes(&beam, &found, None).unwrap(), vec![1, 2, 3, 4, 5, 6]);
    let stated = number_modes_checked(&beam, &found, Some(1)).unwrap();
    assert_eq!((stated.numbers, stated.warning), (vec![1, 2, 3, 4, 5, 6], None));
    match number_modes_checked(&beam, &found, Some(2)) {
        Err(e) => assert!(e.to_string().starts_with("invalid --first-mode = 2: allowed"), "{e}"),
        Ok(n) => assert!(n.warning.is_some(), "--first-mode 2 taken silently: {n:?}"),
    }
}

/// Issue 69, defect 11: one sweep of a simply supported tube, written as each
/// frequency-record kind (complex receptance, magnitude, magnitude with its
/// first frequency set to 0 Hz, a PSD |H|²·Gamma(10, 1/10)), all in lab units
/// (`frequency_hz`), is numbered by `nanobeam identify --beam` without
/// `--first-mode` whatever the kind, and every line any kind reports gets the
/// number the complex record gives the line within 1 % of it (modes 1–4).
/// Generator (no `src/` code): the closed-form modal sum of a simply
/// supported Euler–Bernoulli tube, H(ω) = Σₙ sin(nπa/L) sin(nπb/L) /
/// (ρAL/2 · (ωₙ² − ω² + 2iζₙωₙω)), ωₙ = (nπ/L)²√(EI/ρA), A = πdt,
/// I = πdt(d² + t²)/8 (mean diameter d, wall t), ζₙ = c/(2ρAωₙ), modes
/// 1–8, a = b = 2.1 nm; 2 000 log-spaced points from 1e11 to 2.1e13 rad/s
/// (modes 1–4), complex noise of sd 1e-3·max|H| per component (ChaCha8, seed
/// 11).
///
/// Before the fix (defect 11, `tests/hardening_round3.md`) the PSD reported
/// one line (mode 3) and asked for `--first-mode`: mode 4's diagram pole came
/// out at 0.6 of its ζ, the declared peak at its line was merged into it, and
/// the pole was dropped as narrower than the samples, the peak with it; modes
/// 1–2 then left the fit. Now such a peak (resolved on its own) is restored
/// when the result does not hold its line (`identify::pipeline`): modes 1–3,
/// numbered 1–3 (mode 4 goes to a real pole). Four identifications (the
/// PSD's twice), about 21 s of CPU in the debug build, run as four processes
/// at once: see `tests/hardening_round3.md` for the wall time measured.
#[test]
fn one_sweep_is_numbered_alike_as_every_record_kind() {
    use rand_distr::{Distribution, Gamma, StandardNormal};
    let (l, d, t) = (7.393e-9, 0.678e-9, 0.34e-9);
    let (e, rho, c) = (1e12, 2213.0, 2e-4);
    let (area, inertia) = (std::f64::consts::PI * d * t, std::f64::consts::PI * d * t * (d * d + t * t) / 8.0);
    let rho_a = rho * area;
    let x = 2.1e-9;
    let n_pts = 2000;
    let omegas: Vec<f64> = (0..n_pts).map(|i| 1e11 * (2.1e13f64 / 1e11).powf(i as f64 / (n_pts - 1) as f64)).collect();
    let h: Vec<(f64, f64)> = omegas
        .iter()
        .map(|&w| {
            (1..=8).fold((0.0, 0.0), |(re, im), n| {
                let k = n as f64 * std::f64::consts::PI / l;
                let wn = k * k * (e * inertia / rho_a).sqrt();
                let zeta = c / (2.0 * rho_a * wn);
                let num = (k * x).sin().powi(2) / (rho_a * l / 2.0);
                let (dr, di) = (wn * wn - w * w, 2.0 * zeta * wn * w);
                let den = dr * dr + di * di;
                (re + num * dr / den, im - num * di / den)
            })
        })
        .collect();
    let sd = 1e-3 * h.iter().map(|(a, b)| a.hypot(*b)).fold(0.0, f64::max);
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let noisy: Vec<(f64, f64)> = h
        .iter()
        .map(|(a, b)| {
            let (na, nb): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
            (a + sd * na, b + sd * nb)
        })
        .collect();
    let gamma = Gamma::new(10.0, 0.1).unwrap();
    let psd: Vec<f64> = h.iter().map(|(a, b)| (a * a + b * b) * gamma.sample(&mut rng)).collect();
    let hz = |w: f64| w / (2.0 * std::f64::consts::PI);
    let rows = |f: &dyn Fn(usize) -> String| (0..n_pts).map(f).collect::<Vec<_>>().join("\n");
    let records = [
        (
            "complex",
            format!(
                "frequency_hz,h_re_m_per_n,h_im_m_per_n\n{}",
                rows(&|i| format!("{:e},{:e},{:e}", hz(omegas[i]), noisy[i].0, noisy[i].1))
            ),
        ),
        (
            "magnitude",
            format!(
                "frequency_hz,h_abs_m_per_n\n{}",
                rows(&|i| format!("{:e},{:e}", hz(omegas[i]), noisy[i].0.hypot(noisy[i].1)))
            ),
        ),
        (
            "magnitude from 0 Hz",
            format!(
                "frequency_hz,h_abs_m_per_n\n{}",
                rows(&|i| format!("{:e},{:e}", if i == 0 { 0.0 } else { hz(omegas[i]) }, noisy[i].0.hypot(noisy[i].1)))
            ),
        ),
        (
            "psd",
            format!("frequency_hz,psd_one_sided_m2_per_hz\n{}", rows(&|i| format!("{:e},{:e}", hz(omegas[i]), psd[i]))),
        ),
    ];
    let dir = tempfile::tempdir().unwrap();
    let beam = dir.path().join("beam.yaml");
    std::fs::write(
        &beam,
        "length_nm: 7.393\ndiameter_nm: 0.678\nsection: { tube: { wall_nm: 0.34 } }\nyoungs_modulus_pa: 1.0e12\n\
         density_kg_m3: 2213\nsupport: simply-supported\nelements: 40\n",
    )
    .unwrap();
    // the four identifications run at once (each process is one record; the
    // wall time is what CI pays), their results read in order
    let children: Vec<(&str, std::process::Child)> = records
        .iter()
        .enumerate()
        .map(|(i, (kind, text))| {
            let path = dir.path().join(format!("record{i}.csv"));
            std::fs::write(&path, text).unwrap();
            let child = std::process::Command::new(env!("CARGO_BIN_EXE_nanobeam"))
                .args(["identify", "--beam"])
                .arg(&beam)
                .arg(&path)
                .stdout(std::process::Stdio::piped())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap();
            (*kind, child)
        })
        .collect();
    let mut reference: Vec<(f64, u64)> = Vec::new();
    for (kind, child) in children {
        let out = child.wait_with_output().unwrap();
        assert!(out.status.success(), "{kind}: {}", String::from_utf8_lossy(&out.stderr));
        let yaml: serde_yaml::Value = serde_yaml::from_slice(&out.stdout).unwrap();
        let modes: Vec<(f64, u64)> = yaml["modes"]
            .as_sequence()
            .unwrap()
            .iter()
            .map(|m| (m["omega_rad_s"].as_f64().unwrap(), m["mode"].as_u64().unwrap()))
            .collect();
        if reference.is_empty() {
            assert_eq!(modes.iter().map(|m| m.1).collect::<Vec<_>>(), [1, 2, 3, 4], "{kind}");
            reference = modes;
            continue;
        }
        assert!(modes.len() >= 3, "{kind}: {modes:?}");
        for (w, n) in &modes {
            let same = reference.iter().find(|(r, _)| (w / r - 1.0).abs() < 0.01);
            assert_eq!(same.map(|r| r.1), Some(*n), "{kind}: the line at {w:e} rad/s; complex {reference:?}");
        }
    }
}
