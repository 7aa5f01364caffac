//! `identify` on a 4 000-point complex sweep of the paper's beam holding 5
//! modes, with 0.1 % complex noise (target: ≤ 2 s per call).

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::beam::{frf, modal};
use nanobeam::identify::{identify, IdentifySettings, Measurement};
use nanobeam::reproduce::reconstruction::table_4_beam_from_yaml;
use num_complex::Complex64;
use rand_distr::{Distribution, StandardNormal};

fn record() -> Measurement {
    // the paper's beam: Table 4 truth as reconstructed in paper/reconstructed.yaml
    let beam = table_4_beam_from_yaml(include_str!("../paper/reconstructed.yaml")).unwrap();
    let t = modal(&beam, 6).unwrap();
    let (lo, hi) = (0.2 * t.modes[0].omega_rad_s, 0.5 * (t.modes[4].omega_rad_s + t.modes[5].omega_rad_s));
    let w: Vec<f64> = (0..4000).map(|i| lo + (hi - lo) * i as f64 / 3999.0).collect();
    let h = frf(&beam, 3.6, 6.8, &w).unwrap();
    let sd = 1e-3 * h.iter().map(|z| z.norm()).fold(0.0, f64::max);
    let mut rng = stream(1, Purpose::MeasurementNoise, [1400, 0]);
    let h = h
        .iter()
        .map(|z| {
            let (a, b): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
            z + Complex64::new(a * sd, b * sd)
        })
        .collect();
    Measurement::Complex { omega_rad_s: w, h_m_per_n: h }
}

fn bench(c: &mut Criterion) {
    let data = record();
    let mut g = c.benchmark_group("identify");
    g.sample_size(10);
    g.bench_function("sweep_4000_points_5_modes", |b| {
        b.iter(|| identify(black_box(&data), &IdentifySettings::default()).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
