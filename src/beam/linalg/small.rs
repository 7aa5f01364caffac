//! Dense solves of fixed small size (the 5 × 5 blocks and the 3 × 3 Schur
//! complement of `fast::shear_blocks`): LU with partial pivoting over any
//! [`Scalar`], and the negative count of an LDLᵀ factorisation (the inertia
//! a bordered determinant's mode order is certified by).

// Index loops over the rows and columns of fixed-size matrices read as the
// textbook elimination does (as in `fast::shear_blocks`).
#![allow(clippy::needless_range_loop)]

use crate::beam::linalg::dual::Scalar;

/// LU with partial pivoting of the leading n × n of `a` in place; the
/// determinant, or `None` at a zero pivot. `rhs` (n × m) is overwritten by
/// a⁻¹·rhs.
pub(crate) fn lu_solve<T: Scalar, const N: usize, const M: usize>(
    a: &mut [[T; N]; N],
    n: usize,
    rhs: &mut [[T; M]; N],
    m: usize,
) -> Option<T> {
    let mut det: Option<T> = None;
    let mut sign = false;
    for c in 0..n {
        let piv = (c..n).max_by(|&x, &y| a[x][c].magnitude().total_cmp(&a[y][c].magnitude()))?;
        if !(a[piv][c].magnitude() > 0.0) {
            return None;
        }
        if piv != c {
            a.swap(piv, c);
            rhs.swap(piv, c);
            sign = !sign;
        }
        let d = a[c][c];
        det = Some(det.map_or(d, |x| x * d));
        for r in c + 1..n {
            let f = a[r][c] / d;
            for k in c + 1..n {
                a[r][k] = a[r][k] - f * a[c][k];
            }
            for k in 0..m {
                rhs[r][k] = rhs[r][k] - f * rhs[c][k];
            }
        }
    }
    for r in (0..n).rev() {
        for k in 0..m {
            let mut v = rhs[r][k];
            for c in r + 1..n {
                v = v - a[r][c] * rhs[c][k];
            }
            rhs[r][k] = v / a[r][r];
        }
    }
    let det = det?;
    Some(if sign { -det } else { det })
}

/// Negative pivots of an LDLᵀ without pivoting of the leading n × n of the
/// symmetric `a`; `None` at a zero or non-finite pivot.
pub(crate) fn ldl_negatives<const N: usize>(mut a: [[f64; N]; N], n: usize) -> Option<usize> {
    let mut neg = 0;
    for c in 0..n {
        let d = a[c][c];
        if !(d.is_finite() && d != 0.0) {
            return None;
        }
        neg += usize::from(d < 0.0);
        for r in c + 1..n {
            let f = a[r][c] / d;
            for k in c + 1..=r {
                a[r][k] -= f * a[k][c];
                a[k][r] = a[r][k];
            }
        }
    }
    Some(neg)
}
