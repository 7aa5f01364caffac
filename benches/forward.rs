//! One forward evaluation (20 elements, 3 modes): fast exact path (b), the
//! general path (c) with a support spring, and the state-space reference (a),
//! for N = 1 and N = 2 internal variables. `cold` builds a fresh solver every
//! call (mesh integrals, grid start pencil, everything: the first call of a
//! process); `modal_repeat` calls the free `modal` (per-thread solver) on
//! the same beam; `chain` reuses a
//! `ModalSolver` along a random walk of every parameter including e0a, with
//! steps the size of a calibration's proposals (1 % of e0a, so the pencil
//! eigenpairs are new every call: the certified interpolant of issue 15 for
//! `fast_chain` (3 modes) and `fast_chain_6modes`, RQI from the cached grid
//! pencil for `direct_chain`, the path before issue 15); `warm`
//! perturbs only E (the pencil is bitwise unchanged, as in a calibration of
//! E, ρ, C, Δ, Ω with e0a fixed). `axial_chain`, `shear_chain` (κ moves; g̃
//! is a pencil parameter, so the mesh stays), `shear_fixed_chain` (κ fixed)
//! and `shear_undamped_chain` (κ moves, C = 0: the decoupled path) do the same
//! with the mechanisms of issue 13.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use nanobeam::beam::{modal, modal_state_space, BeamSpec, InternalVariable, ModalSolver, Support};

fn beam(n_iv: usize) -> BeamSpec {
    BeamSpec {
        length_nm: 8.0,
        diameter_nm: 1.0,
        youngs_modulus_pa: 1e12,
        density_kg_m3: 2300.0,
        support: Support::SimplySupported,
        elements: 20,
        nonlocal_e0a_nm: 0.5,
        viscous_damping_n_s_m2: 1e-5,
        internal_variables: [
            InternalVariable { delta: 0.1, omega_rad_s: 1e11 },
            InternalVariable { delta: 0.05, omega_rad_s: 3e12 },
        ][..n_iv]
            .to_vec(),
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

/// One step of a reflecting random walk around `nominal`: ±1 % (u ∈ [−½, ½]),
/// refused beyond ±20 % of the nominal value.
fn step(x: f64, nominal: f64, u: f64) -> f64 {
    let y = x * (1.0 + 0.02 * u);
    if (y / nominal - 1.0).abs() > 0.2 {
        x
    } else {
        y
    }
}

fn bench(c: &mut Criterion) {
    for n_iv in [1, 2] {
        let b = beam(n_iv);
        c.bench_function(&format!("fast_cold_N{n_iv}"), |bch| {
            bch.iter(|| ModalSolver::new().modal(black_box(&b), 3).unwrap())
        });
        c.bench_function(&format!("modal_repeat_N{n_iv}"), |bch| bch.iter(|| modal(black_box(&b), 3).unwrap()));
        let mut solver = ModalSolver::new();
        let mut walk = b.clone();
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = move || {
            // xorshift: the bench needs cheap reproducible noise, not quality
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        // the chain path: interpolated eigenvalues (issue 15) for 3 and 6
        // modes, and the direct eigen-solve (RQI from the grid pencil) before it
        for (label, modes, direct) in
            [("fast_chain", 3, false), ("fast_chain_6modes", 6, false), ("direct_chain", 3, true)]
        {
            let mut solver = if direct { ModalSolver::direct_only() } else { ModalSolver::new() };
            solver.modal(&walk, modes).unwrap();
            c.bench_function(&format!("{label}_N{n_iv}"), |bch| {
                bch.iter(|| {
                    walk.nonlocal_e0a_nm = step(walk.nonlocal_e0a_nm, b.nonlocal_e0a_nm, uniform());
                    walk.youngs_modulus_pa = step(walk.youngs_modulus_pa, b.youngs_modulus_pa, uniform());
                    for (iv, iv0) in walk.internal_variables.iter_mut().zip(&b.internal_variables) {
                        iv.delta = step(iv.delta, iv0.delta, uniform());
                        iv.omega_rad_s = step(iv.omega_rad_s, iv0.omega_rad_s, uniform());
                    }
                    solver.modal(black_box(&walk), modes).unwrap()
                })
            });
        }
        let mut k = 0u64;
        c.bench_function(&format!("fast_warm_N{n_iv}"), |bch| {
            bch.iter(|| {
                k += 1;
                let mut bb = b.clone();
                bb.youngs_modulus_pa *= 1.0 + 1e-6 * (k % 7) as f64;
                solver.modal(black_box(&bb), 3).unwrap()
            })
        });
        let mut bs = b.clone();
        bs.support_rotational_stiffness_n_m_rad = 1e-18;
        let mut solver = ModalSolver::new();
        let mut walk = bs.clone();
        c.bench_function(&format!("general_spring_chain_N{n_iv}"), |bch| {
            bch.iter(|| {
                walk.nonlocal_e0a_nm = step(walk.nonlocal_e0a_nm, bs.nonlocal_e0a_nm, uniform());
                walk.support_rotational_stiffness_n_m_rad =
                    step(walk.support_rotational_stiffness_n_m_rad, bs.support_rotational_stiffness_n_m_rad, uniform());
                walk.youngs_modulus_pa = step(walk.youngs_modulus_pa, bs.youngs_modulus_pa, uniform());
                solver.modal(black_box(&walk), 3).unwrap()
            })
        });
        c.bench_function(&format!("general_spring_N{n_iv}"), |bch| {
            bch.iter(|| ModalSolver::new().modal(black_box(&bs), 3).unwrap())
        });
        // issue 13: axial force (coupled path: RQI on T(s)) and shear
        // deformation (Timoshenko mesh, 5 DOFs/node, decoupled when C = 0 or
        // no rotary inertia: coupled for C > 0, decoupled for `shear_undamped`), each along a chain
        // that moves the new parameter, E and e0a (the Timoshenko mesh is
        // rebuilt only when d or L move: it depends on r̃² = I/(AL²))
        for (name, axial, shear) in [
            ("axial", 2e-9, None),
            ("shear", 0.0, Some(0.9)),
            ("shear_fixed", 0.0, Some(0.9)),
            ("shear_undamped", 0.0, Some(0.9)),
        ] {
            let mut bx = b.clone();
            if name == "shear_undamped" {
                // C = 0: the decoupled path (D̃ ∝ M̃ holds despite the rotary inertia)
                bx.viscous_damping_n_s_m2 = 0.0;
            }
            bx.axial_force_n = axial;
            bx.shear_deformation =
                shear.map(|k| nanobeam::beam::ShearDeformation { poisson_ratio: 0.2, shear_coefficient: k });
            let mut solver = ModalSolver::new();
            let mut walk = bx.clone();
            c.bench_function(&format!("{name}_chain_N{n_iv}"), |bch| {
                bch.iter(|| {
                    walk.nonlocal_e0a_nm = step(walk.nonlocal_e0a_nm, bx.nonlocal_e0a_nm, uniform());
                    walk.youngs_modulus_pa = step(walk.youngs_modulus_pa, bx.youngs_modulus_pa, uniform());
                    if name == "axial" {
                        walk.axial_force_n = step(walk.axial_force_n, bx.axial_force_n, uniform());
                    }
                    if let (Some(sd), Some(sd0)) = (walk.shear_deformation.as_mut(), bx.shear_deformation) {
                        if name != "shear_fixed" {
                            sd.shear_coefficient =
                                step(sd.shear_coefficient, sd0.shear_coefficient, uniform()).min(1.0);
                        }
                    }
                    solver.modal(black_box(&walk), 3).unwrap()
                })
            });
        }
        c.bench_function(&format!("state_space_N{n_iv}"), |bch| {
            bch.iter(|| modal_state_space(black_box(&b), 3).unwrap())
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
