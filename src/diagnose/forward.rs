//! The model's predictions y(θ) = [ω_r, ζ_r], eqs. (34)–(36), for the modes a
//! diagnosis needs.
//!
//! A fast path of the same FE model as `crate::beam::modal`, specialised to
//! what a diagnosis evaluates ~10⁵ times: simply-supported beams, exactly
//! decoupled into standing waves, with an attached mass or end springs as an
//! exact rank-one (secular-equation) update of that basis; other supports and
//! combinations use a dense generalized eigenproblem. tests/diagnose_forward.rs
//! checks every path against `crate::beam::modal` (agreement ≤ 1e-12 without
//! springs). KNOWN DEFECT: with end springs the modal projection below
//! neglects the coupling between the elastic spring and the viscoelastic
//! stiffness across modes: 2e-4 on ω / 3e-3 on ζ at κ = 0.5 EI/L (≈ 0.1 σ).
//! Hand-written rather than calling `beam::modal` because the general
//! (state-space) path there costs ~1–2 ms per call for springs, which would put the
//! hidden-effect suite far beyond its time budget.
//!
//! Model: M = ρA(∫NNᵀ + (e0a)²∫N'N'ᵀ) (+ point mass m N(x)N(x)ᵀ), D = (C/ρA)·M_beam
//! (A5 is A4 with C for ρA), K = EI∫N''N''ᵀ (+ rotational springs on the
//! rotation DOF of each supported, rotation-free end). With φ_r the
//! M-orthonormal modes of (K, M), each mode obeys
//! s² + c_r s + k_s,r + k_b,r [1 + Σ Δi s/(s + Ωi)] = 0 (A8 projected), whose
//! complex root is the pole s_r; ω_r = |s_r|, ζ_r = −Re s_r/|s_r| (34–35).

use nalgebra::{DMatrix, DVector};

use crate::beam::{BeamSpec, Support};

/// One mode's predicted modal pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalPair {
    pub omega_rad_s: f64,
    pub zeta: f64,
}

/// Predicts the first `n_modes` modal pairs, sorted by frequency. `Err` when
/// the model cannot produce them (overdamped mode, singular matrices).
pub fn predict(beam: &BeamSpec, n_modes: usize) -> Result<Vec<ModalPair>, String> {
    if beam.support == Support::SimplySupported
        && beam.point_mass.is_none()
        && beam.support_rotational_stiffness_n_m_rad == 0.0
    {
        return predict_simply_supported(beam, n_modes);
    }
    if beam.support == Support::SimplySupported
        && (beam.point_mass.is_none() || beam.support_rotational_stiffness_n_m_rad == 0.0)
    {
        return predict_rank_one(beam, n_modes);
    }
    dense(beam, n_modes)
}

/// The reference path: dense generalized eigenproblem of (K, M), modal projection.
fn dense(beam: &BeamSpec, n_modes: usize) -> Result<Vec<ModalPair>, String> {
    let ne = beam.elements;
    let l = beam.length_nm * 1e-9;
    let h = l / ne as f64;
    let rho_a = beam.density_kg_m3 * beam.area_m2();
    let ei = beam.youngs_modulus_pa * beam.inertia_m4();
    let ea2 = (beam.nonlocal_e0a_nm * 1e-9).powi(2);
    let ndof = 2 * (ne + 1);
    let mut m = DMatrix::<f64>::zeros(ndof, ndof);
    let mut k = DMatrix::<f64>::zeros(ndof, ndof);
    let cm = [
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h],
    ];
    let cg = [
        [36.0, 3.0 * h, -36.0, 3.0 * h],
        [3.0 * h, 4.0 * h * h, -3.0 * h, -h * h],
        [-36.0, -3.0 * h, 36.0, -3.0 * h],
        [3.0 * h, -h * h, -3.0 * h, 4.0 * h * h],
    ];
    let ck = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
    ];
    for e in 0..ne {
        let o = 2 * e;
        for i in 0..4 {
            for j in 0..4 {
                m[(o + i, o + j)] += rho_a * (h / 420.0 * cm[i][j] + ea2 / (30.0 * h) * cg[i][j]);
                k[(o + i, o + j)] += ei / h.powi(3) * ck[i][j];
            }
        }
    }
    let mut ks = DMatrix::<f64>::zeros(ndof, ndof);
    let kr = beam.support_rotational_stiffness_n_m_rad;
    let (fixed, sprung): (Vec<usize>, Vec<usize>) = match beam.support {
        Support::SimplySupported => (vec![0, ndof - 2], vec![1, ndof - 1]),
        Support::ClampedClamped => (vec![0, 1, ndof - 2, ndof - 1], vec![]),
        Support::ClampedFree => (vec![0, 1], vec![]),
        Support::ClampedPinned => (vec![0, 1, ndof - 2], vec![ndof - 1]),
    };
    for &d in &sprung {
        ks[(d, d)] += kr;
    }
    let mut m_total = m.clone();
    if let Some(pm) = &beam.point_mass {
        let x = (pm.x_nm * 1e-9).clamp(0.0, l);
        let e = ((x / h).floor() as usize).min(ne - 1);
        let xi = x - e as f64 * h;
        let r = xi / h;
        let nv = [
            1.0 - 3.0 * r * r + 2.0 * r.powi(3),
            xi * (1.0 - r).powi(2),
            3.0 * r * r - 2.0 * r.powi(3),
            xi * (r * r - r),
        ];
        for i in 0..4 {
            for j in 0..4 {
                m_total[(2 * e + i, 2 * e + j)] += pm.mass_kg * nv[i] * nv[j];
            }
        }
    }
    let free: Vec<usize> = (0..ndof).filter(|d| !fixed.contains(d)).collect();
    let nf = free.len();
    let sub = |a: &DMatrix<f64>| DMatrix::from_fn(nf, nf, |i, j| a[(free[i], free[j])]);
    let (m_f, mb_f, k_f, ks_f) = (sub(&m_total), sub(&m), sub(&k), sub(&ks));
    let chol = m_f.clone().cholesky().ok_or("mass matrix not positive definite")?;
    let linv = chol.l().try_inverse().ok_or("singular mass matrix")?;
    let a = &linv * (&k_f + &ks_f) * linv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let eig = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..nf).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    if n_modes > nf {
        return Err(format!("{n_modes} modes requested, the mesh has {nf} DOFs"));
    }
    let c_per_rho_a = beam.viscous_damping_n_s_m2 / rho_a;
    let mut out = Vec::with_capacity(n_modes);
    for &idx in order.iter().take(n_modes) {
        let phi: DVector<f64> = linv.transpose() * eig.eigenvectors.column(idx);
        let kb = (phi.transpose() * &k_f * &phi)[(0, 0)];
        let ksr = (phi.transpose() * &ks_f * &phi)[(0, 0)];
        let c = c_per_rho_a * (phi.transpose() * &mb_f * &phi)[(0, 0)];
        out.push(modal_pole(kb, ksr, c, &beam.internal_variables)?);
    }
    out.sort_by(|a, b| a.omega_rad_s.total_cmp(&b.omega_rad_s));
    Ok(out)
}

/// Element matrices (ρA-scaled mass with the nonlocal term of A4, and A6).
fn element_matrices(beam: &BeamSpec) -> ([[f64; 4]; 4], [[f64; 4]; 4]) {
    let h = beam.length_nm * 1e-9 / beam.elements as f64;
    let rho_a = beam.density_kg_m3 * beam.area_m2();
    let ei = beam.youngs_modulus_pa * beam.inertia_m4();
    let ea2 = (beam.nonlocal_e0a_nm * 1e-9).powi(2);
    let cm = [
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h],
    ];
    let cg = [
        [36.0, 3.0 * h, -36.0, 3.0 * h],
        [3.0 * h, 4.0 * h * h, -3.0 * h, -h * h],
        [-36.0, -3.0 * h, 36.0, -3.0 * h],
        [3.0 * h, -h * h, -3.0 * h, 4.0 * h * h],
    ];
    let ck = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
    ];
    let mut m = [[0.0; 4]; 4];
    let mut k = [[0.0; 4]; 4];
    for i in 0..4 {
        for j in 0..4 {
            m[i][j] = rho_a * (h / 420.0 * cm[i][j] + ea2 / (30.0 * h) * cg[i][j]);
            k[i][j] = ei / h.powi(3) * ck[i][j];
        }
    }
    (m, k)
}

/// Uniform simply-supported mesh: the FE modes are exactly the standing waves
/// w_n = sin(k x_n), θ_n = a cos(k x_n), k = rπ/L (the odd periodic extension
/// satisfies the end equations), so each r reduces to a 2×2 Hermitian pencil
/// H_αβ(k) = E_αβ + E_{2+α,2+β} + E_{α,2+β} e^{ikh} + E_{2+α,β} e^{−ikh};
/// its lower root is the r-th relaxed eigenvalue λ_r, and D = (C/ρA)M gives c_r = C/ρA.
fn predict_simply_supported(beam: &BeamSpec, n_modes: usize) -> Result<Vec<ModalPair>, String> {
    use num_complex::Complex64;
    let ne = beam.elements;
    if n_modes > ne {
        return Err(format!("{n_modes} modes requested, the mesh resolves {ne}"));
    }
    let (me, ke) = element_matrices(beam);
    let c = beam.viscous_damping_n_s_m2 / (beam.density_kg_m3 * beam.area_m2());
    let mut out = Vec::with_capacity(n_modes);
    for r in 1..=n_modes {
        let kh = r as f64 * std::f64::consts::PI / ne as f64;
        let ph = Complex64::from_polar(1.0, kh);
        let pencil = |e: &[[f64; 4]; 4]| {
            let mut hm = [[Complex64::new(0.0, 0.0); 2]; 2];
            for a in 0..2 {
                for b in 0..2 {
                    hm[a][b] = Complex64::new(e[a][b] + e[2 + a][2 + b], 0.0) + ph * e[a][2 + b] + ph.conj() * e[2 + a][b];
                }
            }
            hm
        };
        let (m, k) = (pencil(&me), pencil(&ke));
        // det(K − λM) = aλ² − bλ + c0 (real for Hermitian 2×2 pencils)
        let a = m[0][0].re * m[1][1].re - m[0][1].norm_sqr();
        let b = k[0][0].re * m[1][1].re + k[1][1].re * m[0][0].re - 2.0 * (k[0][1] * m[0][1].conj()).re;
        let c0 = k[0][0].re * k[1][1].re - k[0][1].norm_sqr();
        let disc = (b * b - 4.0 * a * c0).max(0.0).sqrt();
        // lower root, written to avoid cancellation: λ = 2c0 / (b + √disc)
        let lambda = 2.0 * c0 / (b + disc);
        out.push(modal_pole(lambda, 0.0, c, &beam.internal_variables)?);
    }
    out.sort_by(|a, b| a.omega_rad_s.total_cmp(&b.omega_rad_s));
    Ok(out)
}

/// One standing wave of the simply-supported mesh, mass-normalised:
/// w_n = sin(k x_n)/√μ, θ_n = a cos(k x_n)/√μ with μ = φᵀMφ.
#[derive(Debug, Clone, Copy)]
struct Wave {
    r: usize,
    lambda: f64,
    k: f64,
    a: f64,
    norm: f64,
    rotation_only: bool,
}

impl Wave {
    fn dofs(&self, node: usize, h: f64) -> (f64, f64) {
        let x = node as f64 * h;
        let w = if self.rotation_only { 0.0 } else { (self.k * x).sin() / self.norm };
        (w, self.a * (self.k * x).cos() / self.norm)
    }
}

/// All 2·ne standing waves (both branches of every wavenumber) of the beam
/// without extensions, sorted by eigenvalue.
fn standing_waves(beam: &BeamSpec) -> Vec<Wave> {
    use num_complex::Complex64;
    let ne = beam.elements;
    let (me, ke) = element_matrices(beam);
    let h = beam.length_nm * 1e-9 / ne as f64;
    let mut out = Vec::with_capacity(2 * ne);
    // r = 0 and r = ne carry only the rotation wave θ_n = cos(k x_n) (sin(k x_n)
    // vanishes at every node); 1 + 2(ne − 1) + 1 = 2ne waves span the free DOFs.
    for r in 0..=ne {
        let kh = r as f64 * std::f64::consts::PI / ne as f64;
        let ph = Complex64::from_polar(1.0, kh);
        let pencil = |e: &[[f64; 4]; 4]| {
            let mut hm = [[Complex64::new(0.0, 0.0); 2]; 2];
            for a in 0..2 {
                for b in 0..2 {
                    hm[a][b] = Complex64::new(e[a][b] + e[2 + a][2 + b], 0.0) + ph * e[a][2 + b] + ph.conj() * e[2 + a][b];
                }
            }
            hm
        };
        let (m, kk) = (pencil(&me), pencil(&ke));
        let k = r as f64 * std::f64::consts::PI / (beam.length_nm * 1e-9);
        let pairs: Vec<(f64, f64)> = if r == 0 || r == ne {
            vec![(kk[1][1].re / m[1][1].re, f64::INFINITY)]
        } else {
            let qa = m[0][0].re * m[1][1].re - m[0][1].norm_sqr();
            let qb = kk[0][0].re * m[1][1].re + kk[1][1].re * m[0][0].re - 2.0 * (kk[0][1] * m[0][1].conj()).re;
            let qc = kk[0][0].re * kk[1][1].re - kk[0][1].norm_sqr();
            let disc = (qb * qb - 4.0 * qa * qc).max(0.0).sqrt();
            [2.0 * qc / (qb + disc), (qb + disc) / (2.0 * qa)]
                .into_iter()
                .map(|lambda| {
                    // eigenvector (1, i a): the off-diagonals are imaginary,
                    // (H00 − λM00) + i a (H01 − λM01) = 0
                    let off = (kk[0][1] - m[0][1] * lambda).im;
                    (lambda, (kk[0][0].re - lambda * m[0][0].re) / off)
                })
                .collect()
        };
        for (lambda, a) in pairs {
            let mut w = Wave { r, lambda, k, a, norm: 1.0, rotation_only: !a.is_finite() };
            if w.rotation_only {
                w.a = 1.0;
            }
            // φᵀMφ element by element from the nodal values (computed once per node)
            let nodal: Vec<(f64, f64)> = (0..=ne).map(|n| w.dofs(n, h)).collect();
            let mut mu = 0.0;
            for e in 0..ne {
                let v = [nodal[e].0, nodal[e].1, nodal[e + 1].0, nodal[e + 1].1];
                for i in 0..4 {
                    for j in 0..4 {
                        mu += v[i] * me[i][j] * v[j];
                    }
                }
            }
            w.norm = mu.sqrt();
            out.push(w);
        }
    }
    out.sort_by(|x, y| x.lambda.total_cmp(&y.lambda));
    out
}

/// Roots of the secular equation of a rank-one update, one per interval.
/// `increasing = true`: stiffness update ΔK = κ u uᵀ, roots of
/// 1/κ + Σ u_j²/(λ_j − λ) = 0 lie in (λ_p, λ_{p+1}) (last: (λ_max, λ_max + κΣu²)).
/// `false`: mass update ΔM = m u uᵀ, roots of 1/(mλ) − Σ u_j²/(λ_j − λ) = 0 in (λ_{p−1}, λ_p).
/// Waves with u_j² ≤ 1e-14·Σu² do not feel the update and stay eigenpairs.
/// Returns (λ, modal coordinates q) for the lowest `n` roots.
fn rank_one(waves: &[Wave], u: &[f64], kappa: f64, increasing: bool, n: usize) -> Vec<(f64, Vec<f64>)> {
    let total: f64 = u.iter().map(|v| v * v).sum();
    let mut out = Vec::new();
    let is_active: Vec<bool> = u.iter().map(|v| v * v > 1e-14 * total).collect();
    let active: Vec<usize> = (0..waves.len()).filter(|&j| is_active[j]).collect();
    for (j, w) in waves.iter().enumerate() {
        if !is_active[j] {
            let mut q = vec![0.0; waves.len()];
            q[j] = 1.0;
            out.push((w.lambda, q));
        }
    }
    let f = |lam: f64| -> f64 {
        let s: f64 = active.iter().map(|&j| u[j] * u[j] / (waves[j].lambda - lam)).sum();
        if increasing { 1.0 / kappa + s } else { 1.0 / (kappa * lam) - s }
    };
    for (p, &j) in active.iter().enumerate().take(n) {
        let (mut lo, mut hi) = if increasing {
            let upper = active.get(p + 1).map_or(waves[j].lambda + kappa * total * 1.0001, |&nx| waves[nx].lambda);
            (waves[j].lambda, upper)
        } else {
            let lower = if p == 0 { 0.0 } else { waves[active[p - 1]].lambda };
            (lower, waves[j].lambda)
        };
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            let v = f(mid);
            // increasing: f rises from −∞ to +∞; mass: f falls from +∞ to −∞
            if (v < 0.0) == increasing { lo = mid } else { hi = mid }
        }
        let lam = 0.5 * (lo + hi);
        let q = (0..waves.len()).map(|i| if is_active[i] { u[i] / (waves[i].lambda - lam) } else { 0.0 }).collect();
        out.push((lam, q));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out.truncate(n);
    out
}

/// Simply-supported beam with either an attached mass or end springs: an
/// exact rank-one update of the standing-wave basis (per symmetry class for
/// the two equal end springs, where ΔK = 2κ u uᵀ within each parity of r).
fn predict_rank_one(beam: &BeamSpec, n_modes: usize) -> Result<Vec<ModalPair>, String> {
    let ne = beam.elements;
    let h = beam.length_nm * 1e-9 / ne as f64;
    let mut plain = beam.clone();
    plain.point_mass = None;
    plain.support_rotational_stiffness_n_m_rad = 0.0;
    let waves = standing_waves(&plain);
    let c = beam.viscous_damping_n_s_m2 / (beam.density_kg_m3 * beam.area_m2());
    let mut modes: Vec<(f64, f64, f64)> = Vec::new(); // (kb, ks, modal mass of the beam part)
    if let Some(pm) = &beam.point_mass {
        let l = beam.length_nm * 1e-9;
        let x = (pm.x_nm * 1e-9).clamp(0.0, l);
        let e = ((x / h).floor() as usize).min(ne - 1);
        let xi = x - e as f64 * h;
        let r = xi / h;
        let nv = [1.0 - 3.0 * r * r + 2.0 * r.powi(3), xi * (1.0 - r).powi(2), 3.0 * r * r - 2.0 * r.powi(3), xi * (r * r - r)];
        let u: Vec<f64> = waves
            .iter()
            .map(|w| {
                let (w0, t0) = w.dofs(e, h);
                let (w1, t1) = w.dofs(e + 1, h);
                nv[0] * w0 + nv[1] * t0 + nv[2] * w1 + nv[3] * t1
            })
            .collect();
        for (lam, q) in rank_one(&waves, &u, pm.mass_kg, false, n_modes) {
            let qq: f64 = q.iter().map(|v| v * v).sum();
            let uq: f64 = u.iter().zip(&q).map(|(a, b)| a * b).sum();
            let mass = qq + pm.mass_kg * uq * uq;
            modes.push((lam, 0.0, qq / mass));
        }
    } else {
        let kappa = 2.0 * beam.support_rotational_stiffness_n_m_rad;
        for parity in [1, 0] {
            let sub: Vec<Wave> = waves.iter().copied().filter(|w| w.r % 2 == parity).collect();
            let u: Vec<f64> = sub.iter().map(|w| w.dofs(0, h).1).collect();
            for (lam, q) in rank_one(&sub, &u, kappa, true, n_modes) {
                let qq: f64 = q.iter().map(|v| v * v).sum();
                let kb: f64 = q.iter().zip(&sub).map(|(v, w)| v * v * w.lambda).sum::<f64>() / qq;
                modes.push((kb, lam - kb, 1.0));
            }
        }
    }
    modes.sort_by(|a, b| (a.0 + a.1).total_cmp(&(b.0 + b.1)));
    if modes.len() < n_modes {
        return Err(format!("{n_modes} modes requested"));
    }
    let mut out: Vec<ModalPair> = modes
        .iter()
        .take(n_modes)
        .map(|&(kb, ks, mb)| modal_pole(kb, ks, c * mb, &beam.internal_variables))
        .collect::<Result<_, _>>()?;
    out.sort_by(|a, b| a.omega_rad_s.total_cmp(&b.omega_rad_s));
    Ok(out)
}

/// Complex root of s² + c s + ks + kb [1 + Σ Δi s/(s + Ωi)] = 0: the polynomial
/// (s² + c s + ks + kb) Π(s + Ωi) + kb Σ Δi s Π_{j≠i}(s + Ωj), solved in
/// frequency units scaled by √kb through its companion matrix.
fn modal_pole(kb: f64, ks: f64, c: f64, ivs: &[crate::beam::InternalVariable]) -> Result<ModalPair, String> {
    let w0 = (kb + ks).sqrt();
    // polynomials in σ = s / w0, coefficients lowest degree first
    let mul = |p: &[f64], q: &[f64]| {
        let mut r = vec![0.0; p.len() + q.len() - 1];
        for (i, a) in p.iter().enumerate() {
            for (j, b) in q.iter().enumerate() {
                r[i + j] += a * b;
            }
        }
        r
    };
    let kbn = kb / (w0 * w0);
    let mut poly = vec![ks / (w0 * w0) + kbn, c / w0, 1.0];
    for iv in ivs {
        poly = mul(&poly, &[iv.omega_rad_s / w0, 1.0]);
    }
    for (i, iv) in ivs.iter().enumerate() {
        let mut term = vec![0.0, kbn * iv.delta];
        for (j, other) in ivs.iter().enumerate() {
            if j != i {
                term = mul(&term, &[other.omega_rad_s / w0, 1.0]);
            }
        }
        for (d, t) in term.iter().enumerate() {
            poly[d] += t;
        }
    }
    let n = poly.len() - 1;
    let lead = poly[n];
    let comp = DMatrix::from_fn(n, n, |i, j| {
        if i == 0 {
            -poly[n - 1 - j] / lead
        } else if j + 1 == i {
            1.0
        } else {
            0.0
        }
    });
    let roots = comp.complex_eigenvalues();
    let best = roots.iter().max_by(|a, b| a.im.abs().total_cmp(&b.im.abs())).ok_or("no roots")?;
    if best.im.abs() <= 1e-12 {
        return Err("overdamped mode".into());
    }
    let s = best * w0;
    let omega = s.norm();
    Ok(ModalPair { omega_rad_s: omega, zeta: -s.re / omega })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam() -> BeamSpec {
        BeamSpec::from_yaml(
            "length_nm: 8.0\ndiameter_nm: 1.0\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300.0\nsupport: simply-supported\nelements: 20\n",
        )
        .unwrap()
    }

    #[test]
    fn local_elastic_simply_supported_matches_closed_form() {
        // ω_r = (rπ/L)² √(EI/ρA); Hermite FE with 20 elements converges as h⁴:
        // relative error for mode 3 ≈ (3π/20)⁴/720·... < 1e-4.
        let b = beam();
        let p = predict(&b, 3).unwrap();
        let l = 8e-9;
        let c = (b.youngs_modulus_pa * b.inertia_m4() / (b.density_kg_m3 * b.area_m2())).sqrt();
        for (r, m) in p.iter().enumerate() {
            let exact = ((r + 1) as f64 * std::f64::consts::PI / l).powi(2) * c;
            assert!((m.omega_rad_s / exact - 1.0).abs() < 1e-4, "{} vs {}", m.omega_rad_s, exact);
            assert!(m.zeta.abs() < 1e-9);
        }
    }

    #[test]
    fn standing_wave_path_equals_general_path() {
        // Same FE model two ways: a vanishing rotational spring (1e-30 N·m/rad,
        // ~1e-21 of EI/L) forces the dense path; the difference is round-off
        // of a 40×40 eigenproblem (≈ 1e-12 relative), bounded here by 1e-9.
        let mut b = beam();
        b.nonlocal_e0a_nm = 1.1;
        b.viscous_damping_n_s_m2 = 1e-4;
        b.internal_variables = vec![crate::beam::InternalVariable { delta: 0.45, omega_rad_s: 6e11 }];
        let fast = predict(&b, 6).unwrap();
        b.support_rotational_stiffness_n_m_rad = 1e-30;
        let dense = predict(&b, 6).unwrap();
        for (f, d) in fast.iter().zip(&dense) {
            assert!((f.omega_rad_s / d.omega_rad_s - 1.0).abs() < 1e-9, "{f:?} {d:?}");
            assert!((f.zeta / d.zeta - 1.0).abs() < 1e-9, "{f:?} {d:?}");
        }
    }

    #[test]
    fn rank_one_updates_equal_dense_path() {
        // Mass (C = 0) and springs through the standing-wave secular equation
        // vs the dense 40×40 path. The dense symmetric eigensolver's error on
        // λ is ≈ n·ε·λ_max (backward stable), i.e. n·ε·λ_max/λ_1 relative on λ_1
        // and half that on ω: that bound (a ×10 safety factor) is the tolerance.
        let mut b = beam();
        b.nonlocal_e0a_nm = 0.9;
        b.internal_variables = vec![crate::beam::InternalVariable { delta: 0.4, omega_rad_s: 5e11 }];
        for (mass, spring) in [(Some(0.3), 0.0), (None, 2.0), (None, 50.0), (Some(0.5), 0.0)] {
            let mut v = b.clone();
            let ei_l = v.youngs_modulus_pa * v.inertia_m4() / 8e-9;
            let rho_al = v.density_kg_m3 * v.area_m2() * 8e-9;
            v.point_mass = mass.map(|mu| crate::beam::PointMass { mass_kg: mu * rho_al, x_nm: if mu > 0.4 { 4.0 } else { 2.9 } });
            v.support_rotational_stiffness_n_m_rad = spring * ei_l;
            let fast = predict(&v, 6).unwrap();
            let dense = dense(&v, 6).unwrap();
            let waves = standing_waves(&b);
            let cond = waves.last().unwrap().lambda / waves[0].lambda;
            let tol = 10.0 * 40.0 * f64::EPSILON * cond;
            for (f, d) in fast.iter().zip(&dense) {
                assert!((f.omega_rad_s / d.omega_rad_s - 1.0).abs() < tol, "{mass:?} {spring} {f:?} {d:?} tol {tol}");
                assert!((f.zeta / d.zeta - 1.0).abs() < tol, "{mass:?} {spring} {f:?} {d:?} tol {tol}");
            }
        }
    }
}
