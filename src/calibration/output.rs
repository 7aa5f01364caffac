//! Files a calibration writes: `chains.csv` (chain, draw, θ…, log posterior;
//! readable by pandas/ArviZ), `summary.json`, and SVG trace, marginal and pair
//! plots. Plain data in, files out; the directory is written atomically.

use std::path::Path;

use crate::bayes::summary::ParameterSummary;
use crate::calibration::CalibrationResult;
use crate::report::svg::{self, HistogramPlot, NamedValues, PairPlot, TracePlot};
use crate::report::table::{fmt_interval, fmt_sig};
use crate::report::ReportError;

/// Column headers of [`summary_cells`].
pub const SUMMARY_HEADERS: [&str; 8] = ["mean", "sd", "sd/mean", "CI95", "MAP", "R-hat", "ESS bulk", "ESS tail"];

/// One parameter's summary as table cells (the columns of [`SUMMARY_HEADERS`]).
pub fn summary_cells(p: &ParameterSummary) -> Vec<String> {
    vec![
        fmt_sig(p.mean, 4),
        fmt_sig(p.sd, 3),
        fmt_sig(p.cv, 3),
        fmt_interval(p.ci95[0], p.ci95[1], 4),
        p.map.map_or("-".into(), |m| fmt_sig(m, 4)),
        format!("{:.4}", p.rhat),
        format!("{:.0}", p.ess_bulk),
        format!("{:.0}", p.ess_tail),
    ]
}

/// `chains.csv`: post-burn-in draws; `draw` is the index in the full chain.
pub fn chains_csv(result: &CalibrationResult) -> String {
    let mut s = String::from("chain,draw");
    for n in &result.names {
        s.push(',');
        s.push_str(n);
    }
    s.push_str(",log_posterior\n");
    for (c, chain) in result.chains.iter().enumerate() {
        for i in result.burn_in..chain.draws.len() {
            s.push_str(&format!("{c},{i}"));
            for x in &chain.draws[i] {
                s.push_str(&format!(",{x:e}"));
            }
            s.push_str(&format!(",{:e}\n", chain.log_posterior[i]));
        }
    }
    s
}

/// `summary.json`: the CLI JSON plus the correlation matrix, the chain starts
/// and the per-chain acceptance.
pub fn summary_json(result: &CalibrationResult) -> serde_json::Value {
    serde_json::json!({
        "parameters": result.summary.parameters,
        "acceptance": result.acceptance,
        "rejected_invalid": result.rejected_invalid,
        "log_posterior_map": result.log_posterior_map,
        "map": result.map_theta,
        "correlation": result.summary.correlation,
        "chain_starts": result.starts,
        "acceptance_per_chain": result.chains.iter().map(|c| c.acceptance_per_stage()).collect::<Vec<_>>(),
        "burn_in": result.burn_in,
        "warnings": result.warnings,
    })
}

/// Writes every file of a calibration into `dir` (which must exist).
/// `reference` optionally marks true values with dashed lines.
pub fn write_calibration_files(
    dir: &Path,
    result: &CalibrationResult,
    reference: Option<&[f64]>,
) -> Result<(), ReportError> {
    let io = |path: &Path, e: std::io::Error| ReportError::Io { path: path.to_path_buf(), source: e };
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| io(&p, e))
    };
    write("chains.csv", &chains_csv(result))?;
    let json = serde_json::to_string_pretty(&summary_json(result)).expect("summary serialises");
    write("summary.json", &(json + "\n"))?;
    for (k, name) in result.names.iter().enumerate() {
        let per_chain: Vec<NamedValues> = result
            .chains
            .iter()
            .enumerate()
            .map(|(c, ch)| NamedValues {
                name: format!("chain {}", c + 1),
                values: ch.draws.iter().map(|t| t[k]).collect(),
            })
            .collect();
        let trace = TracePlot {
            title: format!("Trace of {name}"),
            y_label: name.clone(),
            chains: per_chain,
            reference: reference.map(|r| r[k]),
            ..TracePlot::default()
        };
        write(&format!("trace_{name}.svg"), &svg::trace_plot(&trace)?)?;
        let kept: Vec<NamedValues> = result
            .chains
            .iter()
            .enumerate()
            .map(|(c, ch)| NamedValues {
                name: format!("chain {}", c + 1),
                values: ch.draws[result.burn_in..].iter().map(|t| t[k]).collect(),
            })
            .collect();
        let hist = HistogramPlot {
            title: format!("Marginal posterior of {name}"),
            x_label: name.clone(),
            groups: kept,
            reference: reference.map(|r| r[k]),
            ..HistogramPlot::default()
        };
        write(&format!("marginal_{name}.svg"), &svg::histogram(&hist)?)?;
    }
    let columns: Vec<Vec<f64>> = (0..result.names.len())
        .map(|k| result.chains.iter().flat_map(|ch| ch.draws[result.burn_in..].iter().map(move |t| t[k])).collect())
        .collect();
    let pair = PairPlot {
        title: "Posterior pairs".into(),
        names: result.names.clone(),
        columns,
        reference: reference.map(|r| r.to_vec()),
        ..PairPlot::default()
    };
    write("pairs.svg", &svg::pair_plot(&pair)?)?;
    Ok(())
}
