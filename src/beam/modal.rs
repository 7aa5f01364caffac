//! Poles and modal parameters (34)–(35).
//!
//! # Why the fast path is exact (decoupling)
//! Laplace-transforming (A8) and eliminating q̄ᵢ = Ωᵢ/(s+Ωᵢ) q (see
//! `state_space.rs`) gives the dynamic stiffness
//!   T(s) = s²M + sD + K_spring + G(s)·K,  G(s) = 1 + Σᵢ Δᵢ s/(s + Ωᵢ),
//! and, by the Schur complement of the block state matrix,
//!   det(sI − Aa) = det(M)⁻¹ · det T(s) · Πᵢ (s + Ωᵢ)ⁿ.
//! If D = cM (true when there is no point mass — De = (C/ρA)Me, A5 — or when
//! C = 0) and K_spring = 0, let Φ be the M-orthonormal eigenvectors of the
//! symmetric pencil KΦ = MΦΛ. Then ΦᵀT(s)Φ = diag(s² + cs + λⱼG(s)), so
//!   det T(s) = det(M)·Πⱼ (s² + cs + λⱼG(s))
//! and every pole is a root of one family polynomial
//!   (s² + cs + λⱼ)Πᵢ(s+Ωᵢ) + λⱼ Σᵢ Δᵢ s Π_{k≠i}(s+Ωₖ),
//! of degree N+2 (the extra factors (s+Ωᵢ)ⁿ cancel against the denominators;
//! a variable with Δᵢ = 0 contributes only the uncoupled pole −Ωᵢ, which is
//! unobservable and left out of the modal result). Only the lowest λⱼ are
//! needed: `eigen.rs` finds them with banded Newton–Maehly iterations.
//! A point mass with C > 0 breaks D ∝ M; a support spring breaks K_spring ∝ K
//! (it is not relaxed by G). Then `general_path` solves det T(s) = 0 directly.
//!
//! # What is reported
//! Modes are the complex-conjugate pairs (the Im > 0 member), sorted by |s|;
//! ωᵣ = |sᵣ| (34), ζᵣ = −Re sᵣ/|sᵣ| (35). Real poles (relaxation, overdamped)
//! are reported separately: those of the modal families that were examined
//! (families 1..m, m the smallest count that yields the requested number of
//! pairs; m = n_modes unless a family is overdamped).

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::beam::band::BandLu;
use crate::beam::dual::Dual;
use crate::beam::eigen::{eigenvector, lowest_eigenvalues};
use crate::beam::family::{family_roots, REAL_TOL};
use crate::beam::model::{ScaledModel, UnitMesh};
use crate::beam::spec::BeamSpec;
use crate::beam::{state_space, BeamError};
use crate::error::InputError;

/// Newton tolerance before the Rayleigh-quotient refinement: after a step of
/// 1e-6 relative the quadratic phase leaves ~1e-12, and inverse iteration at
/// that shift plus the Rayleigh quotient (error ∝ vector error²) reach round-off.
const NEWTON_TOL: f64 = 1e-6;

/// One oscillatory mode.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// 1-based index in order of increasing |s|.
    pub mode: usize,
    /// ωᵣ = |sᵣ| (eq. 34), rad/s.
    pub omega_rad_s: f64,
    /// ζᵣ = −Re(sᵣ)/|sᵣ| (eq. 35).
    pub zeta: f64,
    /// The pole with Im > 0, rad/s.
    pub pole: Complex64,
}

/// Modes and, separately, the real poles of the examined modal families.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalResult {
    pub modes: Vec<Mode>,
    /// Negative reals in rad/s, sorted by magnitude.
    pub real_poles_rad_s: Vec<f64>,
}

/// Reusable solver: caches the unit mesh integrals (they depend only on the
/// element count and the supports) and the factorisation workspace, so a call
/// with new E, ρ, d, e0a, C, Δ, Ω only rescales and re-solves.
///
/// It also remembers the last eigenvalues λ̃ of the scaled pencil (K̃, M̃): they
/// depend only on the mesh, e0a/L and the point mass (μ̃ = m/ρAL, x/L) — not on
/// E, ρ, d (beyond μ̃), C, Δ, Ω — so a calibration that varies those reuses
/// them exactly (bitwise key) and pays only for the family polynomials.
#[derive(Debug, Default, Clone)]
pub struct ModalSolver {
    mesh: Option<UnitMesh>,
    work: Vec<Dual<f64>>,
    cache: Option<(PencilKey, Vec<f64>)>,
}

/// Bitwise identity of the scaled pencil (K̃, M̃) for a given mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct PencilKey {
    e_tilde: u64,
    mu: u64,
    x: u64,
}

impl ModalSolver {
    pub fn new() -> Self {
        Self::default()
    }


    /// The fastest exact path: decoupled families when the proof above
    /// applies, otherwise Newton on det T(s) (falling back to the state space).
    pub fn modal(&mut self, beam: &BeamSpec, n_modes: usize) -> Result<ModalResult, BeamError> {
        beam.validate()?;
        let stale = !matches!(&self.mesh, Some(m) if m.elements == beam.elements && m.support == beam.support);
        if stale {
            self.mesh = Some(UnitMesh::new(beam.elements, beam.support));
        }
        if stale {
            self.cache = None;
        }
        let Self { mesh, work, cache } = self;
        let model = ScaledModel::new(beam, mesh.as_ref().expect("mesh just set"));
        check_mode_count(n_modes, model.n())?;
        if model.decouples() {
            let key = PencilKey {
                e_tilde: model.e_tilde.to_bits(),
                mu: model.point_mass.as_ref().map_or(0, |p| p.0.to_bits()),
                x: beam.point_mass.as_ref().map_or(0, |p| (p.x_nm / beam.length_nm).to_bits()),
            };
            decoupled_path(&model, n_modes, work, key, cache)
        } else {
            match general_path(&model, n_modes, work) {
                Ok(r) => Ok(r),
                Err(_) => state_space_modal(&model, n_modes),
            }
        }
    }
}

/// Modal parameters by the fastest exact path (see [`ModalSolver`]).
pub fn modal(beam: &BeamSpec, n_modes: usize) -> Result<ModalResult, BeamError> {
    ModalSolver::new().modal(beam, n_modes)
}

/// Modal parameters from the eigenvalues of the state matrix (A15) (reference).
pub fn modal_state_space(beam: &BeamSpec, n_modes: usize) -> Result<ModalResult, BeamError> {
    beam.validate()?;
    let mesh = UnitMesh::new(beam.elements, beam.support);
    let model = ScaledModel::new(beam, &mesh);
    check_mode_count(n_modes, model.n())?;
    state_space_modal(&model, n_modes)
}

/// Every pole of the state matrix (A15) in rad/s, sorted by |s| then Im s.
/// Count (2 + N)·n, n = free DOFs, N = number of internal variables.
pub fn poles_state_space(beam: &BeamSpec) -> Result<Vec<Complex64>, BeamError> {
    beam.validate()?;
    let mesh = UnitMesh::new(beam.elements, beam.support);
    let model = ScaledModel::new(beam, &mesh);
    Ok(state_space::scaled_poles(&model)?.into_iter().map(|p| p * model.omega_ref).collect())
}

fn check_mode_count(n_modes: usize, n: usize) -> Result<(), BeamError> {
    if n_modes == 0 || n_modes > n {
        return Err(InputError::new("n_modes", n_modes, format!("1..={n} (free DOFs of this mesh)")).into());
    }
    Ok(())
}

/// Sorts the complex pairs (Im > 0 members) of the given families by |s| and
/// keeps `n_modes`; `None` if there are fewer pairs than that.
fn assemble(families: &[Vec<Complex64>], n_modes: usize, omega_ref: f64) -> Option<ModalResult> {
    let mut pairs: Vec<Complex64> = families.iter().flatten().copied().filter(|s| s.im > 0.0).collect();
    if pairs.len() < n_modes {
        return None;
    }
    pairs.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    let modes = pairs
        .iter()
        .take(n_modes)
        .enumerate()
        .map(|(i, &s)| {
            let s = s * omega_ref;
            Mode { mode: i + 1, omega_rad_s: s.norm(), zeta: -s.re / s.norm(), pole: s }
        })
        .collect();
    let mut real: Vec<f64> = families.iter().flatten().filter(|s| s.im == 0.0).map(|s| s.re * omega_ref).collect();
    real.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    Some(ModalResult { modes, real_poles_rad_s: real })
}

fn too_few_modes(n_modes: usize, found: usize) -> BeamError {
    InputError::new("n_modes", n_modes, format!("<= {found} (oscillatory modes of this model; the rest are overdamped)"))
        .into()
}

/// Path (b): exact decoupling.
fn decoupled_path(
    model: &ScaledModel,
    n_modes: usize,
    work: &mut Vec<Dual<f64>>,
    key: PencilKey,
    cache: &mut Option<(PencilKey, Vec<f64>)>,
) -> Result<ModalResult, BeamError> {
    let n = model.n();
    let mut count = n_modes;
    loop {
        let lambdas = match cache {
            Some((k, l)) if *k == key && l.len() >= count => l[..count].to_vec(),
            _ => {
                let l = lowest_eigenvalues(model.k, &model.m, count, NEWTON_TOL, work, &mut |l| {
                    Ok(rayleigh(model, model.k, l)?.0)
                })?;
                *cache = Some((key, l.clone()));
                l
            }
        };
        let families =
            lambdas.iter().map(|&l| family_roots(0.0, l, model.c, &model.ivs)).collect::<Result<Vec<_>, _>>()?;
        if let Some(r) = assemble(&families, n_modes, model.omega_ref) {
            return Ok(r);
        }
        if count == n {
            return Err(too_few_modes(n_modes, families.iter().flatten().filter(|s| s.im > 0.0).count()));
        }
        count = (count + n_modes).min(n);
    }
}

/// One-term modal approximation of family j of a coupled model: with φ the
/// M-normalised eigenvector of (K + K_spring, M) for λ, the family equation
/// s² + c_φ s + a + b G(s) = 0 with b = φᵀKφ, a = λ − b = φᵀK_springφ,
/// c_φ = c̃·φᵀM_beamφ. Exact when the model decouples.
fn family_approximations(
    model: &ScaledModel,
    count: usize,
    work: &mut Vec<Dual<f64>>,
) -> Result<Vec<((f64, f64, f64), Vec<f64>)>, BeamError> {
    let kt = model.k_total();
    let lambdas = lowest_eigenvalues(&kt, &model.m, count, NEWTON_TOL, work, &mut |l| Ok(rayleigh(model, &kt, l)?.0))?;
    lambdas
        .iter()
        .map(|&l| {
            let phi = eigenvector(&kt, &model.m, l)?;
            Ok((rayleigh_of(model, &phi).1, phi))
        })
        .collect()
}

/// Inverse iteration at σ, then the Rayleigh quotient from element energies:
/// λ = (xᵀK̃x + xᵀK̃_spring x)/xᵀM̃x (error quadratic in the eigenvector error).
/// Also returns the one-term family coefficients (a, b, c) = (xᵀK̃_s x, xᵀK̃x,
/// c̃·xᵀM̃_beam x)/xᵀM̃x.
fn rayleigh(model: &ScaledModel, k_total: &crate::beam::band::SymBand, sigma: f64) -> Result<(f64, (f64, f64, f64)), BeamError> {
    let phi = eigenvector(k_total, &model.m, sigma)?;
    Ok(rayleigh_of(model, &phi))
}

fn rayleigh_of(model: &ScaledModel, phi: &[f64]) -> (f64, (f64, f64, f64)) {
    let (k, m, mb, ks) = model.forms(phi);
    ((k + ks) / m, (ks / m, k / m, model.c * mb / m))
}

/// Path (c): Newton on det T(s̃) = 0, T̃(s̃) = s̃²M̃ + s̃c̃M̃_beam + K̃_spring + G(s̃)K̃,
/// one banded complex LU in dual numbers per step (d log det T/ds̃ = tr(T⁻¹T')),
/// Maehly-deflated against the poles already found, started from the roots of
/// the one-term approximations. Any failure → the caller falls back to (a).
fn general_path(model: &ScaledModel, n_modes: usize, work: &mut Vec<Dual<f64>>) -> Result<ModalResult, BeamError> {
    let n = model.n();
    let mut count = n_modes;
    loop {
        let approx = family_approximations(model, count, work)?;
        let mut found: Vec<Complex64> = Vec::new();
        let mut families = Vec::with_capacity(count);
        for ((a, b, c), phi) in &approx {
            let starts = family_roots(*a, *b, *c, &model.ivs)?;
            let mut fam = Vec::with_capacity(starts.len());
            for s0 in starts.into_iter().filter(|s| s.im >= 0.0) {
                // Real poles cluster (one per family within [−Ωᵢ, −Ωᵢ/(1+Δᵢ)]) next
                // to the n-fold poles of det T at −Ωᵢ, where det-Newton crawls;
                // nonlinear Rayleigh-quotient iteration from the family's vector
                // φ picks the family's own root instead.
                let s = if s0.im == 0.0 { nonlinear_rqi(model, s0, phi)? } else { newton_det(model, s0, &found)? };
                // a start from the one-term model is within a few % of its pole;
                // a jump of more than half its size means another pole was hit.
                if (s - s0).norm() > 0.5 * s0.norm() {
                    return Err(BeamError::numerical("det-Newton left its start's neighbourhood"));
                }
                if s0.im == 0.0 {
                    found.push(s);
                    fam.push(s);
                } else {
                    if s.im.abs() <= REAL_TOL * s.norm() {
                        return Err(BeamError::numerical("complex start converged to a real pole"));
                    }
                    let s = Complex64::new(s.re, s.im.abs());
                    found.push(s);
                    found.push(s.conj());
                    fam.push(s);
                    fam.push(s.conj());
                }
            }
            families.push(fam);
        }
        if let Some(r) = assemble(&families, n_modes, model.omega_ref) {
            return Ok(r);
        }
        if count == n {
            return Err(too_few_modes(n_modes, families.iter().flatten().filter(|s| s.im > 0.0).count()));
        }
        count = (count + n_modes).min(n);
    }
}

/// Newton–Maehly on det T̃(s̃): s̃ ← s̃ − 1/(tr(T⁻¹T') − Σ_found 1/(s̃ − f)),
/// quadratic at simple roots, run to 1e-13 relative or to its noise floor
/// (det T is evaluated with ~eps·‖K‖ absolute pivot errors, ≈1e-10 relative in s̃);
/// then polished by Newton on the Rayleigh functional xᵀT(s̃)x with x = T(s̃)⁻¹b
/// evaluated from element energies (error quadratic in the vector error).
fn newton_det(model: &ScaledModel, start: Complex64, found: &[Complex64]) -> Result<Complex64, BeamError> {
    let mut s = start;
    let mut prev = f64::INFINITY;
    let mut converged = false;
    for _ in 0..80 {
        let dlog = dlog_det_t(model, s)?;
        let deflated = dlog - found.iter().map(|&f| 1.0 / (s - f)).sum::<Complex64>();
        let step = -1.0 / deflated;
        if !step.is_finite() {
            return Err(BeamError::numerical("det-Newton produced a non-finite step"));
        }
        if step.norm() <= 1e-7 * s.norm() && step.norm() > 0.5 * prev {
            converged = true;
            break;
        }
        s += step;
        prev = step.norm();
        if step.norm() <= 1e-13 * s.norm() {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(BeamError::numerical("det-Newton did not converge"));
    }
    let before = s;
    for _ in 0..2 {
        s = rayleigh_functional_step(model, s)?;
    }
    if (s - before).norm() > 1e-6 * before.norm() {
        return Err(BeamError::numerical("Rayleigh-functional polish moved too far"));
    }
    Ok(if start.im == 0.0 { Complex64::new(s.re, 0.0) } else { s })
}

/// Nonlinear Rayleigh-quotient iteration for a real pole: s ← root of
/// xᵀT(s)x = 0 (scalar Newton, element-energy forms), x ← T(s)⁻¹T'(s)x.
fn nonlinear_rqi(model: &ScaledModel, s0: Complex64, phi: &[f64]) -> Result<Complex64, BeamError> {
    let mut x: Vec<Complex64> = phi.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    let mut s = s0.re;
    let spring = if model.has_spring() { model.spring } else { 0.0 };
    for _ in 0..50 {
        let (k, m, mb, ks) = model.forms(&x);
        let (k, m, mb, ks) = (k.re, m.re, mb.re, ks.re);
        let mut moved = 0.0;
        for _ in 0..3 {
            let (g, dg) = model.relaxation(Complex64::new(s, 0.0));
            let f = s * s * m + s * model.c * mb + ks + g.re * k;
            let df = 2.0 * s * m + model.c * mb + dg.re * k;
            let step = f / df;
            if !step.is_finite() {
                return Err(BeamError::numerical("non-finite nonlinear RQI step"));
            }
            s -= step;
            moved += step.abs();
        }
        if moved <= 1e-14 * s.abs() {
            return Ok(Complex64::new(s, 0.0));
        }
        let (g, dg) = model.relaxation(Complex64::new(s, 0.0));
        let lu = BandLu::factor(model.n(), |i, j| {
            let ks = if i == j && model.spring_dofs.contains(&i) { spring } else { 0.0 };
            s * s * model.m.get(i, j) + s * model.c * model.m_beam.get(i, j) + ks + g.re * model.k.get(i, j)
        });
        let Some(lu) = lu else { return Ok(Complex64::new(s, 0.0)) };
        let xr: Vec<f64> = x.iter().map(|v| v.re).collect();
        let (mx, mbx, kx) = (model.m.mul_vec(&xr), model.m_beam.mul_vec(&xr), model.k.mul_vec(&xr));
        let mut y: Vec<f64> =
            (0..model.n()).map(|i| 2.0 * s * mx[i] + model.c * mbx[i] + dg.re * kx[i]).collect();
        lu.solve(&mut y);
        let norm = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if !(norm.is_finite() && norm > 0.0) {
            return Err(BeamError::numerical("nonlinear RQI broke down"));
        }
        x = y.iter().map(|v| Complex64::new(v / norm, 0.0)).collect();
    }
    Err(BeamError::numerical("nonlinear RQI did not converge"))
}

/// One inverse iteration x = T(s̃)⁻¹ M̃·1 and one Newton step on xᵀT(s̃)x = 0.
fn rayleigh_functional_step(model: &ScaledModel, s: Complex64) -> Result<Complex64, BeamError> {
    let (g, dg) = model.relaxation(s);
    let spring = if model.has_spring() { model.spring } else { 0.0 };
    let t = |i: usize, j: usize| {
        let ks = if i == j && model.spring_dofs.contains(&i) { spring } else { 0.0 };
        s * s * model.m.get(i, j) + s * (model.c * model.m_beam.get(i, j)) + ks + g * model.k.get(i, j)
    };
    let lu = BandLu::factor(model.n(), t)
        .or_else(|| {
            let s2 = s * (1.0 + 1e-14);
            let (g2, _) = model.relaxation(s2);
            BandLu::factor(model.n(), |i, j| {
                let ks = if i == j && model.spring_dofs.contains(&i) { spring } else { 0.0 };
                s2 * s2 * model.m.get(i, j) + s2 * (model.c * model.m_beam.get(i, j)) + ks + g2 * model.k.get(i, j)
            })
        })
        .ok_or_else(|| BeamError::numerical("T(s) singular in the Rayleigh-functional polish"))?;
    let ones = vec![1.0; model.n()];
    let mut x: Vec<Complex64> = model.m.mul_vec(&ones).into_iter().map(|v| Complex64::new(v, 0.0)).collect();
    lu.solve(&mut x);
    let scale = x.iter().map(|v| v.norm()).fold(0.0, f64::max);
    if !(scale.is_finite() && scale > 0.0) {
        return Err(BeamError::numerical("inverse iteration on T(s) broke down"));
    }
    for v in x.iter_mut() {
        *v /= scale;
    }
    let (k, m, mb, ks) = model.forms(&x);
    let f = s * s * m + s * model.c * mb + ks + g * k;
    let df = 2.0 * s * m + model.c * mb + dg * k;
    let next = s - f / df;
    if !next.is_finite() {
        return Err(BeamError::numerical("non-finite Rayleigh-functional step"));
    }
    Ok(next)
}

/// d/ds̃ log det T̃(s̃) via a dual-number banded LU.
fn dlog_det_t(model: &ScaledModel, s: Complex64) -> Result<Complex64, BeamError> {
    let (g, dg) = model.relaxation(s);
    let c = model.c;
    let spring = if model.has_spring() { model.spring } else { 0.0 };
    let lu = BandLu::factor(model.n(), |i, j| {
        let m = model.m.get(i, j);
        let mb = model.m_beam.get(i, j);
        let k = model.k.get(i, j);
        let ks = if i == j && model.spring_dofs.contains(&i) { spring } else { 0.0 };
        Dual::new(s * s * m + s * (c * mb) + ks + g * k, 2.0 * s * m + c * mb + dg * k)
    })
    .ok_or_else(|| BeamError::numerical("T(s) exactly singular at a Newton iterate"))?;
    Ok(lu.dlog_det())
}

/// Path (a) turned into modal parameters. Real poles are assigned to the
/// family whose one-term equation they satisfy best (exact when decoupled);
/// the uncoupled poles −Ωᵢ of variables with Δᵢ = 0 are dropped.
fn state_space_modal(model: &ScaledModel, n_modes: usize) -> Result<ModalResult, BeamError> {
    let poles = state_space::scaled_poles(model)?;
    let n = model.n();
    let approx = dense_family_approximations(model)?;
    // m: smallest family count whose one-term roots contain n_modes pairs.
    let mut m = 0;
    let mut pairs = 0;
    while m < n && pairs < n_modes {
        let (a, b, c) = approx[m];
        pairs += family_roots(a, b, c, &model.ivs)?.iter().filter(|s| s.im > 0.0).count();
        m += 1;
    }
    let mut modes_s: Vec<Complex64> = poles.iter().copied().filter(|s| s.im > REAL_TOL * s.norm()).collect();
    modes_s.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    if modes_s.len() < n_modes {
        return Err(too_few_modes(n_modes, modes_s.len()));
    }
    let uncoupled = |s: f64| model.ivs_all.iter().any(|&(d, om)| d == 0.0 && (s + om).abs() <= 1e-6 * om);
    let mut real = Vec::new();
    for s in poles.iter().filter(|s| s.im.abs() <= REAL_TOL * s.norm()) {
        let x = s.re;
        if uncoupled(x) {
            continue;
        }
        let sc = Complex64::new(x, 0.0);
        let (g, _) = model.relaxation(sc);
        let best = approx
            .iter()
            .enumerate()
            .map(|(j, &(a, b, c))| (j, ((sc * sc + c * sc + a + b * g).norm() / (x * x + a + b))))
            .min_by(|p, q| p.1.total_cmp(&q.1))
            .map(|p| p.0);
        if matches!(best, Some(j) if j < m) {
            real.push(x * model.omega_ref);
        }
    }
    real.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    let modes = modes_s
        .iter()
        .take(n_modes)
        .enumerate()
        .map(|(i, &s)| {
            let s = s * model.omega_ref;
            Mode { mode: i + 1, omega_rad_s: s.norm(), zeta: -s.re / s.norm(), pole: s }
        })
        .collect();
    Ok(ModalResult { modes, real_poles_rad_s: real })
}

/// (a, b, c) of every family from a dense symmetric eigen-decomposition.
fn dense_family_approximations(model: &ScaledModel) -> Result<Vec<(f64, f64, f64)>, BeamError> {
    let kt = model.k_total().to_dense();
    let chol = nalgebra::Cholesky::new(model.m.to_dense())
        .ok_or_else(|| BeamError::numerical("mass matrix is not positive definite"))?;
    let l = chol.l();
    let linv = l.clone().try_inverse().ok_or_else(|| BeamError::numerical("singular Cholesky factor"))?;
    let c = &linv * kt * linv.transpose();
    let eig = nalgebra::SymmetricEigen::new(c);
    let phis = linv.transpose() * &eig.eigenvectors;
    let k = model.k.to_dense();
    let mb = model.m_beam.to_dense();
    let mut out: Vec<(f64, f64, f64)> = (0..model.n())
        .map(|j| {
            let phi = phis.column(j);
            let lam = eig.eigenvalues[j];
            let b = (phi.transpose() * &k * phi)[(0, 0)];
            (((lam - b).max(0.0)), b, model.c * (phi.transpose() * &mb * phi)[(0, 0)])
        })
        .collect();
    out.sort_by(|x, y| (x.0 + x.1).total_cmp(&(y.0 + y.1)));
    Ok(out)
}

#[cfg(test)]
mod timing {
    use super::*;
    fn best<F: FnMut()>(name: &str, mut f: F) {
        let mut best = std::time::Duration::MAX;
        for _ in 0..30 {
            let t = std::time::Instant::now();
            for _ in 0..50 { f(); }
            best = best.min(t.elapsed() / 50);
        }
        println!("{name}: {best:?}");
    }
    #[test]
    #[ignore]
    fn pieces() {
        let b: BeamSpec = serde_yaml::from_str("length_nm: 8\ndiameter_nm: 1\nyoungs_modulus_pa: 1.0e12\ndensity_kg_m3: 2300\nsupport: simply-supported\nelements: 20\nnonlocal_e0a_nm: 0.5\nviscous_damping_n_s_m2: 1.0e-5\ninternal_variables: [{delta: 0.1, omega_rad_s: 1.0e11}, {delta: 0.05, omega_rad_s: 3.0e12}]\n").unwrap();
        let mesh = UnitMesh::new(20, b.support);
        let model = ScaledModel::new(&b, &mesh);
        let mut work = Vec::new();
        best("eig newton only", || { lowest_eigenvalues(model.k, &model.m, 3, NEWTON_TOL, &mut work, &mut |l| Ok(l)).unwrap(); });
        best("eig + rq", || { lowest_eigenvalues(model.k, &model.m, 3, NEWTON_TOL, &mut work, &mut |l| Ok(rayleigh(&model, model.k, l)?.0)).unwrap(); });
        best("3 families", || { for l in [97.0, 1500.0, 7000.0] { family_roots(0.0, l, model.c, &model.ivs).unwrap(); } });
        best("model", || { ScaledModel::new(&b, &mesh); });
        best("eigenvector", || { eigenvector(model.k, &model.m, 97.409).unwrap(); });
        let phi = eigenvector(model.k, &model.m, 97.409).unwrap();
        best("rayleigh_of", || { rayleigh_of(&model, &phi); });
        best("one ldl", || { model.k.ldl_inertia(&model.m, 50.0, &mut work).unwrap(); });
        best("modal cold", || { modal(&b, 3).unwrap(); });
        let mut solver = ModalSolver::new();
        best("modal cached pencil", || { solver.modal(&b, 3).unwrap(); });
    }
}
