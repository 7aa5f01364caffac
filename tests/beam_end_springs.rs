//! Per-end support springs in the beam file (issue 40, item 2):
//! `support_rotational_stiffness_left_n_m_rad` (x = 0) and
//! `support_rotational_stiffness_right_n_m_rad` (x = L) beside the old
//! both-ends field. Their physics is checked against the independent exact
//! dynamic stiffness in `tests/independent_generator.rs`
//! (`per_end_springs_match_the_exact_dynamic_stiffness`); this file holds
//! the file contract: backward compatibility, the sum rule, the mirror
//! symmetry, and bad input (exit 2, one line naming field, value and range).
//! Data: the project's own `beam` on the catalogue's nominal tube.

use std::process::Command;

use nanobeam::beam::{modal, BeamSpec, Support};

const BEAM: &str = "length_nm: 8\ndiameter_nm: 1\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300\nelements: 20\nnonlocal_e0a_nm: 0.5\ninternal_variables:\n  - {delta: 0.3, omega_rad_s: 3.0e11}\n";

/// EI/L of the tube above (N·m/rad): κ = kL/EI = 1 at this stiffness.
fn k_ref() -> f64 {
    let b = BeamSpec::elastic(8.0, 1.0, 1.0e12, 2300.0, Support::SimplySupported, 20);
    1.0e12 * b.inertia_m4() / 8e-9
}

fn beam(support: &str, extra: &str) -> Result<BeamSpec, nanobeam::error::InputError> {
    BeamSpec::from_yaml(&format!("{BEAM}support: {support}\n{extra}"))
}

fn omegas(b: &BeamSpec) -> Vec<(f64, f64)> {
    modal(b, 5).unwrap().modes.iter().map(|m| (m.omega_rad_s, m.zeta)).collect()
}

fn close(a: &[(f64, f64)], b: &[(f64, f64)], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x.0 / y.0 - 1.0).abs() < tol && (x.1 / y.1 - 1.0).abs() < tol)
}

/// The old field keeps its meaning (every free rotation: both ends of a
/// simply supported beam, x = L of a clamped–pinned one) and equals the
/// same stiffness given to each end; the per-end fields add to it (springs
/// in parallel); a spring at x = 0 alone has the modes of one at x = L
/// alone (the mirror image), and neither has those of the symmetric one.
/// Round-off tolerance: the assembled matrices differ only in the order of
/// additions on one diagonal entry, 1e-12 relative.
#[test]
fn the_both_ends_field_and_the_per_end_fields_compose() {
    let k = 3.0 * k_ref();
    let both = beam("simply-supported", &format!("support_rotational_stiffness_n_m_rad: {k:e}\n")).unwrap();
    let each = beam(
        "simply-supported",
        &format!(
            "support_rotational_stiffness_left_n_m_rad: {k:e}\nsupport_rotational_stiffness_right_n_m_rad: {k:e}\n"
        ),
    )
    .unwrap();
    assert!(close(&omegas(&both), &omegas(&each), 1e-12));
    let half = beam(
        "simply-supported",
        &format!(
            "support_rotational_stiffness_n_m_rad: {:e}\nsupport_rotational_stiffness_left_n_m_rad: {:e}\n",
            k,
            2.0 * k
        ),
    )
    .unwrap();
    let sum = beam(
        "simply-supported",
        &format!(
            "support_rotational_stiffness_left_n_m_rad: {:e}\nsupport_rotational_stiffness_right_n_m_rad: {k:e}\n",
            3.0 * k
        ),
    )
    .unwrap();
    assert!(close(&omegas(&half), &omegas(&sum), 1e-12));
    let left = beam("simply-supported", &format!("support_rotational_stiffness_left_n_m_rad: {k:e}\n")).unwrap();
    let right = beam("simply-supported", &format!("support_rotational_stiffness_right_n_m_rad: {k:e}\n")).unwrap();
    assert!(close(&omegas(&left), &omegas(&right), 1e-12));
    assert!(close(&omegas(&left), &omegas(&left.mirror_image()), 1e-12));
    assert_eq!(left.mirror_image().support_rotational_stiffness_right_n_m_rad, k);
    assert!(!left.mirrors_itself() && both.mirrors_itself());
    // a one-end spring is neither pinned nor the symmetric spring
    let pinned = omegas(&beam("simply-supported", "").unwrap());
    let (w1, w1_pin, w1_both) = (omegas(&left)[0].0, pinned[0].0, omegas(&both)[0].0);
    assert!(w1 > w1_pin * 1.01 && w1 < w1_both * 0.99, "{w1_pin} < {w1} < {w1_both}");
    // clamped–pinned: the old field and the right field are the same spring
    let cp_old = beam("clamped-pinned", &format!("support_rotational_stiffness_n_m_rad: {k:e}\n")).unwrap();
    let cp_right = beam("clamped-pinned", &format!("support_rotational_stiffness_right_n_m_rad: {k:e}\n")).unwrap();
    assert!(close(&omegas(&cp_old), &omegas(&cp_right), 1e-12));
}

/// Bad per-end springs name the field, the value and the allowed range.
#[test]
fn bad_per_end_springs_name_field_value_and_range() {
    let cases = [
        (
            "simply-supported",
            "support_rotational_stiffness_left_n_m_rad: -1.0e-9\n",
            "support_rotational_stiffness_left_n_m_rad",
            ">= 0",
        ),
        (
            "simply-supported",
            "support_rotational_stiffness_right_n_m_rad: .nan\n",
            "support_rotational_stiffness_right_n_m_rad",
            ">= 0",
        ),
        (
            "clamped-pinned",
            "support_rotational_stiffness_left_n_m_rad: 1.0e-9\n",
            "support_rotational_stiffness_left_n_m_rad",
            "only support_rotational_stiffness_right_n_m_rad acts",
        ),
        (
            "clamped-clamped",
            "support_rotational_stiffness_right_n_m_rad: 1.0e-9\n",
            "support_rotational_stiffness_right_n_m_rad",
            "no per-end spring acts",
        ),
        (
            "clamped-free",
            "support_rotational_stiffness_right_n_m_rad: 1.0e-9\n",
            "support_rotational_stiffness_right_n_m_rad",
            "0 on a clamped-free beam",
        ),
        (
            "simply-supported",
            "support_rotational_stiffness_left_n_m_rad: 1.0e10\n",
            "support_rotational_stiffness_left_n_m_rad",
            "k_r L/EI",
        ),
        (
            "simply-supported",
            "support_rotational_stiffness_n_m_rad: 1.0e10\n",
            "support_rotational_stiffness_n_m_rad",
            "k_r L/EI",
        ),
    ];
    for (support, extra, field, range) in cases {
        let e = beam(support, extra).expect_err(extra);
        assert_eq!(e.field, field, "{extra}");
        assert!(e.to_string().contains(range), "{extra}: {e}");
    }
    // the old field stays accepted on every support (it acts where a rotation is free)
    for support in ["clamped-clamped", "clamped-free", "clamped-pinned"] {
        beam(support, "support_rotational_stiffness_n_m_rad: 1.0e-9\n").unwrap();
    }
}

/// Through the CLI: exit 2 and one stderr line naming the field.
#[test]
fn the_cli_refuses_a_spring_on_a_clamped_end_with_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("b.yaml");
    std::fs::write(&p, format!("{BEAM}support: clamped-pinned\nsupport_rotational_stiffness_left_n_m_rad: 1.0e-9\n"))
        .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_nanobeam")).args(["modal", p.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("support_rotational_stiffness_left_n_m_rad = ") && err.contains("x = 0 is clamped"), "{err}");
}

/// The `support-rotational-stiffness` class's upper end, κ = kL/EI = 1e3 at
/// one end (`diagnose::classes::END_SPRING_RANGE`), is a clamp at the
/// diagnosis's noise: ω of modes 1–5 within 0.3 % (the measurement sd) of the
/// clamped–pinned beam's, and its lower end, κ = 1e-2, is no spring: within
/// 0.1 % of the pinned one's.
#[test]
fn the_end_spring_range_spans_pinned_to_clamped() {
    let k = |kappa: f64| kappa * k_ref();
    let cp = omegas(&beam("clamped-pinned", "").unwrap());
    let ss = omegas(&beam("simply-supported", "").unwrap());
    let stiff = omegas(
        &beam("simply-supported", &format!("support_rotational_stiffness_left_n_m_rad: {:e}\n", k(1e3))).unwrap(),
    );
    let soft = omegas(
        &beam("simply-supported", &format!("support_rotational_stiffness_left_n_m_rad: {:e}\n", k(1e-2))).unwrap(),
    );
    for i in 0..5 {
        let (d_clamp, d_pin) = (stiff[i].0 / cp[i].0 - 1.0, soft[i].0 / ss[i].0 - 1.0);
        println!("mode {}: κ 1e3 vs clamped {d_clamp:.2e}; κ 1e-2 vs pinned {d_pin:.2e}", i + 1);
        assert!(d_clamp.abs() < 3e-3 && d_pin.abs() < 1e-3, "mode {}", i + 1);
    }
}
