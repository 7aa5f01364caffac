//! Covariances of a refinement's parameters: the pseudo-inverse of a
//! symmetric Gram matrix, the leverages (the hat matrix's diagonal), and a
//! Welch PSD fit's Whittle sandwich.

use nalgebra::{DMatrix, DVector};

/// Iteration cap of the small dense decompositions (QR-sweeps of an SVD or
/// symmetric eigensolver converge in a few per singular value; 10 000 is
/// only reached when the iteration cycles).
pub(super) const MAX_SWEEPS: usize = 10_000;

/// Lags of the bins' correlation that [`psd_covariance`] estimates. A Hann
/// window's DFT at bin k is ½Y_k − ¼(Y_{k−1} + Y_{k+1}) of the unwindowed
/// one, so over a locally flat spectrum neighbouring bins correlate in
/// amplitude by −2/3 and in power by 4/9 (lag 1), 1/36 (lag 2) and 0 beyond;
/// other tapers of Welch estimates reach no further in practice.
pub const PSD_CORRELATION_LAGS: usize = 2;

/// Covariance of the parameters of a PSD (Whittle) fit whose rows of
/// G = ∂ln S/∂θ are `g` and whose Pearson residuals are x_i = u_i − 1.
///
/// The estimate solves the Whittle score equations Σ_i g_i x_i = 0, so (the
/// usual M-estimator sandwich) Cov(θ̂) = A⁺ Var(Σ g_i x_i) A⁺ with A = GᵀG,
/// and Var(Σ g_i x_i) = Σ_ij g_i g_jᵀ Cov(x_i, x_j). With independent bins of
/// ν averages that is A/ν, the inverse Fisher information. A Welch estimate
/// (the thermal records, and most PSDs a user brings) breaks both halves:
/// - its window correlates neighbouring bins (4/9 at lag 1 for Hann, see
///   [`PSD_CORRELATION_LAGS`]), so Var(Σ g_i x_i) ≈ (1/ν)GᵀRG with
///   R_ij = ρ_|i−j|; for a parameter that moves S smoothly over a line's bins
///   that is (1 + 2Σρ_l) ≈ 1.94 times A/ν for Hann, sd 1.39× wider;
/// - its ν varies along the band: columns that see the same modes (the slices
///   of one tube) average as one at a line, where their shapes make the PSD,
///   and as several between lines, where the other modes' tails mix
///   differently in each.
///
/// Both are estimated from the residuals: ρ̂_l = Σ x_i x_{i+l}/Σ x_i², and
/// 1/ν̂_h = Σ h_i x_i²/Σ h_i(1 − h_i), the Pearson estimate weighted by the
/// leverages h_i = g_iᵀA⁺g_i (the bins that decide the parameters; E x_i² =
/// (1 − h_i)/ν for a linearised fit). On independent bins of one ν both
/// reduce to the inverse Fisher information up to their scatter. None when
/// A is singular.
pub fn psd_covariance(g: &DMatrix<f64>, x: &[f64]) -> Option<DMatrix<f64>> {
    let (a_inv, leverage) = leverages(g)?;
    let m = g.nrows();
    let sum_sq: f64 = x.iter().map(|v| v * v).sum();
    let (mut num, mut den) = (0.0, 0.0);
    for (xi, h) in x.iter().zip(&leverage) {
        let h = h.clamp(0.0, 1.0);
        num += h * xi * xi;
        den += h * (1.0 - h);
    }
    let inv_nu = if den > 0.0 { num / den } else { sum_sq / m.max(1) as f64 };
    let lags = PSD_CORRELATION_LAGS.min(m.saturating_sub(1));
    let rho: Vec<f64> = (1..=lags)
        .map(|lag| if sum_sq > 0.0 { x.iter().zip(&x[lag..]).map(|(a, b)| a * b).sum::<f64>() / sum_sq } else { 0.0 })
        .collect();
    let shrink = positive_correlation_factor(&rho);
    let mut b = g.transpose() * g;
    for (l, r) in rho.iter().enumerate() {
        let lag = l + 1;
        let upper = g.rows(0, m - lag);
        let lower = g.rows(lag, m - lag);
        let cross = upper.transpose() * lower;
        b += (&cross + cross.transpose()) * (r * shrink);
    }
    let cov = &a_inv * b * &a_inv * inv_nu;
    cov.iter().all(|v| v.is_finite()).then_some(cov)
}

/// (JᵀJ)⁺ and the leverages h_i = j_iᵀ(JᵀJ)⁺j_i (the hat matrix's diagonal)
/// of a Jacobian `j`; None when JᵀJ has no pseudo-inverse.
pub(crate) fn leverages(j: &DMatrix<f64>) -> Option<(DMatrix<f64>, Vec<f64>)> {
    let a_inv = pseudo_inverse_sym(&(j.transpose() * j))?;
    let ja = j * &a_inv;
    let h = (0..j.nrows()).map(|i| ja.row(i).dot(&j.row(i))).collect();
    Some((a_inv, h))
}

// `positive_correlation_factor` is written for two lags.

const _: () = assert!(PSD_CORRELATION_LAGS == 2);

/// The factor t ≤ 1 by which the estimated bin correlations ρ₁, ρ₂ must be
/// shrunk so that the banded Toeplitz R they define stays positive
/// semidefinite (otherwise GᵀRG could give a parameter a negative variance).
/// R is PSD when its symbol f(θ) = 1 + 2ρ₁cos θ + 2ρ₂cos 2θ is ≥ 0 on
/// [0, π]; with c = cos θ, f = 1 − 2ρ₂ + 2ρ₁c + 4ρ₂c², a quadratic on
/// [−1, 1] whose minimum lies at an end or, for ρ₂ > 0, at c = −ρ₁/(4ρ₂).
/// Shrinking all ρ by t maps f to 1 + t(f − 1), so t = 1/(1 − f_min) when
/// f_min < 0 (R then singular in one direction, never indefinite).
fn positive_correlation_factor(rho: &[f64]) -> f64 {
    let (r1, r2) = (rho.first().copied().unwrap_or(0.0), rho.get(1).copied().unwrap_or(0.0));
    let f = |c: f64| 1.0 - 2.0 * r2 + 2.0 * r1 * c + 4.0 * r2 * c * c;
    let mut f_min = f(-1.0).min(f(1.0));
    if r2 > 0.0 {
        let c = -r1 / (4.0 * r2);
        if (-1.0..=1.0).contains(&c) {
            f_min = f_min.min(f(c));
        }
    }
    if f_min < 0.0 {
        1.0 / (1.0 - f_min)
    } else {
        1.0
    }
}

/// Pseudo-inverse of a symmetric positive semi-definite matrix, after
/// Jacobi scaling (D⁻¹AD⁻¹, D = sqrt diag A: makes the result independent
/// of parameter units), dropping eigenvalues below 1e-12·max: beyond that
/// condition number the double-precision Gram matrix (relative error ~1e-16
/// times the condition number) no longer determines the direction.
pub(crate) fn pseudo_inverse_sym(a: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let d: Vec<f64> = (0..a.nrows()).map(|i| a[(i, i)].max(f64::MIN_POSITIVE).sqrt()).collect();
    let scaled = DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] / (d[i] * d[j]));
    let eig = scaled.try_symmetric_eigen(f64::EPSILON, MAX_SWEEPS)?;
    let max = eig.eigenvalues.iter().copied().fold(0.0, f64::max);
    if !(max > 0.0 && max.is_finite()) {
        return None;
    }
    let inv = DVector::from_iterator(
        eig.eigenvalues.len(),
        eig.eigenvalues.iter().map(|&l| if l > 1e-12 * max { 1.0 / l } else { 0.0 }),
    );
    let pinv = &eig.eigenvectors * DMatrix::from_diagonal(&inv) * eig.eigenvectors.transpose();
    Some(DMatrix::from_fn(a.nrows(), a.ncols(), |i, j| pinv[(i, j)] / (d[i] * d[j])))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, StandardNormal};

    /// Residuals correlated beyond what a banded R of two lags can hold
    /// (an AR(1) with coefficient 0.95, ρ̂₁ ≈ 0.95, ρ̂₂ ≈ 0.9: the symbol
    /// 1 + 2ρ₁cos θ + 2ρ₂cos 2θ is negative near θ = 2π/3) still give a
    /// positive semidefinite covariance: every eigenvalue ≥ −1e-12 of the
    /// largest, where the unshrunk R gives a negative one.
    #[test]
    fn the_sandwich_stays_positive_semidefinite_under_strong_correlation() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let m = 400;
        let mut x = vec![0.0; m];
        for i in 1..m {
            let e: f64 = StandardNormal.sample(&mut rng);
            x[i] = 0.95 * x[i - 1] + 0.1 * e;
        }
        // three smooth parameters and one that alternates bin to bin
        let g = DMatrix::from_fn(m, 4, |i, j| match j {
            0 => 1.0,
            1 => i as f64 / m as f64,
            2 => ((i as f64) * 2.0 * std::f64::consts::PI / 3.0).cos(),
            _ => ((i as f64) * 2.0 * std::f64::consts::PI / 3.0).sin(),
        });
        let eig = |c: &DMatrix<f64>| c.clone().symmetric_eigen().eigenvalues;
        let cov = psd_covariance(&g, &x).unwrap();
        let e = eig(&cov);
        let max = e.iter().copied().fold(0.0, f64::max);
        assert!(e.iter().all(|&v| v >= -1e-12 * max), "{e}");
        // the same without the shrink: R built from the raw ρ̂ is indefinite
        let ss: f64 = x.iter().map(|v| v * v).sum();
        let rho: Vec<f64> = (1..=2).map(|l| x.iter().zip(&x[l..]).map(|(a, b)| a * b).sum::<f64>() / ss).collect();
        assert!(positive_correlation_factor(&rho) < 1.0, "{rho:?}");
    }

    /// Welch estimate (Hann, 50 % overlap, `segments` segments of `len`) of
    /// white Gaussian noise at bins 2 … len/2 − 2, by a direct DFT written
    /// here (not `identify::thermal`'s FFT).
    fn welch_of_white_noise(len: usize, segments: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
        let n = len * (segments + 1) / 2;
        let x: Vec<f64> = (0..n).map(|_| StandardNormal.sample(rng)).collect();
        let w: Vec<f64> =
            (0..len).map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / len as f64).cos()).collect();
        let bins: Vec<usize> = (2..len / 2 - 1).collect();
        let mut p = vec![0.0; bins.len()];
        for s in 0..segments {
            let seg = &x[s * len / 2..s * len / 2 + len];
            for (out, &k) in p.iter_mut().zip(&bins) {
                let (mut re, mut im) = (0.0, 0.0);
                for (i, (v, wi)) in seg.iter().zip(&w).enumerate() {
                    let (sn, cs) = (2.0 * std::f64::consts::PI * (k * i) as f64 / len as f64).sin_cos();
                    re += v * wi * cs;
                    im -= v * wi * sn;
                }
                *out += (re * re + im * im) / segments as f64;
            }
        }
        p
    }

    /// The level θ = ln S of a flat PSD, fitted by Whittle (θ̂ = ln ȳ), on
    /// Welch estimates of white noise (segments of 128, bins 2 … 61): the
    /// variance of θ̂ over 1 000 replications against the mean of
    /// `psd_covariance`'s prediction. Their ratio is within 4 standard errors
    /// of 1: the empirical variance of 1 000 draws has relative se
    /// √(2/999) = 0.045 (θ̂ is nearly Gaussian: a mean over 60 bins), the
    /// predictions' mean a far smaller one. The
    /// independent-bin information (1/ν̂)/m, the formula before the
    /// sandwich, is low by the Hann window's 1 + 2(4/9 + 1/36) = 1.94 and
    /// fails that test.
    #[test]
    fn the_welch_sandwich_is_the_sampling_variance_of_a_level() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let (reps, mut thetas, mut predicted, mut fisher) = (1000, Vec::new(), 0.0, 0.0);
        for _ in 0..reps {
            let y = welch_of_white_noise(128, 8, &mut rng);
            let m = y.len();
            let mean = y.iter().sum::<f64>() / m as f64;
            thetas.push(mean.ln());
            let x: Vec<f64> = y.iter().map(|v| v / mean - 1.0).collect();
            let g = DMatrix::from_element(m, 1, 1.0);
            predicted += psd_covariance(&g, &x).unwrap()[(0, 0)] / reps as f64;
            fisher += x.iter().map(|v| v * v).sum::<f64>() / (m - 1) as f64 / m as f64 / reps as f64;
        }
        let mu = thetas.iter().sum::<f64>() / reps as f64;
        let empirical = thetas.iter().map(|t| (t - mu).powi(2)).sum::<f64>() / (reps - 1) as f64;
        let se = (2.0 / (reps - 1) as f64).sqrt();
        assert!((predicted / empirical - 1.0).abs() < 4.0 * se, "sandwich {predicted:.3e}, empirical {empirical:.3e}");
        assert!(
            (fisher / empirical - 1.0).abs() > 4.0 * se,
            "independent bins {fisher:.3e}, empirical {empirical:.3e}"
        );
    }
}
