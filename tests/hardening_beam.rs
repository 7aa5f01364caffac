//! Issue 11 (forward model): bounds that the solver handles at every corner,
//! physical mode numbers with overdamped modes, no dense hang, FRF range.

use std::time::{Duration, Instant};

use nanobeam::beam::spec::{
    MAX_C_TILDE, MAX_DELTA, MAX_ELEMENTS, MAX_E_TILDE, MAX_MASS_TILDE, MAX_SPRING_TILDE, OMEGA_TILDE_RANGE,
};
use nanobeam::beam::{
    frf, frf_each, max_frequency_rad_s, modal, modal_state_space, BeamError, BeamSpec, InternalVariable, ModalSolver,
    PointMass, SolverPath, Support, MAX_OMEGA_TILDE,
};

fn base(support: Support, elements: usize) -> BeamSpec {
    BeamSpec::elastic(8.0, 1.0, 1e12, 2300.0, support, elements)
}

/// (EI, ρA, ω_ref, L) of a beam, as `model.rs` forms them.
fn scales(b: &BeamSpec) -> (f64, f64, f64, f64) {
    let l = b.length_nm * 1e-9;
    let ei = b.youngs_modulus_pa * b.inertia_m4();
    let ra = b.density_kg_m3 * b.area_m2();
    (ei, ra, (ei / ra).sqrt() / (l * l), l)
}

/// Each dimensionless group at its bound (0.999 of it), alone, on every
/// support at the smallest and the largest mesh.
fn corner_beams() -> Vec<(String, BeamSpec)> {
    let f = 0.999;
    let mut out = Vec::new();
    for support in Support::ALL {
        for elements in [2, MAX_ELEMENTS] {
            let b = base(support, elements);
            let (ei, ra, w, l) = scales(&b);
            let mut v: Vec<(&str, BeamSpec)> = vec![("plain", b.clone())];
            let mut e = b.clone();
            e.nonlocal_e0a_nm = MAX_E_TILDE * b.length_nm * f;
            v.push(("e0a", e));
            for (name, om) in [("omega_max", OMEGA_TILDE_RANGE.1 * w * f), ("omega_min", OMEGA_TILDE_RANGE.0 * w / f)] {
                let mut e = b.clone();
                e.internal_variables = vec![InternalVariable { delta: MAX_DELTA * f, omega_rad_s: om }];
                v.push((name, e));
            }
            let mut e = b.clone();
            e.viscous_damping_n_s_m2 = MAX_C_TILDE * ra * w * f;
            v.push(("damping", e));
            let mut e = b.clone();
            e.support_rotational_stiffness_n_m_rad = MAX_SPRING_TILDE * ei / l * f;
            v.push(("spring", e));
            let mut e = b.clone();
            e.point_mass = Some(PointMass { mass_kg: MAX_MASS_TILDE * ra * l * f, x_nm: 2.4 });
            v.push(("mass", e));
            for (name, beam) in v {
                out.push((format!("{support:?}/{elements}/{name}"), beam));
            }
        }
    }
    out
}

#[test]
fn every_corner_of_the_allowed_range_gives_finite_modes_quickly() {
    for (name, beam) in corner_beams() {
        beam.validate().unwrap_or_else(|e| panic!("{name}: {e}"));
        let t = Instant::now();
        let r = modal(&beam, 2).unwrap_or_else(|e| panic!("{name}: {e}"));
        // the hang of issue 11 took > 200 s; a corner solve takes milliseconds
        assert!(t.elapsed() < Duration::from_secs(20), "{name}: {:?}", t.elapsed());
        assert_eq!(r.modes.len() + r.overdamped.len(), 2, "{name}");
        for m in &r.modes {
            assert!(m.omega_rad_s.is_finite() && m.omega_rad_s > 0.0 && m.zeta.is_finite(), "{name}: {m:?}");
        }
    }
}

#[test]
fn just_beyond_each_bound_is_refused_naming_the_field() {
    let b = base(Support::SimplySupported, 20);
    let (ei, ra, w, l) = scales(&b);
    let g = 1.01;
    let mut cases: Vec<(BeamSpec, &str)> = Vec::new();
    let mut e = b.clone();
    e.nonlocal_e0a_nm = MAX_E_TILDE * b.length_nm * g;
    cases.push((e, "nonlocal_e0a_nm"));
    let mut e = b.clone();
    e.internal_variables = vec![InternalVariable { delta: MAX_DELTA * g, omega_rad_s: w }];
    cases.push((e, "internal_variables[0].delta"));
    let mut e = b.clone();
    e.internal_variables = vec![InternalVariable { delta: 0.1, omega_rad_s: OMEGA_TILDE_RANGE.1 * w * g }];
    cases.push((e, "internal_variables[0].omega_rad_s"));
    let mut e = b.clone();
    e.viscous_damping_n_s_m2 = MAX_C_TILDE * ra * w * g;
    cases.push((e, "viscous_damping_n_s_m2"));
    let mut e = b.clone();
    e.support_rotational_stiffness_n_m_rad = MAX_SPRING_TILDE * ei / l * g;
    cases.push((e, "support_rotational_stiffness_n_m_rad"));
    let mut e = b.clone();
    e.point_mass = Some(PointMass { mass_kg: MAX_MASS_TILDE * ra * l * g, x_nm: 1.0 });
    cases.push((e, "point_mass.mass_kg"));
    for (v, field) in [(1e308, "length_nm"), (1e-300, "youngs_modulus_pa"), (1e300, "density_kg_m3")] {
        let mut e = b.clone();
        match field {
            "length_nm" => e.length_nm = v,
            "youngs_modulus_pa" => e.youngs_modulus_pa = v,
            _ => e.density_kg_m3 = v,
        }
        cases.push((e, field));
    }
    let mut e = b.clone();
    e.elements = MAX_ELEMENTS + 1;
    cases.push((e, "elements"));
    let mut e = base(Support::ClampedClamped, 1);
    e.elements = 1;
    cases.push((e, "elements"));
    let mut e = b.clone();
    e.internal_variables = vec![InternalVariable { delta: 0.1, omega_rad_s: w }; 17];
    cases.push((e, "internal_variables"));
    for (beam, field) in cases {
        let err = beam.validate().expect_err(field);
        assert_eq!(err.field, field, "{err}");
        assert!(err.to_string().len() < 300, "message too long: {err}");
    }
}

#[test]
fn the_largest_mesh_stays_on_the_banded_path() {
    for support in Support::ALL {
        let mut b = base(support, MAX_ELEMENTS);
        b.nonlocal_e0a_nm = 1.2;
        b.internal_variables = vec![InternalVariable { delta: 0.4, omega_rad_s: 4.5e11 }];
        let mut solver = ModalSolver::new();
        let t = Instant::now();
        solver.modal(&b, 6).unwrap();
        assert_ne!(solver.last_path(), Some(SolverPath::StateSpaceFallback), "{support:?}");
        assert!(t.elapsed() < Duration::from_secs(20), "{support:?}: {:?}", t.elapsed());
    }
}

#[test]
fn the_dense_reference_refuses_large_models_instead_of_hanging() {
    let mut b = base(Support::SimplySupported, MAX_ELEMENTS);
    b.internal_variables = vec![InternalVariable { delta: 0.4, omega_rad_s: 4.5e11 }];
    let t = Instant::now();
    assert!(matches!(modal_state_space(&b, 3), Err(BeamError::Numerical(_))));
    assert!(t.elapsed() < Duration::from_secs(5));
}

/// A beam whose first mode is overdamped (c̃ ≈ 55 > 2√λ₁ ≈ 19.7) and whose
/// modes 2 and 3 are not (2√λ₂ ≈ 79).
fn overdamped_first_mode() -> BeamSpec {
    let mut b = base(Support::SimplySupported, 20);
    b.viscous_damping_n_s_m2 = 1e-2;
    b
}

#[test]
fn an_overdamped_mode_keeps_its_number_and_reports_its_real_poles() {
    let b = overdamped_first_mode();
    let r = modal(&b, 3).unwrap();
    assert_eq!(r.overdamped.len(), 1);
    assert_eq!(r.overdamped[0].mode, 1);
    assert_eq!(r.overdamped[0].poles_rad_s.len(), 2);
    assert!(r.overdamped[0].poles_rad_s.iter().all(|p| *p < 0.0));
    assert_eq!(r.modes.iter().map(|m| m.mode).collect::<Vec<_>>(), vec![2, 3]);
    assert!(r.mode(1).is_none() && r.mode(2).is_some());
    // the same physical numbers from the state-space reference; poles agree to
    // the 1e-9 relative that both exact paths reach (see tests/beam_properties.rs)
    let s = modal_state_space(&b, 3).unwrap();
    assert_eq!(s.overdamped.iter().map(|o| o.mode).collect::<Vec<_>>(), vec![1]);
    for (a, c) in r.modes.iter().zip(&s.modes) {
        assert_eq!(a.mode, c.mode);
        assert!((a.pole - c.pole).norm() <= 1e-9 * a.pole.norm(), "{a:?} vs {c:?}");
    }
    // without damping mode 1 is the same physical mode, now oscillatory
    let mut undamped = b.clone();
    undamped.viscous_damping_n_s_m2 = 0.0;
    let u = modal(&undamped, 3).unwrap();
    assert!(u.overdamped.is_empty());
    assert!((u.modes[1].omega_rad_s - r.modes[0].omega_rad_s).abs() <= 1e-9 * u.modes[1].omega_rad_s);
}

#[test]
fn streamed_frf_equals_the_collected_one_and_the_range_is_checked() {
    let mut b = base(Support::ClampedFree, 20);
    b.internal_variables = vec![InternalVariable { delta: 0.4, omega_rad_s: 4.5e11 }];
    let omegas: Vec<f64> = (0..50).map(|i| 1e10 * 1.2f64.powi(i)).collect();
    let collected = frf(&b, 3.0, 8.0, &omegas).unwrap();
    let mut streamed = Vec::new();
    frf_each(&b, 3.0, 8.0, omegas.iter().copied(), |_, h| {
        streamed.push(h);
        Ok(())
    })
    .unwrap();
    assert_eq!(collected, streamed);
    let max_w = max_frequency_rad_s(&b).unwrap();
    let (_, _, w, _) = scales(&b);
    assert!((max_w / (MAX_OMEGA_TILDE * w) - 1.0).abs() < 1e-12);
    // the largest allowed frequency gives a finite receptance (no overflow)
    assert!(frf(&b, 3.0, 8.0, &[max_w]).unwrap()[0].is_finite());
    match frf(&b, 3.0, 8.0, &[1e11, max_w * 2.0]) {
        Err(BeamError::Input(e)) => assert_eq!(e.field, "omega_rad_s[1]"),
        other => panic!("{other:?}"),
    }
}
