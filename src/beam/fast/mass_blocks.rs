//! The exact fast path of a point mass on a uniform simply supported
//! Euler–Bernoulli mesh with viscous damping, an axial force or internal
//! variables (issue 41): the mass is a rank-1 update of the pencil whose
//! wavenumber blocks `axial_spectrum.rs` gives in closed form, so every pole
//! is a root of one scalar secular function evaluated in O(n_e).
//!
//! # Why it is exact (the derivation)
//! The point mass enters the inertia only (`model.rs`: M̃ + μ̃NNᵀ, N = N(x̃)
//! the interpolation vector of the deflection at x̃), not the damping
//! (D̃ = c̃M̃, the beam's own mass matrix) nor the stiffness. So
//!   T̃(s) = T₀(s) + s²μ̃ N Nᵀ,  T₀(s) = s(s + c̃)M̃ + G(s)K̃ + K̃_N,
//! with T₀ the pencil `axial_spectrum.rs` splits: T₀V = WVB(s), V the
//! wavenumber basis (u_j, v_j), B_j(s) = s(s + c̃)M_j + G(s)K_j + N_j, and
//! VᵀWV = D = diag(d_j) (`spring_spectrum.rs` derives T₀⁻¹ = V(DB)⁻¹Vᵀ from
//! it). With n_j = (u_jᵀN, v_jᵀN) the mass's coordinates in block j, the
//! determinant lemma gives, for s ≠ 0,
//!   det T̃(s) = det T₀(s) · s²μ̃ · h(s),
//!   h(s) = 1/(μ̃s²) + NᵀT₀(s)⁻¹N = 1/(μ̃s²) + Σ_j β_j(s)/δ_j(s),
//! β_j = n_jᵀ adj(B_j) n_j / d_j = (n_u²B_vv − 2n_un_vB_uv + n_v²B_uu)/d_j,
//! δ_j = det B_j (a 1 × 1 block j = 0, n_e: β = n_v²/d_j, δ = B_vv): exact
//! for any damping, internal variables, ẽ and axial force. N has its four
//! nonzeros on the element holding x̃ (nodes a, a + 1; the FE shape functions
//! of `element::shape`), so n_j = (Σ N_w,i sin(jπi/n_e), Σ N_θ,i cos(jπi/n_e))
//! over those two nodes. The sines and cosines are read from a table of
//! sin(πk/n_e), k = 0..2n_e − 1, at k = j·i mod 2n_e: the same rounded
//! numbers wherever the angle recurs, no recurrence error.
//! Newton runs on the pole-free g(s) = Π_{r∈R} δ_r(s) · h(s) with R the
//! blocks whose eigenvalues bracket the mode (below): adj(B_r) is polynomial,
//! so each factor δ_r cancels its own pole, and
//!   g = Π_R δ_r · X + Σ_{r∈R} β_r Π_{R∖r} δ_q,  X = 1/(μ̃s²) + Σ_{j∉R} β_j/δ_j.
//!
//! # Modes (the proof of the order) and poles
//! Physical mode r is the r-th eigenpair of the undamped relaxed pencil
//! (K̃ + K̃_N, M̃ + μ̃NNᵀ) (`modal_result.rs`). On the real axis (s² = −λ,
//! G = 1, c̃ = 0) P(λ) = P₀(λ) − λμ̃NNᵀ, P₀ = K̃ + K̃_N − λM̃, and
//! #{eigenvalues < λ} = neg P(λ) (Sylvester: M̃ + μ̃NNᵀ ≻ 0). Haynsworth's
//! inertia additivity on [[P₀, N], [Nᵀ, 1/(λμ̃)]] (λ > 0) gives
//! In P₀ + In(1/(λμ̃) − NᵀP₀⁻¹N) = In(1/(λμ̃)) + In P, so with the mass-free
//! eigenvalues μ (the whole closed-form spectrum of the blocks)
//!   #{eigenvalues < λ} = #{μ < λ} + [h(λ) > 0],  h(λ) = −1/(λμ̃) + NᵀP₀⁻¹N,
//! where an eigenvalue at which h vanishes or a μ lies is left uncounted
//! (the count returns `None`). A rank-1 increase of the mass lowers every
//! eigenvalue by at most one place (interlacing): μ_{r−1} ≤ λ_r ≤ μ_r
//! (μ₀ = 0), so R is the set of blocks of μ_{r−1} and μ_r. Safeguarded Newton
//! on g(λ) inside the bracket that every count narrows converges to λ_r,
//! accepted only when the count is r − 1 just below it and ≥ r just above it
//! (a relative gap of `spring_spectrum::CERTIFY_GAP`); otherwise the path
//! declines. The path also declines when μ₁ ≤ 0 (the mass-free mesh at or
//! past buckling: the bracket of mode 1 would hold the pole of 1/(λμ̃)).
//! The eigenvector is x = P₀⁻¹N (scaled), y_j = B_j(−λ)⁻¹n_j/d_j in block j,
//! with the forms xᵀAx = Σ_j d_j y_jᵀA_jy_j and Nᵀx = Σ_j n_jᵀy_j; it must
//! satisfy its own Rayleigh quotient (a + b = λ to 1e-8, a guard against a
//! lost vector). From it the one-term family s² + c_x s + a + bG(s) = 0 with
//! m_x = xᵀM̃x + μ̃(Nᵀx)², a = xᵀK̃_Nx/m_x, b = xᵀK̃x/m_x and c_x = c̃·xᵀM̃x/m_x
//! — the starts the coupled reference uses (`coupled.rs`,
//! `family_approximations`: the damping acts on the beam's mass only) — and
//! Newton on g(s) from each complex start, with the reference's acceptance
//! tests (`axial_spectrum::accept_pair`). Only the oscillatory poles are
//! solved: when every pole is asked for and a family has real (relaxation)
//! starts, the path declines, as the other block paths do.
//!
//! # Accuracy
//! The block entries and their rounding are those of `axial_spectrum.rs`
//! (≲ 1.4e-12 relative in the bending eigenvalue at n_e = 40, j = 1). n_j
//! is a sum of two products of table entries and shape values (relative
//! rounding ~eps). Near a root of δ_r the adjugate form loses
//! ~eps·|B_uu B_vv|/|δ_r|, which moves a root of g by ~eps·μ absolutely, as in
//! `spring_spectrum.rs`; Newton stops at a step ≤ 1e-10·|s| with quadratic
//! convergence, so the root is then at that floor. The property test
//! (`tests/beam_mass_blocks.rs`) holds the poles to the coupled reference.

use num_complex::Complex64;

use crate::beam::fast::axial_spectrum::{secular_families, AxialBlocks};
use crate::beam::fast::continuum_tail::MassTail;
use crate::beam::fast::jet::Modulus;
use crate::beam::fast::secular::{certified_eigenvalue, Block};
use crate::beam::fast::spring_spectrum::{Jet, Num};
use crate::beam::fe::element;
use crate::beam::solve::family::Roots;

/// The eigenvector's Rayleigh quotient a + b must be λ to this (relative), as
/// on the spring path: its forms are sums of positive terms rounded to ~1e-13.
const RAYLEIGH_TOL: f64 = 1e-8;

/// The secular data of one beam: blocks, the mass's coordinates n_j and the
/// mass-free spectrum.
#[derive(Debug, Default, Clone)]
pub struct MassScratch {
    pub(crate) blocks: Vec<Block>,
    /// (n_u, n_v) of every block, in the order of `blocks`.
    pub(crate) coords: Vec<[f64; 2]>,
    /// Mass-free eigenvalues with their block, ascending.
    pub(crate) mu: Vec<(f64, usize)>,
    /// The blocks beyond the last of `blocks` in closed form, when the
    /// blocks are a truncated infinite set (the continuum Timoshenko beam,
    /// `shear_continuum.rs`); `None` on a mesh.
    pub(crate) tail: Option<MassTail>,
    /// (sin, cos)(πk/n_e), k = 0..2n_e − 1, for `table_elements`.
    table: Vec<(f64, f64)>,
    table_elements: usize,
    /// μ̃ = m/(ρAL).
    pub(crate) mass: f64,
}

impl MassScratch {
    /// (sin, cos)(jπi/n_e) from the table (module doc).
    fn sin_cos(&self, j: usize, i: usize) -> (f64, f64) {
        self.table[(j * i) % (2 * self.table_elements)]
    }

    /// g = Π_{r∈R} δ_r · h at (p, q, s²) (module doc), with its derivative,
    /// and h itself (from the same terms: the real search counts with it).
    fn secular<T: Num>(&self, p: Jet<T>, q: Jet<T>, s2: Jet<T>, removed: &[usize]) -> (Jet<T>, T) {
        let mut x = Jet::c(1.0).div(s2.scale(self.mass));
        let mut rem: [(Jet<T>, Jet<T>); 2] = [(Jet::c(0.0), Jet::c(0.0)); 2];
        let mut nrem = 0;
        for (j, (b, n)) in self.blocks.iter().zip(&self.coords).enumerate() {
            let (beta, det) = adjugate_form(b, *n, p, q);
            if removed.contains(&j) {
                rem[nrem] = (beta, det);
                nrem += 1;
            } else {
                x = x.add(beta.div(det));
            }
        }
        if let Some(tail) = &self.tail {
            let Some(t) = tail.sum(p, q, &self.coords) else { return (Jet::c(f64::NAN), T::from(f64::NAN)) };
            x = x.add(t);
        }
        match &rem[..nrem] {
            [] => (x, x.v),
            [(b1, d1)] => (x.mul(*d1).add(*b1), x.v + b1.v / d1.v),
            [(b1, d1), (b2, d2)] => {
                (x.mul(d1.mul(*d2)).add(b1.mul(*d2)).add(b2.mul(*d1)), x.v + b1.v / d1.v + b2.v / d2.v)
            }
            _ => unreachable!("at most two blocks bracket a mode"),
        }
    }

    /// h(λ) on the real axis (no pole removed).
    fn h_real(&self, lambda: f64) -> Option<f64> {
        let mut h = -1.0 / (lambda * self.mass);
        for (b, n) in self.blocks.iter().zip(&self.coords) {
            let s = b.shifted(lambda);
            h += if b.single {
                n[1] * n[1] / s.vv
            } else {
                (n[0] * n[0] * s.vv - 2.0 * n[0] * n[1] * s.uv + n[1] * n[1] * s.uu) / (s.uu * s.vv - s.uv * s.uv)
            } / b.d;
        }
        if let Some(tail) = &self.tail {
            h += tail.sum::<f64>(Jet::c(-lambda), Jet::c(1.0), &self.coords)?.v;
        }
        h.is_finite().then_some(h)
    }

    /// #{eigenvalues of the mass pencil < λ} (module doc); `None` where h is
    /// zero or not finite (λ at an eigenvalue or a μ).
    fn count(&self, lambda: f64) -> Option<usize> {
        self.count_with(lambda, self.h_real(lambda)?)
    }

    /// The count at λ from h(λ) already evaluated.
    fn count_with(&self, lambda: f64, h: f64) -> Option<usize> {
        let below = self.mu.partition_point(|&(m, _)| m < lambda);
        (h.is_finite() && h != 0.0).then_some(below + usize::from(h > 0.0))
    }

    /// The certified eigenvalue λ_r (r = r0 + 1) and the blocks R removed
    /// for it; `None` where the path declines.
    fn eigenvalue(&self, r0: usize) -> Option<(f64, [usize; 2], usize)> {
        let (a, b) = (if r0 == 0 { 0.0 } else { self.mu[r0 - 1].0 }, self.mu.get(r0)?.0);
        let mut removed = [0usize; 2];
        let mut nr = 0;
        for &(_, j) in &self.mu[r0.saturating_sub(1)..=r0] {
            if !removed[..nr].contains(&j) {
                removed[nr] = j;
                nr += 1;
            }
        }
        // first-order start: μ_r/(1 + μ̃φ(x̃)²), φ the M-normalised mass-free
        // eigenvector of μ_r
        let (mu, j) = self.mu[r0];
        let (blk, n) = (&self.blocks[j], self.coords[j]);
        let phi2 = if blk.single {
            n[1] * n[1] / (blk.d * blk.m.vv)
        } else {
            let s = blk.shifted(mu);
            let r1 = [-s.uv, s.uu];
            let r2 = [s.vv, -s.uv];
            let y = if r1[0].abs() + r1[1].abs() >= r2[0].abs() + r2[1].abs() { r1 } else { r2 };
            let at = n[0] * y[0] + n[1] * y[1];
            at * at / (blk.d * blk.m.form(y))
        };
        let mut x = mu / (1.0 + self.mass * phi2);
        if !(x > a && x < b) {
            x = 0.5 * (a + b);
        }
        let removed_s = &removed[..nr];
        let lambda = certified_eigenvalue(
            r0,
            (a, b),
            x,
            |x| {
                let m = Jet { v: -x, d: -1.0 };
                let (g, h) = self.secular::<f64>(m, Jet::c(1.0), m, removed_s);
                (g, self.count_with(x, h))
            },
            |x| self.count(x),
        )?;
        Some((lambda, removed, nr))
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
            let (a1, b1, beam_share) = self.one_term(lambda)?;
            Some(((a1, b1, c * beam_share), (removed, nr)))
        };
        let step = |&(removed, nr): &([usize; 2], usize), s| newton_step(self, c, modulus, &removed[..nr], s);
        secular_families(n_modes, all, modulus, roots, family, step)
    }

    /// (a, b, c_x/c̃) of the one-term family of the eigenvector of λ (module doc).
    /// With a tail (the continuum path: no axial force, no damping) the whole
    /// stiffness relaxes, so a = 0 and b = λ exactly, and c_x does not enter.
    fn one_term(&self, lambda: f64) -> Option<(f64, f64, f64)> {
        if self.tail.is_some() {
            return Some((0.0, lambda, 1.0));
        }
        let (mut m, mut k, mut nn, mut at) = (0.0, 0.0, 0.0, 0.0);
        for (b, n) in self.blocks.iter().zip(&self.coords) {
            let s = b.shifted(lambda);
            let y = if b.single {
                [0.0, n[1] / (b.d * s.vv)]
            } else {
                let det = s.uu * s.vv - s.uv * s.uv;
                let c = 1.0 / (b.d * det);
                [c * (s.vv * n[0] - s.uv * n[1]), c * (s.uu * n[1] - s.uv * n[0])]
            };
            m += b.d * b.m.form(y);
            k += b.d * b.k.form(y);
            nn += b.d * b.n.form(y);
            at += n[0] * y[0] + n[1] * y[1];
        }
        let mx = m + self.mass * at * at;
        let (a1, b1) = (nn / mx, k / mx);
        let ok = a1.is_finite() && b1.is_finite() && m > 0.0 && (a1 + b1 - lambda).abs() <= RAYLEIGH_TOL * lambda;
        ok.then_some((a1, b1, m / mx))
    }
}

/// (β, δ) of block `b` at (p, q) for the mass coordinates `n` (module doc).
fn adjugate_form<T: Num>(b: &Block, n: [f64; 2], p: Jet<T>, q: Jet<T>) -> (Jet<T>, Jet<T>) {
    let e = |m: f64, k: f64, nn: f64| p.scale(m).add(q.scale(k)).add(Jet::c(nn));
    let vv = e(b.m.vv, b.k.vv, b.n.vv);
    if b.single {
        return (Jet::c(n[1] * n[1] / b.d), vv);
    }
    let uu = e(b.m.uu, b.k.uu, b.n.uu);
    let uv = e(b.m.uv, b.k.uv, b.n.uv);
    let beta = vv.scale(n[0] * n[0]).sub(uv.scale(2.0 * n[0] * n[1])).add(uu.scale(n[1] * n[1])).scale(1.0 / b.d);
    (beta, uu.mul(vv).sub(uv.mul(uv)))
}

impl AxialBlocks {
    /// Fills `scratch` for (t = ẽ², ñ, μ̃, x̃); `false` unless μ̃ > 0, x̃ ∈ [0, 1],
    /// `n_modes` mass-free eigenvalues exist, all finite, and the lowest is
    /// positive (module doc).
    pub(crate) fn mass_setup(
        &self,
        t: f64,
        (axial, foundation): (f64, f64),
        mass: f64,
        x: f64,
        n_modes: usize,
        scratch: &mut MassScratch,
    ) -> bool {
        scratch.tail = None;
        if !(mass > 0.0 && mass.is_finite() && (0.0..=1.0).contains(&x)) {
            return false;
        }
        if !self.wavenumber_blocks(t, axial, foundation, &mut scratch.blocks, &mut scratch.mu) {
            return false;
        }
        if n_modes > scratch.mu.len() || !scratch.mu.iter().all(|&(m, _)| m.is_finite()) || !(scratch.mu[0].0 > 0.0) {
            return false;
        }
        let ne = self.elements;
        if scratch.table_elements != ne {
            let pi = std::f64::consts::PI;
            scratch.table = (0..2 * ne).map(|k| (pi * k as f64 / ne as f64).sin_cos()).collect();
            scratch.table_elements = ne;
        }
        scratch.mass = mass;
        // the element holding x̃ and N there, as `UnitMesh::shape_vector` forms them
        let h = 1.0 / ne as f64;
        let e = ((x * ne as f64).floor() as usize).min(ne - 1);
        let shape = element::shape(h, x - e as f64 / ne as f64);
        scratch.coords.clear();
        for idx in 0..scratch.blocks.len() {
            // `wavenumber_blocks`'s order: j = 0, n_e, then 1..n_e − 1
            let j = match idx {
                0 => 0,
                1 => ne,
                i => i - 1,
            };
            let (sa, ca) = scratch.sin_cos(j, e);
            let (sb, cb) = scratch.sin_cos(j, e + 1);
            let v = shape[1] * ca + shape[3] * cb;
            let u = if scratch.blocks[idx].single { 0.0 } else { shape[0] * sa + shape[2] * sb };
            scratch.coords.push([u, v]);
        }
        true
    }

    /// The poles of families 1..=n_modes (scaled units) of the beam with a
    /// point mass μ̃ at x̃ into `roots`: every pole when `all`, else the
    /// oscillatory pairs only. `false` when the path declines (module doc):
    /// the caller then runs the reference.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn mass_family_roots(
        &self,
        t: f64,
        (axial, foundation): (f64, f64),
        (mass, x): (f64, f64),
        c: f64,
        modulus: Modulus,
        n_modes: usize,
        all: bool,
        scratch: &mut MassScratch,
        roots: &mut Vec<Roots>,
    ) -> bool {
        if n_modes == 0 || !self.mass_setup(t, (axial, foundation), mass, x, n_modes, scratch) {
            return false;
        }
        scratch.family_roots(c, modulus, n_modes, all, roots)
    }

    /// The lowest `n_modes` eigenvalues of the undamped relaxed pencil
    /// (K̃ + K̃_N, M̃ + μ̃NNᵀ) from the secular equation (module doc); `None`
    /// where the path declines.
    pub fn mass_eigenvalues(
        &self,
        t: f64,
        (axial, foundation): (f64, f64),
        (mass, x): (f64, f64),
        n_modes: usize,
    ) -> Option<Vec<f64>> {
        let mut scratch = MassScratch::default();
        if !self.mass_setup(t, (axial, foundation), mass, x, n_modes, &mut scratch) {
            return None;
        }
        (0..n_modes).map(|r0| scratch.eigenvalue(r0).map(|e| e.0)).collect()
    }
}

/// The Newton step g/g′ of g(s) (module doc) at `s`; the iteration and its
/// stopping rule are `axial_spectrum.rs`'s ([`secular_families`]).
fn newton_step(scratch: &MassScratch, c: f64, modulus: Modulus, removed: &[usize], s: Complex64) -> Complex64 {
    let p = Jet { v: s * (s + c), d: 2.0 * s + c };
    let s2 = Jet { v: s * s, d: 2.0 * s };
    let (e, _) = scratch.secular::<Complex64>(p, modulus.at(s), s2, removed);
    e.v / e.d
}

#[cfg(test)]
mod tests {
    //! Data: the assembled mesh pencil of `model.rs` with the point mass added
    //! to M̃ (`UnitMesh::pencil`) and `eigen.rs`'s solve of it: another code
    //! path than the secular equation.
    use super::*;
    use crate::beam::fe::model::{PencilParams, UnitMesh};
    use crate::beam::solve::eigen::lowest_eigenpairs;
    use crate::beam::spec::Support;

    /// The certified secular eigenvalues are the lowest eigenvalues of the
    /// assembled mass pencil within 3e-12 relative (the tolerance and its
    /// reasons as in `spring_spectrum.rs`'s test: the direct solve's
    /// Rayleigh-quotient rounding and the block eigenvalues' rounding), for
    /// light to heavy masses, at an interior point, on a node and next to a
    /// support, with and without an axial force, on odd and even meshes.
    #[test]
    fn secular_eigenvalues_are_the_assembled_pencils() {
        for ne in [20, 15] {
            let mesh = UnitMesh::new(ne, Support::SimplySupported);
            let blocks = AxialBlocks::new(&mesh).unwrap();
            for (e, mass, x, axial) in [
                (0.0, 0.3, 0.37, 0.0),
                (0.1, 1e-3, 0.5, 0.0),
                (0.2, 0.05, 0.2, 5.0),
                (0.05, 2.0, 0.031, -3.0),
                (0.15, 0.7, 0.9, 40.0),
            ] {
                let t: f64 = e * e;
                let fast = blocks.mass_eigenvalues(t, (axial, 0.0), (mass, x), 6).unwrap();
                let p = PencilParams {
                    e_tilde: e,
                    point_mass: Some((mass, x)),
                    spring: [0.0; 2],
                    axial,
                    shear: 0.0,
                    gradient: 0.0,
                };
                let (k, m) = mesh.pencil(&p);
                let direct = lowest_eigenpairs(&k, &m, 6, &mut Vec::new(), &|v| mesh.pencil_stiffness(&p, v)).unwrap();
                for (f, d) in fast.iter().zip(&direct) {
                    assert!(
                        (f - d.lambda).abs() <= 3e-12 * d.lambda,
                        "n_e {ne} ẽ {e} μ̃ {mass} x̃ {x} ñ {axial}: {f} vs {}",
                        d.lambda
                    );
                }
            }
        }
    }
}
