//! Posterior summaries of MCMC output: per-parameter mean, standard deviation,
//! coefficient of variation, equal-tailed 95 % credible interval and
//! convergence diagnostics, plus the correlation matrix of the parameters.
//!
//! All statistics are over the pooled draws of all chains (post burn-in):
//! * mean θ̄ = (1/S) Σ θ_s, sd = sqrt((1/(S−1)) Σ (θ_s − θ̄)²) (ddof 1);
//! * cv = sd/|θ̄| (serialised as `cov`, the name the CLI prints; +∞ when θ̄ = 0);
//! * ci95 = [Q(0.025), Q(0.975)] with Q the type-7 quantile (linear
//!   interpolation between order statistics, numpy's default `method="linear"`);
//! * rhat / ess_bulk / ess_tail from [`crate::bayes::diagnostics`];
//! * correlation: Pearson correlation r_ij = cov_ij/(sd_i sd_j) of the pooled
//!   draws (NaN where a parameter has zero variance; serialised as null).

use serde::{Deserialize, Serialize};

use super::diagnostics::{convergence_and_quantiles, quantile_select, quantile_sorted};

/// Summary of one scalar parameter. Parameters are in their own units (the
/// name carries the unit); `cov` is dimensionless.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParameterSummary {
    pub name: String,
    pub mean: f64,
    pub sd: f64,
    /// Coefficient of variation sd/|mean| (JSON key `cov`).
    #[serde(rename = "cov")]
    pub cv: f64,
    /// Equal-tailed 95 % credible interval [Q(2.5 %), Q(97.5 %)], type-7 quantiles.
    pub ci95: [f64; 2],
    /// Maximum a posteriori value when known (set by the caller, e.g. from an optimiser).
    pub map: Option<f64>,
    pub rhat: f64,
    pub ess_bulk: f64,
    pub ess_tail: f64,
}

/// Summary of all parameters, in the order of the names given to [`summarize`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub parameters: Vec<ParameterSummary>,
    /// Pearson correlation matrix over the pooled draws, `correlation[i][j]`.
    pub correlation: Vec<Vec<f64>>,
}

impl Summary {
    /// Sets the `map` field of each parameter from a MAP point θ* (same order).
    pub fn with_map(mut self, theta_map: &[f64]) -> Self {
        for (p, &v) in self.parameters.iter_mut().zip(theta_map) {
            p.map = Some(v);
        }
        self
    }
}

/// Mean, sd (ddof 1) and type-7 central 95 % interval of one sample of draws
/// (e.g. a TMCMC population, which carries no chain structure).
pub fn describe(values: &[f64]) -> (f64, f64, [f64; 2]) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let sd = (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    (mean, sd, [quantile_sorted(&sorted, 0.025), quantile_sorted(&sorted, 0.975)])
}

/// Summarises `chains[c][s][i]` = parameter i of draw s of chain c.
///
/// # Panics
/// If the chains are empty, have different lengths, or a draw's length differs
/// from `names.len()` (programming errors: samplers produce rectangular output).
pub fn summarize<C: AsRef<[Vec<f64>]>>(names: &[String], chains: &[C]) -> Summary {
    // borrowed chains: `calibrate` passes slices of its chains (no copy of every draw)
    let chains: Vec<&[Vec<f64>]> = chains.iter().map(AsRef::as_ref).collect();
    let d = names.len();
    assert!(!chains.is_empty() && !chains[0].is_empty(), "summarize: no draws");
    let n = chains[0].len();
    assert!(
        chains.iter().all(|c| c.len() == n && c.iter().all(|th| th.len() == d)),
        "summarize: chains must be rectangular with {d} parameters per draw"
    );
    // per_param[i][c][s]
    let per_param: Vec<Vec<Vec<f64>>> =
        (0..d).map(|i| chains.iter().map(|c| c.iter().map(|th| th[i]).collect()).collect()).collect();
    let pooled: Vec<Vec<f64>> = per_param.iter().map(|p| p.iter().flatten().copied().collect()).collect();
    let s = (n * chains.len()) as f64;
    let means: Vec<f64> = pooled.iter().map(|x| x.iter().sum::<f64>() / s).collect();
    // Centred cross-products; computed on centred data for numerical stability.
    let mut cov = vec![vec![0.0; d]; d];
    for i in 0..d {
        for j in 0..=i {
            let c =
                pooled[i].iter().zip(&pooled[j]).map(|(a, b)| (a - means[i]) * (b - means[j])).sum::<f64>() / (s - 1.0);
            cov[i][j] = c;
            cov[j][i] = c;
        }
    }
    let parameters = (0..d)
        .map(|i| {
            // the interval from the sort of the R̂/ESS ranks when there is one
            let ((rhat, ess_bulk, ess_tail), sorted_ci) = convergence_and_quantiles(&per_param[i], [0.025, 0.975]);
            let ci95 = sorted_ci.unwrap_or_else(|| {
                let mut draws = pooled[i].clone();
                [quantile_select(&mut draws, 0.025), quantile_select(&mut draws, 0.975)]
            });
            let sd = cov[i][i].sqrt();
            ParameterSummary {
                name: names[i].clone(),
                mean: means[i],
                sd,
                cv: sd / means[i].abs(),
                ci95,
                map: None,
                rhat,
                ess_bulk,
                ess_tail,
            }
        })
        .collect();
    let correlation = (0..d)
        .map(|i| {
            (0..d)
                .map(|j| if i == j && cov[i][i] > 0.0 { 1.0 } else { cov[i][j] / (cov[i][i] * cov[j][j]).sqrt() })
                .collect()
        })
        .collect();
    Summary { parameters, correlation }
}
