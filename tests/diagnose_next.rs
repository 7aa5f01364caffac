//! The measurement `next_measurement` suggests must separate the two models
//! it was chosen for (issue 13, item 4), on a case constructed for it.
//!
//! Seed 100 of the hidden suite hides an extra relaxation; its data cannot
//! separate it from a support spring (ln B gap 1.8 < 3, so
//! `support-rotational-stiffness` is listed as an alternative, and since the
//! search extends every single cause within the margin, so is the spring with
//! an attached mass, 1.6 nats behind: the closest rival, which the suggestion
//! must separate). (Seed 110, an
//! axial force against a spring, has no suggestion: both effects fall off as
//! 1/n² and no ω or ζ up to mode 8 separates them by 1 sd, so the answer
//! there is the alternative alone.) The suggested observable is then measured on the truth,
//! with the measurement noise the suggestion assumed (0.3 % on ω, 3 % on ζ,
//! one keyed normal draw), the other quantity of that mode given an sd 1e3
//! times larger so that only the suggested quantity informs; the diagnosis
//! re-run on the extended data must select the truth with the alternative
//! beyond the 3-nat margin. A separation of s predictive sds is worth ≈ s²/2
//! nats, so the test needs s ≳ 2.5 (asserted first).

mod synthetic;

use rand_distr::{Distribution, StandardNormal};

use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::beam::modal;
use nanobeam::calibration::{MeasuredData, ModeObservation};
use nanobeam::diagnose::{diagnose, DiagnoseSettings, Model, ModelClass};
use synthetic::{generate_hidden, Hidden, OMEGA_REL_SD, ZETA_REL_SD};

#[test]
fn the_suggested_measurement_separates_the_pair() {
    let settings = DiagnoseSettings::quick();
    let case = generate_hidden(100, &Hidden::causes(&[ModelClass::ExtraRelaxation]));
    let d = diagnose(&case.data(), &settings).unwrap();
    let truth = ModelClass::ExtraRelaxation.name();
    println!("before: cause {} alternatives {:?} next {:?}", d.cause, d.alternatives, d.next_measurement);
    assert_eq!(d.cause, truth);
    let next = d.next_measurement.expect("an alternative within the margin has a next measurement");
    // the closest rival: an alternative that is not the truth plus more
    let rival = Model::from_name(&next.between[1]).expect("a model name");
    assert!(!rival.causes().contains(&ModelClass::ExtraRelaxation), "{next:?}");
    assert!(d.alternatives.iter().any(|a| a.extension == next.between[1]), "{next:?}");
    assert!(next.separation_sd > 2.5, "{next:?}");

    let mode = modal(&case.truth_beam, next.mode).unwrap().mode(next.mode).copied().expect("oscillatory mode");
    let e: f64 = StandardNormal.sample(&mut stream(100, Purpose::SyntheticCase, [1, 0]));
    let (omega_sd, zeta_sd) = (OMEGA_REL_SD * mode.omega_rad_s, ZETA_REL_SD * mode.zeta);
    let observation = if next.quantity == "omega" {
        ModeObservation {
            mode: next.mode,
            omega_rad_s: mode.omega_rad_s + e * omega_sd,
            omega_sd_rad_s: omega_sd,
            zeta: mode.zeta,
            zeta_sd: 1e3 * zeta_sd,
        }
    } else {
        ModeObservation {
            mode: next.mode,
            omega_rad_s: mode.omega_rad_s,
            omega_sd_rad_s: 1e3 * omega_sd,
            zeta: mode.zeta + e * zeta_sd,
            zeta_sd,
        }
    };
    let mut file = case.file.clone();
    file.modes.push(observation);
    file.modes.sort_by_key(|m| m.mode);
    let after = diagnose(&MeasuredData::from_file(file).unwrap(), &settings).unwrap();
    println!("after: cause {} alternatives {:?}", after.cause, after.alternatives);
    assert_eq!(after.cause, truth);
    assert!(after.alternatives.iter().all(|a| a.extension != next.between[1]), "{:?}", after.alternatives);
}
