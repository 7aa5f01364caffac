//! paper/published.yaml loads strictly; the reference values it encodes are
//! derived correctly; the frequency-unit evidence is internally consistent.

use nanobeam::reproduce::reference::*;
use std::path::Path;

fn yaml_path() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("paper/published.yaml")
}

fn published() -> Published {
    Published::load(&yaml_path()).expect("published.yaml loads")
}

#[test]
fn published_yaml_loads_with_all_cases_and_sourced_claims() {
    let p = published();
    let ids: Vec<&str> = p.cases.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["1A", "1B", "1C", "2A", "2B", "2C", "3"]);
    assert_eq!(p.model.n_elements.value, 20);
    assert_eq!(p.model.support.value, "simply-supported");
    // Every claim, definition and reported number says where it is stated.
    let sources = p
        .claims
        .iter()
        .map(|c| &c.source)
        .chain(p.definitions.iter().map(|d| &d.source))
        .chain(p.reported_values.iter().map(|r| &r.source))
        .chain(p.reported_relative_errors.iter().map(|r| &r.source))
        .chain(p.cases.iter().map(|c| &c.priors_source));
    for s in sources {
        assert!(s.contains('§'), "source without a section: {s}");
    }
    // The unknowns of each case have exactly one prior each, in order.
    for c in &p.cases {
        let prior_names: Vec<&str> = c.priors.iter().map(|q| q.parameter.as_str()).collect();
        let expected: Vec<&str> =
            c.unknowns.iter().map(|u| if u == "beta" { "beta_squared" } else { u.as_str() }).collect();
        assert_eq!(prior_names, expected, "case {}", c.id);
        if let Some(c0) = &c.proposal_c0_sd {
            assert_eq!(c0.len(), c.unknowns.len(), "case {}", c.id);
            // AM scaling sd = 2.4²/d (Haario et al.), d = number of unknowns.
            let sd = c.am_scaling_sd.as_ref().unwrap().value;
            assert!((sd - 2.4f64.powi(2) / c.unknowns.len() as f64).abs() < 1e-12, "case {}", c.id);
        }
    }
}

#[test]
fn unknown_and_missing_fields_are_rejected_with_the_field_named() {
    let text = std::fs::read_to_string(yaml_path()).unwrap();
    let extra = text.replacen("  n_elements:\n    value: 20\n", "  n_elements:\n    value: 20\n    length_nm: 8\n", 1);
    assert_ne!(extra, text);
    let err = Published::from_yaml_str(&extra).unwrap_err();
    assert!(err.to_string().contains("length_nm"), "{err}");
    let missing = text.replacen("\n      printed_decimals: 2\n", "\n", 1);
    assert_ne!(missing, text);
    let err = Published::from_yaml_str(&missing).unwrap_err();
    assert!(err.to_string().contains("printed_decimals"), "{err}");
    let dangling = text.replacen("covariance_set: case_3\n", "covariance_set: case_4\n", 1);
    assert_ne!(dangling, text);
    let err = Published::from_yaml_str(&dangling).unwrap_err();
    assert!(err.field.contains("covariance_set") && err.value == "case_4", "{err}");
}

#[test]
fn rounding_interval_is_half_a_unit_of_the_last_printed_digit() {
    let (lo, hi) = rounding_interval(0.16, 2);
    assert!((lo - 0.155).abs() < 1e-15 && (hi - 0.165).abs() < 1e-15);
    let (lo, hi) = rounding_interval(5.6, 1);
    assert!((lo - 5.55).abs() < 1e-15 && (hi - 5.65).abs() < 1e-15);
}

/// The derivation inverted: value → variance must give back the printed
/// entry, and the interval ends must give back printed ± half a unit.
/// Round-off: a square root and a division each lose ≤ 1 ulp, so relative
/// 1e-14 is ample.
#[test]
fn reference_values_invert_to_the_printed_covariances() {
    let p = published();
    let c_w = p.measurement_error.relative_sd_frequency.value;
    let c_z = p.measurement_error.relative_sd_damping.value;
    assert_eq!((c_w, c_z), (0.003, 0.03));
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs().max(1e-300);
    for set in &p.measurement_error.covariance_sets {
        let m = reference_modal(set, c_w, c_z);
        assert_eq!(m.omega_ghz.len(), 3);
        assert_eq!(m.zeta.len(), 3);
        let h = 0.5 * 10f64.powi(-(set.printed_decimals as i32));
        for (r, &printed) in m.omega_ghz.iter().zip(&set.sigma_omega_omega_diag_ghz2) {
            assert!(close((r.value * c_w).powi(2), printed));
            assert!(close((r.lower * c_w).powi(2), printed - h));
            assert!(close((r.upper * c_w).powi(2), printed + h));
            assert!(r.contains(r.value) && r.lower < r.value && r.value < r.upper);
        }
        for (r, &printed) in m.zeta.iter().zip(&set.sigma_zeta_zeta_diag_1e_minus_6) {
            assert!(close((r.value * c_z).powi(2) * 1e6, printed));
            assert!(close((r.lower * c_z).powi(2) * 1e6, printed - h));
            assert!(close((r.upper * c_z).powi(2) * 1e6, printed + h));
            assert!(r.contains(r.value));
        }
        // Frequencies increase with the mode number (a simply supported beam).
        assert!(m.omega_ghz.windows(2).all(|w| w[0].upper <= w[1].lower));
    }
}

#[test]
fn cases_1_2_reference_omega1_is_400_over_3_ghz() {
    // sqrt(0.16) = 0.4 exactly, 0.4/0.003 = 400/3.
    let p = published();
    let m = reference_modal(p.covariance_set("cases_1_2").unwrap(), 0.003, 0.03);
    assert!((m.omega_ghz[0].value - 400.0 / 3.0).abs() < 1e-12);
    // sqrt(0.16e-6) = 4e-4, 4e-4/0.03 = 1/75.
    assert!((m.zeta[2].value - 1.0 / 75.0).abs() < 1e-15);
    // The interval width is about dω/dp · 0.01 = 0.01/(2c·sqrt(p)); the
    // difference is the second-order term, relative size (h/p)² ≈ 1e-3 here.
    let width = m.omega_ghz[0].upper - m.omega_ghz[0].lower;
    let linear = 0.01 / (2.0 * 0.003 * 0.4);
    assert!((width - linear).abs() / linear < 2e-3, "{width} vs {linear}");
}

#[test]
fn kappa_solves_the_mode_ratio_equation() {
    for (w2, w3) in [(440.0, 790.0), (455.8, 847.9), (300.0, 674.0)] {
        let k = nonlocal_kappa_from_ratio_32(w2, w3).unwrap();
        let ratio = 2.25 * ((1.0 + 4.0 * k) / (1.0 + 9.0 * k)).sqrt();
        assert!((ratio - w3 / w2).abs() < 1e-12, "{w2} {w3}");
    }
    // Local beam (ratio 9/4) ⇒ κ = 0; ratios outside (3/2·..., 9/4] have no κ.
    assert!(nonlocal_kappa_from_ratio_32(4.0, 9.0).unwrap().abs() < 1e-15);
    assert!(nonlocal_kappa_from_ratio_32(4.0, 9.5).is_none());
    assert!(nonlocal_kappa_from_ratio_32(4.0, 5.0).is_none());
}

#[test]
fn implied_lengths_reproduce_omega1() {
    // Round trip: the implied length and κ must give back ω1 through
    // ω1 = (π/L)²·c/sqrt(1+κ) and, locally, ω1 = (π/L)²·c.
    let p = published();
    for m in p.reference_modal_sets() {
        let w = [m.omega_ghz[0].value, m.omega_ghz[1].value, m.omega_ghz[2].value];
        let ev = frequency_unit_evidence(w).unwrap();
        for (beam, imp) in &ev.implications {
            let c = beam.bending_wave_constant_m2_s();
            let local = (PI_ / (imp.local_length_nm * 1e-9)).powi(2) * c;
            let nonlocal = (PI_ / (imp.nonlocal_length_nm * 1e-9)).powi(2) * c / (1.0 + ev.kappa).sqrt();
            assert!((local / imp.omega1_rad_s - 1.0).abs() < 1e-12);
            assert!((nonlocal / imp.omega1_rad_s - 1.0).abs() < 1e-12);
            let kappa_back = (imp.implied_e0a_nm * PI_ / imp.nonlocal_length_nm).powi(2);
            assert!((kappa_back / ev.kappa - 1.0).abs() < 1e-12);
        }
    }
}
const PI_: f64 = std::f64::consts::PI;

#[test]
fn ghz_is_read_as_cyclic_frequency() {
    let p = published();
    for m in p.reference_modal_sets() {
        let w = [m.omega_ghz[0].value, m.omega_ghz[1].value, m.omega_ghz[2].value];
        let ev = frequency_unit_evidence(w).unwrap();
        assert_eq!(ev.favoured, FrequencyReading::Cyclic, "set {}", m.set_id);
        for (_, imp) in &ev.implications {
            match imp.reading {
                FrequencyReading::Cyclic => assert!(imp.e0a_inside_prior, "{imp:?}"),
                FrequencyReading::Angular => assert!(!imp.e0a_inside_prior, "{imp:?}"),
            }
        }
        // The same fact the YAML records as the chosen reading.
        assert_eq!(p.interpretations.frequency_unit.reading, "cyclic");
    }
    assert!((FrequencyReading::Cyclic.to_rad_s(1.0) - 2.0 * PI_ * 1e9).abs() < 1e-3);
    assert_eq!(FrequencyReading::Angular.to_rad_s(1.0), 1e9);
}

#[test]
fn case_3_fourth_mode_prediction_matches_around_1250_ghz() {
    let p = published();
    let stated = p.reported_values.iter().find(|r| r.id == "fourth_mode_frequency_case_3_ghz").unwrap().value;
    let m = reference_modal(p.covariance_set("case_3").unwrap(), 0.003, 0.03);
    // Propagate the Σ rounding: evaluate the prediction at the interval
    // corners of ω2 and ω3 (κ and ω4 are monotone in each).
    let mut preds = vec![];
    for w2 in [m.omega_ghz[1].lower, m.omega_ghz[1].upper] {
        for w3 in [m.omega_ghz[2].lower, m.omega_ghz[2].upper] {
            preds.push(frequency_unit_evidence([m.omega_ghz[0].value, w2, w3]).unwrap().predicted_omega4_ghz);
        }
    }
    let (lo, hi) = preds.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| (l.min(v), h.max(v)));
    // "around 1250 GHz" is read off a figure and printed with 3 significant
    // digits; allow ±25 GHz (half of the 50 GHz step of a 2-digit reading
    // "1.2e3 … 1.3e3") around the rounding range of the prediction.
    assert!(lo - 25.0 <= stated && stated <= hi + 25.0, "predicted [{lo}, {hi}] vs stated {stated}");
}

/// A published-values file that cannot be read, or is not UTF-8, is refused
/// with what is there in the value slot (its path, its first characters as
/// written) and what is allowed, on one short line (issue 69: "(unreadable)").
#[test]
fn an_unreadable_published_file_shows_what_is_there() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("published.yaml");
    let binary = dir.path().join("binary.yaml");
    std::fs::write(&binary, b"model:\n  n_elements: \xff\xfe 20\n").unwrap();
    let cases = [
        (missing.clone(), format!("`{}`", missing.display()), "a readable file ("),
        (dir.path().to_path_buf(), format!("`{}`", dir.path().display()), "a readable file ("),
        (binary, "`model:   n_elements: \u{fffd}\u{fffd} 20`".to_string(), "YAML text in UTF-8 (byte 22 is not UTF-8)"),
    ];
    for (path, value, allowed) in cases {
        let e = Published::load(&path).unwrap_err();
        let line = e.to_string();
        assert!(
            path.display().to_string().chars().count() <= 40,
            "the temporary path is short enough to be shown whole"
        );
        assert_eq!((e.field.as_str(), e.value.as_str()), ("published.yaml", value.as_str()), "{line}");
        assert!(e.allowed.starts_with(allowed), "{line}");
        assert!(!line.contains("(unreadable)") && line.lines().count() == 1 && line.chars().count() <= 200, "{line}");
    }
}
