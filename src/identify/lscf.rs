//! Least-squares complex-frequency-domain estimator (LSCF; Guillaume,
//! Verboven, Vanlanduit, Van der Auweraer & Peeters, "A poly-reference
//! implementation of the least-squares complex frequency-domain estimator",
//! IMAC 2003), single input, single output: the rational-fraction polynomial
//! fit in the z-domain basis that stays well conditioned at high orders.
//!
//! Model: H(ω) ≈ B(Ω)/A(Ω), Ω = exp(−iωΔt), Δt = π/ω_max, with real
//! polynomial coefficients b_j, a_j (j = 0 … n). The linearised ("Levy")
//! equation error e_k = B(Ω_k) − H_k A(Ω_k) is minimised in least squares.
//! Because the basis functions are powers of one unit-modulus number, the
//! normal matrices are Toeplitz:
//!   R_jl = Σ_k cos((j−l)θ_k),  S_jl = −Σ_k Re(H_k e^{−i(l−j)θ_k}),
//!   T_jl = Σ_k |H_k|² cos((j−l)θ_k),   θ_k = ω_kΔt,
//! so they are built once at the highest order in O(N·n_max) and every lower
//! order uses their leading blocks. Eliminating b gives the reduced normal
//! matrix M = T − SᵀR⁻¹S; the denominator solves M a = 0 with a_n = 1
//! (the classical LSCF constraint). Poles: the roots Ω_r of A, s_r = −ln(Ω_r)/Δt.
//!
//! Real-valued data (a PSD or |H|²) are fitted the same way; their rational
//! model has the stable poles and their mirror images −s̄ (|Ω| < 1), which the
//! caller discards by the sign of Re s.

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// The Toeplitz sums of one data set, up to order `n_max`.
pub struct Lscf {
    dt: f64,
    n_max: usize,
    /// r(m), m = 0 … 2n_max (symmetric).
    r: Vec<f64>,
    /// s(m) for m = −n_max … n_max, stored at m + n_max.
    s: Vec<f64>,
    /// t(m), m = 0 … 2n_max.
    t: Vec<f64>,
}

impl Lscf {
    /// Sums for data `h` at `omega_rad_s`, with Δt = π/`w_nyquist`
    /// (`w_nyquist` ≥ the highest frequency: poles up to it are representable).
    pub fn new(omega_rad_s: &[f64], h: &[Complex64], n_max: usize, w_nyquist: f64) -> Self {
        let dt = std::f64::consts::PI / w_nyquist;
        let mut r = vec![0.0; n_max + 1];
        let mut t = vec![0.0; n_max + 1];
        let mut s = vec![0.0; 2 * n_max + 1];
        for (&w, &hk) in omega_rad_s.iter().zip(h) {
            let th = w * dt;
            let step = Complex64::from_polar(1.0, -th);
            let mut z = Complex64::new(1.0, 0.0); // e^{−imθ}
            let h2 = hk.norm_sqr();
            for m in 0..=n_max {
                r[m] += z.re;
                t[m] += h2 * z.re;
                // s(m) = −Re(H e^{−imθ}); s(−m) = −Re(H e^{imθ})
                s[n_max + m] -= (hk * z).re;
                if m > 0 {
                    s[n_max - m] -= (hk * z.conj()).re;
                }
                z *= step;
            }
        }
        Self { dt, n_max, r, s, t }
    }

    /// Poles (rad/s) of the order-`n` fit (1 ≤ n ≤ n_max); `None` when the
    /// reduced normal equations are singular.
    pub fn poles(&self, n: usize) -> Option<Vec<Complex64>> {
        assert!(n >= 1 && n <= self.n_max, "LSCF order out of range");
        let p = n + 1;
        let r = DMatrix::from_fn(p, p, |j, l| self.r[j.abs_diff(l)]);
        let s = DMatrix::from_fn(p, p, |j, l| self.s[(self.n_max + l) - j]);
        let t = DMatrix::from_fn(p, p, |j, l| self.t[j.abs_diff(l)]);
        let rinv_s = r.cholesky()?.solve(&s);
        let m = t - s.transpose() * rinv_s;
        let m00 = m.view((0, 0), (n, n)).into_owned();
        let rhs = -m.view((0, n), (n, 1)).into_owned();
        let a = m00.clone().cholesky().map(|c| c.solve(&rhs)).or_else(|| m00.lu().solve(&rhs))?;
        let mut coeffs: Vec<f64> = a.iter().copied().collect();
        coeffs.push(1.0);
        let roots = polynomial_roots(&coeffs)?;
        Some(roots.into_iter().map(|z| -z.ln() / self.dt).collect())
    }
}

/// Roots of Σ c_j x^j (c monic in its last entry) as the eigenvalues of the
/// companion matrix.
pub fn polynomial_roots(c: &[f64]) -> Option<Vec<Complex64>> {
    let n = c.len() - 1;
    if n == 0 {
        return Some(vec![]);
    }
    let lead = c[n];
    let mut comp = DMatrix::<f64>::zeros(n, n);
    for i in 1..n {
        comp[(i, i - 1)] = 1.0;
    }
    for i in 0..n {
        comp[(i, n - 1)] = -c[i] / lead;
    }
    let ev: DVector<Complex64> = comp.complex_eigenvalues();
    ev.iter().all(|z| z.is_finite()).then(|| ev.iter().copied().collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_mode_rational_data_give_its_poles() {
        // H(s) = Σ R/(s−p) + c.c. on a grid. The z-domain model only
        // approximates an s-domain rational function (the refinement, in s,
        // removes the rest), so the initial poles are checked to 1e-4 relative:
        // the accuracy the stabilisation criteria (1 % in ω) need, with margin.
        let poles = [Complex64::new(-0.02, 1.0), Complex64::new(-0.05, 2.5)];
        let res = [Complex64::new(0.0, -0.5), Complex64::new(0.1, 0.3)];
        let w: Vec<f64> = (1..=400).map(|k| k as f64 * 0.01).collect();
        let h: Vec<Complex64> = w
            .iter()
            .map(|&w| {
                let s = Complex64::new(0.0, w);
                poles.iter().zip(&res).map(|(&p, &r)| r / (s - p) + r.conj() / (s - p.conj())).sum()
            })
            .collect();
        let l = Lscf::new(&w, &h, 20, 4.0);
        let found = l.poles(12).unwrap();
        for p in poles {
            let best = found.iter().map(|q| (q - p).norm() / p.norm()).fold(f64::INFINITY, f64::min);
            assert!(best < 1e-4, "pole {p} not found: {best:e}");
        }
    }
}
