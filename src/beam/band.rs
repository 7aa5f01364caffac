//! Banded matrices of half-bandwidth [`KD`] = 3 (two Hermite DOFs per node,
//! one element couples DOFs at most 3 apart, before and after eliminating
//! supported DOFs) and the two factorisations the solvers need:
//!
//! * [`SymBand::ldl_inertia`]: banded LDLᵀ of A(σ) = K − σM in dual numbers,
//!   returning the Sylvester inertia (number of negative pivots = number of
//!   eigenvalues of K φ = λ M φ below σ, M ≻ 0) and d/dσ log|det A(σ)| = Σ dᵢ'/dᵢ;
//! * [`BandLu`]: banded LU with partial pivoting (LAPACK `gbtrf` layout: the
//!   upper bandwidth grows from KD to 2·KD), generic over f64, Complex64 and
//!   dual numbers, with solve and d(log det)/ds.
//!
//! Hand-written: nalgebra (the listed linear-algebra crate) has no banded
//! factorisations, and dense O(n³) factorisations would be ~50× slower here.

use crate::beam::dual::{Dual, Scalar};

/// Half-bandwidth of every assembled beam matrix.
pub const KD: usize = 3;
const W: usize = KD + 1;

/// Symmetric band matrix, lower triangle stored: (i, i−d) at `data[i·(KD+1) + d]`.
#[derive(Debug, Clone, PartialEq)]
pub struct SymBand {
    pub n: usize,
    pub data: Vec<f64>,
}

impl SymBand {
    pub fn zeros(n: usize) -> Self {
        Self { n, data: vec![0.0; n * W] }
    }

    /// Entry (i, j) for |i − j| ≤ KD (either triangle), else 0.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > KD {
            0.0
        } else {
            self.data[i * W + (i - j)]
        }
    }

    /// Adds `v` to (i, j) and, by symmetry, (j, i). Requires |i − j| ≤ KD.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        debug_assert!(i - j <= KD);
        self.data[i * W + (i - j)] += v;
    }

    /// self + c·other (same size).
    pub fn plus_scaled(&self, c: f64, other: &SymBand) -> SymBand {
        let data = self.data.iter().zip(&other.data).map(|(a, b)| a + c * b).collect();
        SymBand { n: self.n, data }
    }

    /// xᵀ A y.
    pub fn bilinear(&self, x: &[f64], y: &[f64]) -> f64 {
        let mut s = 0.0;
        for i in 0..self.n {
            let lo = i.saturating_sub(KD);
            for j in lo..=i {
                let a = self.data[i * W + (i - j)];
                s += if i == j { a * x[i] * y[i] } else { a * (x[i] * y[j] + x[j] * y[i]) };
            }
        }
        s
    }

    /// y = A x.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        for i in 0..self.n {
            let lo = i.saturating_sub(KD);
            for j in lo..=i {
                let a = self.data[i * W + (i - j)];
                y[i] += a * x[j];
                if i != j {
                    y[j] += a * x[i];
                }
            }
        }
        y
    }

    /// Dense copy (reference paths and tests only).
    pub fn to_dense(&self) -> nalgebra::DMatrix<f64> {
        nalgebra::DMatrix::from_fn(self.n, self.n, |i, j| self.get(i, j))
    }

    /// Banded LDLᵀ (no pivoting) of A(σ) = K − σM with K = `self`, carried in
    /// dual numbers (value K − σM, derivative −M). Returns
    /// (number of negative pivots, Σ dᵢ'/dᵢ = d/dσ log|det A|), or `None` on an
    /// exactly zero pivot (the caller then nudges σ). `work` is reused.
    pub fn ldl_inertia(&self, m: &SymBand, sigma: f64, work: &mut Vec<Dual<f64>>) -> Option<(usize, f64)> {
        let n = self.n;
        work.clear();
        work.extend(self.data.iter().zip(&m.data).map(|(k, mm)| Dual::new(k - sigma * mm, -mm)));
        let mut negatives = 0;
        let mut dlog = 0.0;
        for j in 0..n {
            let d = work[j * W];
            if d.v == 0.0 || !d.v.is_finite() {
                return None;
            }
            if d.v < 0.0 {
                negatives += 1;
            }
            dlog += d.d / d.v;
            let last = (j + KD).min(n - 1);
            // Schur complement update of the trailing KD×KD block:
            // A(i,k) -= A(i,j) A(k,j) / d for j < k <= i <= j+KD.
            let inv = Dual::new(1.0 / d.v, -d.d / (d.v * d.v));
            for i in j + 1..=last {
                let t_i = work[i * W + (i - j)];
                let t_i_inv = t_i * inv;
                for k in j + 1..=i {
                    let t_k = work[k * W + (k - j)];
                    let e = &mut work[i * W + (i - k)];
                    *e = *e - t_i_inv * t_k;
                }
            }
        }
        Some((negatives, dlog))
    }
}

/// General band matrix with kl = KD sub-diagonals and room for 2·KD
/// super-diagonals (fill from row interchanges), factorised in place.
#[derive(Debug, Clone)]
pub struct BandLu<T> {
    n: usize,
    ab: Vec<T>,
    piv: Vec<usize>,
}

const KL: usize = KD;
const KU2: usize = 2 * KD;
const WG: usize = KL + KU2 + 1;

impl<T: Scalar> BandLu<T> {
    /// Builds the band matrix from `entry(i, j)` for |i − j| ≤ KD and factorises it.
    /// Returns `None` if a pivot column is exactly zero (singular matrix).
    pub fn factor(n: usize, mut entry: impl FnMut(usize, usize) -> T) -> Option<Self> {
        let mut ab = vec![T::zero(); n * WG];
        for i in 0..n {
            let lo = i.saturating_sub(KD);
            let hi = (i + KD).min(n.saturating_sub(1));
            for j in lo..=hi {
                ab[i * WG + (j + KL - i)] = entry(i, j);
            }
        }
        let mut lu = BandLu { n, ab, piv: vec![0; n] };
        lu.factor_in_place().then_some(lu)
    }

    #[inline]
    fn idx(i: usize, j: usize) -> usize {
        i * WG + (j + KL - i)
    }

    fn factor_in_place(&mut self) -> bool {
        let n = self.n;
        for k in 0..n {
            let last_row = (k + KL).min(n - 1);
            let last_col = (k + KL + KD).min(n - 1);
            let mut p = k;
            let mut best = self.ab[Self::idx(k, k)].magnitude();
            for i in k + 1..=last_row {
                let m = self.ab[Self::idx(i, k)].magnitude();
                if m > best {
                    best = m;
                    p = i;
                }
            }
            if best == 0.0 || !best.is_finite() {
                return false;
            }
            self.piv[k] = p;
            if p != k {
                for j in k..=last_col {
                    self.ab.swap(Self::idx(k, j), Self::idx(p, j));
                }
            }
            let pivot = self.ab[Self::idx(k, k)];
            for i in k + 1..=last_row {
                let l = self.ab[Self::idx(i, k)] / pivot;
                self.ab[Self::idx(i, k)] = l;
                for j in k + 1..=last_col {
                    let u = self.ab[Self::idx(k, j)];
                    let e = &mut self.ab[Self::idx(i, j)];
                    *e = *e - l * u;
                }
            }
        }
        true
    }

    /// Solves A x = b in place.
    pub fn solve(&self, b: &mut [T]) {
        let n = self.n;
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
            let bk = b[k];
            for i in k + 1..=(k + KL).min(n - 1) {
                b[i] = b[i] - self.ab[Self::idx(i, k)] * bk;
            }
        }
        for i in (0..n).rev() {
            let mut s = b[i];
            for j in i + 1..=(i + KU2).min(n - 1) {
                s = s - self.ab[Self::idx(i, j)] * b[j];
            }
            b[i] = s / self.ab[Self::idx(i, i)];
        }
    }

    /// The diagonal of U (det A = ± Π uᵢᵢ).
    pub fn pivots(&self) -> impl Iterator<Item = T> + '_ {
        (0..self.n).map(|i| self.ab[Self::idx(i, i)])
    }
}

impl<T: Scalar> BandLu<Dual<T>> {
    /// d/ds log det A(s) = Σ uᵢᵢ'/uᵢᵢ (row interchanges only flip the sign of det).
    pub fn dlog_det(&self) -> T {
        self.pivots().fold(T::zero(), |acc, u| acc + u.d / u.v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_complex::Complex64;

    fn random_band(n: usize, seed: u64) -> SymBand {
        let mut s = SymBand::zeros(n);
        let mut x = seed;
        let mut next = || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((x >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for i in 0..n {
            for j in i.saturating_sub(KD)..=i {
                s.add(i, j, if i == j { 4.0 + next() } else { next() });
            }
        }
        s
    }

    #[test]
    fn band_lu_solves_like_dense() {
        let n = 11;
        let a = random_band(n, 3);
        let b = random_band(n, 7);
        // nonsymmetric complex matrix A + i·B with a skew part
        let entry = |i: usize, j: usize| Complex64::new(a.get(i, j) + 0.3 * (i as f64 - j as f64), b.get(i, j));
        let lu = BandLu::factor(n, entry).unwrap();
        let dense = nalgebra::DMatrix::from_fn(n, n, |i, j| if i.abs_diff(j) <= KD { entry(i, j) } else { Complex64::new(0.0, 0.0) });
        let rhs: Vec<Complex64> = (0..n).map(|i| Complex64::new(i as f64, 1.0)).collect();
        let mut x = rhs.clone();
        lu.solve(&mut x);
        let r = &dense * nalgebra::DVector::from_vec(x) - nalgebra::DVector::from_vec(rhs);
        // backward-stable solve of a well-conditioned (diagonally dominant) system: residual ~ n·eps·‖A‖‖x‖
        assert!(r.norm() < 1e-12, "residual {}", r.norm());
    }

    #[test]
    fn inertia_and_log_det_derivative() {
        let n = 9;
        let k = random_band(n, 11);
        let mut m = SymBand::zeros(n);
        for i in 0..n {
            m.add(i, i, 1.0 + 0.1 * i as f64);
            if i > 0 {
                m.add(i, i - 1, 0.05);
            }
        }
        let sigma = 0.7;
        let mut w = Vec::new();
        let (neg, dlog) = k.ldl_inertia(&m, sigma, &mut w).unwrap();
        // reference: eigenvalues of L⁻¹ K L⁻ᵀ with M = L Lᵀ
        let chol = nalgebra::Cholesky::new(m.to_dense()).unwrap();
        let linv = chol.l().try_inverse().unwrap();
        let c = &linv * k.to_dense() * linv.transpose();
        let eig = nalgebra::SymmetricEigen::new(c).eigenvalues;
        let count = eig.iter().filter(|&&l| l < sigma).count();
        let expect: f64 = eig.iter().map(|l| 1.0 / (sigma - l)).sum();
        assert_eq!(neg, count);
        // symmetric eigenvalues are accurate to ~eps‖A‖; the sum has ≤ 9 terms of size ≤ 1/min|σ−λ|
        assert!((dlog - expect).abs() < 1e-10 * expect.abs().max(1.0), "{dlog} vs {expect}");
    }
}
