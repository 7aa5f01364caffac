//! The checks every exact fast path of `beam` is held to, shared by
//! `beam_axial_fast_path.rs`, `beam_spring_fast_path.rs`,
//! `beam_mass_blocks.rs`, `beam_shear_blocks.rs` and
//! `beam_shear_continuum.rs` and `beam_spring_mass_fast_path.rs`: a fast result against a reference solve of the
//! same beam (the coupled RQI of `ModalSolver::direct_only`, or the dense
//! state space), ω relative and ζ absolute, within a tolerance each test
//! derives for its path; and the same bits at any thread count and history.
//! Also the draws their random beams share (relaxations, damping, axial
//! force), so the suites draw the same ranges. Each suite uses a subset of
//! these, hence the `dead_code` allowance.
#![allow(dead_code)]

use nanobeam::beam::spec::{Section, Tube};
use nanobeam::beam::{BeamSpec, InternalVariable, ModalResult, ModalSolver, ShearDeformation, Support};
use rand::Rng;

/// The suites' beam length (nm).
pub const L_NM: f64 = 8.0;

/// The hidden suite's nominal Euler–Bernoulli beam (L = [`L_NM`], d = 1 nm,
/// E = 1 TPa, ρ = 2300 kg/m³, simply supported, `elements`) with e0a ∈ [0, 2]
/// nm and a tube section (wall 0.2–0.45 nm) three times in ten.
pub fn random_nominal_beam(rng: &mut impl Rng, elements: usize) -> BeamSpec {
    let mut b = BeamSpec::elastic(L_NM, 1.0, 1e12, 2300.0, Support::SimplySupported, elements);
    b.nonlocal_e0a_nm = rng.gen_range(0.0..2.0);
    if rng.gen_bool(0.3) {
        b.section = Some(Section { tube: Tube { wall_nm: rng.gen_range(0.2..0.45) } });
    }
    b
}

/// How much a compressive force amplifies relative rounding: λ = λ_K − |λ_N|
/// with λ_N/λ_K ≤ r = |N|/|N_cr| on every mode, so a relative error ε in each
/// part is ε(1 + r)/(1 − r) in λ (at most 19 at r = 0.9); 1 under tension.
pub fn compression_gain(b: &BeamSpec) -> f64 {
    let r = (-b.axial_force_n / nanobeam::beam::buckling_load_n(b).unwrap().abs()).max(0.0);
    (1.0 + r) / (1.0 - r)
}

/// The hidden suite's nominal beam (L = 8 nm, d = 1 nm, E = 1 TPa,
/// ρ = 2300 kg/m³, simply supported, `elements`) with e0a ∈ [0, 2] nm, a tube
/// section (wall 0.2–0.45 nm) three times in ten, and shear deformation
/// (ν ∈ [0.1, 0.35], κ ∈ [0.3, 1], the prior of `diagnose::classes`).
pub fn random_shear_beam(rng: &mut impl Rng, elements: usize) -> BeamSpec {
    let mut b = BeamSpec::elastic(8.0, 1.0, 1e12, 2300.0, Support::SimplySupported, elements);
    b.nonlocal_e0a_nm = rng.gen_range(0.0..2.0);
    if rng.gen_bool(0.3) {
        b.section = Some(Section { tube: Tube { wall_nm: rng.gen_range(0.2..0.45) } });
    }
    b.shear_deformation =
        Some(ShearDeformation { poisson_ratio: rng.gen_range(0.1..0.35), shear_coefficient: rng.gen_range(0.3..1.0) });
    b
}

/// Support springs κ = kL/EI log-uniform on the diagnosis's prior
/// [1e-2, 1e3], at x = 0, at x = L, at both alike or at both apart.
pub fn random_springs(rng: &mut impl Rng, b: &mut BeamSpec) {
    let ei_over_l = b.youngs_modulus_pa * b.inertia_m4() / (b.length_nm * 1e-9);
    let kappa = |rng: &mut dyn rand::RngCore| 10f64.powf(rng.gen_range(-2.0..3.0)) * ei_over_l;
    match rng.gen_range(0..4) {
        0 => b.support_rotational_stiffness_left_n_m_rad = kappa(rng),
        1 => b.support_rotational_stiffness_right_n_m_rad = kappa(rng),
        2 => b.support_rotational_stiffness_n_m_rad = kappa(rng),
        _ => {
            b.support_rotational_stiffness_left_n_m_rad = kappa(rng);
            b.support_rotational_stiffness_right_n_m_rad = kappa(rng);
        }
    }
}

/// 0–2 internal variables, Δ ∈ [0.05, 0.6], Ω log-uniform on
/// [10^10.5, 10^12.5] rad/s.
pub fn random_relaxations(rng: &mut impl Rng) -> Vec<InternalVariable> {
    let nv = rng.gen_range(0..3);
    (0..nv)
        .map(|_| InternalVariable {
            delta: rng.gen_range(0.05..0.6),
            omega_rad_s: 10f64.powf(rng.gen_range(10.5..12.5)),
        })
        .collect()
}

/// Viscous C up to ≈ 2ζω₁ρA with ζ ≈ 0.3 on mode 1 of the nominal beam
/// (ω₁ ≈ 8e11 rad/s): u·8e11·ρA, u uniform on [lo, 0.6).
pub fn random_viscous(rng: &mut impl Rng, b: &BeamSpec, lo: f64) -> f64 {
    let rho_a = b.density_kg_m3 * b.area_m2();
    rng.gen_range(lo..0.6) * 8e11 * rho_a
}

/// An axial force asinh-uniform on [−0.9, 100] N_cr, as the axial-force
/// prior (issue 40), for a buckling load of magnitude `ncr`.
pub fn random_axial(rng: &mut impl Rng, ncr: f64) -> f64 {
    rng.gen_range((-0.9f64).asinh()..100f64.asinh()).sinh() * ncr
}

/// Every mode of `fast` against `reference`: the same modes and overdamped
/// families, ω within `tol` relative, ζ within `2 tol` absolute. Returns the
/// worst relative ω difference.
pub fn compare(fast: &ModalResult, reference: &ModalResult, tol: f64, what: &str) -> f64 {
    let mut worst = 0.0f64;
    assert_eq!(fast.modes.len(), reference.modes.len(), "{what}: mode count");
    assert_eq!(fast.overdamped.len(), reference.overdamped.len(), "{what}: overdamped count");
    for (f, r) in fast.modes.iter().zip(&reference.modes) {
        assert_eq!(f.mode, r.mode, "{what}");
        let rel = (f.omega_rad_s - r.omega_rad_s).abs() / r.omega_rad_s;
        worst = worst.max(rel);
        assert!(rel <= tol, "{what}: mode {} ω {} vs {} ({rel:e})", f.mode, f.omega_rad_s, r.omega_rad_s);
        assert!((f.zeta - r.zeta).abs() <= 2.0 * tol, "{what}: mode {} ζ {} vs {}", f.mode, f.zeta, r.zeta);
    }
    worst
}

/// `solver.observables` of `beam`'s modes 1..=`N` against `reference`: the
/// same success (every mode oscillatory), ω within `tol` relative, ζ within
/// `2 tol` absolute. `None` when the solver did not take its fast path
/// (`took` reads that from the solver after the call), else the worst
/// relative ω difference.
pub fn compare_observables<const N: usize>(
    solver: &mut ModalSolver,
    beam: &nanobeam::beam::BeamSpec,
    took: impl Fn(&ModalSolver) -> bool,
    reference: &ModalResult,
    tol: f64,
    what: &str,
) -> Option<f64> {
    let modes: [usize; N] = std::array::from_fn(|k| k + 1);
    let mut out = vec![0.0; 2 * N];
    let ok = solver.observables(beam, &modes, N, &mut out).unwrap();
    if !took(solver) {
        return None;
    }
    assert_eq!(ok, reference.modes.len() == N, "{what}");
    let mut worst = 0.0f64;
    for (k, &m) in modes.iter().enumerate() {
        let Some(r) = reference.mode(m) else { continue };
        let rel = (out[k] - r.omega_rad_s).abs() / r.omega_rad_s;
        worst = worst.max(rel);
        assert!(rel <= tol, "{what} mode {m}: ω {} vs {} ({rel:e})", out[k], r.omega_rad_s);
        assert!((out[N + k] - r.zeta).abs() <= 2.0 * tol, "{what} mode {m}: ζ {} vs {}", out[N + k], r.zeta);
    }
    Some(worst)
}

/// `observables` of modes 1..=`N` of every beam (each made 10 elements: the
/// dense solve is O(dim³)) against the dense state space (`modal_state_space`,
/// independent of both the secular paths and the RQI), within `tol`
/// ([`compare_observables`]); panics when the fast path is not taken, and
/// prints and returns the worst relative ω difference. `solver` is the
/// solver under test.
pub fn assert_agrees_with_the_state_space<const N: usize>(
    beams: impl IntoIterator<Item = BeamSpec>,
    mut solver: ModalSolver,
    used: fn(&ModalSolver) -> bool,
    tol: f64,
    label: &str,
) -> f64 {
    let mut worst = 0.0f64;
    for (i, mut b) in beams.into_iter().enumerate() {
        b.elements = 10;
        let dense = nanobeam::beam::modal_state_space(&b, N).unwrap();
        let what = format!("beam {i}: {b:?}");
        let w = compare_observables::<N>(&mut solver, &b, used, &dense, tol, &what);
        worst = worst.max(w.unwrap_or_else(|| panic!("{what}: the fast path was not taken")));
    }
    eprintln!("{label} vs state space: worst relative ω difference {worst:e}");
    worst
}

/// The fast path is a function of its input alone: `modal` (5 modes) and
/// `observables` (modes 1–5) of every beam give the same bits from one
/// solver as from two solvers on two threads (the beams split in halves),
/// and as from one solver that saw them in reverse order (every cache and
/// scratch state a history leaves). `new_solver` makes the solver under test.
pub fn assert_same_bits_at_one_and_two_threads_and_after_any_history(
    beams: &[nanobeam::beam::BeamSpec],
    new_solver: fn() -> ModalSolver,
) {
    let obs = |s: &mut ModalSolver, b: &nanobeam::beam::BeamSpec| {
        let mut out = [0.0; 10];
        let ok = s.observables(b, &[1, 2, 3, 4, 5], 5, &mut out).unwrap();
        format!("{ok} {:?}", out.map(f64::to_bits))
    };
    let run = |bs: &[nanobeam::beam::BeamSpec]| -> Vec<String> {
        let mut s = new_solver();
        bs.iter().map(|b| format!("{:?} {}", s.modal(b, 5).unwrap(), obs(&mut s, b))).collect()
    };
    let serial = run(beams);
    let (a, b) = beams.split_at(beams.len() / 2);
    let (ra, rb) = std::thread::scope(|sc| {
        let ha = sc.spawn(|| run(a));
        let hb = sc.spawn(|| run(b));
        (ha.join().unwrap(), hb.join().unwrap())
    });
    let parallel: Vec<String> = ra.into_iter().chain(rb).collect();
    assert_eq!(serial, parallel, "two threads differ from one");
    let reversed: Vec<nanobeam::beam::BeamSpec> = beams.iter().rev().cloned().collect();
    let mut back = run(&reversed);
    back.reverse();
    assert_eq!(serial, back, "a solver's history changes its bits");
}

/// Every beam against the coupled RQI (`ModalSolver::direct_only`, 5 modes):
/// `modal` takes the path exactly when the beam has no internal variable (no
/// real poles to leave to the reference), and both `modal` and
/// `observables` agree within `tol(beam)` ([`compare`],
/// [`compare_observables`]). Asserts that `observables` never declines and
/// returns the worst relative ω difference; `label` names the path in the
/// printed summary.
pub fn assert_agrees_with_the_coupled_reference(
    beams: &[nanobeam::beam::BeamSpec],
    mut fast_solver: ModalSolver,
    used: fn(&ModalSolver) -> bool,
    tol: impl Fn(&nanobeam::beam::BeamSpec) -> f64,
    label: &str,
) -> f64 {
    let mut reference_solver = ModalSolver::direct_only();
    let (mut worst, mut taken, mut declined) = (0.0f64, 0, 0);
    for (i, b) in beams.iter().enumerate() {
        let reference = reference_solver.modal(b, 5).unwrap();
        let fast = fast_solver.modal(b, 5).unwrap();
        let tol = tol(b);
        let what = format!("beam {i}: {b:?}");
        assert_eq!(used(&fast_solver), b.internal_variables.is_empty(), "{what}");
        worst = worst.max(compare(&fast, &reference, tol, &what));
        match compare_observables::<5>(&mut fast_solver, b, used, &reference, tol, &what) {
            Some(w) => {
                taken += 1;
                worst = worst.max(w);
            }
            None => declined += 1,
        }
    }
    eprintln!("{label}: taken {taken}, declined {declined}, worst relative ω difference {worst:e}");
    assert_eq!(declined, 0, "{label} declined");
    worst
}
