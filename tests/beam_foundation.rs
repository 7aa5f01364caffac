//! The Winkler foundation (issue 65) in the forward model. References, none
//! of them `src/`'s solvers: the simply supported continuum closed form
//! ω² = (EIα⁴/(1 + μα²) + k)/ρA (Eringen's operator on the reaction as on the
//! inertia, `beam::fe::scaling`'s module doc), its loss of stability at
//! k = −EIα₁⁴/(1 + μα₁²), and the exact shift of every ω² by k/ρA wherever the
//! foundation's matrix is proportional to the mass (any support). The coupled
//! paths (point mass, springs, axial force, shear) are checked against the
//! state-space reference, a different algorithm on the same matrices.
//! Every tolerance is derived beside it.

use std::f64::consts::PI;

use nanobeam::beam::{
    buckling_load_n, modal, modal_state_space, BeamSpec, InternalVariable, ModalSolver, PointMass, ShearDeformation,
    SolverPath, Support,
};

/// The paper's short SWCNT (L/d = 8).
fn swcnt(support: Support, elements: usize) -> BeamSpec {
    BeamSpec::elastic(8.0, 1.0, 1e12, 2300.0, support, elements)
}

fn ei(b: &BeamSpec) -> f64 {
    b.youngs_modulus_pa * b.inertia_m4()
}

fn rho_a(b: &BeamSpec) -> f64 {
    b.density_kg_m3 * b.area_m2()
}

/// EI/L⁴ in N/m²: the foundation modulus's natural unit.
fn k_unit(b: &BeamSpec) -> f64 {
    ei(b) / (b.length_nm * 1e-9).powi(4)
}

/// The paper's short SWCNT with a relaxation (Δ = 0.3, Ω = 4e11 rad/s), the
/// given e0a, and the coupling extensions (shear κ = 0.9, viscous C, a point
/// mass 3e-26 kg at 2.9 nm, a support spring) the coupled-path tests vary.
fn coupled_beam(support: Support, e0a_nm: f64, (sh, c, mass, spring): (bool, f64, bool, f64)) -> BeamSpec {
    let mut b = swcnt(support, 12);
    b.nonlocal_e0a_nm = e0a_nm;
    b.viscous_damping_n_s_m2 = c;
    b.internal_variables = vec![InternalVariable { delta: 0.3, omega_rad_s: 4e11 }];
    b.shear_deformation = sh.then_some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: 0.9 });
    b.point_mass = mass.then_some(PointMass { mass_kg: 3e-26, x_nm: 2.9 });
    b.support_rotational_stiffness_n_m_rad = spring;
    b
}

/// Simply supported continuum: EI w⁗ + (1 − μ∂²)(ρA ẅ + k w) = 0, w = sin(αx).
fn closed_form_omega2(b: &BeamSpec, n: usize) -> f64 {
    let a = n as f64 * PI / (b.length_nm * 1e-9);
    let mu = (b.nonlocal_e0a_nm * 1e-9).powi(2);
    (ei(b) * a.powi(4) / (1.0 + mu * a * a) + b.elastic_foundation_n_m2) / rho_a(b)
}

/// Simply supported, elastic: the FE ω² against the closed form, for a
/// substrate and a gate's pull, local and nonlocal.
///
/// Tolerance: the foundation's matrix is k̃·M̃, so FE and continuum add the
/// same k/ρA to ω²; what remains is the bending part's Rayleigh–Ritz error,
/// λ_h − λ ∈ [0, (αh)⁴/720·λ_b] to leading order for cubic Hermite elements
/// (`tests/beam_axial_shear.rs` derives it; λ_b = EIα⁴/(ρA(1 + μα²))), with
/// a factor 2 for the O((αh)⁶) rest (αh ≤ 6π/30 < 1), and −1e-12·ω² below
/// for the round-off of the refined eigenvalues.
#[test]
fn simply_supported_foundation_matches_the_closed_form() {
    for e0a in [0.0, 1.2] {
        for k_rel in [-0.7, 0.3, 5.0, 200.0] {
            let mut b = swcnt(Support::SimplySupported, 30);
            b.nonlocal_e0a_nm = e0a;
            // in units of the free beam's k_cr = EIα₁⁴/(1 + μα₁²)
            let mut free = b.clone();
            free.elastic_foundation_n_m2 = 0.0;
            let k_cr = closed_form_omega2(&free, 1) * rho_a(&b);
            b.elastic_foundation_n_m2 = k_rel * k_cr;
            let w = modal(&b, 6).unwrap();
            for n in 1..=6 {
                let exact = closed_form_omega2(&b, n);
                let got = w.modes[n - 1].omega_rad_s.powi(2);
                let ah = n as f64 * PI / 30.0;
                let bending = closed_form_omega2(&free, n);
                let bound = 2.0 * ah.powi(4) / 720.0 * bending;
                let err = got - exact;
                assert!(
                    err > -1e-12 * exact && err < bound,
                    "e0a {e0a} k/k_cr {k_rel} mode {n}: ω² {got:e} vs {exact:e} (err {err:e}, bound {bound:e})"
                );
            }
        }
    }
}

/// Every support, with relaxation and damping, no point mass: the foundation
/// is k̃·M̃ exactly, so each family's constant term grows by k̃ and the
/// undamped ω² of the elastic beam by exactly k/ρA (to the eigen solve's
/// round-off, 1e-10 relative: the refined eigenvalues carry ~1e-12); with
/// relaxation and damping the decoupled fast path must agree with the
/// state-space reference on every pole to 1e-9 (its ~eps·κ(A) error,
/// `tests/beam_properties.rs`).
#[test]
fn the_foundation_shifts_every_omega_squared_by_k_over_rho_a_on_every_support() {
    for support in Support::ALL {
        let mut b = swcnt(support, 16);
        b.nonlocal_e0a_nm = 0.9;
        let free: Vec<f64> = modal(&b, 5).unwrap().modes.iter().map(|m| m.omega_rad_s).collect();
        for k_rel in [-0.4, 2.0, 50.0] {
            // relative to ρAω₁² of the free beam (stable for k_rel > −1)
            b.elastic_foundation_n_m2 = k_rel * rho_a(&b) * free[0] * free[0];
            let shift = b.elastic_foundation_n_m2 / rho_a(&b);
            let got = modal(&b, 5).unwrap();
            for (m, w0) in got.modes.iter().zip(&free) {
                let expected = w0 * w0 + shift;
                assert!(
                    (m.omega_rad_s.powi(2) / expected - 1.0).abs() < 1e-10,
                    "{support:?} k_rel {k_rel}: {:e} vs {expected:e}",
                    m.omega_rad_s.powi(2)
                );
            }
            let mut damped = b.clone();
            damped.viscous_damping_n_s_m2 = 3e-6;
            damped.internal_variables = vec![InternalVariable { delta: 0.3, omega_rad_s: 4e11 }];
            let mut solver = ModalSolver::new();
            let fast = solver.modal(&damped, 4).unwrap();
            assert_eq!(solver.last_path(), Some(SolverPath::Decoupled), "{support:?}");
            let reference = modal_state_space(&damped, 4).unwrap();
            for (f, r) in fast.modes.iter().zip(&reference.modes) {
                assert!((f.pole - r.pole).norm() <= 1e-9 * r.pole.norm(), "{support:?}: {f:?} vs {r:?}");
            }
        }
    }
}

/// The foundation with every coupling extension (point mass, springs, axial
/// force, shear, damping): the fast path the solver takes agrees with the
/// state-space reference to 1e-9 (as above), and a foundation that is zero
/// leaves every result bitwise as without the field.
#[test]
fn the_foundation_with_coupling_extensions_matches_the_state_space_reference() {
    let mut checked = 0;
    for support in Support::ALL {
        for (k_rel, axial, sh, c, mass, spring) in [
            (1.5, 0.0, false, 0.0, true, 0.0),
            (-0.3, 0.0, false, 2e-6, true, 0.0),
            (0.8, 0.3, false, 0.0, false, 0.0),
            (-0.2, -0.3, false, 2e-6, false, 3e-19),
            (2.0, 0.0, true, 0.0, false, 0.0),
            (-0.3, 0.2, true, 2e-6, true, 3e-19),
        ] {
            let mut b = coupled_beam(support, 0.9, (sh, c, mass, spring));
            let plain = modal(&b, 4).unwrap();
            let mut zero = b.clone();
            zero.elastic_foundation_n_m2 = 0.0;
            assert_eq!(modal(&zero, 4).unwrap(), plain);
            let w1 = plain.modes[0].omega_rad_s;
            b.elastic_foundation_n_m2 = k_rel * rho_a(&b) * w1 * w1;
            b.axial_force_n = axial * buckling_load_n(&b).unwrap().abs();
            let fast = ModalSolver::new().modal(&b, 4).unwrap();
            let reference = modal_state_space(&b, 4).unwrap();
            for (f, r) in fast.modes.iter().zip(&reference.modes) {
                assert!((f.pole - r.pole).norm() <= 1e-9 * r.pole.norm(), "{support:?}: {f:?} vs {r:?}\n{b:?}");
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 24);
}

/// A compression past the buckling load of the beam without its foundation,
/// held by the foundation (halfway between the two buckling loads): the
/// coupled path's start vectors come from the pencil with the foundation
/// (`beam::modal`, `held_by_foundation`), so no such beam takes the dense
/// state space, which it did on every solve before (a diagnosis near
/// buckling spent most of its time there, `tests/diagnose_near_buckling.rs`).
/// At e0a = 0.1 nm: at 0.9 nm the compressed Timoshenko mesh has families
/// whose pole lies above their relaxed order, which the numbering check
/// sends to the state space (`tests/beam_axial_shear.rs`,
/// `modes_near_buckling_are_numbered_by_frequency`).
/// The poles agree with the state-space reference to 1e-9 relative, the
/// bound of the test above (the state space's backward error ~eps·‖A‖ with
/// ‖A‖/|s₁| ≲ 1e4 on these 12-element meshes, and the RQI's stopping test).
#[test]
fn a_compression_the_foundation_holds_takes_the_coupled_path() {
    let mut checked = 0;
    for support in Support::ALL {
        for (sh, c, mass, spring) in [
            (true, 0.0, false, 0.0),
            (true, 2e-6, false, 0.0),
            (false, 2e-6, true, 0.0),
            (false, 0.0, false, 3e-19),
            (true, 0.0, true, 3e-19),
        ] {
            let mut b = coupled_beam(support, 0.1, (sh, c, mass, spring));
            let free = buckling_load_n(&b).unwrap();
            let w1 = modal(&b, 4).unwrap().modes[0].omega_rad_s;
            b.elastic_foundation_n_m2 = 0.5 * rho_a(&b) * w1 * w1;
            let held = buckling_load_n(&b).unwrap();
            assert!(held < free, "{support:?}: the foundation raises the buckling load");
            b.axial_force_n = 0.5 * (free + held);
            let mut solver = ModalSolver::new();
            let fast = solver.modal(&b, 4).unwrap();
            assert_ne!(solver.last_path(), Some(SolverPath::StateSpaceFallback), "{support:?}\n{b:?}");
            let reference = modal_state_space(&b, 4).unwrap();
            for (f, r) in fast.modes.iter().zip(&reference.modes) {
                assert!((f.pole - r.pole).norm() <= 1e-9 * r.pole.norm(), "{support:?}: {f:?} vs {r:?}\n{b:?}");
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 20);
}

/// The loss of stability: simply supported, the FE bound is a Rayleigh–Ritz
/// upper bound on λ₁ (error ≤ (π/20)⁴/720 ≈ 2e-7 relative at 20 elements,
/// as above), so k = −(1 − 1e-4)·k_cr of the continuum is stable and
/// −(1 + 1e-4)·k_cr is not; the error names the field and the bound. A
/// substrate raises the buckling load by exactly what it adds to K̃, and a
/// beam both pulled by a gate and compressed names the force.
#[test]
fn a_pulling_foundation_is_bounded_by_the_loss_of_stability() {
    for e0a in [0.0, 1.2] {
        let mut b = swcnt(Support::SimplySupported, 20);
        b.nonlocal_e0a_nm = e0a;
        let k_cr = closed_form_omega2(&b, 1) * rho_a(&b);
        b.elastic_foundation_n_m2 = -(1.0 - 1e-4) * k_cr;
        b.validate().unwrap();
        assert!(modal(&b, 3).unwrap().modes[0].omega_rad_s > 0.0);
        b.elastic_foundation_n_m2 = -(1.0 + 1e-4) * k_cr;
        let e = b.validate().unwrap_err().to_string();
        assert!(e.contains("elastic_foundation_n_m2") && e.contains("loss of stability"), "{e}");
        assert!(e.lines().count() == 1 && e.len() <= 200, "{e}");
    }
    // simply supported, local: mode r buckles at N = −(EIα_r² + k/α_r²),
    // lowest for r = 1 while k < 4EIα₁⁴ (k = 2EI/L⁴ here)
    let mut b = swcnt(Support::SimplySupported, 20);
    let a1 = PI / (b.length_nm * 1e-9);
    b.elastic_foundation_n_m2 = 2.0 * k_unit(&b);
    let expected = -(ei(&b) * a1 * a1 + b.elastic_foundation_n_m2 / (a1 * a1));
    let n_cr = buckling_load_n(&b).unwrap();
    // Rayleigh–Ritz again: |N_cr,h| ≥ |N_cr|, within (π/20)⁴/720 ≈ 2e-7 of it
    assert!(n_cr <= expected * (1.0 - 1e-12) && n_cr >= expected * (1.0 + 1e-6), "{n_cr:e} vs {expected:e}");
    b.axial_force_n = 1.01 * n_cr;
    let e = b.validate().unwrap_err().to_string();
    assert!(e.starts_with("invalid axial_force_n"), "{e}");
    // a gate's pull of half the free beam's k_cr halves the buckling load:
    // 0.6 of the free beam's is then too much, and the force is named
    let k_cr = ei(&b) * a1.powi(4);
    b.elastic_foundation_n_m2 = -0.5 * k_cr;
    b.axial_force_n = -0.6 * ei(&b) * a1 * a1;
    let e = b.validate().unwrap_err().to_string();
    assert!(e.starts_with("invalid axial_force_n"), "{e}");
    b.axial_force_n = -0.4 * ei(&b) * a1 * a1;
    b.validate().unwrap();
    // a pull past k_cr is named, whatever the force
    b.elastic_foundation_n_m2 = -1.5 * k_cr;
    let e = b.validate().unwrap_err().to_string();
    assert!(e.starts_with("invalid elastic_foundation_n_m2"), "{e}");
}
