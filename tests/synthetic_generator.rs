//! The hidden-effect generator of `tests/synthetic/mod.rs` checked on
//! its own: its section-effect solver against the library's modal solver on a
//! uniform section, a defect's mirror symmetry and softening, and the growth
//! that keeps each cause of a pair visible. Data: `tests/synthetic/mod.rs` itself.

mod synthetic;

use nanobeam::beam::{self, BeamSpec, InternalVariable};
use nanobeam::diagnose::{Model, ModelClass, NominalScales};
use synthetic::*;

/// A truth of the generator's kind (nonlocal, one internal variable).
fn base_truth() -> BeamSpec {
    let mut beam = nominal_beam();
    beam.nonlocal_e0a_nm = 1.0;
    beam.internal_variables = vec![InternalVariable { delta: 0.45, omega_rad_s: 3e11 }];
    beam
}

/// A uniform section reproduces the product's solver: both solve the same
/// decoupled pencil, so they differ only by eigensolver rounding (dense
/// Cholesky route: ~κ(M̃)·ε relative on λ, κ ≈ 1e3 for 20 elements, so
/// ≤ 1e-12 on ω; ζ is a ratio of pole parts of the same size) and by the
/// family roots' (companion eigenvalues polished by Newton to round-off, so
/// ~1e-15 more).
#[test]
fn uniform_section_reproduces_the_beam_solver() {
    let beam = base_truth();
    let ours = section_modes(&beam, &vec![1.0; beam.elements], 6).unwrap();
    let theirs = beam::modal(&beam, 6).unwrap().modes;
    for (a, b) in ours.iter().zip(&theirs) {
        assert!((a.omega_rad_s / b.omega_rad_s - 1.0).abs() < 1e-10, "{a:?} vs {b:?}");
        assert!((a.zeta / b.zeta - 1.0).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

/// A defect and its mirror image about midspan give the same modes on a
/// simply supported beam (the uniform mesh mirrors too: equal to
/// rounding), and a defect lowers every frequency (less stiffness, same
/// mass: Rayleigh's quotient) by more than the 0.3 % noise at ε = 0.5.
/// Each cause of a generated pair leaves the best fit of the model of
/// the other cause ≥ [`MIN_SHIFT_SIGMA`] away, on the case's own
/// noise-free data and the truth's own base coordinates. Pair seed 300
/// (relaxation + spring) needed the spring grown ×3.375 past its size
/// alone, so this fails if the growth step is skipped.
#[test]
fn each_cause_of_a_pair_is_visible_against_the_other() {
    use ModelClass::*;
    let causes = [ExtraRelaxation, SupportRotationalStiffness];
    let case = generate_hidden(300, &Hidden::causes(&causes));
    let y0 = predict(&Truth { beam: case.truth_beam.clone(), modal: vec![] }, case.noise_free.len()).unwrap();
    assert_eq!(observations(&y0), case.noise_free);
    let s = NominalScales::of(&case.truth_beam, y0.len()).unwrap();
    for c in causes {
        let z = model_fit_max_z(&Model::with(&causes).without(c), &y0, &case.truth_beam, &s, 300);
        assert!(z >= MIN_SHIFT_SIGMA, "{} absorbed by the other cause: {z:.2} sd", c.name());
    }
}

#[test]
fn a_defect_softens_and_mirrors() {
    let beam = base_truth();
    let defect = |first: f64| Truth { beam: beam.clone(), modal: vec![(Foreign::LocalDefect, [first, 2.0], 0.5)] };
    let clean = beam::modal(&beam, 6).unwrap().modes;
    let (left, right) = (predict(&defect(3.0), 6).unwrap(), predict(&defect(15.0), 6).unwrap());
    for ((a, b), c) in left.iter().zip(&right).zip(&clean) {
        assert!((a.omega_rad_s / b.omega_rad_s - 1.0).abs() < 1e-10, "{a:?} vs {b:?}");
        assert!(a.omega_rad_s < c.omega_rad_s * (1.0 - OMEGA_REL_SD), "{a:?} vs {c:?}");
    }
}
