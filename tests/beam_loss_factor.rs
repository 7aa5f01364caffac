//! The hysteretic loss factor η (issue 65) and the foundation with relaxation
//! in the forward model, against a closed form that shares no code with
//! `src/`: on a simply supported nonlocal beam every extension here keeps the
//! sine modes, and mode n's oscillatory pole is the root in the upper half
//! plane of
//!   (s² + c s + a)(s + Ω) + b(1 + iη)((1 + Δ)s + Ω) = 0,
//! with a = (Nα² + k)/ρA (the axial force and the foundation: elastic),
//! b = EIα⁴/(ρA(1 + μα²)), c = C/ρA, α = nπ/L, one relaxation (Δ, Ω)
//! (Eringen's operator on inertia, damping, force and foundation alike). The
//! cubic's roots come from nalgebra's complex Schur decomposition of its
//! companion matrix, polished by Newton on the cubic itself. The axial force
//! sends `src/` down its wavenumber-block path (Newton on each block's
//! determinant with the modulus G(s)(1 + iη)), the rest down the decoupled
//! families.

use std::f64::consts::PI;

use nalgebra::Matrix3;
use num_complex::Complex64;

use nanobeam::beam::{impulse_response, modal, modal_state_space, BeamSpec, InternalVariable, ModalSolver, Support};

fn swcnt(elements: usize) -> BeamSpec {
    BeamSpec::elastic(8.0, 1.0, 1e12, 2300.0, Support::SimplySupported, elements)
}

/// The closed form's oscillatory pole of mode n (rad/s), largest |s| with Im > 0.
fn closed_form_pole(b: &BeamSpec, n: usize) -> Complex64 {
    let ei = b.youngs_modulus_pa * b.inertia_m4();
    let rho_a = b.density_kg_m3 * b.area_m2();
    let al = n as f64 * PI / (b.length_nm * 1e-9);
    let mu = (b.nonlocal_e0a_nm * 1e-9).powi(2);
    let (delta, omega) = b.internal_variables.first().map_or((0.0, 1.0), |iv| (iv.delta, iv.omega_rad_s));
    let bb = ei * al.powi(4) / (rho_a * (1.0 + mu * al * al));
    let a = (b.axial_force_n * al * al + b.elastic_foundation_n_m2) / rho_a;
    let c = b.viscous_damping_n_s_m2 / rho_a;
    let bc = Complex64::new(bb, bb * b.loss_factor);
    // in x = s/√bb: x³ + p2 x² + p1 x + p0 = 0
    let r = bb.sqrt();
    let p2 = Complex64::new((omega + c) / r, 0.0);
    let p1 = (Complex64::new(c * omega + a, 0.0) + bc * (1.0 + delta)) / (r * r);
    let p0 = (a * omega + bc * omega) / (r * r * r);
    let z = Complex64::new(0.0, 0.0);
    let one = Complex64::new(1.0, 0.0);
    let companion = Matrix3::new(z, z, -p0, one, z, -p1, z, one, -p2);
    let eig = nalgebra::Schur::new(companion).eigenvalues().expect("a complex Schur form");
    let mut x = eig
        .iter()
        .copied()
        .filter(|x| x.im > 0.0)
        .max_by(|p, q| p.norm_sqr().total_cmp(&q.norm_sqr()))
        .expect("an oscillatory root");
    for _ in 0..4 {
        x -= (((x + p2) * x + p1) * x + p0) / ((3.0 * x + 2.0 * p2) * x + p1);
    }
    x * r
}

/// Every mode n ≤ 3 of `b` (40 elements) against the closed form.
///
/// Tolerance: the FE bending eigenvalue is a Rayleigh–Ritz upper bound
/// within (αh)⁴/720 relative (`tests/beam_axial_shear.rs` derives it; the
/// force's and foundation's parts are exact or higher order); b enters the
/// pole with a sensitivity |∂ln s/∂ln b| ≤ (1 + Δ)/2·|(1 + iη)| < 1.5 here,
/// so |δs|/|s| ≤ 1.5·(αh)⁴/720, and a factor 2 covers the O((αh)⁶) rest.
/// ζ = −Re s/|s| moves by at most 2|δs|/|s|.
fn check(b: &BeamSpec, label: &str) {
    let got = modal(b, 3).unwrap_or_else(|e| panic!("{label}: {e}"));
    for n in 1..=3 {
        let exact = closed_form_pole(b, n);
        let ah = n as f64 * PI / b.elements as f64;
        let bound = 2.0 * 1.5 * ah.powi(4) / 720.0;
        let m = &got.modes[n - 1];
        let rel = (m.pole - exact).norm() / exact.norm();
        let zeta = -exact.re / exact.norm();
        assert!(rel <= bound, "{label} mode {n}: pole {} vs {exact} (rel {rel:e}, bound {bound:e})", m.pole);
        assert!((m.zeta - zeta).abs() <= 2.0 * bound, "{label} mode {n}: ζ {} vs {zeta}", m.zeta);
    }
}

#[test]
fn the_loss_factor_and_the_foundation_match_the_closed_form() {
    let iv = InternalVariable { delta: 0.4, omega_rad_s: 6e11 };
    let n_unit = {
        let b = swcnt(40);
        b.youngs_modulus_pa * b.inertia_m4() / (b.length_nm * 1e-9).powi(2)
    };
    let k_unit = n_unit / (8e-9f64).powi(2);
    let mut cases = Vec::new();
    for eta in [0.0, 0.02, 0.3, 0.9] {
        for (e0a, relax, c, axial, found) in [
            (0.0, false, 0.0, 0.0, 0.0),
            (1.0, true, 0.0, 0.0, 0.0),
            (1.0, true, 2e-6, 0.0, 0.0),
            (0.8, true, 0.0, 3.0, 0.0),
            (0.8, true, 1e-6, -2.0, 0.0),
            (1.0, true, 0.0, 0.0, 40.0),
            (1.0, false, 1e-6, 0.0, -30.0),
        ] {
            let mut b = swcnt(40);
            b.loss_factor = eta;
            b.nonlocal_e0a_nm = e0a;
            b.internal_variables = if relax { vec![iv] } else { vec![] };
            b.viscous_damping_n_s_m2 = c;
            b.axial_force_n = axial * n_unit;
            b.elastic_foundation_n_m2 = found * k_unit;
            cases.push(b);
        }
    }
    for b in &cases {
        let label = format!(
            "η {} e0a {} Δ {:?} C {} N {:e} k {:e}",
            b.loss_factor,
            b.nonlocal_e0a_nm,
            b.internal_variables.first().map(|v| v.delta),
            b.viscous_damping_n_s_m2,
            b.axial_force_n,
            b.elastic_foundation_n_m2
        );
        check(b, &label);
    }
}

/// An elastic beam with η alone: s² = −λ(1 + iη) on every family, any
/// support, so every mode's ω is (1 + η²)^¼ times the elastic one and
/// ζ = sin(½ atan η), to the continuation's round-off (1e-12).
#[test]
fn a_loss_factor_alone_damps_every_mode_alike_on_every_support() {
    for support in Support::ALL {
        let mut b = BeamSpec::elastic(8.0, 1.0, 1e12, 2300.0, support, 16);
        b.nonlocal_e0a_nm = 0.7;
        let elastic = modal(&b, 5).unwrap();
        for eta in [1e-4, 0.1, 0.6] {
            b.loss_factor = eta;
            let mut solver = ModalSolver::new();
            let lossy = solver.modal(&b, 5).unwrap();
            let zeta = (0.5 * f64::atan(eta)).sin();
            for (l, e) in lossy.modes.iter().zip(&elastic.modes) {
                let ratio = l.omega_rad_s / e.omega_rad_s / (1.0 + eta * eta).powf(0.25);
                assert!((ratio - 1.0).abs() < 1e-12, "{support:?} η {eta}: ω ratio {ratio}");
                assert!((l.zeta - zeta).abs() < 1e-12, "{support:?} η {eta}: ζ {} vs {zeta}", l.zeta);
            }
            assert!(lossy.overdamped.is_empty() && lossy.real_poles_rad_s.is_empty());
        }
    }
}

/// A hysteretic loss has no time-domain form: the state-space solvers and
/// the impulse response refuse it (exit 1, numerical), and the field is
/// validated to [0, 1).
#[test]
fn a_loss_factor_has_no_state_space_and_is_validated() {
    let mut b = swcnt(12);
    b.loss_factor = 0.1;
    assert!(modal_state_space(&b, 2).unwrap_err().to_string().contains("loss factor"));
    assert!(impulse_response(&b, 3.0, 5.0, 1e-14, 8).is_err());
    for bad in [-0.1, 1.0, f64::NAN] {
        b.loss_factor = bad;
        let e = b.validate().unwrap_err().to_string();
        assert!(e.starts_with("invalid loss_factor") && e.contains("0 <= loss_factor < 1"), "{e}");
    }
}
