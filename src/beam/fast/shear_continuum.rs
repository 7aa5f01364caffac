//! The uniform simply supported Timoshenko beam in closed form (issue 41):
//! with an axial force, viscous damping, a Winkler foundation or any of
//! them together, its poles are those of one
//! 2 × 2 pencil per wavenumber, so a pole costs a scalar Newton iteration
//! instead of a nonlinear Rayleigh-quotient iteration on the 5n_e − 3 DOFs of
//! the mesh (`coupled.rs`).
//!
//! # The pencil per wavenumber (the derivation)
//! The fields of the bending–shear split (`element.rs`: w = w_b + w_s,
//! θ = w_b′, γ = w_s′) on the unit span, with w_b = B sin kx and w_s = S sin kx,
//! k = jπ (j ≥ 1), meet every condition of the simply supported beam: w, w_b,
//! w_s and the curvature χ = w_b″ vanish at both ends. Over [0, 1] the sines
//! and cosines of one k are orthogonal to those of every other and each
//! integrates to ½ when squared, so each integral of `element.rs`'s
//! `TimoshenkoElement` is ½ times (u = (B, S), W = B + S):
//! ∫θ′² = k⁴B², ∫γ² = k²S², ∫w² = W², ∫w′² = k²W², ∫θ² = k²B², ∫w″² = k⁴W².
//! The model's matrices (`model.rs`, `ScaledModel::new`) combine them as
//! M̃ = (∫w² + r̃²∫θ²) + ẽ²(∫w′² + r̃²∫θ′²), M̃_b = ∫w² + ẽ²∫w′²,
//! K̃ = ∫θ′² + g̃∫γ², K̃_N = ñ(∫w′² + ẽ²∫w″²), and the foundation's
//! k̃_f M̃_b (`scaling.rs`: elastic, not relaxed); with a = 1 + ẽ²k² and the ½
//! dropped (it multiplies the whole pencil):
//!   T_k(s) = [[P + R + Bk, P], [P, P + Sh]],
//!   P = a(s² + c̃s + N), N = ñk² + k̃_f, R = a r̃²k²s², Bk = G(s)k⁴, Sh = G(s)g̃k²,
//!   det T_k(s) = P(R + Bk + Sh) + Sh(R + Bk).
//! As g̃ → ∞ the root condition tends to P + R + Bk = 0, the Rayleigh beam.
//!
//! j = 0 adds one more field: θ constant, w_b = θx, w_s = −θx, so w ≡ 0 (the
//! mesh's θ, γ block at zero wavenumber, `shear_blocks.rs`). Only ∫θ² = 1 and
//! ∫γ² = 1 survive: r̃²s² + G(s)g̃ = 0, the shear mode ω² = κGA/ρI, which no
//! damping or foundation (they act on w) and no axial force (on w′, w″) reaches.
//!
//! On s² = −λ, G = 1, c̃ = 0, det T_k is the quadratic Aλ² − Bλ + C with
//!   A = a²r̃²k², B = a(k⁴ + g̃k²) + a²Nr̃²k² + ag̃r̃²k⁴, C = aN(k⁴ + g̃k²) + g̃k⁶,
//! whose two roots are the bending and the shear branch of k. The families
//! are numbered by these eigenvalues over all k, as the mesh numbers its
//! eigenpairs.
//!
//! # Support springs: a rank ≤ 2 update over the infinite block set
//! A rotational spring at an end acts on θ = w_b′ there (`model.rs`: the
//! rotation DOF the support leaves free; elastic, not relaxed). In the
//! coordinates (u, v) = (S, kB) of wavenumber k the end rotations are v at
//! x = 0 and σ_j v at x = 1 (σ_j = (−1)^j), and θ₀ at both ends for j = 0.
//! The quadratic form of the beam is Σ_j ½ u_jᵀ B_j u_j + θ₀²(r̃²s² + Gg̃), so
//! the springs are exactly the secular problem of `spring_spectrum.rs` with
//! d_j = ½ (d₀ = 1) and, without damping or axial force (p = s², q = G),
//!   B_j = pM_j + qK_j,  M_j = a[[1, 1/k], [1/k, (1 + r̃²k²)/k²]],  K_j = diag(g̃k², k²),
//! one block per wavenumber, infinitely many. The path keeps the blocks
//! j = 0..J ([`spring_family_roots`]: J = 4(n + |A|) + 4) and sums the rest,
//! α(z) = [B⁻¹]_vv/d = 2(pa + qg̃z)/D(z), z = k², a = 1 + ẽ²z,
//!   D(z) = D₂z² + D₁z + D₀,  D₂ = (pẽ² + qg̃)(pr̃²ẽ² + q),
//!   D₁ = 2p²r̃²ẽ² + pq + pqg̃(ẽ² + r̃²),  D₀ = p²r̃² + pqg̃,
//! from its Laurent series at z = ∞: with w = 1/z, α = Σ_{i≥0} e_i w^{i+1},
//! e₀ = N₁/D₂, e₁ = (N₀ − D₁e₀)/D₂, e_i = −(D₁e_{i−1} + D₀e_{i−2})/D₂
//! (N₁ = 2(pẽ² + qg̃), N₀ = 2p), so that
//!   Σ_{j>J, σ_j = ±1} α(j²π²) = Σ_i e_i π^{−2(i+1)} Σ_{j>J, σ_j = ±1} j^{−2(i+1)},
//! the last sums fixed numbers per J ([`tail_consts`]). The series converges
//! where every root of D lies inside |z| < (J + 1)²π²; each evaluation bounds
//! them (Fujiwara's bound) and refuses beyond 1/[`TAIL_RATIO`] of that, so the
//! terms fall by ≥ 16 each and [`TAIL_TERMS`] of them leave < 16⁻¹³ of the
//! first. D₂ → 0 (λẽ² → g̃ or λẽ²r̃² → 1 on the real axis) is where the
//! nonlocal Timoshenko continuum's branches accumulate (the shear branch at
//! g̃/ẽ², the bending one at 1/(ẽ²r̃²)): there the roots leave every bound and
//! the path declines, as it must (the mesh has no such point).
//!
//! The spring-free spectrum of the kept blocks numbers the modes
//! (`spring_spectrum.rs`: #{eigenvalues < λ} = #{μ < λ} − neg(H(λ))); it is
//! complete below the bending eigenvalue of J + 1, since the bending branch
//! grows with k (checked on the kept blocks) and the shear branch of a
//! wavenumber lies above its bending one. The eigenvector's one-term forms
//! come from the flexibility F(λ) and F′(λ) (`SpringScratch::one_term`),
//! tail included.
//!
//! # A point mass: a rank-1 update, summed in closed form
//! The mass μ̃ at x̃ adds s²μ̃w(x̃)² (`model.rs`: on the deflection, no Eringen
//! operator, no damping), and w(x̃) = (S + v/k) sin kx̃, so in the same blocks
//! the secular problem of `mass_blocks.rs` holds with n_j = sin(kx̃)·(1, 1/k)
//! (0 for j = 0: w ≡ 0 there). Its terms are
//!   β_j/δ_j = 2 sin²(kx̃)·N(z)/D(z),  N(z) = (r̃²p + qg̃) + (ẽ²r̃²p + q)z,
//! with the D of the springs; they fall only like 1/k² (the shear field's
//! response to a point force), too slowly for the Laurent tail at x̃-dependent
//! weights. But N/D = A₁/(z − z₁) + A₂/(z − z₂) over the two roots of D, and
//! Σ_{j≥1} sin²(jπx̃)/(j²π² − ζ) = (cos(b(1 − 2x̃)) − cos b)/(4b sin b), b = √ζ
//! (from Σ_{j≥1} cos(jθ)/(j² − a²) = 1/2a² − π cos(a(π − θ))/(2a sin aπ),
//! 0 ≤ θ ≤ 2π), so the sum over all j is closed, and the tail is it less the
//! kept blocks' terms ([`MassTail::sum`]; the derivative by the chain rule
//! through z_i(s)). The path declines where D has a double root or b is near
//! 0 or its cosines would overflow. J needs only to hold the mass-free
//! eigenvalues that bracket the modes, and is doubled until they are below
//! the bending eigenvalue of J + 1. The whole stiffness relaxes and nothing
//! else enters (no axial force, no damping on this path), so each mode's
//! one-term family is s² + λG(s) = 0 with λ its certified eigenvalue.
//!
//! The mesh is not the reference here: its shear field is C¹ (γ a nodal DOF),
//! the point force makes γ jump, and the mesh converges at O(h) to O(h²),
//! unevenly. `tests/beam_shear_mass_ode.rs` checks the path against the
//! beam's boundary value problem solved by transfer matrices instead.
//!
//! # What it is exact to
//! This is the continuum limit of the model's mesh, not the mesh: the two
//! differ by the mesh's discretisation error, O(h⁶) in λ asymptotically (the
//! cubic shear field, `element.rs`), far below the Euler–Bernoulli mesh's
//! O(h⁴) on the same number of elements. `tests/beam_shear_continuum.rs`
//! bounds the difference on random beams by the Richardson estimate of the
//! mesh's error; `benches/README.md` records its size. The solver takes the
//! path only on meshes fine enough for that argument ([`APPLIES_UP_TO`]).

use std::f64::consts::PI;

use num_complex::Complex64;

use crate::beam::fast::axial_spectrum::{oscillatory_pairs, Sym2};
#[cfg(doc)]
use crate::beam::fast::continuum_tail::TAIL_TERMS;
use crate::beam::fast::continuum_tail::{tail_consts, MassTail, SpringTail, TailPencil, MAX_BLOCKS, TAIL_RATIO};
use crate::beam::fast::jet::{relaxation, Modulus};
use crate::beam::fast::mass_blocks::MassScratch;
use crate::beam::fast::secular::{block_spectrum, Block};
use crate::beam::fast::spring_spectrum::{Jet, SpringScratch};
use crate::beam::solve::family::{family_roots_into, Roots};

/// The path applies to modes n ≤ n_e / [`APPLIES_UP_TO`] on meshes of at
/// least [`MIN_ELEMENTS`] elements: there kh = nπ/n_e ≤ π/4, where the mesh
/// resolves the mode and its error is in the range the Richardson check of
/// `tests/beam_shear_continuum.rs` measures (the mesh's default is 20
/// elements, and a diagnosis fits 5–6 modes).
pub const APPLIES_UP_TO: usize = 4;
/// See [`APPLIES_UP_TO`].
pub const MIN_ELEMENTS: usize = 20;

/// The scalars of the continuum pencil: ẽ², g̃, r̃², ñ (`model.rs`) and
/// the foundation k̃_f (`scaling.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuumShear {
    pub e2: f64,
    pub shear: f64,
    pub r2: f64,
    pub axial: f64,
    pub foundation: f64,
}

/// One family: its wavenumber (0 for the shear mode) and the one-term forms (a = elastic, b = relaxing share,
/// damping share) of its eigenvector.
#[derive(Debug, Clone, Copy)]
struct Family {
    k: f64,
    a: f64,
    b: f64,
    damping_share: f64,
}

impl ContinuumShear {
    /// N = ñk² + k̃_f at wavenumber k (k2 = k²): the unrelaxed elastic term of P (module doc).
    fn elastic(&self, k2: f64) -> f64 {
        self.axial * k2 + self.foundation
    }

    /// The bending and shear eigenvalues of wavenumber k (module doc), or
    /// `None` when they are not real and positive (buckled or not finite).
    fn branches(&self, k: f64) -> Option<[f64; 2]> {
        let (k2, k4) = (k * k, k * k * k * k);
        let a = 1.0 + self.e2 * k2;
        let qa = a * a * self.r2 * k2;
        let n = self.elastic(k2);
        let qb = a * (k4 + self.shear * k2) + a * a * n * self.r2 * k2 + a * self.shear * self.r2 * k4;
        let qc = a * n * (k4 + self.shear * k2) + self.shear * k4 * k2;
        let disc = qb * qb - 4.0 * qa * qc;
        if !(disc >= 0.0 && qb > 0.0 && qc > 0.0 && qa > 0.0) {
            return None;
        }
        let root = qb + disc.sqrt();
        // the smaller root as 2C/(B + √D): no cancellation
        let pair = [2.0 * qc / root, root / (2.0 * qa)];
        pair.iter().all(|l| l.is_finite() && *l > 0.0).then_some(pair)
    }

    /// The family of eigenvalue `lambda` of wavenumber k: the eigenvector
    /// u = (P + Sh, −P) from the second row of T_k at G = 1, c̃ = 0, and its forms.
    fn family(&self, k: f64, lambda: f64) -> Option<Family> {
        if k == 0.0 {
            return Some(Family { k, a: 0.0, b: lambda, damping_share: 0.0 });
        }
        let (k2, k4) = (k * k, k * k * k * k);
        let a = 1.0 + self.e2 * k2;
        let p = a * (self.elastic(k2) - lambda);
        let (ub, us) = (p + self.shear * k2, -p);
        let w = ub + us;
        let m = a * (w * w + self.r2 * k2 * ub * ub);
        let mb = a * w * w;
        let kr = k4 * ub * ub + self.shear * k2 * us * us;
        let kn = self.elastic(k2) * a * w * w;
        let (fa, fb) = (kn / m, kr / m);
        // the forms reproduce λ (a Rayleigh quotient at an eigenvector)
        let ok = m > 0.0 && fa.is_finite() && fb.is_finite() && (fa + fb - lambda).abs() <= 1e-9 * lambda;
        ok.then_some(Family { k, a: fa, b: fb, damping_share: mb / m })
    }

    /// The families 1..=n_modes in the order of their eigenvalues; `None`
    /// when a branch is not positive or the ordering is not certain (the
    /// bending branch must grow with k up to a wavenumber whose eigenvalue
    /// exceeds the n-th one).
    fn families(&self, n_modes: usize) -> Option<Vec<Family>> {
        let mut all = vec![(self.shear / self.r2, 0.0)];
        let mut last_bending = 0.0;
        let mut j = 1;
        loop {
            let k = j as f64 * std::f64::consts::PI;
            let [bend, sh] = self.branches(k)?;
            if bend <= last_bending {
                return None;
            }
            last_bending = bend;
            all.push((bend, k));
            all.push((sh, k));
            if j >= n_modes {
                let mut sorted: Vec<f64> = all.iter().map(|x| x.0).collect();
                sorted.sort_by(f64::total_cmp);
                // every later wavenumber's bending eigenvalue exceeds `bend`, and
                // its shear eigenvalue its bending one
                if sorted[n_modes - 1] < bend {
                    break;
                }
            }
            if j > 4 * n_modes + 8 {
                return None;
            }
            j += 1;
        }
        all.sort_by(|x, y| x.0.total_cmp(&y.0));
        all.iter().take(n_modes).map(|&(lambda, k)| self.family(k, lambda)).collect()
    }

    /// det T_k(s)/d det T_k/ds (the Newton step), with G(s) from `ivs`.
    fn newton_step(&self, k: f64, s: Complex64, c: f64, ivs: &[(f64, f64)]) -> Complex64 {
        let Jet { v: g, d: dg } = relaxation(ivs, s);
        if k == 0.0 {
            let f = s * s * self.r2 + g * self.shear;
            let df = 2.0 * s * self.r2 + dg * self.shear;
            return f / df;
        }
        let (k2, k4) = (k * k, k * k * k * k);
        let a = 1.0 + self.e2 * k2;
        let p = a * (s * s + c * s + self.elastic(k2));
        let dp = a * (2.0 * s + c);
        let r = a * self.r2 * k2 * s * s;
        let dr = 2.0 * a * self.r2 * k2 * s;
        let (b, db) = (g * k4, dg * k4);
        let (sh, dsh) = (g * self.shear * k2, dg * self.shear * k2);
        let f = p * (r + b + sh) + sh * (r + b);
        let df = dp * (r + b + sh) + p * (dr + db + dsh) + dsh * (r + b) + sh * (dr + db);
        f / df
    }
}

/// The poles of families 1..=n_modes (scaled units) of the continuum pencil
/// `p` with damping c̃ and internal variables `ivs`, into `roots`: the
/// oscillatory pairs; with `all`, the path declines when a family has a real
/// start (its real poles are left to the reference). Family r starts from the
/// one-term roots of its eigenvector's forms, as the mesh paths do
/// (`shear_blocks::family_roots`), and Newton's iteration on det T_k keeps
/// the reference's acceptance tests (`axial_spectrum::accept_pair`). `false`
/// when the path declines: the caller then runs the reference.
pub fn family_roots(
    p: &ContinuumShear,
    c: f64,
    ivs: &[(f64, f64)],
    n_modes: usize,
    all: bool,
    roots: &mut Vec<Roots>,
) -> bool {
    if n_modes == 0 {
        return false;
    }
    let Some(families) = p.families(n_modes) else { return false };
    roots.resize(n_modes, Roots::default());
    let mut found = [Complex64::new(0.0, 0.0); 64];
    let mut nfound = 0;
    let mut starts = Roots::default();
    for (f, out) in families.iter().zip(roots.iter_mut()) {
        let damping = if f.k == 0.0 { 0.0 } else { c * f.damping_share };
        if family_roots_into(f.a, f.b, damping, ivs, &mut starts).is_err() {
            return false;
        }
        if all && starts.iter().any(|s| s.im == 0.0) {
            return false;
        }
        let step = |s| p.newton_step(f.k, s, c, ivs);
        let Some(fam) = oscillatory_pairs(&starts, step, &mut found, &mut nfound) else { return false };
        *out = fam;
    }
    true
}

/// The poles of families 1..=n_modes (scaled units) of the continuum beam
/// `p` without damping or axial force, with support springs k̃ = `spring`
/// (x = 0, x = 1; 0 = none) and internal variables `ivs`, into `roots`
/// (module doc: the secular problem of `spring_spectrum.rs` over the
/// continuum's blocks and their tail); `false` when the path declines.
pub fn spring_family_roots(
    p: &ContinuumShear,
    spring: [f64; 2],
    ivs: &[(f64, f64)],
    n_modes: usize,
    all: bool,
    scratch: &mut SpringScratch,
    roots: &mut Vec<Roots>,
) -> bool {
    if n_modes == 0 || p.axial != 0.0 || p.foundation != 0.0 {
        return false;
    }
    scratch.ends.clear();
    scratch.ends.extend(spring.iter().enumerate().filter(|(_, &k)| k > 0.0).map(|(e, &k)| (k, e)));
    if scratch.ends.is_empty() {
        return false;
    }
    let need = n_modes + scratch.ends.len();
    // J: at least 4(n + |A|) + 4, and enough that the roots of D stay inside
    // the tail's bound a little above the highest eigenvalue the modes can
    // reach (the bracket's top μ), at G = 1 and at the unrelaxed G = 1 + ΣΔ
    // (each evaluation checks its own bound: this only sizes J)
    let mut j_max = 4 * need + 4;
    let Some(mut cutoff) = continuum_blocks(p, j_max, &mut scratch.blocks, &mut scratch.mu) else { return false };
    if scratch.mu.len() < need {
        return false;
    }
    let top = 1.2 * scratch.mu[need - 1].0;
    let unrelaxed = 1.0 + ivs.iter().map(|iv| iv.0).sum::<f64>();
    let pencil = TailPencil { t: p.e2, g: p.shear, r2: p.r2 };
    let tail = |j_max: usize| SpringTail {
        pencil,
        consts: tail_consts(j_max),
        z_limit: ((j_max + 1) as f64 * PI).powi(2) / TAIL_RATIO,
    };
    let reach =
        [1.0, unrelaxed].map(|q| pencil.root_bound::<f64>(Jet::c(-top), Jet::c(q))).into_iter().fold(0.0, f64::max);
    let wanted = ((TAIL_RATIO * reach).sqrt() / PI).ceil() as usize;
    if wanted > j_max + 1 {
        if wanted > MAX_BLOCKS + 1 {
            return false;
        }
        j_max = wanted - 1;
        let Some(c) = continuum_blocks(p, j_max, &mut scratch.blocks, &mut scratch.mu) else { return false };
        cutoff = c;
    }
    // every eigenvalue of the omitted blocks lies above `cutoff` (module doc)
    if scratch.mu.len() < need || scratch.mu[need - 1].0 >= cutoff {
        return false;
    }
    scratch.tail = Some(tail(j_max));
    scratch.partial_fractions();
    scratch.family_roots(0.0, Modulus::relaxed(ivs), n_modes, all, roots)
}

/// The poles of families 1..=n_modes (scaled units) of the continuum beam
/// `p` without damping or axial force, with a point mass μ̃ at x̃ and
/// internal variables `ivs`, into `roots` (module doc: the secular problem of
/// `mass_blocks.rs` over the continuum's blocks and their tail); `false`
/// when the path declines.
pub fn mass_family_roots(
    p: &ContinuumShear,
    (mass, x): (f64, f64),
    ivs: &[(f64, f64)],
    n_modes: usize,
    all: bool,
    scratch: &mut MassScratch,
    roots: &mut Vec<Roots>,
) -> bool {
    if n_modes == 0
        || p.axial != 0.0
        || p.foundation != 0.0
        || !(mass > 0.0 && mass.is_finite() && (0.0..=1.0).contains(&x))
    {
        return false;
    }
    // the kept blocks need only hold the mass-free eigenvalues that bracket
    // the modes (the tail is exact for any J): double J until they do
    let mut j_max = n_modes + 2;
    loop {
        let Some(cutoff) = continuum_blocks(p, j_max, &mut scratch.blocks, &mut scratch.mu) else { return false };
        if scratch.mu.len() >= n_modes && scratch.mu[n_modes - 1].0 < cutoff {
            break;
        }
        j_max *= 2;
        if j_max > MAX_BLOCKS {
            return false;
        }
    }
    if !(scratch.mu[0].0 > 0.0) {
        return false;
    }
    scratch.coords.clear();
    scratch.coords.push([0.0, 0.0]);
    for j in 1..=j_max {
        let k = j as f64 * PI;
        let sin = (k * x).sin();
        scratch.coords.push([sin, sin / k]);
    }
    scratch.mass = mass;
    let pencil = TailPencil { t: p.e2, g: p.shear, r2: p.r2 };
    scratch.tail = Some(MassTail { pencil, c: 1.0 - 2.0 * x, j_max });
    scratch.family_roots(0.0, Modulus::relaxed(ivs), n_modes, all, roots)
}

/// The blocks j = 0..=J of `p` (module doc) and their spectrum into
/// `scratch`; the bending eigenvalue of J + 1, below which the spectrum is
/// complete, or `None` when a branch is not positive, the bending branch does
/// not grow with k up to J + 1, or a block pencil is not definite.
fn continuum_blocks(
    p: &ContinuumShear,
    j_max: usize,
    blocks: &mut Vec<Block>,
    mu: &mut Vec<(f64, usize)>,
) -> Option<f64> {
    let zero = Sym2 { uu: 0.0, uv: 0.0, vv: 0.0 };
    blocks.clear();
    blocks.push(Block {
        m: Sym2 { vv: p.r2, ..zero },
        k: Sym2 { vv: p.shear, ..zero },
        n: zero,
        d: 1.0,
        sign: 1.0,
        single: true,
    });
    let mut last_bending = 0.0;
    for j in 1..=j_max + 1 {
        let k = j as f64 * PI;
        let [bend, _] = p.branches(k)?;
        if bend <= last_bending {
            return None;
        }
        last_bending = bend;
        if j > j_max {
            break;
        }
        let (z, a) = (k * k, 1.0 + p.e2 * k * k);
        blocks.push(Block {
            m: Sym2 { uu: a, uv: a / k, vv: a * (1.0 + p.r2 * z) / z },
            k: Sym2 { uu: p.shear * z, uv: 0.0, vv: z },
            n: zero,
            d: 0.5,
            sign: if j % 2 == 0 { 1.0 } else { -1.0 },
            single: false,
        });
    }
    block_spectrum(blocks, mu).then_some(last_bending)
}

#[cfg(test)]
mod tests {
    //! Data: the closed forms themselves (the Euler–Bernoulli limit) and the
    //! pencil's own eigenvalue equation; the comparison with the mesh is in
    //! `tests/beam_shear_continuum.rs`.
    use super::*;

    /// As g̃ → ∞ without rotary inertia the bending branch is the nonlocal
    /// Euler–Bernoulli one, k⁴/(1 + ẽ²k²) + ñk².
    #[test]
    fn the_bending_branch_tends_to_euler_bernoulli() {
        let p = ContinuumShear { e2: 0.015, shear: 1e12, r2: 1e-12, axial: 3.0, foundation: 0.0 };
        for j in 1..6 {
            let k = j as f64 * std::f64::consts::PI;
            let [bend, _] = p.branches(k).unwrap();
            let eb = k.powi(4) / (1.0 + p.e2 * k * k) + p.axial * k * k;
            assert!((bend - eb).abs() <= 1e-9 * eb, "j {j}: {bend} against {eb}");
        }
    }

    /// Without damping or relaxation the oscillatory root is s = i√λ.
    #[test]
    fn undamped_roots_are_the_eigenvalues() {
        let p = ContinuumShear { e2: 0.0156, shear: 349.0, r2: 1.0 / 1024.0, axial: -2.0, foundation: 0.0 };
        let mut roots = Vec::new();
        assert!(family_roots(&p, 0.0, &[], 5, false, &mut roots));
        let fams = p.families(5).unwrap();
        for (f, r) in fams.iter().zip(&roots) {
            let s = r.iter().find(|s| s.im > 0.0).unwrap();
            let w = (f.a + f.b).sqrt();
            assert!((s.im - w).abs() <= 1e-12 * w && s.re.abs() <= 1e-12 * s.im, "{s} against i{w}");
        }
    }
}
