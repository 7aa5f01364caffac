//! Issue 15: the interpolated fast path of the decoupled model.
//!
//! * every (mesh, mode, e0a piece) interpolant over the whole valid range
//!   (e0a/L ≤ 10) is certified: its measured error bound is ≤ 1e-12 relative
//!   against the direct banded solve;
//! * random points (never Chebyshev or check points) agree with the direct
//!   solve to the certified bound;
//! * the modal results through the interpolant agree with the direct path and do
//!   not depend on what a solver evaluated before.

use nanobeam::beam::{
    direct_eigenvalues, interpolated_eigenvalues, spectrum_certificates, BeamSpec, InternalVariable, ModalSolver,
    Support, CERTIFIED_TOL,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const MAX_E_TILDE: f64 = nanobeam::beam::spec::MAX_E_TILDE;

#[test]
fn every_piece_of_the_valid_range_is_certified() {
    for elements in [20, 7] {
        for support in Support::ALL {
            let certs = spectrum_certificates(elements, support, 6, MAX_E_TILDE * MAX_E_TILDE);
            let mut degrees = Vec::new();
            let mut worst = 0.0f64;
            for c in &certs {
                let c = c.unwrap_or_else(|| panic!("{elements} elements {support:?}: a piece is not certified"));
                assert!(c.bound() <= CERTIFIED_TOL, "{c:?}");
                degrees.push(c.degree);
                worst = worst.max(c.bound());
            }
            assert!(certs.last().unwrap().unwrap().t_hi >= MAX_E_TILDE * MAX_E_TILDE);
            println!(
                "{elements:>3} {support:?}: {} interpolants, degrees {degrees:?}, worst bound {worst:.2e}",
                certs.len()
            );
        }
    }
}

/// 4000 random (support, e0a/L) points, e0a/L log-uniform over [1e-4, 10] plus
/// exact zeros: the interpolated eigenvalues of modes 1–6 agree with the direct
/// solve within the certified 1e-12 (relative). The check is against the same
/// direct solve as the certification, at points it never saw.
#[test]
fn random_points_agree_with_the_direct_solve() {
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    let mut worst = 0.0f64;
    for i in 0..4000 {
        let support = Support::ALL[rng.gen_range(0..4)];
        let e_tilde = if i % 100 == 0 { 0.0 } else { 10f64.powf(rng.gen_range(-4.0..1.0)) };
        let fast = interpolated_eigenvalues(20, support, e_tilde, 6).expect("inside the certified range");
        let direct = direct_eigenvalues(20, support, e_tilde, 6).unwrap();
        for (f, d) in fast.iter().zip(&direct) {
            let rel = (f - d).abs() / d;
            worst = worst.max(rel);
            assert!(rel <= CERTIFIED_TOL, "{support:?} e0a/L = {e_tilde}: {f} vs {d} ({rel:.2e})");
        }
    }
    println!("worst relative difference at 4000 random points: {worst:.2e}");
}

fn beam(support: Support, e0a_nm: f64, c: f64, ivs: &[(f64, f64)]) -> BeamSpec {
    BeamSpec {
        nonlocal_e0a_nm: e0a_nm,
        viscous_damping_n_s_m2: c,
        internal_variables: ivs.iter().map(|&(delta, omega_rad_s)| InternalVariable { delta, omega_rad_s }).collect(),
        ..BeamSpec::elastic(8.0, 1.0, 1e12, 2300.0, support, 20)
    }
}

/// Modal results through the interpolant vs the direct path (both
/// `SolverPath::Decoupled`). The eigenvalues differ by ≤ 1e-12 relative
/// (certified) plus the direct path's own RQI rounding (~1e-14); a pole moves
/// by |d ln s/d ln λ| ≤ 1 times that (s² + cs + λG(s) = 0: for the lightly and
/// moderately damped modes here the factor is ≈ ½), so ω agrees to 2e-12
/// relative and ζ to 2e-12 absolute.
#[test]
fn modal_results_match_the_direct_path() {
    let mut rng = ChaCha8Rng::seed_from_u64(1515);
    let mut fast = ModalSolver::new();
    let mut direct = ModalSolver::direct_only();
    for _ in 0..500 {
        let support = Support::ALL[rng.gen_range(0..4)];
        let n_iv = rng.gen_range(0..=3);
        let ivs: Vec<(f64, f64)> =
            (0..n_iv).map(|_| (rng.gen_range(0.0..0.8), 10f64.powf(rng.gen_range(10.5..13.0)))).collect();
        let b = beam(support, rng.gen_range(0.0..2.5), rng.gen_range(0.0..2e-5), &ivs);
        let a = fast.modal(&b, 4).unwrap();
        assert!(fast.last_used_interpolant(), "{b:?}");
        let r = direct.modal(&b, 4).unwrap();
        assert!(!direct.last_used_interpolant());
        assert_eq!(a.modes.len(), r.modes.len(), "{b:?}");
        for (x, y) in a.modes.iter().zip(&r.modes) {
            assert_eq!(x.mode, y.mode);
            assert!((x.omega_rad_s - y.omega_rad_s).abs() <= 2e-12 * y.omega_rad_s, "{b:?}: {x:?} vs {y:?}");
            assert!((x.zeta - y.zeta).abs() <= 2e-12, "{b:?}: {x:?} vs {y:?}");
        }
    }
}

/// The invariant: a solver that saw other beams (other e0a pieces, other
/// meshes, other mode counts) returns the bits a fresh solver returns.
#[test]
fn results_do_not_depend_on_evaluation_history() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let mut shared = ModalSolver::new();
    for _ in 0..300 {
        let support = Support::ALL[rng.gen_range(0..4)];
        let mut b = beam(support, 10f64.powf(rng.gen_range(-3.0..1.5)), 1e-6, &[(0.4, 3e11)]);
        b.elements = [20, 12][rng.gen_range(0..2)];
        let n = rng.gen_range(1..=6);
        let seen = shared.modal(&b, n).unwrap();
        let fresh = ModalSolver::new().modal(&b, n).unwrap();
        assert_eq!(seen, fresh, "{b:?}");
    }
}

/// Outside the fast paths' scope (a point mass with viscous damping, which
/// couples the modes; e0a/L beyond the range is refused by validation) the
/// direct path answers. A point mass without damping has its own fast path
/// (`tests/beam_point_mass_fast_path.rs`).
#[test]
fn extensions_take_the_direct_path() {
    let mut b = beam(Support::SimplySupported, 1.0, 1e-6, &[(0.4, 3e11)]);
    b.point_mass = Some(nanobeam::beam::PointMass { mass_kg: 3e-26, x_nm: 2.9 });
    let mut s = ModalSolver::new();
    s.modal(&b, 3).unwrap();
    assert!(!s.last_used_interpolant());
    b.viscous_damping_n_s_m2 = 0.0;
    s.modal(&b, 3).unwrap();
    assert!(s.last_used_interpolant());
}

/// `ModalSolver::observables` (what the calibration posterior calls) gives
/// the bits of `modal(..).mode(m)` on every path: interpolated, direct (a
/// support spring), overdamped modes (`false`), modes beyond `n_modes`.
#[test]
fn observables_equal_the_modal_result() {
    let mut rng = ChaCha8Rng::seed_from_u64(1516);
    let mut solver = ModalSolver::new();
    let (mut checked, mut refused) = (0, 0);
    for i in 0..400 {
        let support = Support::ALL[rng.gen_range(0..4)];
        let n_iv = rng.gen_range(0..=2);
        let ivs: Vec<(f64, f64)> =
            (0..n_iv).map(|_| (rng.gen_range(0.0..0.8), 10f64.powf(rng.gen_range(10.5..13.0)))).collect();
        // every 4th beam heavily damped (overdamped low modes), every 5th with a spring
        let c = if i % 4 == 0 { rng.gen_range(1e-4..1e-2) } else { rng.gen_range(0.0..2e-5) };
        let mut b = beam(support, rng.gen_range(0.0..2.5), c, &ivs);
        if i % 5 == 0 {
            b.support_rotational_stiffness_n_m_rad = 1e-18;
        }
        let n_modes = rng.gen_range(1..=4);
        let modes: Vec<usize> = (1..=n_modes).filter(|_| rng.gen_bool(0.7)).collect();
        let reference = ModalSolver::new().modal(&b, n_modes).unwrap();
        let mut out = vec![0.0; 2 * modes.len()];
        let ok = solver.observables(&b, &modes, n_modes, &mut out).unwrap();
        let expected: Option<Vec<f64>> = modes
            .iter()
            .map(|&m| reference.mode(m).map(|x| x.omega_rad_s))
            .chain(modes.iter().map(|&m| reference.mode(m).map(|x| x.zeta)))
            .collect();
        match expected {
            Some(e) if solver.last_used_spring_blocks() && !b.internal_variables.is_empty() => {
                // a simply supported spring beam with internal variables: `observables`
                // takes the secular path (`beam/spring_spectrum.rs`), `modal` the coupled
                // RQI (its real poles): equal to the 4e-12 relative that
                // `tests/beam_spring_fast_path.rs` derives, not bitwise
                assert!(ok, "{b:?} {modes:?}");
                let m = modes.len();
                for k in 0..m {
                    assert!((out[k] - e[k]).abs() <= 4e-12 * e[k], "{b:?}: ω {} vs {}", out[k], e[k]);
                    assert!((out[m + k] - e[m + k]).abs() <= 8e-12, "{b:?}: ζ {} vs {}", out[m + k], e[m + k]);
                }
                checked += 1;
            }
            Some(e) => {
                assert!(ok, "{b:?} {modes:?}");
                assert_eq!(
                    out.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    e.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    "{b:?}"
                );
                checked += 1;
            }
            None => {
                assert!(!ok, "{b:?} {modes:?}");
                refused += 1;
            }
        }
    }
    assert!(checked > 100 && refused > 0, "checked {checked}, refused {refused}");
}
