//! Coverage of `identify`'s intervals on records from the independent
//! generator in `tests/identify_reference` (closed-form Euler–Bernoulli
//! modal sums with analytic shapes, a relaxation pole, both noise kinds,
//! sensors anywhere; no crate beam code). The study over many seeds is
//! `#[ignore]`d (its measured result is in `tests/identify_coverage.md`);
//! a CI-sized subset runs in the suite.

mod identify_reference;

use identify_reference::{positions, record, record_with, Beam, Kind, Noise, Record, Support};
use nanobeam::identify::{identify, IdentifiedMode, IdentifyError, IdentifySettings};

/// Tallies of one (record kind, noise kind) cell.
#[derive(Debug, Default, Clone)]
struct Tally {
    records: usize,
    failed: usize,
    visible: usize,
    found: usize,
    false_modes: usize,
    /// intervals (ω and ζ of every found visible mode)
    intervals: usize,
    within_95: usize,
    within_3sd: usize,
    worst_z: f64,
}

impl Tally {
    /// Counts one interval with standardised error `z` (a non-finite z as
    /// infinitely far); returns |z|.
    fn interval(&mut self, z: f64) -> f64 {
        let z = if z.is_finite() { z.abs() } else { f64::INFINITY };
        self.intervals += 1;
        self.within_95 += usize::from(z <= 1.96);
        self.within_3sd += usize::from(z <= 3.0);
        self.worst_z = self.worst_z.max(z);
        z
    }
}

const SUPPORTS: [Support; 3] = [Support::SimplySupported, Support::ClampedClamped, Support::Cantilever];

fn noise_of(proportional: bool) -> Noise {
    if proportional {
        // 1 % of |signal| plus a floor of 1e-4 of the peak (issue 42's lock-in case)
        Noise::Proportional { floor: 1e-4, b: 0.01 }
    } else {
        // 0.5 % of the peak (issue 42's additive case)
        Noise::Additive { fraction: 5e-3 }
    }
}

fn study(kind: Kind, proportional: bool, seeds: std::ops::Range<u64>) -> Tally {
    let mut t = Tally::default();
    let tag = 4200 + 10 * kind as u64 + u64::from(proportional);
    for seed in seeds {
        let support = SUPPORTS[(seed % 3) as usize];
        let (x_in, x_out) = positions(tag, seed);
        let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
        let rec = record(beam, kind, noise_of(proportional), 3, tag, seed);
        t.records += 1;
        t.visible += rec.visible.len();
        let id = match identify(&rec.data, &IdentifySettings::default()) {
            Ok(id) => id,
            Err(e) => {
                if std::env::var("IDENTIFY_VERBOSE").is_ok() {
                    println!("seed {seed} {support:?}: failed: {e}");
                }
                t.failed += 1;
                continue;
            }
        };
        let near = |w: f64, m: f64| (w - m).abs() < 0.05 * m;
        t.false_modes +=
            id.modes.iter().filter(|m| !rec.beam.modes.iter().any(|b| near(m.omega_rad_s, b.omega))).count();
        let verbose = std::env::var("IDENTIFY_VERBOSE").is_ok();
        if verbose {
            println!("seed {seed} {support:?} x_in {x_in:.3} x_out {x_out:.3}: noise {:?}", id.noise_model);
        }
        for v in &rec.visible {
            let Some(m) = id.modes.iter().find(|m| near(m.omega_rad_s, v.omega)) else {
                if verbose {
                    println!("  missed {v:?}");
                }
                continue;
            };
            t.found += 1;
            if verbose {
                let zw = (m.omega_rad_s - v.omega) / m.omega_sd_rad_s;
                println!("  omega {:.1}: z omega {zw:.2}, z zeta {:.2}", v.omega, (m.zeta - v.zeta) / m.zeta_sd);
            }
            for z in [(m.omega_rad_s - v.omega) / m.omega_sd_rad_s, (m.zeta - v.zeta) / m.zeta_sd] {
                t.interval(z);
            }
        }
    }
    t
}

fn print(kind: Kind, proportional: bool, t: &Tally) {
    let f = |a: usize, b: usize| if b == 0 { f64::NAN } else { a as f64 / b as f64 };
    println!(
        "{kind:?}/{}: records {} failed {} | visible {} found {} ({:.3}) false {} | 95% cover {:.3}, 3sd cover {:.3} ({} intervals), worst |z| {:.1}",
        if proportional { "proportional" } else { "additive" },
        t.records,
        t.failed,
        t.visible,
        t.found,
        f(t.found, t.visible),
        t.false_modes,
        f(t.within_95, t.intervals),
        f(t.within_3sd, t.intervals),
        t.intervals,
        t.worst_z
    );
}

fn seeds() -> u64 {
    std::env::var("IDENTIFY_SEEDS").ok().and_then(|s| s.parse().ok()).unwrap_or(100)
}

#[test]
#[ignore = "coverage study (minutes): result in tests/identify_coverage.md"]
fn coverage_study() {
    let n = seeds();
    let only = std::env::var("IDENTIFY_KINDS").unwrap_or_default();
    for kind in [Kind::Complex, Kind::Magnitude, Kind::Psd, Kind::Time, Kind::Rician] {
        if !only.is_empty() && !only.contains(&format!("{kind:?}")) {
            continue;
        }
        for proportional in [false, true] {
            let noise = std::env::var("IDENTIFY_NOISE").unwrap_or_default();
            if !noise.is_empty() && noise != if proportional { "proportional" } else { "additive" } {
                continue;
            }
            let t = study(kind, proportional, 0..n);
            print(kind, proportional, &t);
        }
    }
}

/// One record of the subset, seed 0, simply supported: every visible mode
/// is found, no false mode is reported, each ω and ζ lies within 3.5 of its
/// reported sd (two-sided miss 4.7e-4 per interval under a correct sd; with
/// about 8 intervals per record a false failure has probability ≈ 0.4 %),
/// and the noise model named matches the generator's.
fn subset_record(kind: Kind, proportional: bool) {
    let tag = 4200 + 10 * kind as u64 + u64::from(proportional);
    let (x_in, x_out) = positions(tag, 0);
    let beam = Beam::new(Support::SimplySupported, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
    let rec = record(beam, kind, noise_of(proportional), 3, tag, 0);
    let id = identify(&rec.data, &IdentifySettings::default()).unwrap();
    assert!(!rec.visible.is_empty());
    assert_visible_found_within_3_5_sd(&rec, &id.modes, &format!("{kind:?} proportional={proportional}"));
    let expected = match (kind, proportional) {
        (Kind::Psd, _) => "welch_gamma",
        (_, true) => "additive_plus_proportional",
        (_, false) => "uniform",
    };
    assert_eq!(id.noise_model.kind, expected, "{kind:?}");
}

/// CI-sized subset: detection under additive noise, where the stabilisation
/// diagram alone lost most modes (issue 42 item 2): a magnitude record and a
/// Welch PSD with a white sensor floor.
#[test]
fn ci_subset_magnitude_and_psd_under_additive_noise() {
    subset_record(Kind::Magnitude, false);
    subset_record(Kind::Psd, false);
}

/// Issue 42's magnitude example, from the independent generator: a simply
/// supported beam, two resonances in a 4 000-point log sweep with 4–6 points
/// in their half-power bands (ζ = 1.5e-3 and 1.2e-3), additive noise of 0.5 %
/// of the peak. Every visible mode is found within 3.5 reported sd (the
/// bound of `subset_record`).
#[test]
fn narrow_resonances_of_a_magnitude_record_under_additive_noise_are_found() {
    let (x_in, x_out) = (0.21, 0.34);
    let mut beam = Beam::new(Support::SimplySupported, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
    beam.modes[0].zeta = 1.5e-3;
    beam.modes[1].zeta = 1.2e-3;
    let rec = record_with(beam, Kind::Magnitude, Noise::Additive { fraction: 5e-3 }, 2, 4000, 4242, 0);
    assert_eq!(rec.visible.len(), 2, "the generator's visibility");
    let id = identify(&rec.data, &IdentifySettings::default()).expect("identified");
    let near = |w: f64, m: f64| (w - m).abs() < 0.05 * m;
    for v in &rec.visible {
        let m = id.modes.iter().find(|m| near(m.omega_rad_s, v.omega)).unwrap_or_else(|| panic!("{v:?} not found"));
        let zw = (m.omega_rad_s - v.omega) / m.omega_sd_rad_s;
        let zz = (m.zeta - v.zeta) / m.zeta_sd;
        println!("narrow: z omega {zw:.2}, z zeta {zz:.2}, peak snr {:.1}", m.peak_snr);
        assert!(zw.abs() <= 3.5 && zz.abs() <= 3.5, "{m:?} vs {v:?}");
    }
}

/// Issue 44 defect 7, from the independent generator: mode 2 of a complex
/// sweep with ζ = 1e-9 (its half-power band ±1e-9·ω far under the 2e-3
/// relative spacing) is refused with exit 2 naming the under-sampled
/// resonance, instead of a partial result.
#[test]
fn an_under_sampled_resonance_is_refused() {
    let (x_in, x_out) = (0.21, 0.34);
    let mut beam = Beam::new(Support::SimplySupported, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
    beam.modes[1].zeta = 1e-9;
    let rec = record(beam, Kind::Complex, Noise::Additive { fraction: 5e-3 }, 3, 4243, 0);
    match identify(&rec.data, &IdentifySettings::default()) {
        Err(IdentifyError::Input(e)) => {
            println!("{e}");
            assert!(e.to_string().contains("half-power band"), "{e}");
        }
        other => panic!("expected an input error, got {:?}", other.map(|id| id.modes)),
    }
}

/// CI-sized subset: the complex sweep under both noise kinds.
#[test]
fn ci_subset_complex_sweep_under_both_noise_kinds() {
    subset_record(Kind::Complex, false);
    subset_record(Kind::Complex, true);
}

/// A ring-down with proportional noise (a² + b²y²): every visible mode is
/// found within 3.5 sd, no false mode, and the noise model named is
/// `additive_plus_proportional`. Its unweighted fit held two poles of the
/// noise (0.92 and 0.95 of Nyquist) and one grew under the weights, which
/// kept the unweighted fit and named `uniform`, until the reweighting
/// dropped such poles (`identify::without_grown_poles`).
#[test]
fn ci_subset_ring_down_with_proportional_noise() {
    subset_record(Kind::Time, true);
}

/// A ring-down with additive noise: its mode 1 (ω = 62 832 rad/s), well
/// above 20 noise sd, was lost by the matrix pencil's diagram; the peaks of
/// the record's spectrum recover it (issue 42 item 2).
#[test]
fn ci_subset_ring_down_with_additive_noise() {
    subset_record(Kind::Time, false);
}

/// CI-sized coverage study (issue 42 items 1 and 2): seeds 0–5 of the
/// study's `kind` / noise cell (the study's records, same generator).
/// Asserts that no record fails, that under additive noise every visible
/// mode is found, and that the 95 % intervals' coverage lies within 3 Monte
/// Carlo sd of 0.95. The Monte Carlo sd: ω and ζ of one mode are
/// correlated, so the effective number of independent intervals lies
/// between the number of modes k and 2k; the bound takes k, sd =
/// sqrt(0.95·0.05/k), which overstates the error (the bar errs towards
/// passing a slightly low coverage, never towards failing a right one: the
/// false-failure rate stays ≤ 0.27 %).
fn subset_coverage(kind: Kind, proportional: bool) {
    let t = study(kind, proportional, 0..6);
    print(kind, proportional, &t);
    assert_eq!(t.failed, 0, "{kind:?} proportional={proportional}: failed records");
    if !proportional {
        assert_eq!(t.found, t.visible, "{kind:?} additive: every visible mode found");
    }
    assert!(t.found > 0);
    let cover = t.within_95 as f64 / t.intervals as f64;
    let bar = 3.0 * (0.95f64 * 0.05 / t.found as f64).sqrt();
    assert!(
        (cover - 0.95).abs() <= bar,
        "{kind:?} proportional={proportional}: 95 % coverage {cover:.3} outside 0.95 ± {bar:.3}"
    );
}

fn ring_down_coverage(proportional: bool) {
    subset_coverage(Kind::Time, proportional);
}

/// Complex sweeps under additive noise (the 100-seed study: 0.918 of 378
/// intervals, 2.0–2.9 MC sd low; tests/identify_coverage.md). A guard
/// against gross failure only: seeds 0–5 cover 18 of 20.
#[test]
fn ci_complex_coverage_under_additive_noise() {
    subset_coverage(Kind::Complex, false);
}

#[test]
fn ci_ring_down_coverage_under_additive_noise() {
    ring_down_coverage(false);
}

/// Proportional noise: detection is measured, not asserted. Seeds 0–5 now
/// pass the bar (0.826 of 46 intervals against 0.95 ± 0.136), but the
/// 100-seed study covers 0.911 (858 intervals), 3.7–5.2 Monte Carlo sd
/// under 0.95, and the oracle fit at the true structure covers 0.928 on the
/// same records: a pass here would come from the bar's width, so the test
/// stays ignored (tests/identify_coverage.md).
#[test]
#[ignore = "known under-coverage: ring-down intervals under proportional noise cover 0.911 over 100 seeds (tests/identify_coverage.md)"]
fn ci_ring_down_coverage_under_proportional_noise() {
    ring_down_coverage(true);
}

/// Issue 44 defect 7's refusal on well-sampled lines: seeds 41 and 99 of
/// the complex / additive study (same generator) were refused with "2
/// samples in the half-power band (a peak 11.2 noise sd above its
/// baseline)" at a true mode whose band holds about 5 samples; the
/// refusal now counts the samples within the noise of the half-power level
/// (`peaks::Peak::samples_near_half`). Each record is identified with no
/// false mode and every visible mode found within 3.5 sd (the bound of
/// `subset_record`).
#[test]
fn well_sampled_lines_about_11_sd_high_are_not_refused() {
    let kind = Kind::Complex;
    let tag = 4200 + 10 * kind as u64;
    for seed in [41, 99] {
        let support = SUPPORTS[(seed % 3) as usize];
        let (x_in, x_out) = positions(tag, seed);
        let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
        let rec = record(beam, kind, noise_of(false), 3, tag, seed);
        let id =
            identify(&rec.data, &IdentifySettings::default()).unwrap_or_else(|e| panic!("seed {seed}: refused: {e}"));
        assert_visible_found_within_3_5_sd(&rec, &id.modes, &format!("seed {seed}"));
    }
}

/// Diagnostic of ring-down records (prints, asserts nothing): for each
/// record, each true mode below the anti-alias cut-off with its spectral
/// SNR, the oracle fit's z (weighted least squares with the generator's own
/// noise sd, started at the true poles) and `identify`'s z.
#[test]
#[ignore = "diagnostic printout"]
fn ring_down_diagnostics() {
    use nanobeam::identify::refine::mode_estimate;
    use nanobeam::identify::Measurement;
    let proportional = std::env::var("IDENTIFY_PROPORTIONAL").is_ok();
    let noise_free = std::env::var("IDENTIFY_NOISE_FREE").is_ok();
    let noise = if noise_free { Noise::Additive { fraction: 0.0 } } else { noise_of(proportional) };
    let kind = Kind::Time;
    let tag = 4200 + 10 * kind as u64 + u64::from(proportional);
    for seed in 0..seeds() {
        let support = SUPPORTS[(seed % 3) as usize];
        let (x_in, x_out) = positions(tag, seed);
        let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
        let rec = record(beam.clone(), kind, noise, 3, tag, seed);
        let Measurement::Time { time_s, .. } = &rec.data else { unreachable!() };
        let RingDownOracle { model, fit: oracle, modes, sd, dt } =
            ring_down_oracle_fit(&rec, noise).expect("a ring-down record");
        // the oracle's sandwich covariance (printed as "sandwich z")
        let sandwich = oracle.as_ref().and_then(|f| {
            let (r, j) = model.eval(&f.theta, true);
            let bread = (j.transpose() * &j).try_inverse()?;
            let mut scaled = j.clone();
            for (i, mut row) in scaled.row_iter_mut().enumerate() {
                row *= r[i];
            }
            let meat = scaled.transpose() * &scaled;
            let mut g = f.clone();
            g.cov = &bread * meat * &bread;
            Some(g)
        });
        let id = if std::env::var("ORACLE_ONLY").is_ok() {
            Err(IdentifyError::Numerical("skipped".into()))
        } else {
            identify(&rec.data, &IdentifySettings::default())
        };
        println!(
            "seed {seed} {support:?} x_in {x_in:.3} x_out {x_out:.3}: {} modes reported",
            id.as_ref().map_or(0, |i| i.modes.len())
        );
        for (r, m) in modes.iter().enumerate() {
            // matched-filter SNR: sqrt(Σ (mode signal / sd)²)
            let amp = m.gain / m.pole().im;
            let snr: f64 = time_s
                .iter()
                .zip(&sd)
                .map(|(&t, s)| (amp * (m.pole().re * t).exp() * (m.pole().im * t).sin() / s).powi(2))
                .sum::<f64>()
                .sqrt();
            let vis = rec.visible.iter().any(|v| v.omega == m.omega);
            let osd = oracle.as_ref().map(|f| {
                let [_, wsd, _, zsd] = mode_estimate(f, r);
                (wsd * std::f64::consts::PI / dt, zsd)
            });
            let oz = oracle.as_ref().map(|f| {
                let [w, wsd, z, zsd] = mode_estimate(f, r);
                let s = std::f64::consts::PI / dt;
                ((w * s - m.omega) / (wsd * s), (z - m.zeta) / zsd)
            });
            if let Some(f) = &sandwich {
                let [w, wsd, z, zsd] = mode_estimate(f, r);
                let s = std::f64::consts::PI / dt;
                println!("  sandwich z {:.2} {:.2}", (w * s - m.omega) / (wsd * s), (z - m.zeta) / zsd);
            }
            if let (Some((ow, oz_)), Ok(i)) = (osd, id.as_ref()) {
                if let Some(x) = i.modes.iter().find(|x| (x.omega_rad_s - m.omega).abs() < 0.05 * m.omega) {
                    println!(
                        "  sd ratio identify/oracle: omega {:.3} zeta {:.3}",
                        x.omega_sd_rad_s / ow,
                        x.zeta_sd / oz_
                    );
                }
            }
            let iz = id.as_ref().ok().and_then(|i| {
                i.modes
                    .iter()
                    .find(|x| (x.omega_rad_s - m.omega).abs() < 0.05 * m.omega)
                    .map(|x| ((x.omega_rad_s - m.omega) / x.omega_sd_rad_s, (x.zeta - m.zeta) / x.zeta_sd))
            });
            println!(
                "  mode {} omega {:.4e} vis {vis} amp/floor {:.1} mf-snr {snr:.1} oracle z {:?} identify z {:?}",
                r + 1,
                m.omega,
                amp.abs() / sd[0].min(sd.iter().copied().fold(f64::INFINITY, f64::min)),
                oz.map(|(a, b)| (format!("{a:.2}"), format!("{b:.2}"))),
                iz.map(|(a, b)| (format!("{a:.2}"), format!("{b:.2}")))
            );
        }
        if let Ok(i) = &id {
            println!("  noise {:?}", i.noise_model);
            for x in &i.modes {
                if !beam.modes.iter().any(|b| (x.omega_rad_s - b.omega).abs() < 0.05 * b.omega) {
                    println!("  FALSE {x:?}");
                }
            }
        }
    }
}

/// Every reported mode lies within 5 % of a true mode (no false mode), and
/// every visible true mode is found with ω and ζ within 3.5 reported sd
/// (`what` labels the failure).
fn assert_visible_found_within_3_5_sd(rec: &Record, modes: &[IdentifiedMode], what: &str) {
    let near = |w: f64, m: f64| (w - m).abs() < 0.05 * m;
    for m in modes {
        assert!(rec.beam.modes.iter().any(|b| near(m.omega_rad_s, b.omega)), "{what}: false mode {m:?}");
    }
    for v in &rec.visible {
        let m = modes.iter().find(|m| near(m.omega_rad_s, v.omega));
        let m = m.unwrap_or_else(|| panic!("{what}: mode at {} not found", v.omega));
        let zw = (m.omega_rad_s - v.omega) / m.omega_sd_rad_s;
        let zz = (m.zeta - v.zeta) / m.zeta_sd;
        println!("{what}: z omega {zw:.2}, z zeta {zz:.2}");
        assert!(zw.abs() <= 3.5 && zz.abs() <= 3.5, "{what}: {m:?} vs {v:?}");
    }
}

/// The oracle of a ring-down record: weighted least squares at the true
/// model structure (the true modes below the anti-alias cut-off, 1
/// relaxation pole and the offset), weights 1/σ(t) from the generator's own
/// clean signal and noise law, started at the true poles. `None` for a
/// record that is not a ring-down; `fit` is `None` when the fit fails.
struct RingDownOracle {
    model: nanobeam::identify::refine::Model,
    fit: Option<nanobeam::identify::refine::FitResult>,
    /// the true modes below the cut-off, in the beam's order
    modes: Vec<identify_reference::TrueMode>,
    /// the generator's noise sd at every sample
    sd: Vec<f64>,
    dt: f64,
}

fn ring_down_oracle_fit(rec: &Record, noise: Noise) -> Option<RingDownOracle> {
    use nanobeam::identify::projected::fit_projected;
    use nanobeam::identify::refine::{FitKind, Model, PER_MODE};
    use nanobeam::identify::{Measurement, Stop};
    use num_complex::Complex64;
    let Measurement::Time { time_s, displacement_m } = &rec.data else { return None };
    let beam = &rec.beam;
    let dt = time_s[1] - time_s[0];
    let cutoff = 0.8 * std::f64::consts::PI / dt;
    let modes: Vec<_> = beam.modes.iter().filter(|m| m.omega < cutoff).copied().collect();
    let peak = displacement_m.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let clean: Vec<f64> = time_s.iter().map(|&t| beam.impulse(t, cutoff)).collect();
    let cpeak = clean.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let sd: Vec<f64> = clean.iter().map(|&v| noise.sd(v, cpeak).max(1e-300)).collect();
    let model = Model {
        kind: FitKind::Time,
        x: (0..time_s.len()).map(|k| std::f64::consts::PI * k as f64).collect(),
        y: displacement_m.iter().map(|v| Complex64::new(v / peak, 0.0)).collect(),
        n_modes: modes.len(),
        n_real: 1,
        poly: vec![0],
        weights: Some(sd.iter().map(|s| sd[0] / s).collect()),
        stop: Stop::default(),
    };
    let mut theta = vec![0.0; model.n_params()];
    for (r, m) in modes.iter().enumerate() {
        let p = m.pole() * dt / std::f64::consts::PI;
        theta[PER_MODE * r] = -p.re;
        theta[PER_MODE * r + 1] = p.im;
    }
    theta[PER_MODE * modes.len()] = beam.gamma * dt / std::f64::consts::PI;
    let fit = model.solve_linear(&theta).and_then(|t| fit_projected(&model, &t));
    Some(RingDownOracle { model, fit, modes, sd, dt })
}

/// The oracle's ([`ring_down_oracle_fit`]) ω, sd ω, ζ, sd ζ (rad/s) per true
/// mode below the cut-off, in the beam's order.
fn ring_down_oracle(rec: &Record, noise: Noise) -> Option<Vec<[f64; 4]>> {
    let o = ring_down_oracle_fit(rec, noise)?;
    let fit = o.fit?;
    let s = std::f64::consts::PI / o.dt;
    Some(estimates_in_rad_s(&fit, o.modes.len(), s))
}

/// ω, sd ω (rad/s: the fit's scaled units times `scale`), ζ, sd ζ of the
/// first `n` modes of an oracle fit.
fn estimates_in_rad_s(fit: &nanobeam::identify::refine::FitResult, n: usize, scale: f64) -> Vec<[f64; 4]> {
    use nanobeam::identify::refine::mode_estimate;
    (0..n)
        .map(|r| {
            let [w, wsd, z, zsd] = mode_estimate(fit, r);
            [w * scale, wsd * scale, z, zsd]
        })
        .collect()
}

/// Breakdown of the ring-down coverage (issue 42 item 1; prints only): for
/// every visible mode `identify` found, its z and the oracle's
/// ([`ring_down_oracle`]), and whether `identify`'s fit holds every true mode
/// below the cut-off (a reported or background pole within 2 % of it), how
/// many of its poles match no true mode, and how many real poles it chose.
/// Summary lines split the coverage by these.
#[test]
#[ignore = "diagnostic printout"]
fn ring_down_breakdown() {
    let proportional = std::env::var("IDENTIFY_PROPORTIONAL").is_ok();
    let noise = noise_of(proportional);
    let kind = Kind::Time;
    let tag = 4200 + 10 * kind as u64 + u64::from(proportional);
    // (label, z identify ω, z identify ζ, z oracle ω, z oracle ζ)
    let mut rows: Vec<(String, [f64; 4])> = Vec::new();
    let first: u64 = std::env::var("IDENTIFY_FIRST").ok().and_then(|s| s.parse().ok()).unwrap_or(0);
    for seed in first..first + seeds() {
        let support = SUPPORTS[(seed % 3) as usize];
        let (x_in, x_out) = positions(tag, seed);
        let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
        let rec = record(beam, kind, noise, 3, tag, seed);
        let identify_settings = IdentifySettings::default();
        let Ok(id) = identify(&rec.data, &identify_settings) else {
            println!("seed {seed}: failed");
            continue;
        };
        let oracle = ring_down_oracle(&rec, noise);
        let nanobeam::identify::Measurement::Time { time_s, .. } = &rec.data else { unreachable!() };
        let dt = time_s[1] - time_s[0];
        let nyquist = std::f64::consts::PI / dt;
        let below: Vec<_> = rec.beam.modes.iter().filter(|m| m.omega < 0.8 * nyquist).copied().collect();
        let poles: Vec<f64> = id.modes.iter().chain(&id.background_modes).map(|m| m.omega_rad_s).collect();
        let held = below.iter().all(|b| poles.iter().any(|&w| (w - b.omega).abs() < 0.02 * b.omega));
        let extra =
            poles.iter().filter(|&&w| !rec.beam.modes.iter().any(|b| (w - b.omega).abs() < 0.02 * b.omega)).count();
        let tag_rec = format!(
            "held={held} extra={extra} real={} noise={}/{}",
            id.real_poles_rad_s.len(),
            id.noise_model.kind,
            id.noise_model.covariance
        );
        println!("seed {seed} {support:?} {tag_rec}");
        if !held {
            for b in &below {
                if !poles.iter().any(|&w| (w - b.omega).abs() < 0.02 * b.omega) {
                    println!("  not in the fit: omega {:.4e} ({:.2} Nyquist)", b.omega, b.omega / nyquist);
                }
            }
        }
        for (k, m) in id.modes.iter().chain(&id.background_modes).enumerate() {
            if !rec.beam.modes.iter().any(|b| (m.omega_rad_s - b.omega).abs() < 0.02 * b.omega) {
                // a reported mode 5 % from every true mode is a false mode of the study
                let reported = k < id.modes.len();
                let false_mode =
                    reported && !rec.beam.modes.iter().any(|b| (m.omega_rad_s - b.omega).abs() < 0.05 * b.omega);
                println!(
                    "  extra pole{}: omega {:.4e} ({:.2} Nyquist) zeta {:.2e} amplitude snr {:.1}",
                    if false_mode {
                        " (FALSE mode)"
                    } else if reported {
                        " (reported)"
                    } else {
                        ""
                    },
                    m.omega_rad_s,
                    m.omega_rad_s / nyquist,
                    m.zeta,
                    m.amplitude_snr
                );
            }
        }
        for v in &rec.visible {
            let Some(m) = id.modes.iter().find(|m| (m.omega_rad_s - v.omega).abs() < 0.05 * v.omega) else { continue };
            let zi = [(m.omega_rad_s - v.omega) / m.omega_sd_rad_s, (m.zeta - v.zeta) / m.zeta_sd];
            let r = below.iter().position(|b| b.omega == v.omega).expect("visible modes lie below the cut-off");
            let zo = oracle
                .as_ref()
                .map_or([f64::NAN; 2], |o| [(o[r][0] - v.omega) / o[r][1], (o[r][2] - v.zeta) / o[r][3]]);
            let sdr = oracle.as_ref().map_or(f64::NAN, |o| m.omega_sd_rad_s / o[r][1]);
            println!(
                "  mode {} ({:.2} Nyquist, amp snr {:.0}): identify z {:+.2} {:+.2} oracle z {:+.2} {:+.2} sd ratio {sdr:.2}",
                r + 1,
                v.omega / nyquist,
                m.amplitude_snr,
                zi[0],
                zi[1],
                zo[0],
                zo[1]
            );
            rows.push((tag_rec.clone(), [zi[0], zi[1], zo[0], zo[1]]));
        }
    }
    let summary = |what: &str, pick: &dyn Fn(&str) -> bool| {
        let sel: Vec<&[f64; 4]> = rows.iter().filter(|(t, _)| pick(t)).map(|(_, z)| z).collect();
        let cover = |k: usize| {
            let z: Vec<f64> = sel.iter().flat_map(|r| [r[k], r[k + 1]]).filter(|z| z.is_finite()).collect();
            let n = z.len().max(1) as f64;
            let c = z.iter().filter(|z| z.abs() <= 1.96).count() as f64 / n;
            let sd = (z.iter().map(|z| z * z).sum::<f64>() / n).sqrt();
            let kurt = z.iter().map(|z| z.powi(4)).sum::<f64>() / n / (sd.powi(4)).max(1e-300);
            format!("cover {c:.3} rms z {sd:.2} kurtosis {kurt:.1} ({} intervals)", z.len())
        };
        println!("{what}: {} modes | identify {} | oracle {}", sel.len(), cover(0), cover(2));
    };
    summary("all", &|_| true);
    summary("fit holds every true mode", &|t| t.starts_with("held=true"));
    summary("fit misses a true mode", &|t| t.starts_with("held=false"));
    summary("no extra pole", &|t| t.contains("extra=0 "));
    summary("extra poles", &|t| !t.contains("extra=0 "));
    summary("held, no extra pole", &|t| t.starts_with("held=true extra=0 "));
    summary("model covariance", &|t| t.ends_with("/model"));
    summary("sandwich covariance", &|t| t.ends_with("/sandwich"));
}

/// A ring-down whose initial poles (matrix pencil and spectrum peaks) miss
/// a true mode: seed 29 of the proportional-noise study (cantilever, same
/// generator). Its mode 4 (2.16e6 rad/s, 0.49 Nyquist) was not in the fit,
/// and mode 3's ζ came out 6.35 reported sd off (the fit bent mode 3 to
/// absorb mode 4's signal); the oracle fit at the true structure puts it at
/// 1.86 sd. The search of the weighted residuals
/// (`identify::with_missed_decay_poles`) adds the pole. Asserts that every
/// true mode below the anti-alias cut-off is held by a fitted pole within
/// 2 % of it and that every visible mode is found within 3.5 sd (the bound
/// of `subset_record`), with no false mode.
#[test]
fn a_mode_the_initial_poles_miss_is_found_in_the_residuals() {
    let (kind, proportional, seed) = (Kind::Time, true, 29);
    let tag = 4200 + 10 * kind as u64 + u64::from(proportional);
    let support = SUPPORTS[(seed % 3) as usize];
    let (x_in, x_out) = positions(tag, seed);
    let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
    let rec = record(beam, kind, noise_of(proportional), 3, tag, seed);
    let id = identify(&rec.data, &IdentifySettings::default()).expect("identified");
    let nanobeam::identify::Measurement::Time { time_s, .. } = &rec.data else { unreachable!() };
    let cutoff = 0.8 * std::f64::consts::PI / (time_s[1] - time_s[0]);
    let poles: Vec<f64> = id.modes.iter().chain(&id.background_modes).map(|m| m.omega_rad_s).collect();
    for b in rec.beam.modes.iter().filter(|b| b.omega < cutoff) {
        assert!(poles.iter().any(|&w| (w - b.omega).abs() < 0.02 * b.omega), "true mode at {} not in the fit", b.omega);
    }
    assert_visible_found_within_3_5_sd(&rec, &id.modes, "seed 29");
}

/// The oracle of a frequency record (complex or magnitude): least squares
/// at the true structure (every true mode of the beam, in band or above it,
/// and the relaxation pole, no residual terms: H is exactly that rational
/// function), uniform weights (the additive noise's own law), started at the
/// true poles and residues. ω, sd ω, ζ, sd ζ (rad/s) per true mode in the
/// beam's order; `None` when the record is a ring-down or the PSD, or the
/// fit fails.
fn frequency_oracle(rec: &Record) -> Option<Vec<[f64; 4]>> {
    use nanobeam::identify::projected::fit_projected;
    use nanobeam::identify::refine::{fit, FitKind, Model, PER_MODE};
    use nanobeam::identify::{Measurement, Stop};
    use num_complex::Complex64;
    let (kind, w, y): (FitKind, &Vec<f64>, Vec<Complex64>) = match &rec.data {
        Measurement::Complex { omega_rad_s, h_m_per_n } => (FitKind::Complex, omega_rad_s, h_m_per_n.clone()),
        Measurement::Magnitude { omega_rad_s, h_abs_m_per_n } => {
            (FitKind::Magnitude, omega_rad_s, h_abs_m_per_n.iter().map(|&v| Complex64::new(v, 0.0)).collect())
        }
        _ => return None,
    };
    let beam = &rec.beam;
    let w_ref = 1.5 * w[w.len() - 1];
    let y_ref = y.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let model = Model {
        kind,
        x: w.iter().map(|v| v / w_ref).collect(),
        y: y.iter().map(|v| v / y_ref).collect(),
        n_modes: beam.modes.len(),
        n_real: 1,
        poly: vec![],
        weights: None,
        stop: Stop::default(),
    };
    // H = gain/((s − p)(s − p̄)) in s̃ = s/w_ref: residue gain/(w_ref²·2i·Im p̃) at p̃
    let mut theta = vec![0.0; model.n_params()];
    for (r, m) in beam.modes.iter().enumerate() {
        let p = m.pole() / w_ref;
        let a = Complex64::new(m.gain / (w_ref * w_ref * y_ref), 0.0) / Complex64::new(0.0, 2.0 * p.im);
        theta[PER_MODE * r..PER_MODE * (r + 1)].copy_from_slice(&[-p.re, p.im, a.re, a.im]);
    }
    let o = PER_MODE * beam.modes.len();
    theta[o] = beam.gamma / w_ref;
    theta[o + 1] = beam.b / (w_ref * y_ref);
    let f = if kind == FitKind::Complex { fit_projected(&model, &theta)? } else { fit(&model, theta, &[])? };
    Some(estimates_in_rad_s(&f, beam.modes.len(), w_ref))
}

/// Breakdown of the coverage of frequency records (prints only; issue 42
/// item 1): `IDENTIFY_KIND=Complex|Magnitude` (default Complex),
/// `IDENTIFY_PROPORTIONAL=1` for proportional noise (the oracle then
/// assumes uniform noise and is not the right oracle). For every visible
/// mode `identify` found: its z and the oracle's ([`frequency_oracle`]),
/// the mode's peak SNR over the noise, the samples in its half-power band,
/// whether `identify`'s fit holds every true mode in the band (a reported
/// or background pole within 2 %), the noise model and covariance chosen,
/// the real poles. Summary lines split the coverage by these.
#[test]
#[ignore = "diagnostic printout"]
fn frequency_breakdown() {
    let proportional = std::env::var("IDENTIFY_PROPORTIONAL").is_ok();
    let kind = match std::env::var("IDENTIFY_KIND").as_deref() {
        Ok("Magnitude") => Kind::Magnitude,
        _ => Kind::Complex,
    };
    let noise = noise_of(proportional);
    let tag = 4200 + 10 * kind as u64 + u64::from(proportional);
    let first: u64 = std::env::var("IDENTIFY_FIRST").ok().and_then(|s| s.parse().ok()).unwrap_or(0);
    // (label, [z identify ω, z identify ζ, z oracle ω, z oracle ζ], snr, band points)
    type Row = (String, [f64; 4], f64, usize);
    let mut rows: Vec<Row> = Vec::new();
    for seed in first..first + seeds() {
        let support = SUPPORTS[(seed % 3) as usize];
        let (x_in, x_out) = positions(tag, seed);
        let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
        let rec = record(beam, kind, noise, 3, tag, seed);
        let Ok(id) = identify(&rec.data, &IdentifySettings::default()) else {
            println!("seed {seed}: failed");
            continue;
        };
        let oracle = frequency_oracle(&rec);
        let w: Vec<f64> = match &rec.data {
            nanobeam::identify::Measurement::Complex { omega_rad_s, .. }
            | nanobeam::identify::Measurement::Magnitude { omega_rad_s, .. } => omega_rad_s.clone(),
            _ => unreachable!(),
        };
        let hi = w[w.len() - 1];
        let peak = match &rec.data {
            nanobeam::identify::Measurement::Complex { h_m_per_n, .. } => {
                h_m_per_n.iter().map(|v| v.norm()).fold(0.0, f64::max)
            }
            nanobeam::identify::Measurement::Magnitude { h_abs_m_per_n, .. } => {
                h_abs_m_per_n.iter().copied().fold(0.0, f64::max)
            }
            _ => unreachable!(),
        };
        let poles: Vec<f64> = id.modes.iter().chain(&id.background_modes).map(|m| m.omega_rad_s).collect();
        let in_band: Vec<_> = rec.beam.modes.iter().filter(|m| m.omega <= hi).copied().collect();
        let held = in_band.iter().all(|b| poles.iter().any(|&p| (p - b.omega).abs() < 0.02 * b.omega));
        let extra = poles
            .iter()
            .filter(|&&p| p <= hi && !rec.beam.modes.iter().any(|b| (p - b.omega).abs() < 0.02 * b.omega))
            .count();
        let label = format!(
            "held={held} extra={extra} real={} noise={}/{}",
            id.real_poles_rad_s.len(),
            id.noise_model.kind,
            id.noise_model.covariance
        );
        println!(
            "seed {seed} {support:?} x {x_in:.3} {x_out:.3} {label} lr {:.1} bp {:.1} real poles {:?}",
            id.noise_model.likelihood_ratio, id.noise_model.breusch_pagan, id.real_poles_rad_s
        );
        for m in id.modes.iter().chain(&id.background_modes) {
            if !rec.beam.modes.iter().any(|b| (m.omega_rad_s - b.omega).abs() < 0.02 * b.omega) {
                println!(
                    "  extra pole: omega {:.4e} ({:.3} of the band top) zeta {:.2e} peak snr {:.1}",
                    m.omega_rad_s,
                    m.omega_rad_s / hi,
                    m.zeta,
                    m.peak_snr
                );
            }
        }
        for v in &rec.visible {
            let Some(m) = id.modes.iter().find(|m| (m.omega_rad_s - v.omega).abs() < 0.05 * v.omega) else {
                println!("  missed visible mode at {:.4e}", v.omega);
                continue;
            };
            let r = rec.beam.modes.iter().position(|b| b.omega == v.omega).expect("a true mode");
            let zi = [(m.omega_rad_s - v.omega) / m.omega_sd_rad_s, (m.zeta - v.zeta) / m.zeta_sd];
            let zo = oracle
                .as_ref()
                .map_or([f64::NAN; 2], |o| [(o[r][0] - v.omega) / o[r][1], (o[r][2] - v.zeta) / o[r][3]]);
            let sdr = oracle.as_ref().map_or([f64::NAN; 2], |o| [m.omega_sd_rad_s / o[r][1], m.zeta_sd / o[r][3]]);
            let snr = v.h(v.omega).norm() / noise.sd(v.h(v.omega).norm(), peak);
            let band = w.iter().filter(|&&x| (x - v.omega).abs() <= v.zeta * v.omega).count();
            println!(
                "  mode {} snr {snr:.0} band {band}: identify z {:+.2} {:+.2} oracle z {:+.2} {:+.2} sd ratio {:.2} {:.2}",
                r + 1,
                zi[0],
                zi[1],
                zo[0],
                zo[1],
                sdr[0],
                sdr[1]
            );
            rows.push((label.clone(), [zi[0], zi[1], zo[0], zo[1]], snr, band));
        }
    }
    let summary = |what: &str, pick: &dyn Fn(&Row) -> bool| {
        let sel: Vec<&[f64; 4]> = rows.iter().filter(|r| pick(r)).map(|r| &r.1).collect();
        let cover = |k: usize| {
            let z: Vec<f64> = sel.iter().flat_map(|r| [r[k], r[k + 1]]).filter(|z| z.is_finite()).collect();
            let n = z.len().max(1) as f64;
            let c = z.iter().filter(|z| z.abs() <= 1.96).count() as f64 / n;
            let sd = (z.iter().map(|z| z * z).sum::<f64>() / n).sqrt();
            let kurt = z.iter().map(|z| z.powi(4)).sum::<f64>() / n / (sd.powi(4)).max(1e-300);
            format!("cover {c:.3} rms z {sd:.2} kurtosis {kurt:.1} ({} intervals)", z.len())
        };
        let omega_zeta = |k: usize| {
            let z: Vec<f64> = sel.iter().map(|r| r[k]).filter(|z| z.is_finite()).collect();
            let n = z.len().max(1) as f64;
            format!("{:.3}", z.iter().filter(|z| z.abs() <= 1.96).count() as f64 / n)
        };
        println!(
            "{what}: {} modes | identify {} (ω {}, ζ {}) | oracle {} (ω {}, ζ {})",
            sel.len(),
            cover(0),
            omega_zeta(0),
            omega_zeta(1),
            cover(2),
            omega_zeta(2),
            omega_zeta(3)
        );
    };
    summary("all", &|_| true);
    summary("fit holds every true mode in the band", &|r| r.0.starts_with("held=true"));
    summary("fit misses a true mode in the band", &|r| r.0.starts_with("held=false"));
    summary("no extra pole in the band", &|r| r.0.contains("extra=0 "));
    summary("extra poles in the band", &|r| !r.0.contains("extra=0 "));
    summary("uniform noise model", &|r| r.0.contains("noise=uniform/"));
    summary("proportional noise model", &|r| r.0.contains("noise=additive_plus_proportional/"));
    summary("model covariance", &|r| r.0.ends_with("/model"));
    summary("sandwich covariance", &|r| r.0.ends_with("/sandwich"));
    for k in 0..=3 {
        summary(&format!("{k} real poles"), &|r| r.0.contains(&format!("real={k} ")));
    }
    summary("snr 20–50", &|r| r.2 < 50.0);
    summary("snr 50–200", &|r| (50.0..200.0).contains(&r.2));
    summary("snr ≥ 200", &|r| r.2 >= 200.0);
    summary("band points 3–5", &|r| r.3 <= 5);
    summary("band points 6–10", &|r| (6..=10).contains(&r.3));
    summary("band points > 10", &|r| r.3 > 10);
}

/// Experiment (prints only): the complex sweep of `IDENTIFY_SEED` (additive
/// noise) refined as `identify` does (poles scaled by 1.5·ω_max, residual
/// terms s̃⁰…s̃², two out-of-band poles at 1.2 and 1.6 of the band top,
/// real-pole starts geometric over the band), started at the true in-band
/// poles, with 0…3 real poles: convergence, evaluations, RSS, BIC.
#[test]
#[ignore = "diagnostic printout"]
fn complex_real_pole_candidates() {
    use nanobeam::identify::projected::fit_projected;
    use nanobeam::identify::refine::{mode_estimate, FitKind, Model, PER_MODE};
    use nanobeam::identify::{Measurement, Stop};
    use num_complex::Complex64;
    let kind = Kind::Complex;
    let tag = 4200 + 10 * kind as u64;
    let seed: u64 = std::env::var("IDENTIFY_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(10);
    let support = SUPPORTS[(seed % 3) as usize];
    let (x_in, x_out) = positions(tag, seed);
    let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
    let rec = record(beam, kind, noise_of(false), 3, tag, seed);
    let Measurement::Complex { omega_rad_s: w, h_m_per_n: y } = &rec.data else { unreachable!() };
    let w_ref = 1.5 * w[w.len() - 1];
    let y_ref = y.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let x: Vec<f64> = w.iter().map(|v| v / w_ref).collect();
    let (lo, hi) = (x[0].max(1e-2), 1.0 / 1.5);
    let mut poles: Vec<Complex64> =
        rec.beam.modes.iter().filter(|m| m.omega <= w[w.len() - 1]).map(|m| m.pole() / w_ref).collect();
    let n_in = poles.len();
    for j in 0..2 {
        let p = (1.2 + 0.4 * j as f64) * hi;
        poles.push(Complex64::new(-0.01 * p, p));
    }
    println!("seed {seed} {support:?}: gamma/w_ref {:.4}, band [{lo:.4}, {hi:.4}]", rec.beam.gamma / w_ref);
    for n_real in 0..=3 {
        let model = Model {
            kind: FitKind::Complex,
            x: x.clone(),
            y: y.iter().map(|v| v / y_ref).collect(),
            n_modes: poles.len(),
            n_real,
            poly: vec![0, 1, 2],
            weights: None,
            stop: Stop::default(),
        };
        let mut theta = vec![0.0; model.n_params()];
        for (r, p) in poles.iter().enumerate() {
            theta[PER_MODE * r] = -p.re;
            theta[PER_MODE * r + 1] = p.im;
        }
        let o = PER_MODE * poles.len();
        for k in 0..n_real {
            theta[o + 2 * k] = lo * (hi / lo).powf((k as f64 + 0.5) / n_real as f64);
        }
        let theta = model.solve_linear(&theta).unwrap();
        match fit_projected(&model, &theta) {
            Some(f) => {
                let m = model.n_residuals() as f64;
                let bic = m * (f.rss / m).ln() + model.n_params() as f64 * m.ln();
                let z: Vec<String> = rec
                    .visible
                    .iter()
                    .filter_map(|v| {
                        let r =
                            (0..n_in).find(|&r| (mode_estimate(&f, r)[0] * w_ref - v.omega).abs() < 0.05 * v.omega)?;
                        let [om, os, ze, zs] = mode_estimate(&f, r);
                        Some(format!("({:+.2} {:+.2})", (om * w_ref - v.omega) / (os * w_ref), (ze - v.zeta) / zs))
                    })
                    .collect();
                let reals: Vec<f64> = (0..n_real).map(|k| f.theta[o + 2 * k]).collect();
                let oob: Vec<String> = (n_in..poles.len())
                    .map(|r| format!("({:.3} {:.3})", f.theta[PER_MODE * r], f.theta[PER_MODE * r + 1]))
                    .collect();
                println!(
                    "  {n_real} real: converged {} evals {} rss {:.6e} bic {bic:.2} real {reals:.4?} oob {oob:?} z {z:?}",
                    f.converged, f.evaluations, f.rss
                );
            }
            None => println!("  {n_real} real: failed"),
        }
    }
}

/// A candidate that stops at its evaluation budget is continued, not
/// dropped for a worse one that converged (`identify`'s `continue_the_leader`): seed 10
/// of the complex / additive study (clamped–clamped, same generator). Its
/// 1-real-pole candidate reached the budget with a BIC 1 080 below the
/// 0-real-pole candidate's; the latter was chosen, without the relaxation
/// pole at 0.3ω₁, and its three modes came out at |z| up to 4.63 (the
/// oracle at the true structure: ≤ 0.59). Asserts a real pole in the fit,
/// within 10 % of the true γ, and every visible mode found within 3.5 sd
/// with no false mode (the bound of `subset_record`).
#[test]
fn a_refinement_at_its_budget_is_continued() {
    let (kind, seed) = (Kind::Complex, 10);
    let tag = 4200 + 10 * kind as u64;
    let support = SUPPORTS[(seed % 3) as usize];
    let (x_in, x_out) = positions(tag, seed);
    let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
    let rec = record(beam, kind, noise_of(false), 3, tag, seed);
    let id = identify(&rec.data, &IdentifySettings::default()).expect("identified");
    let gamma = rec.beam.gamma;
    assert!(
        id.real_poles_rad_s.iter().any(|g| (g - gamma).abs() < 0.1 * gamma),
        "real poles {:?}, relaxation at {gamma}",
        id.real_poles_rad_s
    );
    assert_visible_found_within_3_5_sd(&rec, &id.modes, "seed 10");
}

/// The magnitude / additive cell's suspect (issue 42 item 1; prints only):
/// the generator's magnitude is |(|H| + e)|, folded at zero, so near an
/// antiresonance where |H| is under the noise sd the samples are not the
/// additive Gaussian law the fit assumes. Each record of the study is
/// identified twice: as generated, and as its unfolded twin |H| + e (the
/// same draws of e, regenerated from the generator's stream in its order;
/// the twin's absolute value is checked to be the record). Prints each
/// cell's tally as `study` does. `IDENTIFY_SEEDS` (default 100).
#[test]
#[ignore = "diagnostic printout"]
fn magnitude_fold_check() {
    use nanobeam::bayes::rng::{stream, Purpose};
    use nanobeam::identify::Measurement;
    use rand_distr::{Distribution, StandardNormal};
    let kind = Kind::Magnitude;
    let noise = noise_of(false);
    let tag = 4200 + 10 * kind as u64;
    let (mut folded, mut unfolded) = (Tally::default(), Tally::default());
    for seed in 0..seeds() {
        let support = SUPPORTS[(seed % 3) as usize];
        let (x_in, x_out) = positions(tag, seed);
        let beam = Beam::new(support, 5, 2.0 * std::f64::consts::PI * 1.0e4, x_in, x_out, 0.3);
        let rec = record(beam, kind, noise, 3, tag, seed);
        let Measurement::Magnitude { omega_rad_s, h_abs_m_per_n } = &rec.data else { unreachable!() };
        let h: Vec<f64> = omega_rad_s.iter().map(|&w| rec.beam.h(w).norm()).collect();
        let peak = h.iter().copied().fold(0.0, f64::max);
        let mut rng = stream(42, Purpose::MeasurementNoise, [tag, seed]);
        let twin: Vec<f64> = h
            .iter()
            .map(|&v| {
                let e: f64 = StandardNormal.sample(&mut rng);
                v + noise.sd(v, peak) * e
            })
            .collect();
        assert!(
            twin.iter().zip(h_abs_m_per_n).all(|(a, b)| a.abs() == *b),
            "seed {seed}: the twin is not the record's"
        );
        let negative = twin.iter().filter(|v| **v < 0.0).count();
        let unfolded_rec = Record {
            data: Measurement::Magnitude { omega_rad_s: omega_rad_s.clone(), h_abs_m_per_n: twin },
            visible: rec.visible.clone(),
            beam: rec.beam.clone(),
        };
        for (t, r, what) in [(&mut folded, &rec, "folded"), (&mut unfolded, &unfolded_rec, "unfolded")] {
            t.records += 1;
            t.visible += r.visible.len();
            let Ok(id) = identify(&r.data, &IdentifySettings::default()) else {
                println!("seed {seed} {what}: failed");
                t.failed += 1;
                continue;
            };
            let near = |w: f64, m: f64| (w - m).abs() < 0.05 * m;
            let false_modes =
                id.modes.iter().filter(|m| !r.beam.modes.iter().any(|b| near(m.omega_rad_s, b.omega))).count();
            t.false_modes += false_modes;
            let mut zs = Vec::new();
            for v in &r.visible {
                let Some(m) = id.modes.iter().find(|m| near(m.omega_rad_s, v.omega)) else { continue };
                t.found += 1;
                for z in [(m.omega_rad_s - v.omega) / m.omega_sd_rad_s, (m.zeta - v.zeta) / m.zeta_sd] {
                    let z = t.interval(z);
                    zs.push(format!("{z:.2}"));
                }
            }
            println!(
                "seed {seed} {what}: {negative} negative samples unfolded, noise {}/{}, false {false_modes}, |z| {}",
                id.noise_model.kind,
                id.noise_model.covariance,
                zs.join(" ")
            );
        }
    }
    print(kind, false, &folded);
    println!("(above: as generated, folded; below: the unfolded twin)");
    print(kind, false, &unfolded);
}
