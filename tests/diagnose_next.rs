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

use rand_distr::{Distribution, StandardNormal};

use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::beam::{frf_points, modal};
use nanobeam::calibration::{MeasuredData, ModeObservation};
use nanobeam::diagnose::next::SHAPE_GRID;
use nanobeam::diagnose::synthetic::{generate_hidden, Hidden, OMEGA_REL_SD, ZETA_REL_SD};
use nanobeam::diagnose::{diagnose, DiagnoseSettings, Model, ModelClass};

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

/// When no ω or ζ separates the pair, the suggested mode-shape scan must
/// (`next::shape_measurement`): seed 110 hides an axial force, which its 4
/// modes cannot tell from a support spring (ln B gap 0.24; both shift mode
/// n's ω² by ∝ 1/n²). The truth's scan at the suggested point — computed from
/// the truth's beam as the suggestion defines it, amplitude at x over the
/// largest on the scan grid — is then measured with half the decisive sd
/// (one keyed normal draw), and the log Bayes factor of the two Gaussian
/// predictives (mean, predictive variance + σ²) must reach the decision
/// threshold for the truth. At half the decisive sd its expectation is ≈ 4×
/// the threshold when the truth sits at its model's prediction, so a draw
/// within ±2 sd still decides; a suggestion whose predictions were not the
/// models' (a wrong normalisation, swapped models) would not.
#[test]
fn the_suggested_mode_shape_separates_a_pair_no_mode_separates() {
    let settings = DiagnoseSettings::quick();
    let case = generate_hidden(110, &Hidden::causes(&[ModelClass::AxialForce]));
    let d = diagnose(&case.data(), &settings).unwrap();
    let truth = ModelClass::AxialForce.name();
    println!("cause {} alternatives {:?} next {:?}", d.cause, d.alternatives, d.next_measurement);
    assert_eq!(d.cause, truth);
    assert!(d.next_measurement.is_none(), "{:?}", d.next_measurement);
    let m = d.shape_measurement.expect("a fitting rival that no mode separates gets a shape suggestion");
    println!("{m:?}");
    assert_eq!(m.between[0], truth);
    let rival = Model::from_name(&m.between[1]).expect("a model name");
    assert!(!rival.causes().contains(&ModelClass::AxialForce), "{m:?}");
    assert!(d.alternatives.iter().any(|a| a.extension == m.between[1] && !a.misfits), "{m:?}");

    let beam = &case.truth_beam;
    let omega = modal(beam, m.mode).unwrap().mode(m.mode).expect("oscillatory mode").omega_rad_s;
    let xs: Vec<f64> = (1..SHAPE_GRID).map(|k| k as f64 * beam.length_nm / SHAPE_GRID as f64).collect();
    let amp: Vec<f64> = frf_points(beam, m.drive_x_nm, &xs, &[omega]).unwrap()[0].iter().map(|z| z.norm()).collect();
    let k = xs.iter().position(|&x| x == m.position_x_nm).expect("the suggested point is on the scan grid");
    let t = amp[k] / amp.iter().copied().fold(0.0, f64::max);
    let sigma = 0.5 * m.decisive_measurement_sd;
    let e: f64 = StandardNormal.sample(&mut stream(110, Purpose::SyntheticCase, [2, 0]));
    let y = t + e * sigma;
    let log_density = |mean: f64, sd: f64| {
        let v = sd * sd + sigma * sigma;
        -0.5 * (y - mean).powi(2) / v - 0.5 * v.ln()
    };
    let [ma, mb] = m.predicted_relative_amplitude;
    let [sa, sb] = m.predictive_sd;
    let ln_b = log_density(ma, sa) - log_density(mb, sb);
    println!("truth {t:.5}, measured {y:.5} (sd {sigma:.5}), ln B {ln_b:.2}");
    assert!(ln_b >= settings.log_bayes_factor_threshold, "ln B {ln_b}");
}
