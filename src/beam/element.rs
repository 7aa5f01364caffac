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

/// Values of the interdependent-interpolation Timoshenko element at one point:
/// deflection w and its first two derivatives, section rotation θ and θ'.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimoshenkoShape {
    pub w: [f64; 4],
    pub dw: [f64; 4],
    pub ddw: [f64; 4],
    pub t: [f64; 4],
    pub dt: [f64; 4],
}

/// Shape functions of the interdependent-interpolation ("exact shape
/// function") Timoshenko element: cubic w, quadratic θ, DOFs [w₁, θ₁, w₂, θ₂]
/// with θ the rotation of the cross-section (shear strain γ = w′ − θ),
/// φ = 12EI/(κGAh²). Source: Friedman & Kosmatka, "An improved two-node
/// Timoshenko beam finite element", Computers & Structures 47 (1993) 473–481,
/// eqs. (14)–(15); Reddy, "On locking-free shear deformable beam finite
/// elements", CMAME 149 (1997) 113–132 (the IIE element). With ξ = x̄/h:
///   N_w = 1/(1+φ)·[2ξ³ − 3ξ² − φξ + 1 + φ,  h(ξ³ − (2 + φ/2)ξ² + (1 + φ/2)ξ),
///                 −2ξ³ + 3ξ² + φξ,          h(ξ³ − (1 − φ/2)ξ² − (φ/2)ξ)]
///   N_θ = 1/(1+φ)·[6(ξ² − ξ)/h,  3ξ² − (4 + φ)ξ + 1 + φ,  −6(ξ² − ξ)/h,  3ξ² − (2 − φ)ξ]
/// They solve the homogeneous static Timoshenko equations exactly (γ is
/// constant on the element), so the element does not lock in shear, and at
/// φ = 0 they are the Hermite functions (A3) with N_θ = N_w′.
pub fn timoshenko_shape(h: f64, phi: f64, xbar: f64) -> TimoshenkoShape {
    let x = xbar / h;
    let (x2, x3) = (x * x, x * x * x);
    let c = 1.0 / (1.0 + phi);
    let w = [
        c * (2.0 * x3 - 3.0 * x2 - phi * x + 1.0 + phi),
        c * h * (x3 - (2.0 + 0.5 * phi) * x2 + (1.0 + 0.5 * phi) * x),
        c * (-2.0 * x3 + 3.0 * x2 + phi * x),
        c * h * (x3 - (1.0 - 0.5 * phi) * x2 - 0.5 * phi * x),
    ];
    let dw = [
        c * (6.0 * x2 - 6.0 * x - phi) / h,
        c * (3.0 * x2 - 2.0 * (2.0 + 0.5 * phi) * x + 1.0 + 0.5 * phi),
        c * (-6.0 * x2 + 6.0 * x + phi) / h,
        c * (3.0 * x2 - 2.0 * (1.0 - 0.5 * phi) * x - 0.5 * phi),
    ];
    let ddw = [
        c * (12.0 * x - 6.0) / (h * h),
        c * (6.0 * x - 2.0 * (2.0 + 0.5 * phi)) / h,
        c * (-12.0 * x + 6.0) / (h * h),
        c * (6.0 * x - 2.0 * (1.0 - 0.5 * phi)) / h,
    ];
    let t = [
        c * 6.0 * (x2 - x) / h,
        c * (3.0 * x2 - (4.0 + phi) * x + 1.0 + phi),
        -c * 6.0 * (x2 - x) / h,
        c * (3.0 * x2 - (2.0 - phi) * x),
    ];
    let dt = [
        c * 6.0 * (2.0 * x - 1.0) / (h * h),
        c * (6.0 * x - 4.0 - phi) / h,
        -c * 6.0 * (2.0 * x - 1.0) / (h * h),
        c * (6.0 * x - 2.0 + phi) / h,
    ];
    TimoshenkoShape { w, dw, ddw, t, dt }
}

/// The bare integrals of one Timoshenko element (coefficients applied by the
/// caller, see `model.rs`): with shear parameter g = κGA/EI (per unit length²
/// of the element's coordinate) and φ = 12/(g h²),
/// - `stiffness` = ∫N_θ′N_θ′ᵀ + g∫(N_w′ − N_θ)(N_w′ − N_θ)ᵀ (bending + shear,
///   both scaled by E: they relax together);
/// - `mass_w0` = ∫N_wN_wᵀ, `mass_w1` = ∫N_w′N_w′ᵀ (translational inertia and
///   its nonlocal part, as in (A4));
/// - `mass_t0` = ∫N_θN_θᵀ, `mass_t1` = ∫N_θ′N_θ′ᵀ (rotary inertia ρI and its
///   nonlocal part: Eringen's operator acts on ρI θ̈ as on ρA ẅ);
/// - `geometric_1` = ∫N_w″N_w″ᵀ (the (e0a)² part of the axial-force term;
///   ∫N_w′N_w′ᵀ is `mass_w1`).
///
/// By 4-point Gauss–Legendre, exact to degree 7 (integrands are of degree ≤ 6).
#[derive(Debug, Clone, PartialEq)]
pub struct TimoshenkoElement {
    pub stiffness: Mat4,
    pub mass_w0: Mat4,
    pub mass_w1: Mat4,
    pub mass_t0: Mat4,
    pub mass_t1: Mat4,
    pub geometric_1: Mat4,
}

/// 4-point Gauss–Legendre nodes and weights on [−1, 1].
pub const GAUSS4_X: [f64; 4] =
    [-0.861_136_311_594_052_6, -0.339_981_043_584_856_3, 0.339_981_043_584_856_3, 0.861_136_311_594_052_6];
pub const GAUSS4_W: [f64; 4] =
    [0.347_854_845_137_453_8, 0.652_145_154_862_546_1, 0.652_145_154_862_546_1, 0.347_854_845_137_453_8];

/// The integrals of [`TimoshenkoElement`] for element length h and shear parameter g.
pub fn timoshenko_element(h: f64, g: f64) -> TimoshenkoElement {
    let phi = 12.0 / (g * h * h);
    let z = [[0.0; 4]; 4];
    let mut e = TimoshenkoElement { stiffness: z, mass_w0: z, mass_w1: z, mass_t0: z, mass_t1: z, geometric_1: z };
    for (x, wt) in GAUSS4_X.iter().zip(GAUSS4_W) {
        let s = timoshenko_shape(h, phi, 0.5 * h * (1.0 + x));
        let wt = 0.5 * h * wt;
        let gamma: [f64; 4] = std::array::from_fn(|a| s.dw[a] - s.t[a]);
        for a in 0..4 {
            for b in 0..4 {
                e.stiffness[a][b] += wt * (s.dt[a] * s.dt[b] + g * gamma[a] * gamma[b]);
                e.mass_w0[a][b] += wt * s.w[a] * s.w[b];
                e.mass_w1[a][b] += wt * s.dw[a] * s.dw[b];
                e.mass_t0[a][b] += wt * s.t[a] * s.t[b];
                e.mass_t1[a][b] += wt * s.dt[a] * s.dt[b];
                e.geometric_1[a][b] += wt * s.ddw[a] * s.ddw[b];
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
                for i in 0..4 {
                    for j in 0..4 {
                        assert_eq!(mat[i][j], mat[j][i]);
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

    /// The Timoshenko element's stiffness is the classical closed form
    /// EI/((1+φ)h³)·[[12, 6h, −12, 6h], [6h, (4+φ)h², −6h, (2−φ)h²], ...]
    /// (Przemieniecki, Theory of Matrix Structural Analysis, 1968, §5.6), its
    /// shear strain is constant on the element (no locking), and at g → ∞ every
    /// matrix tends to its Hermite (A3–A7) counterpart.
    #[test]
    fn timoshenko_element_matches_closed_form_and_euler_bernoulli_limit() {
        for (h, g) in [(0.05, 384.0), (0.05, 1e3), (0.3, 40.0), (1.0, 7.0)] {
            let phi = 12.0 / (g * h * h);
            let c = 1.0 / ((1.0 + phi) * h * h * h);
            let h2 = h * h;
            let closed = scale(
                [
                    [12.0, 6.0 * h, -12.0, 6.0 * h],
                    [6.0 * h, (4.0 + phi) * h2, -6.0 * h, (2.0 - phi) * h2],
                    [-12.0, -6.0 * h, 12.0, -6.0 * h],
                    [6.0 * h, (2.0 - phi) * h2, -6.0 * h, (4.0 + phi) * h2],
                ],
                c,
            );
            let e = timoshenko_element(h, g);
            // 4-point Gauss is exact here; agreement to rounding, 1e-12 of the largest entry
            assert_close(e.stiffness, closed, h);
            // γ = w′ − θ is constant along the element for every DOF
            for a in 0..4 {
                let g0 = timoshenko_shape(h, phi, 0.0);
                let g1 = timoshenko_shape(h, phi, 0.37 * h);
                let (ga, gb) = (g0.dw[a] - g0.t[a], g1.dw[a] - g1.t[a]);
                assert!((ga - gb).abs() <= 1e-12 * (1.0 + ga.abs()) / h, "γ varies: {ga} vs {gb}");
            }
        }
        // Euler–Bernoulli limit: φ = 12/(gh²) → 0; the matrices differ from the
        // Hermite ones by O(φ) (shape functions are rational in φ), so at
        // g = 1e12, h = 0.5 (φ = 4.8e-11) they agree to ~1e-10 of the largest entry.
        let (h, g) = (0.5, 1e12);
        let e = timoshenko_element(h, g);
        let near = |a: Mat4, b: Mat4| {
            let s = a.iter().flatten().chain(b.iter().flatten()).fold(0.0f64, |m, v| m.max(v.abs()));
            a.iter().flatten().zip(b.iter().flatten()).all(|(x, y)| (x - y).abs() <= 1e-9 * s)
        };
        assert!(near(e.stiffness, curvature_integral(h)));
        assert!(near(e.mass_w0, mass_integral(h)));
        assert!(near(e.mass_w1, slope_integral(h)));
        assert!(near(e.mass_t0, slope_integral(h)));
        assert!(near(e.mass_t1, curvature_integral(h)));
        assert!(near(e.geometric_1, curvature_integral(h)));
    }
}
