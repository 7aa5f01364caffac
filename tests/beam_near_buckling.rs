//! The coupled path near buckling (issue 44, defect 9): with the axial force
//! at 0.99–0.9999 of the beam's own buckling load, the terms of the Rayleigh
//! functional cancel (k_s + G·k ≈ 0) and its Newton steps stay at their
//! round-off, above the relative stop; the solver used to give up and fall
//! back to the dense state space (1.4–15 ms a solve against ≈ 50 µs). These
//! are the complex-pole cases a scan of 360 such beams found falling back
//! (`tests/hardening_round2.md`); each must now stay on the RQI path, with
//! the oscillatory poles of the state space (the reference, `state_space_modal`,
//! another method on the same discretisation).
//!
//! Tolerance: ω̃₁² = λ₁ ∝ (1 − f), so an absolute error δ in an eigenvalue
//! of the scaled state space (backward error ≈ eps·‖A‖, ‖A‖ ≈ ω̃_max² of the
//! mesh: ≈ 1e5 for 20 elements) is a relative error ≈ δ/(2 ω̃₁²) in ω₁:
//! 1e-16·1e5/(2·1e-4·π⁴) ≈ 3e-10 at 1 − f = 1e-4 before the balancing's and
//! Schur's own growth; the test allows 1e-6 relative in ω and 1e-6 absolute
//! (relative to max(ζ, 1)) in ζ, far above both and far below any physical
//! difference.

use nanobeam::beam::{buckling_load_n, modal_state_space, BeamSpec, InternalVariable, ModalSolver, SolverPath};

fn beam(f: f64, delta: f64, omega_rad_s: f64, c: f64) -> BeamSpec {
    let mut b: BeamSpec = serde_yaml::from_str(
        "{ length_nm: 8.0, diameter_nm: 1.0, youngs_modulus_pa: 1.0e12, density_kg_m3: 2300.0, \
         support: simply-supported, elements: 20 }",
    )
    .unwrap();
    if delta > 0.0 {
        b.internal_variables = vec![InternalVariable { delta, omega_rad_s }];
    }
    b.viscous_damping_n_s_m2 = c;
    b.axial_force_n = f * buckling_load_n(&b).unwrap();
    b
}

#[test]
fn near_buckling_the_coupled_path_keeps_its_complex_poles() {
    let cases = [
        (0.99, 0.05, 1e9, 0.0),
        (0.999, 0.4, 4.5e11, 1e-4),
        (0.9999, 0.0, 1e9, 1e-4),
        (0.9999, 0.0, 1e11, 1e-2),
        (0.9999, 0.05, 1e12, 0.0),
        (0.9999, 0.4, 4.5e11, 0.0),
        (0.9999, 0.4, 1e12, 0.0),
        (0.9999, 2.0, 1e10, 1e-2),
        (0.99999, 2.0, 1e12, 0.0),
    ];
    for (f, d, w, c) in cases {
        let b = beam(f, d, w, c);
        // the coupled path itself: a simply supported beam with a force now takes
        // the wavenumber-block path by default (`beam/axial_spectrum.rs`)
        let mut solver = ModalSolver::direct_only();
        let got = solver.modal(&b, 3).unwrap();
        let reference = modal_state_space(&b, 3).unwrap();
        let case = format!("f {f}, delta {d}, omega {w:e}, c {c}");
        // every family's complex poles found by RQI (real poles of an
        // overdamped first mode may still go to the state space: see the record)
        let path = solver.last_path();
        let oscillatory =
            |r: &nanobeam::beam::ModalResult| r.modes.iter().map(|m| (m.omega_rad_s, m.zeta)).collect::<Vec<_>>();
        let mut observables = vec![0.0; 6];
        let mut obs_solver = ModalSolver::direct_only();
        obs_solver.observables(&b, &[1, 2, 3], 3, &mut observables).unwrap();
        assert_eq!(obs_solver.last_path(), Some(SolverPath::CoupledRqi), "{case}: observables fell back");
        assert_eq!(oscillatory(&got).len(), oscillatory(&reference).len(), "{case}: {path:?}");
        for ((w1, z1), (w0, z0)) in oscillatory(&got).into_iter().zip(oscillatory(&reference)) {
            assert!(((w1 - w0) / w0).abs() < 1e-6, "{case}: omega {w1} vs {w0}");
            assert!((z1 - z0).abs() < 1e-6 * z0.abs().max(1.0), "{case}: zeta {z1} vs {z0}");
        }
    }
}
