//! Initial poles: the stabilisation diagram's (LSCF or the matrix pencil
//! over many orders) and the resonances [`peaks`] declares above the
//! record's local noise that the diagram missed; the refusals of resonances
//! narrower than the sampling.

use num_complex::Complex64;

use super::lscf;
use super::peaks;
use super::pencil;
use super::refine::FitKind;
use super::scaled::Scaled;
use super::stabilisation::Diagram;
use super::thermal;
use super::{IdentifyError, MIN_POINTS_PER_RESONANCE, PENCIL_CAP};
use crate::error::InputError;

/// Poles at orders 2, 4, … of LSCF or the matrix pencil.
pub(super) fn stabilisation_diagram(sc: &Scaled, max_order: usize) -> Result<Diagram, IdentifyError> {
    let n = sc.x.len();
    let (orders, poles): (Vec<usize>, Vec<Vec<Complex64>>) = if sc.kind == FitKind::Time {
        let y: Vec<f64> = sc.y.iter().map(|v| v.re).collect();
        let top = max_order.min(n / 3);
        // pencil L = N/10 within [top order + 10, PENCIL_CAP] (the SVD costs
        // O(N·L²)). Hua & Sarkar's noise-optimal N/3 … N/2 was tried: on
        // 600-sample ring-downs of the paper's beam L = 200 loses a mode in
        // 4 of 200 noise seeds where L = 60 loses none, while a 2 000-sample
        // record of a 10-ms decay needs L = 200 (L = 100 misses its first
        // mode): an empirical choice, stated as such.
        let l = (n / 10).min(PENCIL_CAP).max(top + 10);
        let p = pencil::Pencil::new(&y, std::f64::consts::PI, l)
            .ok_or_else(|| IdentifyError::Numerical("SVD of the Hankel matrix failed".into()))?;
        let top = top.min(p.max_order());
        (2..=top).step_by(2).filter_map(|o| p.poles(o).map(|ps| (o, ps))).unzip()
    } else {
        let h: Vec<Complex64> = match sc.kind {
            FitKind::Complex => sc.y.clone(),
            FitKind::Magnitude => sc.y.iter().map(|v| Complex64::new(v.norm_sqr(), 0.0)).collect(),
            _ => sc.y.clone(),
        };
        // order n has 2n + 2 real unknowns: keep ≥ 2 equations per unknown
        let top = max_order.min(n.saturating_sub(2) / 2);
        let l = if sc.kind == FitKind::Psd {
            lscf::Lscf::stacked(&sc.x, &h, top, 1.0)
        } else {
            lscf::Lscf::normal(&sc.x, &h, top, 1.0)
        };
        (2..=top).step_by(2).filter_map(|o| l.poles(o).map(|ps| (o, ps))).unzip()
    };
    if orders.is_empty() {
        return Err(IdentifyError::Numerical("no model order of the initial estimator could be solved".into()));
    }
    Ok(Diagram::build(orders, &poles))
}

/// Adds the resonances [`peaks::detect`] declares and the diagram missed to
/// the initial poles (sorted by frequency). A PSD's declared peak always
/// joins them (see the comment in the body). Otherwise a declared peak with fewer than
/// [`MIN_POINTS_PER_RESONANCE`] samples above its half-power level may be a
/// line narrower than the sampling. When it stands at least
/// [`REFUSE_FACTOR`] × its declaration threshold high (a single-sample noise
/// excursion that high has probability ≲ 10⁻⁸ per record), the record is
/// refused (exit 2) if fewer than [`MIN_POINTS_PER_RESONANCE`] samples lie
/// within the noise of the half-power level ([`peaks::Peak::samples_near_half`]);
/// otherwise the peak joins the initial poles. A lower peak with too few
/// samples is left out (see [`check_points_per_resonance`] for the
/// diagram's poles).
pub(super) fn merge_peaks(sc: &Scaled, initial: &mut Vec<Complex64>) -> Result<Vec<Complex64>, InputError> {
    let series = match sc.kind {
        FitKind::Complex => peaks::Series::Complex,
        FitKind::Magnitude => peaks::Series::Magnitude,
        _ => peaks::Series::Psd,
    };
    let mut declared = peaks::detect(&sc.x, &sc.y, series);
    // the clearest MAX_DECLARED only: each adds four parameters to every
    // refinement candidate (a thermal record's PSD over 25 THz declared
    // dozens of lines and its refinement ran past 5 minutes)
    declared.sort_by(|a, b| b.statistic.total_cmp(&a.statistic));
    declared.truncate(if sc.kind == FitKind::Psd { MAX_DECLARED_PSD } else { MAX_DECLARED });
    let mut shadowed = Vec::new();
    for mut peak in declared {
        let resolved = peak.samples_above_half >= MIN_POINTS_PER_RESONANCE;
        if !resolved {
            // A PSD's declared peak is kept as a start whatever its count:
            // at ν averages the top sample overshoots the line's top by
            // ≈ 1/√ν of it and sets the half-power level that high, so a line
            // 5 bins wide at ν ≈ 4 (a 0.25-ns MD record) shows 2 samples above
            // it (tests/identify_md.md, round 3). The declaration threshold
            // already bounds false alarms (peaks::FALSE_ALARM per record); a
            // start the data do not hold leaves the report through the fit
            // (peak SNR, samples in the fitted half-power band, `assemble`).
            let clear = sc.kind == FitKind::Psd || peak.statistic >= REFUSE_FACTOR * peak.threshold;
            if !clear {
                continue;
            }
            if sc.kind != FitKind::Psd && peak.samples_near_half < MIN_POINTS_PER_RESONANCE {
                return Err(under_sampled(
                    sc,
                    peak.pole,
                    peak.samples_near_half,
                    &format!("a peak {:.1} noise sd high", peak.statistic),
                ));
            }
            // the noise moved samples of a line it does not show to be
            // under-sampled across the half-power level: its start spans the
            // 3 samples around the peak (1.5 local spacings either side)
            let i = peak.index.min(sc.x.len() - 2);
            let spacing = sc.x[i + 1] - sc.x[i];
            peak.pole.re = peak.pole.re.min(-1.5 * spacing);
        }
        let (w, sigma) = (peak.pole.im, -peak.pole.re);
        let known = is_known(initial, w, sigma);
        if !known {
            initial.push(peak.pole);
        } else if resolved {
            shadowed.push(peak.pole);
        }
    }
    initial.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    Ok(shadowed)
}

/// Free decays: adds the resonances [`peaks::detect`] declares in the
/// record's spectrum and the diagram missed to the initial poles. The DFT
/// of a sampled decay Σ A e^{p t} is Σ A/(1 − e^{(p − iω)Δt}), near a pole
/// A/((iω − p)Δt): a resonance of the form `peaks` reads in a complex sweep,
/// and white noise in time is white complex noise over the bins (equal sd
/// in the real and imaginary parts). The matrix pencil misses modes the
/// spectrum shows: with the pencil parameter capped at [`PENCIL_CAP`], a
/// Hankel row spans few periods of a low mode, and its pole wanders between
/// orders (tests/identify_coverage.md: ring-downs lost 3 of 34 and 7 of 53
/// visible modes). The record is zero-padded to a power of two (at most
/// twice its length: adjacent bins stay nearly independent, as the noise
/// estimate of `peaks` assumes). Peaks within 3 bins of zero frequency are
/// the relaxation background, not a resonance. A declared peak needs no
/// samples in its half-power band here: it is only a start for the
/// refinement, which fits the time samples.
pub(super) fn merge_decay_peaks(sc: &Scaled, initial: &mut Vec<Complex64>) {
    let n = sc.y.len();
    let m = n.next_power_of_two();
    let mut re: Vec<f64> = sc.y.iter().map(|v| v.re).chain(std::iter::repeat(0.0)).take(m).collect();
    let mut im = vec![0.0; m];
    thermal::fft(&mut re, &mut im);
    // bin k: ω̃ = 2πk/(m·π) = 2k/m in the scaled units (time step π, Nyquist 1)
    let x: Vec<f64> = (0..=m / 2).map(|k| 2.0 * k as f64 / m as f64).collect();
    let y: Vec<Complex64> = (0..=m / 2).map(|k| Complex64::new(re[k], im[k])).collect();
    let mut declared = peaks::detect(&x, &y, peaks::Series::Complex);
    declared.retain(|p| p.index >= 3);
    declared.sort_by(|a, b| b.statistic.total_cmp(&a.statistic));
    declared.truncate(MAX_DECLARED);
    for peak in declared {
        let (w, sigma) = (peak.pole.im, -peak.pole.re);
        let known = is_known(initial, w, sigma);
        if !known {
            initial.push(peak.pole);
        }
    }
    initial.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
}

/// Most declared peaks added to the initial poles (the clearest).
const MAX_DECLARED: usize = 8;

/// [`MAX_DECLARED`] for a PSD: a choice, not a derivation. Thermal records
/// reach `identify` cut to their flexural band (`thermal::flexural_band`),
/// where a short MD record's lowest flexural line can rank below the 8th
/// declared peak by statistic (tests/identify_md.md, round 3, with the cost
/// of the larger refinement); 16 keeps at most 4 × 16 pole parameters.
const MAX_DECLARED_PSD: usize = 16;

/// How far above its declaration threshold an under-sampled peak must stand
/// to refuse the record (see [`merge_peaks`]).
const REFUSE_FACTOR: f64 = 2.0;

/// A declared peak within this relative distance (or two half-widths) of a
/// diagram mode is that mode.
pub(super) const FREQ_MERGE: f64 = 0.01;

/// Whether a resonance at ω = `w` with decay rate `sigma` is one of the
/// poles `initial` already: within [`FREQ_MERGE`] of one's |s|, or within
/// twice the wider of the two half-power half-widths.
pub(super) fn is_known(initial: &[Complex64], w: f64, sigma: f64) -> bool {
    initial.iter().any(|p| (p.norm() - w).abs() <= (FREQ_MERGE * w).max(2.0 * sigma.max(-p.re)))
}

/// The refusal of a resonance narrower than the sampling, in the record's
/// terms: the value is the resonance's half-power band, the count and what
/// found the resonance (`what`: a peak's height, a stable pole) go to the
/// allowed part (issue 69: the value slot held a sentence, 245 characters).
pub(super) fn under_sampled(sc: &Scaled, p: Complex64, count: usize, what: &str) -> InputError {
    let (lo, hi) = (p.im + p.re, p.im - p.re);
    let advice = match sc.kind {
        FitKind::Psd => "finer PSD bins (a longer record)",
        _ => "a denser sweep there",
    };
    InputError::new(
        "omega_rad_s",
        format!("[{:.4e}, {:.4e}] rad/s", lo * sc.x_ref, hi * sc.x_ref),
        format!(
            ">= {MIN_POINTS_PER_RESONANCE} samples (it has {count}) in this half-power band of {what} at {:.4e} rad/s: {advice}",
            p.im * sc.x_ref,
        ),
    )
}

/// Each initial mode needs [`MIN_POINTS_PER_RESONANCE`] samples in ω_d ± σ.
pub(super) fn check_points_per_resonance(sc: &Scaled, modes: &[Complex64]) -> Result<(), InputError> {
    for p in modes {
        let (lo, hi) = (p.im + p.re, p.im - p.re);
        let count = sc.x.iter().filter(|&&x| x >= lo && x <= hi).count();
        if count < MIN_POINTS_PER_RESONANCE {
            return Err(under_sampled(sc, *p, count, "a stable pole"));
        }
    }
    Ok(())
}
