//! Maximum a posteriori estimates by Nelder–Mead (argmin), and a multi-start
//! optimiser used to place chains in multimodal posteriors.
//!
//! The simplex lives in standardised coordinates u = (θ − θstart)/scale so the
//! method is scale-invariant (Ω ~ 1e12 rad/s next to Δ ~ 0.5).

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;

use crate::bayes::rng::{stream, Purpose};
use crate::bayes::Posterior;

/// Cost given to infeasible points: finite so the simplex arithmetic stays finite.
const INFEASIBLE_COST: f64 = 1e300;

#[derive(Debug, Clone, PartialEq)]
pub struct MapResult {
    pub theta: Vec<f64>,
    pub log_posterior: f64,
    pub iterations: u64,
}

struct NegLogPosterior<'a> {
    post: &'a dyn Posterior,
    origin: &'a [f64],
    scales: &'a [f64],
}

impl NegLogPosterior<'_> {
    fn theta(&self, u: &[f64]) -> Vec<f64> {
        u.iter().zip(self.origin).zip(self.scales).map(|((u, o), s)| o + u * s).collect()
    }
}

impl CostFunction for NegLogPosterior<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Self::Param) -> Result<f64, ArgminError> {
        let lp = self.post.log_posterior(&self.theta(u));
        Ok(if lp.is_finite() { -lp } else { INFEASIBLE_COST })
    }
}

/// Nelder–Mead from `start`, initial simplex of one `scales` step per axis.
pub fn map_estimate(post: &dyn Posterior, start: &[f64], scales: &[f64], max_iters: u64) -> MapResult {
    let d = start.len();
    let problem = NegLogPosterior { post, origin: start, scales };
    let mut simplex = vec![vec![0.0; d]];
    for k in 0..d {
        let mut v = vec![0.0; d];
        v[k] = 1.0;
        simplex.push(v);
    }
    let fallback = MapResult { theta: start.to_vec(), log_posterior: post.log_posterior(start), iterations: 0 };
    let Ok(solver) = NelderMead::new(simplex).with_sd_tolerance(1e-12) else {
        return fallback;
    };
    match Executor::new(problem, solver).configure(|s| s.max_iters(max_iters)).run() {
        Ok(res) => {
            let state = res.state();
            let u = state.best_param.clone().unwrap_or_else(|| vec![0.0; d]);
            let problem = NegLogPosterior { post, origin: start, scales };
            let theta = problem.theta(&u);
            let lp = post.log_posterior(&theta);
            if lp >= fallback.log_posterior || !fallback.log_posterior.is_finite() {
                MapResult { theta, log_posterior: lp, iterations: state.iter }
            } else {
                fallback
            }
        }
        Err(_) => fallback,
    }
}

/// Draws `n_points` prior samples (stream `(seed, MultiStart, [run, 0])`), keeps the `keep` best and polishes
/// each with Nelder–Mead (restarted once). Returns optima sorted by log
/// posterior, best first.
pub fn multi_start_optimum(
    post: &dyn Posterior,
    scales: &[f64],
    n_points: usize,
    keep: usize,
    seed: u64,
    run: u64,
) -> Vec<MapResult> {
    let rng = stream(seed, Purpose::MultiStart, [run, 0]);
    multi_start_from(post, scales, n_points, keep, rng, 2000)
}

/// [`multi_start_optimum`] with the prior points drawn from `rng` and at
/// most `max_iters` Nelder–Mead iterations per polish.
pub fn multi_start_from(
    post: &dyn Posterior,
    scales: &[f64],
    n_points: usize,
    keep: usize,
    mut rng: rand_chacha::ChaCha8Rng,
    max_iters: u64,
) -> Vec<MapResult> {
    let candidates: Vec<Vec<f64>> = (0..n_points).map(|_| post.sample_prior(&mut rng)).collect();
    polish_best(post, scales, candidates, keep, max_iters)
}

/// The `keep` best of `candidates` by log posterior (infeasible ones
/// dropped), each polished by Nelder–Mead with simplex steps `scales`, then
/// restarted once at a tenth of them; the optima sorted best first. Ties
/// keep the candidates' order, so the result depends on it alone.
pub fn polish_best(
    post: &dyn Posterior,
    scales: &[f64],
    candidates: Vec<Vec<f64>>,
    keep: usize,
    max_iters: u64,
) -> Vec<MapResult> {
    let mut scored: Vec<(f64, Vec<f64>)> = candidates.into_par_iter().map(|t| (post.log_posterior(&t), t)).collect();
    scored.retain(|(lp, _)| lp.is_finite());
    scored.sort_by(|a, b| b.0.total_cmp(&a.0));
    scored.truncate(keep.max(1));
    let mut optima: Vec<MapResult> = scored
        .into_par_iter()
        .map(|(_, t)| {
            let first = map_estimate(post, &t, scales, max_iters);
            let small: Vec<f64> = scales.iter().map(|s| s * 0.1).collect();
            map_estimate(post, &first.theta, &small, max_iters)
        })
        .collect();
    optima.sort_by(|a, b| b.log_posterior.total_cmp(&a.log_posterior));
    optima
}
