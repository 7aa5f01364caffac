//! The calibration cases (§4.2–4.3): synthetic data from the reconstructed
//! truth, DRAM calibration, and the tables and figures the paper groups them
//! into (`paper/specs/tables.yaml`).

use std::time::Instant;

use crate::bayes::Posterior;
use crate::beam::BeamSpec;
use crate::calibration::output::{summary_cells, SUMMARY_HEADERS};
use crate::calibration::{calibrate_posterior, BeamPosterior, CalibrateOptions, CalibrationResult, ModeObservation};
use crate::calibration::{ParameterSet, Target};
use crate::report::svg::{self, HistogramPlot, NamedValues, PairPlot, TracePlot};
use crate::report::table::{fmt_sig, Table};
use crate::reproduce::error::ReproduceError;
use crate::reproduce::reconstruction::Reconstruction;
use crate::reproduce::reference::Published;
use crate::reproduce::replicates::{synthetic_observations, Noise};
use crate::reproduce::results::{CaseParameter, CaseResult};
use crate::reproduce::specs::{CaseSpec, CaseTable, Truth};

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

/// The reconstructed beam that generates a case's data.
pub fn truth_beam<'a>(spec: &CaseSpec, rec: &'a Reconstruction) -> &'a BeamSpec {
    match spec.truth {
        Truth::Table4 => &rec.truth_table_4,
        Truth::Table9 => &rec.truth_table_9,
    }
}

fn truth_value(target: Target, truth: &BeamSpec) -> f64 {
    match target {
        Target::NonlocalE0a => truth.nonlocal_e0a_nm,
        Target::Delta(i) => truth.internal_variables.get(i).map_or(f64::NAN, |v| v.delta),
        Target::Omega(i) => truth.internal_variables.get(i).map_or(f64::NAN, |v| v.omega_rad_s),
        Target::Diameter => truth.diameter_nm,
        _ => f64::NAN,
    }
}

/// Synthetic data (replicate 0 of the case's noise), then DRAM.
pub fn run_case(
    spec: &CaseSpec,
    rec: &Reconstruction,
    published: &Published,
    quick: bool,
) -> Result<CaseOutcome, ReproduceError> {
    let t = Instant::now();
    let truth = truth_beam(spec, rec);
    let cs = published.covariance_set(&spec.covariance_set).expect("validated covariance set id");
    let obs = synthetic_observations(truth, cs, spec.seed, Noise::Replicate(0)).expect("reconstructed truth is valid");
    let params = ParameterSet::from_mapping(&spec.parameters).expect("validated");
    let mut inverse = rec.table_1.clone();
    inverse.diameter_nm = spec.inverse_diameter_nm;
    inverse.internal_variables = spec.inverse_internal_variables.clone();
    let mut truth_vec: Vec<f64> = params.params.iter().map(|p| truth_value(p.target, truth)).collect();
    let c0: Vec<f64> = params.params.iter().map(|p| p.proposal_sd).collect();
    let post = BeamPosterior::from_parts(&inverse, &obs, params.clone());
    // the truth in the canonical order the draws are reported in (exchangeable
    // internal variables by ascending Ω), so each row compares like with like
    post.relabel(&mut truth_vec);
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

/// The case's entry of `results.json`.
pub fn case_result(c: &CaseOutcome) -> CaseResult {
    CaseResult {
        id: c.spec.id.clone(),
        title: c.spec.title.clone(),
        spec_file: spec_file(&c.spec),
        seed: c.spec.seed,
        parameters: c
            .result
            .summary
            .parameters
            .iter()
            .enumerate()
            .map(|(k, p)| CaseParameter {
                summary: p.clone(),
                exact: c.truth[k].is_finite().then_some(c.truth[k]),
                mcse_mean: mcse(c, k),
            })
            .collect(),
        correlation: c.result.summary.correlation.clone(),
        acceptance: c.result.acceptance.clone(),
        rejected_invalid: c.result.rejected_invalid,
        log_posterior_map: c.result.log_posterior_map,
        seconds: c.seconds,
        observations: c.observations.clone(),
    }
}

/// The spec file of a case, relative to the repository (`paper/specs/…`).
pub fn spec_file(spec: &CaseSpec) -> String {
    let name = spec.file.file_name().map_or_else(|| "?".into(), |n| n.to_string_lossy().into_owned());
    format!("paper/specs/{name}")
}

/// Table rows of a group of cases (Tables 7, 8, 12).
pub fn case_table(cases: &[&CaseOutcome]) -> Table {
    let mut t = Table::new(["case", "parameter", "exact"].into_iter().chain(SUMMARY_HEADERS));
    for c in cases {
        for (k, p) in c.result.summary.parameters.iter().enumerate() {
            let exact = if c.truth[k].is_finite() { fmt_sig(c.truth[k], 4) } else { "-".into() };
            t.push_row([c.spec.id.clone(), p.name.clone(), exact].into_iter().chain(summary_cells(p)));
        }
    }
    t
}

/// The cases of a table, in its row order.
pub fn group<'a>(cases: &'a [CaseOutcome], ids: &[String]) -> Vec<&'a CaseOutcome> {
    ids.iter().filter_map(|id| cases.iter().find(|c| c.spec.id == *id)).collect()
}

/// A figure file and what its caption says.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Figure {
    pub file: String,
    pub caption: String,
}

/// One table of cases with its files and figures.
pub struct TableFiles {
    pub files: Vec<(String, String)>,
    pub figures: Vec<Figure>,
}

/// A table of `tables.yaml` (e.g. Table 7) and its Figures (e.g. 4–7).
pub fn table_files(spec: &CaseTable, cases: &[CaseOutcome]) -> Result<TableFiles, ReproduceError> {
    let g = group(cases, &spec.cases);
    let mut out = TableFiles { files: Vec::new(), figures: Vec::new() };
    if g.is_empty() {
        return Ok(out);
    }
    let t = case_table(&g);
    out.files.push((format!("{}.csv", spec.table), t.to_csv()));
    out.files.push((format!("{}.md", spec.table), t.to_markdown()));
    for pf in &spec.parameter_figures {
        parameter_figures(&g, &pf.figure, &pf.parameter, &mut out)?;
    }
    for c in &g {
        let kept = c.result.kept_draws();
        let columns: Vec<Vec<f64>> =
            (0..c.names.len()).map(|k| kept.iter().flatten().map(|t| t[k]).collect()).collect();
        let pp = PairPlot {
            title: format!("{}: pairs, case {}", spec.pair_figure, c.spec.id),
            names: c.names.clone(),
            columns,
            reference: Some(c.truth.clone()),
            max_points: 1500,
            ..PairPlot::default()
        };
        let suffix = if g.len() > 1 { format!("-{}", c.spec.id.to_lowercase()) } else { String::new() };
        let file = format!("{}{suffix}.svg", spec.pair_figure);
        out.files.push((file.clone(), svg::pair_plot(&pp)?));
        out.figures.push(Figure {
            file,
            caption: format!(
                "Case {}: post-burn-in posterior draws (all chains, thinned to 1500 points), marginal histograms on the diagonal, pairwise scatter below; dashed: the true value",
                c.spec.id
            ),
        });
    }
    Ok(out)
}

/// `<figure>a` (trace of chain 1 of every case) and `<figure>b` (marginals) of one parameter.
fn parameter_figures(g: &[&CaseOutcome], fig: &str, name: &str, out: &mut TableFiles) -> Result<(), ReproduceError> {
    let Some(k) = g[0].names.iter().position(|n| n == name) else { return Ok(()) };
    let reference = g[0].truth[k].is_finite().then_some(g[0].truth[k]);
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
        reference,
        ..TracePlot::default()
    };
    out.files.push((format!("{fig}a.svg"), svg::trace_plot(&trace)?));
    out.figures.push(Figure {
        file: format!("{fig}a.svg"),
        caption: format!("{name}: chain 1 of each case, every draw including burn-in; dashed: the true value"),
    });
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
        reference,
        ..HistogramPlot::default()
    };
    out.files.push((format!("{fig}b.svg"), svg::histogram(&hist)?));
    out.figures.push(Figure {
        file: format!("{fig}b.svg"),
        caption: format!("{name}: marginal posterior density of each case (post-burn-in draws of all chains); dashed: the true value"),
    });
    Ok(())
}

/// Monte Carlo standard error of the mean of parameter k: sd/√ESS_bulk.
pub fn mcse(c: &CaseOutcome, k: usize) -> f64 {
    let p = &c.result.summary.parameters[k];
    p.sd / p.ess_bulk.max(1.0).sqrt()
}
