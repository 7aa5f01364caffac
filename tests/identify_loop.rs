//! Closing the loop: model → simulated record (sweep, PSD, ring-down) →
//! `identify` → the model's own modes (`beam::modal`), with and without noise.
//! Run with `-- --nocapture` for the numbers.

use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::beam::{frf, impulse_response, modal, BeamSpec, ModalResult};
use nanobeam::identify::{identify, IdentifiedMode, IdentifySettings, Measurement};
use num_complex::Complex64;
use rand_distr::{Distribution, Gamma, StandardNormal};

/// The paper's beam (Table 4 truth as reconstructed in paper/reconstructed.yaml).
fn paper_beam() -> BeamSpec {
    let text = include_str!("../paper/reconstructed.yaml");
    nanobeam::reproduce::reconstruction::table_4_beam_from_yaml(text).expect("paper/reconstructed.yaml holds Table 4")
}

/// A linear sweep from 0.2·ω₁ to midway between modes k and k + 1.
fn sweep(truth: &ModalResult, k: usize, n: usize) -> Vec<f64> {
    let lo = 0.2 * truth.modes[0].omega_rad_s;
    let hi = 0.5 * (truth.modes[k - 1].omega_rad_s + truth.modes[k].omega_rad_s);
    (0..n).map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64).collect()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn noise_free_sweep_gives_the_model_modes() {
    let beam = paper_beam();
    let truth = modal(&beam, 6).unwrap();
    let all = modal(&beam, 40).unwrap();
    println!(
        "{} mesh modes up to {:e} rad/s, relaxation poles {:e} … {:e} rad/s",
        all.modes.len(),
        all.modes.last().unwrap().omega_rad_s,
        all.real_poles_rad_s.first().unwrap(),
        all.real_poles_rad_s.last().unwrap()
    );
    let w = sweep(&truth, 5, 4000);
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let id = identify(&Measurement::Complex { omega_rad_s: w, h_m_per_n: h }, &IdentifySettings::default()).unwrap();
    assert_eq!(id.modes.len(), 5, "all five modes of the band, nothing else");
    for (m, t) in id.modes.iter().zip(&truth.modes) {
        let (ew, ez) = (rel(m.omega_rad_s, t.omega_rad_s), rel(m.zeta, t.zeta));
        println!("mode {}: omega rel err {ew:.2e}, zeta rel err {ez:.2e}", t.mode);
        // 1e-6 relative for both (the target). What remains is the
        // truncation of the background model (≤ 3 real poles for the 40
        // relaxation poles of the mesh, 2 poles plus a quadratic for the modes
        // above the band): measured ≤ 3.4e-7 on ζ₅, ≤ 5e-9 on ω.
        assert!(ew < 1e-6, "mode {} omega off by {ew:e}", t.mode);
        assert!(ez < 1e-6, "mode {} zeta off by {ez:e}", t.mode);
    }
}

/// Complex Gaussian noise of sd `sd` per component.
fn noisy(h: &[Complex64], sd: f64, replicate: u64) -> Vec<Complex64> {
    let mut rng = stream(12, Purpose::MeasurementNoise, [1200, replicate]);
    h.iter()
        .map(|z| {
            let (a, b): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
            z + Complex64::new(a * sd, b * sd)
        })
        .collect()
}

fn within(m: &IdentifiedMode, omega: f64, zeta: f64, k: f64) -> [bool; 2] {
    [(m.omega_rad_s - omega).abs() <= k * m.omega_sd_rad_s, (m.zeta - zeta).abs() <= k * m.zeta_sd]
}

/// Noise seeds of a coverage test: `default`, or `IDENTIFY_SEEDS` (≥ 200 is the bar).
fn seeds(default: u64) -> u64 {
    std::env::var("IDENTIFY_SEEDS").ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

/// Runs `run(seed)` for every seed of `seeds(n_default)` and checks that the 95 % intervals of the
/// three modes' ω and ζ cover the truth at 95 %. Binomial Monte Carlo error
/// of a coverage rate over n = 200 seeds: sd = sqrt(0.95·0.05/200) = 0.0154;
/// each observable must lie within 3 sd (0.046) of 0.95, the pooled rate
/// (1200 intervals, modes fitted jointly but nearly uncorrelated) within
/// 3·sqrt(0.95·0.05/1200) = 0.019 (for n seeds: 3·sqrt(0.0475/n) and
/// 3·sqrt(0.0475/6n)).
fn assert_coverage(what: &str, truth: &ModalResult, n_default: u64, run: impl Fn(u64) -> Option<Vec<IdentifiedMode>>) {
    let n = seeds(n_default);
    let mut failed = 0;
    let mut hits = [0usize; 6];
    let mut z_sum = [0.0f64; 6];
    let mut z_sq = [0.0f64; 6];
    let t0 = std::time::Instant::now();
    for seed in 0..n {
        // a record whose three modes are not identified gives no interval:
        // counted as six misses
        let Some(modes) = run(seed) else {
            failed += 1;
            continue;
        };
        assert_eq!(modes.len(), 3, "{what}, seed {seed}: three modes");
        for (r, (m, t)) in modes.iter().zip(&truth.modes).enumerate() {
            let [a, b] = within(m, t.omega_rad_s, t.zeta, 1.959964);
            hits[2 * r] += usize::from(a);
            hits[2 * r + 1] += usize::from(b);
            let z = [(m.omega_rad_s - t.omega_rad_s) / m.omega_sd_rad_s, (m.zeta - t.zeta) / m.zeta_sd];
            for j in 0..2 {
                z_sum[2 * r + j] += z[j];
                z_sq[2 * r + j] += z[j] * z[j];
            }
        }
    }
    let mc_sd = (0.95f64 * 0.05 / n as f64).sqrt();
    let names = ["omega_1", "zeta_1", "omega_2", "zeta_2", "omega_3", "zeta_3"];
    let mut bad = Vec::new();
    for (i, (name, &k)) in names.iter().zip(&hits).enumerate() {
        let rate = k as f64 / n as f64;
        let mean = z_sum[i] / n as f64;
        let sd = (z_sq[i] / n as f64 - mean * mean).sqrt();
        println!("{what} {name}: coverage {rate:.3} ({k}/{n}), mean z {mean:.3}, sd z {sd:.3}");
        if (rate - 0.95).abs() > 3.0 * mc_sd {
            bad.push(format!("{name} covers {rate:.3}"));
        }
    }
    let pooled = hits.iter().sum::<usize>() as f64 / (6 * n) as f64;
    println!(
        "{what}: pooled coverage {pooled:.4}, {failed} records without three modes ({:.1} s)",
        t0.elapsed().as_secs_f64()
    );
    assert!(bad.is_empty(), "{what}: {bad:?}");
    assert!((pooled - 0.95).abs() <= 3.0 * (0.95f64 * 0.05 / (6 * n) as f64).sqrt(), "{what}: pooled {pooled}");
}

#[test]
fn intervals_cover_the_truth_at_their_level() {
    // 3 modes, 600-point sweep, complex noise of 0.2 % of max|H| per component.
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let w = sweep(&truth, 3, 600);
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let sd = 2e-3 * h.iter().map(|z| z.norm()).fold(0.0, f64::max);
    assert_coverage("sweep", &truth, 200, |seed| {
        let data = Measurement::Complex { omega_rad_s: w.clone(), h_m_per_n: noisy(&h, sd, seed) };
        identify(&data, &IdentifySettings { modes: Some(3), max_order: 24 }).ok().map(|id| id.modes)
    });
}

#[test]
fn ring_down_intervals_cover_the_truth_at_their_level() {
    // 600-sample lab ring-downs (see `lab_ring_down`), noise 0.1 % of the peak.
    let (t, y0, truth) = paper_ring_down(600, 0);
    let sd = 1e-3 * y0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let clean = paper_ring_down_clean(600);
    assert_coverage("ring-down", &truth, 200, |seed| {
        let mut rng = stream(12, Purpose::MeasurementNoise, [1203, seed]);
        let y = clean.iter().map(|v| v + sd * Distribution::<f64>::sample(&StandardNormal, &mut rng)).collect();
        let data = Measurement::Time { time_s: t.clone(), displacement_m: y };
        identify(&data, &IdentifySettings { modes: Some(3), max_order: 24 }).ok().map(|id| id.modes)
    });
}

/// Thermal-noise PSD: |H|²·S_F (white force), a Welch average of ν = 20
/// periodograms: each bin is |H|²·S_F·χ²₄₀/40 = |H|²·S_F·Gamma(20, 1/20).
fn noisy_psd(h: &[Complex64], seed: u64) -> Vec<f64> {
    let mut rng = stream(12, Purpose::MeasurementNoise, [1201, seed]);
    let gamma = Gamma::new(20.0, 1.0 / 20.0).unwrap();
    h.iter().map(|z| z.norm_sqr() * 1e-20 * gamma.sample(&mut rng)).collect()
}

#[test]
// Measured 2026-11-24 (seed 0): omega_1 1.12 sd, zeta_1 1.34 sd from the
// truth, nu_hat 20.87 (was zeta_1 3.02 sd and ignored: 0 real poles chosen by
// the BIC, mode 1 biased; see identify::likelihood_ratio_selection).
fn noisy_psd_recovers_the_modes_within_their_sd() {
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let w = sweep(&truth, 3, 1500);
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let data = Measurement::Psd { omega_rad_s: w, psd_m2_s_per_rad: noisy_psd(&h, 0) };
    let id = identify(&data, &IdentifySettings::default()).unwrap();
    // the estimated number of averages: 1/ν̂ = noise_sd², ν = 20; its sd
    // over m ≈ 1500 bins is ≈ ν·sqrt(2/m)·(1 + 3/ν)^½ ≈ 0.8, so 20 ± 4
    let nu = 1.0 / (id.noise_sd * id.noise_sd);
    println!("psd: estimated averages {nu:.2}");
    assert!((nu - 20.0).abs() < 4.0, "averages {nu}");
    check_three_modes(&id.modes, &truth, "psd");
}

#[test]
fn psd_intervals_cover_the_truth_at_their_level() {
    // 1500-bin Welch PSDs (ν = 20) over modes 1–3 (with 600 bins of this
    // noise the stabilisation diagram holds only 1–2 of the three modes).
    // Measured 2026-11-24 with IDENTIFY_SEEDS=200 (1445 s at load 3.6–4.6 on
    // 2 cores): omega_1 0.950 (mean z +0.10, sd z 0.99), zeta_1 0.930 (−0.04,
    // 1.01), omega_2 0.945, zeta_2 0.965, omega_3 0.955, zeta_3 0.970, pooled
    // 0.9525, 0 records without three modes: all within the 200-seed bars
    // (0.046, pooled 0.019). CI runs 30 seeds (117 s at load 2.2–2.4, pooled
    // 0.972, omega_1 and zeta_1 29/30): each observable
    // within 3·sqrt(0.0475/30) = 0.119 of 0.95, pooled (180 intervals) within
    // 3·sqrt(0.0475/180) = 0.049.
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let w = sweep(&truth, 3, 1500);
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    assert_coverage("psd", &truth, 30, |seed| {
        let data = Measurement::Psd { omega_rad_s: w.clone(), psd_m2_s_per_rad: noisy_psd(&h, 100 + seed) };
        identify(&data, &IdentifySettings { modes: Some(3), ..IdentifySettings::default() }).ok().map(|id| id.modes)
    });
}

#[test]
#[ignore = "not in CI (its 2-core budget): measured 2026-11-24 with IDENTIFY_SEEDS=60 (167 s, quiet 2-core machine): pooled 0.956, omega_1 0.933 (mean z +0.28, sd z 2.28: an outlying record), zeta_1 0.950, omega_2 0.933, zeta_2 0.967, omega_3 0.983, zeta_3 0.967, 0 records without three modes; all within the 60-seed bars (3 sqrt(0.0475/60) = 0.084 per observable, 0.034 pooled). 200 seeds not run"]
fn magnitude_intervals_cover_the_truth_at_their_level() {
    // |H| only (the sweep's noise, 0.1 % of max|H| per component, then the
    // modulus) over modes 1–3, 1500 points: the joint-LM path the PSD takes,
    // with the Gaussian likelihood and the same real-pole selection.
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let w = sweep(&truth, 3, 1500);
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let sd = 1e-3 * h.iter().map(|z| z.norm()).fold(0.0, f64::max);
    assert_coverage("magnitude", &truth, 200, |seed| {
        let abs: Vec<f64> = noisy(&h, sd, 500 + seed).iter().map(|z| z.norm()).collect();
        let data = Measurement::Magnitude { omega_rad_s: w.clone(), h_abs_m_per_n: abs };
        identify(&data, &IdentifySettings { modes: Some(3), ..IdentifySettings::default() }).ok().map(|id| id.modes)
    });
}

#[test]
fn noisy_magnitude_sweep_recovers_the_modes_within_their_sd() {
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let w = sweep(&truth, 3, 1500);
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let sd = 1e-3 * h.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let abs: Vec<f64> = noisy(&h, sd, 7).iter().map(|z| z.norm()).collect();
    // --modes 3: with the default residue-SNR filter one of the three is
    // currently dropped on magnitude-only data (its residue's sd is inflated
    // by the phase that |H| does not fix).
    let settings = IdentifySettings { modes: Some(3), ..IdentifySettings::default() };
    let id = identify(&Measurement::Magnitude { omega_rad_s: w, h_abs_m_per_n: abs }, &settings).unwrap();
    check_three_modes(&id.modes, &truth, "magnitude");
}

/// A ring-down as a lab records it: the model's impulse response
/// (`beam::impulse_response`, exact state-space stepping) at q = 16 times the
/// target rate, an anti-alias low-pass (Blackman-windowed sinc FIR, cut-off
/// `cutoff` rad/s, length 32q + 1: transition half-width ≈ 5.5π/(L·Δt_fine)
/// ≈ 0.17·Nyquist, stop band ≤ −74 dB), decimation by q, and the first L
/// fine samples dropped (the FIR's start-up, where the output is not yet a
/// sum of exponentials). After that transient the record is exactly
/// Σ G(p)·R·e^{p t} over the beam's poles p: the filter rescales residues, it
/// leaves the poles (ω, ζ) alone, and modes above Nyquist are attenuated
/// below the noise instead of folding onto the band.
fn lab_ring_down(beam: &BeamSpec, nyquist: f64, cutoff: f64, n: usize) -> (Vec<f64>, Vec<f64>) {
    const Q: usize = 16;
    let len = 32 * Q + 1;
    let dt = std::f64::consts::PI / nyquist;
    let dtf = dt / Q as f64;
    let fine = impulse_response(beam, 3.6, 6.8, dtf, n * Q + len).unwrap();
    let c = (len - 1) as f64 / 2.0;
    let taps: Vec<f64> = (0..len)
        .map(|j| {
            let x = j as f64 - c;
            let sinc = if x == 0.0 {
                cutoff * dtf / std::f64::consts::PI
            } else {
                (cutoff * dtf * x).sin() / (std::f64::consts::PI * x)
            };
            let a = 2.0 * std::f64::consts::PI * j as f64 / (len - 1) as f64;
            sinc * (0.42 - 0.5 * a.cos() + 0.08 * (2.0 * a).cos())
        })
        .collect();
    let y = (0..n).map(|k| (0..len).map(|j| taps[j] * fine[k * Q + len - 1 - j]).sum()).collect();
    let t = (0..n).map(|k| k as f64 * dt).collect();
    (t, y)
}

fn paper_ring_down_clean(n: usize) -> Vec<f64> {
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let nyquist = 1.25 * truth.modes[2].omega_rad_s;
    let cutoff = 0.5 * (truth.modes[2].omega_rad_s + truth.modes[3].omega_rad_s);
    lab_ring_down(&beam, nyquist, cutoff, n).1
}

/// The paper's beam rung down with Nyquist 1.25·ω₃ (modes 1–3 in the band,
/// mode 4 at 1.44·ω₃ in the filter's stop band), n samples, noise sd 0.1 %
/// of the peak.
fn paper_ring_down(n: usize, replicate: u64) -> (Vec<f64>, Vec<f64>, ModalResult) {
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let y = paper_ring_down_clean(n);
    let t = (0..n).map(|k| k as f64 * std::f64::consts::PI / (1.25 * truth.modes[2].omega_rad_s)).collect();
    let sd = 1e-3 * y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut rng = stream(12, Purpose::MeasurementNoise, [1202, replicate]);
    let y = y.iter().map(|v| v + sd * Distribution::<f64>::sample(&StandardNormal, &mut rng)).collect();
    (t, y, truth)
}

#[test]
fn noisy_ring_down_recovers_the_modes_within_their_sd() {
    let (t, y, truth) = paper_ring_down(1500, 0);
    let id = identify(&Measurement::Time { time_s: t, displacement_m: y }, &IdentifySettings::default()).unwrap();
    for m in &id.background_modes {
        println!("ring-down background: omega {:e}, zeta {:.5}, snr {:.1}", m.omega_rad_s, m.zeta, m.amplitude_snr);
    }
    check_three_modes(&id.modes, &truth, "ring-down");
}

/// The three modes within 3σ (a two-sided 3σ miss has probability 0.27 %).
fn check_three_modes(modes: &[IdentifiedMode], truth: &ModalResult, what: &str) {
    for m in modes {
        println!(
            "{what}: omega {:e} ± {:.2e}, zeta {:.5} ± {:.2e}",
            m.omega_rad_s, m.omega_sd_rad_s, m.zeta, m.zeta_sd
        );
    }
    assert_eq!(modes.len(), 3, "{what}: three modes");
    for (m, t) in modes.iter().zip(&truth.modes) {
        let [a, b] = within(m, t.omega_rad_s, t.zeta, 3.0);
        assert!(
            a && b,
            "{what}: mode {} ({:e}, {}) vs truth ({:e}, {})",
            t.mode,
            m.omega_rad_s,
            m.zeta,
            t.omega_rad_s,
            t.zeta
        );
    }
}

/// Each reported mode is near a distinct true mode and every ω and ζ lies
/// within 4 of its reported sd: a two-sided 4-sd miss has probability
/// 6.3e-5 under a correct sd, so the 18–24 intervals of three or four
/// records fail falsely with probability ≤ 1.5e-3.
fn check_three_modes_of(
    records: impl Iterator<Item = (u64, Result<Vec<IdentifiedMode>, String>)>,
    truth: &ModalResult,
    what: &str,
) {
    let mut bad = Vec::new();
    for (seed, modes) in records {
        let modes = match modes {
            Ok(m) => m,
            Err(e) => {
                bad.push(format!("seed {seed}: {e}"));
                continue;
            }
        };
        if modes.len() != 3 {
            bad.push(format!("seed {seed}: {} modes", modes.len()));
            continue;
        }
        for (m, t) in modes.iter().zip(&truth.modes) {
            let z = [(m.omega_rad_s - t.omega_rad_s) / m.omega_sd_rad_s, (m.zeta - t.zeta) / m.zeta_sd];
            println!("{what} seed {seed} mode {}: z omega {:.2}, z zeta {:.2}", t.mode, z[0], z[1]);
            if !(z[0].abs() <= 4.0 && z[1].abs() <= 4.0) {
                bad.push(format!("seed {seed} mode {}: z {z:?}", t.mode));
            }
        }
    }
    assert!(bad.is_empty(), "{what}: {bad:?}");
}

/// Issue 44 defect 3: a PSD made as the README says (an `frf` sweep of the
/// paper's beam, 1 500 bins, ν = 20 Welch averages), three seeds, run as a
/// user runs it (no `--modes`): each keeps its three modes. Before the
/// peak-SNR filter one seed of three reported none.
#[test]
fn readme_psd_recipe_keeps_its_three_modes() {
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let w = sweep(&truth, 3, 1500);
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let records = (0..3).map(|seed| {
        let data = Measurement::Psd { omega_rad_s: w.clone(), psd_m2_s_per_rad: noisy_psd(&h, 4400 + seed) };
        (seed, identify(&data, &IdentifySettings::default()).map(|id| id.modes).map_err(|e| e.to_string()))
    });
    check_three_modes_of(records, &truth, "readme psd");
}

/// Issue 44 defect 4: a ring-down of three modes (the paper's beam behind the
/// anti-alias filter of `lab_ring_down`), 0.1 % noise, 3 000 samples: each
/// record identifies exactly its three modes. Of noise seeds 0–39, seeds 8
/// and 11 exited 1 "did not converge" (a noise pole of the diagram grew in
/// every candidate) and seed 35 reported a fourth mode with ζ ≈ 1; seed 0 is
/// a record that always passed.
#[test]
fn three_mode_ring_down_of_3000_samples_converges() {
    let truth = modal(&paper_beam(), 4).unwrap();
    let records = [0, 8, 11, 35].into_iter().map(|seed| {
        let (t, y, _) = paper_ring_down(3000, seed);
        let data = Measurement::Time { time_s: t, displacement_m: y };
        (seed, identify(&data, &IdentifySettings::default()).map(|id| id.modes).map_err(|e| e.to_string()))
    });
    check_three_modes_of(records, &truth, "ring-down 3000");
}

/// A (nearly) noise-free ring-down of the paper's beam (the anti-aliased
/// record of `paper_ring_down` with noise sd `fraction` of its peak;
/// generator: the crate's beam `impulse_response` behind this file's FIR
/// filter) gives its three modes only, each within 3 reported sd of the FE
/// model's. Noise-free, 5 poles fitting the filter's start-up at 10⁻⁷–3·10⁻⁵
/// of the peak were reported as modes before
/// `identify::MIN_RELATIVE_AMPLITUDE`.
fn clean_ring_down_gives_its_three_modes(fraction: f64) {
    let beam = paper_beam();
    let truth = modal(&beam, 4).unwrap();
    let n = 1500;
    let y = paper_ring_down_clean(n);
    let sd = fraction * y.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut rng = stream(12, Purpose::MeasurementNoise, [1203, 0]);
    let y: Vec<f64> = y.iter().map(|v| v + sd * Distribution::<f64>::sample(&StandardNormal, &mut rng)).collect();
    let t = (0..n).map(|k| k as f64 * std::f64::consts::PI / (1.25 * truth.modes[2].omega_rad_s)).collect();
    let id = identify(&Measurement::Time { time_s: t, displacement_m: y }, &IdentifySettings::default()).unwrap();
    for m in &id.background_modes {
        println!("background: omega {:e}, zeta {:.5}, snr {:.1}", m.omega_rad_s, m.zeta, m.amplitude_snr);
    }
    check_three_modes(&id.modes, &truth, "clean ring-down");
}

/// Noise sd 10⁻⁷ of the peak (about a 24-bit converter's quantisation):
/// 2 s. (At 10⁻⁹ mode 3 lies 10 reported sd from the FE model's ω: the
/// filter's start-up then outweighs the noise.)
#[test]
fn nearly_noise_free_ring_down_gives_its_three_modes() {
    clean_ring_down_gives_its_three_modes(1e-7);
}

/// Exactly noise-free: 17 s (the real-pole forward selection fits every
/// candidate, the BIC falling all the way), so not in CI.
#[test]
#[ignore = "17 s: the noise-free twin of nearly_noise_free_ring_down_gives_its_three_modes"]
fn noise_free_ring_down_gives_its_three_modes() {
    clean_ring_down_gives_its_three_modes(0.0);
}
