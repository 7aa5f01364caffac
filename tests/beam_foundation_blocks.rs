//! Issue 66: the Winkler foundation on the exact wavenumber-block paths of
//! the simply supported Euler–Bernoulli mesh (the axial force
//! `axial_spectrum.rs`, the support springs `spring_spectrum.rs`, the point
//! mass `mass_blocks.rs`). The foundation's matrix is k̃·M̃ (`beam::fe::scaling`),
//! and M̃ splits into the same wavenumber blocks M_j as the mesh, so it joins
//! each block's elastic part, N_j + k̃M_j, and every proof of those paths
//! holds with that N_j. Before, such beams took the coupled RQI on the whole
//! assembled T̃(s) (`ModalSolver::direct_only`, `coupled.rs`), which stays
//! the reference here, with the dense state space beside it.
//!
//! Data: generated here (ChaCha8 streams, seeds in each test) over the hidden
//! suite's nominal beam (L = 8 nm, d = 1 nm, E = 1 TPa, ρ = 2300 kg/m³,
//! e0a ∈ [0, 2] nm, solid or tube) with the `elastic-foundation` prior of
//! `diagnose::classes` (k/(ρAω₁⁰²) asinh-uniform on [−0.5, 100], ω₁⁰ the
//! free beam's mode 1 from the continuum closed form; the pull kept within
//! half the margin a compression leaves, so the beam stays stable) and, per
//! beam, one of: an axial force (the axial-force prior), support springs
//! (the spring prior), a point mass (μ̃ log-uniform on [1e-3, 1], any x),
//! each with or without viscous damping and with 0–2 internal variables;
//! 10–40 elements.
//!
//! Tolerances (derived). Both paths solve the same FE model; the reference's
//! poles round to ≤ 1e-12 relative. The block paths' own budget is 4e-12
//! relative on a pole (`tests/beam_mass_blocks.rs` derives it: block entries
//! ≤ 1.4e-12, the adjugate and determinant next to the root ≲ 1.4e-12), with
//! compression's amplification (`compression_gain`). The foundation adds
//! k̃·M_j, one product more in each entry of N_j; a pull (k̃ < 0) cancels
//! against the bending part as a compression does: λ = λ_b − |k̃| with
//! |k̃|/λ_b ≤ q on every mode, so a relative error ε in each part becomes
//! ε(1 + q)/(1 − q) in λ ([`pull_gain`]).

mod fast_path_check;

use fast_path_check::{
    assert_agrees_with_the_coupled_reference, assert_agrees_with_the_state_space,
    assert_same_bits_at_one_and_two_threads_and_after_any_history, compression_gain, random_axial, random_nominal_beam,
    random_relaxations, random_springs, random_viscous, L_NM,
};
use nanobeam::beam::{buckling_load_n, BeamSpec, ModalSolver, PointMass};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative tolerance on a pole against the coupled RQI (module doc).
const S_TOL: f64 = 4e-12;
/// Relative tolerance against the dense state space: ≲ 1e-9 on 10-element
/// meshes (`tests/beam_axial_fast_path.rs`), compared at 1e-7 as there.
const STATE_SPACE_TOL: f64 = 1e-7;

/// ρAω₁⁰² of the free simply supported continuum beam (Eringen): the unit of
/// the foundation prior.
fn rho_a_omega1_sq(b: &BeamSpec) -> f64 {
    let a = std::f64::consts::PI / (b.length_nm * 1e-9);
    let mu = (b.nonlocal_e0a_nm * 1e-9).powi(2);
    b.youngs_modulus_pa * b.inertia_m4() * a.powi(4) / (1.0 + mu * a * a)
}

/// How much a pull amplifies relative rounding (module doc): q = |k|/(ρAω₁⁰²)
/// for k < 0 (mode 1 is where the ratio is largest), 1 for a substrate.
fn pull_gain(b: &BeamSpec) -> f64 {
    let q = (-b.elastic_foundation_n_m2 / rho_a_omega1_sq(b)).max(0.0);
    (1.0 + q) / (1.0 - q)
}

fn random_beam(rng: &mut ChaCha8Rng) -> BeamSpec {
    let elements = [10, 15, 20, 20, 40][rng.gen_range(0..5)];
    let mut b = random_nominal_beam(rng, elements);
    let rho_a = b.density_kg_m3 * b.area_m2();
    // room a compression leaves for a pull: 1 − |N|/N_cr
    let mut room = 1.0;
    match rng.gen_range(0..3) {
        0 => {
            b.axial_force_n = random_axial(rng, buckling_load_n(&b).unwrap().abs());
            room = 1.0 + (b.axial_force_n / buckling_load_n(&b).unwrap().abs()).min(0.0);
        }
        1 => random_springs(rng, &mut b),
        _ => {
            let mu = 10f64.powf(rng.gen_range(-3.0..0.0));
            b.point_mass = Some(PointMass { mass_kg: mu * rho_a * L_NM * 1e-9, x_nm: rng.gen_range(0.0..L_NM) });
        }
    }
    if rng.gen_bool(0.5) {
        b.viscous_damping_n_s_m2 = random_viscous(rng, &b, 0.01);
    }
    b.internal_variables = random_relaxations(rng);
    let u = rng.gen_range((-0.5f64).asinh()..100f64.asinh()).sinh();
    b.elastic_foundation_n_m2 = if u < 0.0 { u * room } else { u } * rho_a_omega1_sq(&b);
    b
}

/// Was the beam's solve one of the three block paths?
fn on_blocks(s: &ModalSolver) -> bool {
    s.last_used_axial_blocks() || s.last_used_spring_blocks() || s.last_used_mass_blocks()
}

/// 200 random beams: a block path is taken by `observables` on every one and
/// by `modal` on those without internal variables; ω and ζ of modes 1–5
/// agree with the coupled RQI within [`S_TOL`] times the amplifications.
#[test]
fn random_beams_with_a_foundation_agree_with_the_coupled_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(6601);
    let beams: Vec<BeamSpec> = (0..200).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_coupled_reference(
        &beams,
        ModalSolver::new(),
        on_blocks,
        |b| S_TOL * compression_gain(&BeamSpec { elastic_foundation_n_m2: 0.0, ..b.clone() }) * pull_gain(b),
        "foundation on the block paths",
    );
}

/// 30 random beams against the dense state space (independent of both the
/// secular equations and the RQI): ω and ζ of modes 1–4 within [`STATE_SPACE_TOL`].
#[test]
fn random_beams_with_a_foundation_agree_with_the_state_space() {
    let mut rng = ChaCha8Rng::seed_from_u64(6602);
    let beams: Vec<BeamSpec> = (0..30).map(|_| random_beam(&mut rng)).collect();
    assert_agrees_with_the_state_space::<4>(
        beams,
        ModalSolver::new(),
        on_blocks,
        STATE_SPACE_TOL,
        "foundation on the block paths",
    );
}

/// Same bits from two threads as from one, and whatever the solver saw before.
#[test]
fn same_bits_at_one_and_two_threads_and_after_any_history() {
    let mut rng = ChaCha8Rng::seed_from_u64(6603);
    let beams: Vec<BeamSpec> = (0..30).map(|_| random_beam(&mut rng)).collect();
    assert_same_bits_at_one_and_two_threads_and_after_any_history(&beams, ModalSolver::new);
}

/// Where the blocks do not have the foundation, the beam goes elsewhere:
/// springs with a point mass together, clamped ends (no wavenumber blocks).
/// A loss factor beside a point mass stays on the blocks (their modulus
/// G(s)(1 + iη), `axial_spectrum.rs`; against the coupled reference in
/// `tests/beam_loss_factor_blocks.rs`).
#[test]
fn the_foundation_leaves_the_block_paths_off_their_hypotheses() {
    let mut rng = ChaCha8Rng::seed_from_u64(6604);
    let mut b = random_nominal_beam(&mut rng, 20);
    b.elastic_foundation_n_m2 = 2.0 * rho_a_omega1_sq(&b);
    let rho_a = b.density_kg_m3 * b.area_m2();
    let mass = PointMass { mass_kg: 0.1 * rho_a * L_NM * 1e-9, x_nm: 3.0 };
    let mut solver = ModalSolver::new();
    let mut both = b.clone();
    both.point_mass = Some(mass);
    both.support_rotational_stiffness_n_m_rad = 1e-19;
    solver.modal(&both, 4).unwrap();
    assert!(!on_blocks(&solver) && !solver.last_used_spring_mass_blocks(), "springs and a mass");
    let mut lossy = b.clone();
    lossy.point_mass = Some(mass);
    lossy.loss_factor = 0.05;
    solver.modal(&lossy, 4).unwrap();
    assert!(on_blocks(&solver), "a loss factor beside a point mass");
    let mut clamped = b.clone();
    clamped.support = nanobeam::beam::Support::ClampedClamped;
    clamped.point_mass = Some(mass);
    solver.modal(&clamped, 4).unwrap();
    assert!(!on_blocks(&solver), "clamped ends");
    let mut plain = b;
    plain.axial_force_n = 1e-9;
    solver.modal(&plain, 4).unwrap();
    assert!(solver.last_used_axial_blocks(), "an axial force with the foundation");
}
