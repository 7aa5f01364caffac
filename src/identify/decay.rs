//! Free decays: poles the fit left out, found in the weighted residuals
//! by the likelihood's own score, and decay poles relocated.

use num_complex::Complex64;

use super::detect::FREQ_MERGE;
use super::projected::fit_projected;
use super::refine::{FitResult, Model, PER_MODE};
use super::select::stable_modes;
use super::thermal;

/// Most poles [`with_missed_decay_poles`] adds to a free decay's fit.
const MAX_MISSED_POLES: usize = 3;

/// False-alarm probability per record of [`with_missed_decay_poles`]'s
/// search (the whole search over frequency and decay rate).
const MISSED_POLE_FALSE_ALARM: f64 = 0.01;

/// Decay rates of the missed-pole search, as σ̃·t̃_end (the number of
/// e-foldings over the record): octaves from a pole that barely decays to
/// one that lives a few samples in 4 000 (e.g. ζ = 2 % at 0.7 Nyquist,
/// σ̃·t̃_end ≈ 170 over 4 000 samples).
const MISSED_POLE_DECAYS: [f64; 11] = [0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0, 256.0, 512.0];

/// A free decay's fit that left out a mode the record holds: the poles the
/// matrix pencil and the spectrum's peaks start from can miss a true mode
/// below the anti-alias cut-off, and the fit then bends the other modes to
/// absorb its signal: their intervals under-cover because they are biased,
/// not because the covariance is wrong (under proportional noise, where the
/// weights put most of the information at the signal's zero crossings, most
/// of the study's under-coverage came from such records;
/// tests/identify_coverage.md).
///
/// The search is the likelihood's own: for a pole p = −σ + iω not in the
/// fit, the weighted least-squares gain of adding it (residues free) is, to
/// first order, the score S(ω, σ) = |Σ_i w_i r̃_i e^{(−σ − iω)t_i}|² / (½ Σ_i w_i² e^{−2σt_i}) / σ̂²
/// (r̃ the weighted residuals, w the weights, σ̂² their variance), a χ²₂
/// variable where no pole is missing. It is evaluated on a 4× zero-padded
/// DFT grid for each rate of [`MISSED_POLE_DECAYS`], away from the fit's
/// own poles. The best candidate is kept when S exceeds u = 2 ln(N/α), with
/// N = (n/2)·(number of rates) independent χ²₂ tests and α =
/// [`MISSED_POLE_FALSE_ALARM`] (Bonferroni: P(max S > u) ≤ N e^{−u/2} = α; the
/// padded grid and the neighbouring rates are correlated, so fewer
/// tests are made in effect and the bound is conservative), and then only when
/// the weighted refit with it lowers the RSS by at least u σ̂² and keeps
/// every pole stable. Up to [`MAX_MISSED_POLES`] rounds. Returns the
/// augmented model (its weights as in `model`), its fitted θ and the new
/// number of identified poles, or `None` when nothing was added.
pub(super) fn with_missed_decay_poles(
    model: &Model,
    fit: &FitResult,
    n_identified: usize,
) -> Option<(Model, Vec<f64>, usize)> {
    let u = missed_pole_bar(model.x.len());
    let (mut model, mut fit, mut n_id) = (model.clone(), fit.clone(), n_identified);
    let mut added = false;
    for _ in 0..MAX_MISSED_POLES {
        let own: Vec<usize> = (0..model.n_modes).collect();
        let Some((_, pole)) = best_missing_pole(&model, &fit.theta, fit.noise_var, &own).filter(|&(s, _)| s > u) else {
            break;
        };
        // the new pole goes after the identified ones (their order is kept)
        let mut theta = Vec::with_capacity(fit.theta.len() + PER_MODE);
        theta.extend_from_slice(&fit.theta[..PER_MODE * n_id]);
        theta.extend_from_slice(&[-pole.re, pole.im, 0.0, 0.0]);
        theta.extend_from_slice(&fit.theta[PER_MODE * n_id..]);
        let bigger = Model { n_modes: model.n_modes + 1, ..model.clone() };
        let Some(f) = fit_projected(&bigger, &theta) else { break };
        let gain = (fit.rss - f.rss) / f.noise_var.max(f64::MIN_POSITIVE);
        if !(stable_modes(&f, n_id + 1) && gain >= u) {
            break;
        }
        (model, fit, n_id) = (bigger, f, n_id + 1);
        added = true;
    }
    added.then_some((model, fit.theta, n_id))
}

/// The bar u = 2 ln(N/α) of [`with_missed_decay_poles`]'s score for a
/// record of `n` samples (N = (n/2)·(number of rates) tests).
pub(super) fn missed_pole_bar(n: usize) -> f64 {
    let tests = (n as f64 / 2.0) * MISSED_POLE_DECAYS.len() as f64;
    2.0 * (tests / MISSED_POLE_FALSE_ALARM).ln()
}

/// The highest score S(ω, σ) of [`with_missed_decay_poles`] over the DFT
/// grid and the decay rates, for the weighted residuals of `model` at
/// `theta` with noise variance `noise_var`, away from the poles `own`
/// (indices of the oscillatory poles of `theta`): the score and the pole.
pub(super) fn best_missing_pole(
    model: &Model,
    theta: &[f64],
    noise_var: f64,
    own: &[usize],
) -> Option<(f64, Complex64)> {
    let n = model.x.len();
    let m = 4 * n.next_power_of_two();
    let weights: Vec<f64> = model.weights.clone().unwrap_or_else(|| vec![1.0; n]);
    let t_end = model.x[n - 1].max(f64::MIN_POSITIVE);
    let (r, _) = model.eval(theta, false);
    let var = noise_var.max(f64::MIN_POSITIVE);
    // the fit's own poles: (ω̃_d, half-width) of each
    let own: Vec<(f64, f64)> = own.iter().map(|&k| (theta[PER_MODE * k + 1], theta[PER_MODE * k].abs())).collect();
    let mut best: Option<(f64, Complex64)> = None;
    for &decays in &MISSED_POLE_DECAYS {
        let sigma = decays / t_end;
        let mut re: Vec<f64> =
            (0..m).map(|i| if i < n { weights[i] * r[i] * (-sigma * model.x[i]).exp() } else { 0.0 }).collect();
        let mut im = vec![0.0; m];
        thermal::fft(&mut re, &mut im);
        let norm: f64 = (0..n).map(|i| (weights[i] * (-sigma * model.x[i]).exp()).powi(2)).sum::<f64>() * 0.5;
        if !(norm > 0.0) {
            continue;
        }
        // bin k: ω̃ = 2k/m (time step π, Nyquist 1); DC and Nyquist left out
        for k in 3..m / 2 - 3 {
            let w = 2.0 * k as f64 / m as f64;
            if own.iter().any(|&(wd, half)| near_pole(w, wd, half, sigma)) {
                continue;
            }
            let score = (re[k] * re[k] + im[k] * im[k]) / norm / var;
            if best.is_none_or(|(s, _)| score > s) {
                best = Some((score, Complex64::new(-sigma, w)));
            }
        }
    }
    best
}

/// Whether the grid frequency `w` of the missed-pole search, at decay rate
/// `sigma`, lies within the neighbourhood of a fitted pole (ω̃_d `wd`,
/// half-width `half`) that the search leaves out.
pub(super) fn near_pole(w: f64, wd: f64, half: f64, sigma: f64) -> bool {
    (w - wd).abs() <= (FREQ_MERGE * wd).max(2.0 * half.max(sigma))
}

/// A free decay's fit with an oscillatory pole stuck away from the mode it
/// stands for: a lightly damped mode that decays in a few dozen samples
/// gives its pole no gradient towards the true frequency from a few
/// half-widths off, and under proportional noise (the weights put the
/// information at the signal's zero crossings) a start that far off stays
/// there, as a false mode beside the true one, which the missed-pole search
/// then leaves out as the pole's neighbourhood (tests/identify_coverage.md:
/// every false mode of the ring-down / proportional study, 6–15 % from a
/// true mode the fit did not hold).
///
/// Each pole k in turn is taken out (the residues of the rest re-solved
/// linearly), and the missed-pole score [`best_missing_pole`] of the
/// residuals is evaluated away from the other poles. When its best
/// candidate passes the same bar u and lies outside pole k's own
/// neighbourhood, the fit is repeated with pole k started there, and kept
/// when its RSS is lower and every identified pole stays stable (the same
/// number of parameters: a lower RSS is a higher likelihood). Returns the
/// relocated fit (same model), or `None` when no pole moved.
pub(super) fn with_relocated_decay_poles(model: &Model, fit: &FitResult, n_identified: usize) -> Option<FitResult> {
    let u = missed_pole_bar(model.x.len());
    let mut current = fit.clone();
    let mut moved = false;
    let smaller = Model { n_modes: model.n_modes.checked_sub(1)?, ..model.clone() };
    for k in 0..model.n_modes {
        let o = PER_MODE * k;
        let mut without: Vec<f64> = current.theta.clone();
        without.drain(o..o + PER_MODE);
        let Some(without) = smaller.solve_linear(&without) else { continue };
        let others: Vec<usize> = (0..smaller.n_modes).collect();
        let Some((score, pole)) = best_missing_pole(&smaller, &without, current.noise_var, &others) else { continue };
        let (wd, half) = (current.theta[o + 1], current.theta[o].abs());
        if !(score > u) || near_pole(pole.im, wd, half, -pole.re) {
            continue;
        }
        let mut theta = current.theta.clone();
        theta[o..o + PER_MODE].copy_from_slice(&[-pole.re, pole.im, 0.0, 0.0]);
        let Some(f) = fit_projected(model, &theta) else { continue };
        if f.rss < current.rss && stable_modes(&f, n_identified) {
            current = f;
            moved = true;
        }
    }
    moved.then_some(current)
}
