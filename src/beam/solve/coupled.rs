//! Path (c), the coupled extensions: a support spring, a point mass with
//! C > 0, an axial force or Timoshenko shear with C > 0 break the decoupling
//! of `modal.rs` (D ∝ M and K_spring = 0). The poles of
//! T̃(s̃) = s̃²M̃ + s̃c̃M̃_beam + K̃_spring + G(s̃)K̃ are then found one by one by
//! nonlinear Rayleigh-quotient iteration on T(s), each from the one-term
//! approximation of its family (root and eigenvector of (K̃ + K̃_spring, M̃);
//! the eigenpairs come from the solver's cache). Any failure is
//! [`BeamError::Numerical`], and the caller falls back to the state space.

use num_complex::Complex64;

use crate::beam::error::BeamError;
use crate::beam::fe::scaling::ScaledModel;
use crate::beam::linalg::band::{ldl_factor_for_inverse_iteration, ldl_solve, BandLu};
use crate::beam::modal_result::{assemble, ModalResult};
use crate::beam::solve::eigen::EigenPair;
use crate::beam::solve::family::{hysteretic_family_roots_into, Roots, REAL_TOL};

/// Which poles the coupled path (c) solves for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Poles {
    /// Every pole of the requested families (what [`crate::beam::ModalSolver::modal`] reports).
    All,
    /// The oscillatory pairs only (what [`crate::beam::ModalSolver::observables`] needs).
    /// Real relaxation poles are not modes; a slow relaxation (Ω̃ ≪ ω̃₁) gives
    /// every family a real pole near −Ω̃/(1 + Δ), equal to leading order for
    /// all families (told apart by their vectors: [`same_real_pole`]), and
    /// should RQI from two of those starts still land on one pole, the
    /// coupled path fails and the dense state space (~25·dim³ flops,
    /// dim = 2n + N·n) takes over for poles no observable uses.
    Oscillatory,
}

/// (a, b, c_φ) of one family's equation, the eigenvector φ it came from and
/// φ's energy forms (k, m, m_b, k_s) (see [`ScaledModel::forms`]).
type FamilyApproximation = ((f64, f64, f64), Vec<f64>, Forms);

/// Energy forms xᵀK̃x, xᵀM̃x, xᵀM̃_beam x, xᵀK̃_spring x of one vector.
type Forms = (f64, f64, f64, f64);

/// One-term modal approximation of family j of a coupled model: with φ the
/// eigenvector of (K + K_spring, M) for λ, the family equation
/// s² + c_φ s + a + b G(s) = 0 with b = φᵀKφ/φᵀMφ, a = λ − b = φᵀK_springφ/φᵀMφ,
/// c_φ = c̃·φᵀM_beamφ/φᵀMφ. Exact when the model decouples. `pairs` are the
/// lowest eigenpairs of (K̃ + K̃_spring, M̃).
fn family_approximations(model: &ScaledModel, pairs: &[EigenPair]) -> Vec<FamilyApproximation> {
    pairs
        .iter()
        .map(|p| {
            let forms @ (k, m, mb, ks) = model.forms(&p.vector);
            ((ks / m, k / m, model.c * mb / m), p.vector.clone(), forms)
        })
        .collect()
}

/// Path (c): the poles of T̃(s̃) = s̃²M̃ + s̃c̃M̃_beam + K̃_spring + G(s̃)K̃ one by
/// one, each by nonlinear Rayleigh-quotient iteration from the one-term
/// approximation of its family (root and eigenvector of (K̃ + K̃_spring, M̃)).
/// `pairs` are the lowest n_modes eigenpairs of (K̃ + K̃_spring, M̃).
/// Any failure → the caller falls back to (a).
pub(crate) fn general_path(
    model: &ScaledModel,
    n_modes: usize,
    pairs: &[EigenPair],
    poles: Poles,
) -> Result<ModalResult, BeamError> {
    // a hysteretic loss has no real (time-domain) poles: the pairs alone
    let poles = if model.loss != 0.0 { Poles::Oscillatory } else { poles };
    {
        let count = n_modes;
        let approx = family_approximations(model, pairs);
        let mut found: Vec<Complex64> = Vec::new();
        // real poles found by RQI with their vectors (see `same_real_pole`)
        let mut found_real: Vec<(f64, Vec<f64>)> = Vec::new();
        let mut families = Vec::with_capacity(count);
        for ((a, b, c), phi, forms) in &approx {
            // the one-term family's roots (with a loss factor its pair alone)
            let mut starts = Roots::default();
            hysteretic_family_roots_into(*a, *b, *c, &model.ivs, model.loss, &mut starts)?;
            let mut fam = Vec::with_capacity(starts.len());
            let wanted = |s: &Complex64| s.im > 0.0 || (s.im == 0.0 && poles == Poles::All);
            for s0 in starts.iter().copied().filter(wanted) {
                // Real poles cluster (one per family within [−Ωᵢ, −Ωᵢ/(1+Δᵢ)]) next
                // to the n-fold poles of det T at −Ωᵢ, where methods on det T crawl;
                // nonlinear Rayleigh-quotient iteration from the family's vector
                // φ picks the family's own root instead.
                if s0.im == 0.0 {
                    let mut pole = nonlinear_rqi(model, s0.re, phi, &[])?;
                    if let RealPole::Rqi(s, x) = &pole {
                        if found_real.iter().any(|(f, y)| same_real_pole(model, (*s, x), (*f, y))) {
                            // a start nearer another family's pole than its own (strong
                            // coupling, clustered relaxation poles): once more, with the
                            // found vectors projected out of the first cycles
                            let avoid: Vec<&[f64]> = found_real.iter().map(|(_, y)| y.as_slice()).collect();
                            pole = match nonlinear_rqi(model, s0.re, phi, &avoid) {
                                Ok(RealPole::Rqi(s, x))
                                    if !found_real.iter().any(|(f, y)| same_real_pole(model, (s, &x), (*f, y))) =>
                                {
                                    RealPole::Rqi(s, x)
                                }
                                // Where the retry, too, fails (a spring coupling a cluster of
                                // slow-relaxation poles, 1 in ~250 draws of
                                // `beam_properties`), the family keeps its one-term root s0,
                                // which every coupled real pole was before the iteration was
                                // run to convergence: no observable uses a real pole, and the
                                // dense fallback's family assignment of real poles is no
                                // better there (`state_space_modal.rs`).
                                _ => RealPole::OneTerm(s0.re),
                            };
                        }
                    }
                    let s = match pole {
                        RealPole::Rqi(s, x) => {
                            // the same neighbourhood and meeting tests as below, with
                            // the vectors telling apart poles closer than 1e-8·|s|
                            if (s - s0.re).abs() > 0.5 * s0.re.abs() {
                                return Err(BeamError::numerical("RQI left its start's neighbourhood"));
                            }
                            if found_real.iter().any(|(f, y)| same_real_pole(model, (s, &x), (*f, y))) {
                                return Err(BeamError::numerical("two starts converged to the same pole"));
                            }
                            found_real.push((s, x));
                            s
                        }
                        RealPole::EqualRates(s) | RealPole::OneTerm(s) => s,
                    };
                    found.push(Complex64::new(s, 0.0));
                    fam.push(Complex64::new(s, 0.0));
                    continue;
                }
                let s = complex_rqi(model, s0, phi, *forms)?;
                // a start from the one-term model is within a few % of its pole;
                // a jump of more than half its size means another pole was hit,
                // and so does landing on a pole found already.
                if (s - s0).norm() > 0.5 * s0.norm() {
                    return Err(BeamError::numerical("RQI left its start's neighbourhood"));
                }
                if found.iter().any(|f| (s - f).norm() <= 1e-8 * s.norm()) {
                    return Err(BeamError::numerical("two starts converged to the same pole"));
                }
                if s.im.abs() <= REAL_TOL * s.norm() {
                    return Err(BeamError::numerical("complex start converged to a real pole"));
                }
                let s = Complex64::new(s.re, s.im.abs());
                found.push(s);
                found.push(s.conj());
                fam.push(s);
                fam.push(s.conj());
            }
            families.push(fam);
        }
        Ok(assemble(&families, n_modes, model.omega_ref))
    }
}

/// The outer stop of [`complex_rqi`]: the same argument as `RQI_TOL` in
/// `eigen.rs` — a move ≤ 1e-6·|s| means the vector was within ~1e-3 before the
/// step, and the cubic rate leaves an error ≲ 1e-18·|s| after it.
const COMPLEX_RQI_TOL: f64 = 1e-6;
const COMPLEX_RQI_MAX_STEPS: usize = 8;

/// Complex nonlinear Rayleigh-quotient iteration for an oscillatory pole:
/// x ← T(s)⁻¹T'(s)x, then s ← the root next to s of the Rayleigh functional
/// xᵀT(s)x = 0 (element-energy forms, so no cancellation of assembled
/// entries). T is complex symmetric, so with the transpose (not the
/// conjugate) the left eigenvector is the right one and the iteration
/// converges cubically, as RQI does for real symmetric pencils. The solves
/// use the unpivoted band LDLᵀ: its result is checked by the convergence of s
/// (and by the caller's neighbourhood tests), with the state space behind it.
///
/// `forms` are φ's (computed with φ): the forms of the real start, which are
/// bitwise those of φ as a complex vector (every imaginary part is 0), and
/// the first step's T'(s)φ skips the products of its zero imaginary part.
fn complex_rqi(model: &ScaledModel, s0: Complex64, phi: &[f64], forms: Forms) -> Result<Complex64, BeamError> {
    let x: Vec<Complex64> = phi.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    let c = |v: f64| Complex64::new(v, 0.0);
    let s = functional_root(model, (c(forms.0), c(forms.1), c(forms.2), c(forms.3)), s0)?;
    rqi_steps(model, x, s, true)
}

/// [`complex_rqi`] from a complex start vector `x` near the pole `s0` (the
/// second attempt of `subspace.rs`): the Rayleigh functional's root next to
/// `s0` first, then the same steps and stop.
pub(crate) fn complex_rqi_from(model: &ScaledModel, s0: Complex64, x: Vec<Complex64>) -> Result<Complex64, BeamError> {
    let s = rayleigh_functional_root(model, &x, s0)?;
    rqi_steps(model, x, s, false)
}

/// The steps of [`complex_rqi`] from the vector `x` and the functional's root
/// `s` there; `real`: every imaginary part of `x` is 0 (the first product
/// skips them).
fn rqi_steps(
    model: &ScaledModel,
    mut x: Vec<Complex64>,
    mut s: Complex64,
    mut real: bool,
) -> Result<Complex64, BeamError> {
    let n = model.n();
    let mut t = Vec::with_capacity(model.k.data.len());
    let (mut re, mut im, mut tmp) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..COMPLEX_RQI_MAX_STEPS {
        let (g, dg) = model.relaxation(s);
        // T(s) in band layout
        t.clear();
        t.extend(
            model
                .m
                .data
                .iter()
                .zip(&model.m_beam.data)
                .zip(&model.k.data)
                .map(|((&m, &mb), &k)| s * s * m + s * (model.c * mb) + g * k),
        );
        for (i, ks) in model.springs() {
            t[i * (model.k.kd + 1)] += ks;
        }
        if let Some(ka) = &model.k_axial {
            t.iter_mut().zip(&ka.data).for_each(|(ti, &v)| *ti += v);
        }
        if model.foundation != 0.0 {
            t.iter_mut().zip(&model.m_beam.data).for_each(|(ti, &v)| *ti += model.foundation * v);
        }
        let tiny = Complex64::new(f64::EPSILON * (model.k.data[0] + s.norm_sqr() * model.m.data[0]), 0.0);
        if !ldl_factor_for_inverse_iteration(&mut t, n, model.k.kd, tiny) {
            return Err(BeamError::numerical("T(s) factorisation broke down in RQI"));
        }
        // y = T'(s) x = (2s M̃ + c̃ M̃_beam + G'(s) K̃) x, from real products of Re x and Im x
        let mut y = vec![Complex64::new(0.0, 0.0); n];
        re.clear();
        re.extend(x.iter().map(|v| v.re));
        im.clear();
        im.extend(x.iter().map(|v| v.im));
        for (mat, coef) in [(&model.m, 2.0 * s), (&model.m_beam, Complex64::new(model.c, 0.0)), (&*model.k, dg)] {
            mat.mul_vec_into(&re, &mut tmp);
            y.iter_mut().zip(&tmp).for_each(|(yi, v)| *yi += coef * v);
            if !real {
                mat.mul_vec_into(&im, &mut tmp);
                y.iter_mut().zip(&tmp).for_each(|(yi, v)| *yi += coef * Complex64::new(0.0, *v));
            }
        }
        real = false;
        ldl_solve(&t, n, model.k.kd, &mut y);
        let scale = y.iter().fold(0.0f64, |a, v| a.max(v.norm_sqr())).sqrt();
        if !(scale.is_finite() && scale > 0.0) {
            return Err(BeamError::numerical("RQI on T(s) broke down"));
        }
        y.iter_mut().for_each(|v| *v /= scale);
        x = y;
        let next = rayleigh_functional_root(model, &x, s)?;
        let moved = (next - s).norm();
        s = next;
        if moved <= COMPLEX_RQI_TOL * s.norm() {
            return Ok(s);
        }
    }
    Err(BeamError::numerical("complex RQI did not converge"))
}

/// The root next to `start` of the Rayleigh functional
/// f(s) = xᵀT(s)x = s²m + s c̃ m_b + k_s + G(s)k (scalar Newton), with the
/// forms from element energies.
fn rayleigh_functional_root(model: &ScaledModel, x: &[Complex64], start: Complex64) -> Result<Complex64, BeamError> {
    functional_root(model, model.forms(x), start)
}

/// The root next to `start` of s²m + s c̃ m_b + k_s + G(s)k for given forms.
fn functional_root(
    model: &ScaledModel,
    (k, m, mb, ks): (Complex64, Complex64, Complex64, Complex64),
    start: Complex64,
) -> Result<Complex64, BeamError> {
    let mut s = start;
    for _ in 0..50 {
        let (g, dg) = model.relaxation(s);
        let f = s * s * m + s * model.c * mb + ks + g * k;
        let df = 2.0 * s * m + model.c * mb + dg * k;
        let step = f / df;
        if !step.is_finite() {
            return Err(BeamError::numerical("non-finite Rayleigh-functional step"));
        }
        s -= step;
        // quadratic convergence: a step at round-off level (4 eps) ends it
        if step.norm_sqr() <= 16.0 * f64::EPSILON * f64::EPSILON * s.norm_sqr() {
            return Ok(s);
        }
    }
    // near buckling the terms cancel (k_s + G k ≈ 0, |s| ≪ 1), so the steps
    // stay at the round-off of f, far above 4 eps·|s|: a root whose residual
    // is at that round-off is as exact as f can tell
    let (g, _) = model.relaxation(s);
    let terms = [s * s * m, s * model.c * mb, ks, g * k];
    if at_roundoff(terms.iter().sum(), terms.iter().map(|t| t.norm()).sum()) {
        return Ok(s);
    }
    Err(BeamError::numerical("Rayleigh functional: Newton did not converge"))
}

/// A residual `f` of a sum of terms whose magnitudes add up to `scale` is at
/// its round-off: |f| ≤ 8 eps·scale (each of the ≤ 4 terms and the sum
/// carries a relative error of a few eps).
fn at_roundoff(f: Complex64, scale: f64) -> bool {
    f.norm() <= 8.0 * f64::EPSILON * scale
}

/// A real pole of the coupled path.
enum RealPole {
    /// Found by [`nonlinear_rqi`], with its eigenvector (max-norm 1).
    Rqi(f64, Vec<f64>),
    /// A start that lies (within a few ulps) between relaxation rates equal to
    /// within a few ulps: s = −Ω̃ᵢ is then an exact pole (q = 0 and the rates'
    /// variables in a combination with ΣΔᵢq̄ᵢ = 0 decay alone at −Ω̃ᵢ, n-fold
    /// per extra equal rate, as the decoupled path lists it once per family),
    /// or the bracket between the rates is narrower than the iteration's
    /// own stop, so that any point of it is the family's pole to that stop.
    EqualRates(f64),
    /// The family's one-term root, kept where the iteration could not
    /// separate the family's pole from a cluster (see `general_path`).
    OneTerm(f64),
}

/// Two real RQI poles (s, x), (f, y) closer than 1e-8·|s| are one pole only if
/// their vectors are parallel in the K̃ inner product. Distinct poles of the
/// symmetric T can be far closer than 1e-8·|s|: between two nearly equal rates
/// G(s) = 1 + ΣΔᵢ s/(s + Ω̃ᵢ) is so steep that every family's root of
/// G(s) = −ν (ν an eigenvalue of (s²M̃ + s c̃ M̃_beam + K̃_spring + K̃_N, K̃),
/// distinct per family) falls within ≈ Δν/G'(s) of the others (1e-9·|s| at
/// rates 1e-4 apart). For distinct poles T(s)x = T(f)y = 0 gives
/// yᵀ(T(s) − T(f))x = 0, i.e.
///   yᵀK̃x = −(s − f)/(G(s) − G(f))·yᵀ((s + f)M̃ + c̃M̃_beam)x,
/// so |cos_K(x, y)| ≲ |s|·(2|s|m + c̃ m_b)/(|ΔG|·k) ≪ 1 where G is steep, and 1
/// for one pole: the test is |cos_K| > 1/2.
fn same_real_pole(model: &ScaledModel, (s, x): (f64, &[f64]), (f, y): (f64, &[f64])) -> bool {
    if (s - f).abs() > 1e-8 * s.abs() {
        return false;
    }
    let (kxy, kxx, kyy) = (model.k.bilinear(x, y), model.k.bilinear(x, x), model.k.bilinear(y, y));
    kxy.abs() > 0.5 * (kxx * kyy).sqrt()
}

/// The open interval between consecutive poles −Ω̃ᵢ of G(s) that holds `s`
/// (−∞ below the fastest rate, 0 above the slowest), or `None` when `s` lies
/// within 8 eps·|s| of two (or more) poles (rates equal to a few ulps).
fn relaxation_bracket(model: &ScaledModel, s: f64) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, 0.0f64);
    let mut near = 0;
    for &(_, w) in &model.ivs {
        let p = -w;
        if (s - p).abs() <= 8.0 * f64::EPSILON * s.abs() {
            near += 1;
        } else if p < s {
            lo = lo.max(p);
        } else {
            hi = hi.min(p);
        }
    }
    (near < 2).then_some((lo, hi))
}

/// Cycles of [`nonlinear_rqi`] with the `avoid` vectors projected out.
const DEFLATED_CYCLES: usize = 3;

/// Nonlinear Rayleigh-quotient iteration for a real pole from the start s0 of
/// family vector φ: s ← root of xᵀT(s)x = 0 (scalar Newton, element-energy
/// forms, kept inside the start's interval between poles of G), then
/// x ← T(s)⁻¹T'(s)x, until a cycle moves s by ≤ 1e-14·|s|. The first cycle
/// always updates x: s0 is the root of φ's own functional (the one-term
/// approximation), so its Newton steps move by round-off only and say
/// nothing about whether φ is the eigenvector.
///
/// `avoid`: vectors of poles found already, K̃-projected out of x in the first
/// [`DEFLATED_CYCLES`] cycles (distinct poles' vectors are nearly
/// K̃-orthogonal, see [`same_real_pole`]), then released so that x converges
/// to the exact eigenvector of the pole it is then nearest.
fn nonlinear_rqi(model: &ScaledModel, s0: f64, phi: &[f64], avoid: &[&[f64]]) -> Result<RealPole, BeamError> {
    let Some((lo, hi)) = relaxation_bracket(model, s0) else { return Ok(RealPole::EqualRates(s0)) };
    if hi - lo <= 1e-14 * s0.abs() {
        return Ok(RealPole::EqualRates(s0));
    }
    let mut x: Vec<f64> = phi.to_vec();
    let mut s = s0;
    for cycle in 0..50 {
        let (k, m, mb, ks) = model.forms(&x);
        let mut moved = 0.0;
        for _ in 0..3 {
            let (g, dg) = model.relaxation(Complex64::new(s, 0.0));
            let f = s * s * m + s * model.c * mb + ks + g.re * k;
            let df = 2.0 * s * m + model.c * mb + dg.re * k;
            let step = f / df;
            if !step.is_finite() {
                return Err(BeamError::numerical("non-finite nonlinear RQI step"));
            }
            // a step across a pole of G would leave the family's interval:
            // halve the way to that pole instead
            let next = s - step;
            let next = if next <= lo {
                0.5 * (s + lo)
            } else if next >= hi {
                0.5 * (s + hi)
            } else {
                next
            };
            moved += (next - s).abs();
            s = next;
        }
        // a root from a projected vector is not yet the pole
        let free = cycle > 0 && (avoid.is_empty() || cycle > DEFLATED_CYCLES);
        if free && moved <= 1e-14 * s.abs() {
            return Ok(RealPole::Rqi(s, x));
        }
        let (g, dg) = model.relaxation(Complex64::new(s, 0.0));
        let lu = BandLu::factor_kd(model.n(), model.k.kd, |i, j| {
            s * s * model.m.get(i, j)
                + s * model.c * model.m_beam.get(i, j)
                + model.unrelaxed_entry(i, j)
                + g.re * model.k.get(i, j)
        });
        // T(s) exactly singular: s is a pole and x the start of its vector
        let Some(lu) = lu else { return Ok(RealPole::Rqi(s, x)) };
        let (mx, mbx, kx) = (model.m.mul_vec(&x), model.m_beam.mul_vec(&x), model.k.mul_vec(&x));
        let mut y: Vec<f64> = (0..model.n()).map(|i| 2.0 * s * mx[i] + model.c * mbx[i] + dg.re * kx[i]).collect();
        lu.solve(&mut y);
        let norm = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if !(norm.is_finite() && norm > 0.0) {
            return Err(BeamError::numerical("nonlinear RQI broke down"));
        }
        x = y.iter().map(|v| v / norm).collect();
        if cycle < DEFLATED_CYCLES && !avoid.is_empty() {
            for v in avoid {
                let c = model.k.bilinear(v, &x) / model.k.bilinear(v, v);
                x.iter_mut().zip(v.iter()).for_each(|(xi, vi)| *xi -= c * vi);
            }
            let norm = x.iter().map(|v| v.abs()).fold(0.0, f64::max);
            if !(norm.is_finite() && norm > 0.0) {
                return Err(BeamError::numerical("nonlinear RQI broke down"));
            }
            x.iter_mut().for_each(|v| *v /= norm);
        }
    }
    // as in `functional_root`: near buckling the functional's terms cancel and
    // its Newton steps stay at their round-off, above 1e-14·|s|
    let (k, m, mb, ks) = model.forms(&x);
    let (g, _) = model.relaxation(Complex64::new(s, 0.0));
    let terms = [s * s * m, s * model.c * mb, ks, g.re * k];
    if at_roundoff(Complex64::new(terms.iter().sum(), 0.0), terms.iter().map(|t| t.abs()).sum()) {
        return Ok(RealPole::Rqi(s, x));
    }
    Err(BeamError::numerical("nonlinear RQI did not converge"))
}
