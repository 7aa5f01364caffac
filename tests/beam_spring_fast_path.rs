//! Issue 41: the exact support-spring fast path of the simply supported
//! Euler–Bernoulli beam (`beam/spring_spectrum.rs`: the springs a rank ≤ 2
//! update of the wavenumber-block pencil, a 1 × 1 or 2 × 2 secular
//! determinant per pole) against the paths it replaces, which stay the
//! reference: the coupled nonlinear RQI on the whole assembled T̃(s)
//! (`ModalSolver::direct_only`, `coupled.rs`) and the dense state space
//! (`modal_state_space`).
//!
//! Data: generated here (ChaCha8 streams, seeds in each test) over the hidden
//! suite's nominal beam (L = 8 nm, d = 1 nm, E = 1 TPa, ρ = 2300 kg/m³,
//! `diagnose::synthetic`) and the priors of the support-rotational-stiffness
//! model and its pairs: each end's κ = kL/EI log-uniform on [1e-2, 1e3]
//! (`diagnose::classes::END_SPRING_RANGE`), one end or both, e0a ∈ [0, 2] nm,
//! viscous C = 0 or up to ζ ≈ 0.3 on mode 1, 0–2 internal variables
//! (Δ ∈ [0.05, 0.6], Ω ∈ [3e10, 3e12] rad/s), solid or tube section, an axial
//! force on a third of the beams (N/|N_cr| ∈ [−0.9, 100], N_cr of the beam with
//! its springs), 10–40 elements.
//!
//! Tolerances (derived). Both paths solve the same FE model. The reference's
//! poles are roots of Rayleigh functionals of converged vectors, rounding
//! ≤ 1e-12 relative (`beam::modal`'s refinement test: Rayleigh quotients
//! from element energies ~1e-14, with a 100× margin). The fast path's block
//! entries carry the bending eigenvalue's rounding ≲ 10·eps/sin²(φ/2) ≤
//! 1.4e-12 at n_e = 40, j = 1 (`tests/beam_axial_fast_path.rs`); its root of
//! the secular g(s) is at Newton's floor (quadratic stop at 1e-10 step); the
//! determinant det B_j of a block next to the root loses
//! ~eps·|B_uu B_vv|/|det B_j| ≤ eps·cond(B_j) ≲ eps·(λ_up/λ_low) ≈
//! 2.2e-16·(2n_e/π)² ≤ 1.4e-12 relative at n_e = 40 (the rotation branch
//! over the bending one of block 1). A pole s then agrees to
//! [`S_TOL`] = 1e-12 + 1.4e-12 + 1.4e-12 ≈ 4e-12 relative, ω = |s| likewise,
//! ζ = −Re s/|s| to 2·S_TOL absolute (|dζ| ≤ 2|ds|/|s|); under compression both
//! sides' rounding is amplified by the cancellation λ = λ_K − |λ_N|
//! (`compression_gain`). The dense state space is accurate to ~eps·cond(A) of
//! its (2n + Nn)-dimensional eigenproblem: ≲ 1e-9 relative on 10-element
//! meshes (measured in `tests/beam_axial_fast_path.rs`), compared at
//! [`STATE_SPACE_TOL`] = 1e-7.

mod fast_path_check;

use fast_path_check::{
    assert_agrees_with_the_coupled_reference, assert_agrees_with_the_state_space,
    assert_same_bits_at_one_and_two_threads_and_after_any_history, compression_gain, random_axial, random_nominal_beam,
    random_relaxations, random_springs, random_viscous, L_NM,
};
use nanobeam::beam::{buckling_load_n, BeamSpec, InternalVariable, ModalSolver, PointMass, ShearDeformation, Support};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative tolerance on a pole against the coupled RQI reference (module doc).
const S_TOL: f64 = 4e-12;
/// Relative tolerance against the dense state space (module doc).
const STATE_SPACE_TOL: f64 = 1e-7;

fn random_beam(rng: &mut ChaCha8Rng) -> BeamSpec {
    let elements = [10, 20, 20, 20, 40][rng.gen_range(0..5)];
    let mut b = random_nominal_beam(rng, elements);
    random_springs(rng, &mut b);
    if rng.gen_bool(0.3) {
        let ncr = buckling_load_n(&b).unwrap().abs();
        b.axial_force_n = random_axial(rng, ncr);
    }
    if rng.gen_bool(0.5) {
        b.viscous_damping_n_s_m2 = random_viscous(rng, &b, 0.0);
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
    let mut rng = ChaCha8Rng::seed_from_u64(4121);
    let beams: Vec<BeamSpec> = (0..300).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_coupled_reference(
        &beams,
        ModalSolver::new(),
        ModalSolver::last_used_spring_blocks,
        |b| S_TOL * compression_gain(b),
        "spring fast path",
    );
}

/// 40 random beams against the dense state space (independent of both the
/// secular equation and the RQI): ω and ζ of modes 1–4 within
/// [`STATE_SPACE_TOL`] (`observables`, internal variables included).
#[test]
fn random_beams_agree_with_the_state_space() {
    let mut rng = ChaCha8Rng::seed_from_u64(4122);
    let beams: Vec<BeamSpec> = (0..40).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_state_space::<4>(
        beams,
        ModalSolver::new(),
        ModalSolver::last_used_spring_blocks,
        STATE_SPACE_TOL,
        "spring fast path",
    );
}

/// The path is taken only on its hypotheses: a simply supported
/// Euler–Bernoulli mesh, no point mass, a spring that acts. Clamped–pinned
/// (a spring at x = L, but no wavenumber split), a point mass, shear
/// deformation and `modal` with real relaxation poles all run the reference.
#[test]
fn the_path_declines_off_its_hypotheses() {
    let mut b = BeamSpec::elastic(L_NM, 1.0, 1e12, 2300.0, Support::SimplySupported, 20);
    b.support_rotational_stiffness_n_m_rad = 1e-9;
    b.nonlocal_e0a_nm = 0.7;
    let mut solver = ModalSolver::new();
    solver.modal(&b, 4).unwrap();
    assert!(solver.last_used_spring_blocks());
    let mut out = [0.0; 8];
    for (what, v) in [
        ("clamped-pinned", BeamSpec { support: Support::ClampedPinned, ..b.clone() }),
        ("point mass", BeamSpec { point_mass: Some(PointMass { mass_kg: 3e-26, x_nm: 2.9 }), ..b.clone() }),
        (
            "shear",
            BeamSpec {
                shear_deformation: Some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: 0.8 }),
                ..b.clone()
            },
        ),
    ] {
        solver.observables(&v, &[1, 2, 3, 4], 4, &mut out).unwrap();
        assert!(!solver.last_used_spring_blocks(), "{what}");
    }
    let mut relax = b.clone();
    relax.internal_variables = vec![InternalVariable { delta: 0.3, omega_rad_s: 4e11 }];
    solver.modal(&relax, 4).unwrap();
    assert!(!solver.last_used_spring_blocks(), "modal with relaxation poles");
    solver.observables(&relax, &[1, 2, 3, 4], 4, &mut out).unwrap();
    assert!(solver.last_used_spring_blocks(), "observables with relaxation");
}

/// Same bits from two threads as from one, and whatever the solver saw
/// before: the path is a function of its input alone.
#[test]
fn same_bits_at_one_and_two_threads_and_after_any_history() {
    let mut rng = ChaCha8Rng::seed_from_u64(4123);
    let beams: Vec<BeamSpec> = (0..40).map(|_| random_beam(&mut rng)).collect();
    assert_same_bits_at_one_and_two_threads_and_after_any_history(&beams, ModalSolver::new);
}
