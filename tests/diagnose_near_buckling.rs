//! Issue 44, defect 9: `diagnose` on a beam compressed to 0.99 of its
//! (Euler–Bernoulli) buckling load. It used to run for minutes (the coupled
//! solver's fallback, fixed in `beam::coupled`) and then to exit 1 because
//! one candidate, `shear-deformation`, has no prior draw that is not buckled.
//!
//! Why that model has none, from closed forms and not from the code: shear
//! lowers the buckling load of a pinned–pinned beam to
//! N_T = N_E / (1 + N_E/(κGA)) (Engesser), and N_E/(κGA) = π²EI/(L²κGA) =
//! (π²/16)(d/L)²·2(1 + ν)/κ ≥ (π²/16)(1/64)·2.4/1 = 0.0231 over the class's
//! prior κ ∈ [0.3, 1] at ν = 0.2 (`DEFAULT_POISSON_RATIO`) and L/d = 8: every
//! draw buckles at N ≤ 0.977 N_E < 0.99 N_E. Such a model has evidence zero;
//! the diagnosis must list it as not evaluable and go on, not end.
//!
//! Its pairs with the shear find no finite likelihood in their screening
//! search either (unless a spring or a tension lifts the load): their bound
//! is −∞, which the report must print rather than fail on.
//!
//! Data: written by hand here (the hardening suite's 8 nm beam and three
//! modes near those of its exact model), 50 TMCMC samples.

use nanobeam::calibration::MeasuredData;
use nanobeam::diagnose::{diagnose_run, report, DiagnoseSettings};

const NEAR_BUCKLING: &str =
    "beam: { length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, \
support: simply-supported, elements: 20, axial_force_n: -7.4942e-9 }
modes:
  - { mode: 1, omega_rad_s: 9.3e11, omega_sd_rad_s: 2.8e9, zeta: 0.0614, zeta_sd: 0.0018 }
  - { mode: 2, omega_rad_s: 3.8e12, omega_sd_rad_s: 1.1e10, zeta: 0.0168, zeta_sd: 0.0005 }
  - { mode: 3, omega_rad_s: 8.4e12, omega_sd_rad_s: 2.5e10, zeta: 0.0080, zeta_sd: 0.0003 }
";

#[test]
fn a_model_that_buckles_under_every_prior_draw_is_listed_not_fatal() {
    let data = MeasuredData::from_yaml(NEAR_BUCKLING).expect("a valid file: 0.99 of the buckling load");
    let settings = DiagnoseSettings { samples: 50, ..DiagnoseSettings::quick() };
    let run = diagnose_run(&data, &settings).expect("a diagnosis, not an error");
    let d = &run.diagnosis;
    assert!(d.not_evaluable.iter().any(|m| m == "shear-deformation"), "{:?}", d.not_evaluable);
    assert!(d.not_evaluable.iter().all(|m| m.contains("shear-deformation")), "{:?}", d.not_evaluable);
    assert!(d.candidates.iter().all(|c| c.extension != "shear-deformation"));
    let hopeless = d.screened.iter().filter(|s| s.log_evidence_bound == f64::NEG_INFINITY).count();
    assert!(hopeless >= 1, "a shear pair with no finite draw: {:?}", d.screened);
    let md = report::markdown(&run, &data, &settings).expect("the report renders a −∞ bound");
    assert!(md.contains("shear-deformation") && md.contains("−∞"), "{md}");
}
