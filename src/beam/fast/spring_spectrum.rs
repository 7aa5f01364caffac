//! The exact fast path of the support rotational springs on a uniform simply
//! supported Euler–Bernoulli mesh (issue 41): the springs are a rank ≤ 2
//! update of the pencil whose wavenumber blocks `axial_spectrum.rs` gives in
//! closed form, so every pole is a root of a 1 × 1 or 2 × 2 secular
//! determinant evaluated in O(n_e).
//!
//! # Why it is exact (the derivation)
//! The springs are elastic: they are not multiplied by the relaxation factor
//! G(s) = 1 + Σᵢ Δᵢ s/(s + Ωᵢ) (`model.rs`, module doc: "elastic only"; the
//! coupled reference adds them unrelaxed, `coupled.rs`). Without a point mass
//! D̃ = c̃M̃, so the scaled dynamic stiffness is
//!   T̃(s) = T₀(s) + E K_s Eᵀ,  T₀(s) = s(s + c̃)M̃ + G(s)K̃ + K̃_N,
//! with K_s = diag(k̃_e) over the ends e whose spring acts (k̃_e > 0; 1 or 2 of
//! them) and E the columns of the identity at their rotation DOFs
//! (`UnitMesh::spring_dofs`). `axial_spectrum.rs` proves, and checks on the
//! assembled mesh (`AxialBlocks::new`), that A V = W V B_A for every
//! A ∈ {k, m₀, m₁}, with V the wavenumber basis (u_j, v_j), W the identity
//! except ½ on the two end rotations, and B_A block diagonal (2 × 2 for
//! 0 < j < n_e, 1 × 1 for j = 0, n_e). Premultiplying by Vᵀ gives
//! VᵀAV = D B_A with D = VᵀWV = diag(d_j): the vectors of different j are
//! W-orthogonal, u_j and v_j have disjoint supports, and
//! d_j = Σ sin² = Σ′ cos² = n_e/2 for 0 < j < n_e, d_j = n_e for j = 0, n_e.
//! So T₀(s)⁻¹ = V (D B(s))⁻¹ Vᵀ with B_j(s) = s(s + c̃)M_j + G(s)K_j + N_j
//! (the blocks of `axial_spectrum.rs`: M_j = m₀_j + ẽ²m₁_j, K_j = k_j,
//! N_j = ñ(m₁_j + ẽ²k_j)). The rows of V at the end rotations are
//! u_j = 0 (w-only) and v_j = cos(0) = 1 at x = 0, cos(jπ) = σ_j = (−1)^j at
//! x = L. Hence
//!   F(s) = Eᵀ T₀(s)⁻¹ E = Σ_j α_j(s) w_j w_jᵀ,  α_j = [B_j(s)⁻¹]_vv / d_j,
//! w_j = (1, σ_j) restricted to the active ends, [B_j⁻¹]_vv = B_j,uu/det B_j
//! (1/B_j for the 1 × 1 blocks), and by the determinant lemma
//!   det T̃(s) = det T₀(s) · det(I + K_s F(s))
//!            ∝ Π_j det B_j(s) · det K_s · det H(s),  H(s) = K_s⁻¹ + F(s),
//! for any damping c̃, internal variables, ẽ and axial force: exact, no
//! approximation beyond the FE model itself. The poles are the roots of
//! det H(s) (generically: a block pole whose residue vanishes at both ends,
//! B_j,uu = det B_j = 0 at one s, is not seen; that needs a coincidence of
//! two real conditions at one complex point).
//!
//! Near a block pole det H is large; Newton is run on the pole-free
//!   g(s) = Π_{r∈R} det B_r(s) · det H(s)
//! with R the blocks whose undamped eigenvalues bound the mode (below), which
//! is entire in those blocks: H = X + Σ_{r∈R} (β_r/δ_r) w_r w_rᵀ with X the
//! rest, β_r = B_r,uu/d_r, δ_r = det B_r, and a 2 × 2 determinant is
//! quadratic, so det(X + Σ α_r w_r w_rᵀ) is det X plus Σ_r α_r w_rᵀ adj(X) w_r
//! plus Σ_{r<q} α_r α_q det[w_r w_q]², with det[w_r w_q]² = (σ_q − σ_r)² ∈ {0, 4}
//! (one end: X + Σ α_r).
//!
//! # Modes (the proof of the order) and poles
//! Physical mode r is the r-th eigenpair of the undamped relaxed pencil
//! (K̃ + K̃_N + E K_s Eᵀ, M̃) (`modal_result.rs`). Its eigenvalue is found on
//! the real axis (s² = −λ, G = 1, c̃ = 0), certified by an exact inertia
//! count: with the spring-free eigenvalues μ (both closed-form eigenvalues of
//! every 2 × 2 block and the two 1 × 1 ones: the whole spectrum of the mesh
//! pencil), Haynsworth's inertia additivity on [[K − λM, E], [Eᵀ, −K_s⁻¹]]
//! gives
//!   #{eigenvalues < λ} = #{μ < λ} − neg(H(λ))
//! (K_s ≻ 0 on the active ends; neg of a 2 × 2 from its determinant and
//! trace). A rank-|R| positive update interlaces: μ_r ≤ λ_r ≤ μ_{r+|A|}, so R
//! is the set of blocks of μ_r … μ_{r+|A|}, the only poles of det H in the
//! bracket. Newton on g(λ), safeguarded by bisection inside the bracket
//! [a, b] that every count narrows, converges to λ_r, and λ_r is accepted
//! only when the count is r − 1 just below it and ≥ r just above it (a
//! relative gap of [`CERTIFY_GAP`](crate::beam::fast::secular::CERTIFY_GAP)); otherwise the path declines.
//! The eigenvector is x = T₀(−λ)⁻¹E z with H(λ)z = 0, in the block basis
//! y_j = (w_jᵀz)/(d_j δ_j) · (−B_uv, B_uu) (a 1 × 1 block: (w_jᵀz)/(d_j B_j)),
//! its forms xᵀAx = Σ_j d_j y_jᵀA_j y_j, and its end rotations
//! x_e = Σ_j (w_j)_e (y_j)_v; it must satisfy its own Rayleigh quotient
//! (a + b = λ to 1e-8, a guard against a lost vector). From it the one-term
//! family s² + c̃s + a + bG(s) = 0 with a = xᵀ(K_s + K̃_N)x/xᵀM̃x,
//! b = xᵀK̃x/xᵀM̃x — the starts the coupled reference uses
//! (`coupled.rs`, `family_approximations`) — and Newton on g(s) from each
//! complex start, with the reference's acceptance tests (a root within half
//! its start's modulus, no two starts on one pole, a complex start not on
//! the real axis). Only the oscillatory poles are solved: when every pole is
//! asked for and a family has real (relaxation) starts, the path declines, as
//! `axial_spectrum.rs` does.
//!
//! # Partial fractions (no axial force)
//! When every N_j = 0 (no axial force: the mesh at ñ = 0, and every
//! continuum block), B_j(p, q) = pM_j + qK_j, and with μ₁ ≤ μ₂ the
//! eigenvalues of the block pencil (K_j, M_j),
//! det B_j = det M_j (p + qμ₁)(p + qμ₂). Then
//!   [B_j⁻¹]_vv / d_j = (pM_uu + qK_uu)/(d_j det B_j) = Σ_i c_i/(p + qμ_i),
//!   c_i = (K_uu − μ_i M_uu) / (d_j det M_j (μ_other − μ_i))
//! (the residues at p = −qμ_i; for a 1 × 1 block c = 1/(d_j M_vv)), which is
//! φ_v²/d_j of the M-normalised eigenvector, ≥ 0 by interlacing
//! (μ₁ ≤ K_uu/M_uu ≤ μ₂). Checked by hand: c₁ + c₂ = M_uu/(d_j det M_j) and
//! c₁μ₂ + c₂μ₁ = K_uu/(d_j det M_j), the numerator's two coefficients. So
//! F(s) = Σ_k c_k/(p + qμ_k) w_k w_kᵀ over the whole spring-free spectrum
//! (`terms`, in the order of `mu`), one complex reciprocal per term instead
//! of a 2 × 2 determinant and quotient of jets per block. The removed set R
//! becomes the terms of μ_r … μ_{r+|A|} themselves (β = c_k,
//! δ = p + qμ_k), and on the real axis H(λ) is the rest's sum plus the
//! removed terms' c_k/(μ_k − λ), so one sweep gives both g and the count.
//! A block whose two eigenvalues are within [`RESIDUE_GAP`](crate::beam::fast::secular::RESIDUE_GAP) (relative) of
//! each other would lose the split to the difference's rounding; the whole
//! beam then keeps the block form.
//!
//! # Accuracy
//! The block entries are those of `axial_spectrum.rs` (relative rounding
//! ≲ 10·eps/sin²(φ/2) in the bending eigenvalue, ≈ 1.4e-12 at n_e = 40,
//! j = 1). det B_j loses ~eps·|B_uu B_vv|/|det B_j| near its roots, which
//! moves a root of g by ~eps·μ absolutely; Newton stops at a step
//! ≤ 1e-10·|s|, the stopping rule of `axial_spectrum.rs` (`newton_from`);
//! convergence is quadratic, so the root is then at the rounding floor. In
//! partial fractions each term is rounded once (μ_k and c_k to a few eps:
//! the residue's difference μ_other − μ_k is ≥ 1e-2 of μ_other on a
//! uniform beam), and no 2 × 2 determinant is formed, so the block form's
//! loss near det B_j = 0 is gone; what the sums lose to cancellation near
//! a root is the secular equation's own conditioning, the same in both
//! forms. The tests below and `tests/beam_spring_fast_path.rs` hold both
//! forms to the same tolerances.

use num_complex::Complex64;

use crate::beam::fast::axial_spectrum::{secular_families, AxialBlocks, Sym2};
use crate::beam::fast::continuum_tail::SpringTail;
pub(crate) use crate::beam::fast::jet::{Jet, Modulus, Num};
use crate::beam::fast::secular::{block_spectrum, certified_eigenvalue, Block};
use crate::beam::solve::family::Roots;

/// The eigenvector's Rayleigh quotient a + b must be λ to this (relative):
/// its forms are sums of positive terms rounded to ~1e-13.
const RAYLEIGH_TOL: f64 = 1e-8;

/// One term of the partial-fraction form of the flexibility (module doc,
/// "Partial fractions"): a spring-free eigenvalue μ_k, its residue c_k and
/// σ_k = (−1)^j of its block, with the products the sums take.
#[derive(Debug, Clone, Copy)]
struct Term {
    mu: f64,
    sign: f64,
    /// c_k, σ_k c_k, c_k μ_k, σ_k c_k μ_k.
    c: [f64; 4],
}

/// The secular data of one beam: blocks, springs and the spring-free spectrum.
#[derive(Debug, Default, Clone)]
pub struct SpringScratch {
    pub(crate) blocks: Vec<Block>,
    /// Spring-free eigenvalues with the block they belong to, ascending.
    pub(crate) mu: Vec<(f64, usize)>,
    /// The active ends' (k̃, end index 0 = x = 0, 1 = x = L).
    pub(crate) ends: Vec<(f64, usize)>,
    /// The blocks beyond the last of `blocks` in closed form, when the
    /// blocks are a truncated infinite set (the continuum Timoshenko beam,
    /// `shear_continuum.rs`); `None` on a mesh, whose blocks are all there.
    pub(crate) tail: Option<SpringTail>,
    /// The partial-fraction terms, one per entry of `mu` and in its order,
    /// when every block has N = 0 ([`Self::partial_fractions`]); empty
    /// otherwise, and the sums then run over the blocks.
    terms: Vec<Term>,
}

impl SpringScratch {
    /// Fills `terms` from `blocks` and `mu` when no block has an axial part
    /// (module doc, "Partial fractions"), else empties it; the callers run
    /// it after filling the blocks.
    pub(crate) fn partial_fractions(&mut self) {
        self.terms.clear();
        let zero = |n: &Sym2| n.uu == 0.0 && n.uv == 0.0 && n.vv == 0.0;
        if !self.blocks.iter().all(|b| zero(&b.n)) {
            return;
        }
        for &(mu, j) in &self.mu {
            let b = &self.blocks[j];
            let Some(c) = b.residue(mu) else {
                self.terms.clear();
                return;
            };
            let sc = b.sign * c;
            self.terms.push(Term { mu, sign: b.sign, c: [c, sc, c * mu, sc * mu] });
        }
    }

    /// The flexibility of the ends from every term but those of `removed`
    /// (a run of consecutive term indices), at (p, q): (F₀₀ = F_LL, F₀L) =
    /// (Σ a_k, Σ σ_k a_k) with a_k = c_k/(p + qμ_k), and their derivatives.
    /// With r = p/q, a_k = c_k/(q(r + μ_k)) and
    /// a_k′ = −c_k(p′ + q′μ_k)/(q²(r + μ_k)²): one reciprocal per term.
    fn term_sums<T: Num>(&self, p: Jet<T>, q: Jet<T>, removed: &[usize]) -> [Jet<T>; 2] {
        let (lo, hi) = match removed {
            [] => (0, 0),
            [first, .., last] => (*first, *last + 1),
            [one] => (*one, *one + 1),
        };
        debug_assert_eq!(hi - lo, removed.len());
        let iq = q.v.recip();
        let r = p.v * iq;
        let zero = T::from(0.0);
        // Σ c·inv, Σ σc·inv, Σ c·inv², Σ σc·inv², Σ cμ·inv², Σ σcμ·inv²
        let mut acc = [zero; 6];
        let mut add = |terms: &[Term]| {
            for t in terms {
                let inv = (r + t.mu).recip();
                let inv2 = inv * inv;
                acc[0] = acc[0] + inv * t.c[0];
                acc[1] = acc[1] + inv * t.c[1];
                acc[2] = acc[2] + inv2 * t.c[0];
                acc[3] = acc[3] + inv2 * t.c[1];
                acc[4] = acc[4] + inv2 * t.c[2];
                acc[5] = acc[5] + inv2 * t.c[3];
            }
        };
        add(&self.terms[..lo]);
        add(&self.terms[hi..]);
        let iq2 = iq * iq;
        let sum = |f: T, a: T, b: T| Jet { v: f * iq, d: zero - (p.d * a + q.d * b) * iq2 };
        [sum(acc[0], acc[2], acc[4]), sum(acc[1], acc[3], acc[5])]
    }

    /// The flexibility of the ends (F₀₀, F₀L) from every block or term but
    /// those of `removed`, the tail included, at (p, q), and the removed
    /// ones' (β, δ, σ) into `rem` (α = β/δ, module doc); `None` where the
    /// tail is outside its bound.
    fn rest<T: Num>(
        &self,
        p: Jet<T>,
        q: Jet<T>,
        removed: &[usize],
        rem: &mut [(Jet<T>, Jet<T>, f64); 3],
    ) -> Option<[Jet<T>; 2]> {
        let mut f = if self.terms.is_empty() {
            let mut sums = [Jet::<T>::c(0.0); 2];
            for (j, b) in self.blocks.iter().enumerate() {
                let (adj, det) = b.parts(p, q);
                let beta = adj.scale(1.0 / b.d);
                if let Some(r) = removed.iter().position(|&r| r == j) {
                    rem[r] = (beta, det, b.sign);
                } else {
                    let slot = usize::from(b.sign < 0.0);
                    sums[slot] = sums[slot].add(beta.div(det));
                }
            }
            [sums[0].add(sums[1]), sums[0].sub(sums[1])]
        } else {
            for (slot, &k) in rem.iter_mut().zip(removed) {
                let t = &self.terms[k];
                *slot = (Jet::c(t.c[0]), p.add(q.scale(t.mu)), t.sign);
            }
            self.term_sums(p, q, removed)
        };
        if let Some(tail) = &self.tail {
            let [te, to] = tail.sums(p, q)?;
            f = [f[0].add(te.add(to)), f[1].add(te.sub(to))];
        }
        Some(f)
    }

    /// (w_j)_e: 1 at x = 0, σ_j at x = L.
    fn w(&self, j: usize, e: usize) -> f64 {
        if e == 0 {
            1.0
        } else {
            self.blocks[j].sign
        }
    }

    /// g = Π_{r∈R} δ_r · det H at (p, q) (module doc), with its derivative;
    /// `removed` holds block indices, or term indices with partial fractions.
    fn secular<T: Num>(&self, p: Jet<T>, q: Jet<T>, removed: &[usize]) -> Jet<T> {
        let mut rem: [(Jet<T>, Jet<T>, f64); 3] = [(Jet::c(0.0), Jet::c(0.0), 0.0); 3];
        let Some(f) = self.rest(p, q, removed, &mut rem) else { return Jet::c(f64::NAN) };
        self.determinant(f, &rem[..removed.len()])
    }

    /// g = Π_{r∈R} δ_r · det(X + Σ_r (β_r/δ_r) w_r w_rᵀ) with X = K_s⁻¹ + F
    /// and F = (F₀₀, F₀L) the rest's flexibility (module doc).
    fn determinant<T: Num>(&self, [f00, f0l]: [Jet<T>; 2], rem: &[(Jet<T>, Jet<T>, f64)]) -> Jet<T> {
        // Π over the removed blocks except those in `skip`
        let prod = |skip: &[usize]| {
            rem.iter().enumerate().filter(|(i, _)| !skip.contains(i)).fold(Jet::c(1.0), |acc, (_, r)| acc.mul(r.1))
        };
        if self.ends.len() == 1 {
            let x = Jet::c(1.0 / self.ends[0].0).add(f00);
            let mut g = x.mul(prod(&[]));
            for (i, r) in rem.iter().enumerate() {
                g = g.add(r.0.mul(prod(&[i])));
            }
            return g;
        }
        let x11 = Jet::c(1.0 / self.ends[0].0).add(f00);
        let x22 = Jet::c(1.0 / self.ends[1].0).add(f00);
        let x12 = f0l;
        let mut g = x11.mul(x22).sub(x12.mul(x12)).mul(prod(&[]));
        for (i, r) in rem.iter().enumerate() {
            // wᵀ adj(X) w with w = (1, σ)
            let quad = x22.add(x11).sub(x12.scale(2.0 * r.2));
            g = g.add(r.0.mul(quad).mul(prod(&[i])));
        }
        for i in 0..rem.len() {
            for k in i + 1..rem.len() {
                let dw = rem[k].2 - rem[i].2;
                if dw != 0.0 {
                    g = g.add(rem[i].0.mul(rem[k].0).mul(prod(&[i, k])).scale(dw * dw));
                }
            }
        }
        g
    }

    /// g(λ) of [`Self::secular`] on the real axis (s² = −λ, G = 1, no
    /// damping) with its derivative in λ, and H(λ) (as [`Self::h_real`]).
    /// With partial fractions both come from one sweep: H is the rest's
    /// flexibility plus the removed terms' c/(μ − λ).
    fn real_secular(&self, lambda: f64, removed: &[usize]) -> (Jet<f64>, Option<[f64; 3]>) {
        let (p, q) = (Jet { v: -lambda, d: -1.0 }, Jet::c(1.0));
        if self.terms.is_empty() {
            return (self.secular::<f64>(p, q, removed), self.h_real(lambda));
        }
        let mut rem: [(Jet<f64>, Jet<f64>, f64); 3] = [(Jet::c(0.0), Jet::c(0.0), 0.0); 3];
        let Some(f) = self.rest(p, q, removed, &mut rem) else { return (Jet::c(f64::NAN), None) };
        let rem = &rem[..removed.len()];
        let (mut f00, mut f0l) = (f[0].v, f[1].v);
        for r in rem {
            let a = r.0.v / r.1.v;
            f00 += a;
            f0l += r.2 * a;
        }
        (self.determinant(f, rem), Some(self.h_from(f00, f0l)).filter(|h| h.iter().all(|v| v.is_finite())))
    }

    /// H from the flexibility (F₀₀, F₀L) of every block: K_s⁻¹ + F on the
    /// active ends, [h11, h12, h22] (one end: h11).
    fn h_from(&self, f00: f64, f0l: f64) -> [f64; 3] {
        if self.ends.len() == 1 {
            [1.0 / self.ends[0].0 + f00, 0.0, 0.0]
        } else {
            [1.0 / self.ends[0].0 + f00, f0l, 1.0 / self.ends[1].0 + f00]
        }
    }

    /// H(λ) on the real axis (no pole removed): [h11, h12, h22] (one end: h11).
    fn h_real(&self, lambda: f64) -> Option<[f64; 3]> {
        let mut f = [0.0; 2];
        if self.terms.is_empty() {
            let mut sums = [0.0; 2];
            for b in &self.blocks {
                let s = b.shifted(lambda);
                let a = if b.single { 1.0 / s.vv } else { s.uu / (s.uu * s.vv - s.uv * s.uv) } / b.d;
                sums[usize::from(b.sign < 0.0)] += a;
            }
            f = [sums[0] + sums[1], sums[0] - sums[1]];
        } else {
            for t in &self.terms {
                let inv = 1.0 / (t.mu - lambda);
                f[0] += t.c[0] * inv;
                f[1] += t.c[1] * inv;
            }
        }
        if let Some(tail) = &self.tail {
            let [te, to] = tail.sums::<f64>(Jet::c(-lambda), Jet::c(1.0))?;
            f = [f[0] + (te.v + to.v), f[1] + (te.v - to.v)];
        }
        let h = self.h_from(f[0], f[1]);
        h.iter().all(|v| v.is_finite()).then_some(h)
    }

    /// #{eigenvalues of the spring pencil < λ} = #{μ < λ} − neg(H(λ)) (module
    /// doc); `None` where H is singular or not finite (λ at an eigenvalue or a μ).
    fn count(&self, lambda: f64) -> Option<usize> {
        self.count_from(lambda, self.h_real(lambda)?)
    }

    /// [`Self::count`] with H(λ) = `h` given.
    fn count_from(&self, lambda: f64, h: [f64; 3]) -> Option<usize> {
        let below = self.mu.partition_point(|&(m, _)| m < lambda);
        let neg = if self.ends.len() == 1 {
            if h[0] == 0.0 {
                return None;
            }
            usize::from(h[0] < 0.0)
        } else {
            let det = h[0] * h[2] - h[1] * h[1];
            if det == 0.0 {
                return None;
            }
            if det < 0.0 {
                1
            } else if h[0] + h[2] < 0.0 {
                2
            } else {
                0
            }
        };
        below.checked_sub(neg)
    }

    /// The certified eigenvalue λ_r (r = r0 + 1) and the blocks R removed
    /// for it; `None` where the path declines.
    fn eigenvalue(&self, r0: usize) -> Option<(f64, [usize; 3], usize)> {
        let na = self.ends.len();
        let (a, b) = (self.mu.get(r0)?.0, self.mu.get(r0 + na)?.0);
        let mut removed = [0usize; 3];
        let mut nr = 0;
        if self.terms.is_empty() {
            for &(_, j) in &self.mu[r0..=r0 + na] {
                if !removed[..nr].contains(&j) {
                    removed[nr] = j;
                    nr += 1;
                }
            }
        } else {
            // the terms of μ_r … μ_{r+|A|}, the poles in the bracket
            for k in r0..=r0 + na {
                removed[nr] = k;
                nr += 1;
            }
        }
        // first-order start: μ_r + Σ_e k̃_e φ_e² with φ the M-normalised
        // spring-free eigenvector of μ_r (its end rotations are ±x_v)
        let (mu, j) = self.mu[r0];
        let blk = &self.blocks[j];
        let xv2_over_m = if blk.single {
            1.0 / (blk.d * blk.m.vv)
        } else {
            let s = blk.shifted(mu);
            // eigenvector from the better-scaled row, as `axial_spectrum.rs`
            let r1 = [-s.uv, s.uu];
            let r2 = [s.vv, -s.uv];
            let x = if r1[0].abs() + r1[1].abs() >= r2[0].abs() + r2[1].abs() { r1 } else { r2 };
            let m = blk.m.uu * x[0] * x[0] + 2.0 * blk.m.uv * x[0] * x[1] + blk.m.vv * x[1] * x[1];
            x[1] * x[1] / (blk.d * m)
        };
        let mut x = mu + self.ends.iter().map(|&(k, _)| k).sum::<f64>() * xv2_over_m;
        if !(x > a && x < b) {
            x = 0.5 * (a + b);
        }
        let removed_s = &removed[..nr];
        let lambda = certified_eigenvalue(
            r0,
            (a, b),
            x,
            |x| {
                let (g, h) = self.real_secular(x, removed_s);
                (g, h.and_then(|h| self.count_from(x, h)))
            },
            |x| self.count(x),
        )?;
        Some((lambda, removed, nr))
    }

    /// The flexibility of the ends (F₀₀, F₀L) over every block, the tail
    /// included, at (p, q).
    fn flexibility<T: Num>(&self, p: Jet<T>, q: Jet<T>) -> Option<[Jet<T>; 2]> {
        self.rest(p, q, &[], &mut [(Jet::c(0.0), Jet::c(0.0), 0.0); 3])
    }

    /// (a, b) of the one-term family of the eigenvector of λ (module doc).
    /// With a tail (an infinite set of blocks) the forms come from the
    /// flexibility instead of a sum over the eigenvector's blocks: with
    /// x = T₀(λ)⁻¹Ez, H(λ)z = 0 and T₀ = K − λM, d(T₀⁻¹)/dλ = T₀⁻¹MT₀⁻¹ gives
    /// xᵀM̃x = zᵀF′(λ)z, and the end rotations are Eᵀx = F(λ)z, so the spring
    /// share is a = Σ_e k̃_e (Fz)_e² / zᵀF′z and b = λ − a (no axial force:
    /// the continuum path is taken without one).
    fn one_term(&self, lambda: f64) -> Option<(f64, f64)> {
        if self.tail.is_some() {
            return self.one_term_from_flexibility(lambda);
        }
        let h = self.h_real(lambda)?;
        let z: [f64; 2] = if self.ends.len() == 1 {
            [1.0, 0.0]
        } else if h[0].abs() + h[1].abs() >= h[1].abs() + h[2].abs() {
            [-h[1], h[0]]
        } else {
            [h[2], -h[1]]
        };
        let (mut m, mut k, mut n) = (0.0, 0.0, 0.0);
        let mut rot = [0.0; 2];
        for (j, b) in self.blocks.iter().enumerate() {
            let zeta: f64 = self.ends.iter().enumerate().map(|(i, &(_, e))| self.w(j, e) * z[i]).sum();
            let s = b.shifted(lambda);
            let y = if b.single {
                [0.0, zeta / (b.d * s.vv)]
            } else {
                let det = s.uu * s.vv - s.uv * s.uv;
                let c = zeta / (b.d * det);
                [-c * s.uv, c * s.uu]
            };
            m += b.d * b.m.form(y);
            k += b.d * b.k.form(y);
            n += b.d * b.n.form(y);
            rot[0] += y[1];
            rot[1] += b.sign * y[1];
        }
        let ks: f64 = self.ends.iter().map(|&(kk, e)| kk * rot[e] * rot[e]).sum();
        let (a1, b1) = ((ks + n) / m, k / m);
        let ok = a1.is_finite() && b1.is_finite() && m > 0.0 && (a1 + b1 - lambda).abs() <= RAYLEIGH_TOL * lambda;
        ok.then_some((a1, b1))
    }

    /// The poles of families 1..=n_modes from the filled scratch into
    /// `roots` (every pole when `all`, else the oscillatory pairs); `false`
    /// when the path declines.
    pub(crate) fn family_roots(
        &self,
        c: f64,
        modulus: Modulus,
        n_modes: usize,
        all: bool,
        roots: &mut Vec<Roots>,
    ) -> bool {
        let family = |r0| {
            let (lambda, removed, nr) = self.eigenvalue(r0)?;
            let (a1, b1) = self.one_term(lambda)?;
            Some(((a1, b1, c), (removed, nr)))
        };
        let step = |&(removed, nr): &([usize; 3], usize), s| newton_step(self, c, modulus, &removed[..nr], s);
        secular_families(n_modes, all, modulus, roots, family, step)
    }

    /// [`Self::one_term`] from the flexibility F(λ) and F′(λ).
    fn one_term_from_flexibility(&self, lambda: f64) -> Option<(f64, f64)> {
        let [f00, f0l] = self.flexibility::<f64>(Jet { v: -lambda, d: -1.0 }, Jet::c(1.0))?;
        let (f, df) = ([f00.v, f0l.v], [f00.d, f0l.d]);
        let (x, m) = if self.ends.len() == 1 {
            ([f[0], 0.0], df[0])
        } else {
            let h = [1.0 / self.ends[0].0 + f[0], f[1], 1.0 / self.ends[1].0 + f[0]];
            let z = if h[0].abs() + h[1].abs() >= h[1].abs() + h[2].abs() { [-h[1], h[0]] } else { [h[2], -h[1]] };
            let x = [f[0] * z[0] + f[1] * z[1], f[1] * z[0] + f[0] * z[1]];
            (x, df[0] * (z[0] * z[0] + z[1] * z[1]) + 2.0 * df[1] * z[0] * z[1])
        };
        self.spring_share(lambda, x, m)
    }

    /// (a, λ − a) with a = Σ_e k̃_e x_e² / m (see [`Self::one_term`]).
    fn spring_share(&self, lambda: f64, x: [f64; 2], m: f64) -> Option<(f64, f64)> {
        let ks: f64 = self.ends.iter().enumerate().map(|(i, &(k, _))| k * x[i] * x[i]).sum();
        let a = ks / m;
        (m > 0.0 && a.is_finite() && a >= 0.0 && a < lambda).then_some((a, lambda - a))
    }
}

impl AxialBlocks {
    /// The wavenumber blocks at (t = ẽ², ñ) into `blocks` (j = 0 and n_e
    /// first, then j = 1..n_e − 1) and the whole spring-free spectrum with
    /// each eigenvalue's block into `mu`, ascending; `false` when a 2 × 2
    /// pencil has no real eigenvalues (not positive definite in M).
    pub(crate) fn wavenumber_blocks(
        &self,
        t: f64,
        axial: f64,
        foundation: f64,
        blocks: &mut Vec<Block>,
        mu: &mut Vec<(f64, usize)>,
    ) -> bool {
        let ne = self.elements;
        blocks.clear();
        mu.clear();
        let sign = |j: usize| if j.is_multiple_of(2) { 1.0 } else { -1.0 };
        let zero = Sym2 { uu: 0.0, uv: 0.0, vv: 0.0 };
        for (j, rot) in [(0usize, &self.rotation[0]), (ne, &self.rotation[1])] {
            let (k, m0, m1) = (rot[0], rot[1], rot[2]);
            let m = Sym2 { vv: m0 + t * m1, ..zero };
            let kk = Sym2 { vv: k, ..zero };
            let n = Sym2 { vv: axial * (m1 + t * k) + foundation * (m0 + t * m1), ..zero };
            blocks.push(Block { m, k: kk, n, d: ne as f64, sign: sign(j), single: true });
        }
        for (i, [k, m0, m1]) in self.blocks.iter().enumerate() {
            let j = i + 1;
            let m = m0.plus(t, *m1);
            let n = m1.plus(t, *k).scaled(axial).plus(foundation, m);
            blocks.push(Block { m, k: *k, n, d: 0.5 * ne as f64, sign: sign(j), single: false });
        }
        block_spectrum(blocks, mu)
    }

    /// Fills `scratch` for (t = ẽ², ñ, k̃ at both ends); `false` unless at
    /// least one spring acts and `n_modes + |A|` spring-free eigenvalues exist,
    /// all finite (not necessarily positive: under compression the beam
    /// without its springs may be past buckling while the beam is not; the
    /// count and λ_r > 0 decide).
    fn spring_setup(
        &self,
        t: f64,
        (axial, foundation): (f64, f64),
        spring: [f64; 2],
        n_modes: usize,
        scratch: &mut SpringScratch,
    ) -> bool {
        scratch.tail = None;
        scratch.ends.clear();
        for (e, &k) in spring.iter().enumerate() {
            if k > 0.0 {
                scratch.ends.push((k, e));
            }
        }
        if scratch.ends.is_empty() {
            return false;
        }
        if !self.wavenumber_blocks(t, axial, foundation, &mut scratch.blocks, &mut scratch.mu) {
            return false;
        }
        scratch.partial_fractions();
        let need = n_modes + scratch.ends.len();
        need <= scratch.mu.len() && scratch.mu.iter().all(|&(m, _)| m.is_finite())
    }

    /// The poles of families 1..=n_modes (scaled units) of the beam with
    /// support springs k̃ = `spring` (x = 0, x = L) into `roots`: every pole
    /// when `all`, else the oscillatory pairs only. `false` when the path
    /// declines (module doc): the caller then runs the reference.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn spring_family_roots(
        &self,
        t: f64,
        (axial, foundation): (f64, f64),
        spring: [f64; 2],
        c: f64,
        modulus: Modulus,
        n_modes: usize,
        all: bool,
        scratch: &mut SpringScratch,
        roots: &mut Vec<Roots>,
    ) -> bool {
        if n_modes == 0 || !self.spring_setup(t, (axial, foundation), spring, n_modes, scratch) {
            return false;
        }
        scratch.family_roots(c, modulus, n_modes, all, roots)
    }

    /// The lowest `n_modes` eigenvalues of the undamped relaxed pencil
    /// (K̃ + K̃_N + K̃_spring, M̃) from the secular equation (module doc);
    /// `None` where the path declines.
    pub fn spring_eigenvalues(
        &self,
        t: f64,
        (axial, foundation): (f64, f64),
        spring: [f64; 2],
        n_modes: usize,
    ) -> Option<Vec<f64>> {
        let mut scratch = SpringScratch::default();
        if !self.spring_setup(t, (axial, foundation), spring, n_modes, &mut scratch) {
            return None;
        }
        (0..n_modes).map(|r0| scratch.eigenvalue(r0).map(|e| e.0)).collect()
    }
}

/// The Newton step g/g′ of g(s) (module doc) at `s`; the iteration and its
/// stopping rule are `axial_spectrum.rs`'s ([`secular_families`]).
fn newton_step(scratch: &SpringScratch, c: f64, modulus: Modulus, removed: &[usize], s: Complex64) -> Complex64 {
    let p = Jet { v: s * (s + c), d: 2.0 * s + c };
    let e = scratch.secular::<Complex64>(p, modulus.at(s), removed);
    e.v / e.d
}

#[cfg(test)]
mod tests {
    //! Data: the assembled mesh pencil of `model.rs` with the springs added
    //! on its rotation DOFs (`UnitMesh::pencil`) and `eigen.rs`'s solve of it:
    //! another code path than the secular equation.
    use super::*;
    use crate::beam::fe::model::{PencilParams, UnitMesh};
    use crate::beam::solve::eigen::lowest_eigenpairs;
    use crate::beam::spec::Support;

    /// The partial fractions are the block form's flexibility (module doc,
    /// "Partial fractions"): F₀₀, F₀L and their derivatives agree at complex
    /// (p, q) off the real axis to 1e-12 of |F₀₀| + |F₀L|. Both are sums of
    /// 40 terms, each rounded to a few eps of its own size, and
    /// |F₀₀| + |F₀L| is the size of the largest sum; the block form's
    /// determinant loses ≤ eps·cond(B_j) ≲ 2.2e-16·(2n_e/π)² ≈ 4e-14 at 20
    /// elements (`tests/beam_spring_fast_path.rs`). The scale is not |F₀L|
    /// itself: F₀L is an alternating sum and cancels (by 2e4 at
    /// p = 2 + 5e4i, where a 50-digit evaluation of the blocks put the
    /// partial fractions 4e-12 and the block form 1e-11 of |F₀L| off).
    #[test]
    fn partial_fractions_are_the_block_form() {
        let mesh = UnitMesh::new(20, Support::SimplySupported);
        let blocks = AxialBlocks::new(&mesh).unwrap();
        let mut scratch = SpringScratch::default();
        for (e, spring) in [(0.0, [1.0, 1.0]), (0.1, [1e-2, 0.0]), (0.2, [0.0, 30.0])] {
            assert!(blocks.spring_setup(e * e, (0.0, 0.0), spring, 5, &mut scratch));
            assert_eq!(scratch.terms.len(), scratch.mu.len());
            for (p, q) in
                [(Complex64::new(-50.0, 30.0), 1.0), (Complex64::new(-3e3, -1e2), 1.3), (Complex64::new(2.0, 5e4), 0.9)]
            {
                let (p, q) =
                    (Jet { v: p, d: 2.0 * p }, Jet { v: Complex64::new(q, 0.2), d: Complex64::new(0.1, -0.3) });
                let fast = scratch.flexibility(p, q).unwrap();
                let terms = std::mem::take(&mut scratch.terms);
                let reference = scratch.flexibility(p, q).unwrap();
                scratch.terms = terms;
                let scale =
                    [reference[0].v.norm() + reference[1].v.norm(), reference[0].d.norm() + reference[1].d.norm()];
                for (f, r) in fast.iter().zip(&reference) {
                    for ((a, b), scale) in [(f.v, r.v), (f.d, r.d)].into_iter().zip(scale) {
                        assert!((a - b).norm() <= 1e-12 * scale, "ẽ {e} k {spring:?} p {:?}: {a} vs {b}", p.v);
                    }
                }
            }
        }
        // an axial force keeps the block form
        assert!(blocks.spring_setup(0.01, (5.0, 0.0), [1.0, 1.0], 5, &mut scratch));
        assert!(scratch.terms.is_empty());
    }

    /// The certified secular eigenvalues are the lowest eigenvalues of the
    /// assembled spring pencil: within 3e-12 relative (the direct solve's
    /// Rayleigh-quotient rounding 1e-12 of `modal.rs`'s refinement test, and
    /// the block eigenvalue rounding ≲ 1e-12 at 20 elements, `axial_spectrum.rs`),
    /// one spring or two, soft (k̃ = 1e-2) to stiff (1e3), with and without
    /// an axial force.
    #[test]
    fn secular_eigenvalues_are_the_assembled_pencils() {
        let mesh = UnitMesh::new(20, Support::SimplySupported);
        let blocks = AxialBlocks::new(&mesh).unwrap();
        for (e, spring, axial) in [
            (0.0, [1.0, 1.0], 0.0),
            (0.1, [1e-2, 0.0], 0.0),
            (0.2, [0.0, 30.0], 5.0),
            (0.05, [1e3, 0.3], -3.0),
            (0.15, [7.0, 1e3], 40.0),
        ] {
            let t: f64 = e * e;
            let fast = blocks.spring_eigenvalues(t, (axial, 0.0), spring, 6).unwrap();
            let p = PencilParams { e_tilde: e, point_mass: None, spring, axial, shear: 0.0, gradient: 0.0 };
            let (k, m) = mesh.pencil(&p);
            let direct = lowest_eigenpairs(&k, &m, 6, &mut Vec::new(), &|x| mesh.pencil_stiffness(&p, x)).unwrap();
            for (f, d) in fast.iter().zip(&direct) {
                assert!((f - d.lambda).abs() <= 3e-12 * d.lambda, "ẽ {e} k {spring:?} ñ {axial}: {f} vs {}", d.lambda);
            }
        }
    }
}
