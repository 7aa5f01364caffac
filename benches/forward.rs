//! One forward evaluation (20 elements, 3 modes): fast exact path (b), the
//! general path (c) with a support spring, and the state-space reference (a),
//! for N = 1 and N = 2 internal variables. `cold` builds a fresh solver every
//! call; `warm` reuses a `ModalSolver` while E is perturbed each call (the
//! scaled pencil — and thus its cached eigenvalues — is unchanged, as in a
//! calibration of E, ρ, C, Δ, Ω).

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
        internal_variables: [InternalVariable { delta: 0.1, omega_rad_s: 1e11 }, InternalVariable { delta: 0.05, omega_rad_s: 3e12 }]
            [..n_iv]
            .to_vec(),
        support_rotational_stiffness_n_m_rad: 0.0,
        point_mass: None,
    }
}

fn bench(c: &mut Criterion) {
    for n_iv in [1, 2] {
        let b = beam(n_iv);
        c.bench_function(&format!("fast_cold_N{n_iv}"), |bch| bch.iter(|| modal(black_box(&b), 3).unwrap()));
        let mut solver = ModalSolver::new();
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
        c.bench_function(&format!("general_spring_N{n_iv}"), |bch| bch.iter(|| modal(black_box(&bs), 3).unwrap()));
        c.bench_function(&format!("state_space_N{n_iv}"), |bch| bch.iter(|| modal_state_space(black_box(&b), 3).unwrap()));
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
