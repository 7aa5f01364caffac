//! The model's predictions y(θ) = [ω_r, ζ_r], eqs. (34)–(36), for the modes a
//! diagnosis needs.
//!
//! TEMPORARY self-contained implementation (Hermite FE of Appendix 1 with a
//! modal reduction) used until `crate::beam::modal` lands on main; then this
//! function delegates to it and the code below goes.
//!
//! Model: M = ρA(∫NNᵀ + (e0a)²∫N'N'ᵀ) (+ point mass m N(x)N(x)ᵀ), D = (C/ρA)·M_beam
//! (A5 is A4 with C for ρA), K = EI∫N''N''ᵀ (+ rotational springs on the
//! rotation DOF of each supported, rotation-free end). With φ_r the
//! M-orthonormal modes of (K, M), each mode obeys
//! s² + c_r s + k_s,r + k_b,r [1 + Σ Δi s/(s + Ωi)] = 0 (A8 projected), whose
//! complex root is the pole s_r; ω_r = |s_r|, ζ_r = −Re s_r/|s_r| (34–35).

use nalgebra::{DMatrix, DVector};

use crate::beam::{BeamSpec, Support};

/// One mode's predicted modal pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalPair {
    pub omega_rad_s: f64,
    pub zeta: f64,
}

/// Predicts the first `n_modes` modal pairs, sorted by frequency. `Err` when
/// the model cannot produce them (overdamped mode, singular matrices).
pub fn predict(beam: &BeamSpec, n_modes: usize) -> Result<Vec<ModalPair>, String> {
    let ne = beam.elements;
    let l = beam.length_nm * 1e-9;
    let h = l / ne as f64;
    let rho_a = beam.density_kg_m3 * beam.area_m2();
    let ei = beam.youngs_modulus_pa * beam.inertia_m4();
    let ea2 = (beam.nonlocal_e0a_nm * 1e-9).powi(2);
    let ndof = 2 * (ne + 1);
    let mut m = DMatrix::<f64>::zeros(ndof, ndof);
    let mut k = DMatrix::<f64>::zeros(ndof, ndof);
    let cm = [
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h],
    ];
    let cg = [
        [36.0, 3.0 * h, -36.0, 3.0 * h],
        [3.0 * h, 4.0 * h * h, -3.0 * h, -h * h],
        [-36.0, -3.0 * h, 36.0, -3.0 * h],
        [3.0 * h, -h * h, -3.0 * h, 4.0 * h * h],
    ];
    let ck = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
    ];
    for e in 0..ne {
        let o = 2 * e;
        for i in 0..4 {
            for j in 0..4 {
                m[(o + i, o + j)] += rho_a * (h / 420.0 * cm[i][j] + ea2 / (30.0 * h) * cg[i][j]);
                k[(o + i, o + j)] += ei / h.powi(3) * ck[i][j];
            }
        }
    }
    let mut ks = DMatrix::<f64>::zeros(ndof, ndof);
    let kr = beam.support_rotational_stiffness_n_m_rad;
    let (fixed, sprung): (Vec<usize>, Vec<usize>) = match beam.support {
        Support::SimplySupported => (vec![0, ndof - 2], vec![1, ndof - 1]),
        Support::ClampedClamped => (vec![0, 1, ndof - 2, ndof - 1], vec![]),
        Support::ClampedFree => (vec![0, 1], vec![]),
        Support::ClampedPinned => (vec![0, 1, ndof - 2], vec![ndof - 1]),
    };
    for &d in &sprung {
        ks[(d, d)] += kr;
    }
    let mut m_total = m.clone();
    if let Some(pm) = &beam.point_mass {
        let x = (pm.x_nm * 1e-9).clamp(0.0, l);
        let e = ((x / h).floor() as usize).min(ne - 1);
        let xi = x - e as f64 * h;
        let r = xi / h;
        let nv = [
            1.0 - 3.0 * r * r + 2.0 * r.powi(3),
            xi * (1.0 - r).powi(2),
            3.0 * r * r - 2.0 * r.powi(3),
            xi * (r * r - r),
        ];
        for i in 0..4 {
            for j in 0..4 {
                m_total[(2 * e + i, 2 * e + j)] += pm.mass_kg * nv[i] * nv[j];
            }
        }
    }
    let free: Vec<usize> = (0..ndof).filter(|d| !fixed.contains(d)).collect();
    let nf = free.len();
    let sub = |a: &DMatrix<f64>| DMatrix::from_fn(nf, nf, |i, j| a[(free[i], free[j])]);
    let (m_f, mb_f, k_f, ks_f) = (sub(&m_total), sub(&m), sub(&k), sub(&ks));
    let chol = m_f.clone().cholesky().ok_or("mass matrix not positive definite")?;
    let linv = chol.l().try_inverse().ok_or("singular mass matrix")?;
    let a = &linv * (&k_f + &ks_f) * linv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let eig = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..nf).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    if n_modes > nf {
        return Err(format!("{n_modes} modes requested, the mesh has {nf} DOFs"));
    }
    let c_per_rho_a = beam.viscous_damping_n_s_m2 / rho_a;
    let mut out = Vec::with_capacity(n_modes);
    for &idx in order.iter().take(n_modes) {
        let phi: DVector<f64> = linv.transpose() * eig.eigenvectors.column(idx);
        let kb = (phi.transpose() * &k_f * &phi)[(0, 0)];
        let ksr = (phi.transpose() * &ks_f * &phi)[(0, 0)];
        let c = c_per_rho_a * (phi.transpose() * &mb_f * &phi)[(0, 0)];
        out.push(modal_pole(kb, ksr, c, &beam.internal_variables)?);
    }
    out.sort_by(|a, b| a.omega_rad_s.total_cmp(&b.omega_rad_s));
    Ok(out)
}

/// Complex root of s² + c s + ks + kb [1 + Σ Δi s/(s + Ωi)] = 0: the polynomial
/// (s² + c s + ks + kb) Π(s + Ωi) + kb Σ Δi s Π_{j≠i}(s + Ωj), solved in
/// frequency units scaled by √kb through its companion matrix.
fn modal_pole(kb: f64, ks: f64, c: f64, ivs: &[crate::beam::InternalVariable]) -> Result<ModalPair, String> {
    let w0 = (kb + ks).sqrt();
    // polynomials in σ = s / w0, coefficients lowest degree first
    let mul = |p: &[f64], q: &[f64]| {
        let mut r = vec![0.0; p.len() + q.len() - 1];
        for (i, a) in p.iter().enumerate() {
            for (j, b) in q.iter().enumerate() {
                r[i + j] += a * b;
            }
        }
        r
    };
    let kbn = kb / (w0 * w0);
    let mut poly = vec![ks / (w0 * w0) + kbn, c / w0, 1.0];
    for iv in ivs {
        poly = mul(&poly, &[iv.omega_rad_s / w0, 1.0]);
    }
    for (i, iv) in ivs.iter().enumerate() {
        let mut term = vec![0.0, kbn * iv.delta];
        for (j, other) in ivs.iter().enumerate() {
            if j != i {
                term = mul(&term, &[other.omega_rad_s / w0, 1.0]);
            }
        }
        for (d, t) in term.iter().enumerate() {
            poly[d] += t;
        }
    }
    let n = poly.len() - 1;
    let lead = poly[n];
    let comp = DMatrix::from_fn(n, n, |i, j| {
        if i == 0 {
            -poly[n - 1 - j] / lead
        } else if j + 1 == i {
            1.0
        } else {
            0.0
        }
    });
    let roots = comp.complex_eigenvalues();
    let best = roots.iter().max_by(|a, b| a.im.abs().total_cmp(&b.im.abs())).ok_or("no roots")?;
    if best.im.abs() <= 1e-12 {
        return Err("overdamped mode".into());
    }
    let s = best * w0;
    let omega = s.norm();
    Ok(ModalPair { omega_rad_s: omega, zeta: -s.re / omega })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam() -> BeamSpec {
        BeamSpec::from_yaml(
            "length_nm: 8.0\ndiameter_nm: 1.0\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300.0\nsupport: simply-supported\nelements: 20\n",
        )
        .unwrap()
    }

    #[test]
    fn local_elastic_simply_supported_matches_closed_form() {
        // ω_r = (rπ/L)² √(EI/ρA); Hermite FE with 20 elements converges as h⁴:
        // relative error for mode 3 ≈ (3π/20)⁴/720·... < 1e-4.
        let b = beam();
        let p = predict(&b, 3).unwrap();
        let l = 8e-9;
        let c = (b.youngs_modulus_pa * b.inertia_m4() / (b.density_kg_m3 * b.area_m2())).sqrt();
        for (r, m) in p.iter().enumerate() {
            let exact = ((r + 1) as f64 * std::f64::consts::PI / l).powi(2) * c;
            assert!((m.omega_rad_s / exact - 1.0).abs() < 1e-4, "{} vs {}", m.omega_rad_s, exact);
            assert!(m.zeta.abs() < 1e-9);
        }
    }
}
