//! The cheap per-replicate inference of the audit (MAP + Laplace carrying the
//! DRAM posterior's shape from replicate 0) against full DRAM on fresh noise
//! replicates: posterior mean and 95 % interval endpoints agree within the
//! stated error.
//!
//! Stated error, per parameter, in units of the DRAM posterior sd:
//!   |mean_transport − mean_DRAM| ≤ 0.15 + 4·√2·(1/√ESS_bulk)
//!   |CI_transport − CI_DRAM|     ≤ 0.25 + 4·√2·(2.67/√ESS_tail)
//! The constants 0.15 / 0.25 bound the approximation itself (the shape of the
//! posterior in Laplace-standardised units changing with the noise draw); the
//! second terms are 4 standard errors of the difference of two Monte Carlo
//! estimates (replicate 0's DRAM, which fixes the shape, and replicate r's
//! DRAM), each with se 1/√ESS (mean) or 2.67/√ESS_tail (2.5 % quantile:
//! √(p(1−p))/φ(z_p) = 0.156/0.0584) in sd units.

use std::path::Path;

use nanobeam::calibration::{calibrate_posterior, BeamPosterior, CalibrateOptions};
use nanobeam::reproduce::cases::{run_case, truth_beam};
use nanobeam::reproduce::reconstruction::reconstruct;
use nanobeam::reproduce::reference::Published;
use nanobeam::reproduce::replicates::{laplace_fit, synthetic_observations, Noise, Shape};
use nanobeam::reproduce::specs::Specs;

#[test]
fn laplace_transport_agrees_with_full_dram_on_fresh_replicates() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let published = Published::load(&root.join("paper/published.yaml")).unwrap();
    let specs = Specs::load(&root.join("paper/specs")).unwrap();
    let rec = reconstruct(&specs.reconstruction, &published);
    let mut worst: (f64, String) = (0.0, String::new());
    for id in ["1B", "2A"] {
        let spec = specs.cases.iter().find(|c| c.id == id).unwrap();
        let case = run_case(spec, &rec, &published, true).expect("case calibrates");
        let scales: Vec<f64> = case.result.summary.parameters.iter().map(|p| p.sd).collect();
        let lap0 = laplace_fit(&case.posterior, &case.result.map_theta, &scales).expect("replicate 0 fits");
        let shape = Shape::measure(&case.result.summary.parameters, &lap0);
        let cs = published.covariance_set(&spec.covariance_set).unwrap();
        for r in [1u64, 2] {
            let obs = synthetic_observations(truth_beam(spec, &rec), cs, spec.seed, Noise::Replicate(r)).unwrap();
            let post = BeamPosterior::from_parts(case.posterior.base_beam(), &obs, case.posterior.parameters().clone());
            let lap = laplace_fit(&post, &case.result.map_theta, &scales).expect("replicate fits");
            let cheap = shape.apply(&lap);
            let c0: Vec<f64> = post.parameters().params.iter().map(|p| p.proposal_sd).collect();
            let dram = calibrate_posterior(&post, &c0, &spec.quick_sampler, &CalibrateOptions::default())
                .expect("replicate calibrates");
            for (k, p) in dram.summary.parameters.iter().enumerate() {
                let ess0 = case.result.summary.parameters[k].ess_bulk.min(p.ess_bulk).max(1.0);
                let tail0 = case.result.summary.parameters[k].ess_tail.min(p.ess_tail).max(1.0);
                let dm = (cheap.mean[k] - p.mean).abs() / p.sd;
                let tol_m = 0.15 + 4.0 * 2f64.sqrt() / ess0.sqrt();
                assert!(dm <= tol_m, "{id} r{r} {}: mean off by {dm:.3} sd > {tol_m:.3}", p.name);
                for e in 0..2 {
                    let dc = (cheap.ci95[k][e] - p.ci95[e]).abs() / p.sd;
                    let tol_c = 0.25 + 4.0 * 2f64.sqrt() * 2.67 / tail0.sqrt();
                    assert!(dc <= tol_c, "{id} r{r} {}: CI end {e} off by {dc:.3} sd > {tol_c:.3}", p.name);
                    if dc > worst.0 {
                        worst = (dc, format!("{id} r{r} {} CI end {e}", p.name));
                    }
                }
                if dm > worst.0 {
                    worst = (dm, format!("{id} r{r} {} mean", p.name));
                }
            }
        }
    }
    eprintln!("largest transport error: {:.3} sd ({})", worst.0, worst.1);
}
