//! `bayes::control` (src/bayes/control.rs): a control that is not cancelled
//! changes no bit of DRAM's, TMCMC's, a MAP search's, an importance batch's or
//! the evidence estimator's output; a cancel stops them within the work
//! between two polls (for the searches and batches seen through
//! `Controlled`: one evaluation per thread); progress counts every DRAM state
//! once.
//!
//! Target ("tripwire Gaussian", written here): a standard normal prior and a
//! Gaussian likelihood N(θ; 1, 0.5²) per coordinate that counts its
//! evaluations and cancels a shared control at evaluation K. The bound on
//! the evaluations after the cancel follows from where the samplers poll
//! (before each TMCMC sample's likelihood or moves, after each DRAM step):
//! at most one unit of polled work per thread that was inside one.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use nanobeam::bayes::chains::{chain_rng, run_chains};
use nanobeam::bayes::dram::{run_chain, DramSettings};
use nanobeam::bayes::evidence::{estimate, EvidenceSettings};
use nanobeam::bayes::importance::importance_log_evidence;
use nanobeam::bayes::map::{map_estimate, multi_start_optimum};
use nanobeam::bayes::tmcmc::{tmcmc, tmcmc_controlled, TmcmcConfig};
use nanobeam::bayes::{BayesError, Cancelled, Control, Controlled, Posterior, Progress};
use rand::RngCore;
use rand_distr::{Distribution, StandardNormal};

struct Tripwire {
    d: usize,
    evaluations: AtomicU64,
    /// cancel `control` at this evaluation (0: never)
    at: u64,
    /// the evaluation count read just after the cancel: the evaluations a
    /// thread started while the cancelling one was between its count and
    /// its cancel (it may be descheduled there) began before the cancel and
    /// are not the control's to stop, so bounds count from here
    counted_at_cancel: AtomicU64,
    control: Control,
}

impl Tripwire {
    fn new(d: usize, at: u64) -> Self {
        Self {
            d,
            evaluations: AtomicU64::new(0),
            at,
            counted_at_cancel: AtomicU64::new(0),
            control: Control::default(),
        }
    }

    /// Evaluations counted after the cancel took effect (see `counted_at_cancel`).
    fn evaluations_after_the_cancel(&self) -> u64 {
        let at_cancel = self.counted_at_cancel.load(Ordering::SeqCst);
        assert!(at_cancel >= self.at, "the trip at evaluation {} never fired", self.at);
        self.evaluations.load(Ordering::SeqCst) - at_cancel
    }
}

impl Posterior for Tripwire {
    fn names(&self) -> Vec<String> {
        (0..self.d).map(|i| format!("x{i}")).collect()
    }
    fn log_prior(&self, t: &[f64]) -> f64 {
        -0.5 * t.iter().map(|x| x * x).sum::<f64>()
    }
    fn log_likelihood(&self, t: &[f64]) -> f64 {
        if self.evaluations.fetch_add(1, Ordering::SeqCst) + 1 == self.at {
            self.control.cancel();
            self.counted_at_cancel.store(self.evaluations.load(Ordering::SeqCst), Ordering::SeqCst);
        }
        -0.5 * t.iter().map(|x| ((x - 1.0) / 0.5).powi(2)).sum::<f64>()
    }
    fn sample_prior(&self, rng: &mut dyn RngCore) -> Vec<f64> {
        (0..self.d).map(|_| StandardNormal.sample(rng)).collect()
    }
}

/// Counts what it is told (the sum of `advance`).
#[derive(Default)]
struct Sum {
    total: AtomicU64,
    done: AtomicU64,
}

impl Progress for Sum {
    fn start(&self, _unit: &'static str, total: u64) {
        self.total.store(total, Ordering::SeqCst);
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::SeqCst);
    }
    fn finish(&self) {}
}

fn config() -> TmcmcConfig {
    TmcmcConfig { n_samples: 200, mh_steps: 3, seed: 11, ..TmcmcConfig::default() }
}

fn dram_settings() -> DramSettings {
    DramSettings {
        draws_per_chain: 1000,
        burn_in: 200,
        nonadaptive_draws: 200,
        adaptation_start: 200,
        covariance_skip: 100,
        seed: 5,
        chains: 2,
        ..DramSettings::default()
    }
}

#[test]
fn tmcmc_with_a_control_that_is_not_cancelled_is_bit_identical() {
    let plain = tmcmc(&Tripwire::new(2, 0), &config()).unwrap();
    let sum = Arc::new(Sum::default());
    let controlled = tmcmc_controlled(&Tripwire::new(2, 0), &config(), &Control::with_progress(sum)).unwrap();
    assert_eq!(plain, controlled);
    assert_eq!(plain.log_evidence.to_bits(), controlled.log_evidence.to_bits());
}

#[test]
fn tmcmc_stops_within_one_sample_per_thread_of_a_cancel() {
    let threads = rayon::current_num_threads() as u64;
    let c = config();
    // one sample's polled unit: its likelihood (stage 0) or its moves (at most
    // mh_steps evaluations: no max_mh_steps here)
    let per_sample = c.mh_steps as u64;
    for at in [50, 200, 650, 1234] {
        let post = Tripwire::new(2, at);
        let r = tmcmc_controlled(&post, &c, &post.control.clone());
        assert_eq!(r.unwrap_err(), BayesError::Cancelled(Cancelled), "cancel at evaluation {at}");
        let after = post.evaluations_after_the_cancel();
        // the thread that cancelled finishes its sample, every other thread its current one
        assert!(after <= threads * per_sample, "{after} evaluations after the cancel at {at} ({threads} threads)");
    }
    // a run never cancelled needs more evaluations than the largest trip
    // point, so each trip above fired inside the run
    let full = Tripwire::new(2, 0);
    tmcmc(&full, &c).unwrap();
    assert!(full.evaluations.load(Ordering::SeqCst) > 1234);
}

#[test]
fn dram_with_a_control_is_bit_identical_and_counts_every_state() {
    let s = dram_settings();
    let starts = vec![vec![0.1, -0.2], vec![-0.3, 0.4]];
    let plain = run_chains(&Tripwire::new(2, 0), &s, &[0.5, 0.5], &starts, 5, None).unwrap();
    let sum = Arc::new(Sum::default());
    let control = Control::with_progress(sum.clone());
    let controlled = run_chains(&Tripwire::new(2, 0), &s, &[0.5, 0.5], &starts, 5, Some(&control)).unwrap();
    for (a, b) in plain.iter().zip(&controlled) {
        assert_eq!(a.draws, b.draws);
        assert_eq!(a.log_posterior, b.log_posterior);
    }
    // 1000 states per chain: three blocks of 256 and the remainder 232
    assert_eq!(sum.done.load(Ordering::SeqCst), 2 * 1000);
}

#[test]
fn dram_stops_at_the_step_after_a_cancel() {
    let s = dram_settings();
    // each step evaluates the posterior once per delayed-rejection stage tried
    let stages = s.stages() as u64;
    let post = Tripwire::new(2, 300);
    let out =
        run_chain(&post, &s, &[0.5, 0.5], &[0.0, 0.0], &mut chain_rng(5, 0), Some(&post.control.clone())).unwrap();
    assert!(out.draws.len() < s.draws_per_chain, "the chain ran to its end");
    assert!(post.evaluations.load(Ordering::SeqCst) - 300 <= stages);
}

#[test]
fn searches_and_batches_through_a_control_that_is_not_cancelled_are_bit_identical() {
    let post = Tripwire::new(3, 0);
    let control = Control::with_progress(Arc::new(Sum::default()));
    let seen = Controlled::new(&post, &control);
    let start = [0.3, -0.2, 0.1];
    let scales = [0.5; 3];
    let plain = map_estimate(&post, &start, &scales, 500);
    let through = map_estimate(&seen, &start, &scales, 500);
    assert_eq!(plain, through);
    assert_eq!(multi_start_optimum(&post, &scales, 100, 3, 7, 0), multi_start_optimum(&seen, &scales, 100, 3, 7, 0));
    // a spread population (no two coordinates in a fixed ratio: its covariance is regular)
    let population: Vec<Vec<f64>> = (0..50)
        .map(|i| {
            let x = i as f64;
            vec![0.8 + 0.3 * (0.7 * x).sin(), 0.8 + 0.3 * (1.3 * x).cos(), 0.8 + 0.3 * (2.9 * x).sin()]
        })
        .collect();
    let a = importance_log_evidence(&post, &plain.theta, None, &population, 400, 3).unwrap();
    let b = importance_log_evidence(&seen, &plain.theta, None, &population, 400, 3).unwrap();
    assert_eq!(a.log_evidence.to_bits(), b.log_evidence.to_bits());
    assert_eq!(a, b);
}

/// The evidence estimator's settings of these tests and the TMCMC config
/// `estimate` derives from them (`EvidenceSettings::tmcmc_config`, private:
/// rebuilt here and checked against the estimator's own TMCMC result).
fn evidence_settings() -> (EvidenceSettings, TmcmcConfig) {
    let s = EvidenceSettings { samples: 200, mh_steps: 3, map_iters: 400 };
    let d = 2.0f64;
    let c = TmcmcConfig {
        n_samples: s.samples,
        mh_steps: s.mh_steps,
        beta: 2.38 / d.sqrt(),
        target_acceptance: 0.234,
        adapt_beta: true,
        max_mh_steps: Some(5 * s.mh_steps),
        seed: 21,
        ..TmcmcConfig::default()
    };
    (s, c)
}

#[test]
fn evidence_stops_within_one_evaluation_per_thread_of_a_cancel_after_tmcmc() {
    // two threads, as on CI: the bound below is per thread
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    pool.install(|| {
        let threads = rayon::current_num_threads() as u64;
        let (s, c) = evidence_settings();
        // where the phases lie: TMCMC's evaluations come first (same config,
        // same draws), the last 4 x samples are the importance batch
        // (IMPORTANCE_DRAWS_PER_SAMPLE), the MAP searches and the Laplace
        // Hessian in between
        let only_tmcmc = Tripwire::new(2, 0);
        let t = tmcmc(&only_tmcmc, &c).unwrap();
        let n_tmcmc = only_tmcmc.evaluations.load(Ordering::SeqCst);
        let full = Tripwire::new(2, 0);
        let e = estimate(&full, &s, 21, true, &[], &Control::default()).unwrap();
        assert_eq!(
            e.tmcmc.as_ref().expect("estimate runs TMCMC").log_evidence.to_bits(),
            t.log_evidence.to_bits(),
            "the rebuilt TMCMC config is estimate's"
        );
        let n = full.evaluations.load(Ordering::SeqCst);
        let batch = 4 * s.samples as u64;
        assert!(n > n_tmcmc + batch + 100, "{n} evaluations, {n_tmcmc} of them TMCMC's");
        // one never cancelled, with a control of its own: the same bits
        let again = Tripwire::new(2, 0);
        let e2 = estimate(&again, &s, 21, true, &[], &Control::with_progress(Arc::new(Sum::default()))).unwrap();
        assert_eq!(e.log_evidence.to_bits(), e2.log_evidence.to_bits());
        assert_eq!((&e.map, &e.draws), (&e2.map, &e2.draws));
        // the first MAP search, the global MAP search's middle, the
        // importance batch's middle and its last draw
        let in_maps = n_tmcmc + (n - batch - n_tmcmc) / 2;
        for at in [n_tmcmc + 5, in_maps, n - batch / 2, n] {
            let post = Tripwire::new(2, at);
            let r = estimate(&post, &s, 21, true, &[], &post.control.clone());
            assert_eq!(r.unwrap_err(), BayesError::Cancelled(Cancelled), "cancel at evaluation {at} of {n}");
            // each thread may have passed the flag just before the cancel
            let after = post.evaluations_after_the_cancel();
            assert!(after <= threads, "{after} evaluations after the cancel at {at} of {n} ({threads} threads)");
        }
    });
}
