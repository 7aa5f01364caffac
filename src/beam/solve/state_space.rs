//! Reference poles: eigenvalues of the augmented state matrix Aa of (A15).
//!
//! # Signs of (A8)–(A15) (lost in the text extraction)
//! Eq. (22)/(A8): M q̈ + D q̇ + (1 + ΣΔᵢ) K q − K Σ Δᵢ q̄ᵢ = P and
//! (Δᵢ/Ωᵢ) K q̄̇ᵢ + Δᵢ K q̄ᵢ − Δᵢ K q = 0, i.e. the coupling blocks are
//! Ka12 = Ka21ᵀ = [−Δ₁K, …, −Δ_N K], Ka22 = diag(ΔᵢK), Da22 = diag(Δᵢ/Ωᵢ K).
//! The second equation is K·(Δᵢ/Ωᵢ)(q̄̇ᵢ − Ωᵢ(q − q̄ᵢ)) = 0, and K is
//! non-singular after the supports, so q̄̇ᵢ = Ωᵢ(q − q̄ᵢ): eq. (17) in nodal
//! form. Hence the q̄ rows of (A15), −(Da22)⁻¹Ka21 = Ωᵢ I and
//! −(Da22)⁻¹Ka22 = −Ωᵢ I, do not involve Δᵢ or K; we build them that way, which
//! stays valid for Δᵢ = 0 (where Da22 itself is singular).
//! With xa = [q; q̄₁ … q̄_N; q̇]:
//!   d/dt q  = q̇
//!   d/dt q̄ᵢ = Ωᵢ q − Ωᵢ q̄ᵢ
//!   d/dt q̇  = −M⁻¹[(1+ΣΔᵢ)K + K_spring + K_N] q + Σ M⁻¹ΔᵢK q̄ᵢ − M⁻¹D q̇
//! (K_N the axial-force stiffness, elastic like the support spring).
//! Dimension (2 + N)·n. Laplace transform: q̄ᵢ = Ωᵢ/(s+Ωᵢ) q, so the elastic
//! force becomes K(1 + ΣΔᵢ − ΣΔᵢΩᵢ/(s+Ωᵢ)) = K(1 + ΣΔᵢ s/(s+Ωᵢ)) — eq. (9).
//!
//! Built in the scaled units of `model.rs`, diagonally balanced (Parlett–
//! Reinsch, powers of 2: exact similarity) and handed to nalgebra's real Schur
//! decomposition.

use nalgebra::{DMatrix, Schur};
use num_complex::Complex64;

use crate::beam::error::BeamError;
use crate::beam::fe::scaling::ScaledModel;

/// Largest state dimension (2 + N)·n the dense reference handles: the real
/// Schur decomposition costs ~25·dim³ flops (≈ 2.7e10 at 1024, a few seconds
/// here); beyond it a fallback to the dense path would run for minutes, so it
/// is a numerical failure instead (exit 1, never a hang).
pub const MAX_DENSE_DIM: usize = 1024;

/// All poles in scaled units (s̃ = s/ω_ref).
pub fn scaled_poles(model: &ScaledModel) -> Result<Vec<Complex64>, BeamError> {
    let dim = (2 + model.ivs_all.len()) * model.n();
    if dim > MAX_DENSE_DIM {
        return Err(BeamError::numerical(format!(
            "the banded solver failed and the dense state-space reference is limited to dimension {MAX_DENSE_DIM} \
             (this model: (2 + {} internal variables) x {} DOFs = {dim}); use fewer elements or request fewer modes",
            model.ivs_all.len(),
            model.n()
        )));
    }
    let a = state_matrix(model)?;
    if a.iter().any(|v| !v.is_finite()) {
        return Err(BeamError::numerical("the state matrix has non-finite entries (scaled parameters out of range)"));
    }
    let a = balance(a);
    let dim = a.nrows();
    // nalgebra deflates a subdiagonal only when |h| ≤ tol·(|h_ii| + |h_jj|)
    // (no norm-relative test, no exceptional shifts). Round-off leaves
    // subdiagonals of size ~eps·‖A‖, so poles much smaller than ‖A‖ (relaxation
    // clusters near −Ωᵢ, e.g. two nearly equal Ωᵢ) may never deflate at
    // tol = eps. Retry with tol = 64ᵏ·eps: zeroing |h| ≤ tol·|λ| perturbs such a
    // pole by ~tol relative (≤ 6e-11 at the last rung), still below the 1e-9
    // agreement the tests demand and comparable to the eps·‖A‖ backward error.
    let schur = [1.0, 64.0, 4096.0, 262_144.0]
        .iter()
        .find_map(|f| Schur::try_new(a.clone(), f * f64::EPSILON, 1_000 * dim.max(1)))
        .ok_or_else(|| BeamError::numerical("real Schur decomposition of the state matrix did not converge"))?;
    let mut poles: Vec<Complex64> = schur.complex_eigenvalues().iter().copied().collect();
    if poles.iter().any(|p| !p.is_finite()) {
        return Err(BeamError::numerical("non-finite eigenvalue of the state matrix"));
    }
    poles.sort_by(|x, y| x.norm().total_cmp(&y.norm()).then(x.im.total_cmp(&y.im)));
    Ok(poles)
}

/// The augmented state matrix (A15) in scaled units.
pub fn state_matrix(model: &ScaledModel) -> Result<DMatrix<f64>, BeamError> {
    if model.loss != 0.0 {
        return Err(BeamError::numerical(
            "a hysteretic loss factor has no state-space (time-domain) form: its modes come from the frequency domain",
        ));
    }
    let n = model.n();
    let nv = model.ivs_all.len();
    let dim = (2 + nv) * n;
    let chol = nalgebra::Cholesky::new(model.m.to_dense())
        .ok_or_else(|| BeamError::numerical("mass matrix is not positive definite"))?;
    let k = model.k.to_dense();
    let mut k_el = &k * (1.0 + model.ivs_all.iter().map(|v| v.0).sum::<f64>());
    for (i, ks) in model.springs() {
        k_el[(i, i)] += ks;
    }
    if let Some(ka) = &model.k_axial {
        k_el += ka.to_dense();
    }
    if model.foundation != 0.0 {
        k_el += model.m_beam.to_dense() * model.foundation;
    }
    let minv_kel = chol.solve(&k_el);
    let minv_k = chol.solve(&k);
    let minv_d = chol.solve(&(model.m_beam.to_dense() * model.c));
    let mut a = DMatrix::<f64>::zeros(dim, dim);
    let v0 = (1 + nv) * n;
    for i in 0..n {
        a[(i, v0 + i)] = 1.0;
    }
    for (iv, &(_, om)) in model.ivs_all.iter().enumerate() {
        let r0 = (1 + iv) * n;
        for i in 0..n {
            a[(r0 + i, i)] = om;
            a[(r0 + i, r0 + i)] = -om;
        }
    }
    for i in 0..n {
        for j in 0..n {
            a[(v0 + i, j)] = -minv_kel[(i, j)];
            a[(v0 + i, v0 + j)] = -minv_d[(i, j)];
            for (iv, &(d, _)) in model.ivs_all.iter().enumerate() {
                a[(v0 + i, (1 + iv) * n + j)] = d * minv_k[(i, j)];
            }
        }
    }
    Ok(a)
}

/// Parlett–Reinsch balancing D⁻¹AD with D a diagonal of powers of 2 (LAPACK
/// `gebal` without permutations): makes row and column norms comparable so the
/// normwise-backward-stable Schur iteration gives small poles small absolute errors.
fn balance(mut a: DMatrix<f64>) -> DMatrix<f64> {
    const RADIX: f64 = 2.0;
    let n = a.nrows();
    let mut done = false;
    let mut sweeps = 0;
    while !done && sweeps < 100 {
        done = true;
        sweeps += 1;
        for i in 0..n {
            let mut c = 0.0;
            let mut r = 0.0;
            for j in 0..n {
                if j != i {
                    c += a[(j, i)].abs();
                    r += a[(i, j)].abs();
                }
            }
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let s = c + r;
            let mut f = 1.0;
            let mut g = r / RADIX;
            while c < g {
                f *= RADIX;
                c *= RADIX * RADIX;
            }
            g = r * RADIX;
            while c > g {
                f /= RADIX;
                c /= RADIX * RADIX;
            }
            if (c + r) / f < 0.95 * s {
                done = false;
                let inv = 1.0 / f;
                for j in 0..n {
                    a[(i, j)] *= inv;
                }
                for j in 0..n {
                    a[(j, i)] *= f;
                }
            }
        }
    }
    a
}
