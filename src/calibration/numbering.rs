//! Physical mode numbers for identified frequencies, over the base model's
//! whole prior (issue 67). The face is `calibration::identified::number_modes`;
//! this file holds the family of beams and the search.
//!
//! # The family
//! The `--beam` file is the nominal beam; a diagnosis will free it where the
//! base model and its causes do, and each of these freedoms moves the modes'
//! spacing, not only their level:
//! - e0a over the default prior ([`E0A_RANGE_NM`], `ParameterSet::paper_n1`);
//! - shear deformation from none to the `shear-deformation` cause's softest
//!   (κ = [`SHEAR_COEFFICIENT_PRIOR`]'s lower end at ν = [`DEFAULT_POISSON_RATIO`]);
//! - the paper's N = 1 internal variable (δ, Ω) over `paper_n1`'s prior
//!   (δ ∈ [0, 1], Ω ∈ [0, 1e13] rad/s);
//! - the nominal section, a factor f on EI/ρA over [`SECTION_FACTOR_RANGE`].
//!
//! Each range is widened to hold the file's own value. One beam of the family
//! has one value of each for all its modes.
//!
//! **The relaxation in closed form.** The relaxation factor multiplies the
//! whole elastic stiffness (bending and shear: `beam::ShearDeformation`), so
//! the pencil s²M + (1 + δ s/(s + Ω)) K = 0 shares the elastic pencil's
//! eigenvectors, and each elastic mode λ = ω_e² gives the cubic
//! s³ + Ω s² + λ(1 + δ) s + λΩ = 0. In u = s/ω_e and r = Ω/ω_e:
//! u³ + r u² + (1 + δ) u + r = 0, whose real root u₀ lies in [−r, 0]
//! (f(−r) = −δr ≤ 0 < f(0) = r), and the oscillatory pair has
//! |u|² = −r/u₀ (the product of the roots is −r). So |s| = ω_e √(−r/u₀):
//! modes far below Ω keep ω_e, modes far above it are stiffened by √(1 + δ)
//! (up to 1.41 over the prior: 0.35 in ln ω), and a relaxation between two
//! modes opens a gap in the spacing there. Exact for the mesh when the file
//! has no support springs and no axial force (elastic, not relaxed); with
//! them, the closed form is a model of the family, not the mesh.
//!
//! **The section in closed form.** f scales the whole stiffness, so |s| of
//! (f, Ω) is √f times |s| of (1, Ω/√f) (substitute s = √f u in the cubic): a
//! common ln-offset c = ½ ln f over the family's Ω' = Ω/√f. The offset is
//! fitted exactly for each numbering (the mean residual, clamped to its
//! range); Ω' spans [0, Ω_max/√f_min], a little more than the prior.
//!
//! **The elastic modes.** ln ω_e of each mode is smooth in u = e0a² and in the
//! shear compliance s = E/(κG) over the Timoshenko range (κ from 1 to the
//! prior's 0.3 at ν = 0.2, s in [2.4, 8]); the Euler–Bernoulli beam (no shear,
//! no rotary inertia: not the s → 0 limit of the Timoshenko beam, whose
//! rotary inertia stays) is a piece of its own. 1/ω_e² is interpolated by
//! a Lagrange polynomial on [`NODES`] Chebyshev–Lobatto points in e0a²
//! (Euler–Bernoulli) and on [`NODES`] × [`NODES`] in (e0a², s) (Timoshenko),
//! each a modal solve of the elastic nominal beam (internal variables and
//! viscous damping removed: viscous damping does not move |s|). Each
//! interpolant is checked against direct solves at its cells' midpoints;
//! twice the largest difference in ln ω is each mode's interpolation bound
//! (the factor 2: an analytic function's interpolation error between check
//! points stays within a small factor of its value at them; Trefethen, ATAP
//! ch. 7–8, as `beam::spectrum` certifies its own). 4 + 3 + 16 + 9 = 32
//! modal solves per numbering instead of one per grid point (697 in the
//! e0a-and-shear version this replaced). Measured bound on the cc7 tube:
//! 3e-5 to 2e-3 over modes 1–10.
//!
//! # The search
//! The numberings are the order-preserving one-to-one maps of the K
//! identified modes (sorted) to the first [`predicted_count`] predicted
//! ones (K + [`EXTRA_PREDICTED`], twice the spare for a sparse record of at
//! most [`SPARSE_RECORD`] modes) with at most [`MAX_SKIPS`] predicted modes
//! skipped between the first and the last (a node at the sensor, a line
//! lost in its neighbours' noise). Each numbering's cost is its least
//! Σᵢ (ln ωᵢ − ln ω_{mᵢ}(θ) − c)² over a grid of θ = (e0a, s, δ, Ω') with c
//! exact ([`GRID`]), then, for every numbering the grid cannot rule out
//! (below), a Nelder–Mead refinement over the continuous family from its
//! grid minimum ([`REFINE_EVALUATIONS`] evaluations, simplex steps one grid
//! step).
//!
//! **What the grid may hide.** A numbering's cost over the continuous family
//! is lower than over the grid. The interpolation bound eᵢ per mode moves
//! the cost's root by at most ‖e‖; and the Gauss–Newton bound of the grid
//! step: near the continuous minimum the cost rises as ‖(I − P)J δθ‖² (the
//! gradient vanishes there; P the projection the fitted offset c removes),
//! and the nearest grid point is within half a step in each coordinate, so
//! the excess is at most (Σ_d ½ ‖(I − P)Δ_d‖)², Δ_d the largest move of the
//! numbering's ln ω to a neighbouring grid point along coordinate d. A
//! numbering whose grid lower bound stays beyond the margin of the best
//! upper bound is ruled out without refinement; the others (and the best
//! numbering from every lowest mode) are refined, and their bounds are then
//! the refined cost's root ± ‖e‖. The refinement is local: a basin the grid
//! misses entirely is not searched (the grid's steps are what a basin must
//! be wider than).
//!
//! **Ambiguity.** The numbering with the least cost is the candidate. Every
//! other numbering whose cost's lower bound exceeds the candidate's upper
//! bound by less than the margin squared also fits a beam of the prior: the
//! numbering is refused, naming the lowest identified mode, both numberings
//! and what would decide. The margin is [`AMBIGUITY_MARGIN`], what the
//! family leaves out (springs, a point mass, tension, a nanotube's
//! atomistic departures from a beam); [`SKIP_MARGIN`] for an alternative
//! with more skipped modes; either widened to 3 noise sd of the modes the
//! two number differently when the identified σ are given
//! (`calibration::identified`).
//!
//! **`--first-mode N`** is checked, not trusted: the numberings from N are
//! searched as above. When the best of them exceeds the best of all by
//! [`FIRST_MODE_TOLERANCE`] or more (bounds as above), no beam of the prior
//! fits N and it is refused; by the margin or more, it is taken with a
//! warning. Among the numberings from N the consecutive one (no skip) is
//! taken when it is within the margin of the best from N; otherwise the
//! best from N, which must be unambiguous.

use rayon::prelude::*;

use crate::bayes::prior::Prior;
use crate::beam::{modal, BeamSpec, ShearDeformation};
use crate::calibration::parameters::{
    ParameterSet, DEFAULT_POISSON_RATIO, SECTION_FACTOR_RANGE, SHEAR_COEFFICIENT_PRIOR,
};
use crate::error::InputError;

/// Least extra root summed squared ln-misfit of an alternative numbering over
/// the chosen one (see the module doc): 0.05 is one mode misplaced by 5 %.
pub const AMBIGUITY_MARGIN: f64 = 0.05;
/// A stated `--first-mode` whose best numbering exceeds the best of all by
/// this much (root summed squared ln-misfit, lower bound) fits no beam of the
/// prior and is refused: one mode misplaced by 20 %, four times the margin.
pub const FIRST_MODE_TOLERANCE: f64 = 0.2;
/// Predicted modes beyond the identified count that a numbering may use.
pub const EXTRA_PREDICTED: usize = 4;
/// Records of at most this many modes get [`EXTRA_PREDICTED`] more spare
/// predicted modes: a sparse record (nodes at the sensor, lines lost in the
/// noise) may start above mode 1 and skip as many as [`MAX_SKIPS`] (3 modes
/// out of modes 1-8 are numbered against 11), and few modes make few
/// numberings.
pub const SPARSE_RECORD: usize = 5;

/// The predicted modes a numbering of `k` identified modes may use, the
/// lowest of them stated as `first` (1-based) or not.
pub fn predicted_count(k: usize, first: Option<usize>) -> usize {
    let spare = if k <= SPARSE_RECORD { 2 * EXTRA_PREDICTED } else { EXTRA_PREDICTED };
    k + spare + first.unwrap_or(1) - 1
}
/// Most predicted modes a numbering may skip between its first and last mode
/// (all the spare ones).
pub const MAX_SKIPS: usize = EXTRA_PREDICTED;
/// The margin for an alternative with more skipped modes than the chosen
/// numbering. Within the prior a true numbering fits to the noise (the
/// interpolation bound is already in [`extra`]'s bounds): σ ≈ 1e-3 per mode
/// gives a root summed squared misfit ≈ σ√K ≤ 0.0035 for K ≤ 12, so an
/// alternative with more skips that fits within 0.01 (about 3× that) may be
/// the truth; one that needs more needs the model's departures and a reason
/// for each skip. Measured: the paper's beam's modes 1-6 against modes
/// 1-5, 7 at 0.019 (`tests/identify_cli.rs`), cc7's at 0.042.
pub const SKIP_MARGIN: f64 = 0.01;
/// The e0a range (nm) the numbering considers: the default prior's.
pub const E0A_RANGE_NM: (f64, f64) = (0.0, 2.0);
/// Interpolation nodes per coordinate (e0a², shear compliance) of the elastic modes.
pub const NODES: usize = 4;
/// Grid points of θ: e0a (uniform), shear compliance (uniform), ln(1 + δ)
/// (uniform), Ω' (0 and then [`OMEGA_PER_DECADE`] per decade, log-uniform).
pub const GRID: [usize; 3] = [21, 9, 7];
/// Grid points of Ω' per decade.
pub const OMEGA_PER_DECADE: f64 = 6.0;

/// The prior the numbering searches, widened to hold the file's values.
#[derive(Debug, Clone, Copy)]
struct Ranges {
    e0a_nm: (f64, f64),
    /// Shear compliance E/(κG) of the Timoshenko beams (with the
    /// Euler–Bernoulli beam, no shear and no rotary inertia, beside them).
    compliance: (f64, f64),
    delta_max: f64,
    omega_max_rad_s: f64,
    /// c = ½ ln f over the section factor's range.
    offset: (f64, f64),
}

impl Ranges {
    fn of(beam: &BeamSpec) -> Self {
        let prior = ParameterSet::paper_n1();
        let upper = |name: &str, fallback: f64| {
            prior
                .params
                .iter()
                .find(|p| p.name == name)
                .and_then(|p| match p.prior {
                    Prior::Uniform { upper, .. } => Some(upper),
                    _ => None,
                })
                .unwrap_or(fallback)
        };
        let file_delta = beam.internal_variables.iter().map(|v| v.delta).fold(0.0, f64::max);
        let file_omega = beam.internal_variables.iter().map(|v| v.omega_rad_s).fold(0.0, f64::max);
        let file_compliance = beam.shear_deformation.map_or(0.0, |sd| 1.0 / sd.shear_to_youngs());
        Ranges {
            e0a_nm: (E0A_RANGE_NM.0.min(beam.nonlocal_e0a_nm), E0A_RANGE_NM.1.max(beam.nonlocal_e0a_nm)),
            compliance: (
                match file_compliance {
                    c if c > 0.0 => c.min(2.0 * (1.0 + DEFAULT_POISSON_RATIO) / SHEAR_COEFFICIENT_PRIOR.1),
                    _ => 2.0 * (1.0 + DEFAULT_POISSON_RATIO) / SHEAR_COEFFICIENT_PRIOR.1,
                },
                (2.0 * (1.0 + DEFAULT_POISSON_RATIO) / SHEAR_COEFFICIENT_PRIOR.0).max(file_compliance),
            ),
            delta_max: upper("delta", 1.0).max(file_delta),
            omega_max_rad_s: upper("omega_rad_s", 1e13).max(file_omega),
            offset: (0.5 * SECTION_FACTOR_RANGE.0.ln(), 0.5 * SECTION_FACTOR_RANGE.1.ln()),
        }
    }

    fn text(&self) -> String {
        format!(
            "e0a in [{}, {}] nm, Euler-Bernoulli or shear kappaG/E in [{:.3}, {:.3}], a relaxation delta <= {} at Omega <= {:.3e} rad/s, section factor on EI/rhoA in [{:.3}, {:.3}]",
            self.e0a_nm.0,
            self.e0a_nm.1,
            1.0 / self.compliance.1,
            1.0 / self.compliance.0,
            self.delta_max,
            self.omega_max_rad_s,
            (2.0 * self.offset.0).exp(),
            (2.0 * self.offset.1).exp()
        )
    }
}

/// Shear deformation of compliance s = E/(κG) > 0 as a beam field. Only κG/E
/// = κ/(2(1 + ν)) = 1/s enters the pencil, so ν = [`DEFAULT_POISSON_RATIO`]
/// where that gives κ ≤ 1, and κ = 1 with the ν that gives 1/s where it
/// does not (s < 2(1 + ν), stiffer shear than any section's).
fn shear_of_compliance(s: f64) -> ShearDeformation {
    let nu = DEFAULT_POISSON_RATIO;
    let kappa = 2.0 * (1.0 + nu) / s;
    if kappa <= 1.0 {
        ShearDeformation { poisson_ratio: nu, shear_coefficient: kappa }
    } else {
        ShearDeformation { poisson_ratio: s / 2.0 - 1.0, shear_coefficient: 1.0 }
    }
}

/// ln(|s|/ω_e) of the oscillatory pole of an elastic mode ω_e under one
/// internal variable (δ, r = Ω/ω_e); NaN when the mode is overdamped.
pub fn relaxation_shift(delta: f64, r: f64) -> f64 {
    if delta == 0.0 {
        return 0.0;
    }
    if r == 0.0 {
        return 0.5 * (1.0 + delta).ln();
    }
    let f = |u: f64| ((u + r) * u + 1.0 + delta) * u + r;
    let (mut lo, mut hi) = (-r, 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let u0 = 0.5 * (lo + hi);
    let (b, c) = (r + u0, -r / u0);
    if b * b >= 4.0 * c || u0 >= 0.0 {
        return f64::NAN;
    }
    0.5 * c.ln()
}

/// The family: predicted ln |s| of the first `n` modes at every grid point.
pub(crate) struct Family {
    /// `n` values per grid point, grid point index ((e·S + s)·D + d)·W + w.
    pred: Vec<f64>,
    n: usize,
    dims: [usize; 4],
    /// Interpolation bound of each mode's ln ω.
    interp: Vec<f64>,
    offset: (f64, f64),
    /// The elastic interpolant: nodes in e0a² and compliance, 1/ω² at the
    /// Euler–Bernoulli nodes (first [`NODES`]) and the Timoshenko ones (from `timoshenko`).
    u_nodes: Vec<f64>,
    s_nodes: Vec<f64>,
    inverse: Vec<Vec<f64>>,
    timoshenko: usize,
    /// The grid's coordinates: e0a, compliance (0 = Euler–Bernoulli),
    /// ln(1 + δ), ln Ω' (−∞ = Ω' = 0).
    axes: [Vec<f64>; 4],
}

fn chebyshev_lobatto(lo: f64, hi: f64, n: usize, i: usize) -> f64 {
    let x = -(std::f64::consts::PI * i as f64 / (n - 1) as f64).cos();
    0.5 * (lo + hi) + 0.5 * (hi - lo) * x
}

/// Lagrange basis weights of `x` on `nodes`.
fn lagrange(nodes: &[f64], x: f64) -> Vec<f64> {
    (0..nodes.len())
        .map(|i| (0..nodes.len()).filter(|&j| j != i).map(|j| (x - nodes[j]) / (nodes[i] - nodes[j])).product::<f64>())
        .collect()
}

/// ln ω_e of mode `j` at e0a² = `u` and compliance `s` from the interpolant:
/// 1/ω² at the Euler–Bernoulli nodes (the first [`NODES`] rows of
/// `inverse`, for s = 0) or the Timoshenko tensor nodes (from row `timoshenko`).
fn interpolate_log(
    u_nodes: &[f64],
    s_nodes: &[f64],
    inverse: &[Vec<f64>],
    timoshenko: usize,
    u: f64,
    s: f64,
    j: usize,
) -> f64 {
    let wu = lagrange(u_nodes, u);
    let y: f64 = if s == 0.0 {
        wu.iter().zip(inverse).map(|(w, row)| w * row[j]).sum()
    } else {
        let ws = lagrange(s_nodes, s);
        wu.iter()
            .enumerate()
            .map(|(a, wa)| {
                ws.iter().enumerate().map(|(b, wb)| wa * wb * inverse[timoshenko + a * NODES + b][j]).sum::<f64>()
            })
            .sum()
    };
    -0.5 * y.ln()
}

impl Family {
    /// The least ln ω of mode 1 and the greatest of the last predicted mode
    /// over the grid, the section's offsets included: where the family's
    /// modes lie (issue 69, defect 6: a record's lines decades from them).
    pub(crate) fn ln_span(&self) -> (f64, f64) {
        let points = self.pred.chunks(self.n);
        let lo = points.clone().map(|p| p[0]).fold(f64::INFINITY, f64::min) + self.offset.0;
        let hi = points.map(|p| p[self.n - 1]).fold(f64::NEG_INFINITY, f64::max) + self.offset.1;
        (lo, hi)
    }

    pub(crate) fn new(beam: &BeamSpec, n: usize) -> Result<Self, InputError> {
        let ranges = Ranges::of(beam);
        let text = ranges.text();
        let elastic = BeamSpec { internal_variables: vec![], viscous_damping_n_s_m2: 0.0, ..beam.clone() };
        let (u_lo, u_hi) = (ranges.e0a_nm.0.powi(2), ranges.e0a_nm.1.powi(2));
        let u_nodes: Vec<f64> = (0..NODES).map(|i| chebyshev_lobatto(u_lo, u_hi, NODES, i)).collect();
        let (s_lo, s_hi) = ranges.compliance;
        let s_nodes: Vec<f64> = (0..NODES).map(|i| chebyshev_lobatto(s_lo, s_hi, NODES, i)).collect();
        let mid = |v: &[f64]| v.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect::<Vec<f64>>();
        let (u_mid, s_mid) = (mid(&u_nodes), mid(&s_nodes));
        // the Euler–Bernoulli piece (s = 0: no shear, no rotary inertia), its
        // nodes then its check points; the Timoshenko piece likewise
        let mut points: Vec<(f64, f64)> = u_nodes.iter().chain(&u_mid).map(|&u| (u, 0.0)).collect();
        for &u in &u_nodes {
            points.extend(s_nodes.iter().map(|&s| (u, s)));
        }
        for &u in &u_mid {
            points.extend(s_mid.iter().map(|&s| (u, s)));
        }
        let timoshenko = 2 * NODES - 1;
        // 1/ω² of the first n modes at each point, in order (rayon collects in order)
        let inverse: Vec<Vec<f64>> = points
            .par_iter()
            .map(|&(u, s)| {
                let e0a = u.max(0.0).sqrt();
                let b = BeamSpec {
                    nonlocal_e0a_nm: e0a,
                    shear_deformation: (s > 0.0).then(|| shear_of_compliance(s)),
                    ..elastic.clone()
                };
                let predicted = modal(&b, n).map_err(|e| {
                    InputError::new(
                        "--beam",
                        format!("{n} predicted modes at e0a = {e0a:.3} nm, E/(kappaG) = {s:.3}"),
                        format!("a beam whose first modes compute over {text} ({e})"),
                    )
                })?;
                let mut w: Vec<f64> = predicted.modes.iter().map(|m| m.omega_rad_s).collect();
                w.sort_by(f64::total_cmp);
                if w.len() < n {
                    return Err(InputError::new(
                        "--beam",
                        format!("{} oscillatory modes at e0a = {e0a:.3} nm, E/(kappaG) = {s:.3}", w.len()),
                        format!("a beam with {n} oscillatory modes over {text}"),
                    ));
                }
                Ok(w.iter().take(n).map(|w| 1.0 / (w * w)).collect())
            })
            .collect::<Result<_, InputError>>()?;
        let interpolate = |u: f64, s: f64, j: usize| interpolate_log(&u_nodes, &s_nodes, &inverse, timoshenko, u, s, j);
        let checks = (NODES..timoshenko).chain(timoshenko + NODES * NODES..points.len());
        let mut interp = vec![0.0f64; n];
        for q in checks {
            let (u, s) = points[q];
            for (j, e) in interp.iter_mut().enumerate() {
                let direct = -0.5 * inverse[q][j].ln();
                *e = e.max(2.0 * (interpolate(u, s, j) - direct).abs());
            }
        }
        if interp.iter().any(|e| !e.is_finite()) {
            return Err(InputError::new(
                "--beam",
                "modes whose interpolation over the prior fails",
                format!("a beam whose first {n} modes are smooth over {text}"),
            ));
        }
        // the grid
        let [ne, ns, nd] = GRID;
        let step =
            |lo: f64, hi: f64, m: usize, i: usize| if m == 1 { lo } else { lo + (hi - lo) * i as f64 / (m - 1) as f64 };
        let mut elastic_logs = Vec::with_capacity(ne * ns * n);
        for ie in 0..ne {
            let e0a = step(ranges.e0a_nm.0, ranges.e0a_nm.1, ne, ie);
            for is in 0..ns {
                // index 0: Euler–Bernoulli; 1..ns: the Timoshenko compliances
                let s = if is == 0 { 0.0 } else { step(s_lo, s_hi, ns - 1, is - 1) };
                for j in 0..n {
                    elastic_logs.push(interpolate(e0a * e0a, s, j));
                }
            }
        }
        let lowest = elastic_logs.iter().copied().fold(f64::INFINITY, f64::min);
        let omega_hi = ranges.omega_max_rad_s / SECTION_FACTOR_RANGE.0.sqrt();
        let ln_lo = lowest - 10f64.ln();
        let mut omegas = vec![0.0];
        if omega_hi.ln() > ln_lo {
            let decades = (omega_hi.ln() - ln_lo) / 10f64.ln();
            let m = ((decades * OMEGA_PER_DECADE).ceil() as usize).max(1);
            omegas.extend((0..=m).map(|i| (ln_lo + (omega_hi.ln() - ln_lo) * i as f64 / m as f64).exp()));
        } else {
            omegas.push(omega_hi);
        }
        let deltas: Vec<f64> = (0..nd).map(|i| step(0.0, (1.0 + ranges.delta_max).ln(), nd, i).exp() - 1.0).collect();
        let nw = omegas.len();
        let pred: Vec<f64> = (0..ne * ns)
            .into_par_iter()
            .flat_map_iter(|es| {
                let logs = &elastic_logs[es * n..(es + 1) * n];
                let mut out = Vec::with_capacity(nd * nw * n);
                for &delta in &deltas {
                    for &omega in &omegas {
                        out.extend(logs.iter().map(|&l| l + relaxation_shift(delta, omega / l.exp())));
                    }
                }
                out
            })
            .collect();
        let e_axis: Vec<f64> = (0..ne).map(|i| step(ranges.e0a_nm.0, ranges.e0a_nm.1, ne, i)).collect();
        let s_axis: Vec<f64> = (0..ns).map(|i| if i == 0 { 0.0 } else { step(s_lo, s_hi, ns - 1, i - 1) }).collect();
        let d_axis: Vec<f64> = deltas.iter().map(|d| d.ln_1p()).collect();
        let w_axis: Vec<f64> = omegas.iter().map(|w| if *w > 0.0 { w.ln() } else { f64::NEG_INFINITY }).collect();
        Ok(Family {
            pred,
            n,
            dims: [ne, ns, nd, nw],
            interp,
            offset: ranges.offset,
            u_nodes,
            s_nodes,
            inverse,
            timoshenko,
            axes: [e_axis, s_axis, d_axis, w_axis],
        })
    }

    /// ln ω_e of mode `j` at e0a² = `u` and compliance `s` (0: Euler–Bernoulli).
    fn elastic_log(&self, u: f64, s: f64, j: usize) -> f64 {
        interpolate_log(&self.u_nodes, &self.s_nodes, &self.inverse, self.timoshenko, u, s, j)
    }

    /// A numbering's cost at the continuous point x = (e0a, s, ln(1 + δ),
    /// ln Ω'), the offset fitted; x is clamped to the family's box.
    fn cost_continuous(&self, ids: &[f64], modes: &[usize], x: &[f64; 4]) -> f64 {
        let clamp = |v: f64, axis: &[f64], lo_extra: f64| {
            let (lo, hi) =
                (axis.iter().copied().filter(|a| a.is_finite()).fold(f64::INFINITY, f64::min), axis[axis.len() - 1]);
            v.clamp(lo - lo_extra, hi)
        };
        let e0a = clamp(x[0], &self.axes[0], 0.0);
        let s = if x[1] == 0.0 { 0.0 } else { clamp(x[1], &self.axes[1][1..], 0.0) };
        let ln_delta = clamp(x[2], &self.axes[2], 0.0);
        // Ω' continues 3 decades below the grid's lowest (Ω' = 0 there to 1e-6)
        let ln_omega = clamp(x[3], &self.axes[3], 3.0 * 10f64.ln());
        let delta = ln_delta.exp() - 1.0;
        let (mut s1, mut s2) = (0.0, 0.0);
        for (&xi, &j) in ids.iter().zip(modes) {
            let l = self.elastic_log(e0a * e0a, s, j);
            let r = xi - l - relaxation_shift(delta, (ln_omega - l).exp());
            s1 += r;
            s2 += r * r;
        }
        let k = ids.len() as f64;
        let c = (s1 / k).clamp(self.offset.0, self.offset.1);
        let cost = s2 - 2.0 * c * s1 + k * c * c;
        if cost.is_finite() {
            cost.max(0.0)
        } else {
            f64::INFINITY
        }
    }

    /// The grid point `g`'s coordinates and the grid steps there.
    fn coordinates(&self, g: usize) -> ([f64; 4], [f64; 4]) {
        let mut rest = g;
        let mut x = [0.0; 4];
        let mut h = [0.0; 4];
        for d in (0..4).rev() {
            let i = rest % self.dims[d];
            rest /= self.dims[d];
            let axis = &self.axes[d];
            x[d] = axis[i];
            let finite: Vec<f64> = axis.iter().copied().filter(|a| a.is_finite() && (d != 1 || *a > 0.0)).collect();
            h[d] =
                if finite.len() > 1 { (finite[finite.len() - 1] - finite[0]) / (finite.len() - 1) as f64 } else { 0.0 };
        }
        if !x[3].is_finite() {
            let lowest = self.axes[3].iter().copied().filter(|a| a.is_finite()).fold(f64::INFINITY, f64::min);
            x[3] = lowest - 2.0 * 10f64.ln();
        }
        (x, h)
    }

    /// A numbering's least cost near grid point `g`: Nelder–Mead over the
    /// continuous family from `g`, simplex steps one grid step (the shear
    /// coordinate fixed at Euler–Bernoulli when `g` is).
    fn refine(&self, ids: &[f64], modes: &[usize], g: usize) -> f64 {
        let (x0, h) = self.coordinates(g);
        let free: Vec<usize> = (0..4).filter(|&d| h[d] > 0.0 && !(d == 1 && x0[1] == 0.0)).collect();
        let point = |y: &[f64]| {
            let mut x = x0;
            for (k, &d) in free.iter().enumerate() {
                x[d] = y[k];
            }
            x
        };
        let f = |y: &[f64]| self.cost_continuous(ids, modes, &point(y));
        let start: Vec<f64> = free.iter().map(|&d| x0[d]).collect();
        let steps: Vec<f64> = free.iter().map(|&d| h[d]).collect();
        nelder_mead(&f, &start, &steps, REFINE_EVALUATIONS)
    }

    fn points(&self) -> usize {
        self.dims.iter().product()
    }

    fn at(&self, g: usize) -> &[f64] {
        &self.pred[g * self.n..(g + 1) * self.n]
    }
}

/// Cost evaluations of one numbering's local refinement.
const REFINE_EVALUATIONS: usize = 300;

/// The least value Nelder–Mead (standard coefficients 1, 2, ½, ½) finds from
/// `start` with initial simplex steps `steps`, within `budget` evaluations.
fn nelder_mead(f: &dyn Fn(&[f64]) -> f64, start: &[f64], steps: &[f64], budget: usize) -> f64 {
    let m = start.len();
    if m == 0 {
        return f(start);
    }
    let mut simplex: Vec<(Vec<f64>, f64)> = Vec::with_capacity(m + 1);
    simplex.push((start.to_vec(), f(start)));
    for i in 0..m {
        let mut p = start.to_vec();
        p[i] += steps[i];
        let v = f(&p);
        simplex.push((p, v));
    }
    let mut evaluations = m + 1;
    while evaluations < budget {
        simplex.sort_by(|a, b| a.1.total_cmp(&b.1));
        if (simplex[m].1 - simplex[0].1).abs() <= 1e-12 * (1.0 + simplex[0].1.abs()) {
            break;
        }
        let centroid: Vec<f64> = (0..m).map(|k| simplex[..m].iter().map(|p| p.0[k]).sum::<f64>() / m as f64).collect();
        let along =
            |t: f64| -> Vec<f64> { (0..m).map(|k| centroid[k] + t * (simplex[m].0[k] - centroid[k])).collect() };
        let reflected = along(-1.0);
        let fr = f(&reflected);
        evaluations += 1;
        if fr < simplex[0].1 {
            let expanded = along(-2.0);
            let fe = f(&expanded);
            evaluations += 1;
            simplex[m] = if fe < fr { (expanded, fe) } else { (reflected, fr) };
        } else if fr < simplex[m - 1].1 {
            simplex[m] = (reflected, fr);
        } else {
            let contracted = if fr < simplex[m].1 { along(-0.5) } else { along(0.5) };
            let fc = f(&contracted);
            evaluations += 1;
            if fc < simplex[m].1.min(fr) {
                simplex[m] = (contracted, fc);
            } else {
                let best = simplex[0].0.clone();
                for p in simplex.iter_mut().skip(1) {
                    p.0 = (0..m).map(|k| best[k] + 0.5 * (p.0[k] - best[k])).collect();
                    p.1 = f(&p.0);
                }
                evaluations += m;
            }
        }
    }
    simplex.iter().map(|p| p.1).fold(f64::INFINITY, f64::min)
}

/// One numbering's fit over the family.
#[derive(Debug, Clone)]
pub(crate) struct Fit {
    /// 0-based predicted indices of the identified modes.
    pub modes: Vec<usize>,
    /// Least grid cost (summed squared ln-misfit, offset fitted).
    pub cost: f64,
    /// Lower bound of its cost over the continuous family.
    pub lower: f64,
    /// Upper bound of its cost over the continuous family (grid cost with
    /// the interpolation bound).
    pub upper: f64,
    /// The grid point of its least grid cost.
    grid: usize,
    /// Its interpolation bound ‖e‖.
    interp: f64,
}

impl Fit {
    pub fn first(&self) -> usize {
        self.modes[0]
    }
}

/// Skipped predicted modes between a numbering's first and last mode.
pub(crate) fn skips(m: &[usize]) -> usize {
    m[m.len() - 1] - m[0] + 1 - m.len()
}

/// Every order-preserving numbering of `k` modes into `n` predicted ones
/// with at most [`MAX_SKIPS`] skips, the lowest in `firsts`, in
/// lexicographic order.
fn numberings(k: usize, n: usize, firsts: std::ops::Range<usize>) -> Vec<Vec<usize>> {
    fn extend(cur: &mut Vec<usize>, k: usize, n: usize, budget: usize, out: &mut Vec<Vec<usize>>) {
        if cur.len() == k {
            out.push(cur.clone());
            return;
        }
        let last = cur[cur.len() - 1];
        for skip in 0..=budget {
            let next = last + 1 + skip;
            if next + (k - cur.len() - 1) >= n {
                break;
            }
            cur.push(next);
            extend(cur, k, n, budget - skip, out);
            cur.pop();
        }
    }
    let mut out = Vec::new();
    for f in firsts {
        if f + k > n {
            break;
        }
        let mut cur = vec![f];
        extend(&mut cur, k, n, MAX_SKIPS, &mut out);
    }
    out
}

/// Residual sums and the fitted offset's cost at grid point `g`.
fn cost_at(family: &Family, ids: &[f64], modes: &[usize], g: usize) -> (f64, f64) {
    let p = family.at(g);
    let (mut s1, mut s2) = (0.0, 0.0);
    for (&x, &j) in ids.iter().zip(modes) {
        let r = x - p[j];
        s1 += r;
        s2 += r * r;
    }
    let k = ids.len() as f64;
    let c = (s1 / k).clamp(family.offset.0, family.offset.1);
    ((s2 - 2.0 * c * s1 + k * c * c).max(0.0), c)
}

/// The fit of one numbering: its least grid cost and its bounds.
fn fit(family: &Family, ids: &[f64], modes: Vec<usize>) -> Fit {
    let mut best = (f64::INFINITY, 0usize, 0.0);
    for g in 0..family.points() {
        let (cost, c) = cost_at(family, ids, &modes, g);
        if cost < best.0 {
            best = (cost, g, c);
        }
    }
    let (cost, g, c) = best;
    let e: f64 = modes.iter().map(|&j| family.interp[j].powi(2)).sum::<f64>().sqrt();
    if !cost.is_finite() {
        return Fit { modes, cost, lower: f64::INFINITY, upper: f64::INFINITY, grid: g, interp: e };
    }
    // the Gauss–Newton bound of the grid step (module doc)
    let free_offset = c > family.offset.0 && c < family.offset.1;
    let mut strides = [0usize; 4];
    let mut stride = 1;
    for d in (0..4).rev() {
        strides[d] = stride;
        stride *= family.dims[d];
    }
    let mut half_steps = 0.0;
    for (d, &stride_d) in strides.iter().enumerate() {
        let index = (g / stride_d) % family.dims[d];
        let mut worst: f64 = 0.0;
        let mut neighbours = [index.checked_sub(1), (index + 1 < family.dims[d]).then_some(index + 1)];
        if d == 1 {
            // the Euler–Bernoulli beam (index 0) is a point of its own, not a
            // neighbour of the Timoshenko compliances
            if index == 0 {
                neighbours = [None, None];
            } else if index == 1 {
                neighbours[0] = None;
            }
        }
        for h in neighbours.into_iter().flatten() {
            let gh = g - index * stride_d + h * stride_d;
            let moves: Vec<f64> = modes.iter().map(|&j| family.at(gh)[j] - family.at(g)[j]).collect();
            let mean = if free_offset { moves.iter().sum::<f64>() / moves.len() as f64 } else { 0.0 };
            let norm = moves.iter().map(|m| (m - mean).powi(2)).sum::<f64>().sqrt();
            // an overdamped neighbour: no bound from it, so none at all
            worst = worst.max(if norm.is_finite() { norm } else { f64::INFINITY });
        }
        half_steps += 0.5 * worst;
    }
    let lower =
        if half_steps.is_finite() { ((cost.sqrt() - e).max(0.0).powi(2) - half_steps.powi(2)).max(0.0) } else { 0.0 };
    let upper = (cost.sqrt() + e).powi(2);
    Fit { modes, cost, lower, upper, grid: g, interp: e }
}

/// The fits of every numbering of `ids` (sorted ln ω) with its lowest mode
/// in `firsts`, in a fixed order, the least grid cost first (ties: the
/// earlier numbering).
pub(crate) fn fits(family: &Family, ids: &[f64], firsts: std::ops::Range<usize>) -> Vec<Fit> {
    let all = numberings(ids.len(), family.n, firsts);
    let mut out: Vec<Fit> = all.into_par_iter().map(|m| fit(family, ids, m)).collect();
    // refine every numbering the grid cannot rule out (its Gauss–Newton
    // lower bound within the margin of the best's upper bound) and the best
    // of every lowest mode (for --first-mode)
    let best_upper = out.iter().map(|f| f.upper).fold(f64::INFINITY, f64::min);
    let mut best_of_first = vec![f64::INFINITY; family.n];
    for f in &out {
        best_of_first[f.first()] = best_of_first[f.first()].min(f.cost);
    }
    out.par_iter_mut().for_each(|f| {
        if f.lower < best_upper + AMBIGUITY_MARGIN.powi(2) || f.cost == best_of_first[f.first()] {
            let refined = family.refine(ids, &f.modes, f.grid).min(f.cost);
            f.cost = refined;
            f.lower = (refined.sqrt() - f.interp).max(0.0).powi(2);
            f.upper = (refined.sqrt() + f.interp).powi(2);
        }
    });
    out.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    out
}

/// Root of how far `other`'s lower bound lies above `best`'s upper bound (0
/// when below): the "extra misfit" the margins are compared with.
pub(crate) fn extra(best: &Fit, other: &Fit) -> f64 {
    (other.lower - best.upper).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relaxation_shift_limits() {
        // far below Ω: elastic; far above: stiffened by √(1 + δ)
        assert!(relaxation_shift(0.5, 1e4).abs() < 1e-7);
        assert!((relaxation_shift(0.5, 1e-4) - 0.5 * 1.5f64.ln()).abs() < 1e-7);
        // the oscillatory pair solves the cubic: u = |u| e^{iφ} with
        // u³ + r u² + (1 + δ) u + r = 0; check through the quadratic factor
        let (delta, r) = (0.8, 1.3);
        let g = relaxation_shift(delta, r);
        let m2 = (2.0 * g).exp();
        // real root u₀ = −r/|u|², and f(u₀) = 0
        let u0 = -r / m2;
        assert!((((u0 + r) * u0 + 1.0 + delta) * u0 + r).abs() < 1e-12);
    }

    #[test]
    fn numberings_are_ordered_with_bounded_skips() {
        let all = numberings(2, 4, 0..4);
        assert_eq!(all, vec![vec![0, 1], vec![0, 2], vec![0, 3], vec![1, 2], vec![1, 3], vec![2, 3]]);
        assert!(numberings(3, 8, 0..1).iter().all(|m| skips(m) <= MAX_SKIPS));
        // from mode 0, [0, a, b] skips b − 2 ≤ MAX_SKIPS = 4: b ≤ 6, and
        // b − 1 choices of a for each b = 2..=6
        assert_eq!(MAX_SKIPS, 4);
        assert_eq!(numberings(3, 8, 0..1).len(), 1 + 2 + 3 + 4 + 5);
    }
}
