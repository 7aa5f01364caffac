//! Hidden-effect tests: synthetic data from a truth with one effect (or none),
//! diagnosed without the truth. Run with `-- --nocapture` for the confusion matrix.

use std::collections::BTreeMap;
use std::time::Instant;

use nanobeam::diagnose::{diagnose, synthetic, DiagnoseSettings, ModelClass};

fn label(c: Option<ModelClass>) -> &'static str {
    c.map_or("none", |c| c.name())
}

#[test]
fn hidden_effects_are_named_and_clean_data_raise_no_alarm() {
    let settings = DiagnoseSettings::quick();
    let t0 = Instant::now();
    // 20 effect seeds (5 per cause, the effect's shape and size drawn by seed) + 5 clean seeds
    let mut cases: Vec<(u64, Option<ModelClass>)> =
        (0..20u64).map(|i| (100 + i, Some(ModelClass::CAUSES[(i % 4) as usize]))).collect();
    cases.extend((0..5u64).map(|i| (200 + i, None)));
    let mut confusion: BTreeMap<(&str, String), usize> = BTreeMap::new();
    let (mut correct, mut total, mut false_alarms) = (0, 0, 0);
    for (seed, effect) in cases {
        let case = synthetic::generate(seed, effect);
        let data = case.data();
        let d = diagnose(&data, &settings).expect("valid synthetic data");
        let truth = label(case.truth);
        *confusion.entry((truth, d.cause.clone())).or_default() += 1;
        println!(
            "seed {seed:3} truth {truth:29} cause {:29} misfit {:5} base-fit max z {:5.1} lnB {:7.2}",
            d.cause, d.misfit_detected, case.base_fit_max_z, d.gain.log_bayes_factor
        );
        if effect.is_some() {
            total += 1;
            correct += usize::from(d.cause == truth);
        } else {
            false_alarms += usize::from(d.cause != "none");
        }
    }
    let causes: Vec<&str> = ModelClass::CAUSES.iter().map(|c| c.name()).chain(["none", "unexplained"]).collect();
    println!("\nconfusion matrix (rows: truth, columns: diagnosed cause)");
    print!("{:30}", "");
    for c in &causes {
        print!("{:>14.14}", c);
    }
    println!();
    for t in causes.iter().take(5) {
        print!("{t:30}");
        for c in &causes {
            print!("{:>14}", confusion.get(&(*t, c.to_string())).copied().unwrap_or(0));
        }
        println!();
    }
    println!(
        "correct {correct}/{total}, false alarms on clean data {false_alarms}/5, {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    // ≥ 95 % of the effect cases named correctly, no false alarm.
    assert!(correct * 100 >= 95 * total, "only {correct}/{total} causes right");
    assert_eq!(false_alarms, 0);
}
