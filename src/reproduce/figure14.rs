//! Figure 14: FRF of the Case-3 reference beam against the posterior
//! predictive FRFs of the calibrated models (§4.3).

use rayon::prelude::*;

use crate::beam::{self, BeamSpec};
use crate::report::svg::{self, Axis, Band, LinePlot, RefLine, Series};
use crate::reproduce::cases::{truth_beam, CaseOutcome};
use crate::reproduce::error::ReproduceError;
use crate::reproduce::reconstruction::{ghz_to_rad_s, Reconstruction};
use crate::reproduce::results::Figure14Result;
use crate::reproduce::specs::{FrfSpec, Specs};

/// Figure 14's numbers and files.
pub struct FrfOutcome {
    pub result: Figure14Result,
    pub files: Vec<(String, String)>,
    /// Fraction of grid frequencies up to the 4th reference mode where the reference lies in the 99 % envelope.
    pub coverage_to_mode_4: f64,
    pub mode_4_ghz: f64,
}

/// Posterior predictive |H| of a case: the curves and their pointwise mean,
/// 0.5 % and 99.5 % quantiles.
struct Predictive {
    curves: Vec<Vec<f64>>,
    mean: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
}

fn abs_frf(fs: &FrfSpec, b: &BeamSpec, w: &[f64]) -> Option<Vec<f64>> {
    let l = b.length_nm;
    beam::frf(b, fs.input_x_fraction * l, fs.output_x_fraction * l, w)
        .ok()
        .map(|h| h.iter().map(|z| z.norm()).collect())
}

/// |H| at `k` posterior draws (evenly spaced over the pooled kept draws).
fn predictive(fs: &FrfSpec, c: &CaseOutcome, w: &[f64], k: usize) -> Predictive {
    let n = w.len();
    let draws: Vec<Vec<f64>> = c.result.kept_draws().into_iter().flatten().collect();
    let k = k.min(draws.len());
    let step = (draws.len() / k.max(1)).max(1);
    let picked: Vec<&Vec<f64>> = draws.iter().step_by(step).take(k).collect();
    let curves: Vec<Vec<f64>> = picked.par_iter().filter_map(|t| abs_frf(fs, &c.posterior.beam_at(t), w)).collect();
    let (mut mean, mut lo, mut hi) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for i in 0..n {
        let mut col: Vec<f64> = curves.iter().map(|c| c[i]).collect();
        col.sort_by(f64::total_cmp);
        mean[i] = col.iter().sum::<f64>() / col.len() as f64;
        lo[i] = crate::bayes::diagnostics::quantile_sorted(&col, 0.005);
        hi[i] = crate::bayes::diagnostics::quantile_sorted(&col, 0.995);
    }
    Predictive { curves, mean, lo, hi }
}

/// The reference and the predictive FRFs of the spec's case (and of its `-N2` sibling when run).
pub fn frf_stage(
    specs: &Specs,
    rec: &Reconstruction,
    cases: &[CaseOutcome],
    quick: bool,
) -> Result<FrfOutcome, ReproduceError> {
    let fs = &specs.frf;
    let case = cases.iter().find(|c| c.spec.id == fs.case).expect("validated case id");
    let reference = truth_beam(&case.spec, rec);
    let n = if quick { fs.quick_points } else { fs.points };
    let f_ghz: Vec<f64> = (0..n).map(|i| fs.from_ghz + (fs.to_ghz - fs.from_ghz) * i as f64 / (n - 1) as f64).collect();
    let w: Vec<f64> = f_ghz.iter().map(|f| ghz_to_rad_s(*f)).collect();
    let href =
        abs_frf(fs, reference, &w).ok_or_else(|| ReproduceError::Failure("Figure 14: reference FRF failed".into()))?;
    let k = if quick { fs.quick_posterior_draws } else { fs.posterior_draws };
    let n1 = predictive(fs, case, &w, k);
    let n2 = cases.iter().find(|c| c.spec.id == format!("{}-N2", fs.case)).map(|c| predictive(fs, c, &w, k));
    let mode_4_ghz = beam::modal(reference, 4).map(|m| m.modes[3].omega_rad_s / ghz_to_rad_s(1.0)).unwrap_or(f64::NAN);
    let upto: Vec<usize> = (0..n).filter(|&i| f_ghz[i] <= mode_4_ghz * 1.02).collect();
    let coverage = |p: &Predictive| {
        upto.iter().filter(|&&i| href[i] >= p.lo[i] && href[i] <= p.hi[i]).count() as f64 / upto.len().max(1) as f64
    };
    // RMS of log10|H_mean| − log10|H_ref| up to mode 4: the FRF error of a model's mean prediction.
    let log_rms = |m: &[f64]| {
        (upto.iter().map(|&i| (m[i].log10() - href[i].log10()).powi(2)).sum::<f64>() / upto.len().max(1) as f64).sqrt()
    };
    let coverage_to_mode_4 = coverage(&n1);
    let result = Figure14Result {
        mode_4_ghz,
        coverage_to_mode_4,
        draws: n1.curves.len(),
        points: n,
        log10_rms_error_to_mode_4_n1: log_rms(&n1.mean),
        log10_rms_error_to_mode_4_n2: n2.as_ref().map(|p| log_rms(&p.mean)),
        coverage_to_mode_4_n2: n2.as_ref().map(coverage),
    };
    let plot = figure(&f_ghz, &href, &n1, n2.as_ref(), mode_4_ghz);
    let mut csv = String::from("f_ghz,reference_m_per_n,mean_m_per_n,lower_0_5_m_per_n,upper_99_5_m_per_n\n");
    for i in 0..n {
        csv += &format!("{},{:e},{:e},{:e},{:e}\n", f_ghz[i], href[i], n1.mean[i], n1.lo[i], n1.hi[i]);
    }
    Ok(FrfOutcome {
        result,
        files: vec![("figure-14.svg".into(), svg::line_plot(&plot)?), ("figure-14.csv".into(), csv)],
        coverage_to_mode_4,
        mode_4_ghz,
    })
}

fn figure(f_ghz: &[f64], href: &[f64], n1: &Predictive, n2: Option<&Predictive>, mode_4_ghz: f64) -> LinePlot {
    let x = f_ghz.to_vec();
    let realizations: Vec<Series> = n1
        .curves
        .iter()
        .take(40)
        .enumerate()
        .map(|(j, c)| Series { name: format!("draw {j}"), x: x.clone(), y: c.clone() })
        .collect();
    let mut series = vec![
        Series { name: "reference (N̄ = 2)".into(), x: x.clone(), y: href.to_vec() },
        Series { name: "predictive mean (N = 1, β-inflated)".into(), x: x.clone(), y: n1.mean.clone() },
    ];
    if let Some(p) = n2 {
        series.push(Series { name: "predictive mean (N = 2, β = 1)".into(), x: x.clone(), y: p.mean.clone() });
    }
    LinePlot {
        title: "Figure 14: FRF |H| (m/N), reference N̄ = 2 vs calibrated N = 1 (Case 3)".into(),
        x_axis: Axis::linear("f (GHz)"),
        y_axis: Axis::log("|H| (m/N)"),
        series,
        realizations,
        band: Some(Band { name: "99 % envelope".into(), x: x.clone(), lower: n1.lo.clone(), upper: n1.hi.clone() }),
        ref_lines: vec![RefLine::Vertical(mode_4_ghz)],
        ..LinePlot::default()
    }
}
