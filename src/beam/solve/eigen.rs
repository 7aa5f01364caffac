//! Lowest eigenvalues of the banded symmetric pencil K φ = λ M φ (M ≻ 0, K ≻ 0
//! after the supports), without forming anything dense.
//!
//! f(σ) = det(K − σM) = det M · Π (λⱼ − σ) is a polynomial with only real
//! roots. Newton's method with Maehly deflation,
//!   σ ← σ − 1 / ( Σⱼ 1/(σ − λⱼ) − Σ_{found} 1/(σ − λ_f) ),
//! started below the next unfound root converges to it monotonically (every
//! remaining term is negative, so the step is positive and smaller than
//! 1/max|1/(σ − λⱼ)| = the distance to the nearest remaining root — no
//! overshoot) and quadratically near it. Σⱼ 1/(σ − λⱼ) = d/dσ log|f(σ)| comes
//! from one dual-number banded LDLᵀ (`SymBand::ldl_inertia`), whose negative-
//! pivot count (Sylvester inertia) certifies that a start point lies below the
//! next root. Cost: O(n) per step, ~5 steps per eigenvalue ([`lowest_eigenpairs`]).
//!
//! When eigenpairs of a nearby pencil are at hand, [`refine_eigenpairs`] is
//! cheaper: Rayleigh-quotient iteration (RQI) from each old vector — cubic
//! convergence, one unpivoted banded LDLᵀ per step — then one inertia count
//! certifies that the refined values are the lowest ones, in order.

use crate::beam::error::BeamError;
use crate::beam::linalg::band::{ShiftedLdl, SymBand};
use crate::beam::linalg::dual::Dual;

/// Below this relative step, a step that fails to halve signals the noise floor.
/// The floor: det(K − σM) is evaluated with absolute pivot errors ~eps·‖K‖,
/// i.e. ~eps·λ_max/λ relative in σ (≈1e-10 for 20 elements); the caller's
/// `refine` (a Rayleigh quotient from element energies) removes it.
const NOISE_TOL: f64 = 1e-7;
const MAX_ITER: usize = 200;

/// Halvings of an overshooting start towards the last eigenvalue found
/// ([`lowest_eigenvalues`]): 40 reach a gap of 0.25·2⁻⁴⁰ ≈ 2e-13 relative,
/// below any two distinct eigenvalues the Newton phase can separate.
const START_HALVINGS: usize = 40;

/// An eigenvalue of K φ = λ M φ and its vector (scaled to max-abs 1).
#[derive(Debug, Clone, PartialEq)]
pub struct EigenPair {
    pub lambda: f64,
    pub vector: Vec<f64>,
}

/// The `count` lowest eigenpairs from scratch: Newton–Maehly on det(K − σM)
/// (see the module doc), then one inverse iteration for the vector and its
/// Rayleigh quotient `stiffness(x)/xᵀMx`. `stiffness(x)` = xᵀKx must be
/// computed without the cancellation of the assembled K (see
/// `UnitMesh::stiffness_form`): it sets the accuracy of every eigenvalue.
pub fn lowest_eigenpairs(
    k: &SymBand,
    m: &SymBand,
    count: usize,
    work: &mut Vec<Dual<f64>>,
    stiffness: &dyn Fn(&[f64]) -> f64,
) -> Result<Vec<EigenPair>, BeamError> {
    let mut pairs = Vec::with_capacity(count);
    let mut mx = Vec::new();
    lowest_eigenvalues(k, m, count, NEWTON_TOL, work, &mut |sigma| {
        let vector = eigenvector(k, m, sigma)?;
        m.mul_vec_into(&vector, &mut mx);
        let lambda = stiffness(&vector) / dot(&vector, &mx);
        pairs.push(EigenPair { lambda, vector });
        Ok(lambda)
    })?;
    Ok(pairs)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Newton tolerance before the Rayleigh-quotient refinement: after a step of
/// 1e-6 relative the quadratic phase leaves ~1e-12, and inverse iteration at
/// that shift plus the Rayleigh quotient (error ∝ vector error²) reach round-off.
const NEWTON_TOL: f64 = 1e-6;

/// RQI stops when the Rayleigh quotient moves by less than this (relative).
/// Derivation: with vector error δ (angle) the quotient errs by ≈ δ²·S
/// (S ≤ λ_max spread, in practice the neighbouring eigenvalue), so a move of
/// ≤ 1e-6·ρ means δ ≲ 1e-3 before the step; RQI's cubic rate then leaves
/// δ ≲ 1e-9·C and a quotient error ≲ 1e-18·S·C², far below the 1e-12 that
/// the fast-vs-state-space tests need, even for a rate constant C ~ 10³.
const RQI_TOL: f64 = 1e-6;

/// More steps than this means the start was far off: give up (the caller
/// falls back to [`lowest_eigenpairs`]).
const RQI_MAX_STEPS: usize = 6;
/// The inertia count that certifies the refined set is taken at λ_top·(1+τ).
/// τ must exceed the count's own noise (the computed LDLᵀ is exact for a
/// pencil perturbed by ~eps·‖K‖, i.e. ≲ 1e-7 relative in λ even for 100
/// elements) and stay below the relative gap to the next eigenvalue (beam
/// spectra are simple with gaps of tens of %); if it does not, the count
/// fails and the caller falls back, so τ only decides speed, never results.
const CERTIFY_TAU: f64 = 1e-4;

/// A start for RQI on the pencil being solved: a vector x, M x and its
/// Rayleigh quotient (the caller may form them cheaply from cached pieces).
#[derive(Debug, Clone, PartialEq)]
pub struct RqiStart {
    pub vector: Vec<f64>,
    pub mx: Vec<f64>,
    pub rho: f64,
}

/// Refines starts (eigenpairs of a nearby pencil) into the lowest
/// `starts.len()` eigenpairs of (K, M) by RQI: x ← (K − ρM)⁻¹Mx,
/// ρ ← stiffness(x)/xᵀMx. `None` when a start does not converge within
/// [`RQI_MAX_STEPS`], when the refined values are not strictly increasing (two
/// starts found the same eigenvalue), or when the inertia count at
/// λ_top·(1+τ) is not `starts.len()` (an eigenvalue was skipped). The result
/// is a function of (K, M, starts) only.
pub fn refine_eigenpairs(
    k: &SymBand,
    m: &SymBand,
    starts: Vec<RqiStart>,
    stiffness: &dyn Fn(&[f64]) -> f64,
    ldl: &mut ShiftedLdl,
) -> Option<Vec<EigenPair>> {
    let mut out: Vec<EigenPair> = Vec::with_capacity(starts.len());
    for RqiStart { vector: mut x, mut mx, mut rho } in starts {
        let mut converged = false;
        for _ in 0..RQI_MAX_STEPS {
            if !ldl.factor_for_inverse_iteration(k, m, rho) {
                return None;
            }
            // y = (K − ρM)⁻¹ M x, scaled to max-abs 1
            ldl.solve(&mut mx);
            let scale = mx.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if !(scale.is_finite() && scale > 0.0) {
                return None;
            }
            x.iter_mut().zip(&mx).for_each(|(xi, v)| *xi = v / scale);
            m.mul_vec_into(&x, &mut mx);
            let next = stiffness(&x) / dot(&x, &mx);
            let moved = (next - rho).abs();
            rho = next;
            if moved <= RQI_TOL * rho {
                converged = true;
                break;
            }
        }
        if !converged || !(rho > 0.0) {
            return None;
        }
        if let Some(prev) = out.last() {
            // distinct by far more than their errors (≲ 1e-12 relative)
            if !(rho > prev.lambda * (1.0 + 1e-9)) {
                return None;
            }
        }
        out.push(EigenPair { lambda: rho, vector: x });
    }
    let top = out.last()?.lambda;
    (ldl.factor(k, m, top * (1.0 + CERTIFY_TAU)) && ldl.negatives() == out.len()).then_some(out)
}

/// The `count` smallest eigenvalues of K φ = λ M φ, ascending. Each Newton
/// estimate is passed through `refine` (e.g. inverse iteration + Rayleigh
/// quotient) before it is used for deflation. Newton stops once its step is
/// below `step_tol` relative (quadratic convergence: the error after that step
/// is ~step_tol²·λ/gap) or at its round-off noise floor. `work` is reused.
fn lowest_eigenvalues(
    k: &SymBand,
    m: &SymBand,
    count: usize,
    step_tol: f64,
    work: &mut Vec<Dual<f64>>,
    refine: &mut dyn FnMut(f64) -> Result<f64, BeamError>,
) -> Result<Vec<f64>, BeamError> {
    let mut found: Vec<f64> = Vec::with_capacity(count);
    while found.len() < count {
        let idx = found.len();
        // Start: 1.25·λ_prev if the inertia says it is still below λ_next, else 0.
        // Past mode ≈ 17 of a beam (λ ∝ j⁴: λ_{j+1}/λ_j < 1.25) the trial
        // overshoots, and Newton from 0 needs steps in proportion to the
        // eigenvalues passed: K modes cost O(K²) steps and past a few
        // hundred modes reach MAX_ITER. So an overshooting trial is halved
        // towards λ_prev (one inertia count each) while it stays above it
        // by more than the Newton tolerance.
        let mut sigma = 0.0;
        let mut state = None;
        if let Some(&prev) = found.last() {
            let mut trial = 1.25 * prev;
            for _ in 0..START_HALVINGS {
                match k.ldl_inertia(m, trial, work) {
                    Some((neg, dlog)) if neg == idx => {
                        sigma = trial;
                        state = Some(dlog);
                        break;
                    }
                    Some((neg, _)) if neg > idx && trial - prev > 2.0 * step_tol * prev => {
                        trial = prev + 0.5 * (trial - prev);
                    }
                    _ => break,
                }
            }
        }
        let mut converged = false;
        let mut prev_step = f64::INFINITY;
        for _ in 0..MAX_ITER {
            let dlog = match state.take() {
                Some(d) => d,
                None => match k.ldl_inertia(m, sigma, work) {
                    Some((_, d)) => d,
                    // exactly zero pivot: nudge σ and retry.
                    None => {
                        sigma = sigma * (1.0 + 1e-13) + 1e-300;
                        continue;
                    }
                },
            };
            let deflated = dlog - found.iter().map(|&l| 1.0 / (sigma - l)).sum::<f64>();
            let step = -1.0 / deflated;
            if !step.is_finite() {
                break;
            }
            let noisy = step.abs() <= NOISE_TOL * sigma.abs() && step.abs() > 0.5 * prev_step;
            if noisy {
                converged = true;
                break;
            }
            sigma += step;
            prev_step = step.abs();
            if step.abs() <= step_tol * sigma.abs() {
                converged = true;
                break;
            }
        }
        if !converged || !(sigma > 0.0) {
            return Err(BeamError::numerical(format!("eigenvalue {} of the FE pencil did not converge", idx + 1)));
        }
        let refined = refine(sigma)?;
        // the refinement only removes round-off noise; a large move means it
        // locked onto another eigenvector
        if !((refined - sigma).abs() <= 1e-6 * sigma) {
            return Err(BeamError::numerical(format!("Rayleigh refinement of eigenvalue {} moved too far", idx + 1)));
        }
        found.push(refined);
    }
    Ok(found)
}

/// Eigenvector of eigenvalue `lambda` by inverse iteration with a banded LU,
/// M-normalised. One step suffices: with the shift within δ (relative) of λ,
/// other components shrink by ~δ·λ/gap (δ ≲ 1e-10 from the Newton phase).
pub fn eigenvector(k: &SymBand, m: &SymBand, lambda: f64) -> Result<Vec<f64>, BeamError> {
    use crate::beam::linalg::band::BandLu;
    let n = k.n;
    let tiny = f64::EPSILON * (k.get(0, 0).abs() + lambda * m.get(0, 0).abs());
    let lu = BandLu::factor_for_inverse_iteration(n, k.kd, |i, j| k.get(i, j) - lambda * m.get(i, j), tiny)
        .ok_or_else(|| BeamError::numerical("singular shifted pencil in inverse iteration"))?;
    let mut x: Vec<f64> = (0..n).map(|i| 1.0 + 0.01 * i as f64).collect();
    for _ in 0..1 {
        let mut y = m.mul_vec(&x);
        lu.solve(&mut y);
        let norm = m.bilinear(&y, &y).sqrt();
        if !(norm.is_finite() && norm > 0.0) {
            return Err(BeamError::numerical("inverse iteration broke down"));
        }
        x = y.iter().map(|v| v / norm).collect();
    }
    Ok(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::fe::model::UnitMesh;
    use crate::beam::spec::Support;

    #[test]
    fn matches_dense_generalized_eigenvalues() {
        for support in Support::ALL {
            let mesh = UnitMesh::new(9, support);
            let m = mesh.m0.plus_scaled(0.02, &mesh.m1);
            let mut w = Vec::new();
            let got = lowest_eigenvalues(&mesh.k, &m, 5, 1e-12, &mut w, &mut |s| Ok(s)).unwrap();
            let chol = nalgebra::Cholesky::new(m.to_dense()).unwrap();
            let linv = chol.l().try_inverse().unwrap();
            let c = &linv * mesh.k.to_dense() * linv.transpose();
            let mut eig: Vec<f64> = nalgebra::SymmetricEigen::new(c).eigenvalues.iter().copied().collect();
            eig.sort_by(f64::total_cmp);
            for (g, e) in got.iter().zip(&eig) {
                // dense reference: backward error ~eps·‖L⁻¹KL⁻ᵀ‖ ≈ 1e-16·λ_max;
                // λ_max/λ₁ ≲ 1e5 here, so 1e-10 relative is a safe bound.
                assert!((g - e).abs() <= 1e-10 * e, "{support:?}: {g} vs {e}");
            }
            let v = eigenvector(&mesh.k, &m, got[1]).unwrap();
            let kv = mesh.k.mul_vec(&v);
            let mv = m.mul_vec(&v);
            let res: f64 = kv.iter().zip(&mv).map(|(a, b)| (a - got[1] * b).powi(2)).sum::<f64>().sqrt();
            let scale: f64 = kv.iter().map(|a| a * a).sum::<f64>().sqrt();
            assert!(res <= 1e-9 * scale, "eigenvector residual {res} vs {scale}");
        }
    }
}
