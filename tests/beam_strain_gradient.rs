//! The strain gradient (issue 65, `strain_gradient_length_nm`) in the forward
//! model. References, none of them `src/`'s assembly or solvers (generator:
//! this file's own code, below):
//! - simply supported: the closed form ω² = EIq⁴(1 + l²q²)/(ρA(1 + (e0a)²q²)),
//!   q = rπ/L (the sine modes are exact under w = w″ = w⁗ = 0,
//!   `beam::fe::scaling`'s module doc), and with a relaxation the root of its
//!   family s² + ω²G(s) = 0, by Newton here;
//! - clamped–clamped (w = w′ = 0 and the natural l²EIw‴ = 0): a global
//!   Rayleigh–Ritz solution in Legendre polynomials times x²(1 − x)², built,
//!   integrated (Gauss–Legendre nodes by Newton here) and solved (nalgebra's
//!   dense symmetric eigensolver) in this file, converged to ~1e-11;
//! - the Rayleigh quotient of the quintic Hermite interpolant of a sine mode,
//!   the interpolant solved here from its six nodal conditions: the upper
//!   bound the FE eigenvalue may not exceed (derivation at its use).
//!
//! Every tolerance is derived beside it.

mod quadrature;

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};
use nanobeam::beam::{
    modal, modal_state_space, BeamSpec, InternalVariable, ModalSolver, PointMass, SolverPath, Support,
};
use num_complex::Complex64;
use quadrature::gauss_legendre;

/// The paper's short SWCNT (L/d = 8).
fn swcnt(support: Support, elements: usize) -> BeamSpec {
    BeamSpec::elastic(8.0, 1.0, 1e12, 2300.0, support, elements)
}

/// ω_ref² = EI/(ρA L⁴): the scaled eigenvalue's unit.
fn omega_ref2(b: &BeamSpec) -> f64 {
    let l = b.length_nm * 1e-9;
    b.youngs_modulus_pa * b.inertia_m4() / (b.density_kg_m3 * b.area_m2() * l.powi(4))
}

/// (l/L, e0a/L) of a beam.
fn scaled_lengths(b: &BeamSpec) -> (f64, f64) {
    (b.strain_gradient_length_nm / b.length_nm, b.nonlocal_e0a_nm / b.length_nm)
}

/// Scaled closed form: λ̃ = q⁴(1 + l̃²q²)/(1 + ẽ²q²), q = rπ.
fn closed_form_lambda(lt: f64, et: f64, r: usize) -> f64 {
    let q = r as f64 * PI;
    q.powi(4) * (1.0 + lt * lt * q * q) / (1.0 + et * et * q * q)
}

/// The Rayleigh quotient (∫w″² + l̃²∫w‴²)/(∫w² + ẽ²∫w′²) of the quintic
/// Hermite interpolant of sin(rπx̃) on `elements` equal elements of [0, 1]:
/// on each element the quintic with the sine's value, slope and curvature at
/// both ends, solved here from those six conditions in the monomial basis.
fn interpolant_quotient(r: usize, elements: usize, lt: f64, et: f64) -> f64 {
    interpolant_quotient_of(r, elements, lt, et, 0)
}

/// [`interpolant_quotient`] with the denominator's derivatives raised by
/// `shift`: 0 for the vibration pencil, 1 for the buckling one
/// (∫w′² + ẽ²∫w″²: the axial force with Eringen's operator on it).
fn interpolant_quotient_of(r: usize, elements: usize, lt: f64, et: f64, shift: i32) -> f64 {
    let h = 1.0 / elements as f64;
    let a = r as f64 * PI;
    // p(ξ) = Σ cₖξᵏ on ξ ∈ [0, 1]; rows: p(0), p′(0), p″(0), p(1), p′(1), p″(1) (ξ-derivatives)
    let rows = DMatrix::from_fn(6, 6, |i, k| {
        let (at_one, order) = (i >= 3, i % 3);
        let kk = k as i32;
        if kk < order as i32 {
            return 0.0;
        }
        let f: f64 = (0..order).map(|j| f64::from(kk - j as i32)).product();
        // at ξ = 1 every power counts, at ξ = 0 only ξ^order
        if at_one || k == order {
            f
        } else {
            0.0
        }
    });
    let lu = rows.lu();
    let gauss = gauss_legendre(8);
    let (mut num, mut den) = (0.0, 0.0);
    for e in 0..elements {
        let x0 = e as f64 * h;
        let nodal = |x: f64| [(a * x).sin(), h * a * (a * x).cos(), -h * h * a * a * (a * x).sin()];
        let (n0, n1) = (nodal(x0), nodal(x0 + h));
        let rhs = DVector::from_vec(vec![n0[0], n0[1], n0[2], n1[0], n1[1], n1[2]]);
        let c = lu.solve(&rhs).expect("the Hermite conditions are regular");
        // the m-th x-derivative at ξ
        let deriv = |xi: f64, m: i32| -> f64 {
            (m as usize..6)
                .map(|k| {
                    let f: f64 = (0..m).map(|j| f64::from(k as i32 - j)).product();
                    f * c[k] * xi.powi(k as i32 - m)
                })
                .sum::<f64>()
                / h.powi(m)
        };
        for &(xi, w) in &gauss {
            let (w2, w3) = (deriv(xi, 2), deriv(xi, 3));
            let (d0, d1) = (deriv(xi, shift), deriv(xi, shift + 1));
            num += h * w * (w2 * w2 + lt * lt * w3 * w3);
            den += h * w * (d0 * d0 + et * et * d1 * d1);
        }
    }
    num / den
}

/// Simply supported, elastic: the FE ω² against the closed form, local and
/// nonlocal, l from a tenth of e0a to 0.4 L.
///
/// Tolerance (two-sided, rigorous): the quintic mesh is a conforming subspace
/// of the beam's energy space with the essential conditions w = w″ = 0, so by
/// min–max the FE λ_r ≥ the exact λ_r; and on the uniform simply supported
/// mesh the FE eigenvectors split by wavenumber into (w, θ, χ) blocks of the
/// patterns (sin, cos, sin)(rπxᵢ) that contain the interpolant I sin(rπx),
/// so the lowest eigenvalue of block r, the FE λ_r for r ≪ elements, is at
/// most the Rayleigh quotient of I sin(rπx) ([`interpolant_quotient`]). That
/// bound falls as h⁶ (the interpolant's w‴ error is O(h³)). Below, −1e-12·ω²
/// for the round-off of the refined eigenvalue (~1e-14 relative, the
/// element-energy Rayleigh quotient) and of the closed form.
#[test]
fn simply_supported_matches_the_closed_form() {
    let mut worst = 0.0f64;
    for e0a in [0.0, 1.2] {
        for lg in [0.12, 0.8, 1.5, 3.2] {
            let mut b = swcnt(Support::SimplySupported, 20);
            b.nonlocal_e0a_nm = e0a;
            b.strain_gradient_length_nm = lg;
            let (lt, et) = scaled_lengths(&b);
            let w = modal(&b, 6).unwrap();
            for r in 1..=6 {
                let exact = closed_form_lambda(lt, et, r) * omega_ref2(&b);
                let upper = interpolant_quotient(r, 20, lt, et) * omega_ref2(&b);
                let got = w.modes[r - 1].omega_rad_s.powi(2);
                let err = got - exact;
                worst = worst.max(err / exact);
                assert!(
                    err >= -1e-12 * exact && got <= upper + 1e-12 * exact,
                    "e0a {e0a} l {lg} mode {r}: ω² {got:e} vs {exact:e} (err {err:e}, Ritz bound {:e})",
                    upper - exact
                );
            }
        }
    }
    eprintln!("simply supported: largest relative ω² error {worst:e}");
}

/// The oscillatory root of s² + λ(1 + Δs/(s + Ω)) = 0, by Newton on
/// (s² + λ)(s + Ω) + λΔs from i√λ (rad/s).
fn relaxed_pole(lambda: f64, delta: f64, omega: f64) -> Complex64 {
    let mut s = Complex64::new(0.0, lambda.sqrt());
    for _ in 0..200 {
        let f = (s * s + lambda) * (s + omega) + lambda * delta * s;
        let df = 2.0 * s * (s + omega) + s * s + lambda + lambda * delta;
        let step = f / df;
        s -= step;
        if step.norm() <= 1e-16 * s.norm() {
            break;
        }
    }
    s
}

/// Simply supported with a relaxation (one internal variable) and e0a: the
/// FE pole against the closed-form family's root at the exact λ. The FE λ
/// lies in [λ, λ_up] (previous test's bound), so its pole lies within
/// |s(λ_up) − s(λ)| of the exact one to first order; the factor 1.01 covers
/// the second order (Δλ/λ ≤ 1e-4 here), and 1e-10|s| the family root
/// solver's and the Newton root's round-off. The path is the decoupled one
/// (D̃ ∝ M̃ and one K̃ that G(s) multiplies whole).
#[test]
fn simply_supported_with_relaxation_matches_the_closed_form_family() {
    let mut b = swcnt(Support::SimplySupported, 20);
    b.nonlocal_e0a_nm = 1.2;
    b.strain_gradient_length_nm = 1.5;
    b.internal_variables = vec![InternalVariable { delta: 0.3, omega_rad_s: 4e11 }];
    let (lt, et) = scaled_lengths(&b);
    let mut solver = ModalSolver::new();
    let got = solver.modal(&b, 5).unwrap();
    assert_eq!(solver.last_path(), Some(SolverPath::Decoupled));
    let mut worst = 0.0f64;
    for r in 1..=5 {
        let lambda = closed_form_lambda(lt, et, r) * omega_ref2(&b);
        let lambda_up = interpolant_quotient(r, 20, lt, et) * omega_ref2(&b);
        let exact = relaxed_pole(lambda, 0.3, 4e11);
        let spread = (relaxed_pole(lambda_up, 0.3, 4e11) - exact).norm();
        let pole = got.mode(r).unwrap().pole;
        let err = (pole - exact).norm();
        worst = worst.max(err / exact.norm());
        assert!(
            err <= 1.01 * spread + 1e-10 * exact.norm(),
            "mode {r}: {pole} vs {exact} (err {err:e}, bound {spread:e})"
        );
    }
    eprintln!("relaxed: largest relative pole error {worst:e}");
}

/// Legendre Pₖ(t) and its first three t-derivatives, k < n, at t
/// (P⁽ᵐ⁾ₖ₊₁ = P⁽ᵐ⁾ₖ₋₁ + (2k + 1)P⁽ᵐ⁻¹⁾ₖ).
fn legendre_derivatives(n: usize, t: f64) -> Vec<[f64; 4]> {
    let mut p = vec![[0.0; 4]; n.max(2)];
    p[0] = [1.0, 0.0, 0.0, 0.0];
    p[1] = [t, 1.0, 0.0, 0.0];
    for k in 1..n.max(2) - 1 {
        let kf = k as f64;
        let mut next = [0.0; 4];
        next[0] = ((2.0 * kf + 1.0) * t * p[k][0] - kf * p[k - 1][0]) / (kf + 1.0);
        for m in 1..4 {
            next[m] = p[k - 1][m] + (2.0 * kf + 1.0) * p[k][m - 1];
        }
        p[k + 1] = next;
    }
    p.truncate(n);
    p
}

/// The lowest `count` scaled eigenvalues of the clamped–clamped strain-gradient
/// beam by global Rayleigh–Ritz: φₖ = x²(1 − x)²Pₖ(2x − 1), k < n (w = w′ = 0
/// at both ends; w″ free, so the natural l²w‴ = 0 holds in the limit),
/// K = ∫φ″φ″ᵀ + l̃²∫φ‴φ‴ᵀ, M = ∫φφᵀ + ẽ²∫φ′φ′ᵀ by 60-point Gauss (exact: the
/// integrands are polynomials of degree ≤ 2n + 6), M = LLᵀ, eig(L⁻¹KL⁻ᵀ).
fn ritz_clamped(n: usize, lt: f64, et: f64, count: usize) -> Vec<f64> {
    let gauss = gauss_legendre(60);
    let mut k = DMatrix::<f64>::zeros(n, n);
    let mut m = DMatrix::<f64>::zeros(n, n);
    for &(x, w) in &gauss {
        // g = x²(1 − x)² = x² − 2x³ + x⁴ and its derivatives
        let g = [
            x * x - 2.0 * x.powi(3) + x.powi(4),
            2.0 * x - 6.0 * x * x + 4.0 * x.powi(3),
            2.0 - 12.0 * x + 12.0 * x * x,
            -12.0 + 24.0 * x,
        ];
        let p = legendre_derivatives(n, 2.0 * x - 1.0);
        // x-derivatives of Pₖ(2x − 1): 2ᵐ P⁽ᵐ⁾
        let phi: Vec<[f64; 4]> = p
            .iter()
            .map(|pk| {
                let d = [pk[0], 2.0 * pk[1], 4.0 * pk[2], 8.0 * pk[3]];
                [
                    g[0] * d[0],
                    g[1] * d[0] + g[0] * d[1],
                    g[2] * d[0] + 2.0 * g[1] * d[1] + g[0] * d[2],
                    g[3] * d[0] + 3.0 * g[2] * d[1] + 3.0 * g[1] * d[2] + g[0] * d[3],
                ]
            })
            .collect();
        for i in 0..n {
            for j in 0..n {
                k[(i, j)] += w * (phi[i][2] * phi[j][2] + lt * lt * phi[i][3] * phi[j][3]);
                m[(i, j)] += w * (phi[i][0] * phi[j][0] + et * et * phi[i][1] * phi[j][1]);
            }
        }
    }
    let l = m.cholesky().expect("M is positive definite").l();
    let linv = l.clone().try_inverse().expect("L is regular");
    let c = &linv * k * linv.transpose();
    let c = (&c + c.transpose()) * 0.5;
    let mut ev: Vec<f64> = c.symmetric_eigen().eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev.truncate(count);
    ev
}

/// The Ritz reference's relative accuracy: 16 and 20 Legendre terms must
/// agree to it. Measured (l = 1.2 nm, e0a = 0.9 nm on L = 8 nm, modes 1–4):
/// the truncation error is spectral (mode 1 settles to 1e-11 by 12 terms),
/// while the round-off of the L⁻¹KL⁻ᵀ route grows with the basis's
/// conditioning, ~1.5e-11 at 20 terms and 1e-10 at 24–32; 20 terms sit at
/// that crossing, and 5e-11 is the larger of the two with a factor ~3.
const REF_TOL: f64 = 5e-11;

/// Clamped–clamped: the FE eigenvalues converge to the Ritz reference from
/// above at the quintic element's rate.
///
/// The reference: 16 and 20 Legendre terms agree to [`REF_TOL`]. The FE: a
/// conforming subspace (w = w′ = 0 essential), so λ_h ≥ λ (−REF_TOL for the
/// reference's own error);
/// the Rayleigh–Ritz error is the squared energy-norm error of the best
/// approximation, O(h³)² = O(h⁶) for the l² part (H³ seminorm, quintic) and
/// O(h⁸) for the EI part, so halving h must divide the error by at least
/// 2⁶/2 = 32 (one halving of slack for the pre-asymptotic constant at
/// 6 elements, where mode 4 has ~1.5 elements per half-wave) and by at most
/// 2⁸·2 (the faster EI part cannot beat its own rate).
#[test]
fn clamped_clamped_converges_at_the_quintic_rate_to_an_independent_ritz_solution() {
    let (lg, e0a) = (1.2, 0.9);
    let modes = 4;
    let probe = {
        let mut b = swcnt(Support::ClampedClamped, 2);
        b.strain_gradient_length_nm = lg;
        b.nonlocal_e0a_nm = e0a;
        b
    };
    let (lt, et) = scaled_lengths(&probe);
    let reference = ritz_clamped(20, lt, et, modes);
    let check = ritz_clamped(16, lt, et, modes);
    for (a, b) in reference.iter().zip(&check) {
        assert!((a / b - 1.0).abs() <= REF_TOL, "Ritz reference not converged: {a} vs {b}");
    }
    let fe = |elements: usize| -> Vec<f64> {
        let mut b = probe.clone();
        b.elements = elements;
        let w = modal(&b, modes).unwrap();
        w.modes.iter().map(|m| m.omega_rad_s.powi(2) / omega_ref2(&b)).collect()
    };
    let errors: Vec<Vec<f64>> =
        [6, 12, 24].iter().map(|&ne| fe(ne).iter().zip(&reference).map(|(h, r)| (h - r) / r).collect()).collect();
    for (level, errs) in errors.iter().enumerate() {
        for (r, e) in errs.iter().enumerate() {
            assert!(*e >= -REF_TOL, "mesh {level} mode {}: below the exact eigenvalue ({e:e})", r + 1);
        }
    }
    let [coarse, mid, fine] = [&errors[0], &errors[1], &errors[2]];
    for (r, ((e1, e2), e3)) in coarse.iter().zip(mid).zip(fine).enumerate() {
        let ratio = e1 / e2;
        eprintln!("mode {}: rel. errors {e1:e} (6), {e2:e} (12), {e3:e} (24); rate {:.2}", r + 1, ratio.log2());
        assert!((32.0..=512.0).contains(&ratio), "mode {}: error ratio {ratio} (errors {e1:e}, {e2:e})", r + 1);
        // 24 elements: the error is at the reference's round-off or within 12's/32
        assert!(*e3 <= e2 / 32.0 + REF_TOL, "mode {}: {e3:e} vs {e2:e}", r + 1);
    }
}

/// l → 0: the C² mesh's modes approach the ordinary (cubic Hermite) beam's on
/// every support. The two meshes differ by their own discretisation errors:
/// the cubic one's is ≤ 2(βh)⁴/720 relative to leading order (Rayleigh–Ritz
/// of cubic Hermite elements, `tests/beam_foundation.rs`; β the mode's
/// wavenumber, below (r + 1)π on every support; factor 2 for the O((βh)⁶)
/// rest), the quintic one's far below it, and l = 1e-5 nm adds
/// l̃²β² ≤ 2e-10 relative.
///
/// With a rotational spring at a pinned end (simply supported, clamped–pinned,
/// k_r L/EI = 10 and a second, one-end spring), the same: the C² mesh keeps
/// w″ free there (`beam::fe::scaling`), so the l → 0 limit is the classical
/// spring condition (with w″ = 0 imposed it missed it by O(h): 0.28 % in ω₁
/// at 40 elements, ten times this bound).
#[test]
fn vanishing_length_scale_is_continuous_with_the_ordinary_beam() {
    let mut beams: Vec<BeamSpec> = Support::ALL.iter().map(|&s| swcnt(s, 40)).collect();
    let k_ref = 1e12 * swcnt(Support::SimplySupported, 40).inertia_m4() / 8e-9;
    for support in [Support::SimplySupported, Support::ClampedPinned] {
        let mut b = swcnt(support, 40);
        b.support_rotational_stiffness_n_m_rad = 10.0 * k_ref;
        beams.push(b);
    }
    let mut one_end = swcnt(Support::SimplySupported, 40);
    one_end.support_rotational_stiffness_left_n_m_rad = 3.0 * k_ref;
    beams.push(one_end);
    for mut b in beams {
        let support = b.support;
        b.nonlocal_e0a_nm = 0.9;
        let plain = modal(&b, 4).unwrap();
        b.strain_gradient_length_nm = 1e-5;
        let graded = modal(&b, 4).unwrap();
        for (r, (p, g)) in plain.modes.iter().zip(&graded.modes).enumerate() {
            let beta_h = (r as f64 + 2.0) * PI / 40.0;
            let bound = 2.0 * beta_h.powi(4) / 720.0 + 1e-9;
            let rel = (g.omega_rad_s.powi(2) / p.omega_rad_s.powi(2) - 1.0).abs();
            assert!(rel <= bound, "{support:?} mode {}: {rel:e} > {bound:e}", r + 1);
        }
    }
}

/// The stiffening is monotone in l and the SS ratio ω(l)/ω(0) follows
/// √(1 + l²q²) on the same C² mesh (the e0a and mesh factors cancel in
/// the ratio to the FE error bound of the first test, 1e-6 here).
#[test]
fn stiffening_grows_with_l_as_the_closed_form_ratio() {
    let mut b = swcnt(Support::SimplySupported, 24);
    b.strain_gradient_length_nm = 1e-6;
    let base = modal(&b, 3).unwrap();
    let mut last = base.modes[0].omega_rad_s;
    for lg in [0.5, 1.0, 2.0, 4.0] {
        b.strain_gradient_length_nm = lg;
        let w = modal(&b, 3).unwrap();
        assert!(w.modes[0].omega_rad_s > last);
        last = w.modes[0].omega_rad_s;
        for r in 1..=3 {
            let q = r as f64 * PI / b.length_nm;
            let want = (1.0 + lg * lg * q * q).sqrt();
            let ratio = w.modes[r - 1].omega_rad_s / base.modes[r - 1].omega_rad_s;
            assert!((ratio / want - 1.0).abs() <= 1e-6, "l {lg} mode {r}: {ratio} vs {want}");
        }
    }
}

/// The coupled paths take the strain gradient too, and no fast path of the
/// cubic mesh does: a point mass with damping (coupled RQI on T(s)) and an
/// axial force, springs and a foundation, the kinds the axial and point-mass
/// fast paths hold, against the state-space reference on the same matrices
/// (a different algorithm; agreement to its ~eps·κ(A) error, 1e-8 relative
/// as in `tests/beam_foundation.rs`'s coupled checks). The simply supported
/// compression with damping, without springs or a point mass, is the one
/// case the C² mesh's own wavenumber blocks take (`gradient_blocks.rs`,
/// `tests/beam_gradient_blocks.rs`); the others stay on the reference.
#[test]
fn coupled_paths_agree_with_the_state_space() {
    let mut cases = Vec::new();
    let mut b = swcnt(Support::ClampedFree, 10);
    b.strain_gradient_length_nm = 1.0;
    b.nonlocal_e0a_nm = 0.6;
    b.viscous_damping_n_s_m2 = 2e-6;
    b.point_mass = Some(PointMass { mass_kg: 2e-25, x_nm: 5.0 });
    cases.push(("point mass + C", b));
    let mut b = swcnt(Support::SimplySupported, 10);
    b.strain_gradient_length_nm = 0.8;
    b.axial_force_n = 2e-9;
    b.support_rotational_stiffness_n_m_rad = 1e-18;
    b.internal_variables = vec![InternalVariable { delta: 0.2, omega_rad_s: 5e11 }];
    cases.push(("axial + springs + relaxation", b));
    let mut b = swcnt(Support::ClampedPinned, 10);
    b.strain_gradient_length_nm = 2.0;
    b.elastic_foundation_n_m2 = 3e8;
    b.viscous_damping_n_s_m2 = 1e-6;
    cases.push(("foundation + C", b));
    let mut b = swcnt(Support::SimplySupported, 10);
    b.strain_gradient_length_nm = 0.5;
    b.axial_force_n = -1e-9;
    b.viscous_damping_n_s_m2 = 1e-6;
    cases.push(("compression + C (the axial fast path's kind)", b));
    let mut b = swcnt(Support::SimplySupported, 10);
    b.strain_gradient_length_nm = 0.5;
    b.point_mass = Some(PointMass { mass_kg: 1e-25, x_nm: 3.0 });
    cases.push(("point mass, C = 0 (the mass spectrum's kind)", b));
    for (name, b) in cases {
        // every fast path of the cubic mesh declines the C² mesh
        let mut solver = ModalSolver::new();
        let fast = solver.modal(&b, 4).unwrap();
        let fast_path = solver.last_used_interpolant()
            || solver.last_used_axial_blocks()
            || solver.last_used_spring_blocks()
            || solver.last_used_spring_mass_blocks()
            || solver.last_used_mass_blocks()
            || solver.last_used_shear_blocks()
            || solver.last_used_shear_continuum();
        assert!(!fast_path, "{name}: a fast path of the cubic mesh took the strain gradient");
        let blocks = name.starts_with("compression");
        assert_eq!(solver.last_used_gradient_blocks(), blocks, "{name}: the C² blocks");
        let reference = modal_state_space(&b, 4).unwrap();
        for (f, r) in fast.modes.iter().zip(&reference.modes) {
            assert!((f.pole - r.pole).norm() <= 1e-8 * r.pole.norm(), "{name}: {f:?} vs {r:?}");
        }
    }
}

/// Bad input: one-line errors naming the field, its value and the range;
/// shear deformation with a strain gradient refused naming both fields.
#[test]
fn bad_length_scales_are_refused_with_the_field() {
    for bad in [-0.1, f64::NAN, f64::INFINITY, 8.5] {
        let mut b = swcnt(Support::SimplySupported, 10);
        b.strain_gradient_length_nm = bad;
        let e = b.validate().unwrap_err();
        assert_eq!(e.field, "strain_gradient_length_nm", "{e}");
        assert!(e.allowed.contains("<= 8"), "{e}");
        assert!(modal(&b, 2).is_err());
    }
    let mut b = swcnt(Support::SimplySupported, 10);
    b.strain_gradient_length_nm = 1.0;
    b.shear_deformation = Some(nanobeam::beam::ShearDeformation { poisson_ratio: 0.2, shear_coefficient: 0.9 });
    let e = b.validate().unwrap_err();
    assert!(e.field == "strain_gradient_length_nm" && e.allowed.contains("shear_deformation"), "{e}");
    let yaml = "length_nm: 8\ndiameter_nm: 1\nyoungs_modulus_pa: 1e12\ndensity_kg_m3: 2300\nsupport: simply-supported\nelements: 10\nstrain_gradient_length_nm: 1.5\n";
    let b = BeamSpec::from_yaml(yaml).unwrap();
    assert_eq!(b.strain_gradient_length_nm, 1.5);
}

/// The largest length scale (l = L, `MAX_GRADIENT_TILDE`) on the smallest
/// and the largest mesh a strain gradient allows (`MAX_GRADIENT_ELEMENTS`):
/// finite modes on every support, and the simply supported ones within
/// the first test's two-sided Ritz bound (with the round-off derived at the
/// assert); 51 elements are refused naming the field.
#[test]
fn the_largest_length_scale_gives_finite_modes_on_every_support() {
    for support in Support::ALL {
        for elements in [2, 50] {
            let mut b = swcnt(support, elements);
            b.strain_gradient_length_nm = b.length_nm;
            let n = if elements == 2 { 1 } else { 6 };
            let w = modal(&b, n).unwrap();
            assert!(w.modes.iter().all(|m| m.omega_rad_s.is_finite() && m.omega_rad_s > 0.0), "{support:?} {elements}");
            if support == Support::SimplySupported && elements == 50 {
                for r in 1..=6 {
                    let exact = closed_form_lambda(1.0, 0.0, r) * omega_ref2(&b);
                    let upper = interpolant_quotient(r, 50, 1.0, 0.0) * omega_ref2(&b);
                    let got = w.modes[r - 1].omega_rad_s.powi(2);
                    // round-off of the eigenvalue's Rayleigh quotient: w‴ is
                    // formed from nodal terms ~h⁻³ times a mode's w‴ ~ q³, a
                    // cancellation of (qh)⁻³ (4e3 for mode 1 on 50 elements;
                    // 2.6e2 on the first test's 20), times a few eps for the
                    // sums (measured 1.7e-12 for mode 1 here)
                    let roundoff = 4.0 * f64::EPSILON * (50.0 / (r as f64 * PI)).powi(3) + 1e-12;
                    assert!(
                        got >= exact * (1.0 - roundoff) && got <= upper + roundoff * exact,
                        "mode {r}: {got:e} vs {exact:e} (round-off {roundoff:e})"
                    );
                }
            }
        }
        let mut b = swcnt(support, 51);
        b.strain_gradient_length_nm = 0.1;
        assert_eq!(b.validate().unwrap_err().field, "elements");
    }
}

/// The static receptance (ω = 0) through the FRF solver, which uses the C²
/// mesh's load vector N − ẽ²N″ (Eringen's operator on the point force) and
/// interpolation vector: against the simply supported series
/// H = Σ (2/L) sin(qx₀) sin(qx)(1 + (e0a)²q²)/(EI q⁴(1 + l²q²)), q = nπ/L
/// (the sine expansion of EI(w⁗ − l²w⁽⁶⁾) = (1 − (e0a)²∂²)δ(x − x₀); 20 000
/// terms, tail ≲ (e0a/l)²/(3π⁴N³) relative). The force and the outputs on
/// nodes: the solution is smooth on every element, its H³ error O(h³) and a
/// point value's, by duality with the equally smooth Green's function,
/// O(h⁶); halving h must divide the error by at least 2⁴ (two orders of
/// slack for the constant: the nonlocal load's δ″ part is the roughest term).
#[test]
fn static_receptance_matches_the_series() {
    let (lg, e0a) = (1.0, 1.2);
    let series = |b: &BeamSpec, x0: f64, x: f64| -> f64 {
        let l = b.length_nm * 1e-9;
        let ei = b.youngs_modulus_pa * b.inertia_m4();
        (1..=20_000)
            .map(|n| {
                let q = n as f64 * PI / l;
                2.0 / l * (q * x0 * 1e-9).sin() * (q * x * 1e-9).sin() * (1.0 + (e0a * 1e-9 * q).powi(2))
                    / (ei * q.powi(4) * (1.0 + (lg * 1e-9 * q).powi(2)))
            })
            .sum()
    };
    for (x0, x) in [(4.0, 4.0), (4.0, 2.0), (2.0, 6.0)] {
        let errors: Vec<f64> = [10, 20]
            .iter()
            .map(|&ne| {
                let mut b = swcnt(Support::SimplySupported, ne);
                b.strain_gradient_length_nm = lg;
                b.nonlocal_e0a_nm = e0a;
                let h = nanobeam::beam::frf(&b, x0, x, &[0.0]).unwrap()[0];
                let exact = series(&b, x0, x);
                assert!(h.im.abs() <= 1e-12 * exact.abs(), "static receptance not real: {h}");
                (h.re - exact).abs() / exact.abs()
            })
            .collect();
        eprintln!("x0 {x0} x {x}: rel. errors {:e} (10), {:e} (20)", errors[0], errors[1]);
        assert!(errors[1] <= errors[0] / 16.0 + 1e-12, "x0 {x0} x {x}: {errors:?}");
    }
}

/// The buckling load of a simply supported strain-gradient beam (the bound
/// `validate` holds a compression to): N_cr = −EIq²(1 + l²q²)/(1 + (e0a)²q²),
/// q = π/L (the static sixth-order equation with Eringen's operator on the
/// force, sine mode). Two-sided as the first test: the conforming C² mesh
/// bounds |N_cr| from above by min–max, and the first wavenumber block's
/// lowest eigenvalue from above by the interpolant's quotient
/// (∫w″² + l̃²∫w‴²)/(∫w′² + ẽ²∫w″²). Round-off: the buckling solve takes its
/// Rayleigh quotient from the assembled K̃ (`buckling_load_n`), whose terms
/// cancel: per node the w–w entries are 1440 l̃²/h̃⁵ (∫(H₀‴)² = 720/h̃⁵ per
/// element) and 240/(7h̃³) (∫(H₀″)²), summed over 1/h̃ nodes against the mode's
/// energy (π⁴ + l̃²π⁶)/2, a cancellation F = (1440 l̃²/h̃⁶ + 34/h̃⁴)/(π⁴ + l̃²π⁶);
/// the allowance is 10·eps·F (the band's other entries are of the same
/// size; F·eps = 1.9e-9 at l̃ = 0.1, measured error 1e-10). A compression
/// just inside the bound is accepted, one just beyond refused naming the
/// field.
#[test]
fn buckling_load_matches_the_closed_form() {
    for (lg, e0a) in [(0.8, 0.0), (1.5, 1.2), (4.0, 0.5)] {
        let mut b = swcnt(Support::SimplySupported, 20);
        b.strain_gradient_length_nm = lg;
        b.nonlocal_e0a_nm = e0a;
        let (lt, et) = scaled_lengths(&b);
        let l = b.length_nm * 1e-9;
        let unit = b.youngs_modulus_pa * b.inertia_m4() / (l * l);
        let q2 = PI * PI;
        let exact = unit * q2 * (1.0 + lt * lt * q2) / (1.0 + et * et * q2);
        let upper = unit * interpolant_quotient_of(1, 20, lt, et, 1);
        let got = -nanobeam::beam::buckling_load_n(&b).unwrap();
        let h: f64 = 1.0 / 20.0;
        let cancel = (1440.0 * lt * lt / h.powi(6) + 34.0 / h.powi(4)) / (q2 * q2 + lt * lt * q2 * q2 * q2);
        let roundoff = 10.0 * f64::EPSILON * cancel;
        assert!(
            got >= exact * (1.0 - roundoff) && got <= upper + roundoff * exact,
            "l {lg} e0a {e0a}: {got:e} vs {exact:e} (Ritz bound {:e}, round-off {roundoff:e})",
            upper - exact
        );
        eprintln!("l {lg} e0a {e0a}: rel. error {:e} (round-off allowance {roundoff:e})", got / exact - 1.0);
        b.axial_force_n = -0.999 * got;
        assert!(b.validate().is_ok());
        b.axial_force_n = -1.001 * got;
        assert_eq!(b.validate().unwrap_err().field, "axial_force_n");
    }
}
