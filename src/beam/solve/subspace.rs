//! The coupled path's second attempt (issue 69, defect 2): when the
//! one-term starts of `coupled.rs` fail, the oscillatory poles from the
//! projection of T̃(s̃) on the pencil's eigenvectors, each polished by the
//! same complex Rayleigh-quotient iteration on the full T̃(s̃), before the
//! dense state space is tried.
//!
//! # Why the one-term starts fail, and what the projection keeps
//! `coupled.rs` starts family j from the scalar equation of its own
//! eigenvector φⱼ of (K̃ + K̃_spring + K̃_N, M̃): every coupling between
//! families (φᵢᵀ M̃_beam φⱼ with rotary inertia or a point mass, the
//! foundation's k̃_f φᵢᵀ M̃_beam φⱼ, which the cached pencil leaves out) is
//! dropped. Where families crowd together — a stiff foundation lifts every
//! ω² by nearly the same k̃_f, so the spacing of the lowest modes shrinks
//! while those couplings do not — two starts converge to one pole and the
//! caller fell back to the dense state space: on a clamped tube with shear,
//! viscous damping, a point mass and a foundation of 40–100 ρA(ω₁⁰)², 7 of
//! 300 prior draws, each 250–300 ms against 1 ms (a diagnosis that "never
//! ends", issue 69).
//!
//! With Φ = [φ₁ … φ_m] the m = `pairs.len()` eigenvectors (the caller
//! passes twice the requested modes, solved from scratch: with a strong
//! relaxation beside a stiff axial force, the requested families alone gave
//! projected poles 5 % off, two of which polished to one pole),
//!   T̃_p(s) = ΦᵀT̃(s)Φ = s²M_p + s c̃ B_p + U_p + G(s) K_p,
//! M_p = ΦᵀM̃Φ, B_p = ΦᵀM̃_beamΦ, U_p = Φᵀ(K̃_spring + K̃_N + k̃_f M̃_beam)Φ,
//! K_p = ΦᵀK̃Φ (G carries the loss factor's 1 + iη) keeps every coupling
//! among the m families exactly and drops only those to the families above
//! them, whose effect on pole j is second order over the gap to them. Its
//! poles are the eigenvalues of the linearisation in z = (x, v = s x,
//! rᵢ = s/(s + Ω̃ᵢ)·x):
//!   s x = v,
//!   s M_p v = −(U_p + K_p) x − c̃ B_p v − Σᵢ Δᵢ K_p rᵢ   (K_p with 1 + iη),
//!   s rᵢ = v − Ω̃ᵢ rᵢ,
//! a dense (2 + N)m matrix (≤ 30 for the diagnosis's 5 modes and 4
//! variables), whose eigenvalues cost microseconds where the full state
//! space (2 + N)n costs the 300 ms above. With a loss factor the
//! linearisation holds for the upper half plane only (where the hysteretic
//! G is defined): only poles with Im s > 0 are used. The caller does not
//! take this path with a loss factor: the dense state space, the reference
//! its assignment is checked against, has no form for one.
//!
//! # What is exact, and what is the start
//! The projected poles are only starts. Each is polished by
//! `coupled::complex_rqi_from` on the full T̃(s̃) from x = Φy (y the null
//! vector of T̃_p there, by one inverse iteration), with the same
//! convergence rule as the first attempt, so a pole returned here is a pole
//! of T̃ to the same tolerance. The assignment to families is the dense
//! state space's (`state_space_modal.rs`): the k-th oscillatory pole by |s|
//! goes to the k-th family whose one-term equation has a pair. It is
//! guarded as there: the polished poles must be distinct, stay within half
//! their size of their starts, and keep the starts' order by |s| (a polish
//! that jumps to another pole breaks one of the three), otherwise the
//! caller falls back to the dense state space as before. Checked against
//! that state space on draws where the first attempt fails
//! (`tests/beam_coupled_subspace.rs`).

use nalgebra::{DMatrix, DVector, Schur};
use num_complex::Complex64;

use crate::beam::error::BeamError;
use crate::beam::fe::scaling::ScaledModel;
use crate::beam::modal_result::{assemble, ModalResult};
use crate::beam::solve::coupled::complex_rqi_from;
use crate::beam::solve::eigen::EigenPair;
use crate::beam::solve::family::{hysteretic_family_roots_into, Roots, REAL_TOL};

/// The oscillatory poles of the first `n_modes` families of `model` from the
/// projection on `pairs` (module doc), each polished on the full T̃(s̃).
/// Any failure is [`BeamError::Numerical`] (the caller then takes the dense
/// state space).
pub(crate) fn subspace_path(
    model: &ScaledModel,
    n_modes: usize,
    pairs: &[EigenPair],
) -> Result<ModalResult, BeamError> {
    let m = pairs.len();
    if m < n_modes || m == 0 {
        return Err(BeamError::numerical("subspace start: fewer eigenpairs than modes"));
    }
    // which families have an oscillatory pair: their one-term equations, as
    // `coupled::general_path` and the dense state space decide it
    let mut has_pair = Vec::with_capacity(n_modes);
    let mut roots = Roots::default();
    for p in pairs.iter().take(n_modes) {
        let (k, mm, mb, ks) = model.forms(&p.vector);
        hysteretic_family_roots_into(ks / mm, k / mm, model.c * mb / mm, &model.ivs, model.loss, &mut roots)?;
        has_pair.push(roots.iter().any(|s| s.im > 0.0));
    }
    let wanted = has_pair.iter().filter(|&&h| h).count();
    let projected = Projection::new(model, pairs);
    let starts = projected.oscillatory_poles()?;
    if starts.len() < wanted {
        return Err(BeamError::numerical("subspace start: the projection has fewer pairs than families"));
    }
    let mut polished: Vec<Complex64> = Vec::with_capacity(wanted);
    for &s0 in starts.iter().take(wanted) {
        let y = projected.null_vector(s0)?;
        let x: Vec<Complex64> = (0..model.n())
            .map(|i| pairs.iter().zip(y.iter()).map(|(p, &yj)| yj * p.vector[i]).sum::<Complex64>())
            .collect();
        let s = complex_rqi_from(model, s0, x)?;
        if (s - s0).norm() > 0.5 * s0.norm() {
            return Err(BeamError::numerical("subspace start: RQI left its start's neighbourhood"));
        }
        if s.im.abs() <= REAL_TOL * s.norm() {
            return Err(BeamError::numerical("subspace start: converged to a real pole"));
        }
        let s = Complex64::new(s.re, s.im.abs());
        if polished.iter().any(|f| (s - f).norm() <= 1e-8 * s.norm()) {
            return Err(BeamError::numerical("subspace start: two starts converged to the same pole"));
        }
        if polished.last().is_some_and(|f| f.norm() > s.norm()) {
            return Err(BeamError::numerical("subspace start: the polished poles left the starts' order"));
        }
        polished.push(s);
    }
    let mut next = polished.into_iter();
    let families: Vec<Vec<Complex64>> = has_pair
        .iter()
        .map(|&h| if h { next.next().map_or_else(Vec::new, |s| vec![s, s.conj()]) } else { Vec::new() })
        .collect();
    Ok(assemble(&families, n_modes, model.omega_ref))
}

/// T̃ projected on the eigenvectors (module doc): its four m × m matrices
/// and the model's relaxations and damping.
struct Projection<'m, 'a> {
    model: &'m ScaledModel<'a>,
    m: DMatrix<f64>,
    b: DMatrix<f64>,
    u: DMatrix<f64>,
    k: DMatrix<f64>,
}

impl<'m, 'a> Projection<'m, 'a> {
    fn new(model: &'m ScaledModel<'a>, pairs: &[EigenPair]) -> Self {
        let dim = pairs.len();
        let vectors: Vec<&[f64]> = pairs.iter().map(|p| p.vector.as_slice()).collect();
        // the symmetric Gram matrix of a bilinear form over the eigenvectors
        let gram = |f: &dyn Fn(&[f64], &[f64]) -> f64| {
            let mut a = DMatrix::zeros(dim, dim);
            for i in 0..dim {
                for j in i..dim {
                    let v = f(vectors[i], vectors[j]);
                    a[(i, j)] = v;
                    a[(j, i)] = v;
                }
            }
            a
        };
        let m = gram(&|x, y| model.m.bilinear(x, y));
        let b = gram(&|x, y| model.m_beam.bilinear(x, y));
        let k = gram(&|x, y| model.k.bilinear(x, y));
        let u = gram(&|x, y| {
            let springs: f64 = model.springs().map(|(d, ks)| ks * x[d] * y[d]).sum();
            let axial = model.k_axial.as_ref().map_or(0.0, |ka| ka.bilinear(x, y));
            let foundation = if model.foundation != 0.0 { model.foundation * model.m_beam.bilinear(x, y) } else { 0.0 };
            springs + axial + foundation
        });
        Projection { model, m, b, u, k }
    }

    /// The poles with Im s > REAL_TOL·|s| of the projected T̃, by |s|.
    fn oscillatory_poles(&self) -> Result<Vec<Complex64>, BeamError> {
        let dim = self.m.nrows();
        let ivs = &self.model.ivs;
        let nv = ivs.len();
        let c = |v: f64| Complex64::new(v, 0.0);
        let h = Complex64::new(1.0, self.model.loss);
        let m_inv = self
            .m
            .clone()
            .cholesky()
            .ok_or_else(|| BeamError::numerical("subspace start: projected mass not positive definite"))?
            .inverse();
        let to_c = |a: &DMatrix<f64>| a.map(c);
        let m_inv = to_c(&m_inv);
        let kh = to_c(&self.k) * h;
        let stiff = &m_inv * (to_c(&self.u) + &kh);
        let damp = &m_inv * to_c(&self.b) * c(self.model.c);
        let n = (2 + nv) * dim;
        let mut a = DMatrix::<Complex64>::zeros(n, n);
        for i in 0..dim {
            a[(i, dim + i)] = c(1.0);
        }
        for i in 0..dim {
            for j in 0..dim {
                a[(dim + i, j)] = -stiff[(i, j)];
                a[(dim + i, dim + j)] = -damp[(i, j)];
            }
        }
        for (v, &(delta, omega)) in ivs.iter().enumerate() {
            let r = (2 + v) * dim;
            let coupling = &m_inv * &kh * c(delta);
            for i in 0..dim {
                for j in 0..dim {
                    a[(dim + i, r + j)] = -coupling[(i, j)];
                }
                a[(r + i, dim + i)] = c(1.0);
                a[(r + i, r + i)] = c(-omega);
            }
        }
        if a.iter().any(|v| !v.is_finite()) {
            return Err(BeamError::numerical("subspace start: non-finite projected state matrix"));
        }
        let schur = Schur::try_new(a, f64::EPSILON, 1_000 * n)
            .ok_or_else(|| BeamError::numerical("subspace start: Schur decomposition did not converge"))?;
        let eig = schur
            .eigenvalues()
            .ok_or_else(|| BeamError::numerical("subspace start: no eigenvalues of the projected state matrix"))?;
        let mut poles: Vec<Complex64> = eig.iter().copied().filter(|s| s.im > REAL_TOL * s.norm()).collect();
        if poles.iter().any(|s| !s.is_finite()) {
            return Err(BeamError::numerical("subspace start: non-finite projected pole"));
        }
        poles.sort_by(|x, y| x.norm().total_cmp(&y.norm()).then(x.im.total_cmp(&y.im)));
        Ok(poles)
    }

    /// T̃_p(s) = s²M_p + s c̃ B_p + U_p + G(s)K_p.
    fn matrix(&self, s: Complex64) -> DMatrix<Complex64> {
        let (g, _) = self.model.relaxation(s);
        let cc = s * self.model.c;
        DMatrix::from_fn(self.m.nrows(), self.m.ncols(), |i, j| {
            s * s * self.m[(i, j)] + cc * self.b[(i, j)] + self.u[(i, j)] + g * self.k[(i, j)]
        })
    }

    /// The null vector of T̃_p(s) at a projected pole s: one inverse
    /// iteration from the all-ones vector (T̃_p(s) is singular to round-off
    /// there, so the solve amplifies the null direction by ~1/eps), scaled
    /// to max-norm 1.
    fn null_vector(&self, s: Complex64) -> Result<DVector<Complex64>, BeamError> {
        let dim = self.m.nrows();
        let t = self.matrix(s);
        let ones = DVector::from_element(dim, Complex64::new(1.0, 0.0));
        // an exactly singular T̃_p(s) leaves LU without a solve: perturb s by
        // one part in 1e12 (still a start within round-off of the pole)
        let y =
            t.lu().solve(&ones).or_else(|| self.matrix(s * (1.0 + 1e-12)).lu().solve(&ones)).ok_or_else(|| {
                BeamError::numerical("subspace start: the projected null vector could not be solved for")
            })?;
        let scale = y.iter().fold(0.0f64, |a, v| a.max(v.norm()));
        if !(scale.is_finite() && scale > 0.0) {
            return Err(BeamError::numerical("subspace start: projected null vector broke down"));
        }
        Ok(y / Complex64::new(scale, 0.0))
    }
}
