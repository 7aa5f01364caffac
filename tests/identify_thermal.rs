//! Thermal-motion records (`time_s,thermal_<name>_m,…`) read into the PSD
//! record by `identify::data` (Welch, `src/identify/thermal.rs`).
//!
//! Generator: a second-order autoregressive process x_k = φ1 x_{k−1} +
//! φ2 x_{k−2} + e_k (a sampled damped oscillator driven by white noise),
//! seeded ChaCha8 Gaussian noise (plus independent white noise for the band
//! test), written here. References independent of the
//! code under test: the AR(2) variance and autocorrelation in closed form
//! (Box & Jenkins, *Time Series Analysis*, §3.2.4), its spectral peak
//! cos ωΔt = φ1(φ2 − 1)/(4φ2), and Bartlett's formula for the standard error
//! of a sample variance.
//!
//! The MD test (`identify_on_the_cc7_md_record_finds_six_modes_numbered_1_to_6`)
//! reads the committed LAMMPS record `data/md/cc7.langevin.csv.gz` (made by
//! LAMMPS, `data/md/README.md`); its reference is the PSD peak list of
//! `docs/md.md` §4, read off a Welch estimate by `data/md/psd.py` (numpy), not
//! by `identify`.

use nanobeam::identify::data::Measurement;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

const DT: f64 = 2e-14;

/// AR(2) with poles at r·e^{±iθ}: (φ1, φ2).
fn ar2(r: f64, theta: f64) -> (f64, f64) {
    (2.0 * r * theta.cos(), -r * r)
}

fn series(phi: (f64, f64), n: usize, seed: u64) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (mut a, mut b) = (0.0, 0.0);
    // 20 000 samples of burn-in: the start's transient decays as r^k (r^20000 < 1e-80 at r = 0.99)
    (0..n + 20_000)
        .map(|_| {
            let e: f64 = StandardNormal.sample(&mut rng);
            let x = phi.0 * a + phi.1 * b + 1e-12 * e;
            b = a;
            a = x;
            x
        })
        .skip(20_000)
        .collect()
}

fn csv(columns: &[Vec<f64>]) -> String {
    let mut s = String::from("time_s");
    for i in 0..columns.len() {
        s.push_str(&format!(",thermal_c{i}_m"));
    }
    s.push('\n');
    for k in 0..columns[0].len() {
        s.push_str(&format!("{:.9e}", k as f64 * DT));
        for c in columns {
            s.push_str(&format!(",{:.9e}", c[k]));
        }
        s.push('\n');
    }
    s
}

fn psd(text: &str) -> (Vec<f64>, Vec<f64>) {
    match Measurement::from_csv(text).unwrap() {
        Measurement::Psd { omega_rad_s, psd_m2_s_per_rad } => (omega_rad_s, psd_m2_s_per_rad),
        other => panic!("not a PSD record: {other:?}"),
    }
}

/// ∫S dω over the one-sided PSD is the variance (γ0 of the AR(2), closed
/// form), and the PSD peaks at the AR(2) spectral peak.
#[test]
fn welch_psd_of_two_columns_has_the_variance_and_the_peak_of_the_process() {
    let (r, theta) = (0.99, 0.3);
    let phi = ar2(r, theta);
    let n = 1 << 15;
    let cols = [series(phi, n, 1), series(phi, n, 2)];
    let (omega, s) = psd(&csv(&cols));
    let d_omega = omega[1] - omega[0];
    let total: f64 = s.iter().sum::<f64>() * d_omega;
    // γ0 = (1 − φ2) σ² / ((1 + φ2)((1 − φ2)² − φ1²)), σ = 1e-12
    let sigma2 = 1e-24;
    let gamma0 = (1.0 - phi.1) * sigma2 / ((1.0 + phi.1) * ((1.0 - phi.1).powi(2) - phi.0 * phi.0));
    // Bartlett: var(sample variance)/γ0² ≈ (2/N) Σ_{k∈ℤ} ρ_k², ρ from the AR(2) recursion;
    // two independent columns of N samples each → N_total = 2N. The Hann-weighted Welch average
    // uses the samples less evenly (effective count ≈ N·(Σw)²/(nΣw²) ≈ 0.9N with 50 % overlap);
    // 5 standard errors on that count bound a false failure at < 1e-6.
    let mut rho = vec![1.0, phi.0 / (1.0 - phi.1)];
    for k in 2..5000 {
        let next = phi.0 * rho[k - 1] + phi.1 * rho[k - 2];
        rho.push(next);
    }
    let sum_rho2 = 2.0 * rho.iter().map(|p| p * p).sum::<f64>() - 1.0;
    let se = (2.0 * sum_rho2 / (0.9 * 2.0 * n as f64)).sqrt();
    assert!((total / gamma0 - 1.0).abs() < 5.0 * se, "∫S dω = {total:e}, γ0 = {gamma0:e}, se {se:.3}");
    // peak: cos(ωΔt) = φ1(φ2 − 1)/(4φ2); the PSD's argmax may sit anywhere within the line's
    // top, whose half-power half-width is ≈ (1 − r)/Δt: that is the tolerance
    let w_peak = (phi.0 * (phi.1 - 1.0) / (4.0 * phi.1)).acos() / DT;
    let k = (0..s.len()).max_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap();
    assert!((omega[k] - w_peak).abs() < (1.0 - r) / DT, "argmax {:e} vs {w_peak:e}", omega[k]);
    // the chosen segment resolves the line: half-power width 2(1 − r)/Δt spans ≥ 4 bins
    // (thermal::MIN_LINE_BINS), and not by a factor 2 more than needed (the segment is the
    // shortest that keeps it so; the width's estimate may sit ±25 % off the true one)
    let bins = 2.0 * (1.0 - r) / DT / d_omega;
    assert!((4.0..=2.0 * 4.0 * 1.25).contains(&bins), "line spans {bins} bins of {d_omega:e}");
}

/// A line narrower than the finest resolution (a sinusoid: no width at
/// all) is refused, and the message names a longer record.
#[test]
fn an_unresolved_line_is_refused_naming_the_record_length() {
    let n = 1 << 12;
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let col: Vec<f64> = (0..n)
        .map(|k| {
            let e: f64 = StandardNormal.sample(&mut rng);
            1e-11 * (0.7 * k as f64).sin() + 1e-15 * e
        })
        .collect();
    let e = Measurement::from_csv(&csv(&[col])).unwrap_err().to_string();
    assert!(e.starts_with("invalid time_s (the record's length) = "), "{e}");
    assert!(e.contains(" s: allowed at least "), "{e}");
    assert!(!e.contains('\n'));
}

/// Langevin records of a clamped–clamped tube as the MD records are made, from
/// a generator written here: each plane's modal coordinate of every line is
/// the sampled damped oscillator (an AR(2) with the poles
/// e^{(−γ/2 ± iω_d)Δt}, γ = 1/τ, the bath's rate: τ = 5 ps, every line
/// 1/(2πτ) = 31.8 GHz wide at half power), at cc11's eleven identified
/// frequencies (`tests/identify_md.md`, round 3) with the equipartition
/// amplitude ∝ 1/ω; three slices (x/L = 0.5, 0.3, 0.15, shapes sin(nπx/L))
/// see the same coordinates, two planes independent ones. 12 618 samples of
/// 20 fs, as `cc11.langevin.csv.gz`: 2 Welch segments of 8 192 samples per
/// column, bins of 6.1 GHz, so every line spans 5.2 bins and is resolved.
fn langevin_tube(seed: u64) -> Vec<Vec<f64>> {
    const CC11_GHZ: [f64; 11] = [133.1, 352.5, 651.0, 1006.2, 1400.4, 1823.5, 2253.3, 2699.6, 3145.6, 3590.9, 4040.2];
    langevin_tube_of(&CC11_GHZ, 12_618, seed)
}

/// `langevin_tube` with the lines `freqs_ghz` and `n` samples.
fn langevin_tube_of(freqs_ghz: &[f64], n: usize, seed: u64) -> Vec<Vec<f64>> {
    let gamma = 1.0 / 5e-12;
    let mut cols = vec![vec![0.0; n]; 6];
    for (k, f) in freqs_ghz.iter().enumerate() {
        let w = 2.0 * std::f64::consts::PI * f * 1e9;
        let phi = ar2((-0.5 * gamma * DT).exp(), (w * w - 0.25 * gamma * gamma).sqrt() * DT);
        // γ0 of the AR(2) with innovations of sd 1e-12 (as in the first test): unit variance, then 1/ω
        let gamma0 = (1.0 - phi.1) * 1e-24 / ((1.0 + phi.1) * ((1.0 - phi.1).powi(2) - phi.0 * phi.0));
        let amplitude = 1e-11 * (2.0 * std::f64::consts::PI * freqs_ghz[0] * 1e9 / w) / gamma0.sqrt();
        for plane in 0..2 {
            let q = series(phi, n, 1000 * seed + 10 * k as u64 + plane as u64);
            for (slice, x) in [0.5, 0.3, 0.15].iter().enumerate() {
                let shape = ((k + 1) as f64 * std::f64::consts::PI * x).sin();
                for (c, v) in cols[2 * slice + plane].iter_mut().zip(&q) {
                    *c += amplitude * shape * v;
                }
            }
        }
    }
    cols
}

/// A resolved Langevin record is not refused for its line width. Before
/// `thermal::UNRESOLVED_LINE_BINS` the check refused at a measured 4 bins,
/// and most of these records were refused although every line spans 5.2
/// bins (a numpy port of the check on 60 records of this kind: narrowest
/// line under 4 bins in 37, the least 3.43; the same port put the old
/// refusal on 7 of the first 10).
#[test]
fn resolved_langevin_tube_records_are_not_refused_for_their_line_width() {
    for seed in 0..20 {
        let text = csv(&langevin_tube(seed));
        if let Err(e) = Measurement::from_csv(&text) {
            panic!("seed {seed}: {e}");
        }
    }
}

/// Issue 69, defect 8: one column of a Langevin tube record is handed on at
/// segments that resolve its lines. `langevin_tube_of` at cc7's length
/// (17 503 samples of 20 fs) and lines (its PSD peaks, `docs/md.md` §4: 305,
/// 751, 1318, 1953, 2612, 3308 GHz), one column at a time (x/L = 0.5 and 0.3, y):
/// every line is 1/(2πτ) = 31.8 GHz wide at half power (τ = 5 ps), and
/// `identify` needs ≥ 3 (`MIN_POINTS_PER_RESONANCE`) bins in each half-power
/// band, so the bins must be ≤ 31.8/3 = 10.6 GHz. Before, one column had to
/// average 8 segments alone (`thermal::MIN_AVERAGES`): 2 048 samples, bins of
/// 24.4 GHz, 1.3 bins a line. Now the finest segment of ≥ 3 averages
/// (`thermal::FIT_AVERAGES`): 8 192 samples, 6.1 GHz, 5.2 bins. The bound
/// is the width in bins, not the segment, and holds for any segment the
/// choice may take that resolves the lines. Welch only, well under a second.
#[test]
fn one_column_of_a_langevin_tube_record_resolves_its_lines() {
    let line_rad_s = 1.0 / 5e-12;
    for seed in 0..3 {
        let cols = langevin_tube_of(&[305.0, 751.0, 1318.0, 1953.0, 2612.0, 3308.0], 17_503, 50 + seed);
        for c in [0, 2] {
            let (omega, _) = psd(&csv(std::slice::from_ref(&cols[c])));
            let bins = line_rad_s / (omega[1] - omega[0]);
            assert!(bins >= 3.0, "seed {seed}, column {c}: a line spans {bins:.2} bins");
        }
    }
}

/// Issue 69, defect 8, on the committed cc7 MD record (made by LAMMPS; its
/// lines are the PSD peaks of `docs/md.md` §4, read by numpy, not by
/// `identify`): one displacement column gives the lines that column shows.
/// `thermal_slice2_y_m` (x/L = 0.3, where no mode of 1–5 has a node): the
/// modes at the first five peaks; `thermal_slice1_y_m` (mid-span, a node of
/// every even mode): the lines at the peaks of modes 1, 3 and 5, three
/// lines. Identified through the library, unnumbered: the mid-span column's
/// numbering (1, 3, 5 against 1, 3, 7 within the prior) needs a shape scan,
/// the numbering's business. Before: slice 2 gave one line, 2.174e12 rad/s
/// with ζ = 0.41 ± 0.30, and mid-span was refused ("157 samples with no stable
/// resonance"). Tolerance: that of the six-mode cc7 test (the bath's
/// half-power half-width 15.9 GHz plus half a 6.1-GHz bin of the reference).
/// Two identifications, about 4 s each in the debug build.
#[test]
fn one_column_of_the_cc7_md_record_gives_the_lines_it_shows() {
    use nanobeam::identify::{identify, IdentifySettings};
    let column = cc7_column;
    for (name, peaks_ghz) in [
        ("thermal_slice2_y_m", &[305.0, 751.0, 1318.0, 1953.0, 2612.0][..]),
        ("thermal_slice1_y_m", &[305.0, 1318.0, 2612.0][..]),
    ] {
        let record = Measurement::from_csv(&column(name)).unwrap();
        let modes = identify(&record, &IdentifySettings::default()).unwrap_or_else(|e| panic!("{name}: {e}")).modes;
        let f_ghz: Vec<f64> = modes.iter().map(|m| m.omega_rad_s / (2.0 * std::f64::consts::PI) / 1e9).collect();
        assert_eq!(f_ghz.len(), peaks_ghz.len(), "{name}: {f_ghz:.1?} GHz");
        for (f, peak) in f_ghz.iter().zip(peaks_ghz) {
            assert!((f - peak).abs() < 15.9 + 3.05, "{name}: {f:.1} GHz vs the PSD peak {peak} GHz ({f_ghz:.1?})");
        }
    }
}

/// The column `name` of the committed cc7 MD record as a one-column
/// thermal record (`time_s,NAME`).
fn cc7_column(name: &str) -> String {
    use std::io::Read;
    let path = format!("{}/data/md/cc7.langevin.csv.gz", env!("CARGO_MANIFEST_DIR"));
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap()).read_to_string(&mut text).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let k = header.iter().position(|h| *h == name).unwrap();
    let rows = lines.map(|l| {
        let v: Vec<&str> = l.split(',').collect();
        format!("{},{}\n", v[0], v[k])
    });
    format!("time_s,{name}\n{}", rows.collect::<String>())
}

/// Issue 69, defect 8, slice 3: the column of the committed cc7 MD record
/// nearest a clamp (`thermal_slice3_y_m`, x/L = 0.15), whose strongest line
/// is mode 2 (mode 1's shape is small there), hands on the flexural band the
/// six-column record does: the band's top lies above the sixth line and
/// below the seventh of the numpy peak list (`docs/md.md` §3 and §4: 3308
/// and 3979 GHz, not `identify`'s), each by the bath's half-power half-width
/// 1/(4πτ) = 15.9 GHz, so every line the six-column record hands on is in it
/// and none above (where the lines of modes 7, 8, … sit on the record's
/// non-flexural motion). Before, the band search started 8× above the
/// strongest line (6 THz, past the flexural band), found no flat floor, and
/// handed on all 4 096 bins, to 25 THz. Welch only, about a second.
#[test]
fn the_cc7_column_near_a_clamp_hands_on_its_flexural_band() {
    let (omega, _) = psd(&cc7_column("thermal_slice3_y_m"));
    let top_ghz = omega.last().unwrap() / (2.0 * std::f64::consts::PI) / 1e9;
    assert!((3308.0 + 15.9..3979.0 - 15.9).contains(&top_ghz), "the band ends at {top_ghz:.0} GHz");
}

/// Issue 69, defect 8, slice 3, end to end: `nanobeam identify --beam
/// data/md/tube-cc7.yaml` on the column at x/L = 0.15 alone reports the six
/// lines of the six-column record, numbered 1–6 at the numpy PSD peaks
/// (`docs/md.md` §4), tolerance as the cc7 test's (15.9 + 3.05 GHz, see
/// `assert_numbered_at_the_peaks`). Before: exit 2, "lines from 4.705e12
/// rad/s fit both modes 2-9, 12 and 2-9, 13", 54 s; after, 15 s (dev
/// build), hence ignored.
#[test]
#[ignore = "about 15 s: run with --ignored"]
fn identify_on_the_cc7_column_near_a_clamp_numbers_its_six_lines() {
    let yaml = identify_on_cc7_beam("cc7-slice3", &cc7_column("thermal_slice3_y_m"));
    let modes = yaml["modes"].as_sequence().unwrap();
    let peaks_ghz = [305.0, 751.0, 1318.0, 1953.0, 2612.0, 3308.0];
    assert_eq!(modes.len(), peaks_ghz.len(), "{modes:?}");
    assert_numbered_at_the_peaks(modes, &peaks_ghz);
}

/// A cantilever's Langevin record as `data/md/cl7.langevin.csv.gz` is made,
/// from the generator of `langevin_tube` (AR(2) modal coordinates, written
/// here): five lines at the peaks a numpy Welch estimate of cl7 shows (49,
/// 317, 806, 1404, 2065 GHz), the bath's τ = 5 ps (so the fundamental's
/// Q = ω/γ ≈ 1.5), equipartition amplitudes ∝ 1/ω, the same coordinates seen
/// by three slices with weights 1, 0.6, 0.3 in two independent planes, `n`
/// samples of 20 fs.
fn langevin_cantilever(n: usize, seed: u64) -> Vec<Vec<f64>> {
    const FREQS_GHZ: [f64; 5] = [49.0, 317.0, 806.0, 1404.0, 2065.0];
    let gamma = 1.0 / 5e-12;
    let mut cols = vec![vec![0.0; n]; 6];
    for (k, f) in FREQS_GHZ.iter().enumerate() {
        let w = 2.0 * std::f64::consts::PI * f * 1e9;
        let phi = ar2((-0.5 * gamma * DT).exp(), (w * w - 0.25 * gamma * gamma).sqrt() * DT);
        let gamma0 = (1.0 - phi.1) * 1e-24 / ((1.0 + phi.1) * ((1.0 - phi.1).powi(2) - phi.0 * phi.0));
        let amplitude = 1e-11 * (FREQS_GHZ[0] / f) / gamma0.sqrt();
        for plane in 0..2 {
            let q = series(phi, n, 1000 * seed + 10 * k as u64 + plane as u64);
            for (slice, weight) in [1.0, 0.6, 0.3].iter().enumerate() {
                for (c, v) in cols[2 * slice + plane].iter_mut().zip(&q) {
                    *c += amplitude * weight * v;
                }
            }
        }
    }
    cols
}

/// Issue 67 item 4: a cantilever record whose fundamental the Welch estimate
/// cannot resolve is refused naming the record length it needs at least
/// (before: the committed cl7 record went through the fit and was refused
/// for a pole at 2 572 GHz "narrower than the sampling", its ζ sds
/// up to 1 230). On `langevin_cantilever` records of cl7's 10 001 samples
/// (finest resolution of 8 averages: 12.2-GHz bins; the 49-GHz line of
/// Q ≈ 1.5 reaches below 4 bins at half power, 20.6 GHz by the closed-form
/// Lorentzian) the refusal names `time_s` and a length above 2e-10 s; a
/// record 4 times that long (same generator, new seed: 1.5-GHz bins, the
/// edge at 13.5 bins) is not refused for it. The committed cl7 record
/// (LAMMPS) gets the same refusal. About 1 s in the debug build.
#[test]
fn a_cantilever_record_whose_fundamental_is_unresolved_names_the_length_it_needs() {
    let prefix = "invalid time_s (the record's length) = 2.000e-10 s: allowed at least ";
    for seed in 0..3 {
        let e = Measurement::from_csv(&csv(&langevin_cantilever(10_001, seed))).unwrap_err().to_string();
        assert!(e.starts_with(prefix), "{e}");
        assert!(!e.contains('\n') && e.len() <= 200, "{e}");
        let least_s: f64 = e.split("at least ").nth(1).and_then(|t| t.split(' ').next()).unwrap().parse().unwrap();
        assert!(least_s > 2.0e-10, "{e}");
        let rows = (4.0 * least_s / DT).round() as usize;
        if let Err(e) = Measurement::from_csv(&csv(&langevin_cantilever(rows, 100 + seed))) {
            assert!(!e.to_string().contains("strongest line"), "{rows} rows: {e}");
        }
    }
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_nanobeam"))
        .args(["identify", "--beam", &format!("{root}/data/md/tube-cl7.yaml")])
        .arg(format!("{root}/data/md/cl7.langevin.csv.gz"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.starts_with(prefix), "{stderr}");
}

/// `time_s,displacement_m` stays the free-decay record; a header mixing
/// thermal and other columns is not a thermal record.
#[test]
fn only_thermal_columns_make_a_thermal_record() {
    let phi = ar2(0.99, 0.3);
    let col = series(phi, 4096, 4);
    let free = csv(std::slice::from_ref(&col)).replace("thermal_c0_m", "displacement_m");
    assert!(matches!(Measurement::from_csv(&free).unwrap(), Measurement::Time { .. }));
    let mixed = csv(&[col.clone(), col]).replace("thermal_c1_m", "displacement_m");
    assert!(Measurement::from_csv(&mixed).is_err());
}

/// The committed clamped–clamped MD record of the 7.39 nm tube, untouched:
/// `nanobeam identify` with the nominal beam reports six modes numbered 1–6
/// at the PSD's peaks of `docs/md.md` §4 (305, 751, 1318, 1953, 2612,
/// 3308 GHz). Tolerance: the reference is the argmax bin of a Welch
/// estimate (6.1 GHz bins), which sits anywhere within the line's top: the
/// bath gives every line the half-power half-width 1/(4πτ) = 15.9 GHz
/// (τ = 5 ps, `data/md/README.md`), plus half a bin of the reference's
/// quantisation, 3.05 GHz: 19 GHz. The frequencies' own sd (≤ 8 GHz here) is
/// inside that.
#[test]
fn identify_on_the_cc7_md_record_finds_six_modes_numbered_1_to_6() {
    let modes = identify_md_record("cc7");
    let peaks_ghz = [305.0, 751.0, 1318.0, 1953.0, 2612.0, 3308.0];
    assert_eq!(modes.len(), peaks_ghz.len(), "{modes:?}");
    assert_numbered_at_the_peaks(&modes, &peaks_ghz);
}

/// `--modes K` on the committed cc7 record (made by LAMMPS, not by `identify`;
/// its six lines are the PSD peaks of `docs/md.md` §4, read by numpy): K ≤ 6
/// gives the K lowest, numbered from 1 (K = 3 run); K = 7, more than the six
/// resonances the record holds, exit 2 naming `--modes` and 6. Before (issue 69,
/// defect 7) every K > 6 filled up from a diagram pole of 240 GHz narrower than
/// the bins with ζ sd 37.8, refused under the name `omega_rad_s (identified
/// modes[0])` (and, with split poles 0.2–0.6 noise sd high as modes 7–8, the
/// numbering asked for `--first-mode`; K = 10 fails the same way). Two
/// identifications, about 4 s each in the debug build. Tolerance: that of the
/// six-mode cc7 test below (the bath's half-power half-width plus half a bin).
#[test]
fn modes_k_on_the_cc7_md_record_never_reports_a_background_pole() {
    use nanobeam::identify::{identify, IdentifyError, IdentifySettings};
    use std::io::Read;
    let path = format!("{}/data/md/cc7.langevin.csv.gz", env!("CARGO_MANIFEST_DIR"));
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(path).unwrap()).read_to_string(&mut text).unwrap();
    let record = Measurement::from_csv(&text).unwrap();
    let run = |k: usize| identify(&record, &IdentifySettings { modes: Some(k), ..IdentifySettings::default() });
    let modes = run(3).unwrap().modes;
    let peaks_ghz = [305.0, 751.0, 1318.0];
    assert_eq!(modes.len(), 3, "{modes:?}");
    for (m, peak) in modes.iter().zip(peaks_ghz) {
        let f_ghz = m.omega_rad_s / (2.0 * std::f64::consts::PI) / 1e9;
        assert!((f_ghz - peak).abs() < 15.9 + 3.05, "{f_ghz:.1} GHz vs the PSD peak {peak} GHz");
    }
    match run(7) {
        Err(IdentifyError::Input(e)) => {
            let line = e.to_string();
            assert!(line.starts_with("invalid --modes = 7: allowed <= 6 "), "{line}");
            assert!(!line.contains('\n') && line.len() <= 200, "{line}");
        }
        other => panic!("--modes 7: {other:?}"),
    }
}

/// identify → diagnose on the committed cc7 record, untouched, defaults
/// (issue 43 item 4). The data are LAMMPS's (`data/md/README.md`); the
/// truth is the record's provenance: a Langevin bath, which is exactly
/// viscous damping with c = (mass per length)/τ = 3.20477e-4 kg/(m·s)
/// (`data/md/cc7.langevin.provenance.yaml`), shear deformation (a tube's
/// short half-wavelengths), and no point mass, spring, axial force of
/// consequence (the clamps measure −0.84 nN, about 2 % of the clamped
/// Euler load 4π²EI/L² = 38 nN at the nominal section) or
/// second relaxation. Expected: shear deformation and viscous damping
/// decided, none of the others decided, and the bath's c inside the
/// selected model's 95 % interval. About 3 min of CPU in the release build
/// (the pairs, then the selected pair's extensions by a third cause,
/// `diagnose::search`), hence ignored in CI; the measured runs are in
/// `tests/identify_md.md`, rounds 5 and 6.
#[test]
#[ignore = "about 3 min in the release build: run with --release --ignored"]
fn identify_then_diagnose_on_the_cc7_md_record_names_shear_and_the_bath() {
    let selected = diagnose_md_record("cc7");
    let ci = selected["posterior"]["viscous_damping_n_s_m2"]["ci95"].as_array().unwrap();
    let (lo, hi) = (ci[0].as_f64().unwrap(), ci[1].as_f64().unwrap());
    let bath = 3.20477e-4;
    assert!(lo <= bath && bath <= hi, "the bath's c {bath} outside [{lo}, {hi}]");
}

/// The same on the 11.4-nm tube (`cc11.langevin.csv.gz`, eleven modes):
/// shear deformation and viscous damping decided, no point mass, spring,
/// axial force or second relaxation. The bath's c is not asserted inside
/// the interval: measured (`tests/identify_md.md`, round 6), the interval
/// ends 5 % below it. Before the Welch sandwich of
/// `identify::covariance::psd_covariance` this record was `unexplained` on ζ₅.
#[test]
#[ignore = "about 5 min in the release build: run with --release --ignored"]
fn identify_then_diagnose_on_the_cc11_md_record_names_shear_and_the_bath() {
    diagnose_md_record("cc11");
}

/// `identify` then `diagnose --json` on the committed MD record `name`,
/// untouched: asserts the verdict shared by the MD tubes (several causes,
/// explained, shear deformation and viscous damping decided, no point mass,
/// spring, relaxation or axial force decided) and returns the selected
/// model's candidate entry.
fn diagnose_md_record(name: &str) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let measured = dir.path().join("measured.yaml");
    std::fs::write(&measured, identified_file(name)).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_nanobeam"))
        .arg("diagnose")
        .arg(&measured)
        .arg("--json")
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let d: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(d["cause"], "multiple", "{}", d["causes"]);
    assert_eq!(d["explained"], true);
    let decided: Vec<&str> = d["decided_causes"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
    for cause in ["shear-deformation", "viscous-damping"] {
        assert!(decided.contains(&cause), "{decided:?}");
    }
    for cause in ["attached-mass", "support-rotational-stiffness", "extra-relaxation", "axial-force"] {
        assert!(!decided.contains(&cause), "{decided:?}");
    }
    d["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .max_by(|a, b| a["probability"].as_f64().unwrap().total_cmp(&b["probability"].as_f64().unwrap()))
        .unwrap()
        .clone()
}

/// `nanobeam identify --beam data/md/tube-NAME.yaml` on the committed
/// record `data/md/NAME.langevin.csv.gz`, untouched: the reported modes.
fn identify_md_record(name: &str) -> Vec<serde_yaml::Value> {
    let yaml: serde_yaml::Value = serde_yaml::from_str(&identified_file(name)).unwrap();
    yaml["modes"].as_sequence().unwrap().clone()
}

/// The measured-data file `nanobeam identify --beam data/md/tube-NAME.yaml`
/// writes for the committed record `data/md/NAME.langevin.csv.gz`, read as
/// committed (gzipped: issue 67).
fn identified_file(name: &str) -> String {
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_nanobeam"))
        .args(["identify", "--beam", &format!("{root}/data/md/tube-{name}.yaml")])
        .arg(format!("{root}/data/md/{name}.langevin.csv.gz"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    String::from_utf8(out.stdout).unwrap()
}

/// The first `peaks_ghz.len()` modes are numbered 1, 2, … and each lies
/// within the bath's half-power half-width 1/(4πτ) = 15.9 GHz plus half a
/// 6.1-GHz bin of the reference (3.05 GHz) of its PSD peak (derivation on
/// the cc7 test).
fn assert_numbered_at_the_peaks(modes: &[serde_yaml::Value], peaks_ghz: &[f64]) {
    let tolerance_ghz = 15.9 + 3.05;
    for (k, (m, peak)) in modes.iter().zip(peaks_ghz).enumerate() {
        assert_eq!(m["mode"].as_u64(), Some(k as u64 + 1), "{modes:?}");
        let f_ghz = m["omega_rad_s"].as_f64().unwrap() / (2.0 * std::f64::consts::PI) / 1e9;
        assert!((f_ghz - peak).abs() < tolerance_ghz, "mode {}: {f_ghz:.1} GHz vs the PSD peak {peak} GHz", k + 1);
    }
}

/// The committed clamped–clamped MD record of the 11.40 nm tube, untouched:
/// `nanobeam identify` with the nominal beam reports at least five modes,
/// numbered 1, 2, … without `--first-mode`, the first five at the PSD's
/// peaks 134, 354, 653, 1001, 1392 GHz (numpy Welch of the same record,
/// `data/md/psd.py`, slice 2; tests/identify_md.md, round 3). Tolerance as
/// for cc7: the bath's half-power half-width 1/(4πτ) = 15.9 GHz plus half
/// a 6.1-GHz bin of the reference, 19 GHz. About 50 s in the debug build
/// (11 modes in the fit), hence ignored in CI.
#[test]
#[ignore = "about 50 s: run with --ignored"]
fn identify_on_the_cc11_md_record_finds_its_low_modes_numbered_from_1() {
    let modes = identify_md_record("cc11");
    let peaks_ghz = [134.0, 354.0, 653.0, 1001.0, 1392.0];
    assert!(modes.len() >= peaks_ghz.len(), "{modes:?}");
    assert_numbered_at_the_peaks(&modes, &peaks_ghz);
}

/// The band stops where the line's tail meets a white floor. Generator: an
/// AR(2) line (poles 0.995·e^{±0.05i} per sample) plus independent white
/// noise whose level equals the AR(2) spectrum σ²/|1 − φ1e^{−iθ} − φ2e^{−2iθ}|²
/// (closed form) at θ_c = 0.8 rad per sample. Expected top: a tail falling
/// as θ⁻⁴ on a white floor S_w has floor S_w(1 + (θ_c/θ)⁴), which lies within
/// 0.2 decade (thermal::FLAT_FLOOR_DECADES) of its lowest value over the next
/// octave from θ ≈ 1.15 θ_c on; the floor is read over ±25 % of the
/// frequency, which moves that point by up to 25 % either way: [0.9, 1.45]·θ_c,
/// widened to [0.8, 1.6]·θ_c for the AR(2) tail's departure from θ⁻⁴ and the
/// estimate's scatter (≥ 8 averages, a 20th percentile over ≥ 100 bins).
/// The line itself (at 0.05) stays in the band.
#[test]
fn the_band_ends_where_the_line_tail_meets_a_white_floor() {
    let (r, theta) = (0.995, 0.05);
    let phi = ar2(r, theta);
    let theta_c: f64 = 0.8;
    let a = num_complex::Complex64::new(0.0, -theta_c).exp();
    let denom = (num_complex::Complex64::new(1.0, 0.0) - phi.0 * a - phi.1 * a * a).norm_sqr();
    // AR(2) driven by 1e-12·N(0,1): its spectrum at θ_c is 1e-24/denom; white noise of that variance
    let sd_white = 1e-12 / denom.sqrt();
    let n = 1 << 16;
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let cols: Vec<Vec<f64>> = (0..2)
        .map(|c| {
            series(phi, n, 20 + c)
                .into_iter()
                .map(|x| {
                    let e: f64 = StandardNormal.sample(&mut rng);
                    x + sd_white * e
                })
                .collect()
        })
        .collect();
    let (omega, _) = psd(&csv(&cols));
    let top = omega.last().unwrap() * DT; // rad per sample
    assert!(top > theta, "band top {top} below the line at {theta}");
    assert!((0.8 * theta_c..=1.6 * theta_c).contains(&top), "band top {top:.3} rad/sample, θ_c = {theta_c}");
}

/// Issue 69, defect 1: a longer record of the same stationary motion gets
/// the segment its lines ask for, not a finer one. A 2-ns record of cc7's
/// six lines (100 000 samples; every line 31.8 GHz wide) in six columns that
/// are two independent planes seen at three slices: before, its narrowest
/// "line" was measured at the finest resolution that averages 8 segments over
/// all columns (65 536 samples, 2 per column), where the averages at a line
/// are those of the two planes (4) and the estimate's scatter made ~4-bin
/// bumps on every line's top; the segment stayed at 65 536 (each line 41.7
/// bins), the fit got 32 768 bins of ν ≈ 4 and ran 100 s into an ambiguous
/// numbering. Tolerance: a line spans ≥ 4 bins (`thermal::MIN_LINE_BINS`);
/// at most a factor 2 more from the power-of-two segments, and another
/// factor 2 from the measurement (where each column averages ≥ 8 segments,
/// the narrowest of six lines measured 6.7 bins for 10.4 in the generator's
/// records of 2 and 4 ns, a numpy port of `narrowest_line`): ≤ 16 bins, where
/// the segment before gave 41.7.
#[test]
fn a_longer_record_of_the_same_lines_gets_the_segment_its_lines_ask_for() {
    const CC7_GHZ: [f64; 6] = [305.0, 751.0, 1318.0, 1953.0, 2612.0, 3308.0];
    let (omega, _) = psd(&csv(&langevin_tube_of(&CC7_GHZ, 100_000, 1)));
    let d_omega = omega[1] - omega[0];
    // half-power width of every line: γ = 1/τ = 2e11 rad/s
    let bins = 2e11 / d_omega;
    assert!((4.0..=2.0 * 2.0 * 4.0).contains(&bins), "lines span {bins:.1} bins of {d_omega:e} rad/s");
}

/// Issue 69, defect 1, end to end: `nanobeam identify --beam
/// data/md/tube-cc7.yaml` on the 2-ns record of the test above reports the
/// six lines, and only them, as modes 1–6 (no `--first-mode`), each ω and ζ
/// within 4 of its sd of the generator's (|p| = ω_k, ζ = γ/(2ω_k), γ = 1/τ:
/// the AR(2) poles are e^{(−γ/2 ± iω_d)Δt} with ω_d² = ω_k² − γ²/4). 4 sd
/// over 12 estimates: a false failure with probability 12 × 6.3e-5 < 1e-3.
/// Before the segment fix, this record exited 2: "5 fitted resonances in the
/// band, none clear: the clearest, at 1.1865e14 rad/s, stands 3.754e31 noise
/// sd high"; after it and before `assemble::spans_every_zeta` it reported a
/// seventh pole at 12.4 THz (ζ = 0.27 ± 0.34) on the PSD's tail, which this
/// floor-free record hands on up to the Nyquist frequency, and exited 2
/// asking for `--first-mode` ("fit both modes 1-6, 11 and 1-6, 10"). 48 s
/// (dev build, load 3–8), hence ignored.
#[test]
#[ignore = "about 50 s: run with --ignored"]
fn identify_on_a_2_ns_record_of_cc7_lines_finds_the_six_modes() {
    const CC7_GHZ: [f64; 6] = [305.0, 751.0, 1318.0, 1953.0, 2612.0, 3308.0];
    let yaml = identify_on_cc7_beam("long-record", &csv(&langevin_tube_of(&CC7_GHZ, 100_000, 1)));
    let modes = yaml["modes"].as_sequence().unwrap();
    assert_eq!(modes.len(), 6, "{modes:?}");
    let gamma = 1.0 / 5e-12;
    for (k, (m, f)) in modes.iter().zip(CC7_GHZ).enumerate() {
        assert_eq!(m["mode"].as_u64(), Some(k as u64 + 1), "{modes:?}");
        let w = 2.0 * std::f64::consts::PI * f * 1e9;
        let get = |key: &str| m[key].as_f64().unwrap();
        let dw = (get("omega_rad_s") - w) / get("omega_sd_rad_s");
        let dz = (get("zeta") - gamma / (2.0 * w)) / get("zeta_sd");
        assert!(dw.abs() < 4.0 && dz.abs() < 4.0, "mode {}: omega {dw:.2} sd, zeta {dz:.2} sd off", k + 1);
    }
}

/// `nanobeam identify --beam data/md/tube-cc7.yaml` on the record `text`
/// (written to a temporary file named by `tag`): its YAML report; the run must succeed.
fn identify_on_cc7_beam(tag: &str, text: &str) -> serde_yaml::Value {
    let path = std::env::temp_dir().join(format!("nanobeam-{tag}-{}.csv", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let root = env!("CARGO_MANIFEST_DIR");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_nanobeam"))
        .args(["identify", "--beam", &format!("{root}/data/md/tube-cc7.yaml")])
        .arg(&path)
        .output()
        .unwrap();
    std::fs::remove_file(&path).unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    serde_yaml::from_slice(&out.stdout).unwrap()
}
