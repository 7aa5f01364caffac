//! One forward evaluation per model class of the `diagnose` catalogue (issue 41,
//! deliverable 1): the base model, each single cause and the pairs with
//! shear deformation, on the hidden suite's nominal beam (simply supported,
//! L = 8 nm, d = 1 nm, E = 1 TPa, ρ = 2300 kg/m³, 20 elements, e0a = 1 nm,
//! Δ = 0.45, Ω = 3e11 rad/s; `diagnose::synthetic`) with 5 modes, through
//! `ModalSolver::observables` as a diagnosis calls it (ω and ζ of modes 1–5).
//!
//! Each call draws every parameter of the model independently, uniform within
//! ±10 % of its nominal value (κ within [0.72, 0.88]): a TMCMC population
//! that has left the prior, so the pencil is new on every call and grid
//! caches hit as often as they do in a search. `fast/…` is the solver a
//! diagnosis uses (`ModalSolver::new`), `reference/…` the one without the
//! interpolated paths (`ModalSolver::direct_only`); the same draws in the same
//! order for both, so their ratio is the fast path's gain (for attached-mass
//! and its C = 0 pairs, the secular path of `beam/mass_spectrum.rs` against
//! the direct decoupled eigen-solve it replaced; for axial-force and its pairs
//! on this simply supported mesh, the wavenumber-block path of
//! `beam/axial_spectrum.rs` against the coupled RQI; for
//! support-rotational-stiffness and its pairs without shear or point mass,
//! the secular path of `beam/spring_spectrum.rs` against the coupled RQI;
//! for attached-mass with viscous damping or an axial force, the rank-1
//! secular path of `beam/mass_blocks.rs` against the coupled RQI).
//! The tables are in `benches/README.md`.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use nanobeam::beam::{BeamSpec, InternalVariable, ModalSolver, PointMass, ShearDeformation, Support};

/// Cause parameters of one model.
#[derive(Clone, Copy, Default)]
struct Causes {
    relaxation: bool,
    viscous: bool,
    spring: bool,
    mass: bool,
    axial: bool,
    shear: bool,
    /// section-mismatch: the diameter (hence EI, ρA) drawn about its nominal value.
    section: bool,
}

const L_NM: f64 = 8.0;
const D_NM: f64 = 1.0;
const E_PA: f64 = 1e12;
const RHO: f64 = 2300.0;

fn nominal() -> BeamSpec {
    BeamSpec {
        length_nm: L_NM,
        diameter_nm: D_NM,
        youngs_modulus_pa: E_PA,
        density_kg_m3: RHO,
        support: Support::SimplySupported,
        elements: 20,
        nonlocal_e0a_nm: 1.0,
        viscous_damping_n_s_m2: 0.0,
        internal_variables: vec![InternalVariable { delta: 0.45, omega_rad_s: 3e11 }],
        support_rotational_stiffness_n_m_rad: 0.0,
        support_rotational_stiffness_left_n_m_rad: 0.0,
        support_rotational_stiffness_right_n_m_rad: 0.0,
        point_mass: None,
        axial_force_n: 0.0,
        elastic_foundation_n_m2: 0.0,
        loss_factor: 0.0,
        strain_gradient_length_nm: 0.0,
        shear_deformation: None,
        section: None,
    }
}

/// A beam of the model `c`, every parameter drawn by `u` (uniform in [−½, ½]).
fn draw(c: Causes, u: &mut impl FnMut() -> f64) -> BeamSpec {
    let mut b = nominal();
    let mut near = |x: f64| x * (1.0 + 0.2 * u());
    b.nonlocal_e0a_nm = near(1.0);
    b.youngs_modulus_pa = near(E_PA);
    b.internal_variables[0].delta = near(0.45);
    b.internal_variables[0].omega_rad_s = near(3e11);
    let ei = E_PA * std::f64::consts::PI * (D_NM * 1e-9).powi(4) / 64.0;
    let rho_a = RHO * std::f64::consts::PI * (D_NM * 1e-9).powi(2) / 4.0;
    let l = L_NM * 1e-9;
    let omega1 = std::f64::consts::PI.powi(2) / (l * l) * (ei / rho_a).sqrt();
    if c.relaxation {
        b.internal_variables.push(InternalVariable { delta: near(0.2), omega_rad_s: near(1e12) });
    }
    if c.viscous {
        // ζ₁ ≈ 1 % at the nominal ω₁ (the prior spans 1e-4..0.3)
        b.viscous_damping_n_s_m2 = near(2.0 * rho_a * omega1 * 0.01);
    }
    if c.spring {
        // κ = k L/EI ≈ 1 at each end, drawn per end as the diagnosis samples
        // them (the prior spans 1e-2..1e3 per end)
        b.support_rotational_stiffness_left_n_m_rad = near(ei / l);
        b.support_rotational_stiffness_right_n_m_rad = near(ei / l);
    }
    if c.mass {
        b.point_mass = Some(PointMass { mass_kg: near(0.1 * rho_a * l), x_nm: near(0.3 * L_NM) });
    }
    if c.axial {
        // a quarter of the local simply supported buckling load, in tension
        b.axial_force_n = near(0.25 * std::f64::consts::PI.powi(2) * ei / (l * l));
    }
    if c.section {
        b.diameter_nm = near(D_NM);
    }
    if c.shear {
        b.shear_deformation = Some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: near(0.8) });
    }
    b
}

fn models() -> Vec<(&'static str, Causes)> {
    let none = Causes::default();
    vec![
        ("base", none),
        ("extra-relaxation", Causes { relaxation: true, ..none }),
        ("viscous-damping", Causes { viscous: true, ..none }),
        ("support-rotational-stiffness", Causes { spring: true, ..none }),
        ("attached-mass", Causes { mass: true, ..none }),
        ("axial-force", Causes { axial: true, ..none }),
        ("shear-deformation", Causes { shear: true, ..none }),
        ("shear+extra-relaxation", Causes { shear: true, relaxation: true, ..none }),
        ("shear+viscous", Causes { shear: true, viscous: true, ..none }),
        ("shear+spring", Causes { shear: true, spring: true, ..none }),
        ("shear+mass", Causes { shear: true, mass: true, ..none }),
        ("shear+axial", Causes { shear: true, axial: true, ..none }),
        ("viscous+mass", Causes { viscous: true, mass: true, ..none }),
        ("axial+mass", Causes { axial: true, mass: true, ..none }),
        ("extra-relaxation+mass", Causes { relaxation: true, mass: true, ..none }),
        ("spring+axial", Causes { spring: true, axial: true, ..none }),
        ("extra-relaxation+spring", Causes { relaxation: true, spring: true, ..none }),
        ("viscous+spring", Causes { viscous: true, spring: true, ..none }),
        ("spring+mass", Causes { spring: true, mass: true, ..none }),
        ("axial+extra-relaxation", Causes { axial: true, relaxation: true, ..none }),
        ("axial+viscous", Causes { axial: true, viscous: true, ..none }),
        ("axial+section-mismatch", Causes { axial: true, section: true, ..none }),
    ]
}

fn bench(c: &mut Criterion) {
    let modes = [1, 2, 3, 4, 5];
    let mut out = [0.0; 10];
    let only = std::env::var("COUPLED_BENCH_MODELS").ok();
    for (name, causes) in models() {
        if let Some(list) = &only {
            if !list.split(',').any(|m| m == name) {
                continue;
            }
        }
        for (label, reference) in [("fast", false), ("reference", true)] {
            let mut solver = if reference { ModalSolver::direct_only() } else { ModalSolver::new() };
            let mut state = 0x2545_f491_4f6c_dd1du64;
            let mut uniform = move || {
                // xorshift: the bench needs cheap reproducible noise, not quality
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            };
            // warm the process-wide interpolant tables and the grid caches once
            for _ in 0..200 {
                let b = draw(causes, &mut uniform);
                solver.observables(&b, &modes, 5, &mut out).unwrap();
            }
            c.bench_function(&format!("{label}/{name}"), |bch| {
                bch.iter(|| {
                    let b = draw(causes, &mut uniform);
                    solver.observables(black_box(&b), &modes, 5, &mut out).unwrap()
                })
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_secs(1))
        .measurement_time(std::time::Duration::from_secs(3));
    targets = bench
}
criterion_main!(benches);
