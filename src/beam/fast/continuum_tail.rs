//! The wavenumber blocks beyond the kept ones of the continuum Timoshenko
//! paths, in closed form (`shear_continuum.rs` derives both): the support
//! springs' sum as a Laurent series with fixed zeta-tail constants
//! ([`SpringTail`]), the point mass's by partial fractions ([`MassTail`]).
//! The secular paths (`spring_spectrum.rs`, `mass_blocks.rs`) add them to
//! their block sums when their blocks are a truncated infinite set.

use std::f64::consts::PI;
use std::sync::OnceLock;

use num_complex::Complex64;

use crate::beam::fast::jet::{Jet, Num};

/// Terms of the spring tail's Laurent series (`shear_continuum.rs`).
pub(crate) const TAIL_TERMS: usize = 13;
/// Every root of D must lie inside 1/TAIL_RATIO of the first omitted
/// wavenumber's z = (J + 1)²π² (`shear_continuum.rs`).
pub(crate) const TAIL_RATIO: f64 = 16.0;
/// The most blocks the spring path keeps (J ≤ MAX_BLOCKS).
pub(crate) const MAX_BLOCKS: usize = 128;

/// π^{−2m} Σ_{j>J} j^{−2m} over even and over odd j, m = 1..=[`TAIL_TERMS`].
pub(crate) type TailConsts = [[f64; 2]; TAIL_TERMS];

/// The tail constants of J blocks, computed once per J.
pub(crate) fn tail_consts(j_max: usize) -> &'static TailConsts {
    static TABLE: [OnceLock<TailConsts>; MAX_BLOCKS + 1] = [const { OnceLock::new() }; MAX_BLOCKS + 1];
    TABLE[j_max].get_or_init(|| {
        std::array::from_fn(|i| {
            let p = 2 * (i as i32 + 1);
            let all = zeta_tail(p, j_max + 1);
            let even = 2f64.powi(-p) * zeta_tail(p, j_max / 2 + 1);
            let scale = PI.powi(-p);
            [scale * even, scale * (all - even)]
        })
    })
}

/// Σ_{j≥n} j^{−p} (p ≥ 2): 64 terms summed, the rest by Euler–Maclaurin,
///   Σ_{j≥x} j^{−p} = x^{1−p}/(p − 1) + x^{−p}/2 + Σ_k B_{2k}/(2k)!·p(p+1)…(p+2k−2)·x^{−p−2k+1} + …,
/// four Bernoulli terms at x = n + 64 ≥ 65: for p ≤ 26 the fifth is below
/// 1e-17 of the sum. Written out: statrs, the crate's special-function
/// dependency, has no zeta function, and only these integer powers are needed.
fn zeta_tail(p: i32, n: usize) -> f64 {
    const BERNOULLI: [f64; 4] = [1.0 / 6.0, -1.0 / 30.0, 1.0 / 42.0, -1.0 / 30.0];
    let x = (n + 64) as f64;
    let pf = f64::from(p);
    let mut sum = x.powi(1 - p) / (pf - 1.0) + 0.5 * x.powi(-p);
    let (mut rising, mut factorial) = (pf, 2.0);
    for (k, b) in (1..).zip(BERNOULLI) {
        sum += b / factorial * rising * x.powi(-p - 2 * k + 1);
        let kf = f64::from(k);
        rising *= (pf + 2.0 * kf - 1.0) * (pf + 2.0 * kf);
        factorial *= (2.0 * kf + 1.0) * (2.0 * kf + 2.0);
    }
    for j in (n..n + 64).rev() {
        sum += (j as f64).powi(-p);
    }
    sum
}

/// The scalars both tails read, ẽ² (`t`), g̃ and r̃², with the denominator D
/// of their terms (`shear_continuum.rs`).
#[derive(Debug, Clone, Copy)]
pub struct TailPencil {
    pub(crate) t: f64,
    pub(crate) g: f64,
    pub(crate) r2: f64,
}

impl TailPencil {
    /// [D₂, D₁, D₀] of the terms' denominator at (p, q) (`shear_continuum.rs`).
    fn denominator<T: Num>(&self, p: Jet<T>, q: Jet<T>) -> [Jet<T>; 3] {
        let (pp, pq) = (p.mul(p), p.mul(q));
        [
            p.scale(self.t).add(q.scale(self.g)).mul(p.scale(self.r2 * self.t).add(q)),
            pp.scale(2.0 * self.r2 * self.t).add(pq.scale(1.0 + self.g * (self.t + self.r2))),
            pp.scale(self.r2).add(pq.scale(self.g)),
        ]
    }

    /// Fujiwara's bound on the roots of D at (p, q): every root of
    /// D₂z² + D₁z + D₀ has |z| ≤ 2 max(|D₁/D₂|, |D₀/2D₂|^½).
    pub(crate) fn root_bound<T: Num>(&self, p: Jet<T>, q: Jet<T>) -> f64 {
        let [d2, d1, d0] = self.denominator(p, q).map(|d| d.v.modulus());
        2.0 * (d1 / d2).max((0.5 * d0 / d2).sqrt())
    }
}

/// The blocks j > J of the spring path in closed form (`shear_continuum.rs`).
#[derive(Debug, Clone, Copy)]
pub struct SpringTail {
    pub(crate) pencil: TailPencil,
    pub(crate) consts: &'static TailConsts,
    pub(crate) z_limit: f64,
}

impl SpringTail {
    /// (Σ over even j > J, Σ over odd j > J) of α_j at (p, q), with
    /// derivatives; `None` where the series may not converge (`shear_continuum.rs`).
    pub(crate) fn sums<T: Num>(&self, p: Jet<T>, q: Jet<T>) -> Option<[Jet<T>; 2]> {
        let pen = &self.pencil;
        let a = p.scale(pen.t).add(q.scale(pen.g));
        let [d2, d1, d0] = pen.denominator(p, q);
        if !(pen.root_bound(p, q) <= self.z_limit) {
            return None;
        }
        let inv = Jet::c(1.0).div(d2);
        let mut prev = a.scale(2.0).mul(inv);
        let mut e = p.scale(2.0).sub(d1.mul(prev)).mul(inv);
        let c = &self.consts;
        let mut sums = [prev.scale(c[0][0]).add(e.scale(c[1][0])), prev.scale(c[0][1]).add(e.scale(c[1][1]))];
        for ci in &c[2..] {
            let next = Jet::c(0.0).sub(d1.mul(e).add(d0.mul(prev))).mul(inv);
            (prev, e) = (e, next);
            sums = [sums[0].add(e.scale(ci[0])), sums[1].add(e.scale(ci[1]))];
        }
        Some(sums)
    }
}

/// The blocks j > J of the point-mass path in closed form (`shear_continuum.rs`).
#[derive(Debug, Clone, Copy)]
pub struct MassTail {
    pub(crate) pencil: TailPencil,
    /// 1 − 2x̃.
    pub(crate) c: f64,
    pub(crate) j_max: usize,
}

/// Φ(ζ) = Σ_{j≥1} sin²(jπx̃)/(j²π² − ζ) = (cos(b(1 − 2x̃)) − cos b)/(4b sin b),
/// b = √ζ (`shear_continuum.rs`), and dΦ/dζ; `None` near b = 0 (a removable point the
/// path never needs) or where cos and sin would overflow.
fn phi(zeta: Complex64, c: f64) -> Option<(Complex64, Complex64)> {
    let b = zeta.sqrt();
    if !(b.norm() > 1e-3 && b.im.abs() < 300.0) {
        return None;
    }
    let (sb, cb) = (b.sin(), b.cos());
    let num = (b * c).cos() - cb;
    let den = 4.0 * b * sb;
    let dnum = -c * (b * c).sin() + sb;
    let dden = 4.0 * (sb + b * cb);
    let v = num / den;
    let d = (dnum * den - num * dden) / (den * den) / (2.0 * b);
    (v.re.is_finite() && v.im.is_finite() && d.re.is_finite() && d.im.is_finite()).then_some((v, d))
}

impl MassTail {
    /// Σ_{j>J} β_j/δ_j at (p, q), with its derivative (`shear_continuum.rs`): the sum
    /// over all j ≥ 1 in closed form by partial fractions of N/D, less the
    /// kept blocks' terms j = 1..J (`coords[j][0]` = sin(jπx̃)); `None` where D
    /// has a double root or Φ is not evaluable.
    pub(crate) fn sum<T: Num>(&self, p: Jet<T>, q: Jet<T>, coords: &[[f64; 2]]) -> Option<Jet<T>> {
        let cx = |j: Jet<T>| Jet { v: j.v.to_complex(), d: j.d.to_complex() };
        let (p, q) = (cx(p), cx(q));
        let sp = &self.pencil;
        let n1 = p.scale(sp.t * sp.r2).add(q);
        let n0 = p.scale(sp.r2).add(q.scale(sp.g));
        let [d2, d1, d0] = sp.denominator(p, q);
        let disc = d1.mul(d1).sub(d2.mul(d0).scale(4.0));
        let root = disc.v.sqrt();
        if root.norm() == 0.0 {
            return None;
        }
        let sq = Jet { v: root, d: disc.d / (2.0 * root) };
        // the root of larger modulus from −(D₁ ± √disc)/2D₂, the other as D₀/w (no cancellation)
        let sign = if (d1.v + sq.v).norm() >= (d1.v - sq.v).norm() { 1.0 } else { -1.0 };
        let w = d1.add(sq.scale(sign)).scale(-0.5);
        let (z1, z2) = (w.div(d2), d0.div(w));
        if !((z1.v - z2.v).norm() > 1e-8 * (z1.v.norm() + z2.v.norm())) {
            return None;
        }
        let a1 = n1.mul(z1).add(n0).scale(2.0).div(d2.mul(z1.sub(z2)));
        let a2 = n1.mul(z2).add(n0).scale(2.0).div(d2.mul(z2.sub(z1)));
        let (f1, g1) = phi(z1.v, self.c)?;
        let (f2, g2) = phi(z2.v, self.c)?;
        let phi1 = Jet { v: f1, d: g1 * z1.d };
        let phi2 = Jet { v: f2, d: g2 * z2.d };
        let mut tail = a1.mul(phi1).add(a2.mul(phi2));
        for (j, n) in coords.iter().enumerate().take(self.j_max + 1).skip(1) {
            let z = (j as f64 * PI).powi(2);
            let term = n1.scale(z).add(n0).scale(2.0 * n[0] * n[0]).div(d2.scale(z * z).add(d1.scale(z)).add(d0));
            tail = tail.sub(term);
        }
        let back = |c: Complex64| T::from_complex(c);
        Some(Jet { v: back(tail.v), d: back(tail.d) })
    }
}

#[cfg(test)]
mod tests {
    //! Data: brute-force sums of the omitted blocks' own terms (their 2 × 2
    //! inverses) and the zeta function's closed forms; no secular path.
    use super::*;

    /// ẽ², g̃ and r̃² of a test beam.
    struct Params {
        e2: f64,
        shear: f64,
        r2: f64,
    }

    /// The tail in closed form is the brute-force sum of the omitted blocks'
    /// α_j = [B_j⁻¹]_vv/d_j (2 × 2 inverses of the blocks themselves, j up to
    /// 2·10⁵, the rest from its leading term) at a complex point near mode 5
    /// with a relaxation's G, to 1e-10 relative.
    #[test]
    fn the_spring_tail_is_the_sum_of_the_omitted_blocks() {
        let p = Params { e2: 0.0156, shear: 349.0, r2: 1.0 / 1024.0 };
        let j_max = 28;
        let tail = SpringTail {
            pencil: TailPencil { t: p.e2, g: p.shear, r2: p.r2 },
            consts: tail_consts(j_max),
            z_limit: ((j_max + 1) as f64 * PI).powi(2) / TAIL_RATIO,
        };
        let s = Complex64::new(-2.0, 60.0);
        let g = Complex64::new(1.0, 0.0) + 0.3 * s / (s + 40.0);
        let (pj, qj) = (Jet { v: s * s, d: 2.0 * s }, Jet { v: g, d: Complex64::new(0.0, 0.0) });
        let [even, odd] = tail.sums(pj, qj).unwrap();
        let mut brute = [Complex64::new(0.0, 0.0); 2];
        let last = 200_000;
        for j in j_max + 1..=last {
            let k = j as f64 * PI;
            let (z, a) = (k * k, 1.0 + p.e2 * k * k);
            let (pv, qv) = (s * s, g);
            let uu = pv * a + qv * p.shear * z;
            let uv = pv * a / k;
            let vv = pv * a * (1.0 + p.r2 * z) / z + qv * z;
            brute[j % 2] += 2.0 * uu / (uu * vv - uv * uv);
        }
        // the rest: α ≈ e₀/z, e₀ = 2(pẽ² + qg̃)/D₂, and for even N = last
        // Σ_{j>N, even} j⁻² = ¼Σ_{i>N/2} i⁻² = 1/2N − 1/2N² + O(N⁻³),
        // Σ_{j>N, odd} j⁻² = (1/N − 1/2N²) − that = 1/2N + O(N⁻³)
        let e0 = 2.0 * (s * s * p.e2 + g * p.shear) / ((s * s * p.e2 + g * p.shear) * (s * s * p.r2 * p.e2 + g));
        let n = last as f64;
        brute[0] += e0 / (PI * PI) * (0.5 / n - 0.5 / (n * n));
        brute[1] += e0 / (PI * PI) * (0.5 / n);
        for (got, want) in [(even.v, brute[0]), (odd.v, brute[1])] {
            assert!((got - want).norm() <= 1e-10 * want.norm(), "{got} against {want}");
        }
    }

    /// Σ_{j≥n} j^{−p} against its values in closed form: ζ(2) = π²/6 and
    /// ζ(4) = π⁴/90 minus the first terms (n = 1 is the whole sum), and a
    /// direct sum for p = 26.
    #[test]
    fn the_zeta_tail_is_exact() {
        assert!((zeta_tail(2, 1) - PI * PI / 6.0).abs() <= 1e-15);
        assert!((zeta_tail(4, 1) - PI.powi(4) / 90.0).abs() <= 1e-15);
        let partial: f64 = (1..30).map(|j| (j as f64).powi(-2)).sum();
        assert!((zeta_tail(2, 30) - (PI * PI / 6.0 - partial)).abs() <= 1e-14);
        let direct: f64 = (30..200).rev().map(|j| (j as f64).powi(-26)).sum();
        assert!((zeta_tail(26, 30) - direct).abs() <= 1e-15 * direct);
    }

    /// The point-mass tail in closed form is the brute-force sum of the
    /// omitted blocks' β_j/δ_j (2 × 2 inverses of the blocks, j up to 2·10⁵,
    /// the rest from its leading term) at a complex point with a
    /// relaxation's G, at two mass positions, to 1e-10 relative.
    #[test]
    fn the_mass_tail_is_the_sum_of_the_omitted_blocks() {
        let p = Params { e2: 0.0156, shear: 349.0, r2: 1.0 / 1024.0 };
        let j_max = 8;
        let s = Complex64::new(-2.0, 60.0);
        let g = Complex64::new(1.0, 0.0) + 0.3 * s / (s + 40.0);
        let (pj, qj) = (Jet { v: s * s, d: 2.0 * s }, Jet { v: g, d: Complex64::new(0.0, 0.0) });
        for x in [0.4847, 0.1] {
            let coords: Vec<[f64; 2]> = (0..=j_max)
                .map(|j| {
                    let k = j as f64 * PI;
                    if j == 0 {
                        [0.0, 0.0]
                    } else {
                        [(k * x).sin(), (k * x).sin() / k]
                    }
                })
                .collect();
            let pencil = TailPencil { t: p.e2, g: p.shear, r2: p.r2 };
            let tail = MassTail { pencil, c: 1.0 - 2.0 * x, j_max };
            let got = tail.sum(pj, qj, &coords).unwrap().v;
            let mut brute = Complex64::new(0.0, 0.0);
            let last = 200_000;
            for j in j_max + 1..=last {
                let k = j as f64 * PI;
                let (z, a) = (k * k, 1.0 + p.e2 * k * k);
                let (pv, qv) = (s * s, g);
                let (uu, uv, vv) = (pv * a + qv * p.shear * z, pv * a / k, pv * a * (1.0 + p.r2 * z) / z + qv * z);
                let n = [(k * x).sin(), (k * x).sin() / k];
                let beta = n[0] * n[0] * vv - 2.0 * n[0] * n[1] * uv + n[1] * n[1] * uu;
                brute += 2.0 * beta / (uu * vv - uv * uv);
            }
            // the rest: β/δ ≈ 2 sin²(kx̃)·N₁/(D₂z), mean sin² = ½: Σ_{j>N} 1/(jπ)² ≈ 1/(π²N)
            let n1 = s * s * p.e2 * p.r2 + g;
            let d2 = (s * s * p.e2 + g * p.shear) * (s * s * p.r2 * p.e2 + g);
            brute += n1 / d2 / (PI * PI * last as f64);
            assert!((got - brute).norm() <= 1e-10 * brute.norm(), "x̃ {x}: {got} against {brute}");
        }
    }
}
