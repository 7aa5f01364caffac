//! The paper pipeline: specs → reconstruction → forward tables and maps →
//! calibration cases (in parallel) → FRF → audit → files and report.
//!
//! Everything is computed before anything is written; the output directory is
//! then built in a temporary sibling and renamed, so a failure leaves it as it
//! was.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use rand_distr::{Distribution, StandardNormal};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::{json, Value};

use crate::bayes::rng::{stream, Purpose};
use crate::beam::{self, BeamSpec, InternalVariable};
use crate::calibration::output::{summary_cells, write_calibration_files, SUMMARY_HEADERS};
use crate::calibration::{
    calibrate_posterior, BeamPosterior, CalibrateOptions, CalibrationResult, ModeObservation, ParameterSet, Target,
};
use crate::report::render::{render_template, write_dir_atomically};
use crate::report::svg::{
    self, Axis, Band, Heatmap, HistogramPlot, LinePlot, NamedValues, PairPlot, RefLine, Series, TracePlot,
};
use crate::report::table::{fmt_interval, fmt_sig, Table};
use crate::report::ReportError;
use crate::reproduce::reconstruction::{ghz_to_rad_s, reconstruct, Reconstruction};
use crate::reproduce::reference::Published;
use crate::reproduce::specs::{CaseSpec, Specs, Truth};

/// Where to read and write.
#[derive(Debug, Clone)]
pub struct Options {
    /// Repository root (holds `paper/`).
    pub root: PathBuf,
    pub out: PathBuf,
    pub quick: bool,
}

/// Why a reproduction stopped.
#[derive(Debug)]
pub enum ReproduceError {
    Input(String),
    Failure(String),
}

impl std::fmt::Display for ReproduceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReproduceError::Input(s) | ReproduceError::Failure(s) => write!(f, "{s}"),
        }
    }
}

impl From<ReportError> for ReproduceError {
    fn from(e: ReportError) -> Self {
        ReproduceError::Failure(e.to_string())
    }
}

/// One calibration case's outcome.
pub struct CaseOutcome {
    pub spec: CaseSpec,
    pub names: Vec<String>,
    /// True value of each parameter (NaN where the truth has no counterpart, e.g. β).
    pub truth: Vec<f64>,
    pub observations: Vec<ModeObservation>,
    pub result: CalibrationResult,
    pub posterior: BeamPosterior,
    pub seconds: f64,
}

/// One audit line.
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    pub id: String,
    pub claim: String,
    pub source: String,
    pub reproduced: String,
    pub tolerance: String,
    pub pass: bool,
    pub note: String,
}

/// What `run` returns (also written as results.json).
pub struct RunSummary {
    pub results: Value,
    pub verdicts: Vec<Verdict>,
    pub timings: Vec<(String, f64)>,
}

/// Runs the whole reproduction into `opts.out`.
pub fn run(opts: &Options) -> Result<RunSummary, ReproduceError> {
    let t_all = Instant::now();
    let mut timings: Vec<(String, f64)> = Vec::new();
    let mut stage = |name: &str, t: Instant| timings.push((name.to_string(), t.elapsed().as_secs_f64()));

    let t = Instant::now();
    let published = Published::load(&opts.root.join("paper/published.yaml"))
        .map_err(|e| ReproduceError::Input(format!("paper/published.yaml: {e}")))?;
    let specs = Specs::load(&opts.root.join("paper/specs")).map_err(|e| ReproduceError::Input(e.to_string()))?;
    let templates = opts.root.join("paper/templates");
    stage("load", t);

    let t = Instant::now();
    let rec = reconstruct(&specs.reconstruction, &published);
    let reconstructed_yaml = reconstructed_yaml(&rec, &specs);
    stage("reconstruction", t);

    let t = Instant::now();
    let forward = forward_stage(&specs, &rec, opts.quick)?;
    stage("table_2_figures_1_3", t);

    let t = Instant::now();
    let cases: Vec<CaseOutcome> =
        specs.cases.par_iter().map(|c| run_case(c, &rec, &published, opts.quick)).collect::<Result<_, _>>()?;
    stage("cases", t);

    let t = Instant::now();
    let frf = frf_stage(&specs, &rec, &cases, opts.quick)?;
    stage("figure_14", t);

    let t = Instant::now();
    let evidence = evidence_stage(&cases, opts.quick);
    stage("case_3_evidence", t);

    let t = Instant::now();
    let diagnosis = diagnosis_stage(&cases, &rec, opts.quick)?;
    stage("case_3_diagnosis", t);

    let t = Instant::now();
    let verdicts = audit(&published, &rec, &forward, &cases, &frf);
    stage("audit", t);
    timings.push(("total_before_writing".into(), t_all.elapsed().as_secs_f64()));

    let case_json: Vec<Value> = cases.iter().map(case_json).collect();
    let results = json!({
        "quick": opts.quick,
        "reconstruction": reconstruction_json(&rec),
        "table_2": forward.table2_rows,
        "cases": case_json,
        "figure_14": frf.json,
        "case_3_evidence": evidence,
        "case_3_diagnosis": diagnosis,
        "audit": verdicts,
        "timings_s": timings.iter().map(|(k, v)| (k.clone(), json!(v))).collect::<serde_json::Map<_, _>>(),
    });

    let mut context = report_context(&rec, &forward, &cases, &frf, &verdicts, &timings, opts.quick);
    context["case_3_evidence"] = evidence.clone();
    context["case_3_diagnosis"] = diagnosis.clone();
    let report = render_template(&templates, "report.md.tera", &context)?;

    write_dir_atomically(&opts.out, |dir: &Path| -> Result<(), ReproduceError> {
        let w = |name: &str, text: &str| -> Result<(), ReproduceError> {
            std::fs::write(dir.join(name), text).map_err(|e| ReproduceError::Failure(format!("{name}: {e}")))
        };
        w("reconstructed.yaml", &reconstructed_yaml)?;
        for (name, fit) in [("table-5", &rec.fit_table_4), ("table-10", &rec.fit_table_9)] {
            let t = fit_table(fit);
            w(&format!("{name}.csv"), &t.to_csv())?;
            w(&format!("{name}.md"), &t.to_markdown())?;
        }
        for (name, text) in &forward.files {
            w(name, text)?;
        }
        for (name, text) in case_group_files(&cases)? {
            w(&name, &text)?;
        }
        for (name, text) in &frf.files {
            w(name, text)?;
        }
        for c in &cases {
            let sub = dir.join(format!("case-{}", c.spec.id.to_lowercase()));
            std::fs::create_dir_all(&sub).map_err(|e| ReproduceError::Failure(e.to_string()))?;
            write_calibration_files(&sub, &c.result, Some(&c.truth))?;
        }
        w("results.json", &(serde_json::to_string_pretty(&results).expect("json") + "\n"))?;
        w("report.md", &report)?;
        Ok(())
    })?;
    // The generated, snapshot-checked copy of the reconstruction lives in paper/.
    std::fs::write(opts.root.join("paper/reconstructed.yaml"), &reconstructed_yaml)
        .map_err(|e| ReproduceError::Failure(format!("paper/reconstructed.yaml: {e}")))?;
    Ok(RunSummary { results, verdicts, timings })
}

// ---------------------------------------------------------------------------
// Reconstruction output
// ---------------------------------------------------------------------------

/// Rounds to `sig` significant digits.
fn round_sig(x: f64, sig: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let e = x.abs().log10().floor() as i32;
    let f = 10f64.powi(sig - 1 - e);
    (x * f).round() / f
}

/// Exact or closed-form numbers (printed references, their intervals, mode
/// frequencies of a fixed beam): 6 significant digits, stable against
/// last-bit differences.
fn r6(x: f64) -> f64 {
    round_sig(x, 6)
}

/// Fitted numbers: 5 significant digits. The Nelder–Mead fit stops when the
/// spread of −log L over its simplex is < 1e-12, which resolves a parameter
/// only to ~√(2e-12/curvature): the flattest direction (Ω of the σ-fit) moved
/// by 2.4e-6 relative when the forward model's round-off changed. Five digits
/// (half-step 5e-6 … 5e-5) sit above that and stay ≥ 10× below the σ-level
/// resolution of the fit (0.3 % frequency noise on three modes determines L,
/// the best-resolved parameter since ω ∝ L⁻², only to ≈ 0.1 %).
fn r5(x: f64) -> f64 {
    round_sig(x, 5)
}

fn reconstruction_json(rec: &Reconstruction) -> Value {
    let fit = |f: &crate::reproduce::reconstruction::Fit| {
        json!({
            "parameters": f.parameters.iter().map(|(n, v)| (n.clone(), json!(r5(*v)))).collect::<serde_json::Map<_, _>>(),
            "chi2": r5(f.chi2),
            "runner_up_chi2": f.runner_up_chi2.map(r5),
            "weighting": f.weighting,
            "all_within_rounding": f.all_within_rounding(),
            "values": f.values.iter().map(|v| json!({
                "mode": v.mode, "quantity": v.quantity, "reference": r6(v.reference),
                "interval": [r6(v.interval[0]), r6(v.interval[1])], "reproduced": r5(v.reproduced),
                "residual_sigma": (v.residual_sigma * 1000.0).round() / 1000.0, "within_rounding": v.within_rounding,
            })).collect::<Vec<_>>(),
        })
    };
    json!({
        "table_1": {
            "length_nm": r5(rec.table_1.length_nm), "diameter_nm": rec.table_1.diameter_nm,
            "youngs_modulus_pa": rec.table_1.youngs_modulus_pa, "density_kg_m3": rec.table_1.density_kg_m3,
        },
        "table_4_fit": fit(&rec.fit_table_4),
        "table_9_fit": fit(&rec.fit_table_9),
        "table_4_sigma_fit": fit(&rec.sigma_fit_table_4),
        "table_9_sigma_fit": fit(&rec.sigma_fit_table_9),
    })
}

fn reconstructed_yaml(rec: &Reconstruction, specs: &Specs) -> String {
    let header = "# GENERATED by `cargo xtask reproduce` (reproduce::reconstruction); do not edit.\n\
# Reference values (Tables 5, 10) are derived from the printed covariances; the lost\n\
# inputs (Tables 1, 4, 9) are their least-squares fit in units of the paper's sigma.\n";
    let body = json!({
        "fixed_assumptions": {
            "diameter_nm": specs.reconstruction.diameter_nm,
            "youngs_modulus_pa": specs.reconstruction.youngs_modulus_pa,
            "density_kg_m3": specs.reconstruction.density_kg_m3,
            "support": specs.reconstruction.support.name(),
            "elements": specs.reconstruction.elements,
            "frequency_unit": "the paper's GHz is cyclic frequency: omega_rad_s = 2*pi*1e9*GHz",
            "identifiable": "only EI/(rho A L^4) and e0a/L; L is fitted with d, E, rho held",
        },
        "reconstruction": reconstruction_json(rec),
    });
    header.to_string() + &serde_yaml::to_string(&body).expect("yaml")
}

// ---------------------------------------------------------------------------
// Table 2 and Figures 1–3
// ---------------------------------------------------------------------------

pub struct ForwardOutcome {
    pub table2_rows: Vec<Value>,
    pub table2_md: String,
    /// maps[r] = (ratio grid [e0a][Ω], zeta grid) for mode r+1.
    pub maps: Vec<(Vec<Vec<f64>>, Vec<Vec<f64>>)>,
    pub e0a: Vec<f64>,
    pub omega: Vec<f64>,
    pub local_omega: Vec<f64>,
    pub delta: f64,
    pub files: Vec<(String, String)>,
}

fn forward_stage(specs: &Specs, rec: &Reconstruction, quick: bool) -> Result<ForwardOutcome, ReproduceError> {
    let fs = &specs.forward;
    let local = rec.table_1.clone();
    let m = beam::modal(&local, fs.modes).map_err(|e| ReproduceError::Failure(format!("Table 2: {e}")))?;
    let local_omega: Vec<f64> = m.modes.iter().map(|x| x.omega_rad_s).collect();
    let mut t2 = Table::new(["mode", "omega_rad_s", "f_ghz"]);
    let mut rows = Vec::new();
    for (i, w) in local_omega.iter().enumerate() {
        t2.push_row([format!("{}", i + 1), fmt_sig(*w, 6), fmt_sig(w / ghz_to_rad_s(1.0), 6)]);
        rows.push(json!({"mode": i + 1, "omega_rad_s": r6(*w), "f_ghz": r6(w / ghz_to_rad_s(1.0))}));
    }
    let delta = fs.delta.unwrap_or_else(|| rec.truth_table_4.internal_variables[0].delta);
    let e0a = fs.e0a_nm.values(quick);
    let omega = fs.omega_rad_s.values(quick);
    let grid: Vec<Vec<Vec<(f64, f64)>>> = e0a
        .par_iter()
        .map(|&e| {
            omega
                .iter()
                .map(|&w| {
                    let mut b = local.clone();
                    b.nonlocal_e0a_nm = e;
                    b.internal_variables = vec![InternalVariable { delta, omega_rad_s: w }];
                    match beam::modal(&b, fs.modes) {
                        Ok(r) => r.modes.iter().map(|x| (x.omega_rad_s, x.zeta)).collect(),
                        Err(_) => vec![(f64::NAN, f64::NAN); fs.modes],
                    }
                })
                .collect()
        })
        .collect();
    let mut maps = Vec::new();
    let mut files = vec![("table-2.csv".to_string(), t2.to_csv()), ("table-2.md".to_string(), t2.to_markdown())];
    for r in 0..fs.modes {
        let ratio: Vec<Vec<f64>> =
            grid.iter().map(|row| row.iter().map(|v| v[r].0 / local_omega[r]).collect()).collect();
        let zeta: Vec<Vec<f64>> = grid.iter().map(|row| row.iter().map(|v| v[r].1).collect()).collect();
        let mut csv = String::from("e0a_nm,omega_rad_s,omega_ratio,zeta\n");
        for (i, e) in e0a.iter().enumerate() {
            for (j, w) in omega.iter().enumerate() {
                csv += &format!("{e},{w:e},{:.9},{:.9}\n", ratio[i][j], zeta[i][j]);
            }
        }
        files.push((format!("figure-{}.csv", r + 1), csv));
        // Heatmap z is indexed [y][x]: y = e0a, x = Ω.
        for (suffix, z, label) in
            [("a", &ratio, format!("ω{}/ω'{}", r + 1, r + 1)), ("b", &zeta, format!("ζ{}", r + 1))]
        {
            let hm = Heatmap {
                title: format!("Figure {}{}: mode {} (Δ = {:.3})", r + 1, suffix, r + 1, delta),
                x_axis: Axis::log("Ω (rad/s)"),
                y_axis: Axis::linear("e0a (nm)"),
                x: omega.clone(),
                y: e0a.clone(),
                z: z.clone(),
                z_label: label,
                ..Heatmap::default()
            };
            files.push((format!("figure-{}{}.svg", r + 1, suffix), svg::heatmap(&hm)?));
        }
        maps.push((ratio, zeta));
    }
    Ok(ForwardOutcome { table2_rows: rows, table2_md: t2.to_markdown(), maps, e0a, omega, local_omega, delta, files })
}

// ---------------------------------------------------------------------------
// Calibration cases
// ---------------------------------------------------------------------------

fn truth_value(target: Target, truth: &BeamSpec) -> f64 {
    match target {
        Target::NonlocalE0a => truth.nonlocal_e0a_nm,
        Target::Delta(i) => truth.internal_variables.get(i).map_or(f64::NAN, |v| v.delta),
        Target::Omega(i) => truth.internal_variables.get(i).map_or(f64::NAN, |v| v.omega_rad_s),
        Target::Diameter => truth.diameter_nm,
        _ => f64::NAN,
    }
}

/// Synthetic measured data y = y0 + ε, ε ~ N(0, Σ) (eq. 37), σ = √Σ printed.
fn synthetic_observations(truth: &BeamSpec, published: &Published, set: &str, seed: u64) -> Vec<ModeObservation> {
    let cs = published.covariance_set(set).expect("validated covariance set id");
    let y0 = beam::modal(truth, 3).expect("reconstructed truth is a valid beam");
    let mut rng = stream(seed, Purpose::MeasurementNoise, [0, 0]);
    y0.modes
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let sw = cs.sigma_omega_omega_diag_ghz2[i].sqrt() * ghz_to_rad_s(1.0);
            let sz = (cs.sigma_zeta_zeta_diag_1e_minus_6[i] * 1e-6).sqrt();
            let ew: f64 = StandardNormal.sample(&mut rng);
            let ez: f64 = StandardNormal.sample(&mut rng);
            ModeObservation {
                mode: i + 1,
                omega_rad_s: m.omega_rad_s + sw * ew,
                omega_sd_rad_s: sw,
                zeta: m.zeta + sz * ez,
                zeta_sd: sz,
            }
        })
        .collect()
}

fn run_case(
    spec: &CaseSpec,
    rec: &Reconstruction,
    published: &Published,
    quick: bool,
) -> Result<CaseOutcome, ReproduceError> {
    let t = Instant::now();
    let truth = match spec.truth {
        Truth::Table4 => &rec.truth_table_4,
        Truth::Table9 => &rec.truth_table_9,
    };
    let obs = synthetic_observations(truth, published, &spec.covariance_set, spec.seed);
    let params = ParameterSet::from_mapping(&spec.parameters).expect("validated");
    let mut inverse = rec.table_1.clone();
    inverse.diameter_nm = spec.inverse_diameter_nm;
    inverse.internal_variables = vec![InternalVariable { delta: 0.5, omega_rad_s: 1e12 }];
    let truth_vec: Vec<f64> = params.params.iter().map(|p| truth_value(p.target, truth)).collect();
    let c0: Vec<f64> = params.params.iter().map(|p| p.proposal_sd).collect();
    let post = BeamPosterior::from_parts(&inverse, &obs, params.clone());
    let mut sampler = if quick { spec.quick_sampler.clone() } else { spec.sampler.clone() };
    sampler.seed = spec.seed;
    let result = calibrate_posterior(&post, &c0, &sampler, &CalibrateOptions::default())
        .map_err(|e| ReproduceError::Failure(format!("case {}: {e}", spec.id)))?;
    Ok(CaseOutcome {
        spec: spec.clone(),
        names: params.names(),
        truth: truth_vec,
        observations: obs,
        result,
        posterior: post,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// Monte Carlo standard error of the mean of parameter k: sd/√ESS_bulk.
fn mcse(c: &CaseOutcome, k: usize) -> f64 {
    let p = &c.result.summary.parameters[k];
    p.sd / p.ess_bulk.max(1.0).sqrt()
}

fn case_json(c: &CaseOutcome) -> Value {
    let params: Vec<Value> = c
        .result
        .summary
        .parameters
        .iter()
        .enumerate()
        .map(|(k, p)| {
            json!({
                "name": p.name, "exact": if c.truth[k].is_finite() { json!(c.truth[k]) } else { Value::Null },
                "mean": p.mean, "sd": p.sd, "cv": p.cv, "ci95": p.ci95, "map": p.map,
                "rhat": p.rhat, "ess_bulk": p.ess_bulk, "ess_tail": p.ess_tail, "mcse_mean": mcse(c, k),
            })
        })
        .collect();
    json!({
        "id": c.spec.id, "title": c.spec.title, "parameters": params,
        "correlation": c.result.summary.correlation,
        "acceptance": c.result.acceptance, "rejected_invalid": c.result.rejected_invalid,
        "log_posterior_map": c.result.log_posterior_map, "seconds": c.seconds,
        "observations": c.observations.iter().map(|o| json!({"mode": o.mode, "omega_rad_s": o.omega_rad_s, "omega_sd_rad_s": o.omega_sd_rad_s, "zeta": o.zeta, "zeta_sd": o.zeta_sd})).collect::<Vec<_>>(),
    })
}

/// Table rows of a group of cases (Tables 7, 8, 12).
fn case_table(cases: &[&CaseOutcome]) -> Table {
    let mut t = Table::new(["case", "parameter", "exact"].into_iter().chain(SUMMARY_HEADERS));
    for c in cases {
        for (k, p) in c.result.summary.parameters.iter().enumerate() {
            let exact = if c.truth[k].is_finite() { fmt_sig(c.truth[k], 4) } else { "-".into() };
            t.push_row([c.spec.id.clone(), p.name.clone(), exact].into_iter().chain(summary_cells(p)));
        }
    }
    t
}

fn group<'a>(cases: &'a [CaseOutcome], ids: &[&str]) -> Vec<&'a CaseOutcome> {
    ids.iter().filter_map(|id| cases.iter().find(|c| c.spec.id == *id)).collect()
}

/// Tables 7, 8, 12 and Figures 4–13.
fn case_group_files(cases: &[CaseOutcome]) -> Result<Vec<(String, String)>, ReproduceError> {
    let mut files = Vec::new();
    let groups: [(&str, &[&str], &[(&str, &str)], &str); 3] = [
        (
            "table-7",
            &["1A", "1B", "1C"],
            &[("figure-4", "nonlocal_e0a_nm"), ("figure-5", "delta"), ("figure-6", "omega_rad_s")],
            "figure-7",
        ),
        (
            "table-8",
            &["2A", "2B", "2C"],
            &[
                ("figure-8", "nonlocal_e0a_nm"),
                ("figure-9", "delta"),
                ("figure-10", "omega_rad_s"),
                ("figure-11", "diameter_nm"),
            ],
            "figure-12",
        ),
        ("table-12", &["3", "3-N2"], &[], "figure-13"),
    ];
    for (table, ids, figs, pair) in groups {
        let g = group(cases, ids);
        if g.is_empty() {
            continue;
        }
        let t = case_table(&g);
        files.push((format!("{table}.csv"), t.to_csv()));
        files.push((format!("{table}.md"), t.to_markdown()));
        for (fig, name) in figs {
            let Some(k) = g[0].names.iter().position(|n| n == name) else { continue };
            let trace = TracePlot {
                title: format!("{fig}a: chain 1 of each case, {name}"),
                y_label: name.to_string(),
                chains: g
                    .iter()
                    .map(|c| NamedValues {
                        name: c.spec.id.clone(),
                        values: c.result.chains[0].draws.iter().map(|t| t[k]).collect(),
                    })
                    .collect(),
                reference: g[0].truth[k].is_finite().then_some(g[0].truth[k]),
                ..TracePlot::default()
            };
            files.push((format!("{fig}a.svg"), svg::trace_plot(&trace)?));
            let hist = HistogramPlot {
                title: format!("{fig}b: marginal posteriors of {name}"),
                x_label: name.to_string(),
                groups: g
                    .iter()
                    .map(|c| NamedValues {
                        name: c.spec.id.clone(),
                        values: c.result.kept_draws().iter().flatten().map(|t| t[k]).collect(),
                    })
                    .collect(),
                reference: g[0].truth[k].is_finite().then_some(g[0].truth[k]),
                ..HistogramPlot::default()
            };
            files.push((format!("{fig}b.svg"), svg::histogram(&hist)?));
        }
        for c in &g {
            let kept = c.result.kept_draws();
            let columns: Vec<Vec<f64>> =
                (0..c.names.len()).map(|k| kept.iter().flatten().map(|t| t[k]).collect()).collect();
            let pp = PairPlot {
                title: format!("{pair}: pairs, case {}", c.spec.id),
                names: c.names.clone(),
                columns,
                reference: Some(c.truth.clone()),
                max_points: 1500,
                ..PairPlot::default()
            };
            let suffix = if g.len() > 1 { format!("-{}", c.spec.id.to_lowercase()) } else { String::new() };
            files.push((format!("{pair}{suffix}.svg"), svg::pair_plot(&pp)?));
        }
    }
    Ok(files)
}

// ---------------------------------------------------------------------------
// Figure 14
// ---------------------------------------------------------------------------

pub struct FrfOutcome {
    pub json: Value,
    pub files: Vec<(String, String)>,
    /// Fraction of grid frequencies up to the 4th reference mode where the reference lies in the 99 % envelope.
    pub coverage_to_mode_4: f64,
    pub mode_4_ghz: f64,
}

fn frf_stage(
    specs: &Specs,
    rec: &Reconstruction,
    cases: &[CaseOutcome],
    quick: bool,
) -> Result<FrfOutcome, ReproduceError> {
    let fs = &specs.frf;
    let case = cases.iter().find(|c| c.spec.id == fs.case).expect("validated case id");
    let reference = match case.spec.truth {
        Truth::Table4 => &rec.truth_table_4,
        Truth::Table9 => &rec.truth_table_9,
    };
    let n = if quick { fs.quick_points } else { fs.points };
    let f_ghz: Vec<f64> = (0..n).map(|i| fs.from_ghz + (fs.to_ghz - fs.from_ghz) * i as f64 / (n - 1) as f64).collect();
    let w: Vec<f64> = f_ghz.iter().map(|f| ghz_to_rad_s(*f)).collect();
    let at = |b: &BeamSpec| -> Option<Vec<f64>> {
        let l = b.length_nm;
        beam::frf(b, fs.input_x_fraction * l, fs.output_x_fraction * l, &w)
            .ok()
            .map(|h| h.iter().map(|z| z.norm()).collect())
    };
    let href = at(reference).ok_or_else(|| ReproduceError::Failure("Figure 14: reference FRF failed".into()))?;
    let k = if quick { fs.quick_posterior_draws } else { fs.posterior_draws };
    // Posterior predictive FRFs of a case: (curves, mean, 0.5 % and 99.5 % quantiles).
    let predictive = |c: &CaseOutcome| {
        let draws: Vec<Vec<f64>> = c.result.kept_draws().into_iter().flatten().collect();
        let k = k.min(draws.len());
        let step = (draws.len() / k.max(1)).max(1);
        let picked: Vec<&Vec<f64>> = draws.iter().step_by(step).take(k).collect();
        let curves: Vec<Vec<f64>> = picked.par_iter().filter_map(|t| at(&c.posterior.beam_at(t))).collect();
        let (mut mean, mut lo, mut hi) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for i in 0..n {
            let mut col: Vec<f64> = curves.iter().map(|c| c[i]).collect();
            col.sort_by(f64::total_cmp);
            mean[i] = col.iter().sum::<f64>() / col.len() as f64;
            lo[i] = crate::bayes::diagnostics::quantile_sorted(&col, 0.005);
            hi[i] = crate::bayes::diagnostics::quantile_sorted(&col, 0.995);
        }
        (curves, mean, lo, hi)
    };
    let (curves, mean, lo, hi) = predictive(case);
    let n2 = cases.iter().find(|c| c.spec.id == format!("{}-N2", fs.case)).map(predictive);
    let mode_4_ghz = beam::modal(reference, 4).map(|m| m.modes[3].omega_rad_s / ghz_to_rad_s(1.0)).unwrap_or(f64::NAN);
    let upto: Vec<usize> = (0..n).filter(|&i| f_ghz[i] <= mode_4_ghz * 1.02).collect();
    let covered = upto.iter().filter(|&&i| href[i] >= lo[i] && href[i] <= hi[i]).count();
    let coverage_to_mode_4 = covered as f64 / upto.len().max(1) as f64;
    // RMS of log10|H_mean| − log10|H_ref| up to mode 4: the FRF error of a model's mean prediction.
    let log_rms = |m: &[f64]| {
        (upto.iter().map(|&i| (m[i].log10() - href[i].log10()).powi(2)).sum::<f64>() / upto.len().max(1) as f64).sqrt()
    };
    let err_n1 = log_rms(&mean);
    let err_n2 = n2.as_ref().map(|(_, m, _, _)| log_rms(m));
    let coverage_n2 = n2.as_ref().map(|(_, _, l, h)| {
        upto.iter().filter(|&&i| href[i] >= l[i] && href[i] <= h[i]).count() as f64 / upto.len().max(1) as f64
    });
    let realizations: Vec<Series> = curves
        .iter()
        .take(40)
        .enumerate()
        .map(|(j, c)| Series { name: format!("draw {j}"), x: f_ghz.clone(), y: c.clone() })
        .collect();
    let plot = LinePlot {
        title: "Figure 14: FRF |H| (m/N), reference N̄ = 2 vs calibrated N = 1 (Case 3)".into(),
        x_axis: Axis::linear("f (GHz)"),
        y_axis: Axis::log("|H| (m/N)"),
        series: vec![
            Series { name: "reference (N̄ = 2)".into(), x: f_ghz.clone(), y: href.clone() },
            Series { name: "posterior mean (N = 1, β-inflated)".into(), x: f_ghz.clone(), y: mean.clone() },
        ]
        .into_iter()
        .chain(n2.as_ref().map(|(_, m, _, _)| Series {
            name: "posterior mean (N = 2, β = 1)".into(),
            x: f_ghz.clone(),
            y: m.clone(),
        }))
        .collect(),
        realizations,
        band: Some(Band { name: "99 % envelope".into(), x: f_ghz.clone(), lower: lo.clone(), upper: hi.clone() }),
        ref_lines: vec![RefLine::Vertical(mode_4_ghz)],
        ..LinePlot::default()
    };
    let mut csv = String::from("f_ghz,reference_m_per_n,mean_m_per_n,lower_0_5_m_per_n,upper_99_5_m_per_n\n");
    for i in 0..n {
        csv += &format!("{},{:e},{:e},{:e},{:e}\n", f_ghz[i], href[i], mean[i], lo[i], hi[i]);
    }
    Ok(FrfOutcome {
        json: json!({"mode_4_ghz": mode_4_ghz, "coverage_to_mode_4": coverage_to_mode_4, "draws": curves.len(), "points": n,
            "log10_rms_error_to_mode_4_n1": err_n1, "log10_rms_error_to_mode_4_n2": err_n2, "coverage_to_mode_4_n2": coverage_n2}),
        files: vec![("figure-14.svg".into(), svg::line_plot(&plot)?), ("figure-14.csv".into(), csv)],
        coverage_to_mode_4,
        mode_4_ghz,
    })
}

// ---------------------------------------------------------------------------
// Case 3: evidence of the β-inflated N = 1 class against the N = 2 class
// ---------------------------------------------------------------------------

/// log evidence of each Case-3 model class by TMCMC (Ching & Chen 2007) on the
/// same synthetic data; the log Bayes factor says what the second internal
/// variable buys over absorbing the misfit into β. Null when a case is absent.
fn evidence_stage(cases: &[CaseOutcome], quick: bool) -> Value {
    let config = |seed: u64| crate::bayes::tmcmc::TmcmcConfig {
        n_samples: if quick { 300 } else { 1500 },
        seed,
        ..Default::default()
    };
    let one = |id: &str| -> Option<(f64, f64)> {
        let c = cases.iter().find(|c| c.spec.id == id)?;
        crate::bayes::tmcmc::tmcmc(&c.posterior, &config(c.spec.seed)).ok().map(|r| (r.log_evidence, r.log_evidence_se))
    };
    let (n1, n2) = rayon::join(|| one("3"), || one("3-N2"));
    match (n1, n2) {
        (Some((z1, s1)), Some((z2, s2))) => json!({
            "log_evidence_n1_beta": z1, "log_evidence_n1_beta_se": s1,
            "log_evidence_n2": z2, "log_evidence_n2_se": s2,
            "log_bayes_factor_n2_vs_n1_beta": z2 - z1,
        }),
        _ => Value::Null,
    }
}

/// `nanobeam diagnose` on the Case-3 data (the same noisy observations the
/// β-inflated calibration saw; base model = the paper's N = 1 beam with the
/// Table-1 geometry): which cause it names and by how much.
fn diagnosis_stage(cases: &[CaseOutcome], rec: &Reconstruction, quick: bool) -> Result<Value, ReproduceError> {
    use crate::diagnose::{diagnose, DiagnoseSettings};
    let Some(c) = cases.iter().find(|c| c.spec.id == "3") else { return Ok(Value::Null) };
    let mut beam = rec.table_1.clone();
    beam.diameter_nm = c.spec.inverse_diameter_nm;
    beam.internal_variables = vec![];
    let file = crate::calibration::measured::MeasuredFile {
        beam,
        modes: c.observations.clone(),
        held_out_modes: vec![],
        parameters: None,
        sampler: None,
    };
    let data = crate::calibration::measured::MeasuredData::from_file(file)
        .map_err(|e| ReproduceError::Failure(format!("case 3 as measured data: {e}")))?;
    let settings = DiagnoseSettings {
        seed: Some(c.spec.seed),
        ..if quick { DiagnoseSettings::quick() } else { DiagnoseSettings::default() }
    };
    let d = diagnose(&data, &settings).map_err(|e| ReproduceError::Failure(format!("case 3 diagnosis: {e}")))?;
    let probability = |name: &str| d.candidates.iter().find(|k| k.extension == name).map(|k| k.probability);
    Ok(json!({
        "misfit_detected": d.misfit_detected,
        "cause": d.cause,
        "log_bayes_factor": d.gain.log_bayes_factor,
        "baseline_beta_log_bayes_factor": d.baseline.log_bayes_factor,
        "cause_probability": probability(&d.cause),
        "rms_z_before": d.gain.rms_z_before,
        "rms_z_after": d.gain.rms_z_after,
        "candidates": d.candidates.iter().map(|k| json!({"extension": k.extension, "log_bayes_factor": k.log_bayes_factor, "probability": k.probability})).collect::<Vec<_>>(),
    }))
}

// ---------------------------------------------------------------------------
// Audit
// ---------------------------------------------------------------------------

fn claim_source(p: &Published, id: &str) -> (String, String) {
    p.claims
        .iter()
        .find(|c| c.id == id)
        .map(|c| (c.statement.clone(), c.source.clone()))
        .unwrap_or_else(|| (id.to_string(), "-".to_string()))
}

fn param(c: &CaseOutcome, name: &str) -> Option<usize> {
    c.names.iter().position(|n| n == name)
}

fn covers(c: &CaseOutcome, k: usize) -> bool {
    let p = &c.result.summary.parameters[k];
    p.ci95[0] <= c.truth[k] && c.truth[k] <= p.ci95[1]
}

fn audit(
    p: &Published,
    rec: &Reconstruction,
    fwd: &ForwardOutcome,
    cases: &[CaseOutcome],
    frf: &FrfOutcome,
) -> Vec<Verdict> {
    let mut v = Vec::new();
    let mut push =
        |id: &str, claim: String, source: String, reproduced: String, tolerance: &str, pass: bool, note: &str| {
            v.push(Verdict {
                id: id.into(),
                claim,
                source,
                reproduced,
                tolerance: tolerance.into(),
                pass,
                note: if pass { String::new() } else { note.into() },
            });
        };
    for (id, fit, table) in [("table_5", &rec.fit_table_4, "Table 5"), ("table_10", &rec.fit_table_9, "Table 10")] {
        let worst = fit.values.iter().map(|x| x.residual_sigma.abs()).fold(0.0, f64::max);
        push(
            id,
            format!("{table} reference values (encoded by the printed Σ) are reproduced by the reconstructed inputs"),
            "§4.2 after eq. (38) / §4.3 after eq. (41): printed Σωω, Σζζ".into(),
            format!("χ² = {:.3}, max |residual| = {:.3} σ, {} of {} inside their rounding intervals", fit.chi2, worst, fit.values.iter().filter(|x| x.within_rounding).count(), fit.values.len()),
            "every value inside the rounding interval of its printed Σ entry",
            fit.all_within_rounding(),
            "neither the σ-weighted nor the rounding-weighted multi-start fit (fixed d, E, ρ) lands inside every rounding interval; the residuals show which value resists",
        );
    }
    let get = |id: &str| cases.iter().find(|c| c.spec.id == id);
    // Case 1.
    if let Some(a) = get("1A") {
        let (claim, src) = claim_source(p, "case_1a_covers_truth");
        let ok: Vec<bool> = ["nonlocal_e0a_nm", "delta", "omega_rad_s"]
            .iter()
            .filter_map(|n| param(a, n))
            .map(|k| covers(a, k))
            .collect();
        push(
            "case_1a_covers_truth",
            claim,
            src,
            format!("truth inside CI95: {ok:?} (e0a, Δ, Ω)"),
            "truth ∈ CI95",
            ok.iter().all(|x| *x),
            "a 95 % interval misses its truth 5 % of the time by design; see the case table",
        );
    }
    for id in ["1B", "1C"] {
        if let Some(c) = get(id) {
            let (claim, src) = claim_source(p, "cases_1b_1c_miss_delta_omega");
            let miss: Vec<bool> =
                ["delta", "omega_rad_s"].iter().filter_map(|n| param(c, n)).map(|k| !covers(c, k)).collect();
            push(&format!("case_{}_misses_delta_omega", id.to_lowercase()), claim, src, format!("truth outside CI95 (Δ, Ω): {miss:?}"), "truth ∉ CI95 for both", miss.iter().all(|x| *x), "the bias from a 3 % diameter error depends on the lost Table 1/4 values; with the reconstructed ones it is smaller than the posterior width");
        }
    }
    let e0a_all: Vec<bool> = ["1A", "1B", "1C"]
        .iter()
        .filter_map(|id| get(id))
        .filter_map(|c| param(c, "nonlocal_e0a_nm").map(|k| covers(c, k)))
        .collect();
    if !e0a_all.is_empty() {
        let (claim, src) = claim_source(p, "e0a_covered_all_case_1");
        push(
            "e0a_covered_all_case_1",
            claim,
            src,
            format!("{e0a_all:?}"),
            "truth ∈ CI95 in 1A, 1B, 1C",
            e0a_all.iter().all(|x| *x),
            "e0a absorbs part of the diameter error here",
        );
    }
    for re in &p.reported_relative_errors {
        let Some(c) = get(&re.case) else { continue };
        let Some(k) = param(c, &re.parameter) else { continue };
        let pr = &c.result.summary.parameters[k];
        let rel = (pr.mean - c.truth[k]).abs() / c.truth[k].abs();
        // Tolerance: the printed "around N %" (±0.5 percentage points of
        // rounding) plus 2 Monte Carlo standard errors of the mean.
        let tol = 0.005 + 2.0 * mcse(c, k) / c.truth[k].abs();
        push(
            &format!("relative_error_{}_{}", re.case.to_lowercase(), re.parameter),
            format!("Case {}: relative error of the mean of {} ≈ {:.0} %", re.case, re.parameter, 100.0 * re.relative_error_approx),
            re.source.clone(),
            format!("{:.1} %", 100.0 * rel),
            &format!("± {:.1} points", 100.0 * tol),
            (rel - re.relative_error_approx).abs() <= tol,
            "the bias induced by a 3 % diameter error depends on the lost Table 1/4 values, which are reconstructed here only up to their identifiable combination",
        );
    }
    // Case 2.
    let c2: Vec<bool> = ["2A", "2B", "2C"]
        .iter()
        .filter_map(|id| get(id))
        .flat_map(|c| {
            ["nonlocal_e0a_nm", "delta", "omega_rad_s"]
                .iter()
                .filter_map(|n| param(c, n))
                .map(|k| covers(c, k))
                .collect::<Vec<_>>()
        })
        .collect();
    if !c2.is_empty() {
        let (claim, src) = claim_source(p, "cases_2_cover_truth");
        push(
            "cases_2_cover_truth",
            claim,
            src,
            format!("{} of {} (e0a, Δ, Ω) × (2A, 2B, 2C) inside CI95", c2.iter().filter(|x| **x).count(), c2.len()),
            "all inside",
            c2.iter().all(|x| *x),
            "see Table 8",
        );
    }
    if let (Some(a1), Some(a2)) = (get("1A"), get("2A")) {
        if let (Some(k1), Some(k2)) = (param(a1, "delta"), param(a2, "delta")) {
            let (s1, s2) = (a1.result.summary.parameters[k1].sd, a2.result.summary.parameters[k2].sd);
            let (claim, src) = claim_source(p, "cases_2_wider_delta_omega");
            push(
                "cases_2_wider_delta_omega",
                claim,
                src,
                format!("sd(Δ): 1A {} vs 2A {}", fmt_sig(s1, 3), fmt_sig(s2, 3)),
                "2A > 1A",
                s2 > s1,
                "",
            );
        }
    }
    let corr = |c: &CaseOutcome, a: &str, b: &str| -> Option<f64> {
        Some(c.result.summary.correlation[param(c, a)?][param(c, b)?])
    };
    if let Some(r) = get("1A").and_then(|c| corr(c, "nonlocal_e0a_nm", "delta")) {
        let (claim, src) = claim_source(p, "corr_e0a_delta_positive");
        push("corr_e0a_delta_positive", claim, src, format!("ρ(e0a, Δ) = {r:.3} in 1A"), "> 0", r > 0.0, "");
    }
    if let Some(r) = get("2A").and_then(|c| corr(c, "diameter_nm", "delta")) {
        let (claim, src) = claim_source(p, "corr_d_delta_negative");
        push("corr_d_delta_negative", claim, src, format!("ρ(d, Δ) = {r:.3} in 2A"), "< 0", r < 0.0, "");
    }
    // §4.1 maps.
    let mut monotone = true;
    for (ratio, _) in &fwd.maps {
        for j in 0..fwd.omega.len() {
            for i in 1..fwd.e0a.len() {
                monotone &= ratio[i][j] < ratio[i - 1][j];
            }
        }
    }
    let (claim, src) = claim_source(p, "omega_decreases_with_e0a");
    push(
        "omega_decreases_with_e0a",
        claim,
        src,
        format!("strictly decreasing along e0a at every Ω of the grid: {monotone}"),
        "exact (no tolerance)",
        monotone,
        "",
    );
    let mut ridge = Vec::new();
    for (r, (_, zeta)) in fwd.maps.iter().enumerate() {
        let row = &zeta[0];
        let j = (0..row.len()).max_by(|&a, &b| row[a].total_cmp(&row[b])).unwrap_or(0);
        ridge.push(fwd.omega[j] / fwd.local_omega[r]);
    }
    let ok = ridge.iter().all(|x| (0.33..=3.0).contains(x));
    let (claim, src) = claim_source(p, "damping_ridge_near_omega_r");
    push(
        "damping_ridge_near_omega_r",
        claim,
        src,
        format!(
            "Ω at the ζ_r peak / ω'_r (e0a = 0): {:?}",
            ridge.iter().map(|x| (x * 100.0).round() / 100.0).collect::<Vec<_>>()
        ),
        "within a factor 3 (peak of a Debye-type loss at Ω ≈ ω/√(1+Δ))",
        ok,
        "",
    );
    // Case 3.
    if let Some(c3) = get("3") {
        if let Some(k) = param(c3, "nonlocal_e0a_nm") {
            let (claim, src) = claim_source(p, "case_3_e0a_outside_ci95");
            let pr = &c3.result.summary.parameters[k];
            push(
                "case_3_e0a_outside_ci95",
                claim,
                src,
                format!("truth {} vs CI95 {}", fmt_sig(c3.truth[k], 4), fmt_interval(pr.ci95[0], pr.ci95[1], 4)),
                "truth ∉ CI95",
                !covers(c3, k),
                "with the reconstructed N̄ = 2 truth the N = 1 model's bias in e0a is smaller than its posterior width",
            );
        }
        if let Some(k) = param(c3, "beta_squared") {
            let draws: Vec<f64> = c3.result.kept_draws().iter().flatten().map(|t| t[k].sqrt()).collect();
            let mean = draws.iter().sum::<f64>() / draws.len() as f64;
            let (claim, src) = claim_source(p, "case_3_beta_near_4");
            push("case_3_beta_near_4", claim, src, format!("posterior mean of β = {mean:.2}"), "4 ± 0.5 (\"around 4\" read to the nearest integer)", (mean - 4.0).abs() <= 0.5, "β measures the N = 1 model's misfit to the reconstructed N̄ = 2 data, which fits Table 10 only approximately (see reconstruction)");
        }
    }
    let (claim, src) = claim_source(p, "case_3_envelope_covers_to_mode_4");
    push(
        "case_3_envelope_covers_to_mode_4",
        claim,
        src,
        format!(
            "{:.0} % of frequencies up to mode 4 ({:.0} GHz) inside the 99 % envelope",
            100.0 * frf.coverage_to_mode_4,
            frf.mode_4_ghz
        ),
        "≥ 95 % of the grid",
        frf.coverage_to_mode_4 >= 0.95,
        "the envelope misses the reference near some resonance peaks",
    );
    if let Some(rv) = p.reported_values.iter().find(|r| r.id == "fourth_mode_frequency_case_3_ghz") {
        let tol = 0.02 * rv.value;
        push(
            "fourth_mode_frequency_case_3_ghz",
            "The Case-3 reference beam's fourth mode lies around 1250 GHz".into(),
            rv.source.clone(),
            format!("{:.0} GHz", frf.mode_4_ghz),
            "± 2 % (\"around\" a value read off a figure)",
            (frf.mode_4_ghz - rv.value).abs() <= tol,
            "",
        );
    }
    let worst_rhat = cases.iter().flat_map(|c| c.result.summary.parameters.iter().map(|p| p.rhat)).fold(1.0, f64::max);
    let min_ess =
        cases.iter().flat_map(|c| c.result.summary.parameters.iter().map(|p| p.ess_bulk)).fold(f64::INFINITY, f64::min);
    let (claim, src) = claim_source(p, "chains_converged");
    push(
        "chains_converged",
        claim,
        src,
        format!("max R-hat {worst_rhat:.4}, min bulk ESS {min_ess:.0} over all cases"),
        "R-hat < 1.01 and ESS > 400 (added by this reproduction)",
        worst_rhat < 1.01 && min_ess > 400.0,
        "some chains have not mixed to the Vehtari et al. (2021) standard at these settings",
    );
    v
}

// ---------------------------------------------------------------------------
// Report
// ---------------------------------------------------------------------------

/// Tables 5 and 10: reference values, their rounding intervals and the reconstruction's fit.
fn fit_table(f: &crate::reproduce::reconstruction::Fit) -> Table {
    let mut t =
        Table::new(["mode", "quantity", "reference", "rounding interval", "reproduced", "residual (σ)", "inside"]);
    for x in &f.values {
        t.push_row([
            x.mode.to_string(),
            x.quantity.to_string(),
            fmt_sig(x.reference, 5),
            fmt_interval(x.interval[0], x.interval[1], 5),
            fmt_sig(x.reproduced, 5),
            format!("{:+.3}", x.residual_sigma),
            if x.within_rounding { "✓".into() } else { "✗".into() },
        ]);
    }
    t
}

fn report_context(
    rec: &Reconstruction,
    fwd: &ForwardOutcome,
    cases: &[CaseOutcome],
    frf: &FrfOutcome,
    verdicts: &[Verdict],
    timings: &[(String, f64)],
    quick: bool,
) -> Value {
    let fit_table = |f| fit_table(f).to_markdown();
    let params = |f: &crate::reproduce::reconstruction::Fit| {
        f.parameters.iter().map(|(n, v)| format!("{n} = {}", fmt_sig(*v, 5))).collect::<Vec<_>>().join(", ")
    };
    let mut tables = BTreeMap::new();
    for (name, ids) in
        [("table_7", vec!["1A", "1B", "1C"]), ("table_8", vec!["2A", "2B", "2C"]), ("table_12", vec!["3", "3-N2"])]
    {
        let g = group(cases, &ids);
        if !g.is_empty() {
            tables.insert(name, case_table(&g).to_markdown());
        }
    }
    let mut audit = Table::new(["id", "claim", "reproduced", "tolerance", "verdict", "why not"]);
    for v in verdicts {
        audit.push_row([
            v.id.clone(),
            v.claim.clone(),
            v.reproduced.clone(),
            v.tolerance.clone(),
            if v.pass { "✓".into() } else { "✗".into() },
            v.note.clone(),
        ]);
    }
    let mut timing = Table::new(["stage", "wall time (s)"]);
    for (k, s) in timings {
        timing.push_row([k.clone(), format!("{s:.2}")]);
    }
    let mut case_times = Table::new(["case", "wall time (s)", "acceptance per DR stage", "rejected invalid"]);
    for c in cases {
        case_times.push_row([
            c.spec.id.clone(),
            format!("{:.2}", c.seconds),
            format!("{:?}", c.result.acceptance.iter().map(|a| (a * 1000.0).round() / 1000.0).collect::<Vec<_>>()),
            c.result.rejected_invalid.to_string(),
        ]);
    }
    json!({
        "quick": quick,
        "table_1_length_nm": fmt_sig(rec.table_1.length_nm, 5),
        "table_4_parameters": params(&rec.fit_table_4),
        "table_9_parameters": params(&rec.fit_table_9),
        "table_5_fit": fit_table(&rec.fit_table_4),
        "table_10_fit": fit_table(&rec.fit_table_9),
        "table_5_chi2": format!("{:.3}", rec.fit_table_4.chi2),
        "table_10_chi2": format!("{:.3}", rec.fit_table_9.chi2),
        "table_10_all_inside": rec.fit_table_9.all_within_rounding(),
        "table_5_sigma_fit": fit_table(&rec.sigma_fit_table_4),
        "table_10_sigma_fit": fit_table(&rec.sigma_fit_table_9),
        "table_5_sigma_chi2": format!("{:.3}", rec.sigma_fit_table_4.chi2),
        "table_10_sigma_chi2": format!("{:.3}", rec.sigma_fit_table_9.chi2),
        "table_5_all_inside": rec.fit_table_4.all_within_rounding(),
        "table_2": fwd.table2_md,
        "maps_delta": format!("{:.4}", fwd.delta),
        "tables": tables,
        "figure_14_coverage": format!("{:.0}", 100.0 * frf.coverage_to_mode_4),
        "figure_14": frf.json,
        "audit": audit.to_markdown(),
        "audit_failures": verdicts.iter().filter(|v| !v.pass).count(),
        "audit_total": verdicts.len(),
        "timings": timing.to_markdown(),
        "case_times": case_times.to_markdown(),
    })
}
