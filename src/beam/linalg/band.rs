//! Banded matrices of half-bandwidth [`KD`] = 3 (two Hermite DOFs per node,
//! one element couples DOFs at most 3 apart, before and after eliminating
//! supported DOFs) — or, for the Timoshenko mesh (five DOFs per node), a
//! runtime half-bandwidth up to [`MAX_KD`] = 9 (`SymBand::kd`; the KD = 3 code
//! paths are unchanged) — and the factorisations the solvers need:
//!
//! * [`SymBand::ldl_inertia`]: banded LDLᵀ of A(σ) = K − σM in dual numbers,
//!   returning the Sylvester inertia (number of negative pivots = number of
//!   eigenvalues of K φ = λ M φ below σ, M ≻ 0) and d/dσ log|det A(σ)| = Σ dᵢ'/dᵢ;
//! * [`ShiftedLdl`] / [`ldl_factor_for_inverse_iteration`] + [`ldl_solve`]:
//!   unpivoted band LDLᵀ with stored multipliers (real symmetric or complex
//!   symmetric), the workhorse of Rayleigh-quotient iteration;
//! * [`BandLu`]: banded LU with partial pivoting (LAPACK `gbtrf` layout: the
//!   upper bandwidth grows from KD to 2·KD), generic over f64 and Complex64,
//!   for the FRF and the from-scratch paths.
//!
//! Hand-written: nalgebra (the listed linear-algebra crate) has no banded
//! factorisations, and dense O(n³) factorisations would be ~50× slower here.

use crate::beam::linalg::dual::{Dual, Scalar};

/// Half-bandwidth of the Euler–Bernoulli beam matrices.
pub const KD: usize = 3;
const W: usize = KD + 1;
/// Largest runtime half-bandwidth (the 5-DOF-per-node Timoshenko mesh:
/// 2·5 − 1 = 9).
pub const MAX_KD: usize = 9;

/// Symmetric band matrix of half-bandwidth `kd`, lower triangle stored:
/// (i, i−d) at `data[i·(kd+1) + d]`.
#[derive(Debug, Clone, PartialEq)]
pub struct SymBand {
    pub n: usize,
    pub kd: usize,
    pub data: Vec<f64>,
}

impl SymBand {
    pub fn zeros(n: usize) -> Self {
        Self { n, kd: KD, data: vec![0.0; n * W] }
    }

    /// Zeros with half-bandwidth `kd` ≤ [`MAX_KD`].
    pub fn zeros_kd(n: usize, kd: usize) -> Self {
        assert!(kd <= MAX_KD, "half-bandwidth {kd} > {MAX_KD}");
        Self { n, kd, data: vec![0.0; n * (kd + 1)] }
    }

    /// Entry (i, j) for |i − j| ≤ kd (either triangle), else 0.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > self.kd {
            0.0
        } else {
            self.data[i * (self.kd + 1) + (i - j)]
        }
    }

    /// Adds `v` to (i, j) and, by symmetry, (j, i). Requires |i − j| ≤ kd.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        debug_assert!(i - j <= self.kd);
        self.data[i * (self.kd + 1) + (i - j)] += v;
    }

    /// self + c·other (same size and bandwidth).
    pub fn plus_scaled(&self, c: f64, other: &SymBand) -> SymBand {
        debug_assert_eq!(self.kd, other.kd);
        let data = self.data.iter().zip(&other.data).map(|(a, b)| a + c * b).collect();
        SymBand { n: self.n, kd: self.kd, data }
    }

    /// xᵀ A y.
    pub fn bilinear(&self, x: &[f64], y: &[f64]) -> f64 {
        let mut s = 0.0;
        let w = self.kd + 1;
        for i in 0..self.n {
            let lo = i.saturating_sub(self.kd);
            for j in lo..=i {
                let a = self.data[i * w + (i - j)];
                s += if i == j { a * x[i] * y[i] } else { a * (x[i] * y[j] + x[j] * y[i]) };
            }
        }
        s
    }

    /// y = A x.
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n];
        self.mul_vec_into(x, &mut y);
        y
    }

    /// y = A x into a caller's buffer (resized to n), row by row as a gather
    /// yᵢ = Σ_d A(i, i−d) x_{i−d} + Σ_d A(i+d, i) x_{i+d}: every yᵢ is independent,
    /// so interior rows pipeline (a scatter form chains through y).
    pub fn mul_vec_into(&self, x: &[f64], y: &mut Vec<f64>) {
        let n = self.n;
        y.clear();
        y.resize(n, 0.0);
        let a = &self.data;
        match self.kd {
            MAX_KD => mul_vec_fixed::<MAX_KD>(a, n, x, y),
            KD => mul_vec_rows::<KD>(a, n, x, y, |i| {
                // the Euler–Bernoulli band, unrolled: pairs at each distance
                let rows: &[f64; 7 * W] = a[(i - KD) * W..(i + KD + 1) * W].try_into().expect("7 rows");
                let xs: &[f64; 2 * KD + 1] = x[i - KD..=i + KD].try_into().expect("window");
                let c = KD * W; // row i inside `rows`
                rows[c] * xs[KD]
                    + (rows[c + 1] * xs[2] + rows[c + W + 1] * xs[4])
                    + (rows[c + 2] * xs[1] + rows[c + 2 * W + 2] * xs[5])
                    + (rows[c + 3] * xs[0] + rows[c + 3 * W + 3] * xs[6])
            }),
            kd => y.iter_mut().enumerate().for_each(|(i, yi)| *yi = gather_row(a, kd, n, x, i)),
        }
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
        work.clear();
        work.extend(self.data.iter().zip(&m.data).map(|(k, mm)| Dual::new(k - sigma * mm, -mm)));
        let mut negatives = 0;
        let mut dlog = 0.0;
        ldl_in_place(work, self.n, self.kd, false, |d| {
            if d.v == 0.0 || !d.v.is_finite() {
                return None;
            }
            negatives += usize::from(d.v < 0.0);
            dlog += d.d / d.v;
            Some(d)
        })
        .then_some((negatives, dlog))
    }
}

/// In-place banded LDLᵀ of a symmetric band matrix in [`SymBand`] layout,
/// handing each pivot to `pivot`, which returns the pivot to use (the same,
/// or a replacement for an exact zero) or `None` to stop (the function then
/// returns false). With `store`, the
/// multipliers L(i, j) = A(i, j)/dⱼ replace the sub-diagonal entries (for
/// [`ShiftedLdl::solve`]); otherwise they are left as the Schur values.
fn ldl_in_place<T: Scalar>(
    a: &mut [T],
    n: usize,
    kd: usize,
    store: bool,
    mut pivot: impl FnMut(T) -> Option<T>,
) -> bool {
    let w = kd + 1;
    for j in 0..n {
        let Some(d) = pivot(a[j * w]) else { return false };
        a[j * w] = d;
        // column j below the diagonal: (j + 1 + r, j) sits at row j+1+r, offset r+1
        let below = kd.min(n - 1 - j);
        let mut col = [T::zero(); MAX_KD];
        for (r, c) in col.iter_mut().enumerate().take(below) {
            *c = a[(j + 1 + r) * w + r + 1];
        }
        // Schur complement of the trailing block: A(i,k) −= A(i,j) A(k,j) / d
        for r in 0..below {
            let l = col[r] / d;
            let row = &mut a[(j + 1 + r) * w..(j + 1 + r) * w + r + 2];
            if store {
                row[r + 1] = l;
            }
            // row offsets r − c for c = 0..=r, i.e. reversed
            for (e, &cc) in row[..=r].iter_mut().rev().zip(&col[..=r]) {
                *e = *e - l * cc;
            }
        }
    }
    true
}

/// y = A x for a band of compile-time half-bandwidth K (the Timoshenko
/// mesh's 9): the runtime-kd gather of [`SymBand::mul_vec_into`] with the
/// boundary tests hoisted out of the interior rows, so the inner loop has a
/// fixed trip count and no branches. The additions run in the same order
/// as the runtime loop's, so the result is bitwise the same (measured:
/// `SymBand::mul_vec_into` was 23 % of a coupled shear chain step).
fn mul_vec_fixed<const K: usize>(a: &[f64], n: usize, x: &[f64], y: &mut [f64]) {
    let w = K + 1;
    mul_vec_rows::<K>(a, n, x, y, |i| {
        let mut s = a[i * w] * x[i];
        for d in 1..=K {
            s += a[i * w + d] * x[i - d];
            s += a[(i + d) * w + d] * x[i + d];
        }
        s
    });
}

/// Row i of y = A x for a band of half-bandwidth `kd`, with the tests for
/// the band's ends: the reference order of additions (diagonal, then at each
/// distance d the lower and the upper neighbour).
fn gather_row(a: &[f64], kd: usize, n: usize, x: &[f64], i: usize) -> f64 {
    let w = kd + 1;
    let mut s = a[i * w] * x[i];
    for d in 1..=kd {
        if d <= i {
            s += a[i * w + d] * x[i - d];
        }
        if i + d < n {
            s += a[(i + d) * w + d] * x[i + d];
        }
    }
    s
}

/// y = A x for half-bandwidth K: [`gather_row`] on the K rows at each end
/// (and everywhere when n < 2K + 1), `interior(i)` on the rows whose band
/// lies inside the matrix.
fn mul_vec_rows<const K: usize>(a: &[f64], n: usize, x: &[f64], y: &mut [f64], interior: impl Fn(usize) -> f64) {
    if n < 2 * K + 1 {
        for (i, yi) in y.iter_mut().enumerate() {
            *yi = gather_row(a, K, n, x, i);
        }
        return;
    }
    for i in (0..K).chain(n - K..n) {
        y[i] = gather_row(a, K, n, x, i);
    }
    for (i, yi) in y.iter_mut().enumerate().take(n - K).skip(K) {
        *yi = interior(i);
    }
}

/// LDLᵀ of a shifted pencil K − σM without pivoting, for inverse iteration
/// (Rayleigh-quotient iteration) on the symmetric pencil. Without pivoting the
/// factorisation is not backward stable for every indefinite matrix (a nearly
/// singular leading block inflates the multipliers); its users therefore
/// verify what they compute (Rayleigh quotients, inertia counts) and fall back
/// to a pivoted path when the check fails. Its reward: the band stays at KD
/// and the negative pivots give the inertia at σ for free.
#[derive(Debug, Clone, Default)]
pub struct ShiftedLdl {
    n: usize,
    kd: usize,
    a: Vec<f64>,
    negatives: usize,
}

impl ShiftedLdl {
    /// Factorises K − σM (`k` = K); false on an exactly zero or non-finite pivot.
    /// Columns with a full band below them take an unrolled path (same
    /// arithmetic as [`ldl_in_place`], with 1/d formed once).
    pub fn factor(&mut self, k: &SymBand, m: &SymBand, sigma: f64) -> bool {
        self.factor_with(k, m, sigma, None)
    }

    /// As [`Self::factor`], but for inverse iteration at a shift that may be
    /// an eigenvalue to working precision (RQI gets there): an exactly zero
    /// pivot is replaced by `tiny` (the classic remedy — the solve then
    /// returns a huge multiple of the eigenvector, which is what is wanted).
    pub fn factor_for_inverse_iteration(&mut self, k: &SymBand, m: &SymBand, sigma: f64) -> bool {
        let tiny = f64::EPSILON * (k.data[0].abs() + (sigma * m.data[0]).abs());
        self.factor_with(k, m, sigma, Some(tiny))
    }

    fn factor_with(&mut self, k: &SymBand, m: &SymBand, sigma: f64, tiny: Option<f64>) -> bool {
        let n = k.n;
        self.n = n;
        self.kd = k.kd;
        self.a.clear();
        self.a.extend(k.data.iter().zip(&m.data).map(|(kk, mm)| kk - sigma * mm));
        let mut negatives = 0;
        // the unrolled block below is for KD = 3; other bandwidths take the generic loop
        let full = if k.kd == KD { n.saturating_sub(KD) } else { 0 };
        for j in 0..full {
            let blk: &mut [f64; 4 * W] = (&mut self.a[j * W..(j + 4) * W]).try_into().expect("4 rows");
            let mut d = blk[0];
            if d == 0.0 {
                if let Some(t) = tiny {
                    d = t;
                    blk[0] = t;
                }
            }
            if d == 0.0 || !d.is_finite() {
                self.negatives = negatives;
                return false;
            }
            negatives += usize::from(d < 0.0);
            let inv = 1.0 / d;
            // (j+1+r, j) sits at row r+1, offset r+1
            let (c0, c1, c2) = (blk[W + 1], blk[2 * W + 2], blk[3 * W + 3]);
            let (l0, l1, l2) = (c0 * inv, c1 * inv, c2 * inv);
            blk[W + 1] = l0;
            blk[2 * W + 2] = l1;
            blk[3 * W + 3] = l2;
            blk[W] -= l0 * c0;
            blk[2 * W + 1] -= l1 * c0;
            blk[2 * W] -= l1 * c1;
            blk[3 * W + 2] -= l2 * c0;
            blk[3 * W + 1] -= l2 * c1;
            blk[3 * W] -= l2 * c2;
        }
        let tail = &mut self.a[full * W..];
        let ok = ldl_in_place(tail, n - full, k.kd, true, |d| {
            let d = if d == 0.0 { tiny.unwrap_or(d) } else { d };
            negatives += usize::from(d < 0.0);
            (d != 0.0 && d.is_finite()).then_some(d)
        });
        self.negatives = negatives;
        ok
    }

    /// Number of negative pivots = eigenvalues of (K, M) below σ.
    pub fn negatives(&self) -> usize {
        self.negatives
    }

    /// Solves (K − σM) x = b in place.
    pub fn solve(&self, b: &mut [f64]) {
        ldl_solve(&self.a, self.n, self.kd, b);
    }
}

/// LDLᵀ (no pivoting, no conjugation) of a complex-symmetric or real
/// symmetric band matrix given in [`SymBand`] layout, in place, for inverse
/// iteration: an exactly zero pivot is replaced by `tiny` (see
/// [`ShiftedLdl::factor_for_inverse_iteration`]). False on a non-finite pivot.
/// Same caveat as [`ShiftedLdl`]: callers verify what they compute.
pub fn ldl_factor_for_inverse_iteration<T: Scalar>(a: &mut [T], n: usize, kd: usize, tiny: T) -> bool {
    ldl_in_place(a, n, kd, true, |d| {
        let d = if d.magnitude() == 0.0 { tiny } else { d };
        (d.magnitude() != 0.0 && d.magnitude().is_finite()).then_some(d)
    })
}

/// Solves A x = b in place with a factorisation from [`ldl_in_place`] with
/// stored multipliers: L z = b, D y = z, Lᵀ x = y.
pub fn ldl_solve<T: Scalar>(a: &[T], n: usize, kd: usize, b: &mut [T]) {
    let w = kd + 1;
    for i in 0..n {
        let row = &a[i * w..i * w + w];
        let mut s = b[i];
        // the newest unknown last: one multiply-add on the dependency chain
        for d in (1..=kd.min(i)).rev() {
            s = s - row[d] * b[i - d];
        }
        b[i] = s;
    }
    for i in 0..n {
        b[i] = b[i] / a[i * w];
    }
    // back substitution with Lᵀ: x_i = y_i − Σ_d L(i+d, i) x_{i+d}
    for i in (0..n).rev() {
        let mut s = b[i];
        for d in (1..=kd.min(n - 1 - i)).rev() {
            s = s - a[(i + d) * w + d] * b[i + d];
        }
        b[i] = s;
    }
}

/// General band matrix with kl = KD sub-diagonals and room for 2·KD
/// super-diagonals (fill from row interchanges), factorised in place.
#[derive(Debug, Clone)]
pub struct BandLu<T> {
    n: usize,
    /// kl = kd sub-diagonals, 2·kd super-diagonals, row width kl + 2kd + 1.
    kd: usize,
    ab: Vec<T>,
    piv: Vec<usize>,
}

impl<T: Scalar> BandLu<T> {
    /// Builds the band matrix of half-bandwidth `kd` ≤ [`MAX_KD`] from
    /// `entry(i, j)` for |i − j| ≤ kd and factorises it. Returns `None` if a
    /// pivot column is exactly zero (singular matrix).
    pub fn factor_kd(n: usize, kd: usize, entry: impl FnMut(usize, usize) -> T) -> Option<Self> {
        Self::factor_with(n, kd, entry, None)
    }

    /// For inverse iteration at a (numerically) exact eigenvalue: an exactly
    /// zero pivot is replaced by `tiny` (the classic remedy: the solve then
    /// returns a huge multiple of the eigenvector, which is what is wanted).
    pub fn factor_for_inverse_iteration(
        n: usize,
        kd: usize,
        entry: impl FnMut(usize, usize) -> T,
        tiny: T,
    ) -> Option<Self> {
        Self::factor_with(n, kd, entry, Some(tiny))
    }

    fn factor_with(n: usize, kd: usize, mut entry: impl FnMut(usize, usize) -> T, tiny: Option<T>) -> Option<Self> {
        let wg = 3 * kd + 1;
        let mut ab = vec![T::zero(); n * wg];
        for i in 0..n {
            let lo = i.saturating_sub(kd);
            let hi = (i + kd).min(n.saturating_sub(1));
            for j in lo..=hi {
                ab[i * wg + (j + kd - i)] = entry(i, j);
            }
        }
        let mut lu = BandLu { n, kd, ab, piv: vec![0; n] };
        lu.factor_in_place(tiny).then_some(lu)
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        i * (3 * self.kd + 1) + (j + self.kd - i)
    }

    /// Row-major band storage: row i holds columns i−KL ..= i+KU2 at offsets
    /// 0..WG, so the row operations below are slice operations (no per-entry
    /// index arithmetic or bounds checks in the inner loops).
    fn factor_in_place(&mut self, tiny: Option<T>) -> bool {
        let n = self.n;
        let (kl, kd, wg) = (self.kd, self.kd, 3 * self.kd + 1);
        for k in 0..n {
            let last_row = (k + kl).min(n - 1);
            let last_col = (k + kl + kd).min(n - 1);
            let mut p = k;
            let mut best = self.ab[self.idx(k, k)].magnitude();
            for i in k + 1..=last_row {
                let m = self.ab[self.idx(i, k)].magnitude();
                if m > best {
                    best = m;
                    p = i;
                }
            }
            if !best.is_finite() {
                return false;
            }
            if best == 0.0 {
                match tiny {
                    Some(t) => {
                        let kk = self.idx(k, k);
                        self.ab[kk] = t;
                    }
                    None => return false,
                }
            }
            self.piv[k] = p;
            let len = last_col - k + 1;
            if p != k {
                // row k: columns k.. at offset kl; row p: at offset kl − (p − k)
                let (head, tail) = self.ab.split_at_mut(p * wg);
                let rk = &mut head[k * wg + kl..k * wg + kl + len];
                let rp = &mut tail[kl - (p - k)..kl - (p - k) + len];
                rk.swap_with_slice(rp);
            }
            let (head, tail) = self.ab.split_at_mut((k + 1) * wg);
            let rk = &head[k * wg + kl..k * wg + kl + len];
            let pivot = rk[0];
            for (r, row) in tail.chunks_exact_mut(wg).take(last_row - k).enumerate() {
                let off = kl - (r + 1); // column k in row k + r + 1
                let ri = &mut row[off..off + len];
                let l = ri[0] / pivot;
                ri[0] = l;
                for (e, &u) in ri[1..].iter_mut().zip(&rk[1..]) {
                    *e = *e - l * u;
                }
            }
        }
        true
    }

    /// Solves A x = b in place.
    pub fn solve(&self, b: &mut [T]) {
        let n = self.n;
        let (kl, ku2, wg) = (self.kd, 2 * self.kd, 3 * self.kd + 1);
        for k in 0..n {
            let p = self.piv[k];
            if p != k {
                b.swap(k, p);
            }
            let bk = b[k];
            let hi = (k + kl).min(n - 1);
            for (i, bi) in b.iter_mut().enumerate().take(hi + 1).skip(k + 1) {
                *bi = *bi - self.ab[self.idx(i, k)] * bk;
            }
        }
        for i in (0..n).rev() {
            let hi = (i + ku2).min(n - 1);
            let row = &self.ab[i * wg + kl..i * wg + kl + (hi - i) + 1];
            let mut s = b[i];
            for (&a, &x) in row[1..].iter().zip(&b[i + 1..=hi]) {
                s = s - a * x;
            }
            b[i] = s / row[0];
        }
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

    /// The fixed-K product (half-bandwidth 9) is bitwise the runtime loop's
    /// (same additions in the same order) and, to rounding, the dense product
    /// (n·eps·‖A‖‖x‖ ≲ 1e-13 for these O(1) entries), for n below, at and
    /// above 2K + 1.
    #[test]
    fn wide_band_product_matches_runtime_loop_and_dense() {
        for n in [5usize, 19, 40] {
            let mut s = SymBand::zeros_kd(n, MAX_KD);
            let mut v = 0.37f64;
            for i in 0..n {
                for j in i.saturating_sub(MAX_KD)..=i {
                    v = (v * 7.13 + 0.29).fract();
                    s.add(i, j, if i == j { 4.0 + v } else { v - 0.5 });
                }
            }
            let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.61).sin()).collect();
            let mut y = Vec::new();
            s.mul_vec_into(&x, &mut y);
            let (kd, w) = (s.kd, s.kd + 1);
            for i in 0..n {
                let mut r = s.data[i * w] * x[i];
                for d in 1..=kd {
                    if d <= i {
                        r += s.data[i * w + d] * x[i - d];
                    }
                    if i + d < n {
                        r += s.data[(i + d) * w + d] * x[i + d];
                    }
                }
                assert_eq!(y[i].to_bits(), r.to_bits(), "n={n} row {i}");
            }
            let dense = s.to_dense() * nalgebra::DVector::from_vec(x);
            for i in 0..n {
                assert!((dense[i] - y[i]).abs() <= 1e-13, "n={n} row {i}: {} vs {}", dense[i], y[i]);
            }
        }
    }

    #[test]
    fn band_lu_solves_like_dense() {
        let n = 11;
        let a = random_band(n, 3);
        let b = random_band(n, 7);
        // nonsymmetric complex matrix A + i·B with a skew part
        let entry = |i: usize, j: usize| Complex64::new(a.get(i, j) + 0.3 * (i as f64 - j as f64), b.get(i, j));
        let lu = BandLu::factor_kd(n, KD, entry).unwrap();
        let dense =
            nalgebra::DMatrix::from_fn(
                n,
                n,
                |i, j| if i.abs_diff(j) <= KD { entry(i, j) } else { Complex64::new(0.0, 0.0) },
            );
        let rhs: Vec<Complex64> = (0..n).map(|i| Complex64::new(i as f64, 1.0)).collect();
        let mut x = rhs.clone();
        lu.solve(&mut x);
        let r = &dense * nalgebra::DVector::from_vec(x) - nalgebra::DVector::from_vec(rhs);
        // backward-stable solve of a well-conditioned (diagonally dominant) system: residual ~ n·eps·‖A‖‖x‖
        assert!(r.norm() < 1e-12, "residual {}", r.norm());
    }

    /// A small SPD tridiagonal "mass": diagonal 1 + 0.1 i, off-diagonal 0.05.
    fn test_mass(n: usize) -> SymBand {
        let mut m = SymBand::zeros(n);
        for i in 0..n {
            m.add(i, i, 1.0 + 0.1 * i as f64);
            if i > 0 {
                m.add(i, i - 1, 0.05);
            }
        }
        m
    }

    #[test]
    fn shifted_ldl_solves_counts_and_multiplies_like_dense() {
        for n in [2, 4, 13] {
            let k = random_band(n, 5);
            let m = test_mass(n);
            let x: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5).sin()).collect();
            let dense_mx = m.to_dense() * nalgebra::DVector::from_column_slice(&x);
            let mut mx = Vec::new();
            m.mul_vec_into(&x, &mut mx);
            // a handful of products of O(1) terms: rounding ≲ 10 eps
            assert!((nalgebra::DVector::from_vec(mx) - &dense_mx).norm() < 1e-14);
            let sigma = 0.9;
            let mut ldl = ShiftedLdl::default();
            assert!(ldl.factor(&k, &m, sigma));
            let a = k.to_dense() - m.to_dense() * sigma;
            let chol = nalgebra::Cholesky::new(m.to_dense()).unwrap();
            let linv = chol.l().try_inverse().unwrap();
            let eig = nalgebra::SymmetricEigen::new(&linv * k.to_dense() * linv.transpose()).eigenvalues;
            assert_eq!(ldl.negatives(), eig.iter().filter(|&&l| l < sigma).count());
            let mut b = x.clone();
            ldl.solve(&mut b);
            let r = &a * nalgebra::DVector::from_vec(b) - nalgebra::DVector::from_vec(x);
            // random diagonally weighted band, σ away from its eigenvalues:
            // backward-stable-sized residual n·eps·‖A‖‖x‖ ≈ 1e-14
            assert!(r.norm() < 1e-12, "n = {n}: residual {}", r.norm());
        }
    }

    #[test]
    fn inertia_and_log_det_derivative() {
        let n = 9;
        let k = random_band(n, 11);
        let m = test_mass(n);
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
