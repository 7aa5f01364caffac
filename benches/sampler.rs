//! Per-step overhead of DRAM (2 stages, the paper's §4.2 structure) on a
//! trivial 3-D Gaussian target, so the number is the sampler's own cost
//! (proposal, acceptance, recursive covariance update, Cholesky refresh).
//! ns/step = 1e9 / throughput. Budget: 4 chains × 20 000 draws with a
//! ~5 µs model must fit in 5 s on 2 cores, so this must stay ≪ 1 µs/step.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use nanobeam::bayes::chains::chain_rng;
use nanobeam::bayes::dram::{run_chain, DramSettings};
use nanobeam::bayes::Posterior;
use rand::RngCore;

struct Gaussian3;

impl Posterior for Gaussian3 {
    fn names(&self) -> Vec<String> {
        vec!["a".into(), "b".into(), "c".into()]
    }
    fn dim(&self) -> usize {
        3
    }
    fn log_prior(&self, _t: &[f64]) -> f64 {
        0.0
    }
    fn log_likelihood(&self, t: &[f64]) -> f64 {
        -0.5 * (t[0] * t[0] + t[1] * t[1] / 4.0 + t[2] * t[2] * 9.0)
    }
    fn sample_prior(&self, _rng: &mut dyn RngCore) -> Vec<f64> {
        vec![0.0; 3]
    }
}

fn bench_dram(c: &mut Criterion) {
    let steps = 20_000;
    let mut group = c.benchmark_group("dram_3d_gaussian");
    group.throughput(Throughput::Elements(steps as u64 - 1));
    group.sample_size(20);
    for (label, n0) in [("adaptive_from_4000", 4000), ("non_adaptive", steps)] {
        let settings = DramSettings {
            draws_per_chain: steps,
            burn_in: 0,
            nonadaptive_draws: n0,
            adaptation_start: n0,
            covariance_skip: n0.min(3000),
            ..DramSettings::default()
        };
        group.bench_function(label, |b| {
            b.iter(|| run_chain(&Gaussian3, &settings, &[0.5, 0.5, 0.5], &[0.0; 3], &mut chain_rng(1, 0), None))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_dram);
criterion_main!(benches);
