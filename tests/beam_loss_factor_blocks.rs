//! The hysteretic loss factor η on the Euler–Bernoulli wavenumber-block paths
//! (`beam/fast/axial_spectrum.rs`, "A hysteretic loss factor": G(s) becomes
//! G(s)(1 + iη) in every block and secular function, the starts the
//! reference's hysteretic one-term roots) against the path they replace,
//! which stays the reference: the coupled nonlinear RQI on the whole
//! assembled T̃(s) with the same modulus (`ModalSolver::direct_only`,
//! `coupled.rs`). The dense state space cannot hold a loss factor (it is
//! defined in the frequency domain only); `tests/beam_loss_factor.rs` holds
//! the axial-force block path to a closed form that shares no code with `src/`.
//!
//! Data: generated here (ChaCha8 streams, seeds in each test) over the hidden
//! suite's nominal beam (`fast_path_check::random_nominal_beam`) and the
//! priors of the diagnosis: η log-uniform on `diagnose::classes`'s
//! `LOSS_FACTOR_RANGE` [2e-4, 0.6], 0–2 internal variables, support springs,
//! a point mass (μ̃ ∈ [1e-3, 1]), an axial force (N/|N_cr| ∈ [−0.9, 100]), a
//! foundation (k̃_f up to 100π⁴, the `elastic-foundation` prior's scale) and
//! viscous damping, in the combinations each path takes; 10–40 elements.
//!
//! Tolerance: the paths' own suites' [`S_TOL`] (`beam_spring_fast_path.rs`
//! derives it: the reference's Rayleigh functionals ≤ 1e-12, the block
//! entries' and the secular determinant's rounding ≤ 1.4e-12 each at 40
//! elements), times the compression gain. The loss factor adds one complex
//! product (1 + iη)·G per evaluation on each side, a rounding of a few eps.

mod fast_path_check;

use fast_path_check::{
    assert_same_bits_at_one_and_two_threads_and_after_any_history, compare, compare_observables, compression_gain,
    random_axial, random_nominal_beam, random_relaxations, random_springs, random_viscous, L_NM,
};
use nanobeam::beam::{buckling_load_n, BeamSpec, ModalSolver, PointMass, ShearDeformation};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Relative tolerance on a pole against the coupled RQI reference (module doc).
const S_TOL: f64 = 4e-12;

/// The block paths a loss factor now takes, with the solver's report of each.
#[derive(Debug, Clone, Copy)]
enum Path {
    Spring,
    SpringMass,
    Mass,
    Axial,
}

impl Path {
    fn used(self) -> fn(&ModalSolver) -> bool {
        match self {
            Path::Spring => ModalSolver::last_used_spring_blocks,
            Path::SpringMass => ModalSolver::last_used_spring_mass_blocks,
            Path::Mass => ModalSolver::last_used_mass_blocks,
            Path::Axial => ModalSolver::last_used_axial_blocks,
        }
    }
}

fn point_mass(rng: &mut ChaCha8Rng, b: &BeamSpec) -> PointMass {
    let rho_a = b.density_kg_m3 * b.area_m2();
    let mu = 10f64.powf(rng.gen_range(-3.0..0.0));
    PointMass { mass_kg: mu * rho_a * L_NM * 1e-9, x_nm: rng.gen_range(0.0..L_NM) }
}

/// k (N/m²) with k̃_f = kL⁴/EI up to 100π⁴ (log-uniform from 0.1π⁴).
fn foundation(rng: &mut ChaCha8Rng, b: &BeamSpec) -> f64 {
    let ei = b.youngs_modulus_pa * b.inertia_m4();
    let l4 = (b.length_nm * 1e-9).powi(4);
    10f64.powf(rng.gen_range(-1.0..2.0)) * std::f64::consts::PI.powi(4) * ei / l4
}

/// A beam of `path`'s hypotheses with a loss factor.
fn random_beam(rng: &mut ChaCha8Rng, path: Path) -> BeamSpec {
    let elements = [10, 15, 20, 20, 40][rng.gen_range(0..5)];
    let mut b = random_nominal_beam(rng, elements);
    let (lo, hi) = nanobeam::diagnose::classes::LOSS_FACTOR_RANGE;
    b.loss_factor = 10f64.powf(rng.gen_range(lo.log10()..hi.log10()));
    b.internal_variables = random_relaxations(rng);
    match path {
        Path::Spring => random_springs(rng, &mut b),
        Path::SpringMass => {
            random_springs(rng, &mut b);
            b.point_mass = Some(point_mass(rng, &b));
        }
        // a point mass leaves the decoupled families only beside damping, a force or a foundation
        Path::Mass => b.point_mass = Some(point_mass(rng, &b)),
        Path::Axial => {}
    }
    let force = |rng: &mut ChaCha8Rng, b: &BeamSpec| {
        random_axial(rng, buckling_load_n(&BeamSpec { point_mass: None, ..b.clone() }).unwrap().abs())
    };
    match path {
        Path::Axial => b.axial_force_n = force(rng, &b),
        Path::Mass => match rng.gen_range(0..3) {
            0 => b.viscous_damping_n_s_m2 = random_viscous(rng, &b, 0.01),
            1 => b.axial_force_n = force(rng, &b),
            _ => b.elastic_foundation_n_m2 = foundation(rng, &b),
        },
        Path::Spring if rng.gen_bool(0.3) => b.axial_force_n = force(rng, &b),
        _ => {}
    }
    if !matches!(path, Path::Mass | Path::SpringMass) && rng.gen_bool(0.3) {
        b.elastic_foundation_n_m2 = foundation(rng, &b);
    }
    if !matches!(path, Path::Mass) && rng.gen_bool(0.5) {
        b.viscous_damping_n_s_m2 = random_viscous(rng, &b, 0.0);
    }
    b
}

/// 60 random beams per path: `modal` and `observables` (modes 1–5) take the
/// path on every one (a loss factor has no real poles to leave to the
/// reference) and agree with the coupled RQI within [`S_TOL`] times the
/// compression gain.
#[test]
fn random_beams_with_a_loss_factor_agree_with_the_coupled_reference() {
    for (seed, path) in [(4411, Path::Spring), (4412, Path::SpringMass), (4413, Path::Mass), (4414, Path::Axial)] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (mut reference_solver, mut solver) = (ModalSolver::direct_only(), ModalSolver::new());
        let mut worst = 0.0f64;
        for i in 0..60 {
            let b = random_beam(&mut rng, path);
            let what = format!("{path:?} beam {i}: {b:?}");
            let reference = reference_solver.modal(&b, 5).unwrap_or_else(|e| panic!("{what}: {e}"));
            let fast = solver.modal(&b, 5).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert!(path.used()(&solver), "{what}: modal did not take the path");
            // the force was drawn against the buckling load without the mass and the foundation
            let tol =
                S_TOL * compression_gain(&BeamSpec { point_mass: None, elastic_foundation_n_m2: 0.0, ..b.clone() });
            worst = worst.max(compare(&fast, &reference, tol, &what));
            let w = compare_observables::<5>(&mut solver, &b, path.used(), &reference, tol, &what);
            worst = worst.max(w.unwrap_or_else(|| panic!("{what}: observables did not take the path")));
        }
        eprintln!("{path:?} with a loss factor: worst relative ω difference {worst:e}");
    }
}

/// The loss factor's poles move with η as the closed form's do on the
/// decoupled families: ζ = sin(½ atan η) of an undamped elastic beam
/// (`solve::family`'s check), here on the spring path, whose families a
/// spring couples: with no relaxation and no damping the springs are part of
/// the elastic stiffness, T(s) = s²M + (1 + iη)K + K_s, not a multiple of
/// one pencil, so ζ falls below sin(½ atan η) by the springs' share of the
/// stiffness. Asserted: 0 < ζ < sin(½ atan η) on every mode, strictly
/// increasing in η, and the same value from both paths.
#[test]
fn a_loss_factor_beside_springs_damps_less_than_on_the_bare_beam() {
    let mut b = BeamSpec::elastic(L_NM, 1.0, 1e12, 2300.0, nanobeam::beam::Support::SimplySupported, 20);
    b.support_rotational_stiffness_n_m_rad = 1e-9;
    b.nonlocal_e0a_nm = 0.5;
    let (mut solver, mut reference) = (ModalSolver::new(), ModalSolver::direct_only());
    let mut last = [0.0; 4];
    for eta in [0.01, 0.05, 0.2, 0.6] {
        b.loss_factor = eta;
        let fast = solver.modal(&b, 4).unwrap();
        assert!(solver.last_used_spring_blocks());
        let slow = reference.modal(&b, 4).unwrap();
        compare(&fast, &slow, S_TOL, &format!("η = {eta}"));
        let bare = (0.5 * eta.atan()).sin();
        for (k, m) in fast.modes.iter().enumerate() {
            assert!(m.zeta > last[k] && m.zeta < bare, "η = {eta} mode {}: ζ {} (bare {bare})", m.mode, m.zeta);
            last[k] = m.zeta;
        }
    }
}

/// A loss factor on a Timoshenko mesh beside a coupling still runs the
/// reference (no Timoshenko path has it), and the block paths' own suites'
/// beams without a loss factor take them as before.
#[test]
fn the_timoshenko_mesh_with_a_loss_factor_declines() {
    let mut b = BeamSpec::elastic(L_NM, 1.0, 1e12, 2300.0, nanobeam::beam::Support::SimplySupported, 20);
    b.support_rotational_stiffness_n_m_rad = 1e-9;
    b.loss_factor = 0.1;
    b.shear_deformation = Some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: 0.8 });
    let mut solver = ModalSolver::new();
    let mut out = [0.0; 8];
    solver.observables(&b, &[1, 2, 3, 4], 4, &mut out).unwrap();
    assert!(!solver.last_used_spring_blocks() && !solver.last_used_shear_continuum());
    b.shear_deformation = None;
    solver.observables(&b, &[1, 2, 3, 4], 4, &mut out).unwrap();
    assert!(solver.last_used_spring_blocks());
}

/// Same bits from two threads as from one, and whatever the solver saw
/// before, on beams of every path with a loss factor.
#[test]
fn same_bits_at_one_and_two_threads_and_after_any_history() {
    let mut rng = ChaCha8Rng::seed_from_u64(4415);
    let beams: Vec<BeamSpec> = [Path::Spring, Path::SpringMass, Path::Mass, Path::Axial]
        .iter()
        .flat_map(|&p| (0..6).map(move |_| p))
        .map(|p| random_beam(&mut rng, p))
        .collect();
    assert_same_bits_at_one_and_two_threads_and_after_any_history(&beams, ModalSolver::new);
}
