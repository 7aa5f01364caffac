//! Per-step overhead of DRAM (2 stages, the paper's §4.2 structure) on a
//! trivial 3-D Gaussian target, so the number is the sampler's own cost
//! (proposal, acceptance, recursive covariance update, Cholesky refresh).
//! ns/step = 1e9 / throughput. Issue 15: the per-draw budget of a whole
//! `nanobeam calibrate` is ~1–2 µs, so this must stay a few hundred ns.
//! `beam_posterior` is one log-posterior evaluation of the comparison's
//! calibration (`benches/pymcmcstat/measured.yaml`: N = 1, modes 1–3, θ moving
//! by proposal-sized steps) and `beam_chain` a whole DRAM chain on it (per draw).

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
    // "non_adaptive": the proposal adapts only after the last draw (the
    // settings require adaptation to start inside the chain)
    for (label, n0) in [("adaptive_from_4000", 4000), ("non_adaptive", steps - 1)] {
        let settings = DramSettings {
            draws_per_chain: steps,
            burn_in: 0,
            nonadaptive_draws: n0,
            adaptation_start: n0,
            covariance_skip: n0.min(3000),
            ..DramSettings::default()
        };
        group.bench_function(label, |b| {
            b.iter(|| {
                run_chain(&Gaussian3, &settings, &[0.5, 0.5, 0.5], &[0.0; 3], &mut chain_rng(1, 0), None).unwrap()
            })
        });
    }
    group.finish();
}

fn bench_beam(c: &mut Criterion) {
    use nanobeam::calibration::{BeamPosterior, MeasuredData};
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/benches/pymcmcstat/measured.yaml")).unwrap();
    let data = MeasuredData::from_yaml(&text).unwrap();
    let post = BeamPosterior::new(&data, data.parameters.clone());
    let theta = [1.05, 0.45, 3.0e11];
    let mut k = 0u64;
    c.bench_function("beam_posterior", |b| {
        b.iter(|| {
            k += 1;
            let u = (k % 17) as f64 / 17.0 - 0.5;
            post.log_posterior(&[theta[0] + 0.01 * u, theta[1] - 0.01 * u, theta[2] * (1.0 + 0.02 * u)])
        })
    });
    let steps = 20_000;
    let mut group = c.benchmark_group("beam_chain");
    group.throughput(Throughput::Elements(steps as u64 - 1));
    group.sample_size(10);
    let settings = DramSettings { draws_per_chain: steps, ..DramSettings::default() };
    let c0: Vec<f64> = data.parameters.params.iter().map(|p| p.proposal_sd).collect();
    group.bench_function("paper_settings", |b| {
        b.iter(|| run_chain(&post, &settings, &c0, &theta, &mut chain_rng(1, 0), None).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench_dram, bench_beam);
criterion_main!(benches);
