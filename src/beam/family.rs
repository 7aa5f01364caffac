//! Poles of one modal family: the roots of
//!   s² + c s + a + b·G(s) = 0,  G(s) = 1 + Σᵢ Δᵢ s/(s + Ωᵢ),
//! i.e. of the degree-(N+2) polynomial
//!   p(s) = (s² + c s + a + b) Πᵢ(s + Ωᵢ) + b Σᵢ Δᵢ s Π_{k≠i}(s + Ωₖ)
//! (only Δᵢ > 0 enter: a term with Δᵢ = 0 is an uncoupled factor (s + Ωᵢ)).
//! In the decoupled case a = 0, b = λ, c = C/ρA (dimensionless units).
//!
//! Method: Aberth–Ehrlich simultaneous iteration on p evaluated in the product
//! form above (more accurate than expanded coefficients), after scaling s by
//! w = √(a+b) so that the oscillatory pair has |ŝ| ≈ 1. Roots are then paired:
//! |Im| ≤ [`REAL_TOL`]·|s| is real (snapped to the axis and Newton-polished in
//! real arithmetic), the rest are matched to exact complex conjugates (the
//! polynomial is real). Hand-written because no listed crate finds polynomial
//! roots; nalgebra's companion-matrix eigenvalues would allocate on every call.

use num_complex::Complex64;

use crate::beam::dual::Dual;
use crate::beam::BeamError;

/// Imaginary part (relative to |s|) below which a root counts as real.
/// Aberth reaches ~1e-15 on simple roots; a double real root (critical damping)
/// is only resolved to ~√eps ≈ 1e-8, so anything below 1e-7 is "real" (ζ within
/// 5e-15 of 1).
pub const REAL_TOL: f64 = 1e-7;

/// Roots of the family polynomial, conjugate pairs exact, reals exactly real.
pub fn family_roots(a: f64, b: f64, c: f64, ivs: &[(f64, f64)]) -> Result<Vec<Complex64>, BeamError> {
    let w = (a + b).sqrt();
    if !(w.is_finite() && w > 0.0) {
        return Err(BeamError::numerical("non-positive family stiffness"));
    }
    let ch = c / w;
    let bh = b / (w * w);
    let mut ivh = [(0.0, 0.0); 16];
    let nv = ivs.len();
    if nv > ivh.len() {
        return Err(BeamError::numerical("more than 16 internal variables"));
    }
    for (slot, &(d, om)) in ivh.iter_mut().zip(ivs) {
        *slot = (d, om / w);
    }
    let ivh = &ivh[..nv];
    let mut roots = if nv == 0 { quadratic(ch) } else { aberth(ch, bh, ivh)? };
    for r in roots.iter_mut() {
        *r *= w;
    }
    Ok(roots)
}

/// ŝ² + ĉŝ + 1 = 0, stable for both regimes.
fn quadratic(c: f64) -> Vec<Complex64> {
    let half = 0.5 * c;
    let disc = half * half - 1.0;
    if disc < 0.0 {
        let im = (-disc).sqrt();
        vec![Complex64::new(-half, im), Complex64::new(-half, -im)]
    } else {
        let r1 = -(half + disc.sqrt());
        vec![Complex64::new(r1, 0.0), Complex64::new(1.0 / r1, 0.0)]
    }
}

/// p(ŝ) and p'(ŝ) in product form (scaled: a + b = 1).
fn eval(s: Complex64, c: f64, b: f64, ivs: &[(f64, f64)]) -> (Complex64, Complex64) {
    let z = Dual::new(s, Complex64::new(1.0, 0.0));
    let cst = |x: f64| Dual::new(Complex64::new(x, 0.0), Complex64::new(0.0, 0.0));
    let mut prod = cst(1.0);
    for &(_, om) in ivs {
        prod = prod * (z + cst(om));
    }
    let mut p = (z * z + cst(c) * z + cst(1.0)) * prod;
    for (i, &(d, _)) in ivs.iter().enumerate() {
        let mut t = cst(b * d) * z;
        for (k, &(_, om)) in ivs.iter().enumerate() {
            if k != i {
                t = t * (z + cst(om));
            }
        }
        p = p + t;
    }
    (p.v, p.d)
}

/// p'(ŝ)/p(ŝ) without forming p: with f(ŝ) = ŝ² + ĉŝ + 1 + b̂ Σ Δᵢ ŝ/(ŝ + Ω̂ᵢ)
/// (the family equation) and p = f·Π(ŝ + Ω̂ᵢ),
///   p'/p = f'/f + Σ 1/(ŝ + Ω̂ᵢ),  f' = 2ŝ + ĉ + b̂ Σ Δᵢ Ω̂ᵢ/(ŝ + Ω̂ᵢ)².
/// One complex reciprocal per internal variable instead of the dual-number
/// products of [`eval`] (3× cheaper; Aberth needs only this ratio). Near a
/// relaxation root f is a difference of large terms, but its absolute error
/// ~eps·|Δᵢŝ/(ŝ+Ω̂ᵢ)| over |f'| ~ |ΔᵢΩ̂ᵢ/(ŝ+Ω̂ᵢ)²| moves the root by only
/// ~eps·|ŝ + Ω̂ᵢ|: no accuracy is lost. `None` when ŝ hits −Ω̂ᵢ exactly or p
/// vanishes (the caller then uses [`eval`]).
fn log_derivative(s: Complex64, c: f64, b: f64, ivs: &[(f64, f64)]) -> Option<Complex64> {
    let mut f = s * s + c * s + 1.0;
    let mut df = 2.0 * s + c;
    let mut sum_r = Complex64::new(0.0, 0.0);
    for &(d, om) in ivs {
        let r = (s + om).inv();
        f += b * d * s * r;
        df += b * d * om * r * r;
        sum_r += r;
    }
    let w = df / f + sum_r;
    w.is_finite().then_some(w)
}

/// p'/p at ŝ, or `None` at an exact root (p = 0).
fn log_derivative_or_eval(s: Complex64, c: f64, b: f64, ivs: &[(f64, f64)]) -> Option<Complex64> {
    log_derivative(s, c, b, ivs).or_else(|| {
        let (p, dp) = eval(s, c, b, ivs);
        (p != Complex64::new(0.0, 0.0)).then(|| dp / p)
    })
}

fn aberth(c: f64, b: f64, ivs: &[(f64, f64)]) -> Result<Vec<Complex64>, BeamError> {
    let deg = ivs.len() + 2;
    // Starts near the expected roots (oscillatory pair near ±i, relaxation roots
    // near −Ωᵢ), rotated off the real axis and made pairwise distinct so the
    // conjugate symmetry of the start cannot trap real starts on the axis.
    let mut z: Vec<Complex64> = Vec::with_capacity(deg);
    z.push(Complex64::from_polar(1.0, 1.9));
    z.push(Complex64::from_polar(1.05, -1.95));
    for (i, &(_, om)) in ivs.iter().enumerate() {
        z.push(Complex64::from_polar(om * (1.0 + 0.013 * i as f64), std::f64::consts::PI - 0.05 - 0.01 * i as f64));
    }
    let mut done = false;
    for _ in 0..500 {
        // squared relative step (norm_sqr: no hypot in the hot loop)
        let mut max_rel2 = 0.0f64;
        for k in 0..deg {
            let Some(w) = log_derivative_or_eval(z[k], c, b, ivs) else { continue };
            let mut sum = Complex64::new(0.0, 0.0);
            for j in 0..deg {
                if j != k {
                    sum += (z[k] - z[j]).inv();
                }
            }
            // Aberth: step = (p/p') / (1 − (p/p')·Σ) = 1 / (p'/p − Σ)
            let step = (w - sum).inv();
            if !step.is_finite() {
                return Err(BeamError::numerical("Aberth iteration produced a non-finite step"));
            }
            z[k] -= step;
            max_rel2 = max_rel2.max(step.norm_sqr() / z[k].norm_sqr().max(f64::MIN_POSITIVE));
        }
        if max_rel2 <= 1e-30 {
            done = true;
            break;
        }
    }
    if !done {
        // Aberth stalls only at (near-)multiple roots; the residual test decides.
        for &zk in &z {
            let ratio = log_derivative_or_eval(zk, c, b, ivs).map_or(Complex64::new(0.0, 0.0), |w| w.inv());
            if !(ratio.norm() <= 1e-7 * zk.norm()) {
                return Err(BeamError::numerical("Aberth iteration did not converge"));
            }
        }
    }
    pair_up(z, |x| {
        let (p, dp) = eval(Complex64::new(x, 0.0), c, b, ivs);
        x - p.re / dp.re
    })
}

/// Snaps near-real roots to the axis (one real Newton polish) and replaces
/// each complex pair by an exact conjugate pair.
fn pair_up(z: Vec<Complex64>, newton_real: impl Fn(f64) -> f64) -> Result<Vec<Complex64>, BeamError> {
    let mut out = Vec::with_capacity(z.len());
    let (mut upper, mut lower) = (Vec::new(), Vec::new());
    for r in z {
        if r.im.abs() <= REAL_TOL * r.norm() {
            let x = newton_real(r.re);
            out.push(Complex64::new(if x.is_finite() { x } else { r.re }, 0.0));
        } else if r.im > 0.0 {
            upper.push(r);
        } else {
            lower.push(r);
        }
    }
    if upper.len() != lower.len() {
        return Err(BeamError::numerical("family roots are not closed under conjugation"));
    }
    for u in upper {
        let (j, _) = lower
            .iter()
            .enumerate()
            .map(|(j, l)| (j, (l.conj() - u).norm()))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .ok_or_else(|| BeamError::numerical("unpaired root"))?;
        let l = lower.swap_remove(j);
        let m = 0.5 * (u + l.conj());
        out.push(m);
        out.push(m.conj());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Backward-error style residual: |p(s)| over the same expression with every
    /// term replaced by its magnitude. A root computed in double precision
    /// satisfies this to a small multiple of eps (≈ 2e-16 × a few operations).
    fn residual(s: Complex64, a: f64, b: f64, c: f64, ivs: &[(f64, f64)]) -> f64 {
        let r = s.norm();
        let mut p = s * s + c * s + a + b;
        let mut scale = r * r + c * r + a + b;
        for &(_, o) in ivs {
            p *= s + o;
            scale *= r + o;
        }
        for (i, &(d, _)) in ivs.iter().enumerate() {
            let mut t = b * d * s;
            let mut ts = b * d * r;
            for (k, &(_, o)) in ivs.iter().enumerate() {
                if k != i {
                    t *= s + o;
                    ts *= r + o;
                }
            }
            p += t;
            scale += ts;
        }
        p.norm() / scale
    }

    #[test]
    fn roots_satisfy_the_family_equation() {
        type Case = (f64, f64, f64, Vec<(f64, f64)>);
        let cases: [Case; 5] = [
            (0.0, 97.4, 0.3, vec![]),
            (0.0, 97.4, 30.0, vec![]),
            (0.0, 97.4, 0.1, vec![(0.2, 5.0)]),
            (3.0, 1500.0, 0.0, vec![(0.2, 5.0), (0.05, 400.0)]),
            (0.0, 9.0, 0.01, vec![(0.5, 1e6)]),
        ];
        for (a, b, c, ivs) in cases {
            let r = family_roots(a, b, c, &ivs).unwrap();
            assert_eq!(r.len(), 2 + ivs.len());
            for s in &r {
                // ≤ ~10 operations each contributing ≤ eps: 1e-14 leaves a 20× margin
                assert!(residual(*s, a, b, c, &ivs) < 1e-14, "{s} for {a} {b} {c} {ivs:?}");
            }
            // closed under conjugation, exactly
            for s in &r {
                assert!(r.iter().any(|t| *t == s.conj()));
            }
        }
    }
}
