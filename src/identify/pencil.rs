//! Matrix pencil method for a uniformly sampled free decay (Hua & Sarkar,
//! "Matrix pencil method for estimating parameters of exponentially
//! damped/undamped sinusoids in noise", IEEE Trans. ASSP 38(5), 1990), the
//! single-output relative of ERA (Juang & Pappa 1985) with the same
//! SVD-truncated shift-invariance step.
//!
//! y_k = Σ_r c_r z_r^k, z_r = exp(s_r Δt). With the Hankel matrix
//! Y (rows k = 0 … N−L−1, columns l = 0 … L: Y_kl = y_{k+l}) and its thin SVD
//! Y = UΣVᵀ, keep the first M right singular vectors V_M (an order-M model);
//! V₁ = V_M without its last row, V₂ = without its first row. The z_r are the
//! eigenvalues of V₁⁺V₂ (least-squares shift invariance) and s_r = ln(z_r)/Δt.
//! One SVD serves every order of the stabilisation diagram.

use nalgebra::DMatrix;
use num_complex::Complex64;

/// The SVD of the data's Hankel matrix, reused across orders.
pub struct Pencil {
    dt: f64,
    /// Right singular vectors as columns, by decreasing singular value.
    v: DMatrix<f64>,
}

impl Pencil {
    /// `pencil` = L, the number of Hankel columns minus one (Hua & Sarkar
    /// recommend N/3 ≤ L ≤ N/2 for noise; more than the highest order plus a
    /// margin suffices and bounds the cost).
    pub fn new(y: &[f64], dt: f64, pencil: usize) -> Option<Self> {
        let n = y.len();
        let l = pencil.min(n / 2);
        let rows = n - l;
        let hankel = DMatrix::from_fn(rows, l + 1, |k, j| y[k + j]);
        // bounded iterations (nalgebra's unbounded SVD can cycle)
        let svd = hankel.try_svd(false, true, f64::EPSILON, 10_000)?;
        let vt = svd.v_t?;
        let mut order: Vec<usize> = (0..svd.singular_values.len()).collect();
        order.sort_by(|&a, &b| svd.singular_values[b].total_cmp(&svd.singular_values[a]));
        let v = DMatrix::from_fn(l + 1, order.len(), |i, j| vt[(order[j], i)]);
        Some(Self { dt, v })
    }

    /// Highest order available.
    pub fn max_order(&self) -> usize {
        self.v.ncols().min(self.v.nrows() - 1)
    }

    /// Poles (rad/s) of the order-`m` model.
    pub fn poles(&self, m: usize) -> Option<Vec<Complex64>> {
        let rows = self.v.nrows();
        let vm = self.v.columns(0, m);
        let v1 = vm.rows(0, rows - 1).into_owned();
        let v2 = vm.rows(1, rows - 1).into_owned();
        let a = v1.pseudo_inverse(1e-12).ok()? * v2;
        let z = a.complex_eigenvalues();
        if z.iter().any(|z| !z.is_finite() || z.norm() == 0.0) {
            return None;
        }
        Some(z.iter().map(|z| z.ln() / self.dt).collect())
    }
}
