//! The diagnosis report: Markdown from `paper/templates/diagnose.md.tera`
//! (compiled in, rendered by `report::render`) and figures by `report::svg`:
//! standardized residuals of the base and the assessed model, model
//! probabilities, and the assessed model's marginal posteriors. The directory
//! is written by `report::render::write_dir_atomically`, so a failure leaves
//! an existing DIR untouched.

use std::path::Path;

use serde::Serialize;
use serde_json::json;

use crate::calibration::{MeasuredData, ModeObservation};
use crate::report::render::{render_embedded, write_dir_atomically};
use crate::report::svg::{bar_chart, histogram, residual_plot, BarChart, HistogramPlot, NamedValues, ResidualPlot};
use crate::report::table::fmt_sig;
use crate::report::ReportError;

use super::{ppc, DiagnoseSettings, Diagnosis, DiagnosisRun};

const TEMPLATE: &str = include_str!("../../paper/templates/diagnose.md.tera");

#[derive(Serialize)]
struct Row {
    mode: usize,
    quantity: String,
    z_before: f64,
    p_before: String,
    z_after: f64,
    p_after: String,
}

#[derive(Serialize)]
struct PostRow {
    name: String,
    mean: String,
    sd: String,
    lo: String,
    hi: String,
    figure: String,
}

/// File name of the marginal-posterior figure of parameter `name`.
fn posterior_figure(name: &str) -> String {
    format!("posterior-{name}.svg")
}

/// The Markdown report.
pub fn markdown(run: &DiagnosisRun, data: &MeasuredData, s: &DiagnoseSettings) -> Result<String, ReportError> {
    let d = &run.diagnosis;
    let rows: Vec<Row> = d
        .misfit
        .iter()
        .zip(&d.gain.misfit_after)
        .map(|(b, a)| Row {
            mode: b.mode,
            quantity: match b.x_nm {
                Some(x) => format!("{} at {x:.2} nm", b.quantity),
                None => b.quantity.to_string(),
            },
            z_before: b.z,
            p_before: format!("{:.2e}", b.ppp),
            z_after: a.z,
            p_after: format!("{:.2e}", a.ppp),
        })
        .collect();
    let assessed = d.candidates.iter().find(|c| c.extension == d.gain.extension).unwrap_or(&d.base);
    let post: Vec<PostRow> = assessed
        .posterior
        .iter()
        .map(|(name, p)| PostRow {
            name: name.clone(),
            mean: fmt_sig(p.mean, 5),
            sd: fmt_sig(p.sd, 3),
            lo: fmt_sig(p.ci95[0], 5),
            hi: fmt_sig(p.ci95[1], 5),
            figure: posterior_figure(name),
        })
        .collect();
    let ctx = json!({
        "d": d,
        "noise_extension": super::Model::Baseline.name(),
        "causal_fitting": d.fitting_alternatives(false),
        "noise_fits": d.fitting_alternatives(true) > 0,
        "rows": rows,
        "post": post,
        "z_threshold": ppc::z_threshold(d.thresholds.per_test_alpha_sidak),
        "n_fitted": d.misfit.len(),
        "fitted_modes": mode_list(&data.modes),
        "held_out_modes": mode_list(&data.held_out_modes),
        "scans": data
            .mode_scans
            .iter()
            .map(|s| format!("scan of mode {}: {} points, drive at {:.2} nm", s.mode, s.points.len(), s.drive_x_nm))
            .collect::<Vec<_>>()
            .join("; "),
        "seed": s.seed.unwrap_or(data.sampler.seed),
        "samples": s.samples,
        "mh_steps": s.mh_steps,
        "screen_optimiser_margin": super::screen::OPTIMISER_MARGIN_NATS,
        "screen_laplace_margin": super::screen::LAPLACE_MARGIN_NATS,
        "next_max_mode": super::next::MAX_MODE,
        "next_min_separation_sd": super::next::MIN_SEPARATION_SD,
        "shape_grid": super::next::SHAPE_GRID,
        "mass_mirror_length_nm": assessed.point_mass_x_mirror_ambiguous.then_some(data.beam.length_nm),
        "section_sentence": assessed.section_mismatch.map(|r| r.sentence()),
    });
    render_embedded("diagnose.md.tera", TEMPLATE, &ctx)
}

/// Every figure of the report as (file name, SVG text).
pub fn figures(run: &DiagnosisRun) -> Result<Vec<(String, String)>, ReportError> {
    let d = &run.diagnosis;
    let label = |c: &ppc::Check| match (c.quantity, c.x_nm) {
        (_, Some(x)) => format!("A{}@{x:.2}", c.mode),
        ("omega", None) => format!("ω{}", c.mode),
        _ => format!("ζ{}", c.mode),
    };
    let residuals = residual_plot(&ResidualPlot {
        title: "Standardized residuals per observable".into(),
        labels: d.misfit.iter().map(label).collect(),
        groups: vec![
            NamedValues::new("base", d.misfit.iter().map(|c| c.z).collect()),
            NamedValues::new(d.gain.extension.clone(), d.gain.misfit_after.iter().map(|c| c.z).collect()),
        ],
        band: ppc::z_threshold(d.thresholds.per_test_alpha_sidak),
        ..ResidualPlot::default()
    })?;
    let mut bars = vec![("base".to_string(), d.base.probability)];
    bars.extend(d.candidates.iter().map(|c| (c.extension.clone(), c.probability)));
    let probabilities = bar_chart(&BarChart {
        title: "Posterior model probabilities".into(),
        y_label: "P(M | data) (-)".into(),
        categories: bars.iter().map(|b| b.0.clone()).collect(),
        values: bars.iter().map(|b| b.1).collect(),
        y_range: Some((0.0, 1.1)),
        size: (160 + 90 * bars.len() as u32, 450),
    })?;
    let mut out = vec![("residuals.svg".to_string(), residuals), ("probabilities.svg".to_string(), probabilities)];
    let assessed = super::Model::from_name(&d.gain.extension);
    if let Some(r) = assessed.and_then(|m| run.run_of(&m)) {
        let names = crate::bayes::Posterior::names(&r.posterior);
        for (k, name) in names.iter().enumerate() {
            let values: Vec<f64> = r.draws.iter().map(|u| r.posterior.to_inner(u)[k]).collect();
            let svg = histogram(&HistogramPlot {
                title: format!("Posterior of {name} under {}", d.gain.extension),
                x_label: name.clone(),
                groups: vec![NamedValues::new(d.gain.extension.clone(), values)],
                bins: 30,
                ..HistogramPlot::default()
            })?;
            out.push((posterior_figure(name), svg));
        }
    }
    Ok(out)
}

/// Writes `report.md`, `diagnosis.json` and the figures to `dir` atomically.
pub fn write_report(
    dir: &Path,
    run: &DiagnosisRun,
    data: &MeasuredData,
    s: &DiagnoseSettings,
) -> Result<(), ReportError> {
    let mut files = vec![
        ("report.md".to_string(), markdown(run, data, s)?),
        ("diagnosis.json".to_string(), serde_json::to_string_pretty(&run.diagnosis).expect("plain data") + "\n"),
    ];
    files.extend(figures(run)?);
    write_dir_atomically(dir, |tmp| {
        for (name, content) in &files {
            let path = tmp.join(name);
            std::fs::write(&path, content).map_err(|e| ReportError::io(&path, e))?;
        }
        Ok::<(), ReportError>(())
    })
}

/// The plain-text summary `nanobeam diagnose` prints without `--json`: the
/// verdict, the decided causes, the alternatives and whether each fits, the
/// next measurement, and the parameters on a prior bound.
pub fn summary(d: &Diagnosis) -> String {
    let mut t = format!(
        "misfit detected: {}\ncause: {}\nexplained: {}\nln B ({} vs base): {:.2}\nRMS z: {:.2} -> {:.2}\n",
        d.misfit_detected,
        d.cause,
        d.explained,
        d.gain.extension,
        d.gain.log_bayes_factor,
        d.gain.rms_z_before,
        d.gain.rms_z_after,
    );
    t += &format!(
        "chi2 of the fitted observables: {:.1} on {:.1} dof (p {:.2e}) -> {:.1} on {:.1} dof (p {:.2e}); misfit below p {}\n",
        d.misfit_omnibus.chi2,
        d.misfit_omnibus.dof,
        d.misfit_omnibus.p,
        d.gain.omnibus_after.chi2,
        d.gain.omnibus_after.dof,
        d.gain.omnibus_after.p,
        d.thresholds.omnibus_alpha,
    );
    if let Some(r) = d.candidates.iter().find(|c| c.extension == d.gain.extension).and_then(|c| c.section_mismatch) {
        t += &format!("section-mismatch: the tube {}\n", r.sentence());
    }
    if d.causes.len() > d.decided_causes.len() {
        let decided = if d.decided_causes.is_empty() { "none".to_string() } else { d.decided_causes.join(", ") };
        t += &format!("decided causes: {decided} (of {})\n", d.causes.join(", "));
        for u in &d.undecided {
            t += &format!("undecided: {}: {}\n", u.cause, u.reason);
        }
    }
    for a in &d.alternatives {
        let fit = match (a.misfits, a.is_noise()) {
            (true, _) => "; misfits, so no explanation",
            (false, true) => {
                "; noise larger than the stated sds explains the data about as well: repeat the \
                              measured modes to estimate their scatter"
            }
            (false, false) => "",
        };
        t += &format!("alternative: {} (ln B gap {:.2}{fit})\n", a.extension, a.log_bayes_factor_gap);
    }
    let fitting = d.fitting_alternatives(false);
    let causal = d.alternatives.iter().filter(|a| !a.is_noise()).count();
    match (&d.next_measurement, fitting == 0) {
        (Some(n), _) => {
            t += &format!(
                "next measurement: {} of mode {} ({:.1} sd apart under {} and {})\n",
                n.quantity, n.mode, n.separation_sd, n.between[0], n.between[1]
            )
        }
        (None, false) => {
            t += &format!(
                "next measurement: none of this kind (no omega or zeta of an unmeasured mode <= {} separates any \
                 alternative that fits by {} sd; a measurement of another kind is needed)\n",
                super::next::MAX_MODE,
                super::next::MIN_SEPARATION_SD
            );
            if let Some(m) = &d.shape_measurement {
                t += &format!(
                    "mode-shape measurement: scan mode {} at its resonance (drive at {:.2} nm); at x = {:.2} nm \
                     the amplitude relative to the largest is {:.4} under {} and {:.4} under {}; measured to \
                     +-{:.4} it decides (feed the scan back as `mode_scans`, points x = k L/{})\n",
                    m.mode,
                    m.drive_x_nm,
                    m.position_x_nm,
                    m.predicted_relative_amplitude[0],
                    m.between[0],
                    m.predicted_relative_amplitude[1],
                    m.between[1],
                    m.decisive_measurement_sd,
                    super::next::SHAPE_GRID
                );
            }
        }
        (None, true) if causal > 0 => t += "next measurement: none needed (every alternative misfits)\n",
        (None, true) => {}
    }
    if let Some(f) = &d.falsifying_measurement {
        let rivals: Vec<String> = f
            .rivals
            .iter()
            .map(|r| {
                format!("{} predicts {} ({:.1} sd apart)", r.model, crate::error::fmt_num(r.predicted), r.separation_sd)
            })
            .collect();
        t += &format!(
            "would falsify: {} of mode {}: {} predicts {}, 95% interval [{}, {}] (measured to +-{}); a value \
             outside it falsifies the verdict, which is decided only among the catalogue's classes; {}\n",
            f.quantity,
            f.mode,
            f.model,
            crate::error::fmt_num(f.predicted),
            crate::error::fmt_num(f.interval_95[0]),
            crate::error::fmt_num(f.interval_95[1]),
            crate::error::fmt_num(f.measurement_sd),
            rivals.join("; ")
        );
    }
    let assessed = d.candidates.iter().find(|c| c.extension == d.gain.extension);
    for h in assessed.map_or(&[][..], |c| &c.map_on_prior_bound) {
        t += &format!(
            "on a prior bound: {} = {} (bound {}) in {}: the data ask for more of this effect than its class \
             allows, so the effect may lie outside the catalogue\n",
            h.parameter,
            crate::error::fmt_num(h.map),
            crate::error::fmt_num(h.bound),
            d.gain.extension
        );
    }
    t
}

/// The observations of `modes` as the file lists them (for the report).
fn mode_list(modes: &[ModeObservation]) -> String {
    modes.iter().map(|m| m.mode.to_string()).collect::<Vec<_>>().join(", ")
}
