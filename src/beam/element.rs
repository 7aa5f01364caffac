//! Hermite beam element, Appendix 1 (A3)–(A7), in nanometre length units.
//!
//! Shape functions (A3) with ξ = x̄/h, h = element length:
//! N = [1 − 3ξ² + 2ξ³, h(ξ − 2ξ² + ξ³), 3ξ² − 2ξ³, h(−ξ² + ξ³)]ᵀ,
//! DOFs [w₁, θ₁, w₂, θ₂] (θ = dw/dx̄).
//!
//! Closed-form integrals (exact for cubics):
//! ∫N Nᵀ   = h/420 [[156, 22h, 54, −13h], [22h, 4h², 13h, −3h²], [54, 13h, 156, −22h], [−13h, −3h², −22h, 4h²]]
//! ∫N'N'ᵀ  = 1/(30h) [[36, 3h, −36, 3h], [3h, 4h², −3h, −h²], [−36, −3h, 36, −3h], [3h, −h², −3h, 4h²]]
//! ∫N''N''ᵀ = 1/h³ [[12, 6h, −12, 6h], [6h, 4h², −6h, 2h²], [−12, −6h, 12, −6h], [6h, 2h², −6h, 4h²]]
//!
//! so (A4) Me = ρA(∫NNᵀ + (e0a)²∫N'N'ᵀ), (A5) De = C(∫NNᵀ + (e0a)²∫N'N'ᵀ) = (C/ρA)·Me,
//! (A6) Ke = EI ∫N''N''ᵀ. The coefficients ρA, C, EI are applied by the caller
//! (see `model.rs` for the scaling), so these functions return the bare integrals.
//!
//! Nodal load (A7) for a point force f(x̄) = F δ(x̄ − x̄₀):
//! Pe = ∫(N − (e0a)² N'') F δ(x̄ − x̄₀) dx̄ = F (N(x̄₀) − (e0a)² N''(x̄₀)).
//! The minus sign comes from the nonlocal operator (1 − (e0a)² ∂²/∂x²) applied to f in (19)–(20).

/// 4×4 element matrix.
pub type Mat4 = [[f64; 4]; 4];

/// ∫₀ʰ N Nᵀ dx̄ (consistent mass integral).
pub fn mass_integral(h: f64) -> Mat4 {
    let c = h / 420.0;
    let h2 = h * h;
    scale(
        [
            [156.0, 22.0 * h, 54.0, -13.0 * h],
            [22.0 * h, 4.0 * h2, 13.0 * h, -3.0 * h2],
            [54.0, 13.0 * h, 156.0, -22.0 * h],
            [-13.0 * h, -3.0 * h2, -22.0 * h, 4.0 * h2],
        ],
        c,
    )
}

/// ∫₀ʰ N' N'ᵀ dx̄ (the nonlocal "rotary-like" mass integral of (A4)).
pub fn slope_integral(h: f64) -> Mat4 {
    let c = 1.0 / (30.0 * h);
    let h2 = h * h;
    scale(
        [
            [36.0, 3.0 * h, -36.0, 3.0 * h],
            [3.0 * h, 4.0 * h2, -3.0 * h, -h2],
            [-36.0, -3.0 * h, 36.0, -3.0 * h],
            [3.0 * h, -h2, -3.0 * h, 4.0 * h2],
        ],
        c,
    )
}

/// ∫₀ʰ N'' N''ᵀ dx̄ (bending stiffness integral of (A6)).
pub fn curvature_integral(h: f64) -> Mat4 {
    let c = 1.0 / (h * h * h);
    let h2 = h * h;
    scale(
        [
            [12.0, 6.0 * h, -12.0, 6.0 * h],
            [6.0 * h, 4.0 * h2, -6.0 * h, 2.0 * h2],
            [-12.0, -6.0 * h, 12.0, -6.0 * h],
            [6.0 * h, 2.0 * h2, -6.0 * h, 4.0 * h2],
        ],
        c,
    )
}

fn scale(mut m: Mat4, c: f64) -> Mat4 {
    for row in m.iter_mut() {
        for v in row.iter_mut() {
            *v *= c;
        }
    }
    m
}

/// N(x̄) of (A3) at local coordinate x̄ ∈ [0, h].
pub fn shape(h: f64, xbar: f64) -> [f64; 4] {
    let x = xbar / h;
    let (x2, x3) = (x * x, x * x * x);
    [1.0 - 3.0 * x2 + 2.0 * x3, h * (x - 2.0 * x2 + x3), 3.0 * x2 - 2.0 * x3, h * (x3 - x2)]
}

/// dN/dx̄ at x̄ ∈ [0, h].
pub fn shape_d(h: f64, xbar: f64) -> [f64; 4] {
    let x = xbar / h;
    [(-6.0 * x + 6.0 * x * x) / h, 1.0 - 4.0 * x + 3.0 * x * x, (6.0 * x - 6.0 * x * x) / h, -2.0 * x + 3.0 * x * x]
}

/// d²N/dx̄² at x̄ ∈ [0, h].
pub fn shape_dd(h: f64, xbar: f64) -> [f64; 4] {
    let x = xbar / h;
    let h2 = h * h;
    [(-6.0 + 12.0 * x) / h2, (-4.0 + 6.0 * x) / h, (6.0 - 12.0 * x) / h2, (-2.0 + 6.0 * x) / h]
}

/// Per-unit-force nodal load of (A7): N(x̄₀) − (e0a)² N''(x̄₀).
pub fn point_load(h: f64, xbar: f64, e0a: f64) -> [f64; 4] {
    let n = shape(h, xbar);
    let dd = shape_dd(h, xbar);
    let e2 = e0a * e0a;
    [n[0] - e2 * dd[0], n[1] - e2 * dd[1], n[2] - e2 * dd[2], n[3] - e2 * dd[3]]
}

/// 8×8 element matrix of the Timoshenko element.
pub type Mat8 = [[f64; 8]; 8];

/// The fields of the Timoshenko element at one point, each as its 8 DOF
/// coefficients: deflection w, w′, w″, section rotation θ = w_b′ and θ′ = w_b″,
/// shear strain γ = w_s′.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimoshenkoPoint {
    pub w: [f64; 8],
    pub dw: [f64; 8],
    pub ddw: [f64; 8],
    pub rot: [f64; 8],
    pub drot: [f64; 8],
    pub shear: [f64; 8],
}

/// The bending–shear split Timoshenko element (after the decomposition
/// w = w_b + w_s, θ = w_b′, γ = w_s′ of the Timoshenko kinematics; e.g.
/// Wang, Reddy & Lee, *Shear Deformable Beams and Plates*, Elsevier 2000,
/// §2.4, and the "two-variable" beam elements built on it). Both parts are
/// cubic Hermite (A3), so with the nodal DOFs
/// [w₁, θ₁, s₁, γ₁, w₂, θ₂, s₂, γ₂] (w total deflection, θ section rotation,
/// s = w_s, γ = w_s′ shear strain):
///   w_b = N·[w₁ − s₁, θ₁, w₂ − s₂, θ₂],  w_s = N·[s₁, γ₁, s₂, γ₂],
///   w = w_b + w_s = N·[w₁, θ₁ + γ₁, w₂, θ₂ + γ₂].
/// No constraint ties γ to w and θ, so the element cannot lock in shear; w_b
/// is H²-conforming (Hermite), so eigenvalues converge at O(h⁴) as for
/// the Euler–Bernoulli element; with s = γ = 0 every matrix is its Hermite
/// (A4)–(A6) counterpart (the Euler–Bernoulli limit). Four DOFs per node:
/// the assembled band has half-width 7.
pub fn timoshenko_point(h: f64, xbar: f64) -> TimoshenkoPoint {
    let (n, d, dd) = (shape(h, xbar), shape_d(h, xbar), shape_dd(h, xbar));
    let wb = |f: [f64; 4]| [f[0], f[1], -f[0], 0.0, f[2], f[3], -f[2], 0.0];
    let ws = |f: [f64; 4]| [0.0, 0.0, f[0], f[1], 0.0, 0.0, f[2], f[3]];
    let w = |f: [f64; 4]| [f[0], f[1], 0.0, f[1], f[2], f[3], 0.0, f[3]];
    TimoshenkoPoint { w: w(n), dw: w(d), ddw: w(dd), rot: wb(d), drot: wb(dd), shear: ws(d) }
}

/// The bare integrals of one Timoshenko element (coefficients applied by
/// the caller, see `model.rs`):
/// - `bending` = ∫θ′θ′ᵀ, `shear` = ∫γγᵀ (scaled by E and κG: they relax together);
/// - `mass_w0` = ∫wwᵀ, `mass_w1` = ∫w′w′ᵀ (translational inertia and its
///   nonlocal part, as in (A4));
/// - `mass_t0` = ∫θθᵀ (rotary inertia ρI; its nonlocal part ∫θ′θ′ᵀ is
///   `bending`: Eringen's operator acts on ρI θ̈ as on ρA ẅ);
/// - `geometric_1` = ∫w″w″ᵀ (the (e0a)² part of the axial-force term;
///   ∫w′w′ᵀ is `mass_w1`).
///
/// By 4-point Gauss–Legendre, exact to degree 7 (integrands are of degree ≤ 6).
#[derive(Debug, Clone, PartialEq)]
pub struct TimoshenkoElement {
    pub bending: Mat8,
    pub shear: Mat8,
    pub mass_w0: Mat8,
    pub mass_w1: Mat8,
    pub mass_t0: Mat8,
    pub geometric_1: Mat8,
}

/// 4-point Gauss–Legendre nodes and weights on [−1, 1].
pub const GAUSS4_X: [f64; 4] =
    [-0.861_136_311_594_052_6, -0.339_981_043_584_856_3, 0.339_981_043_584_856_3, 0.861_136_311_594_052_6];
pub const GAUSS4_W: [f64; 4] =
    [0.347_854_845_137_453_8, 0.652_145_154_862_546_1, 0.652_145_154_862_546_1, 0.347_854_845_137_453_8];

/// The integrals of [`TimoshenkoElement`] for element length h.
pub fn timoshenko_element(h: f64) -> TimoshenkoElement {
    let z = [[0.0; 8]; 8];
    let mut e = TimoshenkoElement { bending: z, shear: z, mass_w0: z, mass_w1: z, mass_t0: z, geometric_1: z };
    for (x, wt) in GAUSS4_X.iter().zip(GAUSS4_W) {
        let p = timoshenko_point(h, 0.5 * h * (1.0 + x));
        let wt = 0.5 * h * wt;
        for a in 0..8 {
            for b in 0..8 {
                e.bending[a][b] += wt * p.drot[a] * p.drot[b];
                e.shear[a][b] += wt * p.shear[a] * p.shear[b];
                e.mass_w0[a][b] += wt * p.w[a] * p.w[b];
                e.mass_w1[a][b] += wt * p.dw[a] * p.dw[b];
                e.mass_t0[a][b] += wt * p.rot[a] * p.rot[b];
                e.geometric_1[a][b] += wt * p.ddw[a] * p.ddw[b];
            }
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Gauss–Legendre 5-point rule on [0, h]: exact for degree ≤ 9 (the
    /// integrands are of degree ≤ 6), so agreement is to round-off, ~1e-13
    /// relative for entries of size O(h^k).
    fn gauss<F: Fn(f64) -> Mat4>(h: f64, f: F) -> Mat4 {
        let xs = [0.0, -0.538_469_310_105_683, 0.538_469_310_105_683, -0.906_179_845_938_664, 0.906_179_845_938_664];
        let ws = [
            0.568_888_888_888_889,
            0.478_628_670_499_366,
            0.478_628_670_499_366,
            0.236_926_885_056_189,
            0.236_926_885_056_189,
        ];
        let mut out = [[0.0; 4]; 4];
        for (x, w) in xs.iter().zip(ws) {
            let m = f(0.5 * h * (1.0 + x));
            for i in 0..4 {
                for j in 0..4 {
                    out[i][j] += 0.5 * h * w * m[i][j];
                }
            }
        }
        out
    }

    fn outer(a: [f64; 4]) -> Mat4 {
        let mut m = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] = a[i] * a[j];
            }
        }
        m
    }

    fn assert_close(a: Mat4, b: Mat4, h: f64) {
        // Gauss weights are given to 15 digits: 1e-12 relative to the largest entry.
        let scale = a.iter().flatten().chain(b.iter().flatten()).fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..4 {
            for j in 0..4 {
                assert!((a[i][j] - b[i][j]).abs() <= 1e-12 * scale, "h={h} ({i},{j}): {} vs {}", a[i][j], b[i][j]);
            }
        }
    }

    #[test]
    fn closed_forms_match_quadrature_and_are_symmetric() {
        for h in [0.1, 0.4, 1.0, 2.5] {
            let m = mass_integral(h);
            let s = slope_integral(h);
            let k = curvature_integral(h);
            assert_close(m, gauss(h, |x| outer(shape(h, x))), h);
            assert_close(s, gauss(h, |x| outer(shape_d(h, x))), h);
            assert_close(k, gauss(h, |x| outer(shape_dd(h, x))), h);
            for mat in [m, s, k] {
                for (i, row) in mat.iter().enumerate() {
                    for (j, v) in row.iter().enumerate() {
                        assert_eq!(*v, mat[j][i]);
                    }
                }
            }
        }
    }

    #[test]
    fn stiffness_has_two_rigid_body_modes_and_mass_is_total_mass() {
        let h = 0.7;
        let k = curvature_integral(h);
        // translation [1,0,1,0] and rotation about node 1: w = x̄ -> [0,1,h,1]
        for v in [[1.0, 0.0, 1.0, 0.0], [0.0, 1.0, h, 1.0]] {
            for row in k.iter() {
                let r: f64 = row.iter().zip(v).map(|(a, b)| a * b).sum();
                assert!(r.abs() < 1e-12 / h.powi(3), "K·rigid = {r}");
            }
        }
        // rank 2: a bending mode has positive energy
        let bend = [0.0, 1.0, 0.0, -1.0];
        let e: f64 = (0..4).map(|i| (0..4).map(|j| bend[i] * k[i][j] * bend[j]).sum::<f64>()).sum();
        assert!(e > 0.0);
        // uᵀ ∫NNᵀ u with u = rigid translation = ∫1 dx̄ = h (partition of unity)
        let m = mass_integral(h);
        let t = [1.0, 0.0, 1.0, 0.0];
        let total: f64 = (0..4).map(|i| (0..4).map(|j| t[i] * m[i][j] * t[j]).sum::<f64>()).sum();
        assert!((total - h).abs() < 1e-14);
        // the slope integral sees no rigid translation
        let s = slope_integral(h);
        let st: f64 = (0..4).map(|i| (0..4).map(|j| t[i] * s[i][j] * t[j]).sum::<f64>()).sum();
        assert!(st.abs() < 1e-14);
    }

    #[test]
    fn point_load_is_local_reduces_to_shape_functions() {
        let p = point_load(2.0, 0.5, 0.0);
        assert_eq!(p, shape(2.0, 0.5));
        // ΣN₁+N₃ = 1 (partition of unity) and ΣN''₁+N''₃ = 0 so the translational resultant is F
        let p = point_load(2.0, 0.3, 0.8);
        assert!((p[0] + p[2] - 1.0).abs() < 1e-14);
    }

    /// Euler–Bernoulli limit of the Timoshenko element: restricted to the
    /// (w, θ) DOFs (s = γ = 0, no shear strain) every matrix is its Hermite
    /// counterpart (same 4-point rule, so equal to rounding, 1e-12 of the
    /// largest entry); the shear matrix vanishes there; and a pure shear
    /// deflection (w = s, γ = s′, θ = 0) has no bending energy.
    #[test]
    fn timoshenko_element_reduces_to_hermite_without_shear() {
        for h in [0.05, 0.4, 1.0] {
            let e = timoshenko_element(h);
            let eb_dofs = [0, 1, 4, 5];
            let restrict =
                |m: &Mat8| -> Mat4 { std::array::from_fn(|i| std::array::from_fn(|j| m[eb_dofs[i]][eb_dofs[j]])) };
            assert_close(restrict(&e.bending), curvature_integral(h), h);
            assert_close(restrict(&e.mass_w0), mass_integral(h), h);
            assert_close(restrict(&e.mass_w1), slope_integral(h), h);
            assert_close(restrict(&e.mass_t0), slope_integral(h), h);
            assert_close(restrict(&e.geometric_1), curvature_integral(h), h);
            assert!(restrict(&e.shear).iter().flatten().all(|v| *v == 0.0));
            // pure shear: w = s = linear, γ = slope, θ = 0 → w_b ≡ 0
            let q = [0.0, 0.0, 0.0, 0.3, 0.3 * h, 0.0, 0.3 * h, 0.3];
            let energy = |m: &Mat8| (0..8).map(|a| (0..8).map(|b| q[a] * m[a][b] * q[b]).sum::<f64>()).sum::<f64>();
            assert!(energy(&e.bending).abs() < 1e-15, "{}", energy(&e.bending));
            assert!((energy(&e.shear) - 0.09 * h).abs() < 1e-14, "{}", energy(&e.shear));
        }
    }
}
