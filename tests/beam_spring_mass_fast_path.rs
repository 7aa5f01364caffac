//! Issue 41: the exact fast path of support springs and a point mass together
//! on the simply supported Euler–Bernoulli beam without an axial force
//! (`beam/spring_mass.rs`: a secular determinant of order ≤ 3 over the
//! beam's whole spring- and mass-free spectrum) against the paths it
//! replaces, which stay the reference: the coupled nonlinear RQI on the whole
//! assembled T̃(s) (`ModalSolver::direct_only`, `coupled.rs`) and the dense
//! state space (`modal_state_space`).
//!
//! Data: generated here (ChaCha8 streams, seeds in each test) over the hidden
//! suite's nominal beam (L = 8 nm, d = 1 nm, E = 1 TPa, ρ = 2300 kg/m³) and
//! the priors of the `support-rotational-stiffness + attached-mass` pair
//! (`diagnose::classes`): each end's κ = kL/EI log-uniform on [1e-2, 1e3],
//! one end or both (`fast_path_check::random_springs`), μ̃ = m/(ρAL)
//! log-uniform on [1e-3, 1], x ~ U[0, L], e0a ∈ [0, 2] nm, solid or tube
//! section, viscous C up to ζ ≈ 0.3 on mode 1 on half the beams, 0–2 internal
//! variables, 10–40 elements, odd meshes included.
//!
//! Tolerances (derived). Both paths solve the same FE model; the reference's
//! poles round to ≤ 1e-12 relative (`beam::modal`'s refinement test). The fast
//! path's block entries carry ≤ 1.4e-12 (the bending eigenvalue at n_e = 40,
//! j = 1, `tests/beam_axial_fast_path.rs`); its block eigenvectors, normalised
//! in M, round to a few eps over their eigenvalues' relative gap (≥ 1e-2,
//! so ≲ 1e-13), and the root is at Newton's floor. So a pole agrees to
//! [`S_TOL`] = 4e-12 relative, ω = |s| likewise and ζ to 2·S_TOL absolute,
//! the tolerance of the spring and point-mass paths' suites. No axial force,
//! so no compression gain. The dense state space is accurate to ≲ 1e-9
//! relative on 10-element meshes (`tests/beam_axial_fast_path.rs`),
//! compared at [`STATE_SPACE_TOL`] = 1e-7.

mod fast_path_check;

use fast_path_check::{
    assert_agrees_with_the_coupled_reference, assert_agrees_with_the_state_space,
    assert_same_bits_at_one_and_two_threads_and_after_any_history, random_nominal_beam, random_relaxations,
    random_springs, L_NM,
};
use nanobeam::beam::{BeamSpec, InternalVariable, ModalSolver, PointMass, ShearDeformation, Support};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative tolerance on a pole against the coupled RQI reference (module doc).
const S_TOL: f64 = 4e-12;
/// Relative tolerance against the dense state space (module doc).
const STATE_SPACE_TOL: f64 = 1e-7;

fn random_beam(rng: &mut ChaCha8Rng) -> BeamSpec {
    let elements = [10, 15, 20, 20, 40][rng.gen_range(0..5)];
    let mut b = random_nominal_beam(rng, elements);
    random_springs(rng, &mut b);
    let rho_a = b.density_kg_m3 * b.area_m2();
    let mu = 10f64.powf(rng.gen_range(-3.0..0.0));
    b.point_mass = Some(PointMass { mass_kg: mu * rho_a * L_NM * 1e-9, x_nm: rng.gen_range(0.0..L_NM) });
    if rng.gen_bool(0.5) {
        // C up to ≈ 2ζω₁ρA with ζ ≈ 0.3 on mode 1 of the nominal beam (ω₁ ≈ 8e11 rad/s)
        b.viscous_damping_n_s_m2 = rng.gen_range(0.01..0.6) * 8e11 * rho_a;
    }
    b.internal_variables = random_relaxations(rng);
    b
}

/// 300 random beams: the fast path is taken by `observables` on every one
/// and by `modal` on those without internal variables (with them `modal`
/// reports real relaxation poles, left to the reference); ω and ζ of modes
/// 1–5 agree with the coupled RQI reference within [`S_TOL`].
#[test]
fn random_beams_agree_with_the_coupled_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(4161);
    let beams: Vec<BeamSpec> = (0..300).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_coupled_reference(
        &beams,
        ModalSolver::new(),
        ModalSolver::last_used_spring_mass_blocks,
        |_| S_TOL,
        "spring + point-mass path",
    );
}

/// 40 random beams against the dense state space (independent of both the
/// secular determinant and the RQI): ω and ζ of modes 1–4 within
/// [`STATE_SPACE_TOL`] (`observables`, internal variables included).
#[test]
fn random_beams_agree_with_the_state_space() {
    let mut rng = ChaCha8Rng::seed_from_u64(4162);
    let beams: Vec<BeamSpec> = (0..40).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_state_space::<4>(
        beams,
        ModalSolver::new(),
        ModalSolver::last_used_spring_mass_blocks,
        STATE_SPACE_TOL,
        "spring + point-mass path",
    );
}

/// The path is taken only on its hypotheses: a simply supported
/// Euler–Bernoulli mesh with a spring and a point mass and no axial force.
/// An axial force, clamped–pinned, no spring, no mass, shear deformation and
/// `modal` with real relaxation poles all go elsewhere.
#[test]
fn the_path_declines_off_its_hypotheses() {
    let mut b = BeamSpec::elastic(L_NM, 1.0, 1e12, 2300.0, Support::SimplySupported, 20);
    b.point_mass = Some(PointMass { mass_kg: 3e-26, x_nm: 2.9 });
    b.support_rotational_stiffness_left_n_m_rad = 1e-9;
    b.nonlocal_e0a_nm = 0.7;
    let mut solver = ModalSolver::new();
    solver.modal(&b, 4).unwrap();
    assert!(solver.last_used_spring_mass_blocks());
    let mut out = [0.0; 8];
    for (what, v) in [
        ("axial force", BeamSpec { axial_force_n: 1e-9, ..b.clone() }),
        (
            "clamped-pinned",
            BeamSpec {
                support: Support::ClampedPinned,
                support_rotational_stiffness_left_n_m_rad: 0.0,
                support_rotational_stiffness_right_n_m_rad: 1e-9,
                ..b.clone()
            },
        ),
        ("no spring", BeamSpec { support_rotational_stiffness_left_n_m_rad: 0.0, ..b.clone() }),
        ("no mass", BeamSpec { point_mass: None, ..b.clone() }),
        (
            "shear",
            BeamSpec {
                shear_deformation: Some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: 0.8 }),
                ..b.clone()
            },
        ),
    ] {
        solver.observables(&v, &[1, 2, 3, 4], 4, &mut out).unwrap();
        assert!(!solver.last_used_spring_mass_blocks(), "{what}");
    }
    let mut relax = b.clone();
    relax.internal_variables = vec![InternalVariable { delta: 0.3, omega_rad_s: 4e11 }];
    solver.modal(&relax, 4).unwrap();
    assert!(!solver.last_used_spring_mass_blocks(), "modal with relaxation poles");
    solver.observables(&relax, &[1, 2, 3, 4], 4, &mut out).unwrap();
    assert!(solver.last_used_spring_mass_blocks(), "observables with relaxation");
}

/// Same bits from two threads as from one, and whatever the solver saw
/// before: the path is a function of its input alone.
#[test]
fn same_bits_at_one_and_two_threads_and_after_any_history() {
    let mut rng = ChaCha8Rng::seed_from_u64(4163);
    let beams: Vec<BeamSpec> = (0..40).map(|_| random_beam(&mut rng)).collect();
    assert_same_bits_at_one_and_two_threads_and_after_any_history(&beams, ModalSolver::new);
}
