//! Files a calibration writes: `chains.csv` (chain, draw, θ…, log posterior;
//! readable by pandas), `summary.json`, `inference_data.nc` (ArviZ
//! InferenceData: `arviz.from_netcdf("inference_data.nc")`), and SVG trace,
//! marginal and pair plots. Plain data in, files out; the directory is
//! written atomically.

use std::path::Path;

use crate::bayes::rng::{stream, Purpose};
use crate::bayes::summary::ParameterSummary;
use crate::bayes::Posterior;
use crate::calibration::{BeamPosterior, CalibrationResult};
use crate::report::inference_data::{Group, InferenceData, Variable};
use crate::report::svg::{self, HistogramPlot, NamedValues, PairPlot, TracePlot};
use crate::report::table::{fmt_interval, fmt_sig, NumberFormatter};
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
    // The same bytes as `write!(s, "{c},{i}")` and `",{x:e}"`, through zmij/itoa
    // (`NumberFormatter`): core::fmt made this file ~10 % of a whole calibrate.
    let rows: usize = result.chains.iter().map(|c| c.draws.len().saturating_sub(result.burn_in)).sum();
    // ~16 bytes per number: one allocation for the whole file
    s.reserve(rows * (12 + 16 * (result.names.len() + 1)));
    let mut f = NumberFormatter::default();
    // A rejected proposal repeats the previous draw: the text of a row's
    // numbers is a function of their bits, so a row whose θ and log posterior
    // are bitwise those of the previous row reuses its text (about a quarter
    // of the rows of a typical run).
    let mut numbers = String::new();
    let mut previous: Option<(&[f64], u64)> = None;
    for (c, chain) in result.chains.iter().enumerate() {
        for i in result.burn_in..chain.draws.len() {
            f.push_int(&mut s, c);
            s.push(',');
            f.push_int(&mut s, i);
            let (theta, lp) = (chain.draws[i].as_slice(), chain.log_posterior[i]);
            let repeated = previous.is_some_and(|(t, l)| {
                l == lp.to_bits()
                    && t.len() == theta.len()
                    && t.iter().zip(theta).all(|(a, b)| a.to_bits() == b.to_bits())
            });
            if !repeated {
                numbers.clear();
                for &x in theta {
                    numbers.push(',');
                    f.push_lower_exp(&mut numbers, x);
                }
                numbers.push(',');
                f.push_lower_exp(&mut numbers, lp);
                numbers.push('\n');
                previous = Some((theta, lp.to_bits()));
            }
            s.push_str(&numbers);
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

/// At most this many draws per chain go into `inference_data.nc` (every k-th
/// kept draw, k = ⌈kept/1000⌉): the pointwise log-likelihood costs one forward
/// solve per stored draw, and 1000 draws per chain resolve LOO and posterior
/// summaries well below their Monte Carlo error at the chains' ESS.
/// `chains.csv` keeps every draw.
pub const INFERENCE_DATA_MAX_DRAWS: usize = 1000;

/// Prior draws in the InferenceData `prior` group.
pub const INFERENCE_DATA_PRIOR_DRAWS: usize = 1000;

/// What the InferenceData file needs besides the chains.
pub struct InferenceContext<'a> {
    pub posterior: &'a BeamPosterior,
    /// The calibration's master seed (attribute; keys the prior draws).
    pub seed: u64,
}

fn chain_draw(chains: usize, draws: usize) -> Vec<(String, usize)> {
    vec![("chain".into(), chains), ("draw".into(), draws)]
}

/// The groups ArviZ reads: `posterior` and `sample_stats` (chain, draw),
/// `log_likelihood` (chain, draw, mode; one variable per observable:
/// `omega_rad_s`, `zeta`, for LOO), `observed_data` (mode), `prior` (1 chain
/// of prior draws), and attributes (nanobeam version, seed, thinning).
pub fn inference_data(result: &CalibrationResult, ctx: &InferenceContext) -> InferenceData {
    let post = ctx.posterior;
    let kept = result.chains.first().map_or(0, |c| c.draws.len() - result.burn_in);
    let stride = kept.div_ceil(INFERENCE_DATA_MAX_DRAWS).max(1);
    let idx: Vec<usize> = (result.burn_in..result.burn_in + kept).step_by(stride).collect();
    let (nc, nd) = (result.chains.len(), idx.len());
    let per_draw = |f: &dyn Fn(usize, usize) -> f64| -> Vec<f64> {
        (0..nc).flat_map(|c| idx.iter().map(move |&i| (c, i))).map(|(c, i)| f(c, i)).collect()
    };
    let posterior = Group {
        name: "posterior".into(),
        variables: (0..result.names.len())
            .map(|k| Variable {
                name: result.names[k].clone(),
                dims: chain_draw(nc, nd),
                values: per_draw(&|c, i| result.chains[c].draws[i][k]),
            })
            .collect(),
        ..Group::default()
    };
    let stages = result.chains.first().map_or(0, |c| c.accepted.len());
    let sample_stats = Group {
        name: "sample_stats".into(),
        variables: vec![
            Variable {
                name: "lp".into(),
                dims: chain_draw(nc, nd),
                values: per_draw(&|c, i| result.chains[c].log_posterior[i]),
            },
            Variable {
                name: "acceptance_rate_per_dr_stage".into(),
                dims: vec![("chain".into(), nc), ("dr_stage".into(), stages)],
                values: result.chains.iter().flat_map(|c| c.acceptance_per_stage()).collect(),
            },
        ],
        ..Group::default()
    };
    let (log_likelihood, observed) = pointwise(result, post, &idx);
    let mut rng = stream(ctx.seed, Purpose::PriorDraws, [0, 0]);
    let prior_draws: Vec<Vec<f64>> = (0..INFERENCE_DATA_PRIOR_DRAWS).map(|_| post.sample_prior(&mut rng)).collect();
    let prior = Group {
        name: "prior".into(),
        variables: (0..result.names.len())
            .map(|k| Variable {
                name: result.names[k].clone(),
                dims: chain_draw(1, INFERENCE_DATA_PRIOR_DRAWS),
                values: prior_draws.iter().map(|t| t[k]).collect(),
            })
            .collect(),
        ..Group::default()
    };
    let attributes = vec![
        ("nanobeam_version".to_string(), env!("CARGO_PKG_VERSION").to_string()),
        ("inference_library".to_string(), "nanobeam (DRAM)".to_string()),
        ("seed".to_string(), ctx.seed.to_string()),
        ("thinning".to_string(), format!("every {stride}-th post-burn-in draw (burn-in {})", result.burn_in)),
    ];
    let groups = [posterior, sample_stats, log_likelihood, observed, prior]
        .into_iter()
        .map(|mut g| {
            g.attributes = attributes.clone();
            g
        })
        .collect();
    InferenceData { groups, attributes }
}

/// `log_likelihood` and `observed_data`: log N(y_k | A_k(θ), (β σ_k)²) of
/// every observable at every stored draw (eq. 26/41 term by term; NaN where the
/// model fails), and y itself.
fn pointwise(result: &CalibrationResult, post: &BeamPosterior, idx: &[usize]) -> (Group, Group) {
    use rayon::prelude::*;
    let (y, sd) = (post.observed(), post.sd());
    let m = post.fitted_modes().len();
    // the scans' points follow the modes' ω and ζ (posterior module doc)
    let points = y.len() - 2 * m;
    let thetas: Vec<&Vec<f64>> = result.chains.iter().flat_map(|c| idx.iter().map(move |&i| &c.draws[i])).collect();
    let terms: Vec<Vec<f64>> = thetas
        .par_iter()
        .map(|t| match post.predict(t) {
            Some(p) => {
                let beta = post.beta_at(t);
                (0..y.len())
                    .map(|k| {
                        let s = beta * sd[k];
                        -0.5 * ((y[k] - p[k]) / s).powi(2) - s.ln() - 0.5 * (2.0 * std::f64::consts::PI).ln()
                    })
                    .collect()
            }
            None => vec![f64::NAN; y.len()],
        })
        .collect();
    let dims = vec![("chain".into(), result.chains.len()), ("draw".into(), idx.len()), ("mode".into(), m)];
    let var = |name: &str, off: usize, (dim, len): (&str, usize)| {
        let mut dims = dims.clone();
        dims[2] = (dim.into(), len);
        Variable {
            name: name.into(),
            dims,
            values: terms.iter().flat_map(|t| t[off..off + len].iter().copied()).collect(),
        }
    };
    let obs = |name: &str, off: usize, (dim, len): (&str, usize)| Variable {
        name: name.into(),
        dims: vec![(dim.into(), len)],
        values: y[off..off + len].to_vec(),
    };
    let mut log_likelihood = vec![var("omega_rad_s", 0, ("mode", m)), var("zeta", m, ("mode", m))];
    let mut observed = vec![obs("omega_rad_s", 0, ("mode", m)), obs("zeta", m, ("mode", m))];
    if points > 0 {
        log_likelihood.push(var("relative_amplitude", 2 * m, ("scan_point", points)));
        observed.push(obs("relative_amplitude", 2 * m, ("scan_point", points)));
    }
    (
        Group { name: "log_likelihood".into(), variables: log_likelihood, ..Group::default() },
        Group { name: "observed_data".into(), variables: observed, ..Group::default() },
    )
}

/// Writes every file of a calibration into `dir` (which must exist).
/// `reference` optionally marks true values with dashed lines; with an
/// [`InferenceContext`] the ArviZ file `inference_data.nc` is written too.
pub fn write_calibration_files(
    dir: &Path,
    result: &CalibrationResult,
    reference: Option<&[f64]>,
    inference: Option<&InferenceContext>,
) -> Result<(), ReportError> {
    let io = |path: &Path, e: std::io::Error| ReportError::Io { path: path.to_path_buf(), source: e };
    let write = |name: &str, text: &str| {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(|e| io(&p, e))
    };
    write("chains.csv", &chains_csv(result))?;
    let json = serde_json::to_string_pretty(&summary_json(result)).expect("summary serialises");
    write("summary.json", &(json + "\n"))?;
    if let Some(ctx) = inference {
        let p = dir.join("inference_data.nc");
        std::fs::write(&p, inference_data(result, ctx).to_netcdf()?).map_err(|e| io(&p, e))?;
    }
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
