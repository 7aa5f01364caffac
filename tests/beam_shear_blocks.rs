//! Issue 41: the exact bordered wavenumber-block fast path of the simply
//! supported Timoshenko beam (`beam/shear_blocks.rs`: the mesh is the mirror
//! mesh, split exactly into 5 × 5 blocks, bordered by χ₀, χ_L, s_L; the poles
//! are roots of a small bordered determinant evaluated in O(n_e)) against the
//! paths it replaces, which stay the reference: the coupled nonlinear RQI on
//! the whole assembled T̃(s) (`ModalSolver::direct_only`, `coupled.rs`) and the
//! dense state space (`modal_state_space`).
//!
//! Data: generated here (ChaCha8 streams, seeds in each test) over the hidden
//! suite's nominal beam (L = 8 nm, d = 1 nm, E = 1 TPa, ρ = 2300 kg/m³,
//! `diagnose::synthetic`) with shear deformation (κ ∈ [0.3, 1], the prior of
//! `diagnose::classes`; ν ∈ [0.1, 0.35]) and what the path covers: a
//! tension (N/|N_cr| ∈ (0, 100]; a compression drawn from [−0.9, 0) becomes
//! damping, since 2026-12-08) and/or viscous C up to ζ ≈ 0.3 on mode 1,
//! 0–2 internal variables (Δ ∈ [0.05, 0.6], Ω ∈ [3e10, 3e12] rad/s),
//! e0a ∈ [0, 2] nm, solid or tube section, 10–40 elements.
//!
//! Tolerances (derived). Both paths solve the same FE model. The reference's
//! poles are roots of Rayleigh functionals of converged vectors, rounding
//! ≤ 1e-12 relative (`beam::modal`'s refinement test, as in
//! `tests/beam_spring_fast_path.rs`). The fast path's block entries are a few
//! rounded operations on the element entries, with the same-parity sums
//! written with sin²(φ/2) as in `axial_spectrum.rs`, so the bending
//! eigenvalue of a block carries the bound derived there,
//! ≲ 10·eps/sin²(φ/2) ≤ 1.4e-12 at n_e = 40, j = 1; the bordered determinant
//! sums n_e + 1 Schur terms X_jᵀ(d_jB_j)⁻¹X_j, each exact to
//! ~eps·cond(B_j) ≲ eps·(2n_e/π)² ≤ 1.4e-12 relative at n_e = 40 (the spring
//! path's bound on det B_j); the root is at Newton's floor (quadratic stop at a
//! 1e-10 step). A pole then agrees to 1e-12 + 1.4e-12 + 1.4e-12 ≈ 4e-12,
//! [`S_TOL`] = 5e-12 relative on ω, ζ to 2·S_TOL absolute; a compressive
//! force amplifies both sides' rounding by (1 + r)/(1 − r)
//! (`compression_gain`). The split itself is falsifiable: a relative
//! perturbation of 1e-6 of one block entry raises the invariance residual
//! from ~1e-15 to > 1e-9 and the mesh is refused (`shear_blocks.rs`, unit
//! test `wavenumber_blocks_are_invariant_only_when_simply_supported`), and
//! to first order it would move an eigenvalue by ~1e-6 relative, six orders
//! above [`S_TOL`] (an estimate: no test runs the perturbed path itself). The dense state space is accurate to ~eps·cond(A) of its
//! eigenproblem: compared at [`STATE_SPACE_TOL`] = 1e-7 on 10-element
//! meshes, as the spring path is.

mod fast_path_check;

use fast_path_check::{
    assert_agrees_with_the_coupled_reference, assert_agrees_with_the_state_space,
    assert_same_bits_at_one_and_two_threads_and_after_any_history, compression_gain, random_axial, random_relaxations,
    random_shear_beam, random_viscous, L_NM,
};
use nanobeam::beam::{buckling_load_n, BeamSpec, InternalVariable, ModalSolver, PointMass, ShearDeformation, Support};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative tolerance on a pole against the coupled RQI reference (module doc).
const S_TOL: f64 = 5e-12;
/// Relative tolerance against the dense state space (module doc).
const STATE_SPACE_TOL: f64 = 1e-7;

fn random_beam(rng: &mut ChaCha8Rng) -> BeamSpec {
    let elements = [10, 20, 20, 20, 40][rng.gen_range(0..5)];
    let mut b = random_shear_beam(rng, elements);
    // a tension, damping, or both; a compression drawn becomes damping (the
    // path declines a compression: its families follow the blocks' relaxed
    // order, which a compressed nonlocal Timoshenko mesh need not keep in |s|,
    // `beam::modal`'s `families_below`)
    let which = rng.gen_range(0..3);
    let mut damped = which != 0;
    if which != 1 {
        let ncr = buckling_load_n(&b).unwrap().abs();
        let n = random_axial(rng, ncr);
        if n > 0.0 {
            b.axial_force_n = n;
        } else {
            damped = true;
        }
    }
    if damped {
        b.viscous_damping_n_s_m2 = random_viscous(rng, &b, 0.01);
    }
    b.internal_variables = random_relaxations(rng);
    b
}

/// 240 random beams: the fast path is taken by `observables` on every one
/// and by `modal` on those without internal variables (with them `modal`
/// reports real relaxation poles, left to the reference); ω and ζ of modes
/// 1–5 agree with the coupled RQI reference within [`S_TOL`].
#[test]
fn random_beams_agree_with_the_coupled_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(4131);
    let beams: Vec<BeamSpec> = (0..240).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_coupled_reference(
        &beams,
        ModalSolver::with_shear_blocks(),
        ModalSolver::last_used_shear_blocks,
        |b| S_TOL * compression_gain(b),
        "shear block path",
    );
}

/// 40 random beams against the dense state space (independent of both the
/// block determinant and the RQI): ω and ζ of modes 1–4 within
/// [`STATE_SPACE_TOL`] (`observables`, internal variables included).
#[test]
fn random_beams_agree_with_the_state_space() {
    let mut rng = ChaCha8Rng::seed_from_u64(4132);
    let beams: Vec<BeamSpec> = (0..40).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_state_space::<4>(
        beams,
        ModalSolver::with_shear_blocks(),
        ModalSolver::last_used_shear_blocks,
        STATE_SPACE_TOL,
        "shear block path",
    );
}

/// The path is taken only when asked for (`ModalSolver::with_shear_blocks`)
/// and on its hypotheses: a simply supported Timoshenko
/// mesh with a tension or C > 0, no point mass, no spring. Clamped
/// supports, a point mass, a spring, a compression, Euler–Bernoulli, and
/// shear alone with C = 0 (the interpolated decoupled path) do not take it.
#[test]
fn the_path_declines_off_its_hypotheses() {
    let mut b = BeamSpec::elastic(L_NM, 1.0, 1e12, 2300.0, Support::SimplySupported, 20);
    b.shear_deformation = Some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: 0.8 });
    b.nonlocal_e0a_nm = 0.7;
    b.viscous_damping_n_s_m2 = 0.1 * 8e11 * b.density_kg_m3 * b.area_m2();
    // the default solver does not take it (opt-in, not yet faster: benches/README.md)
    let mut default_solver = ModalSolver::new();
    default_solver.modal(&b, 4).unwrap();
    assert!(!default_solver.last_used_shear_blocks());
    let mut solver = ModalSolver::with_shear_blocks();
    solver.modal(&b, 4).unwrap();
    assert!(solver.last_used_shear_blocks());
    let mut out = [0.0; 8];
    for (what, v) in [
        ("clamped-pinned", BeamSpec { support: Support::ClampedPinned, ..b.clone() }),
        ("clamped-clamped", BeamSpec { support: Support::ClampedClamped, ..b.clone() }),
        ("point mass", BeamSpec { point_mass: Some(PointMass { mass_kg: 3e-26, x_nm: 2.9 }), ..b.clone() }),
        ("spring", BeamSpec { support_rotational_stiffness_n_m_rad: 1e-9, ..b.clone() }),
        ("Euler-Bernoulli", BeamSpec { shear_deformation: None, ..b.clone() }),
        ("shear alone", BeamSpec { viscous_damping_n_s_m2: 0.0, ..b.clone() }),
        ("compression", BeamSpec { axial_force_n: -0.3 * buckling_load_n(&b).unwrap().abs(), ..b.clone() }),
    ] {
        solver.observables(&v, &[1, 2, 3, 4], 4, &mut out).unwrap();
        assert!(!solver.last_used_shear_blocks(), "{what}");
    }
    let mut relax = b.clone();
    relax.internal_variables = vec![InternalVariable { delta: 0.3, omega_rad_s: 4e11 }];
    solver.modal(&relax, 4).unwrap();
    assert!(!solver.last_used_shear_blocks(), "modal with relaxation poles");
    solver.observables(&relax, &[1, 2, 3, 4], 4, &mut out).unwrap();
    assert!(solver.last_used_shear_blocks(), "observables with relaxation");
}

/// Same bits from two threads as from one, and whatever the solver saw
/// before: the path is a function of its input alone.
#[test]
fn same_bits_at_one_and_two_threads_and_after_any_history() {
    let mut rng = ChaCha8Rng::seed_from_u64(4133);
    let beams: Vec<BeamSpec> = (0..40).map(|_| random_beam(&mut rng)).collect();
    assert_same_bits_at_one_and_two_threads_and_after_any_history(&beams, ModalSolver::with_shear_blocks);
}
