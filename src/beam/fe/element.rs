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

/// Quintic Hermite shape functions on [0, h] (ξ = x̄/h), DOFs
/// [u₁, u₁′, u₁″, u₂, u₂′, u₂″] (value, slope and curvature at each end):
///   H = [1 − 10ξ³ + 15ξ⁴ − 6ξ⁵, h(ξ − 6ξ³ + 8ξ⁴ − 3ξ⁵), (h²/2)ξ²(1 − ξ)³,
///        10ξ³ − 15ξ⁴ + 6ξ⁵, h(−4ξ³ + 7ξ⁴ − 3ξ⁵), (h²/2)ξ³(1 − ξ)²].
/// Derived from the 6 interpolation conditions (each Hᵢ has unit i-th nodal
/// value/derivative and zero others; e.g. Hᵢ with a triple root at the
/// other end), so the six interpolate every polynomial of degree ≤ 5
/// exactly; tested below. Returns [H, dH/dx̄, d²H/dx̄²] at x̄ ∈ [0, h].
pub fn quintic_shape(h: f64, xbar: f64) -> [[f64; 6]; 3] {
    let x = xbar / h;
    let (x2, x3, x4, x5) = (x * x, x * x * x, x * x * x * x, x * x * x * x * x);
    let half_h2 = 0.5 * h * h;
    let n = [
        1.0 - 10.0 * x3 + 15.0 * x4 - 6.0 * x5,
        h * (x - 6.0 * x3 + 8.0 * x4 - 3.0 * x5),
        half_h2 * (x2 - 3.0 * x3 + 3.0 * x4 - x5),
        10.0 * x3 - 15.0 * x4 + 6.0 * x5,
        h * (-4.0 * x3 + 7.0 * x4 - 3.0 * x5),
        half_h2 * (x3 - 2.0 * x4 + x5),
    ];
    let d = [
        (-30.0 * x2 + 60.0 * x3 - 30.0 * x4) / h,
        1.0 - 18.0 * x2 + 32.0 * x3 - 15.0 * x4,
        0.5 * h * (2.0 * x - 9.0 * x2 + 12.0 * x3 - 5.0 * x4),
        (30.0 * x2 - 60.0 * x3 + 30.0 * x4) / h,
        -12.0 * x2 + 28.0 * x3 - 15.0 * x4,
        0.5 * h * (3.0 * x2 - 8.0 * x3 + 5.0 * x4),
    ];
    let dd = [
        (-60.0 * x + 180.0 * x2 - 120.0 * x3) / (h * h),
        (-36.0 * x + 96.0 * x2 - 60.0 * x3) / h,
        0.5 * (2.0 - 18.0 * x + 36.0 * x2 - 20.0 * x3),
        (60.0 * x - 180.0 * x2 + 120.0 * x3) / (h * h),
        (-24.0 * x + 84.0 * x2 - 60.0 * x3) / h,
        0.5 * (6.0 * x - 24.0 * x2 + 20.0 * x3),
    ];
    [n, d, dd]
}

/// d³H/dx̄³ of [`quintic_shape`] at x̄ ∈ [0, h]: the strain gradient's
/// curvature slope w‴, a quadratic on the element (each entry the derivative
/// of the corresponding d²H/dx̄² row).
pub fn quintic_shape_ddd(h: f64, xbar: f64) -> [f64; 6] {
    let x = xbar / h;
    let x2 = x * x;
    let (h2, h3) = (h * h, h * h * h);
    [
        (-60.0 + 360.0 * x - 360.0 * x2) / h3,
        (-36.0 + 192.0 * x - 180.0 * x2) / h2,
        0.5 * (-18.0 + 72.0 * x - 60.0 * x2) / h,
        (60.0 - 360.0 * x + 360.0 * x2) / h3,
        (-24.0 + 168.0 * x - 180.0 * x2) / h2,
        0.5 * (6.0 - 48.0 * x + 60.0 * x2) / h,
    ]
}

/// DOFs per node of the C² (strain-gradient) Euler–Bernoulli element: [w, θ, χ]
/// (deflection, slope w′, curvature w″).
pub const GRADIENT_DPN: usize = 3;
/// DOFs per C² element (two nodes).
pub const GRADIENT_DOFS: usize = 2 * GRADIENT_DPN;
/// 6×6 element matrix of the C² element.
pub type Mat6 = [[f64; GRADIENT_DOFS]; GRADIENT_DOFS];

/// The bare integrals of one C² Euler–Bernoulli element, the quintic Hermite
/// element of [`quintic_shape`] with DOFs [w₁, θ₁, χ₁, w₂, θ₂, χ₂]:
/// `mass` = ∫NNᵀ, `slope` = ∫N′N′ᵀ (Eringen's part of (A4) and the axial
/// force's ∫w′w′), `curvature` = ∫N″N″ᵀ (EI's bending, (A6)),
/// `gradient` = ∫N‴N‴ᵀ (the strain gradient's EI l² ∫w‴v‴). By 6-point
/// Gauss–Legendre, exact to degree 11 (the integrands are of degree ≤ 10).
/// The element is C² across nodes (w, w′, w″ are nodal DOFs), so w‴ is
/// square-integrable over the mesh: the conforming space of the sixth-order
/// energy.
#[derive(Debug, Clone, PartialEq)]
pub struct GradientElement {
    pub mass: Mat6,
    pub slope: Mat6,
    pub curvature: Mat6,
    pub gradient: Mat6,
}

/// The integrals of [`GradientElement`] for element length h.
pub fn gradient_element(h: f64) -> GradientElement {
    let z = [[0.0; GRADIENT_DOFS]; GRADIENT_DOFS];
    let mut e = GradientElement { mass: z, slope: z, curvature: z, gradient: z };
    for (x, wt) in GAUSS6_X.iter().zip(GAUSS6_W) {
        let xl = 0.5 * h * (1.0 + x);
        let [n, d, dd] = quintic_shape(h, xl);
        let ddd = quintic_shape_ddd(h, xl);
        let wt = 0.5 * h * wt;
        for a in 0..GRADIENT_DOFS {
            for b in 0..GRADIENT_DOFS {
                e.mass[a][b] += wt * n[a] * n[b];
                e.slope[a][b] += wt * d[a] * d[b];
                e.curvature[a][b] += wt * dd[a] * dd[b];
                e.gradient[a][b] += wt * ddd[a] * ddd[b];
            }
        }
    }
    e
}

/// DOFs per node of the Timoshenko element: [w, θ, χ, s, γ].
pub const TIMOSHENKO_DPN: usize = 5;
/// DOFs per Timoshenko element (two nodes).
pub const TIMOSHENKO_DOFS: usize = 2 * TIMOSHENKO_DPN;

/// A field of the Timoshenko element at one point: its coefficients on the
/// element's 10 DOFs.
pub type TimoshenkoRow = [f64; TIMOSHENKO_DOFS];

/// 10×10 element matrix of the Timoshenko element.
pub type Mat10 = [[f64; TIMOSHENKO_DOFS]; TIMOSHENKO_DOFS];

/// The fields of the Timoshenko element at one point, each as its 10 DOF
/// coefficients: deflection w, w′, w″, section rotation θ = w_b′ and θ′ = w_b″,
/// shear strain γ = w_s′.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimoshenkoPoint {
    pub w: TimoshenkoRow,
    pub dw: TimoshenkoRow,
    pub ddw: TimoshenkoRow,
    pub rot: TimoshenkoRow,
    pub drot: TimoshenkoRow,
    pub shear: TimoshenkoRow,
}

/// The bending–shear split Timoshenko element (after the decomposition
/// w = w_b + w_s, θ = w_b′, γ = w_s′ of the Timoshenko kinematics; e.g.
/// Wang, Reddy & Lee, *Shear Deformable Beams and Plates*, Elsevier 2000,
/// §2.4, and the "two-variable" beam elements built on it). The bending part
/// w_b is quintic Hermite ([`quintic_shape`], N5), the shear part w_s cubic
/// Hermite (A3, N3), so with the nodal DOFs [w, θ, χ, s, γ] (w total
/// deflection, θ = w_b′ section rotation, χ = θ′ = w_b″ bending curvature,
/// s = w_s, γ = w_s′ shear strain), element DOFs
/// [w₁, θ₁, χ₁, s₁, γ₁, w₂, θ₂, χ₂, s₂, γ₂]:
///   w_b = N5·[w₁ − s₁, θ₁, χ₁, w₂ − s₂, θ₂, χ₂],  w_s = N3·[s₁, γ₁, s₂, γ₂],
///   w = w_b + w_s.
/// No constraint ties γ to w and θ, so the element cannot lock in shear.
/// Rayleigh–Ritz error: the eigenvalue error is the squared energy-norm
/// error of the best approximation of the mode; w_b enters through H²
/// (EI∫θ′², quintic: O(h⁴) per field, O(h⁸) in λ), w_s through H¹ only
/// (κGA∫γ², cubic: O(h³), O(h⁶) in λ, weighted by the mode's shear share of
/// its strain energy). With s = γ = 0 the (w, θ, χ) matrices are the quintic
/// Hermite element's (the Euler–Bernoulli limit). Five DOFs per node: the
/// assembled band has half-width 2·5 − 1 = 9.
pub fn timoshenko_point(h: f64, xbar: f64) -> TimoshenkoPoint {
    let [n5, d5, dd5] = quintic_shape(h, xbar);
    let (n3, d3) = (shape(h, xbar), shape_d(h, xbar));
    let wb = |f: [f64; 6]| [f[0], f[1], f[2], -f[0], 0.0, f[3], f[4], f[5], -f[3], 0.0];
    let ws = |g: [f64; 4]| [0.0, 0.0, 0.0, g[0], g[1], 0.0, 0.0, 0.0, g[2], g[3]];
    let w = |f: [f64; 6], g: [f64; 4]| -> TimoshenkoRow {
        let (b, s) = (wb(f), ws(g));
        std::array::from_fn(|a| b[a] + s[a])
    };
    let dd3 = shape_dd(h, xbar);
    TimoshenkoPoint { w: w(n5, n3), dw: w(d5, d3), ddw: w(dd5, dd3), rot: wb(d5), drot: wb(dd5), shear: ws(d3) }
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
/// By 6-point Gauss–Legendre, exact to degree 11: the integrands are
/// products of two fields of degree ≤ 5 (w), so of degree ≤ 10.
#[derive(Debug, Clone, PartialEq)]
pub struct TimoshenkoElement {
    pub bending: Mat10,
    pub shear: Mat10,
    pub mass_w0: Mat10,
    pub mass_w1: Mat10,
    pub mass_t0: Mat10,
    pub geometric_1: Mat10,
}

/// 6-point Gauss–Legendre nodes and weights on [−1, 1] (exact to degree 11;
/// the roots of P₆ by Newton's method in 50-digit arithmetic, rounded to the
/// nearest f64; weights 2/((1 − x²)P₆′(x)²)).
pub const GAUSS6_X: [f64; 6] = [
    -0.932_469_514_203_152,
    -0.661_209_386_466_264_5,
    -0.238_619_186_083_196_9,
    0.238_619_186_083_196_9,
    0.661_209_386_466_264_5,
    0.932_469_514_203_152,
];
pub const GAUSS6_W: [f64; 6] = [
    0.171_324_492_379_170_36,
    0.360_761_573_048_138_6,
    0.467_913_934_572_691_04,
    0.467_913_934_572_691_04,
    0.360_761_573_048_138_6,
    0.171_324_492_379_170_36,
];

/// The integrals of [`TimoshenkoElement`] for element length h.
pub fn timoshenko_element(h: f64) -> TimoshenkoElement {
    let z = [[0.0; TIMOSHENKO_DOFS]; TIMOSHENKO_DOFS];
    let mut e = TimoshenkoElement { bending: z, shear: z, mass_w0: z, mass_w1: z, mass_t0: z, geometric_1: z };
    for (x, wt) in GAUSS6_X.iter().zip(GAUSS6_W) {
        let p = timoshenko_point(h, 0.5 * h * (1.0 + x));
        let wt = 0.5 * h * wt;
        for a in 0..TIMOSHENKO_DOFS {
            for b in 0..TIMOSHENKO_DOFS {
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

    fn assert_close<const N: usize>(a: [[f64; N]; N], b: [[f64; N]; N], h: f64) {
        // Gauss weights are given to 15 digits: 1e-12 relative to the largest entry.
        let scale = a.iter().flatten().chain(b.iter().flatten()).fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..N {
            for j in 0..N {
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

    /// The quintic Hermite shape functions of [`quintic_shape`]:
    /// - interpolation conditions: [H, H′, H″] at x̄ = 0 and x̄ = h pick the
    ///   six nodal values (δᵢⱼ);
    /// - partition of unity: H₀ + H₃ = 1 (and its derivatives vanish);
    /// - exactness: the interpolant of every monomial (x̄ − c)ᵏ, k ≤ 5, from its
    ///   nodal value, slope and curvature is the monomial itself (value, first
    ///   and second derivative) at interior points.
    ///
    /// Tolerance: each Hᵢ⁽ʳ⁾ is a sum of terms with integer coefficients ≤ 180
    /// (relative rounding ≲ 180·4 ulp ≈ 2e-13 of hʲ⁻ʳ), six of them per
    /// interpolant: 1e-12 of Σ|qᵢ|hʲⁱ⁻ʳ. The nodal conditions (ξ ∈ {0, 1},
    /// integer sums) and the partition of unity are exact up to one rounding.
    #[test]
    fn quintic_shape_functions_interpolate_and_are_exact_to_degree_5() {
        for h in [0.05, 0.7, 2.5] {
            for (node, xbar) in [(0usize, 0.0), (1, h)] {
                let s = quintic_shape(h, xbar);
                for (order, row) in s.iter().enumerate() {
                    for (i, v) in row.iter().enumerate() {
                        let want = if i == 3 * node + order { 1.0 } else { 0.0 };
                        assert!((v - want).abs() <= 1e-13, "h={h} node {node} order {order} H{i}: {v}");
                    }
                }
            }
            for xi in [0.0, 0.13, 0.5, 0.77, 1.0] {
                let [n, d, dd] = quintic_shape(h, xi * h);
                assert!((n[0] + n[3] - 1.0).abs() <= 1e-13, "{}", n[0] + n[3]);
                assert!((d[0] + d[3]).abs() <= 1e-13 / h && (dd[0] + dd[3]).abs() <= 1e-13 / (h * h));
            }
            let c = 0.3 * h;
            for k in 0..=5i32 {
                // p = (x̄ − c)ᵏ and its first two derivatives
                let p = |x: f64, order: i32| -> f64 {
                    let coef: f64 = (0..order).map(|j| f64::from(k - j)).product();
                    if k < order {
                        0.0
                    } else {
                        coef * (x - c).powi(k - order)
                    }
                };
                let q = [p(0.0, 0), p(0.0, 1), p(0.0, 2), p(h, 0), p(h, 1), p(h, 2)];
                for xi in [0.1, 0.37, 0.5, 0.81] {
                    let x = xi * h;
                    let s = quintic_shape(h, x);
                    for order in 0..3 {
                        let interp: f64 = s[order as usize].iter().zip(&q).map(|(a, b)| a * b).sum();
                        // |Hᵢ⁽ʳ⁾| ≤ 180·h^(jᵢ − r) (jᵢ = 0, 1, 2 for value, slope, curvature DOFs)
                        let scale: f64 =
                            q.iter().zip([0, 1, 2, 0, 1, 2]).map(|(v, j)| v.abs() * h.powi(j - order)).sum();
                        let exact = p(x, order);
                        assert!(
                            (interp - exact).abs() <= 1e-12 * scale.max(1e-300),
                            "h={h} k={k} order {order} at ξ={xi}: {interp} vs {exact}"
                        );
                    }
                }
            }
        }
    }

    /// [`quintic_shape_ddd`] is the third derivative of the interpolant: the
    /// interpolant of (x̄ − c)ᵏ, k ≤ 5, has the monomial's third derivative
    /// (same tolerance argument as above, with |Hᵢ‴| ≤ 360·h^(jᵢ − 3)); and the
    /// C² element's integrals equal the exact polynomial integrals of
    /// `quintic_integral` (r = 0..3) to 1e-12 of the largest entry (Gauss
    /// weights given to 16 digits, entries summed over 6 points).
    #[test]
    fn quintic_third_derivative_and_gradient_element_are_exact() {
        for h in [0.05, 0.7, 2.5] {
            let c = 0.3 * h;
            for k in 0..=5i32 {
                let p = |x: f64, order: i32| -> f64 {
                    let coef: f64 = (0..order).map(|j| f64::from(k - j)).product();
                    if k < order {
                        0.0
                    } else {
                        coef * (x - c).powi(k - order)
                    }
                };
                let q = [p(0.0, 0), p(0.0, 1), p(0.0, 2), p(h, 0), p(h, 1), p(h, 2)];
                for xi in [0.0, 0.1, 0.37, 0.5, 0.81, 1.0] {
                    let x = xi * h;
                    let interp: f64 = quintic_shape_ddd(h, x).iter().zip(&q).map(|(a, b)| a * b).sum();
                    let scale: f64 = q.iter().zip([0, 1, 2, 0, 1, 2]).map(|(v, j)| v.abs() * h.powi(j - 3)).sum();
                    let exact = p(x, 3);
                    assert!(
                        (interp - exact).abs() <= 2e-12 * scale.max(1e-300),
                        "h={h} k={k} at ξ={xi}: {interp} vs {exact}"
                    );
                }
            }
            let e = gradient_element(h);
            for (r, got) in [(0, e.mass), (1, e.slope), (2, e.curvature), (3, e.gradient)] {
                assert_close(got, quintic_integral(h, r), h);
            }
        }
    }

    /// Monomial coefficients (in ξ = x̄/h) of the six quintic Hermite shape
    /// functions: an independent route to their integrals.
    fn quintic_coefficients(h: f64) -> [[f64; 6]; 6] {
        let (h1, h2) = (h, 0.5 * h * h);
        [
            [1.0, 0.0, 0.0, -10.0, 15.0, -6.0],
            [0.0, h1, 0.0, -6.0 * h1, 8.0 * h1, -3.0 * h1],
            [0.0, 0.0, h2, -3.0 * h2, 3.0 * h2, -h2],
            [0.0, 0.0, 0.0, 10.0, -15.0, 6.0],
            [0.0, 0.0, 0.0, -4.0 * h1, 7.0 * h1, -3.0 * h1],
            [0.0, 0.0, 0.0, h2, -2.0 * h2, h2],
        ]
    }

    /// ∫₀ʰ (dʳNᵢ/dx̄ʳ)(dʳNⱼ/dx̄ʳ) dx̄ of the quintic Hermite functions, exactly
    /// (polynomial products, ∫₀¹ ξᵐ dξ = 1/(m + 1)).
    fn quintic_integral(h: f64, r: usize) -> [[f64; 6]; 6] {
        let c = quintic_coefficients(h);
        // r-th derivative in x̄: coefficient of ξᵏ⁻ʳ is k!/(k−r)!·cₖ/hʳ
        let deriv = |ci: &[f64; 6]| -> [f64; 6] {
            std::array::from_fn(|m| {
                let k = m + r;
                if k > 5 {
                    return 0.0;
                }
                let f: f64 = (0..r).map(|j| (k - j) as f64).product();
                f * ci[k] / h.powi(r as i32)
            })
        };
        let d: Vec<[f64; 6]> = c.iter().map(deriv).collect();
        std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let mut s = 0.0;
                for (a, da) in d[i].iter().enumerate() {
                    for (b, db) in d[j].iter().enumerate() {
                        s += da * db / (a + b + 1) as f64;
                    }
                }
                h * s
            })
        })
    }

    fn energy<const N: usize>(m: &[[f64; N]; N], q: &[f64; N]) -> f64 {
        (0..N).map(|a| (0..N).map(|b| q[a] * m[a][b] * q[b]).sum::<f64>()).sum()
    }

    /// Euler–Bernoulli limit of the Timoshenko element: restricted to the
    /// (w, θ, χ) DOFs (s = γ = 0, no shear strain, θ = w′) every matrix is
    /// the quintic Hermite element's (∫N5″N5″ᵀ for bending and the (e0a)²
    /// geometric part, ∫N5N5ᵀ, ∫N5′N5′ᵀ for mass, nonlocal mass and rotary
    /// inertia), here integrated exactly from the monomial coefficients:
    /// the 6-point rule is exact for these degree-≤ 10 integrands, so they
    /// agree to rounding (1e-12 of the largest entry). A cubic deflection
    /// (nodal χ = its curvature) has exactly the energies of the cubic
    /// Hermite element (A4)–(A6) (the quintic space contains the cubics).
    /// The shear matrix vanishes there; a pure shear deflection (w = s,
    /// γ = s′, θ = χ = 0) has no bending energy and shear energy ∫γ².
    #[test]
    fn timoshenko_element_reduces_to_hermite_without_shear() {
        for h in [0.05, 0.4, 1.0] {
            let e = timoshenko_element(h);
            let eb_dofs = [0, 1, 2, 5, 6, 7];
            let restrict = |m: &Mat10| -> [[f64; 6]; 6] {
                std::array::from_fn(|i| std::array::from_fn(|j| m[eb_dofs[i]][eb_dofs[j]]))
            };
            let (q0, q1, q2) = (quintic_integral(h, 0), quintic_integral(h, 1), quintic_integral(h, 2));
            assert_close(restrict(&e.bending), q2, h);
            assert_close(restrict(&e.mass_w0), q0, h);
            assert_close(restrict(&e.mass_w1), q1, h);
            assert_close(restrict(&e.mass_t0), q1, h);
            assert_close(restrict(&e.geometric_1), q2, h);
            assert!(restrict(&e.shear).iter().flatten().all(|v| *v == 0.0));
            // a cubic p(x̄) = 0.2 − 0.5x̄ + 0.9x̄² − 0.4x̄³ on the element
            let p = [0.2, -0.5, 0.9, -0.4];
            let at = |x: f64| {
                [
                    p[0] + p[1] * x + p[2] * x * x + p[3] * x * x * x,
                    p[1] + 2.0 * p[2] * x + 3.0 * p[3] * x * x,
                    2.0 * p[2] + 6.0 * p[3] * x,
                ]
            };
            let (a, b) = (at(0.0), at(h));
            let q10 = [a[0], a[1], a[2], 0.0, 0.0, b[0], b[1], b[2], 0.0, 0.0];
            let q4 = [a[0], a[1], b[0], b[1]];
            let abs = |m: &[[f64; 10]; 10]| m.map(|r| r.map(f64::abs));
            let abs4 = |m: &Mat4| m.map(|r| r.map(f64::abs));
            let q10a = q10.map(f64::abs);
            let q4a = q4.map(f64::abs);
            for (m10, m4) in
                [(&e.bending, curvature_integral(h)), (&e.mass_w0, mass_integral(h)), (&e.mass_w1, slope_integral(h))]
            {
                let (quintic, cubic) = (energy(m10, &q10), energy(&m4, &q4));
                // both exact for the same ∫ of a polynomial: rounding only. A
                // quadratic form of n² ≤ 100 terms (entries of size up to
                // 12/h³ that cancel) rounds to ≲ n²·eps·Σ|qₐ||mₐᵦ||qᵦ|: 1e-13 of that
                // sum covers it (and the entries' own quadrature rounding).
                let scale = energy(&abs(m10), &q10a) + energy(&abs4(&m4), &q4a);
                assert!((quintic - cubic).abs() <= 1e-13 * scale, "h={h}: {quintic} vs {cubic} (scale {scale:e})");
            }
            // pure shear: w = s = linear, γ = slope, θ = χ = 0 → w_b ≡ 0
            let q = [0.0, 0.0, 0.0, 0.0, 0.3, 0.3 * h, 0.0, 0.0, 0.3 * h, 0.3];
            assert!(energy(&e.bending, &q).abs() < 1e-15, "{}", energy(&e.bending, &q));
            assert!((energy(&e.shear, &q) - 0.09 * h).abs() < 1e-14, "{}", energy(&e.shear, &q));
        }
    }
}
