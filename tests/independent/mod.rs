//! An independent hidden-effect generator: modal data of a nonlocal
//! viscoelastic Euler–Bernoulli beam computed without the project's `beam`
//! module (issue 40, deliverable 5). It shares the physics under test (the
//! paper's model) but none of its code or discretisation:
//!
//! - **Undamped modes, exact.** The beam is cut into uniform segments. On each,
//!   the relaxed, undamped equation in x̃ = x/L,
//!   P w'''' + (λ m ẽ² − ñ) w'' − λ m w = 0, P = e + ñ ẽ²,
//!   (e = EI/EI₀, m = ρA/(ρA)₀ of the segment, ẽ = e0a/L, ñ = N L²/EI₀,
//!   λ = (ω/ω_ref)², ω_ref = √(EI₀/(ρA)₀)/L²; Eringen's operator on the inertia
//!   and on the axial-force term, Reddy 2007 eq. 28, as the paper's model) has
//!   the exact solutions e^{±αx̃}, cos βx̃, sin βx̃. Boundary, interface and
//!   hinge conditions on (w, w', M̂ = P w'', V̂ = −P w''' + (ñ − λ m ẽ²) w') make
//!   a square matrix D(λ) whose determinant vanishes at the eigenvalues
//!   (exact dynamic stiffness); they are bracketed by sign changes on a
//!   geometric grid and bisected. The exponentials are written decaying from
//!   each segment's ends, so the string regime (α large) stays well scaled.
//! - **Damping by modal correspondence.** With the first [`BASIS_MODES`]
//!   mass-normalised undamped modes φ_j, the damped problem is projected:
//!   s² I + s c̃ I + G(s) K_b + (Λ − K_b) q = 0, G(s) = 1 + Σ Δᵢ s/(s + Ω̃ᵢ)
//!   (eq. 8–9), K_b = ∫ e φ_i'' φ_j'' (the bending energy: the only stiffness
//!   that relaxes, as in the paper's model; end and hinge springs, the axial
//!   force and the stretching of a curved tube are elastic). The viscous
//!   damping matrix is assumed c̃ M̃ (the paper's A5 for a uniform beam). The
//!   poles are the eigenvalues of the real state matrix on (q, q̇, rᵢ),
//!   ṙᵢ = Δᵢ K_b q̇ − Ω̃ᵢ rᵢ. Truncation to the basis is the one approximation;
//!   `tests/independent_generator.rs` bounds it by doubling the basis.
//! - **Initial curvature.** A shallow stress-free shape w₀(x) = h·shape(x̃) with
//!   immovable ends adds the stretching stiffness (EA/EI₀)·g gᵀ,
//!   g_j = ∫ shape'·φ_j' dx̃ (h in metres, shallow-arch theory, local).
//!
//! Lengths in nm in the public fields, everything else SI; the dimensionless
//! quantities are internal.

// each test file that includes this module uses part of it; the index loops
// below are the matrix algebra's subscripts (rows of D, basis functions, modes)
#![allow(dead_code, clippy::needless_range_loop)]

use nalgebra::{DMatrix, DVector};
use num_complex::Complex64 as C64;

/// One end of the beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum End {
    /// w = 0 and a rotational spring k (N·m/rad; 0 = pinned).
    Pinned { spring_n_m_rad: f64 },
    /// w = 0, w' = 0.
    Clamped,
    /// No support.
    Free,
}

/// The truth: geometry and material of the tube as it is (which the file may declare otherwise).
#[derive(Debug, Clone)]
pub struct Truth {
    pub length_nm: f64,
    /// Solid circle of this diameter (the section the nominal beam declares).
    pub diameter_nm: f64,
    pub youngs_modulus_pa: f64,
    pub density_kg_m3: f64,
    /// Mass per length added uniformly (adsorbate layer), relative to ρA.
    pub added_mass_fraction: f64,
    pub e0a_nm: f64,
    /// N (tension > 0).
    pub axial_force_n: f64,
    pub ends: [End; 2],
    /// (Δ, Ω rad/s) per internal variable.
    pub relaxations: Vec<(f64, f64)>,
    /// C (N·s/m²); damping matrix C/ρA·M̃.
    pub viscous_damping_n_s_m2: f64,
    /// Crack hinges: (position nm, rotational stiffness N·m/rad).
    pub hinges: Vec<(f64, f64)>,
    /// EI(x) = EI·(1 − softening·x/L) in [`SOFTENING_SEGMENTS`] steps: a tube
    /// warmer towards x = L (E falls with temperature).
    pub ei_linear_softening: f64,
    /// A tapered tube: the diameter falls linearly, d(x) = d·(1 − taper·x/L),
    /// so EI ∝ d⁴ and ρA ∝ d² (solid section, the adsorbate's mass fraction
    /// kept), in [`SOFTENING_SEGMENTS`] steps of the midpoint values.
    pub taper: f64,
    /// Initial curvature: (amplitude nm, weight of the antisymmetric sin 2πx̃ shape beside sin πx̃).
    pub curvature: Option<(f64, f64)>,
}

impl Truth {
    /// A clean simply supported tube.
    pub fn simply_supported(length_nm: f64, diameter_nm: f64, youngs_modulus_pa: f64, density_kg_m3: f64) -> Self {
        Truth {
            length_nm,
            diameter_nm,
            youngs_modulus_pa,
            density_kg_m3,
            added_mass_fraction: 0.0,
            e0a_nm: 0.0,
            axial_force_n: 0.0,
            ends: [End::Pinned { spring_n_m_rad: 0.0 }; 2],
            relaxations: vec![],
            viscous_damping_n_s_m2: 0.0,
            hinges: vec![],
            ei_linear_softening: 0.0,
            taper: 0.0,
            curvature: None,
        }
    }

    pub fn area_m2(&self) -> f64 {
        let r = 0.5 * self.diameter_nm * 1e-9;
        std::f64::consts::PI * r * r
    }

    pub fn inertia_m4(&self) -> f64 {
        let r = 0.5 * self.diameter_nm * 1e-9;
        0.25 * std::f64::consts::PI * r.powi(4)
    }

    pub fn ei(&self) -> f64 {
        self.youngs_modulus_pa * self.inertia_m4()
    }

    /// ρA of the tube itself (without the adsorbate).
    pub fn rho_a(&self) -> f64 {
        self.density_kg_m3 * self.area_m2()
    }

    /// ω_ref = √(EI/ρA)/L² of the tube itself (rad/s).
    pub fn omega_ref(&self) -> f64 {
        let l = self.length_nm * 1e-9;
        (self.ei() / self.rho_a()).sqrt() / (l * l)
    }

    /// |N_cr| of the local, uniform beam with these ends and no springs
    /// (π²EI/L² pinned–pinned, 4π² clamped–clamped, 2.0457π² clamped–pinned,
    /// π²/4 clamped–free; Timoshenko & Gere, Theory of Elastic Stability, §2).
    pub fn buckling_load_n(&self) -> f64 {
        let l = self.length_nm * 1e-9;
        let c = match self.ends {
            [End::Clamped, End::Clamped] => 4.0,
            [End::Clamped, End::Pinned { .. }] | [End::Pinned { .. }, End::Clamped] => 2.045_75,
            [End::Clamped, End::Free] | [End::Free, End::Clamped] => 0.25,
            _ => 1.0,
        };
        c * std::f64::consts::PI.powi(2) * self.ei() / (l * l)
    }
}

/// A mode of the truth: the pole s (rad/s), ω = |s|, ζ = −Re s/|s|.
#[derive(Debug, Clone, Copy)]
pub struct Pole {
    pub omega_rad_s: f64,
    pub zeta: f64,
}

/// Undamped modes kept as the basis of the damped projection.
pub const BASIS_MODES: usize = 14;

/// One uniform segment [x0, x1] (dimensionless) with stiffness and mass factors.
#[derive(Debug, Clone, Copy)]
struct Segment {
    x0: f64,
    x1: f64,
    e: f64,
    m: f64,
}

/// Steps of a softening EI: the truth's EI is the staircase of the linear
/// profile's midpoint values (the staircase is the truth, solved exactly).
const SOFTENING_SEGMENTS: usize = 16;

/// The dimensionless problem.
#[derive(Debug, Clone)]
struct Problem {
    segments: Vec<Segment>,
    /// Hinge stiffness k̃ = kL/EI₀ at the start of segment i (index i ≥ 1).
    hinge_at: Vec<Option<f64>>,
    e_tilde: f64,
    n_tilde: f64,
    ends: [(End, f64); 2],
}

impl Problem {
    fn of(t: &Truth) -> Self {
        let l = t.length_nm * 1e-9;
        let ei0 = t.ei();
        let mut cuts: Vec<f64> = vec![0.0, 1.0];
        let nseg = if t.ei_linear_softening != 0.0 || t.taper != 0.0 { SOFTENING_SEGMENTS } else { 1 };
        cuts.extend((1..nseg).map(|i| i as f64 / nseg as f64));
        cuts.extend(t.hinges.iter().map(|&(x, _)| x / t.length_nm));
        cuts.sort_by(f64::total_cmp);
        cuts.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        let m = 1.0 + t.added_mass_fraction;
        let segments: Vec<Segment> = cuts
            .windows(2)
            .map(|w| {
                let x = 0.5 * (w[0] + w[1]);
                let d = 1.0 - t.taper * x;
                Segment { x0: w[0], x1: w[1], e: (1.0 - t.ei_linear_softening * x) * d.powi(4), m: m * d * d }
            })
            .collect();
        let hinge_at = segments
            .iter()
            .map(|s| {
                t.hinges
                    .iter()
                    .find(|&&(x, _)| (x / t.length_nm - s.x0).abs() < 1e-12 && s.x0 > 0.0)
                    .map(|&(_, k)| k * l / ei0)
            })
            .collect();
        let spring = |e: End| match e {
            End::Pinned { spring_n_m_rad } => spring_n_m_rad * l / ei0,
            _ => 0.0,
        };
        Problem {
            segments,
            hinge_at,
            e_tilde: t.e0a_nm / t.length_nm,
            n_tilde: t.axial_force_n * l * l / ei0,
            ends: [(t.ends[0], spring(t.ends[0])), (t.ends[1], spring(t.ends[1]))],
        }
    }

    /// (α, β) of a segment at λ: the roots ±α, ±iβ of P r⁴ + Q r² − R = 0.
    fn roots(&self, s: &Segment, lambda: f64) -> (f64, f64, f64) {
        let e2 = self.e_tilde * self.e_tilde;
        let p = s.e + self.n_tilde * e2;
        let q = lambda * s.m * e2 - self.n_tilde;
        let r = lambda * s.m;
        let disc = (q * q + 4.0 * p * r).sqrt();
        // α² = (−q + disc)/2p, β² = (q + disc)/2p, each written without cancellation
        let (a2, b2) = if q >= 0.0 {
            (2.0 * r / (q + disc), (q + disc) / (2.0 * p))
        } else {
            ((disc - q) / (2.0 * p), 2.0 * r / (disc - q))
        };
        (a2.sqrt(), b2.sqrt(), p)
    }

    /// Values (w, w', w'', w''') of the 4 basis functions of segment `s` at x:
    /// e^{α(x−x1)}, e^{−α(x−x0)}, cos β(x−x0), sin β(x−x0).
    fn basis(&self, s: &Segment, lambda: f64, x: f64) -> [[f64; 4]; 4] {
        let (a, b, _) = self.roots(s, lambda);
        let (u, v) = ((a * (x - s.x1)).exp(), (-a * (x - s.x0)).exp());
        let (c, sn) = ((b * (x - s.x0)).cos(), (b * (x - s.x0)).sin());
        let mut out = [[0.0; 4]; 4];
        for d in 0..4 {
            let ad = a.powi(d as i32);
            let bd = b.powi(d as i32);
            out[d][0] = ad * u;
            out[d][1] = if d % 2 == 0 { ad * v } else { -ad * v };
            // derivatives of cos and sin cycle: cos → −sin → −cos → sin
            let (dc, ds) = match d {
                0 => (c, sn),
                1 => (-sn, c),
                2 => (-c, -sn),
                _ => (sn, -c),
            };
            out[d][2] = bd * dc;
            out[d][3] = bd * ds;
        }
        out
    }

    /// Rows (w, w', M̂, V̂) of segment `s` at x, as coefficients of its 4 basis functions.
    fn state(&self, s: &Segment, lambda: f64, x: f64) -> [[f64; 4]; 4] {
        let d = self.basis(s, lambda, x);
        let (_, _, p) = self.roots(s, lambda);
        let shear = self.n_tilde - lambda * s.m * self.e_tilde * self.e_tilde;
        let mut out = [[0.0; 4]; 4];
        for k in 0..4 {
            out[0][k] = d[0][k];
            out[1][k] = d[1][k];
            out[2][k] = p * d[2][k];
            out[3][k] = -p * d[3][k] + shear * d[1][k];
        }
        out
    }

    /// D(λ): 4 unknowns per segment; 2 rows per end, 4 per interface.
    fn matrix(&self, lambda: f64) -> DMatrix<f64> {
        let ns = self.segments.len();
        let mut d = DMatrix::<f64>::zeros(4 * ns, 4 * ns);
        let mut row = 0;
        let end_rows =
            |d: &mut DMatrix<f64>, row: &mut usize, seg: usize, st: [[f64; 4]; 4], end: (End, f64), sign: f64| {
                let rows: [[f64; 4]; 2] = match end.0 {
                    End::Clamped => [st[0], st[1]],
                    End::Free => [st[2], st[3]],
                    // sign·M̂ + k̃ w' = 0 (sign −1 at x = 0, +1 at x = 1: the weak form's boundary terms)
                    End::Pinned { .. } => [st[0], std::array::from_fn(|k| sign * st[2][k] + end.1 * st[1][k])],
                };
                for r in rows {
                    for k in 0..4 {
                        d[(*row, 4 * seg + k)] = r[k];
                    }
                    *row += 1;
                }
            };
        let first = &self.segments[0];
        end_rows(&mut d, &mut row, 0, self.state(first, lambda, first.x0), self.ends[0], -1.0);
        for i in 1..ns {
            let (l, r) = (&self.segments[i - 1], &self.segments[i]);
            let (sl, sr) = (self.state(l, lambda, l.x1), self.state(r, lambda, r.x0));
            for q in 0..4 {
                for k in 0..4 {
                    d[(row, 4 * (i - 1) + k)] = sl[q][k];
                    d[(row, 4 * i + k)] = -sr[q][k];
                }
                if q == 1 {
                    if let Some(kh) = self.hinge_at[i] {
                        // w'⁺ − w'⁻ = M̂/k̃: the row reads w'⁻ − w'⁺ + M̂⁻/k̃ = 0
                        for k in 0..4 {
                            d[(row, 4 * (i - 1) + k)] += sl[2][k] / kh;
                        }
                    }
                }
                row += 1;
            }
        }
        let last = &self.segments[ns - 1];
        end_rows(&mut d, &mut row, ns - 1, self.state(last, lambda, last.x1), self.ends[1], 1.0);
        // rows scaled to unit max norm (the sign of the determinant is unchanged)
        for r in 0..d.nrows() {
            let m = d.row(r).amax();
            if m > 0.0 {
                d.row_mut(r).scale_mut(1.0 / m);
            }
        }
        d
    }

    /// The damped dynamic stiffness D(s̃) (complex s̃): on each segment
    /// P w'''' − (ñ + I ẽ²) w'' + I w = 0 with P = G(s̃) e + ñ ẽ², I = (s̃² + c̃ s̃) m,
    /// G = 1 + Σ Δᵢ s̃/(s̃ + Ω̃ᵢ); M̂ = P w'', V̂ = −P w''' + (ñ + I ẽ²) w'. The basis
    /// is e^{±√μ₁ ξ} (decaying from each end) for the root μ₁ of P μ² − (ñ + Iẽ²) μ + I = 0
    /// with the larger real part, and cosh(√μ₂ ξ), sinh(√μ₂ ξ)/√μ₂ (entire in μ₂,
    /// so D is analytic across the negative real axis where μ₂ lies) for the other.
    fn matrix_c(&self, ivs: &[(f64, f64)], c: f64, s: C64) -> DMatrix<C64> {
        let g = ivs.iter().fold(C64::new(1.0, 0.0), |g, &(d, om)| g + d * s / (s + om));
        let e2 = self.e_tilde * self.e_tilde;
        let ns = self.segments.len();
        let state = |seg: &Segment, x: f64| -> [[C64; 4]; 4] {
            let p = g * seg.e + self.n_tilde * e2;
            let inertia = (s * s + c * s) * seg.m;
            let b = inertia * e2 + self.n_tilde;
            let disc = (b * b - 4.0 * p * inertia).sqrt();
            let (m1, m2) = ((b + disc) / (2.0 * p), (b - disc) / (2.0 * p));
            let (mu1, mu2) = if m1.re >= m2.re { (m1, m2) } else { (m2, m1) };
            let a = mu1.sqrt();
            let (u, v) = ((a * (x - seg.x1)).exp(), (-a * (x - seg.x0)).exp());
            let xi = x - seg.x0;
            let q = mu2.sqrt();
            let (ch, sh) = ((q * xi).cosh(), (q * xi).sinh());
            // sinh(qξ)/q without the division at q → 0
            let shq = if q.norm() * xi.abs() < 1e-8 { C64::new(xi, 0.0) } else { sh / q };
            // derivatives 0..3 of each basis function
            let d: [[C64; 4]; 4] = [
                [u, v, ch, shq],
                [a * u, -a * v, q * sh, ch],
                [a * a * u, a * a * v, mu2 * ch, q * sh],
                [a * a * a * u, -a * a * a * v, mu2 * q * sh, mu2 * ch],
            ];
            let mut out = [[C64::new(0.0, 0.0); 4]; 4];
            for k in 0..4 {
                out[0][k] = d[0][k];
                out[1][k] = d[1][k];
                out[2][k] = p * d[2][k];
                out[3][k] = -p * d[3][k] + b * d[1][k];
            }
            out
        };
        let mut dm = DMatrix::<C64>::zeros(4 * ns, 4 * ns);
        let mut row = 0;
        let put = |dm: &mut DMatrix<C64>, row: &mut usize, seg: usize, r: [C64; 4]| {
            for k in 0..4 {
                dm[(*row, 4 * seg + k)] = r[k];
            }
            *row += 1;
        };
        let end = |st: [[C64; 4]; 4], end: (End, f64), sign: f64| -> [[C64; 4]; 2] {
            match end.0 {
                End::Clamped => [st[0], st[1]],
                End::Free => [st[2], st[3]],
                End::Pinned { .. } => [st[0], std::array::from_fn(|k| st[2][k] * sign + st[1][k] * end.1)],
            }
        };
        let first = &self.segments[0];
        for r in end(state(first, first.x0), self.ends[0], -1.0) {
            put(&mut dm, &mut row, 0, r);
        }
        for i in 1..ns {
            let (l, r) = (&self.segments[i - 1], &self.segments[i]);
            let (sl, sr) = (state(l, l.x1), state(r, r.x0));
            for q in 0..4 {
                for k in 0..4 {
                    dm[(row, 4 * (i - 1) + k)] = sl[q][k];
                    dm[(row, 4 * i + k)] = -sr[q][k];
                }
                if q == 1 {
                    if let Some(kh) = self.hinge_at[i] {
                        for k in 0..4 {
                            dm[(row, 4 * (i - 1) + k)] += sl[2][k] / kh;
                        }
                    }
                }
                row += 1;
            }
        }
        let last = &self.segments[ns - 1];
        for r in end(state(last, last.x1), self.ends[1], 1.0) {
            put(&mut dm, &mut row, ns - 1, r);
        }
        // no row scaling here: a scaling by entry magnitudes is not analytic in s̃ and would slow the secant
        dm
    }

    /// The zero of det D(s̃) nearest the projection's pole `s0` (secant
    /// iteration on det D, which is analytic near a simple zero; 60 steps at
    /// most, stopped at |Δs| ≤ 1e-13|s|). Panics when it does not converge
    /// (a generator that cannot place its own pole).
    fn refine(&self, ivs: &[(f64, f64)], c: f64, s0: C64) -> C64 {
        let f = |s: C64| self.matrix_c(ivs, c, s).lu().determinant();
        let (mut a, mut b) = (s0, s0 * (1.0 + 1e-6));
        let (mut fa, mut fb) = (f(a), f(b));
        for _ in 0..60 {
            let step = fb * (b - a) / (fb - fa);
            let next = b - step;
            if step.norm() <= 1e-13 * b.norm() {
                assert!((next - s0).norm() < 0.05 * s0.norm(), "refined pole {next} far from the projection's {s0}");
                return next;
            }
            (a, fa) = (b, fb);
            b = next;
            fb = f(b);
        }
        panic!("independent generator: the pole near {s0} did not converge");
    }

    fn det(&self, lambda: f64) -> f64 {
        self.matrix(lambda).lu().determinant()
    }

    /// The lowest `n` eigenvalues λ (bracketed on a geometric grid of ω̃ = √λ, bisected to rounding).
    fn eigenvalues(&self, n: usize) -> Vec<f64> {
        let mut found = Vec::new();
        // ω̃₁ ≥ 0.5 for every beam the generator builds (a cantilever's is 3.5);
        // neighbouring ω̃ differ by ≥ 7 % (a string's 15th against its 14th),
        // so a 1 % grid brackets each root once
        let mut w = 0.5;
        let ratio = 1.01;
        let mut f = self.det(w * w);
        while found.len() < n {
            let w2 = w * ratio;
            let f2 = self.det(w2 * w2);
            assert!(w2 < 1e7, "independent generator: fewer than {n} modes below ω̃ = 1e7");
            if f.signum() != f2.signum() {
                let (mut a, mut b, mut fa) = (w, w2, f);
                for _ in 0..200 {
                    let c = 0.5 * (a + b);
                    if c <= a || c >= b {
                        break;
                    }
                    let fc = self.det(c * c);
                    if fc.signum() == fa.signum() {
                        a = c;
                        fa = fc;
                    } else {
                        b = c;
                    }
                }
                let root = 0.5 * (a + b);
                found.push(root * root);
            }
            w = w2;
            f = f2;
        }
        found
    }

    /// The mode shape at λ: the coefficient vector spanning D(λ)'s null space.
    fn shape(&self, lambda: f64) -> DVector<f64> {
        let svd = self.matrix(lambda).svd(false, true);
        let vt = svd.v_t.expect("v_t requested");
        let (k, _) = svd.singular_values.iter().enumerate().min_by(|a, b| a.1.total_cmp(b.1)).expect("non-empty");
        vt.row(k).transpose()
    }

    /// (w, w', w'') of a mode with coefficients `c` at x in segment i.
    fn eval(&self, i: usize, c: &DVector<f64>, lambda: f64, x: f64) -> [f64; 3] {
        let d = self.basis(&self.segments[i], lambda, x);
        std::array::from_fn(|q| (0..4).map(|k| d[q][k] * c[4 * i + k]).sum())
    }
}

/// Simpson panels per segment for the modal integrals (error O(h⁴) of the
/// integrand's 4th derivative: ≤ 1e-10 relative for the basis's wavenumbers
/// ≤ 60 at 400 panels per unit length).
const PANELS_PER_UNIT: usize = 400;

/// Samples of every basis mode on a Simpson grid: (weights, m·ẽ factor, e, [w, w', w''] per mode).
struct Sampled {
    weights: Vec<f64>,
    mass: Vec<f64>,
    stiffness: Vec<f64>,
    x: Vec<f64>,
    modes: Vec<Vec<[f64; 3]>>,
}

fn sample_modes(p: &Problem, lambdas: &[f64]) -> Sampled {
    let shapes: Vec<DVector<f64>> = lambdas.iter().map(|&l| p.shape(l)).collect();
    let mut s =
        Sampled { weights: vec![], mass: vec![], stiffness: vec![], x: vec![], modes: vec![vec![]; lambdas.len()] };
    for (i, seg) in p.segments.iter().enumerate() {
        let panels = 2 * ((PANELS_PER_UNIT as f64 * (seg.x1 - seg.x0) / 2.0).ceil() as usize).max(4);
        let h = (seg.x1 - seg.x0) / panels as f64;
        for j in 0..=panels {
            let x = seg.x0 + j as f64 * h;
            let w = if j == 0 || j == panels {
                1.0
            } else if j % 2 == 1 {
                4.0
            } else {
                2.0
            };
            s.weights.push(w * h / 3.0);
            s.mass.push(seg.m);
            s.stiffness.push(seg.e);
            s.x.push(x);
            for (k, c) in shapes.iter().enumerate() {
                s.modes[k].push(p.eval(i, c, lambdas[k], x));
            }
        }
    }
    // mass-normalise: ∫ m (w² + ẽ² w'²) = 1
    let e2 = p.e_tilde * p.e_tilde;
    for k in 0..lambdas.len() {
        let mk: f64 = s.modes[k]
            .iter()
            .zip(&s.weights)
            .zip(&s.mass)
            .map(|((v, w), m)| w * m * (v[0] * v[0] + e2 * v[1] * v[1]))
            .sum();
        let f = 1.0 / mk.sqrt();
        s.modes[k].iter_mut().for_each(|v| v.iter_mut().for_each(|a| *a *= f));
    }
    s
}

/// The lowest `n` undamped frequencies of the truth (rad/s): relaxed modulus, no damping, no curvature.
pub fn undamped_omegas(t: &Truth, n: usize) -> Vec<f64> {
    let p = Problem::of(t);
    p.eigenvalues(n).iter().map(|l| l.sqrt() * t.omega_ref()).collect()
}

/// The lowest `n` poles of the truth: the projection on `basis` undamped
/// modes, then (without curvature) each pole refined to a zero of the damped
/// dynamic stiffness [`Problem::refine`]. The projection alone converges
/// slowly where an elastic spring or hinge meets the relaxing bending (the
/// elastic modes satisfy M̂ = k w' with the relaxed modulus, the damped mode
/// with G(s)·EI: 0.13 % in ω₁ and 3 % in ζ₁ between 14 and 28 modes on a
/// one-end spring and a hinge); on a curved simply supported tube it is
/// exact (the sine modes satisfy every boundary condition and the
/// curvature's shape couples only the first two).
pub fn poles_with_basis(t: &Truth, n: usize, basis: usize) -> Vec<Pole> {
    assert!(basis >= n, "the basis must hold the modes asked for");
    let p = Problem::of(t);
    let lambdas = p.eigenvalues(basis);
    let s = sample_modes(&p, &lambdas);
    let nb = basis;
    // K_b = ∫ e φ_i'' φ_j'' ; Λ = diag(λ) (+ curvature stretching)
    let mut kb = DMatrix::<f64>::zeros(nb, nb);
    for i in 0..nb {
        for j in 0..=i {
            let v: f64 =
                (0..s.weights.len()).map(|q| s.weights[q] * s.stiffness[q] * s.modes[i][q][2] * s.modes[j][q][2]).sum();
            kb[(i, j)] = v;
            kb[(j, i)] = v;
        }
    }
    let mut total = DMatrix::<f64>::from_diagonal(&DVector::from_vec(lambdas.clone()));
    if let Some((h_nm, anti)) = t.curvature {
        // shape' of sin πx̃ + anti·sin 2πx̃, amplitude h (m); EA/EI₀ in 1/m²
        let pi = std::f64::consts::PI;
        let g: Vec<f64> = (0..nb)
            .map(|j| {
                (0..s.weights.len())
                    .map(|q| {
                        let x = s.x[q];
                        let d0 = pi * (pi * x).cos() + anti * 2.0 * pi * (2.0 * pi * x).cos();
                        s.weights[q] * d0 * s.modes[j][q][1]
                    })
                    .sum()
            })
            .collect();
        let kappa = t.youngs_modulus_pa * t.area_m2() / t.ei() * (h_nm * 1e-9).powi(2);
        for i in 0..nb {
            for j in 0..nb {
                total[(i, j)] += kappa * g[i] * g[j];
            }
        }
    }
    let ku = &total - &kb;
    let ivs: Vec<(f64, f64)> = t.relaxations.iter().map(|&(d, w)| (d, w / t.omega_ref())).collect();
    let c = t.viscous_damping_n_s_m2 / (t.rho_a() * t.omega_ref());
    // state (q, v, r_1..r_N): q̇ = v; v̇ = −(K_b + K_u) q − c v − Σ r; ṙᵢ = Δᵢ K_b v − Ω̃ᵢ rᵢ
    let dim = (2 + ivs.len()) * nb;
    let mut a = DMatrix::<f64>::zeros(dim, dim);
    for i in 0..nb {
        a[(i, nb + i)] = 1.0;
        a[(nb + i, nb + i)] = -c;
        for j in 0..nb {
            a[(nb + i, j)] = -(kb[(i, j)] + ku[(i, j)]);
        }
        for (r, &(delta, om)) in ivs.iter().enumerate() {
            let o = (2 + r) * nb;
            a[(nb + i, o + i)] = -1.0;
            a[(o + i, o + i)] = -om;
            for j in 0..nb {
                a[(o + i, nb + j)] = delta * kb[(i, j)];
            }
        }
    }
    // the relaxation blocks put clusters of real eigenvalues near −Ω̃ᵢ, which
    // the eigensolver returns split into pairs with Im ≈ 1e-7|s|: a pole is
    // oscillatory when ζ < 0.9 (every beam mode here has ζ < 0.3)
    let mut poles: Vec<num_complex::Complex<f64>> =
        a.complex_eigenvalues().iter().copied().filter(|z| z.im > 0.0 && -z.re < 0.9 * z.norm()).collect();
    poles.sort_by(|x, y| x.im.total_cmp(&y.im));
    let exact = t.curvature.is_none();
    poles
        .iter()
        .take(n)
        .map(|&z| {
            let z = if exact { p.refine(&ivs, c, z) } else { z } * t.omega_ref();
            Pole { omega_rad_s: z.norm(), zeta: -z.re / z.norm() }
        })
        .collect()
}

/// The lowest `n` poles of the truth ([`poles_with_basis`] with [`BASIS_MODES`]).
pub fn poles(t: &Truth, n: usize) -> Vec<Pole> {
    poles_with_basis(t, n, BASIS_MODES.max(n + 6))
}
