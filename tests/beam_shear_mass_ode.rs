//! Issue 41: the continuum point-mass path of the simply supported nonlocal
//! Timoshenko beam (`beam/shear_continuum.rs`, `mass_family_roots`) against
//! an oracle written here that shares no code or formulation with it: the
//! beam as a two-point boundary value problem, solved by transfer matrices.
//!
//! Why not the mesh. The Timoshenko mesh (`element.rs`) carries the shear
//! field as a cubic Hermite with γ = w_s′ a nodal DOF, so γ is continuous;
//! under a point mass the shear force jumps, and so does γ. The mesh cannot
//! follow the jump even with the mass on a node, and converges at O(h) to
//! O(h²), unevenly between levels (measured on random beams: |Δ₂| > |Δ₁| seen,
//! rates 2–5), so no Richardson bound of the mesh's error holds at 20–80
//! elements. The continuum has no such error; this oracle checks it.
//!
//! The oracle. The undamped relaxed beam of `model.rs` in scaled units is
//! the stationary point of
//!   ∫ θ′² + g̃(w′ − θ)² − λ[w² + r̃²θ² + ẽ²(w′² + r̃²θ′²)] dx − λμ̃ w(x̃)²
//! (the forms of `ScaledModel::new`), whose Euler–Lagrange equations are
//!   (g̃ − λẽ²) w″ = g̃θ′ − λw,   (1 − λẽ²r̃²) θ″ = −g̃(w′ − θ) − λr̃²θ,
//! with w = 0 and θ′ = 0 at the simply supported ends (the natural condition
//! of θ), w, θ and θ′ continuous at x̃, and Q = (g̃ − λẽ²)w′ − g̃θ jumping by
//! −λμ̃w(x̃) there. With y = (w, w′, θ, θ′), y′ = A(λ)y on each side; the
//! solutions from x = 0 (columns w′(0), θ(0)) carried to x̃ by e^{A x̃} and
//! across the jump, and those from x = 1 carried back by e^{−A(1 − x̃)}, must
//! meet: λ is an eigenvalue exactly where the 4 × 4 matching determinant
//! vanishes. nalgebra's matrix exponential (`Matrix4::exp`) does the carrying.
//!
//! Data: generated here (ChaCha8, seed in the test): the diagnosis's nominal
//! beam (L = 8 nm, d = 1 nm, E = 1 TPa) with shear (κ ∈ [0.3, 1],
//! ν ∈ [0.1, 0.35]), solid or tube section, e0a ∈ [0, 2] nm, a point mass
//! μ̃ log-uniform on [1e-3, 1] anywhere on the span, no damping, 0–2
//! internal variables on half of them. With G(s) = 1 + ΣΔᵢs/(s + Ω̃ᵢ) the
//! whole stiffness relaxes and neither the inertia nor the mass does, so the
//! functional at a pole s is the one above with λ = −s²/G(s): each pole of
//! mode n gives back λ_n exactly, which checks the complex poles against the
//! same oracle.
//!
//! Tolerance (derived). The determinant is evaluated in floating point from
//! columns whose entries grow like e^{√g̃}; its rounding is ≲ 64·eps times
//! Hadamard's bound Π‖c_i‖ on its magnitude (each entry carries the
//! exponential's relative error, ≲ 16·eps for nalgebra's Padé scaling and
//! squaring at these norms, through a 4-term expansion). A root of a function
//! known to ±δ moves by ≤ δ/|∂det/∂λ|, the slope taken by a central
//! difference. The path's eigenvalue must lie within that of a sign change
//! of the determinant, plus the path's own rounding (1e-11 relative: the
//! certified real search stops at 1e-13, the tail's cancellation loses two
//! digits, `shear_continuum.rs`), and the count of sign changes below it must
//! be the mode number less one (the numbering).

mod fast_path_check;

use fast_path_check::{random_relaxations, random_shear_beam};
use nalgebra::{Matrix4, Vector4};
use nanobeam::beam::{BeamSpec, ModalSolver, PointMass};
use num_complex::Complex64;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const MODES: usize = 5;
/// The path's own rounding of λ, relative (module doc).
const PATH_ROUNDING: f64 = 1e-11;

/// The scaled parameters of a beam, computed here from its fields.
struct Scaled {
    g: f64,
    r2: f64,
    e2: f64,
    mu: f64,
    x: f64,
    omega_ref: f64,
}

fn scaled(b: &BeamSpec) -> Scaled {
    let l = b.length_nm * 1e-9;
    let d = b.diameter_nm * 1e-9;
    let (area, inertia) = match &b.section {
        None => (std::f64::consts::PI * d * d / 4.0, std::f64::consts::PI * d.powi(4) / 64.0),
        Some(s) => {
            let t = s.tube.wall_nm * 1e-9;
            (std::f64::consts::PI * d * t, std::f64::consts::PI * d * t * (d * d + t * t) / 8.0)
        }
    };
    let sd = b.shear_deformation.expect("a shear beam");
    let shear_modulus = b.youngs_modulus_pa / (2.0 * (1.0 + sd.poisson_ratio));
    let pm = b.point_mass.as_ref().expect("a point mass");
    let rho_a = b.density_kg_m3 * area;
    Scaled {
        g: sd.shear_coefficient * shear_modulus * area * l * l / (b.youngs_modulus_pa * inertia),
        r2: inertia / (area * l * l),
        e2: (b.nonlocal_e0a_nm / b.length_nm).powi(2),
        mu: pm.mass_kg / (rho_a * l),
        x: pm.x_nm / b.length_nm,
        omega_ref: (b.youngs_modulus_pa * inertia / rho_a).sqrt() / (l * l),
    }
}

/// The matching determinant at λ and Hadamard's bound on its magnitude.
fn matching(p: &Scaled, lambda: f64) -> (f64, f64) {
    let cw = p.g - lambda * p.e2;
    let ct = 1.0 - lambda * p.e2 * p.r2;
    #[rustfmt::skip]
    let a = Matrix4::new(
        0.0, 1.0, 0.0, 0.0,
        -lambda / cw, 0.0, 0.0, p.g / cw,
        0.0, 0.0, 0.0, 1.0,
        0.0, -p.g / ct, (p.g - lambda * p.r2) / ct, 0.0,
    );
    let left = (a * p.x).exp();
    let right = (a * -(1.0 - p.x)).exp();
    let starts = [Vector4::new(0.0, 1.0, 0.0, 0.0), Vector4::new(0.0, 0.0, 1.0, 0.0)];
    let mut m = Matrix4::zeros();
    for (i, y0) in starts.iter().enumerate() {
        let mut y = left * y0;
        y[1] -= lambda * p.mu * y[0] / cw;
        m.set_column(i, &y);
        m.set_column(2 + i, &(-(right * y0)));
    }
    let hadamard: f64 = m.column_iter().map(|c| c.norm()).product();
    (m.determinant(), hadamard)
}

/// The oracle's eigenvalues below `top`: sign changes of the determinant on a
/// geometric grid, each refined by bisection; with the uncertainty of each
/// root (module doc).
fn oracle_eigenvalues(p: &Scaled, top: f64) -> Vec<(f64, f64)> {
    let n = 4000;
    let lo = 1e-3;
    let grid: Vec<f64> = (0..=n).map(|i| lo * (top / lo).powf(i as f64 / n as f64)).collect();
    let mut roots = Vec::new();
    let mut prev = matching(p, grid[0]).0;
    for w in grid.windows(2) {
        let next = matching(p, w[1]).0;
        if prev.signum() != next.signum() {
            let (mut a, mut b) = (w[0], w[1]);
            let sa = prev.signum();
            for _ in 0..200 {
                let mid = 0.5 * (a + b);
                if mid <= a || mid >= b {
                    break;
                }
                if matching(p, mid).0.signum() == sa {
                    a = mid;
                } else {
                    b = mid;
                }
            }
            let root = 0.5 * (a + b);
            let h = 1e-6 * root;
            let slope = (matching(p, root + h).0 - matching(p, root - h).0) / (2.0 * h);
            let (_, hadamard) = matching(p, root);
            let delta = 64.0 * f64::EPSILON * hadamard / slope.abs() + (b - a);
            roots.push((root, delta));
        }
        prev = next;
    }
    roots
}

/// 80 random beams with a point mass: the continuum path is taken, and the
/// λ of modes 1–5 (from the poles, module doc) are the oracle's first five
/// roots (numbering included) within the oracle's uncertainty plus the
/// path's rounding.
#[test]
fn point_mass_poles_are_the_boundary_value_problems_eigenvalues() {
    let mut rng = ChaCha8Rng::seed_from_u64(4146);
    let mut solver = ModalSolver::new();
    let modes: [usize; MODES] = std::array::from_fn(|k| k + 1);
    let mut worst = 0.0f64;
    for i in 0..80 {
        let mut b = random_shear_beam(&mut rng, 20);
        let beam_mass = b.density_kg_m3 * b.area_m2() * b.length_nm * 1e-9;
        let mass_kg = 10f64.powf(rng.gen_range(-3.0..0.0)) * beam_mass;
        b.point_mass = Some(PointMass { mass_kg, x_nm: rng.gen_range(0.0..1.0) * b.length_nm });
        if i % 2 == 1 {
            b.internal_variables = random_relaxations(&mut rng);
        }
        let what = format!("beam {i}: {b:?}");
        let mut out = [0.0; 2 * MODES];
        assert!(solver.observables(&b, &modes, MODES, &mut out).unwrap(), "{what}");
        assert!(solver.last_used_shear_continuum(), "{what}: the continuum path was not taken");
        let p = scaled(&b);
        // λ = −s²/G(s) at each mode's pole s = ω(−ζ + i√(1 − ζ²)) (scaled)
        let lambdas: Vec<f64> = (0..MODES)
            .map(|k| {
                let (w, z) = (out[k] / p.omega_ref, out[MODES + k]);
                let s = w * Complex64::new(-z, (1.0 - z * z).sqrt());
                let g: Complex64 = Complex64::new(1.0, 0.0)
                    + b.internal_variables
                        .iter()
                        .map(|iv| iv.delta * s / (s + iv.omega_rad_s / p.omega_ref))
                        .sum::<Complex64>();
                let lambda = -s * s / g;
                assert!(lambda.im.abs() <= 1e-9 * lambda.re, "{what} mode {}: λ = {lambda} is not real", k + 1);
                lambda.re
            })
            .collect();
        // the grid stops short of λẽ² = g̃, where A(λ) is singular (the bending
        // branch accumulates there, so every mode lies below it)
        let top = lambdas[MODES - 1];
        let accumulation = if p.e2 > 0.0 { p.g / p.e2 } else { f64::INFINITY };
        let oracle = oracle_eigenvalues(&p, top + 0.5 * (0.1 * top).min(accumulation - top));
        assert!(oracle.len() >= MODES, "{what}: the oracle found {} roots", oracle.len());
        for (k, (&lambda, &(root, delta))) in lambdas.iter().zip(&oracle).enumerate() {
            let bound = delta + PATH_ROUNDING * root;
            let diff = (lambda - root).abs();
            assert!(diff <= bound, "{what} mode {}: λ {lambda} against the oracle's {root} ± {delta:e}", k + 1);
            worst = worst.max(diff / root);
        }
    }
    eprintln!("point mass continuum vs boundary value problem: worst relative λ difference {worst:e}");
}
