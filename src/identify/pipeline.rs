//! The identification's pipeline: the phases of the module doc in order,
//! asking the caller's [`Stop`] between them.

use num_complex::Complex64;

use super::assemble::assemble;
use super::data::Measurement;
use super::decay::{with_missed_decay_poles, with_relocated_decay_poles};
use super::detect::{
    check_points_per_resonance, is_known, merge_decay_peaks, merge_peaks, stabilisation_diagram, FREQ_MERGE,
};
use super::projected::fit_projected;
use super::refine::{FitKind, Model, Stop};
use super::scaled::{scale, Scaled};
use super::select::{best_refinement, restart_from_prefix, reweight, stable_modes, without_growing_poles};
use super::stabilisation::Diagram;
use super::{Identification, IdentifyError, IdentifySettings, MIN_POINTS_PER_RESONANCE};
use crate::error::InputError;

/// Identifies the modes of a record.
pub fn identify(m: &Measurement, settings: &IdentifySettings) -> Result<Identification, IdentifyError> {
    identify_controlled(m, settings, &Stop::default())
}

/// [`identify`], asking `stop` between its phases (the stabilisation
/// diagram, the initial poles, the refinement, the noise model's reweighting)
/// and inside every least-squares fit at each residual evaluation ([`Stop`]),
/// and returning [`IdentifyError::Cancelled`] once it says yes (whatever a
/// fit it cut short would have reported). `stop` only reads a flag: a run it
/// never stops gives the same result as [`identify`]. (A closure, not
/// `bayes::Control`: this layer uses `error` only.)
pub fn identify_controlled(
    m: &Measurement,
    settings: &IdentifySettings,
    stop: &Stop,
) -> Result<Identification, IdentifyError> {
    match identify_until(m, settings, stop) {
        Err(_) if stop.requested() => Err(IdentifyError::Cancelled),
        result => result,
    }
}

/// The body of [`identify_controlled`].
fn identify_until(m: &Measurement, settings: &IdentifySettings, stop: &Stop) -> Result<Identification, IdentifyError> {
    let check = || if stop.requested() { Err(IdentifyError::Cancelled) } else { Ok(()) };
    if settings.modes == Some(0) {
        return Err(InputError::new("--modes", 0, ">= 1").into());
    }
    let sc = scale(m, stop);
    let diagram = stabilisation_diagram(&sc, settings.max_order)?;
    check()?;
    let mut lost = Vec::new();
    let first = attempt(m, settings, stop, &sc, &diagram, false, &mut lost);
    // a resolved PSD peak the first attempt lost with the narrow pole it had
    // merged into (see `attempt`) and whose line no identified mode holds:
    // the attempt again with the peak as a start, kept when it finds more
    // lines (a record whose result holds every such line is fitted once)
    let holds = |id: &Identification| {
        lost.iter().all(|p| {
            let (w, sigma) = (p.im * sc.x_ref, -p.re * sc.x_ref);
            id.found_omegas_rad_s.iter().any(|&f| (f - w).abs() <= (FREQ_MERGE * w).max(2.0 * sigma))
        })
    };
    match first {
        Err(IdentifyError::Cancelled) => Err(IdentifyError::Cancelled),
        first if lost.is_empty() || first.as_ref().is_ok_and(holds) => first,
        first => {
            check()?;
            match (first, attempt(m, settings, stop, &sc, &diagram, true, &mut Vec::new())) {
                (Ok(a), Ok(b)) if b.found_omegas_rad_s.len() > a.found_omegas_rad_s.len() => Ok(b),
                (Err(_), Ok(b)) => Ok(b),
                (first, _) => first,
            }
        }
    }
}

/// One identification from the stabilisation diagram: its poles, the
/// declared peaks ([`merge_peaks`]), the refinement, the reweighting and the
/// report. Also pushes onto `lost` the resolved PSD peaks lost with a narrow pole:
/// `merge_peaks` deduplicates a declared peak against a diagram pole within
/// its width, and a PSD pole whose half-power band then holds fewer than
/// [`MIN_POINTS_PER_RESONANCE`] samples is dropped as the periodogram's
/// scatter, taking the peak's line with it (issue 69, defect 11: a PSD of a
/// simply supported tube lost mode 4 so, its diagram pole at 0.6 of the
/// line's ζ). A peak counts when it is itself resolved (≥
/// [`MIN_POINTS_PER_RESONANCE`] samples above its half-power level, and its
/// own band holds as many) and no kept pole is within its merge distance;
/// with `restore` those peaks join the initial poles. Restoring them always
/// (or dropping the narrow poles before the merge, which has the same
/// effect) was measured to lose mode 3 of the cc11 MD record, whose result
/// holds the restored line (mode 11) without it: the two starts split
/// mode 3's line between two background poles.
fn attempt(
    m: &Measurement,
    settings: &IdentifySettings,
    stop: &Stop,
    sc: &Scaled,
    diagram: &Diagram,
    restore: bool,
    lost: &mut Vec<Complex64>,
) -> Result<Identification, IdentifyError> {
    let check = || if stop.requested() { Err(IdentifyError::Cancelled) } else { Ok(()) };
    let diagram = diagram.clone();
    // PSD: a Welch bin's relative sd 1/√ν (0.22 for ν = 20) moves LSCF's
    // damping estimates between orders by more than DAMPING_TOL, so that 9 of
    // 60 PSDs of the paper's beam (1 500 bins, ν = 20) kept fewer than 3 of
    // their 3 modes; a cluster stable in frequency over half the orders is
    // accepted, the refinement and the residue SNR (or `--modes K`) decide.
    let from_diagram = diagram.modes(0.0, 1.0, sc.kind == FitKind::Psd);
    let mut initial = from_diagram.clone();
    let mut shadowed = Vec::new();
    if sc.kind == FitKind::Time {
        merge_decay_peaks(sc, &mut initial);
    } else {
        shadowed = merge_peaks(sc, &mut initial)?;
    }
    if sc.kind == FitKind::Psd {
        // a PSD's line spans at least the window's main lobe: a pole of the
        // diagram narrower than the bins is the periodogram's scatter, stable
        // in frequency only (measured: 3 of 12 PSDs with a white floor were
        // refused for such a pole at 0–1 samples, their modes all found apart)
        let resolved = |p: &Complex64| {
            let (lo, hi) = (p.im + p.re, p.im - p.re);
            p.norm() > sc.band.1 || sc.x.iter().filter(|&&x| x >= lo && x <= hi).count() >= MIN_POINTS_PER_RESONANCE
        };
        initial.retain(resolved);
        for p in shadowed {
            let (w, sigma) = (p.im, -p.re);
            let known = is_known(&initial, w, sigma);
            if !known && resolved(&p) {
                lost.push(p);
            }
        }
        if restore {
            initial.extend(lost.iter().copied());
            initial.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
        }
    }
    let in_band = initial.iter().filter(|p| p.norm() >= sc.band.0 && p.norm() <= sc.band.1).count();
    if in_band == 0 {
        return Err(InputError::new(
            m.abscissa_name(),
            format!("{} samples", m.len()),
            "a record with at least one resonance stable in the stabilisation diagram (these have none)",
        )
        .into());
    }
    if let Some(k) = settings.modes {
        if k > in_band {
            return Err(
                InputError::new("--modes", k, format!("<= {in_band} (the stable modes this record supports)")).into()
            );
        }
    }
    if sc.kind != FitKind::Time {
        let band: Vec<Complex64> = initial.iter().copied().filter(|p| p.norm() <= sc.band.1).collect();
        check_points_per_resonance(sc, &band)?;
    }
    check()?;
    let (model, fit) = match best_refinement(sc, &initial) {
        Ok(v) => v,
        Err(e) if sc.kind == FitKind::Time => match without_growing_poles(sc, &initial) {
            Some((kept, v)) => {
                initial = kept;
                v
            }
            None if initial.len() > from_diagram.len() && !from_diagram.is_empty() => {
                initial = from_diagram;
                match best_refinement(sc, &initial) {
                    Ok(v) => v,
                    Err(_) => restart_from_prefix(sc, &initial).ok_or(e)?,
                }
            }
            None => restart_from_prefix(sc, &initial).ok_or(e)?,
        },
        // declared peaks the refinement cannot hold stable: the diagram's
        // poles alone (the refinement recovers a missed mode through its
        // out-of-band poles, see `assemble`)
        Err(e) if initial.len() > from_diagram.len() && !from_diagram.is_empty() => {
            check()?;
            initial = from_diagram;
            best_refinement(sc, &initial).map_err(|_| e)?
        }
        Err(e) => return Err(e),
    };
    check()?;
    let (mut model, mut fit, mut noise_model, mut n_identified) = reweight(sc, model, fit, initial.len());
    check()?;
    if sc.kind == FitKind::Time && settings.modes.is_none() {
        let relocated = with_relocated_decay_poles(&model, &fit, n_identified);
        let start = relocated.as_ref().unwrap_or(&fit);
        let changed = with_missed_decay_poles(&model, start, n_identified)
            .or_else(|| relocated.as_ref().map(|f| (model.clone(), f.theta.clone(), n_identified)));
        if let Some((augmented, theta, n)) = changed {
            // the noise model is chosen again on the fit that holds them: the
            // unweighted refit from the augmented poles, then the reweighting
            let plain = Model { weights: None, ..augmented };
            if let Some(f) = fit_projected(&plain, &theta).filter(|f| stable_modes(f, n)) {
                (model, fit, noise_model, n_identified) = reweight(sc, plain, f, n);
            }
        }
        check()?;
    }
    assemble(m, sc, (&model, &fit), diagram, n_identified, settings.modes, noise_model)
}
