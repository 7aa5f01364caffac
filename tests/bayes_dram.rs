//! DRAM correctness: detailed balance of the n-stage delayed-rejection kernel,
//! stationarity on known targets, flat likelihood → prior, determinism and
//! invalid-proposal handling.

use nalgebra::DMatrix;
use nanobeam::bayes::chains::run_chains;
use nanobeam::bayes::diagnostics::ess;
use nanobeam::bayes::dram::{dr_acceptance, DramSettings};
use nanobeam::bayes::Posterior;
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A posterior given by closures, with a uniform box prior.
struct Target<F: Fn(&[f64]) -> f64 + Sync> {
    lo: Vec<f64>,
    hi: Vec<f64>,
    log_lik: F,
}

impl<F: Fn(&[f64]) -> f64 + Sync> Posterior for Target<F> {
    fn names(&self) -> Vec<String> {
        (0..self.lo.len()).map(|i| format!("x{i}")).collect()
    }
    fn log_prior(&self, t: &[f64]) -> f64 {
        if t.iter().zip(&self.lo).zip(&self.hi).all(|((x, l), h)| x >= l && x <= h) {
            0.0
        } else {
            f64::NEG_INFINITY
        }
    }
    fn log_likelihood(&self, t: &[f64]) -> f64 {
        (self.log_lik)(t)
    }
    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        self.lo.iter().zip(&self.hi).map(|(l, h)| l + (h - l) * rng.gen::<f64>()).collect()
    }
}

/// A skewed, non-Gaussian 3-D log target.
fn log_target(x: &[f64]) -> f64 {
    -0.5 * (x[0] * x[0] + (x[1] - 0.3 * x[0] * x[0]).powi(2) / 0.5) - x[2].abs().powf(1.5) + 0.2 * x[0] * x[2]
}

/// log N(to; from, γ LLᵀ) without the constant shared by both directions.
fn log_q(l: &DMatrix<f64>, gamma: f64, from: &[f64], to: &[f64]) -> f64 {
    let d = nalgebra::DVector::from_iterator(from.len(), to.iter().zip(from).map(|(a, b)| a - b));
    -0.5 * l.solve_lower_triangular(&d).unwrap().norm_squared() / gamma
}

fn random_point(rng: &mut ChaCha8Rng) -> Vec<f64> {
    (0..3).map(|_| rng.gen_range(-1.5..1.5)).collect()
}

fn proposal_chol() -> DMatrix<f64> {
    let c = DMatrix::from_row_slice(3, 3, &[0.8, 0.2, 0.1, 0.2, 0.5, -0.1, 0.1, -0.1, 0.6]);
    c.cholesky().unwrap().l()
}

/// log of the probability flux along a path that is rejected at every stage
/// but the last and accepted there: π(y0) Π_j q_j(y0 → yj) (1 − α_j) · α_last.
/// `alpha` is the acceptance function under test.
/// An acceptance function α(points, log π, path) under test.
type AlphaFn<'a> = dyn Fn(&[Vec<f64>], &[f64], &[usize]) -> f64 + 'a;

fn log_flux(points: &[Vec<f64>], path: &[usize], gammas: &[f64], l: &DMatrix<f64>, alpha: &AlphaFn<'_>) -> f64 {
    let log_pi: Vec<f64> = points.iter().map(|p| log_target(p)).collect();
    let y0 = path[0];
    let mut f = log_pi[y0];
    for j in 1..path.len() {
        f += log_q(l, gammas[j - 1], &points[y0], &points[path[j]]);
        let a = alpha(points, &log_pi, &path[..=j]);
        f += if j + 1 < path.len() { (1.0 - a).ln() } else { a.ln() };
    }
    f
}

/// Largest relative flux mismatch |F_fwd − F_rev| / max(F) over random paths.
fn worst_balance_error(stages: usize, alpha: &AlphaFn<'_>) -> f64 {
    let l = proposal_chol();
    let gammas = [1.0, 0.1, 0.05];
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut worst: f64 = 0.0;
    let mut informative = 0;
    for _ in 0..20_000 {
        let points: Vec<Vec<f64>> = (0..=stages).map(|_| random_point(&mut rng)).collect();
        let fwd: Vec<usize> = (0..=stages).collect();
        let rev: Vec<usize> = fwd.iter().rev().copied().collect();
        let ff = log_flux(&points, &fwd, &gammas, &l, alpha);
        let fr = log_flux(&points, &rev, &gammas, &l, alpha);
        if ff.is_finite() || fr.is_finite() {
            informative += 1;
            let (a, b) = (ff.exp(), fr.exp());
            worst = worst.max((a - b).abs() / a.max(b));
        }
    }
    assert!(informative > 1000, "too few paths with non-zero flux: {informative}");
    worst
}

/// Detailed balance of the DR kernel for 2 and 3 stages. Both fluxes are
/// products of the same O(10) floating-point factors in a different order, so
/// they agree to a few ulps (~1e-15); 1e-10 is the bound and leaves
/// room for exp/ln rounding of O(1) logs.
#[test]
fn delayed_rejection_satisfies_detailed_balance() {
    let l = proposal_chol();
    let gammas = [1.0, 0.1, 0.05];
    let alpha = |p: &[Vec<f64>], lp: &[f64], path: &[usize]| dr_acceptance(p, lp, path, &gammas, &l);
    for stages in [2, 3] {
        let err = worst_balance_error(stages, &alpha);
        assert!(err < 1e-10, "{stages} stages: relative flux mismatch {err:e}");
    }
}

/// The same check rejects a plausible wrong formula: the stage-2 ratio
/// without the q1 and (1 − α1) reverse-path factors (a common mistake).
#[test]
fn detailed_balance_check_detects_a_wrong_acceptance() {
    let l = proposal_chol();
    let gammas = [1.0, 0.1, 0.05];
    let wrong = |p: &[Vec<f64>], lp: &[f64], path: &[usize]| {
        if path.len() == 2 {
            dr_acceptance(p, lp, path, &gammas, &l)
        } else {
            let (a, b) = (path[0], path[path.len() - 1]);
            (lp[b] - lp[a]).exp().min(1.0)
        }
    };
    let err = worst_balance_error(2, &wrong);
    assert!(err > 1e-3, "the wrong formula passed the balance check: {err:e}");
}

fn short_settings() -> DramSettings {
    DramSettings { draws_per_chain: 40_000, burn_in: 5_000, ..DramSettings::default() }
}

/// Pooled post-burn-in draws of parameter k, per chain.
fn per_chain(chains: &[nanobeam::bayes::dram::ChainOutput], burn: usize, f: impl Fn(&[f64]) -> f64) -> Vec<Vec<f64>> {
    chains.iter().map(|c| c.draws[burn..].iter().map(|t| f(t)).collect()).collect()
}

/// |mean of f − truth| within 4 Monte Carlo standard errors, SE = sd/√ESS
/// (ESS by Geyer's initial monotone sequence over the chains).
fn assert_within_mcse(chains: &[Vec<f64>], truth: f64, what: &str) {
    let all: Vec<f64> = chains.concat();
    let n = all.len() as f64;
    let mean = all.iter().sum::<f64>() / n;
    let var = all.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let se = (var / ess(chains)).sqrt();
    assert!((mean - truth).abs() < 4.0 * se, "{what}: mean {mean} vs truth {truth}, 4 SE = {}", 4.0 * se);
}

#[test]
fn stationary_on_correlated_gaussian() {
    // Σ with correlations 0.9, −0.5 and scales 1, 10, 0.1.
    let sigma = DMatrix::from_row_slice(3, 3, &[1.0, 9.0, -0.05, 9.0, 100.0, -0.2, -0.05, -0.2, 0.01]);
    let prec = sigma.clone().try_inverse().unwrap();
    let mu = [1.0, -2.0, 0.5];
    let target = Target {
        lo: vec![-50.0, -500.0, -5.0],
        hi: vec![50.0, 500.0, 5.0],
        log_lik: move |x: &[f64]| {
            let d = nalgebra::DVector::from_iterator(3, x.iter().zip(&mu).map(|(a, b)| a - b));
            -0.5 * (d.transpose() * &prec * &d)[0]
        },
    };
    let starts: Vec<Vec<f64>> = (0..4).map(|c| vec![0.5 + 0.1 * c as f64, 0.0, 0.4]).collect();
    let s = short_settings();
    let chains = run_chains(&target, &s, &[0.5, 5.0, 0.05], &starts, 7, None).expect("valid settings");
    for k in 0..3 {
        assert_within_mcse(&per_chain(&chains, s.burn_in, |t| t[k]), mu[k], &format!("mean x{k}"));
        for m in k..3 {
            let prod = per_chain(&chains, s.burn_in, |t| (t[k] - mu[k]) * (t[m] - mu[m]));
            assert_within_mcse(&prod, sigma[(k, m)], &format!("cov x{k} x{m}"));
        }
    }
}

/// Haario's twisted Gaussian: x1 ~ N(0, a²), x2 | x1 ~ N(−b(x1² − a²), 1), so
/// E = 0, Var x1 = a², Var x2 = 1 + 2 b² a⁴, Cov = 0.
#[test]
fn stationary_on_banana() {
    let (a, b) = (2.0f64, 0.25f64);
    let target = Target {
        lo: vec![-40.0, -80.0],
        hi: vec![40.0, 80.0],
        log_lik: move |x: &[f64]| {
            let y2 = x[1] + b * (x[0] * x[0] - a * a);
            -0.5 * (x[0] * x[0] / (a * a) + y2 * y2)
        },
    };
    let starts: Vec<Vec<f64>> = (0..4).map(|c| vec![0.1 * c as f64, 0.0]).collect();
    let s = DramSettings { draws_per_chain: 60_000, ..short_settings() };
    let chains = run_chains(&target, &s, &[1.0, 1.0], &starts, 3, None).expect("valid settings");
    let burn = s.burn_in;
    assert_within_mcse(&per_chain(&chains, burn, |t| t[0]), 0.0, "mean x1");
    assert_within_mcse(&per_chain(&chains, burn, |t| t[1]), 0.0, "mean x2");
    assert_within_mcse(&per_chain(&chains, burn, |t| t[0] * t[0]), a * a, "var x1");
    assert_within_mcse(&per_chain(&chains, burn, |t| t[1] * t[1]), 1.0 + 2.0 * b * b * a.powi(4), "var x2");
    assert_within_mcse(&per_chain(&chains, burn, |t| t[0] * t[1]), 0.0, "cov x1 x2");
}

/// A flat likelihood returns the prior: uniform box [0, 2] × [−1, 3].
#[test]
fn flat_likelihood_returns_the_prior() {
    let target = Target { lo: vec![0.0, -1.0], hi: vec![2.0, 3.0], log_lik: |_x: &[f64]| 0.0 };
    let starts: Vec<Vec<f64>> = (0..4).map(|c| vec![1.0, 0.1 * c as f64]).collect();
    let s = short_settings();
    let chains = run_chains(&target, &s, &[0.1, 0.2], &starts, 5, None).expect("valid settings");
    assert_within_mcse(&per_chain(&chains, s.burn_in, |t| t[0]), 1.0, "mean x0");
    assert_within_mcse(&per_chain(&chains, s.burn_in, |t| t[1]), 1.0, "mean x1");
    // Var of U[a, b] = (b − a)²/12.
    assert_within_mcse(&per_chain(&chains, s.burn_in, |t| (t[0] - 1.0).powi(2)), 4.0 / 12.0, "var x0");
    assert_within_mcse(&per_chain(&chains, s.burn_in, |t| (t[1] - 1.0).powi(2)), 16.0 / 12.0, "var x1");
}

#[test]
fn deterministic_for_any_thread_count_and_distinct_across_chains() {
    let target =
        Target { lo: vec![-5.0; 2], hi: vec![5.0; 2], log_lik: |x: &[f64]| -0.5 * (x[0] * x[0] + x[1] * x[1]) };
    let starts = vec![vec![0.0, 0.0]; 3];
    let s = DramSettings { draws_per_chain: 6_000, burn_in: 1_000, ..DramSettings::default() };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run_chains(&target, &s, &[0.5, 0.5], &starts, 42, None).expect("valid settings"))
    };
    let one = run(1);
    let two = run(2);
    assert_eq!(one, two);
    assert_ne!(one[0].draws, one[1].draws, "chains share a random stream");
    assert_eq!(run(2), two);
}

/// A region where the model returns NaN is never entered, and every such
/// proposal is counted.
#[test]
fn nan_model_output_is_a_counted_rejection() {
    let target = Target {
        lo: vec![-3.0],
        hi: vec![3.0],
        log_lik: |x: &[f64]| if x[0] > 1.0 { f64::NAN } else { -0.5 * x[0] * x[0] },
    };
    let s = DramSettings { draws_per_chain: 10_000, burn_in: 1_000, ..DramSettings::default() };
    let chains = run_chains(&target, &s, &[1.0], &[vec![0.0]], 1, None).expect("valid settings");
    assert!(chains[0].rejected_invalid > 100);
    assert!(chains[0].draws.iter().all(|t| t[0] <= 1.0));
}
