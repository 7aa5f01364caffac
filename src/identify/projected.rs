//! Variable projection for the record kinds linear in the residues
//! (complex receptances, free decays): Levenberg–Marquardt over the poles
//! alone, the residues solved at every step.

use super::covariance::MAX_SWEEPS;
use super::refine::{finish, FitResult, Model, PER_MODE};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt, TerminationReason};
use nalgebra::storage::Owned;
use nalgebra::{DMatrix, DVector, Dyn};

/// LM evaluation budget of the projected problem, VARPRO_PATIENCE·(q + 1)
/// for q poles: a safety net for a candidate whose surplus background
/// pole crawls along a flat valley (measured, paper's beam, 4 000 points,
/// 5 modes: the 0-real-pole candidate stops here, 120 evaluations, its
/// out-of-band pole collapsing onto the real axis to imitate the relaxation;
/// with γ = e^η the 1–3-pole candidates converged by [`VARPRO_FTOL`] in
/// 25–131 evaluations, except the 3-pole candidate of one noisy sweep, which
/// reached its budget of 144 — a candidate the BIC forward selection does
/// not fit on that record).
pub const VARPRO_PATIENCE: usize = 8;

/// Relative-reduction tolerance of the projected LM (MINPACK's ftol: stop
/// when the actual and the predicted relative reductions of ‖r‖² are both
/// ≤ ftol). Near the optimum the Gauss–Newton prediction is the whole
/// remaining reduction, and a parameter t standard deviations from the
/// optimum raises RSS = σ̂²(m − p) by t²σ̂², a relative t²/(m − p); stopping at
/// ftol therefore leaves t ≤ √(ftol·(m − p)) sd: 1e-10 with m − p ≤ 10⁵
/// residuals gives t ≤ 3·10⁻³ sd, invisible in any reported interval, and
/// for a noise-free record (σ̂ ≈ 10⁻⁹ of ω, the truncation of the background
/// model) an error of ~10⁻¹² relative, far below the 10⁻⁶ target.
pub const VARPRO_FTOL: f64 = 1e-10;

/// Variable projection (Golub & Pereyra, "The differentiation of
/// pseudo-inverses and nonlinear least squares problems whose variables
/// separate", SIAM J. Numer. Anal. 10, 1973) for the kinds linear in the
/// residues (complex, time): Levenberg–Marquardt over the poles α only, the
/// residues c(α) = Φ(α)⁺y solved at every step, residual r(α) = Φc(α) − y and
/// Kaufman's Jacobian J = P⊥ ∂(Φc)/∂α with P⊥ = I − QQᵀ, Q an orthonormal basis
/// of range Φ (L. Kaufman, BIT 15, 1975). Eliminating the residues removes the
/// long, ill-conditioned valleys of the joint problem, so the background
/// poles converge instead of crawling. The covariance is that of the joint
/// problem at the optimum ([`finish`]): the two coincide there.
///
/// The decay rates γ_k of the real poles are optimised as η_k = ln γ_k
/// (γ > 0: the relaxation poles of a passive beam are stable; a surplus
/// pole that is not needed drifts towards 0 or ∞ along η, where its column
/// of Φ becomes dependent and the rank cut drops it, instead of crossing to
/// an unstable pole). `theta0` must have γ_k > 0.
pub fn fit_projected(model: &Model, theta0: &[f64]) -> Option<FitResult> {
    let problem = Projected::new(model, theta0)?;
    let (problem, report) = LevenbergMarquardt::new()
        .with_ftol(VARPRO_FTOL)
        .with_xtol(1e-14)
        .with_patience(VARPRO_PATIENCE)
        .minimize(problem);
    if !report.termination.was_successful() && report.number_of_evaluations == 0 {
        return None;
    }
    let theta = problem.theta()?;
    let converged = matches!(report.termination, TerminationReason::Converged { .. } | TerminationReason::Orthogonal);
    finish(model, theta, report.number_of_evaluations, converged, &[])
}

/// The reduced problem of [`fit_projected`], handed to the LM crate in
/// compressed form (see [`Projected::compressed`]).
struct Projected<'a> {
    model: &'a Model,
    nonlinear: Vec<usize>,
    linear: Vec<usize>,
    /// θ with the current poles (residues overwritten at each projection).
    template: Vec<f64>,
    /// The poles as optimised: θ_j, or ln θ_j where `log` is set (γ_k).
    alpha: DVector<f64>,
    log: Vec<bool>,
    /// The factorisation of the last [`Projected::residual_norm`], keyed by
    /// its poles: the crate asks for the Jacobian at the point whose
    /// residuals it has just accepted, so the QR of Φ is reused once.
    /// (A function of α alone: reuse changes speed, never values.)
    cache: std::cell::RefCell<Option<(DVector<f64>, Factored)>>,
}

/// Rank cut of Φ: singular values of R (Φ = QR) at or below this fraction
/// of the largest mean numerically dependent columns (a runaway background
/// pole), whose directions are left out of range Φ.
const RANK_CUT: f64 = 1e-13;

/// Φ = QR at the current poles (Householder: Q is kept as reflectors, never
/// formed), R = U S Vᵀ, the data rotated, z = Qᵀy, and the residues.
struct Factored {
    qr: nalgebra::QR<f64, Dyn, Dyn>,
    /// U's columns with S > [`RANK_CUT`]·S_max: range Φ is Q₁U_keep.
    u_keep: DMatrix<f64>,
    /// Qᵀy.
    qty: DVector<f64>,
    /// c = V_keep S_keep⁻¹ U_keepᵀ(Qᵀy)₁…ₙ (minimum-norm least squares).
    c: DVector<f64>,
}

impl Factored {
    /// Qᵀ P⊥ v given w = Qᵀv: P⊥ = I − Q₁U_keepU_keepᵀQ₁ᵀ leaves the rows
    /// n… alone and removes range U_keep from the rows 0…n.
    fn project_rotated(&self, w: &mut DMatrix<f64>) {
        let n = self.u_keep.nrows();
        let top = w.rows(0, n).into_owned();
        let along = &self.u_keep * (self.u_keep.transpose() * &top);
        w.rows_mut(0, n).copy_from(&(top - along));
    }
}

impl<'a> Projected<'a> {
    /// The reduced problem at the poles of `theta0` (γ_k > 0 required).
    fn new(model: &'a Model, theta0: &[f64]) -> Option<Self> {
        let nonlinear = model.nonlinear_indices();
        let o = PER_MODE * model.n_modes;
        let log: Vec<bool> = nonlinear.iter().map(|&j| j >= o).collect();
        if nonlinear.iter().zip(&log).any(|(&j, &l)| l && !(theta0[j] > 0.0)) {
            return None;
        }
        let alpha = DVector::from_iterator(
            nonlinear.len(),
            nonlinear.iter().zip(&log).map(|(&j, &l)| if l { theta0[j].ln() } else { theta0[j] }),
        );
        let linear = model.linear_indices();
        Some(Projected { model, nonlinear, linear, template: theta0.to_vec(), alpha, log, cache: Default::default() })
    }

    /// θ_j of the k-th pole parameter.
    fn pole(&self, k: usize) -> f64 {
        if self.log[k] {
            // |η| ≤ 700 keeps γ finite and nonzero (e^709 overflows): a trial
            // step beyond is a pole at 10^±304, whose column the rank cut drops,
            // so the LM sees a finite residual and shortens its step
            self.alpha[k].clamp(-700.0, 700.0).exp()
        } else {
            self.alpha[k]
        }
    }

    /// θ with the current poles and zero residues.
    fn poles_only(&self) -> Vec<f64> {
        let mut theta = self.template.clone();
        for (k, &j) in self.nonlinear.iter().enumerate() {
            theta[j] = self.pole(k);
        }
        for &j in &self.linear {
            theta[j] = 0.0;
        }
        theta
    }

    /// θ with the current poles and the residues `c`.
    fn with_residues(&self, c: &DVector<f64>) -> Vec<f64> {
        let mut theta = self.poles_only();
        for (k, &j) in self.linear.iter().enumerate() {
            theta[j] = c[k];
        }
        theta
    }

    /// Householder QR of Φ (O(m n²)), then the small R = U S Vᵀ (cheaper
    /// than an SVD of the tall Φ), z = Qᵀy by the reflectors and the residues.
    fn factor(&self) -> Option<Factored> {
        let theta = self.poles_only();
        let (r0, phi) = self.model.eval_columns(&theta, &self.linear);
        // (nalgebra's SVD does not terminate on non-finite input)
        if !r0.iter().chain(phi.iter()).all(|v| v.is_finite()) {
            return None;
        }
        let qr = phi.qr();
        // bounded iterations: nalgebra's unbounded SVD can cycle on a
        // degenerate R (a runaway background pole); `None` ends this candidate
        let svd = qr.r().try_svd(true, true, f64::EPSILON, MAX_SWEEPS)?;
        let (u, vt) = (svd.u.as_ref()?, svd.v_t.as_ref()?);
        let sv = &svd.singular_values;
        let smax = sv.iter().copied().fold(0.0, f64::max);
        if !(smax > 0.0 && smax.is_finite()) {
            return None;
        }
        let keep: Vec<usize> = (0..sv.len()).filter(|&i| sv[i] > RANK_CUT * smax).collect();
        let u_keep = u.select_columns(&keep);
        // r₀ = model(θ with zero residues) − y = −y
        let mut qty = -r0;
        qr.q_tr_mul(&mut qty);
        let coef = u_keep.transpose() * qty.rows(0, self.linear.len());
        let mut c = DVector::zeros(self.linear.len());
        for (k, &i) in keep.iter().enumerate() {
            c += vt.row(i).transpose() * (coef[k] / sv[i]);
        }
        Some(Factored { qr, u_keep, qty, c })
    }

    /// θ(α) = (α, c(α)).
    fn theta(&self) -> Option<Vec<f64>> {
        Some(self.with_residues(&self.factor()?.c))
    }

    /// Qᵀ P⊥ y = −Qᵀr, the residual in rotated coordinates.
    fn rotated_residual(f: &Factored) -> DMatrix<f64> {
        let mut w = DMatrix::from_column_slice(f.qty.nrows(), 1, f.qty.as_slice());
        f.project_rotated(&mut w);
        w
    }

    /// The residual and Kaufman's Jacobian compressed to q + 1 rows
    /// (q poles): with U an orthonormal basis of span[r, J] (J = P⊥∂(Φc)/∂α
    /// and r = −P⊥y), the LM subproblem min‖Jp − r‖² + λ‖Dp‖² equals
    /// min‖UᵀJp − Uᵀr‖² + λ‖Dp‖², and the column norms (the LM's scaling D)
    /// are the same. With the QR [QᵀP⊥y, QᵀP⊥J] = V R₂ (Q orthogonal, so
    /// this is the QR of [P⊥y, P⊥J] rotated), Uᵀr = ‖r‖e₁ (row 0 sign-fixed)
    /// and UᵀJ = R₂'s last q columns: the crate's pivoted QR then works on a
    /// (q+1)×q matrix instead of m×q, and [`Self::residual_norm`] needs no
    /// Jacobian. The trust-region steps are those of the uncompressed
    /// problem up to round-off.
    fn compressed(&self) -> Option<DMatrix<f64>> {
        let q = self.nonlinear.len();
        let cached = self.cache.borrow_mut().take().filter(|(a, _)| *a == self.alpha).map(|(_, f)| f);
        let f = match cached {
            Some(f) => f,
            None => self.factor()?,
        };
        let (_, mut ja) = self.model.eval_columns(&self.with_residues(&f.c), &self.nonlinear);
        // chain rule for η = ln γ: ∂/∂η = γ·∂/∂γ
        for k in 0..q {
            if self.log[k] {
                let g = self.pole(k);
                ja.column_mut(k).scale_mut(g);
            }
        }
        if !ja.iter().all(|v| v.is_finite()) {
            return None;
        }
        f.qr.q_tr_mul(&mut ja);
        f.project_rotated(&mut ja);
        let mut w = DMatrix::zeros(ja.nrows(), q + 1);
        w.set_column(0, &Self::rotated_residual(&f).column(0));
        w.columns_mut(1, q).copy_from(&ja);
        let r2 = w.qr().r();
        // Vᵀ(−r) = R₂[0,0]e₁: flip row 0 so that the residual is +‖r‖e₁
        let sign = if r2[(0, 0)] > 0.0 { -1.0 } else { 1.0 };
        let mut j = r2.columns(1, q).into_owned();
        j.row_mut(0).scale_mut(sign);
        Some(j)
    }

    /// ‖r(α)‖ = ‖QᵀP⊥y‖; keeps the factorisation for the Jacobian.
    fn residual_norm(&self) -> Option<f64> {
        let f = self.factor()?;
        let norm = Self::rotated_residual(&f).norm();
        *self.cache.borrow_mut() = Some((self.alpha.clone(), f));
        Some(norm)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Projected<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.alpha.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.alpha.clone()
    }

    /// ‖r‖e₁ (q + 1 rows; see [`Projected::compressed`]).
    fn residuals(&self) -> Option<DVector<f64>> {
        if self.model.stop.requested() {
            return None;
        }
        let norm = self.residual_norm()?;
        let mut r = DVector::zeros(self.nonlinear.len() + 1);
        r[0] = norm;
        norm.is_finite().then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let j = self.compressed()?;
        j.iter().all(|v| v.is_finite()).then_some(j)
    }
}
