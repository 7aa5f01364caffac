//! Open-world hidden-effect suite (issue 13): synthetic data from a truth with
//! no effect, one of the six catalogue causes, two at once, or an effect no
//! class models, diagnosed without the truth at quick settings. Run with
//! `-- --nocapture` for the per-case lines and the confusion matrix.
//!
//! 73 cases: 5 clean, 4 per single cause (24), 40 pairs (5 of each of the
//! 8 kinds in `PAIRS`), 4 foreign
//! (`synthetic::Foreign`, alternating: `ModeCoupling`, one mode in an
//! avoided crossing with a lossy resonance outside the beam, and
//! `LocalDefect`, EI lowered over 1–3 elements). Every effect alone moves some
//! observable ≥ `synthetic::MIN_SHIFT_SIGMA` σ against the best base fit
//! (the generator grows it until it does); a foreign effect also against the
//! best fit of every catalogue model of one or two causes; each cause of a
//! pair also against the best fit of the other cause's model (since
//! 2026-11-27: the "base" of an effect in a pair is the model without it).
//!
//! Targets (the issue's): single causes ≥ 95 % right (23 of 24), both causes
//! of a pair named in ≥ 80 % of pairs (32 of 40), foreign effects
//! `unexplained` in 100 %, no false alarm on clean data. These are counts on
//! fixed seeds, not rates estimated with an error: the test fails on any
//! seed that falls below them.
//!
//! The pairs also test the advice (issue 13, item 4, at scale): every pair
//! whose diagnosis suggests a next measurement gets the suggested mode (ω
//! and ζ, the generator's noise) or mode-shape scan measured on the truth
//! and is diagnosed again, right answers too, without knowledge of the
//! truth; the test asserts that no right answer is unsettled and reports
//! both-named after the advice.
//! Every case whose diagnosis suggests a mode-shape scan instead (no ω or ζ
//! separates its alternatives) has the scan read on the truth and fed back
//! as `mode_scans` data ([`measure_scan`]), and is diagnosed again (a pair
//! counts it as its verdict after the advice); when one of the two models is
//! the truth's, the rerun must put it ahead by the decision threshold
//! ([`scan_gap`]). The expectation from the two predictives at the one
//! suggested point ([`shape_check`]) is printed beside it.
//! Each pair's noise-free data are diagnosed too ([`NoiseFree::Diagnose`]),
//! which tells a miss that a luckier noise draw would have avoided from one
//! the effects' sizes do not support.
//!
//! CI runs a fixed part of each world: the first seed of each single cause
//! (100–105), the first two clean seeds (200, 201), the first pair (300) and
//! the first foreign effect (400), each of which must be right. The whole
//! closed world alone (29 diagnoses) took 749 s of the 25-min CI run on 2
//! cores (2026-11-24), half CI's ~15-min budget; the whole suite runs with
//! `cargo test --test diagnose_hidden -- --ignored --nocapture`.

mod synthetic;

use std::collections::BTreeMap;
use std::time::Instant;

use rayon::prelude::*;

use rand_distr::{Distribution, StandardNormal};

use nanobeam::bayes::rng::{stream, Purpose};
use nanobeam::beam::modal;
use nanobeam::calibration::{MeasuredData, ModeObservation, ModeScan};
use nanobeam::diagnose::next::ShapeMeasurement;
use nanobeam::diagnose::{decided_causes, diagnose, DiagnoseSettings, Diagnosis, Model, ModelClass};

use synthetic::{generate_hidden, Foreign, Hidden, SyntheticCase, OMEGA_REL_SD, ZETA_REL_SD};
use ModelClass::*;

const PAIRS: [[ModelClass; 2]; 8] = [
    [ExtraRelaxation, SupportRotationalStiffness],
    [ViscousDamping, AttachedMass],
    [AxialForce, AttachedMass],
    [ExtraRelaxation, AxialForce],
    [ViscousDamping, AxialForce],
    [SupportRotationalStiffness, AttachedMass],
    [ShearDeformation, ViscousDamping],
    [ExtraRelaxation, AttachedMass],
];

/// The closed-world part: 5 clean cases and 4 per single cause.
fn closed_cases() -> Vec<(u64, Hidden)> {
    let mut cases: Vec<(u64, Hidden)> = (0..5u64).map(|i| (200 + i, Hidden::clean())).collect();
    cases.extend((0..24u64).map(|i| (100 + i, Hidden::causes(&[ModelClass::CAUSES[(i % 6) as usize]]))));
    cases
}

/// How many pairs the open world draws: 5 of each kind. Eight (one of
/// each) said 6/8 on 2026-11-24; the next 32 seeds said 16/32, so eight
/// pairs estimate the rate too coarsely to hold a target to.
const N_PAIRS: u64 = 40;

/// The open-world part: 40 pairs (seed 300 + i draws `PAIRS[i % 8]`) and 4 foreign effects.
fn open_cases() -> Vec<(u64, Hidden)> {
    let mut cases: Vec<(u64, Hidden)> =
        (0..N_PAIRS).map(|i| (300 + i, Hidden::causes(&PAIRS[(i % 8) as usize]))).collect();
    let n = Foreign::ALL.len() as u64;
    cases.extend((0..4).map(|i| (400 + i, Hidden::foreign(Foreign::ALL[(i % n) as usize]))));
    cases
}

/// The column of the confusion matrix: the verdict, with the causes when several.
fn verdict(d: &Diagnosis) -> String {
    if d.cause == "multiple" {
        d.causes.join("+")
    } else {
        d.cause.clone()
    }
}

/// The seeds CI diagnoses: the first of each single cause and the first two clean ones.
fn ci_cases() -> Vec<(u64, Hidden)> {
    closed_cases().into_iter().filter(|(seed, _)| (100..106).contains(seed) || (200..202).contains(seed)).collect()
}

/// Every single cause named on its first seed, no false alarm on two clean
/// sets. Seed 104 hides an axial force that its 6 modes cannot tell from a
/// support spring (both shift mode n's ω² by ∝ 1/n²; no unmeasured ω or ζ
/// separates them by 1 sd), so it gets a mode-shape suggestion instead: the
/// scan of mode 4 is sinusoidal under the tension and bent near the supports
/// under the spring (0.618 against 0.582 of the largest amplitude at 0.7 L,
/// decisive to ±0.015, measured 2026-11-26), and the truth's scan, fed back
/// as data, must decide for the tension ([`measure_scan`], [`scan_gap`];
/// 2026-11-27: the spring went from 0.36 to 29.7 nats behind).
///
/// Since seed 104's 6 modes cannot separate the two, its first verdict may
/// name either (a 0.36-nat call for the tension before the per-end spring
/// class; the spring's second end tips it to the spring after, tests/
/// diagnose_hidden.md). Either is honest only as "cannot separate": nothing
/// decided, the truth an alternative, and the truth's scan fed back deciding
/// for it ([`Tally::singles_undecided`]); a confounded seed other than 104 is
/// a regression.
#[test]
fn first_seed_of_every_single_cause_is_named_and_clean_data_raise_no_alarm() {
    let t = tally(ci_cases(), Follow::No, NoiseFree::Skip);
    screening_is_covered(&t);
    assert_eq!(t.scan_decides_for_truth, t.scan_checkable, "the truth's scan fed back does not decide for it");
    if !filtered() {
        // the suite's singles draw the six causes it was built with (`closed_cases`), not section-mismatch
        assert_eq!(t.singles, 6);
        assert!(t.shape_checkable >= 1, "seed 104's mode-shape suggestion between the tension and the spring");
        assert!(t.scan_checkable >= 1, "seed 104's scan fed back");
    }
    assert_eq!(
        t.singles_right + t.singles_undecided.len(),
        t.singles,
        "singles named {} + honestly undecided {:?} of {}",
        t.singles_right,
        t.singles_undecided,
        t.singles
    );
    assert!(
        t.singles_undecided.iter().all(|&s| s == 104),
        "undecided beyond the confounded seed 104: {:?}",
        t.singles_undecided
    );
    assert_eq!(t.false_alarms, 0);
    assert_eq!(t.decided_wrong, 0, "a decided cause that is not a true cause");
    if let Some(d) = t.diagnoses.get(&100) {
        the_suggested_measurement_separates_the_rival(100, d);
    }
}

/// The measurement `next_measurement` suggests must separate the two models
/// it was chosen for, checked on seed 100's diagnosis (its first one, made by
/// the test above, not repeated).
///
/// Seed 100 hides an extra relaxation; its data cannot separate it from a
/// support spring (`support-rotational-stiffness` within the alternative
/// margin), and since the search extends every single cause within the
/// margin, the spring with an attached mass is an alternative too: the
/// closest rival, which the suggestion must separate. The suggested
/// observable is measured on the truth with the measurement noise the
/// suggestion assumed (`OMEGA_REL_SD`, `ZETA_REL_SD`; one keyed normal draw),
/// the other quantity of that mode given an sd 1e3 times larger so that only
/// the suggested quantity informs; the diagnosis re-run on the extended data
/// must select the truth with the rival beyond the margin. A separation of s
/// predictive sds is worth ≈ s²/2 nats, so the check needs s ≳ 2.5 (asserted
/// first) to clear the 3-nat margin.
fn the_suggested_measurement_separates_the_rival(seed: u64, d: &Diagnosis) {
    let settings = DiagnoseSettings::quick();
    let case = generate_hidden(seed, &Hidden::causes(&[ExtraRelaxation]));
    let truth = ExtraRelaxation.name();
    println!("seed {seed} before: cause {} alternatives {:?} next {:?}", d.cause, d.alternatives, d.next_measurement);
    assert_eq!(d.cause, truth);
    let next = d.next_measurement.as_ref().expect("an alternative within the margin has a next measurement");
    let rival = Model::from_name(&next.between[1]).expect("a model name");
    assert!(!rival.causes().contains(&ExtraRelaxation), "{next:?}");
    assert!(d.alternatives.iter().any(|a| a.extension == next.between[1]), "{next:?}");
    // With `loss-factor` in the catalogue the nearest rival is spring + loss
    // factor, which the best single observable (ω₈) separates by 2.3 sd
    // (2026-12-07): too little to clear the margin alone (≈ 2.7 nats < 3).
    // Then the measurement must move the rival away without changing the
    // selection; at ≥ 2.5 sd it must clear the margin.
    let separates = next.separation_sd > 2.5;
    let gap_before = d.alternatives.iter().find(|a| a.extension == next.between[1]).map(|a| a.log_bayes_factor_gap);

    let mode = modal(&case.truth_beam, next.mode).unwrap().mode(next.mode).copied().expect("oscillatory mode");
    let e: f64 = StandardNormal.sample(&mut stream(seed, Purpose::SyntheticCase, [1, 0]));
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
    println!("seed {seed} after: cause {} alternatives {:?}", after.cause, after.alternatives);
    assert_eq!(after.cause, truth);
    let gap_after = after.alternatives.iter().find(|a| a.extension == next.between[1]).map(|a| a.log_bayes_factor_gap);
    if separates {
        assert!(gap_after.is_none(), "{:?}", after.alternatives);
    } else {
        assert!(gap_after.is_none() || gap_after > gap_before, "rival gap {gap_before:?} -> {gap_after:?}");
    }
}

/// The first pair has both causes named; the first foreign effect is `unexplained`.
#[test]
fn first_pair_is_named_and_first_foreign_effect_is_unexplained() {
    let t = tally(
        open_cases().into_iter().filter(|(seed, _)| [300, 400].contains(seed)).collect(),
        Follow::No,
        NoiseFree::Skip,
    );
    screening_is_covered(&t);
    assert_eq!(t.scan_decides_for_truth, t.scan_checkable, "the truth's scan fed back does not decide for it");
    if !filtered() {
        assert_eq!((t.pairs, t.foreign), (1, 1));
    }
    // With `loss-factor` in the catalogue (issue 65) seed 300's relaxation +
    // spring reads as spring + loss factor, nothing decided, the true pair an
    // alternative within the margin (2026-12-07, tests/diagnose_hidden.md): a
    // flat damping and a second relaxation fit its five modes alike. That is
    // a "cannot tell", not a wrong name; what must hold is that the truth is
    // then listed and nothing is decided.
    if t.pairs_right < t.pairs {
        let d = t.diagnoses.get(&300).expect("seed 300 diagnosed");
        let truth = "extra-relaxation+support-rotational-stiffness";
        assert!(d.decided_causes.is_empty(), "seed 300 not named, yet {:?} decided", d.decided_causes);
        assert!(
            d.alternatives.iter().any(|a| a.extension == truth),
            "seed 300: the true pair neither named nor an alternative: {:?}",
            d.alternatives
        );
    }
    assert_eq!(t.foreign_unexplained, t.foreign, "a foreign effect must be unexplained");
    assert_eq!(t.decided_wrong, 0, "a decided cause that is not a true cause");
}

/// The screening's two margins (`diagnose::screen`), where they can be
/// measured (the models whose full evidence was computed after all): the
/// likelihood at their MAP, found by the evidence's own searches, above the
/// screening search's best stays below `OPTIMISER_MARGIN_NATS`, and their
/// full ln Z above the screening search's Laplace evidence below
/// `LAPLACE_MARGIN_NATS`. Either in full on a screened model could hide one
/// that changes a decision.
fn screening_is_covered(t: &Tally) {
    use nanobeam::diagnose::screen::{LAPLACE_MARGIN_NATS, OPTIMISER_MARGIN_NATS};
    println!(
        "screened models {}; largest screening shortfall {:.2} nats, largest ln Z over the screening Laplace {:.2} nats",
        t.screened, t.screen_shortfall_max, t.screen_laplace_excess_max
    );
    assert!(
        t.screen_shortfall_max < OPTIMISER_MARGIN_NATS,
        "a screening search fell {:.2} nats short of a computed model's MAP",
        t.screen_shortfall_max
    );
    assert!(
        t.screen_laplace_excess_max < LAPLACE_MARGIN_NATS,
        "a computed model's ln Z exceeds its screening Laplace evidence by {:.2} nats",
        t.screen_laplace_excess_max
    );
}

/// Single causes ≥ 95 % right, no false alarm on clean data (the whole closed world).
#[test]
#[ignore = "the whole closed world (29 diagnoses) takes 750-1200 s on 2 cores, more than the suite's budget; CI \
            runs the first seed of each cause and two clean ones. Last measured 2026-11-27 at 6801c95: singles 23/24 \
            (114 named axial-force, named right after its suggested scan), clean 5/5; history in \
            tests/diagnose_hidden.md"]
fn single_hidden_causes_are_named_and_clean_data_raise_no_alarm() {
    let t = tally(closed_cases(), Follow::No, NoiseFree::Skip);
    assert_eq!(t.scan_decides_for_truth, t.scan_checkable, "the truth's scan fed back does not decide for it");
    assert!(t.singles_right * 100 >= 95 * t.singles, "singles {}/{}", t.singles_right, t.singles);
    assert_eq!(t.false_alarms, 0);
    assert_eq!(t.decided_wrong, 0, "a decided cause that is not a true cause");
}

/// Both causes of a pair named in ≥ 80 % of pairs; foreign effects `unexplained` in 100 %.
#[test]
#[ignore = "pair target not met: both causes named on the first verdict in 29/40 (target 32/40), 37/40 after \
            following the advice, foreign 4/4 (2026-11-27 at 62c4069, 2137 s on 2 cores); 6 of the 11 misses a \
            support spring and a tension taken for each other, the truth the listed alternative; history and the \
            misses case by case in tests/diagnose_hidden.md"]
fn pairs_are_named_and_foreign_effects_are_unexplained() {
    let t = tally(open_cases(), Follow::SuggestedMode, NoiseFree::Diagnose);
    assert_eq!(t.scan_decides_for_truth, t.scan_checkable, "the truth's scan fed back does not decide for it");
    assert_eq!(t.pairs_unsettled, 0, "measuring the suggested mode unsettled a right answer");
    assert!(t.pairs_right_after >= t.pairs_right);
    assert_eq!(t.pairs_confidently_wrong, 0, "a pair named wrongly without the truth as an alternative");
    assert_eq!(t.decided_wrong, 0, "a decided cause that is not a true cause");
    assert!(t.pairs_right * 100 >= 80 * t.pairs, "pairs {}/{}", t.pairs_right, t.pairs);
    assert_eq!(t.foreign_unexplained, t.foreign, "foreign effects must be unexplained");
}

#[derive(Default)]
struct Tally {
    /// The largest shortfall of a screening search (`diagnose::screen`): the
    /// likelihood at a computed model's MAP above the search's best, over
    /// every model of every diagnosis that has both.
    screen_shortfall_max: f64,
    /// The largest excess of a computed model's ln Z over the screening
    /// search's Laplace evidence, over every model that has both.
    screen_laplace_excess_max: f64,
    /// Models screened out, over every diagnosis.
    screened: usize,
    singles: usize,
    singles_right: usize,
    /// Seeds of singles named wrongly but honestly: nothing decided, the
    /// truth among the alternatives, and the truth's scan (the shape
    /// suggestion, fed back) deciding for it by the threshold.
    singles_undecided: Vec<u64>,
    pairs: usize,
    pairs_right: usize,
    /// Pairs named wrongly with the true pair not among the alternatives
    /// (the worst outcome: a confident wrong name).
    pairs_confidently_wrong: usize,
    foreign: usize,
    foreign_unexplained: usize,
    false_alarms: usize,
    /// Cases with a decided cause (`Diagnosis::decided_causes`) that is not a true cause.
    decided_wrong: usize,
    /// The same, had every alternative counted (also those that misfit).
    decided_wrong_any_alternative: usize,
    /// Pairs whose diagnosis suggested a next measurement ([`Follow::SuggestedMode`]).
    pairs_followed: usize,
    /// Pairs with both causes named once the suggested mode is measured
    /// (the first verdict where nothing was suggested).
    pairs_right_after: usize,
    /// Pairs with a decided cause that is not true once the suggested mode is measured.
    pairs_decided_wrong_after: usize,
    /// Pairs right before the suggested mode was measured and not after.
    pairs_unsettled: usize,
    /// Cases with a mode-shape suggestion (`Diagnosis::shape_measurement`).
    shape_suggested: usize,
    /// Those whose two models include the truth's ([`shape_check`]).
    shape_checkable: usize,
    /// Those where the truth's scan, measured at half the decisive sd, is
    /// expected to favour the truth's model by the decision threshold.
    shape_decides_for_truth: usize,
    /// Shape suggestions followed ([`measure_scan`]) whose two models include the truth's ([`scan_gap`]).
    scan_checkable: usize,
    /// Those where the rerun puts the truth's model ahead of the other by the decision threshold.
    scan_decides_for_truth: usize,
    /// Pairs whose noise-free data were diagnosed too ([`NoiseFree::Diagnose`]).
    pairs_noise_free: usize,
    /// Those whose noise-free data have both causes named.
    pairs_noise_free_named: usize,
    /// Those named on the noisy data and on the noise-free data.
    pairs_named_both_ways: usize,
    /// Every case's first diagnosis, by seed (for checks that build on one).
    diagnoses: BTreeMap<u64, Diagnosis>,
}

/// The mode-shape advice checked on the truth: when one of the two models
/// the suggestion separates is the truth's, the expected ln B of the truth's
/// model over the other when the truth's scan at the suggested point
/// ([`ShapeMeasurement::value_of`]) is measured with half the decisive sd
/// ([`ShapeMeasurement::expected_log_bayes_factor`]; `None` when neither is
/// the truth's). When the truth sits at its model's prediction this is ≈ 4×
/// the threshold. Why the expectation and not one keyed draw: a draw is
/// N(mean, ≈ 5²) in ln B there, so one case in ~25 falls below the threshold
/// by chance (seed 110: −1.3 at a draw of ≈ −2.5 sd, measured 2026-11-26),
/// which says nothing about the advice.
///
/// Printed, not asserted, since the scan itself is fed back ([`scan_gap`]),
/// which is the real test of the advice. This expectation reads one point
/// and takes each predictive as a Gaussian; a folded mass's predictive is an
/// equal mixture of two mirror images, which need not be near-Gaussian (the
/// likely reason, not checked). On fresh pairs 342, 358 and 374 (tension or
/// spring + mass, 2026-11-27) it was 0.7, 1.2 and 2.0 while the whole scan
/// fed back put the truth's model 94.5, 30.9 and 29.4 nats ahead.
fn shape_check(case: &SyntheticCase, m: &ShapeMeasurement) -> Option<f64> {
    let first = truth_side(case, m)? == 0;
    let ln_b = m.expected_log_bayes_factor(m.value_of(&case.truth_beam)?, 0.5 * m.decisive_measurement_sd);
    Some(if first { ln_b } else { -ln_b })
}

/// Which of the two models a shape suggestion separates is the truth's (0 or 1; `None`: neither).
fn truth_side(case: &SyntheticCase, m: &ShapeMeasurement) -> Option<usize> {
    let truth = Model::with(&case.hidden.causes);
    m.between.iter().position(|n| Model::from_name(n).as_ref() == Some(&truth))
}

/// The suggested scan read on the truth ([`ShapeMeasurement::scan_on`]), every
/// point of the grid at half the decisive sd (the instrument the suggestion
/// says would decide, with a margin), Gaussian noise keyed by the seed and
/// the mode. Readings below 5 sd are left out, as a lab leaves out points by
/// a node where the amplitude is lost in the noise (a magnitude's noise is
/// not Gaussian there, and a reading cannot be negative).
fn measure_scan(case: &SyntheticCase, m: &ShapeMeasurement, seed: u64) -> ModeScan {
    let sd = 0.5 * m.decisive_measurement_sd;
    let mut scan = m.scan_on(&case.truth_beam, sd).expect("the truth computes");
    let mut rng = stream(seed, Purpose::SyntheticCase, [3, m.mode as u64]);
    for p in &mut scan.points {
        let e: f64 = StandardNormal.sample(&mut rng);
        p.relative_amplitude += e * sd;
    }
    scan.points.retain(|p| p.relative_amplitude >= 5.0 * sd);
    scan
}

/// The scan fed back, judged on the truth: when one of the two models the
/// suggestion separates is the truth's, ln Z of the truth's model minus ln Z
/// of the other in the diagnosis with the scan (`None` when neither is the
/// truth's). The advice worked when this is at least the decision threshold.
fn scan_gap(case: &SyntheticCase, m: &ShapeMeasurement, with_scan: &Diagnosis) -> Option<f64> {
    let t = truth_side(case, m)?;
    let z = |name: &str| with_scan.candidates.iter().find(|c| c.extension == name).map(|c| c.log_evidence);
    Some(z(&m.between[t])? - z(&m.between[1 - t])?)
}

/// Whether a pair whose diagnosis suggests a next measurement gets it.
#[derive(Clone, Copy, PartialEq)]
enum Follow {
    No,
    /// The suggested mode is measured on the truth (or, where a mode-shape
    /// scan is suggested instead, the scan, [`measure_scan`]) and the
    /// diagnosis re-run: what a lab following the tool's advice would do. Every pair with a
    /// suggestion is followed, the right ones too (the advice must not
    /// unsettle a right answer), and never with knowledge of the truth.
    SuggestedMode,
}

/// Whether a pair's noise-free data ([`SyntheticCase::noise_free_data`]) are
/// diagnosed beside its noisy data.
#[derive(Clone, Copy, PartialEq)]
enum NoiseFree {
    Skip,
    /// The data's expectation, diagnosed at the same settings: both causes
    /// named there means the effects' sizes support naming them, the noise
    /// draw aside. Not named means that the rules the issue sets (a cause
    /// only at ln B ≥ 3 against the model without it, fewer causes unless
    /// more beat them by as much) do not name both on the expected data with
    /// these class priors, up to the evidence estimates' error (≈ 0.1–0.3
    /// nats): the true pair's ln Z minus that of the pair without each cause
    /// is printed, below 3 for a cause the data do not ask for, and a rival
    /// ahead of the true pair shows in the verdict.
    Diagnose,
}

/// ln Z of the true pair's model minus ln Z of that model without each cause,
/// from `d`'s candidates (`None` when one was not evaluated).
fn cause_gains(hidden: &Hidden, d: &Diagnosis) -> Vec<(&'static str, Option<f64>)> {
    let ln_z = |m: &Model| d.candidates.iter().find(|c| c.extension == m.name()).map(|c| c.log_evidence);
    let truth = Model::with(&hidden.causes);
    hidden.causes.iter().map(|&c| (c.name(), ln_z(&truth).zip(ln_z(&truth.without(c))).map(|(a, b)| a - b))).collect()
}

/// Mode `mode` of the truth with the generator's noise (0.3 % on ω, 3 % on
/// ζ; one keyed draw each): one resonance peak of a sweep gives both.
fn measure(case: &SyntheticCase, mode: usize, seed: u64) -> ModeObservation {
    let m = *modal(&case.truth_beam, mode).expect("the truth computes").mode(mode).expect("an oscillatory mode");
    let mut rng = stream(seed, Purpose::SyntheticCase, [2, mode as u64]);
    let (e1, e2): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
    let (omega_sd, zeta_sd) = (OMEGA_REL_SD * m.omega_rad_s, ZETA_REL_SD * m.zeta);
    ModeObservation {
        mode,
        omega_rad_s: m.omega_rad_s + e1 * omega_sd,
        omega_sd_rad_s: omega_sd,
        zeta: m.zeta + e2 * zeta_sd,
        zeta_sd,
    }
}

/// Are both causes of the pair `hidden` named (and the model explains the data)?
fn pair_named(hidden: &Hidden, d: &Diagnosis) -> bool {
    d.explained && hidden.causes.iter().all(|c| d.causes.contains(&c.name().to_string()))
}

/// Does `d` decide a cause `hidden` does not have?
fn decides_wrong(hidden: &Hidden, decided: &[String]) -> bool {
    decided.iter().any(|c| !hidden.causes.iter().any(|h| h.name() == c.as_str()))
}

/// True when `NANOBEAM_HIDDEN_SEEDS` keeps only some seeds: the tests then
/// check the verdicts of the seeds kept, not how many cases of each kind ran.
fn filtered() -> bool {
    std::env::var_os("NANOBEAM_HIDDEN_SEEDS").is_some()
}

/// Diagnoses every case (in parallel), prints one line per case and the confusion, and counts.
///
/// `NANOBEAM_HIDDEN_SEEDS=105,111` (a developer's aid) keeps only those seeds.
fn tally(cases: Vec<(u64, Hidden)>, follow: Follow, noise_free: NoiseFree) -> Tally {
    let settings = DiagnoseSettings::quick();
    let only: Option<Vec<u64>> = std::env::var("NANOBEAM_HIDDEN_SEEDS").ok().map(|v| {
        v.split(',').map(|s| s.trim().parse().expect("NANOBEAM_HIDDEN_SEEDS: comma-separated seeds")).collect()
    });
    let cases: Vec<(u64, Hidden)> =
        cases.into_iter().filter(|(seed, _)| only.as_ref().is_none_or(|o| o.contains(seed))).collect();
    let t0 = Instant::now();
    type Outcome = (u64, Hidden, f64, Diagnosis, f64, Option<Diagnosis>, Option<f64>, Option<Diagnosis>, Option<f64>);
    let results: Vec<Outcome> = cases
        .into_par_iter()
        .map(|(seed, hidden)| {
            let t = Instant::now();
            let case = generate_hidden(seed, &hidden);
            let d = diagnose(&case.data(), &settings).expect("valid synthetic data");
            // progress as cases finish (the table below is in seed order)
            eprintln!("seed {seed} {} → {} ({:.0} s)", hidden.label(), verdict(&d), t.elapsed().as_secs_f64());
            let after = match (&d.next_measurement, hidden.causes.len(), follow) {
                (Some(next), 2, Follow::SuggestedMode) if hidden.foreign.is_none() => {
                    let mut file = case.file.clone();
                    file.modes.push(measure(&case, next.mode, seed));
                    file.modes.sort_by_key(|m| m.mode);
                    let data = MeasuredData::from_file(file).expect("the truth's mode is valid data");
                    let a = diagnose(&data, &settings).expect("valid synthetic data");
                    eprintln!("seed {seed} + mode {} → {}", next.mode, verdict(&a));
                    Some(a)
                }
                _ => None,
            };
            // every shape suggestion is followed: the scan read on the truth, fed back as data
            let scanned = d.shape_measurement.as_ref().map(|m| {
                let mut file = case.file.clone();
                file.mode_scans.push(measure_scan(&case, m, seed));
                let data = MeasuredData::from_file(file).expect("the truth's scan is valid data");
                let a = diagnose(&data, &settings).expect("valid synthetic data");
                eprintln!("seed {seed} + scan of mode {} → {}", m.mode, verdict(&a));
                a
            });
            let after = match (after, &scanned, hidden.causes.len(), follow) {
                (None, Some(a), 2, Follow::SuggestedMode) if hidden.foreign.is_none() => Some(a.clone()),
                (after, ..) => after,
            };
            let scan_gap = d.shape_measurement.as_ref().zip(scanned.as_ref()).and_then(|(m, a)| scan_gap(&case, m, a));
            let shape = d.shape_measurement.as_ref().and_then(|m| shape_check(&case, m));
            let expected = (noise_free == NoiseFree::Diagnose && hidden.causes.len() == 2 && hidden.foreign.is_none())
                .then(|| diagnose(&case.noise_free_data(), &settings).expect("valid synthetic data"));
            (seed, hidden, case.base_fit_max_z, d, t.elapsed().as_secs_f64(), after, shape, expected, scan_gap)
        })
        .collect();
    let mut confusion: BTreeMap<(String, String), usize> = BTreeMap::new();
    let mut t = Tally::default();
    for (seed, hidden, z, d, secs, after, shape, expected, scan_gap) in &results {
        t.diagnoses.insert(*seed, d.clone());
        t.screened += d.screened.len();
        for c in &d.screen_checks {
            t.screen_shortfall_max = t.screen_shortfall_max.max(c.log_likelihood_at_map - c.log_likelihood_max_found);
            if let Some(l) = c.log_evidence_laplace {
                t.screen_laplace_excess_max = t.screen_laplace_excess_max.max(c.log_evidence - l);
            }
        }
        let truth = hidden.label();
        let got = verdict(d);
        *confusion.entry((truth.clone(), got.clone())).or_default() += 1;
        println!(
            "seed {seed:3} truth {truth:45} verdict {got:45} base-fit max z {z:6.1} lnB {:7.2} decided {:?} partial {:?} alternatives {:?} on prior bound {:?} {secs:.1} s",
            d.gain.log_bayes_factor,
            d.decided_causes,
            d.best_partial_explanation,
            d.alternatives.iter().map(|a| &a.extension).collect::<Vec<_>>(),
            d.candidates
                .iter()
                .filter(|c| c.extension == d.gain.extension)
                .flat_map(|c| c.map_on_prior_bound.iter().map(|h| &h.parameter))
                .collect::<Vec<_>>()
        );
        if let Some(m) = &d.shape_measurement {
            println!(
                "    shape: mode {} at {:.2} nm, {} {:.4} against {} {:.4}, decisive sd {:.4}; expected ln B for \
                 the truth at half that sd: {}",
                m.mode,
                m.position_x_nm,
                m.between[0],
                m.predicted_relative_amplitude[0],
                m.between[1],
                m.predicted_relative_amplitude[1],
                m.decisive_measurement_sd,
                shape.map_or("(neither is the truth's model)".to_string(), |b| format!("{b:.1}"))
            );
        }
        t.shape_suggested += usize::from(d.shape_measurement.is_some());
        t.shape_checkable += usize::from(shape.is_some());
        let threshold = DiagnoseSettings::quick().log_bayes_factor_threshold;
        t.shape_decides_for_truth += usize::from(shape.is_some_and(|b| b >= threshold));
        if let Some(g) = scan_gap {
            println!("    + the truth's scan: ln Z of the truth's model over the other {g:.1}");
        }
        t.scan_checkable += usize::from(scan_gap.is_some());
        t.scan_decides_for_truth += usize::from(scan_gap.is_some_and(|g| g >= threshold));
        t.decided_wrong += usize::from(decides_wrong(hidden, &d.decided_causes));
        let any = if d.explained { decided_causes(&d.causes, &unscreened(&d.alternatives)) } else { vec![] };
        t.decided_wrong_any_alternative += usize::from(decides_wrong(hidden, &any));
        if let Some(a) = after {
            let what = match (&d.next_measurement, &d.shape_measurement) {
                (Some(n), _) => format!("mode {} ({}, {:.1} sd)", n.mode, n.quantity, n.separation_sd),
                (None, Some(m)) => format!("scan of mode {}", m.mode),
                (None, None) => unreachable!("a follow-up follows a suggestion"),
            };
            println!(
                "    + {what}: verdict {} decided {:?} alternatives {:?}",
                verdict(a),
                a.decided_causes,
                a.alternatives.iter().map(|a| (&a.extension, a.misfits)).collect::<Vec<_>>()
            );
        }
        match (hidden.foreign, hidden.causes.len()) {
            (Some(_), _) => {
                t.foreign += 1;
                t.foreign_unexplained += usize::from(d.cause == "unexplained");
            }
            (None, 0) => t.false_alarms += usize::from(d.cause != "none"),
            (None, 1) => {
                t.singles += 1;
                t.singles_right += usize::from(d.cause == truth);
                let honest = d.decided_causes.is_empty()
                    && d.alternatives.iter().any(|a| a.extension == truth)
                    && scan_gap.is_some_and(|g| g >= threshold);
                if d.cause != truth && honest {
                    t.singles_undecided.push(*seed);
                }
            }
            (None, _) => {
                t.pairs += 1;
                let named = hidden.causes.iter().all(|c| d.causes.contains(&c.name().to_string()));
                t.pairs_right += usize::from(d.explained && named);
                let last = after.as_ref().unwrap_or(d);
                t.pairs_followed += usize::from(after.is_some());
                t.pairs_right_after += usize::from(pair_named(hidden, last));
                t.pairs_unsettled += usize::from(pair_named(hidden, d) && !pair_named(hidden, last));
                t.pairs_decided_wrong_after += usize::from(decides_wrong(hidden, &last.decided_causes));
                let doubted = d.alternatives.iter().any(|a| {
                    let alt = Model::from_name(&a.extension).expect("alternatives name models");
                    hidden.causes.iter().all(|c| alt.causes().contains(c))
                });
                t.pairs_confidently_wrong += usize::from(d.explained && !named && !doubted);
                if let Some(e) = expected {
                    println!(
                        "    noise-free data: verdict {} decided {:?} alternatives {:?}; ln B of each true cause \
                         against the true pair without it {}",
                        verdict(e),
                        e.decided_causes,
                        e.alternatives.iter().map(|a| &a.extension).collect::<Vec<_>>(),
                        cause_gains(hidden, e)
                            .iter()
                            .map(|(c, g)| format!("{c} {}", g.map_or("-".into(), |g| format!("{g:.1}"))))
                            .collect::<Vec<_>>()
                            .join(", ")
                    );
                    t.pairs_noise_free += 1;
                    let named_noise_free = pair_named(hidden, e);
                    t.pairs_noise_free_named += usize::from(named_noise_free);
                    t.pairs_named_both_ways += usize::from(named_noise_free && pair_named(hidden, d));
                }
            }
        }
    }
    println!("\nconfusion (truth → verdict: count)");
    for ((t, v), n) in &confusion {
        println!("  {t:45} → {v:45} {n}");
    }
    if follow == Follow::SuggestedMode {
        println!(
            "pairs with a suggested measurement {}; both named after measuring it {}/{} (before {}/{}; unsettled \
             {}); decided cause not true after {}",
            t.pairs_followed,
            t.pairs_right_after,
            t.pairs,
            t.pairs_right,
            t.pairs,
            t.pairs_unsettled,
            t.pairs_decided_wrong_after
        );
    }
    if t.pairs_noise_free > 0 {
        println!(
            "pairs both named on the noise-free data {}/{}: on both data {}, on the noise-free data only {}, on \
             the noisy data only {}",
            t.pairs_noise_free_named,
            t.pairs_noise_free,
            t.pairs_named_both_ways,
            t.pairs_noise_free_named - t.pairs_named_both_ways,
            t.pairs_right - t.pairs_named_both_ways
        );
    }
    println!(
        "cases with a decided cause that is not true had misfitting alternatives counted: {}",
        t.decided_wrong_any_alternative
    );
    println!(
        "mode-shape suggestions {}; with the truth's model one of the two {}; the truth's scan expected to decide \
         for it {}; fed back, decides for it {}",
        t.shape_suggested, t.shape_checkable, t.shape_decides_for_truth, t.scan_decides_for_truth
    );
    println!(
        "singles {}/{}, pairs both named {}/{} (wrong with the truth not an alternative: {}), foreign unexplained \
         {}/{}, false alarms {}, cases with a decided cause that is not true {}; {:.0} s",
        t.singles_right,
        t.singles,
        t.pairs_right,
        t.pairs,
        t.pairs_confidently_wrong,
        t.foreign_unexplained,
        t.foreign,
        t.false_alarms,
        t.decided_wrong,
        t0.elapsed().as_secs_f64()
    );
    t
}

/// `alternatives` as if none misfitted (the rule before misfitting alternatives were screened).
fn unscreened(alternatives: &[nanobeam::diagnose::Alternative]) -> Vec<nanobeam::diagnose::Alternative> {
    alternatives.iter().map(|a| nanobeam::diagnose::Alternative { misfits: false, ..a.clone() }).collect()
}

/// A developer's aid: writes the measured-data file of every CI case (the
/// seeds of `ci_cases`, 300 and 400) to the directory `NANOBEAM_HIDDEN_DUMP`
/// names, so that two builds' `nanobeam diagnose` can be timed on the same
/// inputs (the record of issue 41's screening in `tests/diagnose_hidden.md`).
#[test]
#[ignore = "a developer's aid: writes the CI cases' files to $NANOBEAM_HIDDEN_DUMP"]
fn write_the_ci_cases() {
    let dir =
        std::path::PathBuf::from(std::env::var("NANOBEAM_HIDDEN_DUMP").expect("NANOBEAM_HIDDEN_DUMP: a directory"));
    std::fs::create_dir_all(&dir).expect("the dump directory can be made");
    let open = open_cases().into_iter().filter(|(seed, _)| [300, 400].contains(seed));
    for (seed, hidden) in ci_cases().into_iter().chain(open) {
        let case = generate_hidden(seed, &hidden);
        let name = format!("{seed}-{}.yaml", hidden.label().replace([':', '+'], "_"));
        std::fs::write(dir.join(name), serde_yaml::to_string(&case.file).expect("a file serialises"))
            .expect("the dump directory is writable");
    }
}
