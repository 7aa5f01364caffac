//! Thermal-motion records: a displacement time series of a structure driven
//! by its heat bath (molecular dynamics, a Brownian cantilever), turned into
//! the one-sided displacement PSD that identification fits.
//!
//! Header `time_s,thermal_<name>_m[,thermal_<name>_m…]`: uniform times, then
//! one or more displacement columns in metres (e.g. the y and z motion of one
//! slice, or several slices). Each column is an independent realisation of
//! the same modes; their Welch estimates are averaged. LAMMPS' `fix ave/time`
//! and `fix print` files become such a record with the one-line conversion in
//! `docs/md.md`.
//!
//! Welch's method: Hann window, 50 % overlap, mean removed per segment; the
//! PSD is per rad/s and one-sided, so its integral over ω ≥ 0 is the
//! variance. The segment length is chosen from the lines themselves: the
//! narrowest clear line of the flexural band (`flexural_band`: the lines
//! handed on) is measured at the finest resolution at which every column
//! alone still averages [`MIN_AVERAGES`] segments, or, when it is not
//! resolved there (measures under [`MIN_LINE_BINS`]), at the finest that
//! averages [`MIN_AVERAGES`] over all columns; then the shortest power-of-two segment
//! that keeps it at [`MIN_LINE_BINS`] bins or more at half power is used (the
//! most averages, the least variance). Columns that see the same modes (the
//! slices of one tube) add no averages at a line, so counting them as
//! independent measured a long record's lines where each averaged a handful
//! of segments: a 2-ns six-column record (two planes at three slices) was
//! measured at 65 536 samples, 2 segments a column, ~4 at a line, and the
//! estimate's scatter made ~4-bin bumps on every line's top (each line 42
//! bins wide); the bump was taken for the narrowest line, the segment stayed
//! the finest, and the PSD handed on grew with the record (32 768 bins of
//! ν ≈ 4 at 2 ns: a 140-s fit into an ambiguous numbering, issue 69, defect
//! 1). So the narrowest line is measured again at the finest segment of
//! which every column alone averages [`MIN_AVERAGES`] (a lower bound on the
//! averages at a line whatever the columns share). A line resolved there
//! (≥ [`MIN_LINE_BINS`]) spans as many more bins in the finer estimate as
//! the segment is longer, a scatter bump the window's few bins at every
//! segment: when the finer estimate's narrowest line measures under half
//! that (room for each measurement's ±25 %), it is a bump, and the segment
//! is chosen from the coarser measurement. Otherwise the finer measurement
//! stands (a coarse one overstates a line's width by the window's ~1–3 bins,
//! and halving from it can leave the line unresolved). A record too short
//! for one column to resolve its lines (the MD records: one column of cc7's
//! 17 503 samples averages 16 segments of 2 048 and 7 of 4 096; at 2 048 a
//! 31.8-GHz line spans 1.3 bins) is measured as before. When it measures under
//! [`MIN_LINE_BINS`] there (a short record, or one column), it is measured
//! again at the finest resolution that averages [`FIT_AVERAGES`] (segments ×
//! columns: the estimate's relative variance is 1/(K·C)), and the segment
//! chosen from that. A record whose narrowest line measures
//! no wider than a line of half a bin ([`UNRESOLVED_LINE_BINS`]) even then
//! is refused, naming the record length that would resolve it; lines between
//! that and three bins are judged after the fit, on their fitted widths. So
//! is a record whose strongest line reaches within [`LOW_EDGE_BINS`] of 0 Hz
//! at half power (a cantilever's fundamental in a short record), naming the
//! least record length that could resolve it.
//! The PSD handed on stops where the floor under the lines stops falling
//! (`flexural_band`): the beam's lines sit in the lowest few per cent of a
//! molecular-dynamics record's Welch band.

use std::f64::consts::PI;

use crate::error::InputError;

/// Fewest Welch segments (over all columns) an estimate may average: with
/// 8 averages the PSD's relative standard deviation is ≈ 1/√8 ≈ 0.35.
pub const MIN_AVERAGES: usize = 8;

/// Fewest Welch averages (segments × columns) of the estimate handed on when
/// the flexural band's narrowest line is unresolved at [`MIN_AVERAGES`]
/// (measured under [`MIN_LINE_BINS`]). The estimate's relative variance is
/// 1/(K·C) for K segments of each of C independent columns, and the one
/// thing the estimate must still do before the fit is tell a line from the
/// floor: `narrowest_line` takes a bin 10× over its neighbourhood's median
/// for a line. A bin of a white floor is its mean times χ²₂ᵥ/(2ν), ν = K·C, so
/// P(> 10× the mean) = P(χ²₂ᵥ > 20ν) = e^(−10ν) Σ_{j<ν} (10ν)^j/j!:
/// 4.5e-5 at ν = 1, 4.3e-8 at ν = 2, 4.5e-11 at ν = 3, i.e. over the 4 096
/// bins of an 8 192-sample segment 0.18, 1.8e-4 and 1.8e-7 false lines per
/// record; ν = 3 is the least that keeps that under 1e-6. The fit needs no
/// floor of its own: its Whittle likelihood takes ν from the residuals (ν̂),
/// and `nu_warning` compares it with the segments. One column of the cc7 MD
/// record (17 503 samples) averages 3 segments of 8 192 (bins of 6.1 GHz, the
/// bath's 31.8-GHz lines 5.2 bins wide); at [`MIN_AVERAGES`] it had 2 048
/// (1.3 bins a line: issue 69, defect 8). (Columns that see the same modes
/// are correlated at a line, so ν there lies between K and K·C: the floor
/// counts K·C as [`MIN_AVERAGES`] does.)
pub const FIT_AVERAGES: usize = 3;

/// Bins a line should span at half power, as measured by the narrowest-line
/// estimate, before the segment is halved for more averages, and the
/// resolution a refusal's advice aims at: identification needs ≥ 3 samples in
/// each half-power band (an interval of w bins holds ⌊w⌋ of them), and one
/// bin of margin for the estimate's scatter.
pub const MIN_LINE_BINS: f64 = 4.0;

/// A record is refused before any fit when its narrowest clear line measures
/// fewer bins than this: the estimate's width (half power of the three-bin
/// average, see `narrowest_line`) of a line of true half-power width w bins,
/// computed on the noise-free Welch expectation (Lorentzian ⊛ the Hann
/// window's power kernel, then the three-bin average), is 3.00–3.05 for a
/// pure tone, 3.13–3.26 for w = 0.5 (by the line's offset from a bin centre),
/// 3.32 for w = 1, 4.56 for w = 3 and 6.24 for w = 5.2, so a line measured
/// under 3.2 is about half a bin wide or less. Refusing at
/// [`MIN_LINE_BINS`] instead refused most resolved records: on a noisy
/// estimate the narrowest of ten lines measures low (the maximum bin sits
/// above the line's top), as Langevin records whose every line spans 5.2
/// bins showed (`tests/identify_md.md`, round 6). Lines between half a bin
/// and three bins pass here; `identify` refuses them after the fit, when
/// their fitted half-power band holds fewer than `MIN_POINTS_PER_RESONANCE`
/// bins.
pub const UNRESOLVED_LINE_BINS: f64 = 3.2;

/// Bins from 0 Hz within which a Welch estimate does not hold a line: each
/// segment's mean removal empties bin 0 and, through the Hann window's ±2-bin
/// main lobe, the bins up to 2; bin 3 still carries the leakage of that
/// notch. A record whose strongest line (a thermal record's fundamental,
/// which equipartition makes the largest) has its lower half-power edge
/// below this at the finest resolution of [`MIN_AVERAGES`] averages, or
/// whose largest bin (from bin 1) lies below it with no edge seen, is
/// refused, naming the record length without which no segment of
/// [`MIN_AVERAGES`] averages puts the line's peak 1.5 bins past this (a
/// necessary length: a line of Q < 1.2 shows no lower half-power edge at
/// any resolution, hence "or a weaker bath"): the line is not resolved, and
/// it dominates the PSD that every other line is fitted in. Measured on the
/// committed cantilever record `cl7.langevin` (200 ps, fundamental near
/// 49 GHz at Q ≈ 1.5, bins of 12.2 GHz): the fit that followed returned
/// poles of ζ sd up to 1 230 and a refusal naming a pole at 2 572 GHz
/// narrower than the sampling (`tests/identify_md.md`, round 8).
pub const LOW_EDGE_BINS: f64 = 4.0;

/// Shortest segment considered, in samples.
const MIN_SEGMENT: usize = 64;

/// Whether a header names a thermal-motion record.
pub fn is_thermal(header: &[String]) -> bool {
    header.len() >= 2
        && header[0] == "time_s"
        && header[1..].iter().all(|n| n.starts_with("thermal_") && n.ends_with("_m") && n.len() > 10)
}

/// The one-sided displacement PSD `(omega_rad_s, psd_m2_s_per_rad)` of a
/// thermal-motion record (`time_s` uniform, checked by the caller; `columns`
/// each as long as `time_s`), the PSD record `data` then builds.
pub fn psd_of(time_s: &[f64], columns: &[Vec<f64>]) -> Result<(Vec<f64>, Vec<f64>), InputError> {
    let n = time_s.len();
    // the canonical step: the same bits for every time origin (`step`)
    let dt = super::step::sampling_step(time_s);
    let record_s = n as f64 * dt;
    let averages = |seg: usize| columns.len() * welch_count(n, seg);
    let finest = finest_segment(n, columns.len(), MIN_AVERAGES);
    if finest == 0 {
        return Err(InputError::new(
            "rows",
            n,
            format!(
                ">= {} samples per column for {MIN_AVERAGES} Welch segments of {MIN_SEGMENT} samples",
                MIN_SEGMENT * (MIN_AVERAGES.div_ceil(columns.len()) + 1) / 2
            ),
        ));
    }
    let psd = welch(columns, finest);
    // (an estimate with an empty bin, a constant column, is refused below as such)
    let empty_bin = psd[1..].iter().any(|&v| !(v > 0.0));
    let low = if empty_bin { None } else { strongest_line_edge(&psd) };
    if let Some((peak, edge)) = low.filter(|&(_, edge)| edge < LOW_EDGE_BINS) {
        // a necessary length, not a sufficient one: segments that put the
        // line's peak LOW_EDGE_BINS + 1.5 bins up (room for the 3 samples of
        // a half-power band above the distorted bins); the edge itself, a
        // noisy crossing that a line of Q < 1.2 never shows, gives no bound
        let mut seg = finest;
        while (seg as f64) < finest as f64 * (LOW_EDGE_BINS + 1.5) / peak as f64 {
            seg *= 2;
        }
        let rows = seg * (MIN_AVERAGES.div_ceil(columns.len()) + 1) / 2;
        return Err(InputError::new(
            RECORD_LENGTH,
            format!("{record_s:.3e} s"),
            format!(
                "at least {:.3e} s, or a weaker bath, resolving its strongest line ({:.3e} Hz: half-power band from \
                 {edge:.1} bins of {:.3e} Hz, < {LOW_EDGE_BINS})",
                rows as f64 * dt,
                peak as f64 / (finest as f64 * dt),
                1.0 / (finest as f64 * dt),
            ),
        ));
    }
    // the lines measured are the flexural band's (`flexural_band` of this
    // estimate): a line above it is not handed on, and may be narrower (cc7's
    // narrowest line over the whole band is a non-flexural one above it)
    let (mut finest, mut psd) = (finest, psd);
    let mut narrowest = narrowest_flexural_line(&psd);
    // checked where every column alone averages MIN_AVERAGES (columns that
    // see the same modes add no averages at a line): a line resolved there
    // spans finest/per_column times its bins here, a scatter bump the
    // window's few bins whatever the segment; under half the line's bins
    // here, the narrowest measured is a bump (issue 69, defect 1, see the
    // module doc)
    let per_column = finest_segment(n, 1, MIN_AVERAGES);
    if per_column > 0 && per_column < finest {
        let coarse = welch(columns, per_column);
        let measured = narrowest_flexural_line(&coarse);
        let scale = (finest / per_column) as f64;
        if let Some((_, w)) = measured.filter(|&(_, w)| w >= MIN_LINE_BINS) {
            if narrowest.is_none_or(|(_, here)| here < 0.5 * w * scale) {
                (finest, psd, narrowest) = (per_column, coarse, measured);
            }
        }
    }
    if narrowest.is_some_and(|(_, w)| (UNRESOLVED_LINE_BINS..MIN_LINE_BINS).contains(&w)) {
        // unresolved at MIN_AVERAGES (a line of true width ≲ 2 bins measures
        // under MIN_LINE_BINS): the finest segment that still averages
        // FIT_AVERAGES, measured again there
        let s = finest_segment(n, columns.len(), FIT_AVERAGES);
        if s > finest {
            finest = s;
            psd = welch(columns, s);
            narrowest = narrowest_flexural_line(&psd);
        }
    }
    let chosen = match narrowest {
        Some((bin, width)) if width < UNRESOLVED_LINE_BINS => {
            let f_hz = bin as f64 / (finest as f64 * dt);
            return Err(InputError::new(
                RECORD_LENGTH,
                format!("{record_s:.3e} s"),
                format!(
                    "at least {:.3e} s ({:.1}x longer): the line at {:.4e} Hz spans {width:.1} bins of {:.3e} Hz \
                     ({} averages of {:.3e} s), < {UNRESOLVED_LINE_BINS}",
                    record_s * 2.0 * MIN_LINE_BINS / width,
                    2.0 * MIN_LINE_BINS / width,
                    f_hz,
                    1.0 / (finest as f64 * dt),
                    averages(finest),
                    finest as f64 * dt,
                ),
            ));
        }
        Some((_, width)) => {
            let mut s = finest;
            let mut w = width;
            while s / 2 >= MIN_SEGMENT && w / 2.0 >= MIN_LINE_BINS {
                s /= 2;
                w /= 2.0;
            }
            s
        }
        None => finest,
    };
    let psd = if chosen == finest { psd } else { welch(columns, chosen) };
    // per Hz (two-sided folded) → per rad/s: S_ω = S_f/(2π); bin k at ω = 2πk/(N_seg Δt)
    let d_omega = 2.0 * PI / (chosen as f64 * dt);
    let mut omega = Vec::with_capacity(psd.len());
    let mut value = Vec::with_capacity(psd.len());
    for (k, &p) in psd.iter().enumerate().skip(1) {
        omega.push(k as f64 * d_omega);
        value.push(p * dt / (2.0 * PI));
    }
    if let Some(k) = value.iter().position(|&v| !(v > 0.0 && v.is_finite())) {
        return Err(InputError::new(
            format!("PSD bin {}", k + 1),
            value[k],
            "> 0 (a displacement column is constant over a segment)",
        ));
    }
    let keep = flexural_band(&value);
    omega.truncate(keep);
    value.truncate(keep);
    Ok((omega, value))
}

/// The field of a refusal of the record's length: the value is the length
/// in seconds, what it needs the allowed part (issue 69: the value slot held
/// "a record of 6.000e-12 s").
pub const RECORD_LENGTH: &str = "time_s (the record's length)";

/// Factor above the frequency of the record's strongest line at which the band's top is first
/// looked for (see `flexural_band`).
pub const BAND_SEARCH_START: f64 = 8.0;

/// How far (decades) under the strongest line a lower line may stand and
/// still be taken for the fundamental when the band search from the
/// strongest line finds no flat floor (see `flexural_band`). Equipartition
/// gives mode n a variance ∝ 1/ω_n², and with one bath width its PSD peak
/// scales alike, so a column that sees every mode alike shows the
/// fundamental strongest; near a clamp the shapes grow as (β_n x)², i.e.
/// φ_n² ∝ β_n⁴ ∝ ω_n², which cancels that: the low lines stand alike there
/// (cc7 at x/L = 0.15: mode 1 0.21 decades under mode 2), whichever is
/// strongest. One decade leaves room for the estimate's scatter (3 averages:
/// a bin's sd is 58 % of its mean) and the shapes' departure from (β_n x)²;
/// a line 10× under the strongest is not the one that sets the band.
pub const LOW_LINE_DECADES: f64 = 1.0;

/// How close (decades) the PSD's floor must come to its lowest value over
/// the next octave for the background to count as flat (see `flexural_band`).
pub const FLAT_FLOOR_DECADES: f64 = 0.2;

/// The number of bins (from the first) that hold the beam's lines: the
/// band ends where the background under the lines stops falling. Below it
/// the background is the lines' own tails (a resonance's PSD falls as ω⁻⁴
/// above it), above it the PSD lies on a flat floor that no beam mode makes
/// (in an MD record, the slices' motion that is not the tube's bending:
/// docs/md.md §3) and the fit's Whittle likelihood would weigh its
/// thousands of bins like those of the lines.
/// The floor at bin i is the 20th percentile of the PSD over ±25 % of its
/// frequency (at least ±8 bins: a line fills less than that, so the floor is
/// the background between lines); it is flat at i when it lies within
/// [`FLAT_FLOOR_DECADES`] of its lowest value over bins i … 2i. The search
/// starts [`BAND_SEARCH_START`] times above the frequency of the strongest
/// line (a clamped or free beam's first three modes span a factor 5.4 or
/// 17.5, so the lowest lines are never cut; below a cantilever's overdamped
/// fundamental the floor is flat too). Equipartition makes the fundamental
/// the strongest line of a column that sees every mode alike, but not of one
/// near a clamp, where the shapes weigh mode 2 above mode 1: in cc7's column
/// at x/L = 0.15, mode 2 (745 GHz) stands 0.2 decades over mode 1, the search
/// started at 6 THz, past the flexural band, in the record's non-flexural
/// motion, whose floor never flattens, and all 4 096 bins were handed on,
/// the non-flexural lines with them (issue 69, defect 8). So when no flat
/// floor is found from there, the search is repeated from
/// [`BAND_SEARCH_START`] times the lowest line (a local maximum over ±2 bins
/// of the three-bin average) within [`LOW_LINE_DECADES`] of the strongest
/// (in that column the floor then first reads flat at 3.39–3.44 THz at
/// segments of 2 048–8 192 samples; the six-column record's band ends at
/// 3.39). A PSD whose floor never flattens from either start is kept whole.
fn flexural_band(psd: &[f64]) -> usize {
    let n = psd.len();
    let smooth = |i: usize| {
        let s = &psd[i.saturating_sub(1)..(i + 2).min(n)];
        s.iter().sum::<f64>() / s.len() as f64
    };
    let Some(strongest) = (2..n).max_by(|&a, &b| smooth(a).total_cmp(&smooth(b))) else { return n };
    let mut scratch = Vec::new();
    let floor: Vec<f64> = (0..n)
        .map(|i| {
            let lo = (i * 4 / 5).min(i.saturating_sub(8));
            let hi = (i * 5 / 4).max(i + 8).min(n - 1);
            scratch.clear();
            scratch.extend_from_slice(&psd[lo..=hi]);
            let k = (scratch.len() - 1) / 5;
            scratch.select_nth_unstable_by(k, f64::total_cmp).1.log10()
        })
        .collect();
    // the first bin from `start` whose floor is flat over the octave above
    let flat_from = |start: usize| {
        (start..n)
            .take_while(|&i| 2 * (i + 1) <= n)
            .find(|&i| {
                let lowest = floor[i..2 * (i + 1)].iter().copied().fold(f64::INFINITY, f64::min);
                floor[i] - lowest <= FLAT_FLOOR_DECADES
            })
            .map(|i| i + 1)
    };
    // psd[i] is bin i + 1 (bin 0 is not returned): frequencies scale as i + 1
    let from = |line: usize| flat_from(((line + 1) as f64 * BAND_SEARCH_START) as usize);
    // no flat floor above that: the strongest line may not be the
    // fundamental (a column near a clamp), and the search started past the
    // flexural band; searched again from the lowest line within
    // LOW_LINE_DECADES of it, if any (issue 69, defect 8, see the doc)
    let lowest = || {
        (2..strongest).find(|&i| {
            let v = smooth(i);
            v >= smooth(strongest) * 10f64.powf(-LOW_LINE_DECADES)
                && (i.saturating_sub(2)..(i + 3).min(n)).all(|j| smooth(j) <= v)
        })
    };
    from(strongest).or_else(|| lowest().and_then(from)).unwrap_or(n)
}

/// The narrowest clear line of `psd` within its flexural band (the lines
/// handed on): `narrowest_line` on the bins up to `flexural_band`.
fn narrowest_flexural_line(psd: &[f64]) -> Option<(usize, f64)> {
    narrowest_line(&psd[..flexural_band(&psd[1..]) + 1])
}

/// The longest power-of-two segment (from [`MIN_SEGMENT`]) of which
/// `columns` columns of `n` samples hold `count` Welch segments in all; 0
/// when none does.
fn finest_segment(n: usize, columns: usize, count: usize) -> usize {
    let mut finest = 0;
    let mut seg = MIN_SEGMENT;
    while seg <= n && columns * welch_count(n, seg) >= count {
        finest = seg;
        seg *= 2;
    }
    finest
}

/// Segments of `seg` samples with 50 % overlap in `n` samples.
fn welch_count(n: usize, seg: usize) -> usize {
    if seg > n {
        0
    } else {
        (n - seg) / (seg / 2) + 1
    }
}

/// Mean over columns and segments of |FFT(w·(x − x̄))|²/Σw² at bins
/// 0..=seg/2, doubled except at 0 and seg/2: the one-sided periodogram whose
/// sum over bins divided by seg is the windowed variance (times Δt it is the
/// PSD per Hz).
fn welch(columns: &[Vec<f64>], seg: usize) -> Vec<f64> {
    let window: Vec<f64> = (0..seg).map(|i| 0.5 - 0.5 * (2.0 * PI * i as f64 / seg as f64).cos()).collect();
    let norm: f64 = window.iter().map(|w| w * w).sum();
    let mut acc = vec![0.0; seg / 2 + 1];
    let mut count = 0usize;
    let mut re = vec![0.0; seg];
    let mut im = vec![0.0; seg];
    for x in columns {
        let mut start = 0;
        while start + seg <= x.len() {
            let s = &x[start..start + seg];
            let mean = s.iter().sum::<f64>() / seg as f64;
            for i in 0..seg {
                re[i] = (s[i] - mean) * window[i];
                im[i] = 0.0;
            }
            fft(&mut re, &mut im);
            for (k, a) in acc.iter_mut().enumerate() {
                let p = (re[k] * re[k] + im[k] * im[k]) / norm;
                *a += if k == 0 || k == seg / 2 { p } else { 2.0 * p };
            }
            count += 1;
            start += seg / 2;
        }
    }
    acc.iter().map(|a| a / count as f64).collect()
}

/// The narrowest clear line of a PSD: (bin of its maximum, half-power width
/// in bins, interpolated, of the PSD averaged over three bins). A clear line is a local maximum over ±2 bins that
/// stands 10× above the median of the PSD within ±25 % of its frequency
/// (at least ±8 bins). That floor scales with the frequency, not with the
/// resolution, so a well-resolved line (quality factor ≳ 4) stands clear at
/// every segment length; a noise bump on the flank of a line does not (its
/// neighbourhood holds the flank), and neither does one on a flat floor (with
/// 8 averages an estimate exceeds 10× its mean with probability < 1e-9).
/// Bins 0 and 1, emptied by removing each segment's mean through the Hann
/// window's ±2-bin main lobe, are left out. None when there is no clear line.
fn narrowest_line(raw: &[f64]) -> Option<(usize, f64)> {
    // three-bin moving average: the maximum bin of a noisy estimate sits above
    // the line's top (by ≈ one standard deviation, 25–35 % at 8–16 averages),
    // which would put the half-power level too high and the width too low;
    // averaging three bins divides that bias by √3 and broadens a line of
    // w ≥ 4 bins by < 0.3 bin
    let p: Vec<f64> = (0..raw.len())
        .map(|i| {
            let s = &raw[i.saturating_sub(1)..(i + 2).min(raw.len())];
            s.iter().sum::<f64>() / s.len() as f64
        })
        .collect();
    let mut best: Option<(usize, f64)> = None;
    let mut scratch = Vec::with_capacity(p.len());
    for i in 4..p.len().saturating_sub(2) {
        if p[i - 2..=i + 2].iter().any(|&v| v > p[i]) {
            continue;
        }
        let reach = (i / 4).max(8);
        scratch.clear();
        scratch.extend_from_slice(&p[i.saturating_sub(reach).max(2)..(i + reach + 1).min(p.len())]);
        let mid = scratch.len() / 2;
        let floor = *scratch.select_nth_unstable_by(mid, f64::total_cmp).1;
        if p[i] < 10.0 * floor {
            continue;
        }
        let half = p[i] / 2.0;
        let edge = |dir: isize| -> f64 {
            let mut j = i as isize;
            loop {
                let next = j + dir;
                if next < 0 || next as usize >= p.len() {
                    return (j - i as isize).unsigned_abs() as f64;
                }
                let (a, b) = (p[j as usize], p[next as usize]);
                if b < half {
                    // linear interpolation of the half-power crossing between j and next
                    return (j - i as isize).unsigned_abs() as f64 + (a - half) / (a - b);
                }
                j = next;
            }
        };
        let width = edge(-1) + edge(1);
        if best.is_none_or(|(_, w)| width < w) {
            best = Some((i, width));
        }
    }
    best
}

/// The strongest line of a Welch estimate `raw` (bin 0 at 0 Hz) and the bin
/// of its lower half-power edge, on the three-bin average (as
/// `narrowest_line`, bin 0 left out), the crossing interpolated linearly:
/// 0 when the estimate does not fall to half the line's height between it
/// and bin 1 (its lowest bins hold the top of the line, or a spectrum rising
/// towards 0 Hz). None when the estimate has fewer than 3 bins or its
/// largest value stands under 10× its median (no line).
fn strongest_line_edge(raw: &[f64]) -> Option<(usize, f64)> {
    let n = raw.len();
    if n < 3 {
        return None;
    }
    let p: Vec<f64> = (0..n)
        .map(|i| {
            let s = &raw[i.saturating_sub(1).max(1)..(i + 2).min(n)];
            s.iter().sum::<f64>() / s.len() as f64
        })
        .collect();
    let peak = (1..n).max_by(|&a, &b| p[a].total_cmp(&p[b]))?;
    // a line stands 10× over the estimate's median (as in `narrowest_line`:
    // a white estimate of ≥ 8 averages exceeds that with probability < 1e-9);
    // a constant column's round-off or a white record has none
    let mut sorted: Vec<f64> = p[1..].to_vec();
    let mid = sorted.len() / 2;
    let median = *sorted.select_nth_unstable_by(mid, f64::total_cmp).1;
    if !(p[peak] > 0.0 && p[peak] >= 10.0 * median) {
        return None;
    }
    let half = p[peak] / 2.0;
    let mut j = peak;
    while j > 1 {
        if p[j - 1] < half {
            return Some((peak, (j - 1) as f64 + (half - p[j - 1]) / (p[j] - p[j - 1])));
        }
        j -= 1;
    }
    Some((peak, 0.0))
}

/// In-place radix-2 FFT (length a power of two). Written here rather than
/// taken from a crate: the project has no FFT dependency, Welch needs only
/// this forward transform of power-of-two segments, and adding one for these
/// twenty lines would add a dependency to every build. Also the spectrum
/// of a free decay in `identify`'s peak search.
pub(crate) fn fft(re: &mut [f64], im: &mut [f64]) {
    let n = re.len();
    let mut j = 0;
    for i in 1..n {
        let mut bit = n >> 1;
        while j & bit != 0 {
            j ^= bit;
            bit >>= 1;
        }
        j |= bit;
        if i < j {
            re.swap(i, j);
            im.swap(i, j);
        }
    }
    let mut len = 2;
    while len <= n {
        let ang = -2.0 * PI / len as f64;
        for start in (0..n).step_by(len) {
            for k in 0..len / 2 {
                let (s, c) = (ang * k as f64).sin_cos();
                let (a, b) = (start + k, start + k + len / 2);
                let tr = re[b] * c - im[b] * s;
                let ti = re[b] * s + im[b] * c;
                re[b] = re[a] - tr;
                im[b] = im[a] - ti;
                re[a] += tr;
                im[a] += ti;
            }
        }
        len <<= 1;
    }
}

/// Welch segments of one column and the number of columns of a
/// thermal-motion record's PSD: the record `text` (its header, its first two
/// times, its row count) and the PSD's bin spacing `d_omega_rad_s` give the
/// segment length. `None` when `text` is not a thermal-motion record.
pub fn welch_segments(text: &str, d_omega_rad_s: f64) -> Option<(usize, usize)> {
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let header: Vec<String> =
        lines.next()?.split(',').map(|s| s.trim().trim_start_matches('\u{feff}').to_string()).collect();
    if !is_thermal(&header) {
        return None;
    }
    let time = |l: Option<&str>| l.and_then(|l| l.split(',').next()).and_then(|v| v.trim().parse::<f64>().ok());
    let (t0, t1) = (time(lines.next())?, time(lines.next())?);
    let rows = 2 + lines.count();
    let seg = (2.0 * PI / (d_omega_rad_s * (t1 - t0))).round() as usize;
    Some((welch_count(rows, seg), header.len() - 1))
}

/// Below this fraction of one column's Welch segments, the fit's ν̂
/// (1/noise_sd² of a PSD fit) says the fit does not describe the PSD. The
/// independent averages ν lie between one column's segment count K (columns
/// that see the same modes, e.g. slices of one tube, are fully correlated at a
/// line) and the count over all columns; with a Hann window and 50 % overlap
/// ν ≈ 0.95 K per independent column (Welch 1967: adjacent segments correlate
/// by 0.167² in power), and ν̂ from hundreds of bins is itself good to
/// ≲ 10 %: half of K is a misfit, not scatter.
pub const NU_WARN_FRACTION: f64 = 0.5;

/// The `warning:` line for a PSD fit whose ν̂ = 1/noise_sd² lies far below
/// the `per_column` Welch segments of each of the record's `columns` (None
/// when it does not).
pub fn nu_warning(noise_sd: f64, (per_column, columns): (usize, usize)) -> Option<String> {
    let nu = 1.0 / (noise_sd * noise_sd);
    (nu < NU_WARN_FRACTION * per_column as f64).then(|| {
        format!(
            "the fit's residual scatter is that of {nu:.2} Welch averages (relative sd {noise_sd:.3}) where each of the \
             record's {columns} columns gives {per_column} segments: the fit misses structure of the PSD (lines or \
             background); the modes' sd, scaled by that scatter, are wider than the record's segments would give"
        )
    })
}

/// The warning (without its `warning: ` prefix) for a fit of the record
/// `text` whose PSD has the abscissa `omega_rad_s` (its bin spacing gives the
/// Welch segment length) and the residual noise sd `noise_sd`: the
/// [`nu_warning`] of a thermal-motion record, None for any other record or a
/// fit whose ν̂ the segments explain. The CLI prints it on stderr, the Python
/// `identify` issues it as a `RuntimeWarning`: one text for both.
pub fn fit_warning(text: &str, omega_rad_s: &[f64], noise_sd: f64) -> Option<String> {
    let [w0, w1, ..] = omega_rad_s else { return None };
    welch_segments(text, w1 - w0).and_then(|k| nu_warning(noise_sd, k))
}
