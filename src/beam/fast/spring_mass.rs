//! The exact fast path of support rotational springs and a point mass
//! together on a uniform simply supported Euler–Bernoulli mesh without an
//! axial force (issue 41): both are low-rank updates of the pencil whose
//! wavenumber blocks `axial_spectrum.rs` gives in closed form, so every pole
//! is a root of a secular determinant of order |A| + 1 ≤ 3 over the whole
//! spring- and mass-free spectrum, evaluated in O(n_e).
//!
//! # Why it is exact (the derivation)
//! The springs act on the end rotations, unrelaxed (`spring_spectrum.rs`);
//! the point mass on the inertia only, undamped (`mass_blocks.rs`). So
//!   T̃(s) = T₀(s) + U C(s) Uᵀ,  T₀(s) = pM̃ + qK̃,  p = s(s + c̃), q = G(s),
//! with U = [E, N]: the columns of the identity at the active ends' rotation
//! DOFs and the interpolation vector N(x̃) of the deflection at the mass, and
//! C(s) = diag(k̃_e …, μ̃s²). Without an axial force each wavenumber block is
//! B_j = pM_j + qK_j, so with the block pencil's M-normalised eigenvectors φ_k
//! (eigenvalue μ_k; the whole spectrum of the mesh pencil, `mu`)
//!   F(s) = Uᵀ T₀(s)⁻¹ U = Σ_k u_k u_kᵀ / (p + qμ_k),
//!   u_k = (φ_k,v, σ_j φ_k,v, n_jᵀφ_k) / √d_j   (active ends, then the mass),
//! from T₀⁻¹ = V(DB)⁻¹Vᵀ (`spring_spectrum.rs`), the end rows of V (1 and
//! σ_j = (−1)^j on v_j) and the mass's block coordinates n_j
//! (`mass_blocks.rs`). The determinant lemma gives
//!   det T̃(s) = det T₀(s) · det C(s) · det H(s),  H = C(s)⁻¹ + F(s),
//! for any damping and internal variables: exact, no approximation beyond
//! the FE model itself.
//!
//! Newton runs on the pole-free g(s) = Π_{r∈R} δ_r · det H with
//! δ_r = p + qμ_r over the terms R whose poles bound the mode (below).
//! Writing X = C⁻¹ + Σ_{k∉R} u_k u_kᵀ/δ_k, the bordered matrix
//!   Q = [[X, U_R], [U_Rᵀ, −diag(δ_r)]]
//! has det Q = det(−diag δ) · det(X + U_R diag(δ)⁻¹ U_Rᵀ) (Schur complement
//! of the lower block), so g = (−1)^{|R|} det Q: entire in the removed
//! terms, of order ≤ 3 + 4, and evaluated by Gaussian elimination with
//! partial pivoting on jets.
//!
//! # Modes (the proof of the order)
//! Physical mode r is the r-th eigenpair of the undamped relaxed pencil
//! (K̃ + EK_sEᵀ, M̃ + μ̃NNᵀ). On the real axis (p = −λ, q = 1, s² = −λ) with
//! P₀ = K̃ − λM̃ and C = diag(k̃_e …, −λμ̃), Haynsworth's inertia additivity on
//! [[P₀, U], [Uᵀ, −C⁻¹]] (both Schur complements) gives
//! In(−C⁻¹) + In P = In P₀ + In(−H), and Sylvester (M̃ + μ̃NNᵀ ≻ 0) makes
//! #{eigenvalues < λ} = neg P, so
//!   #{eigenvalues < λ} = #{μ < λ} + pos(H(λ)) − |A|
//! (C⁻¹ has |A| positive entries and one negative for λ > 0). pos(H) of a
//! real symmetric matrix of order ≤ 3 is the number of sign changes of its
//! characteristic polynomial's coefficients (Descartes' rule, exact when
//! every root is real); a singular H, or λ at a μ, leaves the count `None`.
//! The springs raise every eigenvalue by at most |A| places and the mass
//! lowers it by at most one (interlacing), so μ_{r−1} ≤ λ_r ≤ μ_{r+|A|}
//! (μ₀ = 0) and R is the terms of μ_{r−1} … μ_{r+|A|}. Safeguarded Newton
//! on g(λ) inside the bracket that every count narrows converges to λ_r,
//! accepted only when the count is r − 1 just below it and ≥ r just above it
//! (a relative gap of `spring_spectrum::CERTIFY_GAP`,
//! `spring_spectrum::certified_eigenvalue`); otherwise the path declines, as it
//! does when μ₁ ≤ 0 or a block's two eigenvalues nearly coincide
//! (`spring_spectrum::RESIDUE_GAP`: the eigenvectors are then not
//! separable).
//!
//! The eigenvector is x = T₀(−λ)⁻¹Uz with H(λ)z = 0: its constraint values
//! are Uᵀx = F(λ)z (end rotations θ_e, the mass's deflection w) and
//! xᵀM̃x = zᵀF′(λ)z, F′ = Σ_k u_k u_kᵀ/(μ_k − λ)² (d(P₀⁻¹)/dλ = P₀⁻¹M̃P₀⁻¹).
//! With m_x = xᵀM̃x + μ̃w² the one-term family is
//! s² + c_x s + a + bG(s) = 0, a = Σ_e k̃_e θ_e²/m_x (the unrelaxed springs),
//! b = λ − a, c_x = c̃·xᵀM̃x/m_x — the starts the coupled reference uses
//! (`coupled.rs`, `family_approximations`) — and Newton on g(s) from each
//! complex start with the reference's acceptance tests
//! (`axial_spectrum::accept_pair`). Only the oscillatory poles are solved:
//! when every pole is asked for and a family has real (relaxation) starts,
//! the path declines, as the other block paths do.
//!
//! # Accuracy
//! The block entries are those of `axial_spectrum.rs` (≲ 1.4e-12 relative
//! in the bending eigenvalue at n_e = 40, j = 1). Each φ_k is the null
//! vector of the better-scaled row of S − μ_kM, normalised in M: rounding a
//! few eps over the relative gap of the block's two eigenvalues (≥ 1e-2 on a
//! uniform beam). The sums are those of `spring_spectrum.rs`'s partial
//! fractions, and Newton stops at a step ≤ 1e-10·|s| with quadratic
//! convergence. The property test (`tests/beam_spring_mass_fast_path.rs`)
//! holds the poles to the coupled reference.

use num_complex::Complex64;

use crate::beam::fast::axial_spectrum::{secular_families, AxialBlocks};
use crate::beam::fast::jet::Modulus;
use crate::beam::fast::mass_blocks::MassScratch;
use crate::beam::fast::secular::{certified_eigenvalue, RESIDUE_GAP};
use crate::beam::fast::spring_spectrum::{Jet, Num};
use crate::beam::solve::family::Roots;

/// H(λ)z must vanish to this, relative to |H||z|, at a certified eigenvalue:
/// H is singular there up to the rounding of its sums (~1e-13).
const NULL_TOL: f64 = 1e-8;
/// At most |A| + 2 removed terms (module doc).
const MAX_REMOVED: usize = 4;
/// The order of the bordered matrix: |A| + 1 constraints and the removed terms.
const MAX_ORDER: usize = 3 + MAX_REMOVED;

/// One term: a spring- and mass-free eigenvalue μ_k, its constraint vector
/// u_k and the products u_a u_b over the upper triangle (row-major).
#[derive(Debug, Clone, Copy, Default)]
struct Term {
    mu: f64,
    u: [f64; 3],
    uu: [f64; 6],
}

/// The secular data of one beam.
#[derive(Debug, Default, Clone)]
pub struct SpringMassScratch {
    /// The mass path's blocks, spectrum and mass coordinates.
    mass: MassScratch,
    terms: Vec<Term>,
    /// k̃ of the active ends (1 or 2).
    springs: Vec<f64>,
    /// The constraint count m = |A| + 1 (the ends, then the mass).
    m: usize,
}

/// The index of entry (a, b), a ≤ b, of an m × m upper triangle, row-major.
fn tri(m: usize, a: usize, b: usize) -> usize {
    a * m - a * (a + 1) / 2 + b
}

impl SpringMassScratch {
    /// The terms from the mass path's blocks (module doc); `false` when a
    /// block's eigenvalues nearly coincide or a vector is not finite.
    fn fill_terms(&mut self, ends: &[usize]) -> bool {
        self.terms.clear();
        let m = self.m;
        for &(mu, j) in &self.mass.mu {
            let b = &self.mass.blocks[j];
            let n = self.mass.coords[j];
            let phi = if b.single {
                [0.0, 1.0 / b.m.vv.sqrt()]
            } else {
                let Some((low, up)) = b.eigenvalues() else { return false };
                let other = if mu == low { up } else { low };
                if !((other - mu).abs() > RESIDUE_GAP * other.abs().max(mu.abs())) {
                    return false;
                }
                let s = b.shifted(mu);
                let r1 = [-s.uv, s.uu];
                let r2 = [s.vv, -s.uv];
                let x = if r1[0].abs() + r1[1].abs() >= r2[0].abs() + r2[1].abs() { r1 } else { r2 };
                let norm = b.m.form(x).sqrt();
                [x[0] / norm, x[1] / norm]
            };
            let scale = 1.0 / b.d.sqrt();
            let mut u = [0.0; 3];
            for (i, &e) in ends.iter().enumerate() {
                u[i] = if e == 0 { phi[1] } else { b.sign * phi[1] } * scale;
            }
            u[m - 1] = (n[0] * phi[0] + n[1] * phi[1]) * scale;
            if !u.iter().all(|v| v.is_finite()) {
                return false;
            }
            let mut t = Term { mu, u, ..Term::default() };
            for a in 0..m {
                for c in a..m {
                    let k = tri(m, a, c);
                    t.uu[k] = u[a] * u[c];
                }
            }
            self.terms.push(t);
        }
        true
    }

    /// Σ_{k∉removed} u_k u_kᵀ/(p + qμ_k) over the upper triangle, with
    /// derivatives: with r = p/q, 1/(p + qμ_k) = 1/(q(r + μ_k)) and its
    /// derivative −(p′ + q′μ_k)/(q²(r + μ_k)²), one reciprocal per term.
    fn rest_sums<T: Num>(&self, p: Jet<T>, q: Jet<T>, removed: (usize, usize)) -> [Jet<T>; 6] {
        let n = tri(self.m, self.m - 1, self.m - 1) + 1;
        let iq = q.v.recip();
        let r = p.v * iq;
        let zero = T::from(0.0);
        let (mut f, mut d) = ([zero; 6], [zero; 6]);
        for t in self.terms[..removed.0].iter().chain(&self.terms[removed.1..]) {
            let inv = (r + t.mu).recip();
            let dk = (p.d + q.d * t.mu) * (inv * inv);
            for k in 0..n {
                f[k] = f[k] + inv * t.uu[k];
                d[k] = d[k] + dk * t.uu[k];
            }
        }
        let iq2 = iq * iq;
        std::array::from_fn(|k| Jet { v: f[k] * iq, d: zero - d[k] * iq2 })
    }

    /// X = C⁻¹ + the rest's flexibility as a full m × m matrix of jets.
    fn x_matrix<T: Num>(&self, p: Jet<T>, q: Jet<T>, s2: Jet<T>, removed: (usize, usize)) -> [[Jet<T>; 3]; 3] {
        let m = self.m;
        let f = self.rest_sums(p, q, removed);
        let mut x = [[Jet::c(0.0); 3]; 3];
        for a in 0..m {
            for c in a..m {
                x[a][c] = f[tri(m, a, c)];
                x[c][a] = x[a][c];
            }
        }
        for (i, &k) in self.springs.iter().enumerate() {
            x[i][i] = x[i][i].add(Jet::c(1.0 / k));
        }
        x[m - 1][m - 1] = x[m - 1][m - 1].add(Jet::c(1.0).div(s2.scale(self.mass.mass)));
        x
    }

    /// g = (−1)^{|R|} det Q at (p, q, s²) (module doc), with its derivative.
    fn secular<T: Num>(&self, p: Jet<T>, q: Jet<T>, s2: Jet<T>, removed: (usize, usize)) -> Jet<T> {
        self.bordered(self.x_matrix(p, q, s2, removed), p, q, removed)
    }

    /// (−1)^{|R|} det Q from X (module doc).
    fn bordered<T: Num>(&self, x: [[Jet<T>; 3]; 3], p: Jet<T>, q: Jet<T>, removed: (usize, usize)) -> Jet<T> {
        let (m, nr) = (self.m, removed.1 - removed.0);
        let n = m + nr;
        let mut a = [[Jet::<T>::c(0.0); MAX_ORDER]; MAX_ORDER];
        for i in 0..m {
            a[i][..m].copy_from_slice(&x[i][..m]);
        }
        for (r, t) in self.terms[removed.0..removed.1].iter().enumerate() {
            for (i, &u) in t.u[..m].iter().enumerate() {
                a[i][m + r] = Jet::c(u);
                a[m + r][i] = Jet::c(u);
            }
            a[m + r][m + r] = Jet::c(0.0).sub(p.add(q.scale(t.mu)));
        }
        let d = determinant(&mut a, n);
        if nr % 2 == 1 {
            Jet::c(0.0).sub(d)
        } else {
            d
        }
    }

    /// g(λ) on the real axis (p = s² = −λ, q = 1) with its derivative in λ,
    /// and H(λ) from the same sweep: X plus the removed terms' u uᵀ/(μ − λ).
    fn real_secular(&self, lambda: f64, removed: (usize, usize)) -> (Jet<f64>, Option<[[f64; 3]; 3]>) {
        let p = Jet { v: -lambda, d: -1.0 };
        let x = self.x_matrix(p, Jet::c(1.0), p, removed);
        let m = self.m;
        let mut h = [[0.0; 3]; 3];
        for i in 0..m {
            for j in 0..m {
                h[i][j] = x[i][j].v;
            }
        }
        for t in &self.terms[removed.0..removed.1] {
            let inv = 1.0 / (t.mu - lambda);
            for (row, ui) in h.iter_mut().zip(&t.u).take(m) {
                for (v, uj) in row.iter_mut().zip(&t.u).take(m) {
                    *v += ui * uj * inv;
                }
            }
        }
        let finite = h.iter().flatten().all(|v| v.is_finite());
        (self.bordered(x, p, Jet::c(1.0), removed), finite.then_some(h))
    }

    /// H(λ) on the real axis, values only (the certifying counts).
    fn h_value(&self, lambda: f64) -> [[f64; 3]; 3] {
        let m = self.m;
        let n = tri(m, m - 1, m - 1) + 1;
        let mut f = [0.0; 6];
        for t in &self.terms {
            let inv = 1.0 / (t.mu - lambda);
            for (v, uu) in f.iter_mut().zip(&t.uu).take(n) {
                *v += uu * inv;
            }
        }
        let mut h = [[0.0; 3]; 3];
        for a in 0..m {
            for c in a..m {
                h[a][c] = f[tri(m, a, c)];
                h[c][a] = h[a][c];
            }
        }
        for (i, &k) in self.springs.iter().enumerate() {
            h[i][i] += 1.0 / k;
        }
        h[m - 1][m - 1] -= 1.0 / (self.mass.mass * lambda);
        h
    }

    /// H(λ) (every term) and F′(λ) on the real axis, full m × m.
    fn h_real(&self, lambda: f64) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
        let (p, q, s2) = (Jet { v: -lambda, d: -1.0 }, Jet::c(1.0), Jet { v: -lambda, d: -1.0 });
        let x = self.x_matrix(p, q, s2, (0, 0));
        let mut h = [[0.0; 3]; 3];
        let mut dh = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                h[i][j] = x[i][j].v;
                dh[i][j] = x[i][j].d;
            }
        }
        // C⁻¹'s mass entry −1/(λμ̃) is not part of F′
        let m = self.m;
        dh[m - 1][m - 1] -= 1.0 / (self.mass.mass * lambda * lambda);
        (h, dh)
    }

    /// #{eigenvalues < λ} = #{μ < λ} + pos(H(λ)) − |A| (module doc); `None`
    /// where H is singular or not finite.
    fn count(&self, lambda: f64) -> Option<usize> {
        if !(lambda > 0.0) {
            return Some(0);
        }
        self.count_from(lambda, &self.h_value(lambda))
    }

    /// [`Self::count`] with H(λ) = `h` given (λ > 0).
    fn count_from(&self, lambda: f64, h: &[[f64; 3]; 3]) -> Option<usize> {
        let pos = positive_eigenvalues(h, self.m)?;
        let below = self.mass.mu.partition_point(|&(m, _)| m < lambda);
        (below + pos).checked_sub(self.springs.len())
    }

    /// The removed terms of mode r0 + 1: μ_{r−1} … μ_{r+|A|} (module doc).
    fn removed(&self, r0: usize) -> (usize, usize) {
        (r0.saturating_sub(1), r0 + self.springs.len() + 1)
    }

    /// The certified eigenvalue λ_r (r = r0 + 1); `None` where the path declines.
    fn eigenvalue(&self, r0: usize) -> Option<f64> {
        let na = self.springs.len();
        let mu = &self.mass.mu;
        let a = if r0 == 0 { 0.0 } else { mu.get(r0 - 1)?.0 };
        let b = mu.get(r0 + na)?.0;
        let removed = self.removed(r0);
        // first-order start: the springs raise μ_r by Σ_e k̃_e u_e², the mass
        // scales it by 1/(1 + μ̃u_m²) (u: the M̃-normalised mode's constraint values)
        let t = &self.terms[r0];
        let raise: f64 = self.springs.iter().enumerate().map(|(i, &k)| k * t.u[i] * t.u[i]).sum();
        let w = t.u[self.m - 1];
        let mut x = (t.mu + raise) / (1.0 + self.mass.mass * w * w);
        if !(x > a && x < b) {
            x = 0.5 * (a + b);
        }
        certified_eigenvalue(
            r0,
            (a, b),
            x,
            |x| {
                let (g, h) = self.real_secular(x, removed);
                (g, h.and_then(|h| self.count_from(x, &h)))
            },
            |x| self.count(x),
        )
    }

    /// (a, b, c_x/c̃) of the one-term family of the eigenvector of λ (module doc).
    fn one_term(&self, lambda: f64) -> Option<(f64, f64, f64)> {
        let m = self.m;
        let (h, dh) = self.h_real(lambda);
        let z = null_vector(&h, m)?;
        let hz: f64 = (0..m).map(|i| (0..m).map(|j| h[i][j] * z[j]).sum::<f64>().powi(2)).sum::<f64>().sqrt();
        let hn: f64 = (0..m).flat_map(|i| (0..m).map(move |j| (i, j))).map(|(i, j)| h[i][j].abs()).fold(0.0, f64::max);
        let zn = z.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if !(hz <= NULL_TOL * hn * zn) {
            return None;
        }
        // F = H − C⁻¹ and F′ = dH without C⁻¹'s part (`h_real`)
        let mut f = h;
        for (i, &k) in self.springs.iter().enumerate() {
            f[i][i] -= 1.0 / k;
        }
        f[m - 1][m - 1] += 1.0 / (self.mass.mass * lambda);
        let y: [f64; 3] = std::array::from_fn(|i| if i < m { (0..m).map(|j| f[i][j] * z[j]).sum() } else { 0.0 });
        let beam_mass: f64 = (0..m).map(|i| (0..m).map(|j| z[i] * dh[i][j] * z[j]).sum::<f64>()).sum();
        let m_x = beam_mass + self.mass.mass * y[m - 1] * y[m - 1];
        let ks: f64 = self.springs.iter().enumerate().map(|(i, &k)| k * y[i] * y[i]).sum();
        let a1 = ks / m_x;
        let ok = beam_mass > 0.0 && m_x.is_finite() && a1.is_finite() && a1 >= 0.0 && a1 < lambda;
        ok.then_some((a1, lambda - a1, beam_mass / m_x))
    }

    /// The poles of families 1..=n_modes into `roots` (every pole when
    /// `all`, else the oscillatory pairs); `false` when the path declines.
    fn family_roots(&self, c: f64, modulus: Modulus, n_modes: usize, all: bool, roots: &mut Vec<Roots>) -> bool {
        let family = |r0| {
            let lambda = self.eigenvalue(r0)?;
            let (a1, b1, beam_share) = self.one_term(lambda)?;
            Some(((a1, b1, c * beam_share), self.removed(r0)))
        };
        let step = |&removed: &(usize, usize), s: Complex64| {
            let p = Jet { v: s * (s + c), d: 2.0 * s + c };
            let s2 = Jet { v: s * s, d: 2.0 * s };
            let e = self.secular::<Complex64>(p, modulus.at(s), s2, removed);
            e.v / e.d
        };
        secular_families(n_modes, all, modulus, roots, family, step)
    }
}

/// det of the leading n × n block of `a` by Gaussian elimination with
/// partial pivoting on the values (destroys `a`).
fn determinant<T: Num>(a: &mut [[Jet<T>; MAX_ORDER]; MAX_ORDER], n: usize) -> Jet<T> {
    let mut det = Jet::c(1.0);
    for k in 0..n {
        // pivot by |re| + |im|: any norm serves, and this one needs no hypot
        let size = |v: T| v.to_complex().l1_norm();
        let piv = (k..n).max_by(|&i, &j| size(a[i][k].v).total_cmp(&size(a[j][k].v))).unwrap_or(k);
        if piv != k {
            a.swap(piv, k);
            det = Jet::c(0.0).sub(det);
        }
        let pivot = a[k][k];
        det = det.mul(pivot);
        if size(pivot.v) == 0.0 {
            return det;
        }
        let row = a[k];
        for r in &mut a[k + 1..n] {
            let l = r[k].div(pivot);
            for (x, y) in r[k + 1..n].iter_mut().zip(&row[k + 1..n]) {
                *x = x.sub(l.mul(*y));
            }
        }
    }
    det
}

/// The number of positive eigenvalues of the real symmetric m × m `h`
/// (m ≤ 3): the sign changes of its characteristic polynomial's coefficients
/// (module doc); `None` when h is singular or not finite.
fn positive_eigenvalues(h: &[[f64; 3]; 3], m: usize) -> Option<usize> {
    let tr: f64 = (0..m).map(|i| h[i][i]).sum();
    let (c2, det) = match m {
        1 => (0.0, h[0][0]),
        2 => (0.0, h[0][0] * h[1][1] - h[0][1] * h[0][1]),
        _ => {
            let minor = |i: usize, j: usize| h[i][i] * h[j][j] - h[i][j] * h[i][j];
            let c2 = minor(0, 1) + minor(0, 2) + minor(1, 2);
            let det = h[0][0] * minor(1, 2) - h[0][1] * (h[0][1] * h[2][2] - h[1][2] * h[0][2])
                + h[0][2] * (h[0][1] * h[1][2] - h[1][1] * h[0][2]);
            (c2, det)
        }
    };
    if !(det.is_finite() && tr.is_finite() && c2.is_finite()) || det == 0.0 {
        return None;
    }
    // t^m − tr t^{m−1} + c₂ t^{m−2} − det (m = 3); t² − tr t + det (m = 2); t − det (m = 1)
    let coeffs: &[f64] = match m {
        1 => &[1.0, -det],
        2 => &[1.0, -tr, det],
        _ => &[1.0, -tr, c2, -det],
    };
    let signs: Vec<f64> = coeffs.iter().copied().filter(|c| *c != 0.0).collect();
    Some(signs.windows(2).filter(|w| w[0] * w[1] < 0.0).count())
}

/// A null vector of the (numerically) singular symmetric m × m `h`: for
/// m = 3 the largest cross product of two rows, for m = 2 the better-scaled
/// row turned, for m = 1 the unit.
fn null_vector(h: &[[f64; 3]; 3], m: usize) -> Option<[f64; 3]> {
    let z = match m {
        1 => [1.0, 0.0, 0.0],
        2 => {
            if h[0][0].abs() + h[0][1].abs() >= h[1][0].abs() + h[1][1].abs() {
                [-h[0][1], h[0][0], 0.0]
            } else {
                [h[1][1], -h[1][0], 0.0]
            }
        }
        _ => {
            let cross = |a: [f64; 3], b: [f64; 3]| {
                [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
            };
            let n2 = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>();
            [cross(h[0], h[1]), cross(h[0], h[2]), cross(h[1], h[2])]
                .into_iter()
                .max_by(|a, b| n2(*a).total_cmp(&n2(*b)))?
        }
    };
    z.iter().any(|v| *v != 0.0).then_some(z)
}

impl AxialBlocks {
    /// Fills `scratch` for (t = ẽ², k̃ at both ends, μ̃, x̃), no axial force;
    /// `false` unless a spring acts, the mass path's setup holds and
    /// n_modes + |A| eigenvalues exist.
    fn spring_mass_setup(
        &self,
        t: f64,
        spring: [f64; 2],
        (mass, x): (f64, f64),
        n_modes: usize,
        scratch: &mut SpringMassScratch,
    ) -> bool {
        let mut ends = [0usize; 2];
        scratch.springs.clear();
        for (e, &k) in spring.iter().enumerate() {
            if k > 0.0 && k.is_finite() {
                ends[scratch.springs.len()] = e;
                scratch.springs.push(k);
            }
        }
        let na = scratch.springs.len();
        if na == 0 || !self.mass_setup(t, (0.0, 0.0), mass, x, n_modes + na, &mut scratch.mass) {
            return false;
        }
        scratch.m = na + 1;
        scratch.fill_terms(&ends[..na])
    }

    /// The poles of families 1..=n_modes (scaled units) of the beam with
    /// support springs k̃ = `spring` (x = 0, x = L) and a point mass μ̃ at x̃,
    /// without an axial force, into `roots`: every pole when `all`, else the
    /// oscillatory pairs only. `false` when the path declines (module doc):
    /// the caller then runs the reference.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn spring_mass_family_roots(
        &self,
        t: f64,
        spring: [f64; 2],
        mass: (f64, f64),
        c: f64,
        modulus: Modulus,
        n_modes: usize,
        all: bool,
        scratch: &mut SpringMassScratch,
        roots: &mut Vec<Roots>,
    ) -> bool {
        if n_modes == 0 || !self.spring_mass_setup(t, spring, mass, n_modes, scratch) {
            return false;
        }
        scratch.family_roots(c, modulus, n_modes, all, roots)
    }

    /// The lowest `n_modes` eigenvalues of the undamped relaxed pencil from
    /// the secular determinant (module doc); `None` where the path declines.
    pub fn spring_mass_eigenvalues(
        &self,
        t: f64,
        spring: [f64; 2],
        mass: (f64, f64),
        n_modes: usize,
    ) -> Option<Vec<f64>> {
        let mut scratch = SpringMassScratch::default();
        if !self.spring_mass_setup(t, spring, mass, n_modes, &mut scratch) {
            return None;
        }
        (0..n_modes).map(|r0| scratch.eigenvalue(r0)).collect()
    }
}

#[cfg(test)]
mod tests {
    //! Data: the assembled mesh pencil of `model.rs` with the springs and
    //! the mass added (`UnitMesh::pencil`) and `eigen.rs`'s solve of it:
    //! another code path than the secular determinant.
    use super::*;
    use crate::beam::fe::model::{PencilParams, UnitMesh};
    use crate::beam::solve::eigen::lowest_eigenpairs;
    use crate::beam::spec::Support;

    /// The certified secular eigenvalues are the lowest eigenvalues of the
    /// assembled pencil within 3e-12 relative (the tolerance of
    /// `spring_spectrum.rs`'s and `mass_blocks.rs`'s same tests: the direct
    /// solve's Rayleigh-quotient rounding and the block eigenvalue's), one
    /// spring or two, light to heavy masses, at nodes and between them.
    #[test]
    fn secular_eigenvalues_are_the_assembled_pencils() {
        for ne in [20, 15] {
            let mesh = UnitMesh::new(ne, Support::SimplySupported);
            let blocks = AxialBlocks::new(&mesh).unwrap();
            for (e, spring, mass, x) in [
                (0.0, [1.0, 1.0], 0.1, 0.3),
                (0.1, [1e-2, 0.0], 1.0, 0.5),
                (0.2, [0.0, 30.0], 1e-3, 0.77),
                (0.05, [1e3, 0.3], 0.4, 0.1),
                (0.15, [7.0, 1e3], 0.05, 0.6),
            ] {
                let t: f64 = e * e;
                let fast = blocks.spring_mass_eigenvalues(t, spring, (mass, x), 6).unwrap();
                let p = PencilParams {
                    e_tilde: e,
                    point_mass: Some((mass, x)),
                    spring,
                    axial: 0.0,
                    shear: 0.0,
                    gradient: 0.0,
                };
                let (k, m) = mesh.pencil(&p);
                let direct = lowest_eigenpairs(&k, &m, 6, &mut Vec::new(), &|v| mesh.pencil_stiffness(&p, v)).unwrap();
                for (f, d) in fast.iter().zip(&direct) {
                    assert!(
                        (f - d.lambda).abs() <= 3e-12 * d.lambda,
                        "n_e {ne} ẽ {e} k {spring:?} μ̃ {mass} x̃ {x}: {f} vs {}",
                        d.lambda
                    );
                }
            }
        }
    }
}
