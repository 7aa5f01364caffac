use nanobeam::diagnose::{diagnose, synthetic, DiagnoseSettings, ModelClass};
use std::time::Instant;
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seed: u64 = args.get(1).map(|s| s.parse().unwrap()).unwrap_or(1);
    let eff = args.get(2).and_then(|s| ModelClass::from_name(s));
    let samples: usize = args.get(3).map(|s| s.parse().unwrap()).unwrap_or(400);
    let t = Instant::now();
    let case = if args.get(2).map(|s| s == "case3").unwrap_or(false) {
        synthetic::SyntheticCase { file: synthetic::paper_case3(), truth: None, truth_beam: synthetic::nominal_beam(), base_fit_max_z: 0.0 }
    } else { synthetic::generate(seed, eff) };
    println!("gen {:?} z={:.2} modes={} t={:?} truth={:?}", case.truth.map(|c| c.name()), case.base_fit_max_z, case.file.modes.len(), t.elapsed(), case.truth_beam);
    let t = Instant::now();
    let s = DiagnoseSettings { samples, ..DiagnoseSettings::quick() };
    let d = diagnose(&case.data(), &s).unwrap();
    println!("diag t={:?} cause={} misfit={}", t.elapsed(), d.cause, d.misfit_detected);
    println!("base lnZ={:.2} lap={:?}; baseline lbf {:.2}", d.base.log_evidence, d.base.log_evidence_laplace, d.baseline.log_bayes_factor);
    for c in &d.candidates { println!("  {:30} lnZ={:8.2} lap={:?} lbf={:6.2} p={:.3}", c.extension, c.log_evidence, c.log_evidence_laplace.map(|v| (v*100.0).round()/100.0), c.log_bayes_factor, c.probability); }
    for m in &d.misfit { print!("({} {} z={:.1} p={:.1e}) ", m.mode, m.quantity, m.z, m.ppp); }
    println!();
    println!("gain rms {:.2} -> {:.2}", d.gain.rms_z_before, d.gain.rms_z_after);
}
