//! The diagnosis report: Markdown rendered with tera from
//! `paper/templates/diagnose.md.tera` (compiled in) plus SVG plots (plotters):
//! residuals before/after, class probabilities, the extended model's posterior.
//! The directory is written atomically (sibling temp dir, then rename), so a
//! failure leaves an existing DIR untouched.

use std::path::Path;

use plotters::prelude::*;
use serde::Serialize;
use statrs::distribution::{ContinuousCDF, Normal};

use crate::calibration::MeasuredData;

use super::{DiagnoseSettings, DiagnosisRun, ModelClass};

const TEMPLATE: &str = include_str!("../../paper/templates/diagnose.md.tera");

#[derive(Serialize)]
struct Row {
    mode: usize,
    quantity: &'static str,
    z_before: f64,
    p_before: String,
    z_after: f64,
    p_after: String,
}

#[derive(Serialize)]
struct Cand {
    extension: String,
    log_evidence: f64,
    laplace: String,
    log_bayes_factor: f64,
    probability: f64,
}

#[derive(Serialize)]
struct PostRow {
    name: String,
    mean: String,
    sd: String,
    lo: String,
    hi: String,
}

fn fmt_opt(v: Option<f64>) -> String {
    v.map_or("—".to_string(), |x| format!("{x:.2}"))
}

/// |z| matching a two-sided p-value `alpha`.
fn z_of(alpha: f64) -> f64 {
    Normal::new(0.0, 1.0).expect("standard normal").inverse_cdf(1.0 - alpha / 2.0)
}

/// The Markdown report.
pub fn markdown(run: &DiagnosisRun, data: &MeasuredData, s: &DiagnoseSettings) -> Result<String, String> {
    let d = &run.diagnosis;
    let rows: Vec<Row> = d
        .misfit
        .iter()
        .zip(&d.gain.misfit_after)
        .map(|(b, a)| Row {
            mode: b.mode,
            quantity: b.quantity,
            z_before: b.z,
            p_before: format!("{:.2e}", b.ppp),
            z_after: a.z,
            p_after: format!("{:.2e}", a.ppp),
        })
        .collect();
    let cands: Vec<Cand> = d
        .candidates
        .iter()
        .map(|c| Cand {
            extension: c.extension.clone(),
            log_evidence: c.log_evidence,
            laplace: fmt_opt(c.log_evidence_laplace),
            log_bayes_factor: c.log_bayes_factor,
            probability: c.probability,
        })
        .collect();
    let gain_c = d.candidates.iter().find(|c| c.extension == d.gain.extension).expect("gain class is a candidate");
    let post: Vec<PostRow> = gain_c
        .posterior
        .iter()
        .map(|(name, p)| PostRow {
            name: name.clone(),
            mean: format!("{:.4e}", p.mean),
            sd: format!("{:.3e}", p.sd),
            lo: format!("{:.4e}", p.ci95[0]),
            hi: format!("{:.4e}", p.ci95[1]),
        })
        .collect();
    let mut ctx = tera::Context::new();
    ctx.insert("d", d);
    ctx.insert("rows", &rows);
    ctx.insert("cands", &cands);
    ctx.insert("post", &post);
    ctx.insert("base_laplace", &fmt_opt(d.base.log_evidence_laplace));
    ctx.insert("baseline_laplace", &fmt_opt(d.baseline.log_evidence_laplace));
    ctx.insert("z_threshold", &z_of(d.thresholds.per_test_alpha_sidak));
    ctx.insert("n_fitted", &d.misfit.len());
    ctx.insert("fitted_modes", &data.modes.iter().map(|m| m.mode.to_string()).collect::<Vec<_>>().join(", "));
    ctx.insert(
        "held_out_modes",
        &data.held_out_modes.iter().map(|m| m.mode.to_string()).collect::<Vec<_>>().join(", "),
    );
    ctx.insert("seed", &s.seed.unwrap_or(data.sampler.seed));
    ctx.insert("samples", &s.samples);
    ctx.insert("mh_steps", &s.mh_steps);
    tera::Tera::one_off(TEMPLATE, &ctx, false).map_err(|e| format!("template: {e:?}"))
}

fn svg_err<E: std::fmt::Debug>(e: E) -> String {
    format!("plot: {e:?}")
}

/// Standardized residual per observable, base vs extended, with the Šidák |z| band.
pub fn residuals_svg(run: &DiagnosisRun) -> Result<String, String> {
    let d = &run.diagnosis;
    let zt = z_of(d.thresholds.per_test_alpha_sidak);
    let n = d.misfit.len();
    let zmax = d.misfit.iter().chain(&d.gain.misfit_after).map(|c| c.z.abs()).fold(zt, f64::max) * 1.1;
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (760, 420)).into_drawing_area();
        root.fill(&WHITE).map_err(svg_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption("Standardized residuals per observable", ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(-0.5f64..(n as f64 - 0.5), -zmax..zmax)
            .map_err(svg_err)?;
        let labels: Vec<String> =
            d.misfit.iter().map(|c| format!("{}{}", if c.quantity == "omega" { "ω" } else { "ζ" }, c.mode)).collect();
        chart
            .configure_mesh()
            .x_labels(n)
            .x_label_formatter(&|x| labels.get(x.round() as usize).cloned().unwrap_or_default())
            .y_desc("z")
            .draw()
            .map_err(svg_err)?;
        for sign in [-1.0, 1.0] {
            chart
                .draw_series(LineSeries::new(vec![(-0.5, sign * zt), (n as f64 - 0.5, sign * zt)], RED.stroke_width(1)))
                .map_err(svg_err)?;
        }
        chart
            .draw_series(d.misfit.iter().enumerate().map(|(i, c)| Circle::new((i as f64 - 0.1, c.z), 5, BLUE.filled())))
            .map_err(svg_err)?
            .label("base")
            .legend(|(x, y)| Circle::new((x, y), 5, BLUE.filled()));
        chart
            .draw_series(
                d.gain
                    .misfit_after
                    .iter()
                    .enumerate()
                    .map(|(i, c)| TriangleMarker::new((i as f64 + 0.1, c.z), 6, GREEN.filled())),
            )
            .map_err(svg_err)?
            .label(d.gain.extension.as_str())
            .legend(|(x, y)| TriangleMarker::new((x, y), 6, GREEN.filled()));
        chart.configure_series_labels().border_style(BLACK).background_style(WHITE).draw().map_err(svg_err)?;
        root.present().map_err(svg_err)?;
    }
    Ok(s)
}

/// Posterior class probabilities (base + causes).
pub fn probabilities_svg(run: &DiagnosisRun) -> Result<String, String> {
    let d = &run.diagnosis;
    let mut bars: Vec<(String, f64)> = vec![("base".into(), d.base.probability)];
    bars.extend(d.candidates.iter().map(|c| (c.extension.clone(), c.probability)));
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (760, 360)).into_drawing_area();
        root.fill(&WHITE).map_err(svg_err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption("Posterior class probabilities", ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(-0.5f64..(bars.len() as f64 - 0.5), 0.0f64..1.05)
            .map_err(svg_err)?;
        chart
            .configure_mesh()
            .x_labels(bars.len())
            .x_label_formatter(&|x| bars.get(x.round() as usize).map(|b| b.0.clone()).unwrap_or_default())
            .y_desc("P(M | y)")
            .draw()
            .map_err(svg_err)?;
        chart
            .draw_series(
                bars.iter().enumerate().map(|(i, b)| {
                    Rectangle::new([(i as f64 - 0.35, 0.0), (i as f64 + 0.35, b.1)], BLUE.mix(0.7).filled())
                }),
            )
            .map_err(svg_err)?;
        root.present().map_err(svg_err)?;
    }
    Ok(s)
}

/// Marginal histograms of the extended model's parameters (log10 for log-uniform ones).
pub fn posterior_svg(run: &DiagnosisRun) -> Result<String, String> {
    let d = &run.diagnosis;
    let class = ModelClass::from_name(&d.gain.extension).expect("known class");
    let r = run.runs.iter().find(|r| r.class == class).expect("class ran");
    let names = r.posterior.params.set.names();
    let k = names.len();
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, (300 * k as u32, 300)).into_drawing_area();
        root.fill(&WHITE).map_err(svg_err)?;
        for (i, area) in root.split_evenly((1, k)).iter().enumerate() {
            let log = r.posterior.params.log_scale[i];
            let v: Vec<f64> =
                r.tmcmc.samples.iter().map(|u| if log { u[i] / std::f64::consts::LN_10 } else { u[i] }).collect();
            let (lo, hi) = v.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
            let (lo, hi) =
                if hi > lo { (lo, hi) } else { (lo - 0.5 * lo.abs().max(1e-300), hi + 0.5 * hi.abs().max(1e-300)) };
            let bins = 30;
            let w = (hi - lo) / bins as f64;
            let mut counts = vec![0usize; bins];
            for x in &v {
                counts[(((x - lo) / w) as usize).min(bins - 1)] += 1;
            }
            let top = *counts.iter().max().unwrap_or(&1) as f64 * 1.1;
            let label = if log { format!("log10 {}", names[i]) } else { names[i].clone() };
            let mut chart = ChartBuilder::on(area)
                .caption(label, ("sans-serif", 13))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(10)
                .build_cartesian_2d(lo..hi, 0.0..top)
                .map_err(svg_err)?;
            chart.configure_mesh().x_labels(4).y_labels(0).draw().map_err(svg_err)?;
            chart
                .draw_series(counts.iter().enumerate().map(|(b, &c)| {
                    let x0 = lo + b as f64 * w;
                    Rectangle::new([(x0, 0.0), (x0 + w, c as f64)], GREEN.mix(0.6).filled())
                }))
                .map_err(svg_err)?;
        }
        root.present().map_err(svg_err)?;
    }
    Ok(s)
}

/// Writes `report.md`, `diagnosis.json` and the three SVGs to `dir` atomically.
pub fn write_report(dir: &Path, run: &DiagnosisRun, data: &MeasuredData, s: &DiagnoseSettings) -> Result<(), String> {
    let files = vec![
        ("report.md", markdown(run, data, s)?),
        ("diagnosis.json", serde_json::to_string_pretty(&run.diagnosis).map_err(|e| e.to_string())?),
        ("residuals.svg", residuals_svg(run)?),
        ("probabilities.svg", probabilities_svg(run)?),
        ("posterior.svg", posterior_svg(run)?),
    ];
    write_dir_atomically(dir, &files).map_err(|e| format!("writing {}: {e}", dir.display()))
}

/// Writes `files` through the shared atomic writer
/// ([`crate::report::render::write_dir_atomically`]: marker file, swap lock,
/// signal cleanup); `dir` is left as it was on any error.
pub fn write_dir_atomically(dir: &Path, files: &[(&str, String)]) -> Result<(), crate::report::ReportError> {
    crate::report::render::write_dir_atomically(dir, |tmp| {
        for (f, content) in files {
            std::fs::write(tmp.join(f), content)
                .map_err(|e| crate::report::ReportError::Io { path: tmp.join(f), source: e })?;
        }
        Ok(())
    })
}
