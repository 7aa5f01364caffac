//! Overdispersed chain starts (issue 14, item 5): on a bimodal target whose
//! modes no chain can cross, chains placed one proposal step from the best
//! optimum agree with each other and miss a mode (split-R̂ ≈ 1), while the
//! overdispersed starts of `calibrate_posterior` put chains in both modes and
//! split-R̂ flags it.

use nanobeam::bayes::chains::run_chains;
use nanobeam::bayes::diagnostics::rhat;
use nanobeam::bayes::map::multi_start_optimum;
use nanobeam::bayes::Posterior;
use nanobeam::calibration::run::{overdispersed_starts, single_start};
use nanobeam::calibration::DramSettings;
use rand::{Rng, RngCore};

/// Two Gaussian modes, at x = −4 (sd 0.25, the higher peak) and x = +4 (sd
/// 0.4), equal mass, on the box [−10, 10]². Halfway between them the density
/// is below e^{−50} of either peak, so a random-walk chain never crosses.
struct Bimodal;

const CENTRES: [f64; 2] = [-4.0, 4.0];
const SDS: [f64; 2] = [0.25, 0.4];

impl Posterior for Bimodal {
    fn names(&self) -> Vec<String> {
        vec!["x".into(), "y".into()]
    }
    fn log_prior(&self, t: &[f64]) -> f64 {
        if t.iter().all(|x| (-10.0..=10.0).contains(x)) {
            0.0
        } else {
            f64::NEG_INFINITY
        }
    }
    fn log_likelihood(&self, t: &[f64]) -> f64 {
        let comp = |k: usize| {
            let s = SDS[k];
            -0.5 * (((t[0] - CENTRES[k]) / s).powi(2) + (t[1] / s).powi(2)) - 2.0 * s.ln()
        };
        let (a, b) = (comp(0), comp(1));
        let m = a.max(b);
        m + ((a - m).exp() + (b - m).exp()).ln()
    }
    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        (0..2).map(|_| -10.0 + 20.0 * rng.gen::<f64>()).collect()
    }
}

fn sampler(seed: u64) -> DramSettings {
    DramSettings {
        draws_per_chain: 3000,
        burn_in: 1000,
        nonadaptive_draws: 500,
        adaptation_start: 500,
        covariance_skip: 200,
        chains: 4,
        seed,
        multistart_points: 64,
        ..DramSettings::default()
    }
}

/// Post-burn-in x of every chain.
fn x_chains(post: &Bimodal, starts: &[Vec<f64>], s: &DramSettings) -> Vec<Vec<f64>> {
    let c0 = [0.1, 0.1];
    run_chains(post, s, &c0, starts, s.seed, None)
        .expect("valid settings")
        .iter()
        .map(|c| c.draws[s.burn_in..].iter().map(|t| t[0]).collect())
        .collect()
}

/// The side (−1 / +1) of every chain's mean.
fn sides(x: &[Vec<f64>]) -> Vec<f64> {
    x.iter().map(|c| (c.iter().sum::<f64>() / c.len() as f64).signum()).collect()
}

#[test]
fn single_start_chains_agree_and_miss_a_mode_overdispersed_chains_flag_it() {
    let post = Bimodal;
    let c0 = [0.1, 0.1];
    for seed in 1..=3 {
        let s = sampler(seed);
        let optima = multi_start_optimum(&post, &c0, s.multistart_points, 4, seed, 0);
        // Single start: all chains on one side, and R̂ cannot tell.
        let single = x_chains(&post, &single_start(&post, &c0, &optima[0].theta, 4, seed), &s);
        let side = sides(&single);
        assert!(side.iter().all(|x| *x == side[0]), "seed {seed}: single-start chains split: {side:?}");
        let r_single = rhat(&single);
        // Within one Gaussian mode, 4 × 2000 draws: split-R̂ − 1 is O(1/ESS) ≈ 1e-3.
        assert!(r_single < 1.01, "seed {seed}: single-start R-hat {r_single}");
        // Overdispersed: both modes occupied, R̂ far above any threshold. With
        // half the chains at −4 and half at +4 (sd ≤ 0.4), between-chain variance
        // is ≈ 16 against within ≈ 0.1: R̂ ≈ √(1 + 16/0.1) ≫ 1.1.
        let starts = overdispersed_starts(&post, &c0, &optima, 4, seed);
        let over = x_chains(&post, &starts, &s);
        let side = sides(&over);
        assert!(side.contains(&-1.0) && side.contains(&1.0), "seed {seed}: overdispersed chains in one mode: {side:?}");
        let r_over = rhat(&over);
        assert!(r_over > 1.1, "seed {seed}: overdispersed R-hat {r_over} does not flag the second mode");
    }
}

#[test]
fn overdispersed_starts_are_keyed_and_distinct() {
    let post = Bimodal;
    let c0 = [0.1, 0.1];
    let optima = multi_start_optimum(&post, &c0, 64, 4, 7, 0);
    let a = overdispersed_starts(&post, &c0, &optima, 4, 7);
    assert_eq!(a, overdispersed_starts(&post, &c0, &optima, 4, 7), "same seed, same starts");
    assert_ne!(a, overdispersed_starts(&post, &c0, &optima, 4, 8), "the seed keys the starts");
    for i in 0..4 {
        for j in 0..i {
            assert_ne!(a[i], a[j], "chains {i} and {j} share a start");
        }
    }
}
