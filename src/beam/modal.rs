//! Poles and modal parameters (34)–(35).
//!
//! # Why the fast path is exact (decoupling)
//! Laplace-transforming (A8) and eliminating q̄ᵢ = Ωᵢ/(s+Ωᵢ) q (see
//! `state_space.rs`) gives the dynamic stiffness
//!   T(s) = s²M + sD + K_spring + G(s)·K,  G(s) = 1 + Σᵢ Δᵢ s/(s + Ωᵢ),
//! and, by the Schur complement of the block state matrix,
//!   det(sI − Aa) = det(M)⁻¹ · det T(s) · Πᵢ (s + Ωᵢ)ⁿ.
//! If D = cM (true when there is no point mass — De = (C/ρA)Me, A5 — or when
//! C = 0) and K_spring = 0, let Φ be the M-orthonormal eigenvectors of the
//! symmetric pencil KΦ = MΦΛ. Then ΦᵀT(s)Φ = diag(s² + cs + λⱼG(s)), so
//!   det T(s) = det(M)·Πⱼ (s² + cs + λⱼG(s))
//! and every pole is a root of one family polynomial
//!   (s² + cs + λⱼ)Πᵢ(s+Ωᵢ) + λⱼ Σᵢ Δᵢ s Π_{k≠i}(s+Ωₖ),
//! of degree N+2 (the extra factors (s+Ωᵢ)ⁿ cancel against the denominators;
//! a variable with Δᵢ = 0 contributes only the uncoupled pole −Ωᵢ, which is
//! unobservable and left out of the modal result). Only the lowest λⱼ are
//! needed: `eigen.rs` finds them (Rayleigh-quotient iteration from a cached
//! nearby pencil, certified by an inertia count; Newton–Maehly from scratch
//! otherwise).
//! A point mass with C > 0 breaks D ∝ M; a support spring breaks K_spring ∝ K
//! (it is not relaxed by G). Then `general_path` solves T(s)x = 0 pole by pole
//! (nonlinear Rayleigh-quotient iteration).
//!
//! # What is reported
//! Physical mode r is modal family r: the r-th eigenpair of the undamped,
//! relaxed pencil (K̃ + K̃_spring, M̃) (for an undamped or lightly damped
//! beam the same order as increasing |s|). Its oscillatory pair (the Im > 0
//! member; with several internal variables the pair of largest |s|) gives
//! ωᵣ = |sᵣ| (34), ζᵣ = −Re sᵣ/|sᵣ| (35). A family without a complex pair is
//! an overdamped mode: it keeps its number and is reported with its real
//! poles in [`ModalResult::overdamped`], so a measured "mode 2" is always
//! physical mode 2. All real poles (relaxation, overdamped) of families
//! 1..=n_modes are also listed in `real_poles_rad_s`.

use std::collections::HashMap;

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::beam::band::{ldl_factor_for_inverse_iteration, ldl_solve, BandLu, ShiftedLdl, SymBand};
use crate::beam::dual::Dual;
use crate::beam::eigen::{lowest_eigenpairs, refine_eigenpairs, EigenPair, RqiStart};
use crate::beam::family::{decoupled_family_roots_into, family_roots, Roots, REAL_TOL};
use crate::beam::model::{PencilParams, ScaledModel, Scaling, UnitMesh};
use crate::beam::shear_spectrum::ShearSpectrumTable;
use crate::beam::spec::BeamSpec;
use crate::beam::spectrum::SpectrumTable;
use crate::beam::{state_space, BeamError};
use crate::error::InputError;

/// One oscillatory mode.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    /// 1-based index in order of increasing |s|.
    pub mode: usize,
    /// ωᵣ = |sᵣ| (eq. 34), rad/s.
    pub omega_rad_s: f64,
    /// ζᵣ = −Re(sᵣ)/|sᵣ| (eq. 35).
    pub zeta: f64,
    /// The pole with Im > 0, rad/s.
    pub pole: Complex64,
}

/// An overdamped mode: its family has only real poles.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OverdampedMode {
    /// Physical mode number (1-based family index).
    pub mode: usize,
    /// The family's real poles in rad/s, sorted by magnitude.
    pub poles_rad_s: Vec<f64>,
}

/// Physical modes 1..=n_modes: oscillatory ones in `modes`, overdamped ones
/// in `overdamped` (each number in exactly one of them), and separately the
/// real poles of those modal families.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModalResult {
    /// Oscillatory modes in increasing mode number (gaps where overdamped).
    pub modes: Vec<Mode>,
    /// Negative reals in rad/s, sorted by magnitude.
    pub real_poles_rad_s: Vec<f64>,
    /// Overdamped modes in increasing mode number.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overdamped: Vec<OverdampedMode>,
}

impl ModalResult {
    /// Oscillatory physical mode `number` (1-based); `None` when it is
    /// overdamped or was not computed.
    pub fn mode(&self, number: usize) -> Option<&Mode> {
        self.modes.iter().find(|m| m.mode == number)
    }
}

/// Reusable solver: caches the unit mesh integrals (they depend only on the
/// element count and the supports) and the pencil eigenpairs, so a call with
/// new parameters mostly rescales and re-solves small problems.
///
/// The lowest eigenpairs of the undamped relaxed pencil (K̃ + K̃_spring, M̃)
/// depend only on [`PencilParams`] (ẽ, point mass, spring), not on E, ρ, d, C,
/// Δ, Ω; they are found (see `EigenCache`) by
/// 1. exact reuse when the parameters are bitwise those of the last call;
/// 2. otherwise Rayleigh-quotient iteration from the eigenpairs of the
///    nearest grid pencil ([`PencilParams::snapped`], cached), certified by
///    an inertia count;
/// 3. otherwise (or if 2 fails) Newton–Maehly from scratch.
///
/// Every result is a function of the call's input alone — the caches change
/// how fast it comes, never its bits — so a solver shared by the chains of a
/// thread keeps outputs independent of the thread count.
///
/// The Euler–Bernoulli decoupled model without a point mass (any N, viscous
/// C, any section and material) takes the fastest route of all: the pencil
/// depends on ẽ alone, and λ̃_r(ẽ²) comes from a certified Chebyshev
/// interpolant (`spectrum.rs`: relative error ≤ 1e-12 against the direct
/// solve, measured when it is built; a function of (mesh, mode, e0a piece)
/// only), then one root solve per family. Where no certified interpolant
/// exists the eigenpairs are solved directly as above. So does the decoupled
/// Timoshenko model (shear deformation, C = 0, no other extension): its pencil
/// depends on (ẽ, g̃), interpolated in `shear_spectrum.rs`. The coupled extensions
/// (spring, point mass with C > 0, axial force, Timoshenko with C > 0) keep
/// the RQI path: their poles need nonlinear RQI on T(s) whatever the pencil
/// start costs (see `general_path`), and the pencil depends on 2–3 parameters.
#[derive(Debug, Default, Clone)]
pub struct ModalSolver {
    mesh: Option<UnitMesh>,
    eigen: EigenCache,
    last_path: Option<SolverPath>,
    spectrum: SpectrumTable,
    shear_spectrum: ShearSpectrumTable,
    /// Never use the interpolant (reference solver for tests and benches).
    direct_only: bool,
    last_interpolated: bool,
    lambdas: Vec<f64>,
    roots: Vec<Roots>,
}

/// Which method produced the last [`ModalSolver::modal`] result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolverPath {
    /// (b) exact decoupling into family polynomials.
    Decoupled,
    /// (c) coupling extensions: nonlinear Rayleigh-quotient iteration on T(s)
    /// from each family's one-term approximation.
    CoupledRqi,
    /// (a) the state-space reference, used because (b)/(c) failed numerically.
    StateSpaceFallback,
}

/// Grid start pencils kept per solver (≈ 6 kB each for 6 modes of a
/// 20-element mesh). A calibration chain visits a few cells; a TMCMC run of
/// a 3-parameter pencil class (point mass: ẽ, μ̃, x̃) visits thousands while
/// its population still spreads over the prior, then settles in a few.
const GRID_CACHE: usize = 1024;
/// Plain grid pencils (ẽ, g̃) kept per solver. Measured on a 5-mode
/// shear-deformation search (17 models, 1.1 M solves, 2 threads): 2 012
/// distinct plain cells in all, so ≈ 1 000 per thread; with plain and
/// extended cells sharing one cache of 1 024, 18.6 k plain misses (each a
/// Newton–Maehly solve from scratch) for those 2 012 cells.
const PLAIN_GRID_CACHE: usize = 2048;

/// Eigenpair caches of one mesh (see [`ModalSolver`]).
#[derive(Debug, Default, Clone)]
struct EigenCache {
    work: Vec<Dual<f64>>,
    ldl: ShiftedLdl,
    exact: Option<([u64; 6], Vec<EigenPair>)>,
    /// Grid pencil eigenvectors keyed by [`PencilParams::bits`] of the grid
    /// point: plain pencils (ẽ, g̃) and extended ones apart, so that a
    /// population sweeping an extended grid does not evict the parents every
    /// extended cell is refined from.
    grid: HashMap<[u64; 6], Vec<GridVector>>,
    plain_grid: HashMap<[u64; 6], Vec<GridVector>>,
    /// How the last [`EigenCache::lowest`] call got its answer (for tests).
    last_method: Option<EigenMethod>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum EigenMethod {
    Reused,
    Refined,
    Scratch,
}

/// An eigenvector of a grid pencil with the parameter-free pieces of its
/// products, so that its RQI start on any pencil of the mesh costs O(n):
/// M̃x = M̃₀x + ẽ²M̃₁x + μ̃N(Nᵀx), xᵀM̃x = xᵀM̃₀x + ẽ²xᵀM̃₁x + μ̃(Nᵀx)²,
/// xᵀ(K̃ + K̃_spring + K̃_N)x = xᵀK̃x + k̃_r Σ_spring xᵢ² + ñ(xᵀG̃₀x + ẽ²xᵀG̃₁x),
/// with xᵀK̃x = xᵀK̃_bx + g̃·xᵀK̃_γx on a Timoshenko mesh.
#[derive(Debug, Clone)]
struct GridVector {
    vector: Vec<f64>,
    m0x: Vec<f64>,
    m1x: Vec<f64>,
    /// xᵀK̃x without shear (Euler–Bernoulli: all of it) and xᵀ(Σ∫γγᵀ)x.
    k_form: f64,
    shear_form: f64,
    m0_form: f64,
    m1_form: f64,
    spring_sq: f64,
    /// xᵀG̃₀x and xᵀG̃₁x (axial-force forms; 0 when the mesh pencil has no force).
    g_forms: (f64, f64),
}

impl GridVector {
    fn new(mesh: &UnitMesh, vector: Vec<f64>) -> Self {
        let (mut m0x, mut m1x) = (Vec::new(), Vec::new());
        mesh.m0.mul_vec_into(&vector, &mut m0x);
        mesh.m1.mul_vec_into(&vector, &mut m1x);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        GridVector {
            k_form: mesh.stiffness_form(&vector, 0.0),
            shear_form: mesh.shear.as_ref().map_or(0.0, |sh| sh.ks.bilinear(&vector, &vector)),
            m0_form: dot(&vector, &m0x),
            m1_form: dot(&vector, &m1x),
            spring_sq: mesh.spring_dofs.iter().map(|&i| vector[i] * vector[i]).sum(),
            g_forms: {
                let f = mesh.energy_forms_ext(&vector, 0.0);
                (f[5], f[6])
            },
            vector,
            m0x,
            m1x,
        }
    }

    fn start(&self, params: &PencilParams, point_mass: Option<&(f64, Vec<f64>)>) -> RqiStart {
        let e2 = params.e_tilde * params.e_tilde;
        let mut mx: Vec<f64> = self.m0x.iter().zip(&self.m1x).map(|(a, b)| a + e2 * b).collect();
        let mut m_form = self.m0_form + e2 * self.m1_form;
        if let Some((mu, nv)) = point_mass {
            let w: f64 = nv.iter().zip(&self.vector).map(|(a, b)| a * b).sum();
            mx.iter_mut().zip(nv).for_each(|(y, a)| *y += mu * w * a);
            m_form += mu * w * w;
        }
        let k_n = if params.axial != 0.0 { params.axial * (self.g_forms.0 + e2 * self.g_forms.1) } else { 0.0 };
        let rho = (self.k_form + params.shear * self.shear_form + params.spring * self.spring_sq + k_n) / m_form;
        RqiStart { vector: self.vector.clone(), mx, rho }
    }
}

impl EigenCache {
    /// The `count` lowest eigenpairs of (k, m), the pencil of `params`.
    fn lowest(
        &mut self,
        mesh: &UnitMesh,
        params: &PencilParams,
        k: &SymBand,
        m: &SymBand,
        point_mass: Option<&(f64, Vec<f64>)>,
        count: usize,
    ) -> Result<&[EigenPair], BeamError> {
        let key = params.bits();
        // exact reuse only for the same count: certification depends on it,
        // and a different count must give what a fresh solve would.
        if !matches!(&self.exact, Some((kk, p)) if *kk == key && p.len() == count) {
            let rq = |x: &[f64]| mesh.pencil_stiffness(params, x);
            let starts: Option<Vec<RqiStart>> = self
                .grid_starts(mesh, params.snapped(), count)
                .map(|grid| grid.iter().map(|g| g.start(params, point_mass)).collect());
            let refined = starts.and_then(|starts| refine_eigenpairs(k, m, starts, &rq, &mut self.ldl));
            let pairs = match refined {
                Some(p) => {
                    self.last_method = Some(EigenMethod::Refined);
                    p
                }
                None => {
                    self.last_method = Some(EigenMethod::Scratch);
                    lowest_eigenpairs(k, m, count, &mut self.work, &rq)?
                }
            };
            self.exact = Some((key, pairs));
        } else {
            self.last_method = Some(EigenMethod::Reused);
        }
        Ok(&self.exact.as_ref().expect("just set").1)
    }

    /// The eigenvectors of the grid pencil `g`, at least `count` of them,
    /// computed from scratch on a miss (the first `count` of a longer list are
    /// the same numbers: Newton–Maehly finds them in order); `None` if that fails.
    fn grid_starts(&mut self, mesh: &UnitMesh, g: PencilParams, count: usize) -> Option<&[GridVector]> {
        let key = g.bits();
        let plain = g.plain() == g;
        let hit = matches!(self.cells(plain).get(&key), Some(e) if e.len() >= count);
        if !hit {
            let (kg, mg) = mesh.pencil(&g);
            let rq = |x: &[f64]| mesh.pencil_stiffness(&g, x);
            // an extended grid pencil (spring, point mass, axial force) first
            // by RQI from its plain parent (same ẽ and g̃, no extension: a few
            // hundred cells, so nearly always cached), certified like any
            // refinement; Newton–Maehly from scratch only if that fails. A
            // TMCMC population spread over a 2–4-parameter prior misses the
            // grid on most draws (measured: 38 k misses in 42 k solves for
            // attached-mass + shear-deformation), and a scratch solve costs
            // several times a certified refinement.
            let parent = g.plain();
            let pairs = if parent != g {
                let pm = g.point_mass.map(|(mu, x)| (mu, mesh.shape_vector(x)));
                let starts: Option<Vec<RqiStart>> = self
                    .grid_starts(mesh, parent, count)
                    .map(|grid| grid.iter().map(|v| v.start(&g, pm.as_ref())).collect());
                starts.and_then(|starts| refine_eigenpairs(&kg, &mg, starts, &rq, &mut self.ldl))
            } else {
                None
            };
            let pairs = match pairs {
                Some(p) => p,
                None => lowest_eigenpairs(&kg, &mg, count, &mut self.work, &rq).ok()?,
            };
            let cells = self.cells(plain);
            if cells.len() >= if plain { PLAIN_GRID_CACHE } else { GRID_CACHE } {
                // wholesale reset: the cache only changes speed, never results
                cells.clear();
            }
            cells.insert(key, pairs.into_iter().map(|p| GridVector::new(mesh, p.vector)).collect());
        }
        self.cells(plain).get(&key).map(|e| &e[..count])
    }

    /// The plain grid (ẽ, g̃) or the extended one.
    fn cells(&mut self, plain: bool) -> &mut HashMap<[u64; 6], Vec<GridVector>> {
        if plain {
            &mut self.plain_grid
        } else {
            &mut self.grid
        }
    }
}

impl ModalSolver {
    pub fn new() -> Self {
        Self::default()
    }

    /// A solver that never uses the eigenvalue interpolant: every eigenpair
    /// from the direct banded solve (the reference the interpolant is certified against).
    pub fn direct_only() -> Self {
        Self { direct_only: true, ..Self::default() }
    }

    /// True when the last result's eigenvalues came from the certified interpolant.
    pub fn last_used_interpolant(&self) -> bool {
        self.last_interpolated
    }

    /// The path used by the last successful or attempted call.
    pub fn last_path(&self) -> Option<SolverPath> {
        self.last_path
    }

    /// Validates `beam` and rebuilds the mesh (dropping the caches built on
    /// the old one) unless it is bitwise the one `UnitMesh::for_beam` would build.
    fn prepare(&mut self, beam: &BeamSpec) -> Result<(), BeamError> {
        beam.validate()?;
        let stale = !matches!(&self.mesh, Some(m) if m.matches(beam));
        if stale {
            self.mesh = Some(UnitMesh::for_beam(beam));
            self.eigen = EigenCache::default();
            self.spectrum = SpectrumTable::default();
            self.shear_spectrum = ShearSpectrumTable::default();
        }
        self.last_interpolated = false;
        Ok(())
    }

    /// The fastest exact path: decoupled families when the proof above
    /// applies, otherwise RQI on T(s) (falling back to the state space).
    pub fn modal(&mut self, beam: &BeamSpec, n_modes: usize) -> Result<ModalResult, BeamError> {
        self.solve(beam, n_modes, Poles::All)
    }

    /// [`Self::modal`], on the coupled path with or without the real poles.
    fn solve(&mut self, beam: &BeamSpec, n_modes: usize, poles: Poles) -> Result<ModalResult, BeamError> {
        self.prepare(beam)?;
        if !self.direct_only {
            if let Some(result) = self.interpolated(beam, n_modes) {
                self.last_path = Some(SolverPath::Decoupled);
                self.last_interpolated = true;
                return Ok(result);
            }
        }
        let Self { mesh, eigen, last_path, .. } = self;
        let model = ScaledModel::new(beam, mesh.as_ref().expect("mesh just set"));
        check_mode_count(n_modes, model.n())?;
        let (path, result) = if model.decouples() {
            (SolverPath::Decoupled, decoupled_path(&model, n_modes, eigen))
        } else {
            (SolverPath::CoupledRqi, general_path(&model, n_modes, eigen, poles))
        };
        *last_path = Some(path);
        match result {
            Err(BeamError::Numerical(_)) => {
                *last_path = Some(SolverPath::StateSpaceFallback);
                state_space_modal(&model, n_modes)
            }
            other => other,
        }
    }
}

impl ModalSolver {
    /// The interpolated decoupled path, or `None` when it does not apply (a
    /// coupling extension, a point mass, shear deformation, e0a beyond the
    /// interpolated range, an uncertified piece, a root solve that fails): the
    /// caller then takes the direct path. Which one is taken is a function of
    /// the input alone. The beam was validated by the caller.
    fn interpolated(&mut self, beam: &BeamSpec, n_modes: usize) -> Option<ModalResult> {
        let omega_ref = self.interpolated_roots(beam, n_modes)?;
        Some(assemble(&self.roots, n_modes, omega_ref))
    }

    /// The families 1..=n_modes of the interpolated path into `self.roots`
    /// (scaled units), returning ω_ref; `None` when the path does not apply
    /// (see [`Self::interpolated`]).
    fn interpolated_roots(&mut self, beam: &BeamSpec, n_modes: usize) -> Option<f64> {
        let mesh = self.mesh.as_ref()?;
        let sc = Scaling::new(beam);
        // the same tests as ScaledModel::decouples with no point mass and no rotary inertia
        let spring = sc.spring > 0.0 && !mesh.spring_dofs.is_empty();
        // Timoshenko decouples only without damping (rotary inertia: `shear_spectrum.rs`)
        let shear = mesh.shear.is_some();
        if (shear && sc.c != 0.0) || beam.point_mass.is_some() || spring || sc.axial != 0.0 {
            return None;
        }
        if n_modes == 0 || n_modes > mesh.n() {
            return None;
        }
        self.lambdas.resize(n_modes, 0.0);
        let t = sc.e_tilde * sc.e_tilde;
        let found = if shear {
            let g = crate::beam::model::shear_params(beam).map_or(0.0, |(g, _)| g);
            self.shear_spectrum.lambdas(mesh, t, g, &mut self.lambdas)
        } else {
            self.spectrum.lambdas(mesh, t, &mut self.lambdas)
        };
        if !found {
            return None;
        }
        let mut ivs = [(0.0, 0.0); crate::beam::spec::MAX_INTERNAL_VARIABLES];
        let mut nv = 0;
        for iv in beam.internal_variables.iter().filter(|iv| iv.delta > 0.0) {
            ivs[nv] = (iv.delta, iv.omega_rad_s / sc.omega_ref);
            nv += 1;
        }
        self.roots.resize(n_modes, Roots::default());
        decoupled_family_roots_into(&self.lambdas, sc.c, &ivs[..nv], &mut self.roots).ok()?;
        Some(sc.omega_ref)
    }

    /// ω (rad/s) and ζ of the physical modes `modes` (1-based, each ≤ n_modes)
    /// into `out` = [ω…, ζ…] (length 2·modes.len()): the numbers of
    /// `self.modal(beam, n_modes)?.mode(m)`, bit for bit, without building the
    /// [`ModalResult`] on the interpolated path (issue 15: a calibration
    /// evaluates this ~1.75 times per draw, and the result's vectors, the sort
    /// of its real poles and the copy into a prediction vector were ~5 % of a
    /// whole `calibrate`). On the coupled path only the oscillatory poles are
    /// solved ([`Poles::Oscillatory`]): the same RQI from the same starts, so
    /// the same bits, except where `modal` falls back to the state space
    /// because two real-pole starts met (then both are exact to the
    /// solvers' tolerance, not bitwise equal). `Ok(false)` when a requested
    /// mode is overdamped or was not computed.
    pub fn observables(
        &mut self,
        beam: &BeamSpec,
        modes: &[usize],
        n_modes: usize,
        out: &mut [f64],
    ) -> Result<bool, BeamError> {
        debug_assert_eq!(out.len(), 2 * modes.len());
        self.prepare(beam)?;
        let m = modes.len();
        if !self.direct_only {
            if let Some(omega_ref) = self.interpolated_roots(beam, n_modes) {
                self.last_path = Some(SolverPath::Decoupled);
                self.last_interpolated = true;
                for (k, &mode) in modes.iter().enumerate() {
                    let Some(fam) = mode.checked_sub(1).and_then(|j| self.roots.get(j)).filter(|_| mode <= n_modes)
                    else {
                        return Ok(false);
                    };
                    // the pair and the formulas of `assemble`
                    let Some(s) = oscillatory_pair(fam) else { return Ok(false) };
                    let r = s.norm_sqr().sqrt();
                    out[k] = r * omega_ref;
                    out[m + k] = -s.re / r;
                }
                return Ok(true);
            }
        }
        let result = self.solve(beam, n_modes, Poles::Oscillatory)?;
        for (k, &mode) in modes.iter().enumerate() {
            let Some(md) = result.mode(mode) else { return Ok(false) };
            out[k] = md.omega_rad_s;
            out[m + k] = md.zeta;
        }
        Ok(true)
    }
}

/// Which poles the coupled path (c) solves for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Poles {
    /// Every pole of the requested families (what [`ModalSolver::modal`] reports).
    All,
    /// The oscillatory pairs only (what [`ModalSolver::observables`] needs).
    /// Real relaxation poles are not modes; a slow relaxation (Ω̃ ≪ ω̃₁) gives
    /// every family a real pole near −Ω̃/(1 + Δ), equal to leading order for
    /// all families, and RQI from two of those starts can land on one pole:
    /// the coupled path then fails and the dense state space (~25·dim³ flops,
    /// dim = 2n + N·n) takes over for poles no observable uses.
    Oscillatory,
}

/// The oscillatory member of a family: the Im > 0 root of largest |s|.
fn oscillatory_pair(family: &[Complex64]) -> Option<Complex64> {
    family.iter().copied().filter(|s| s.im > 0.0).max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
}

thread_local! {
    /// One reusable solver per thread for [`modal`]: its caches (mesh
    /// integrals, pencil eigenpairs) change how fast a result comes, never its
    /// bits, so sharing it across calls and chains of a thread keeps outputs
    /// independent of the thread schedule.
    static THREAD_SOLVER: std::cell::RefCell<ModalSolver> = std::cell::RefCell::new(ModalSolver::new());
}

/// Modal parameters by the fastest exact path (see [`ModalSolver`]), through
/// this thread's reusable solver (a fresh one if that is busy, e.g. on a
/// re-entrant call).
pub fn modal(beam: &BeamSpec, n_modes: usize) -> Result<ModalResult, BeamError> {
    THREAD_SOLVER.with(|s| match s.try_borrow_mut() {
        Ok(mut solver) => solver.modal(beam, n_modes),
        Err(_) => ModalSolver::new().modal(beam, n_modes),
    })
}

/// [`ModalSolver::observables`] through this thread's reusable solver (see [`modal`]).
pub fn modal_observables(beam: &BeamSpec, modes: &[usize], n_modes: usize, out: &mut [f64]) -> Result<bool, BeamError> {
    THREAD_SOLVER.with(|s| match s.try_borrow_mut() {
        Ok(mut solver) => solver.observables(beam, modes, n_modes, out),
        Err(_) => ModalSolver::new().observables(beam, modes, n_modes, out),
    })
}

/// Modal parameters from the eigenvalues of the state matrix (A15) (reference).
pub fn modal_state_space(beam: &BeamSpec, n_modes: usize) -> Result<ModalResult, BeamError> {
    beam.validate()?;
    let mesh = UnitMesh::for_beam(beam);
    let model = ScaledModel::new(beam, &mesh);
    check_mode_count(n_modes, model.n())?;
    state_space_modal(&model, n_modes)
}

/// Every pole of the state matrix (A15) in rad/s, sorted by |s| then Im s.
/// Count (2 + N)·n, n = free DOFs, N = number of internal variables.
pub fn poles_state_space(beam: &BeamSpec) -> Result<Vec<Complex64>, BeamError> {
    beam.validate()?;
    let mesh = UnitMesh::for_beam(beam);
    let model = ScaledModel::new(beam, &mesh);
    Ok(state_space::scaled_poles(&model)?.into_iter().map(|p| p * model.omega_ref).collect())
}

fn check_mode_count(n_modes: usize, n: usize) -> Result<(), BeamError> {
    if n_modes == 0 || n_modes > n {
        return Err(InputError::new("n_modes", n_modes, format!("1..={n} (free DOFs of this mesh)")).into());
    }
    Ok(())
}

/// Physical modes 1..=n_modes from the roots of families 1..=n_modes (in
/// eigenpair order): each family's oscillatory pair (largest |s| if there
/// are several) or, without one, an overdamped mode with its real roots.
fn assemble<F: std::ops::Deref<Target = [Complex64]>>(families: &[F], n_modes: usize, omega_ref: f64) -> ModalResult {
    let mut modes = Vec::with_capacity(n_modes);
    let mut overdamped = Vec::new();
    for (j, fam) in families.iter().take(n_modes).enumerate() {
        match oscillatory_pair(fam) {
            Some(s) => {
                // |s̃| in scaled units (O(1)..O(1e6): no overflow in the square,
                // so no hypot), then to rad/s
                let r = s.norm_sqr().sqrt();
                modes.push(Mode { mode: j + 1, omega_rad_s: r * omega_ref, zeta: -s.re / r, pole: s * omega_ref });
            }
            None => {
                let mut poles: Vec<f64> = fam.iter().filter(|s| s.im == 0.0).map(|s| s.re * omega_ref).collect();
                poles.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
                overdamped.push(OverdampedMode { mode: j + 1, poles_rad_s: poles });
            }
        }
    }
    let mut real: Vec<f64> = families
        .iter()
        .take(n_modes)
        .flat_map(|f| f.iter())
        .filter(|s| s.im == 0.0)
        .map(|s| s.re * omega_ref)
        .collect();
    real.sort_by(|a, b| a.abs().total_cmp(&b.abs()));
    ModalResult { modes, real_poles_rad_s: real, overdamped }
}

/// Path (b): exact decoupling.
fn decoupled_path(model: &ScaledModel, n_modes: usize, eigen: &mut EigenCache) -> Result<ModalResult, BeamError> {
    let params = model.pencil_params();
    let pairs = eigen.lowest(model.mesh, &params, &model.k, &model.m, model.point_mass.as_ref(), n_modes)?;
    let families =
        pairs.iter().map(|p| family_roots(0.0, p.lambda, model.c, &model.ivs)).collect::<Result<Vec<_>, _>>()?;
    Ok(assemble(&families, n_modes, model.omega_ref))
}

/// (a, b, c_φ) of one family's equation, the eigenvector φ it came from and
/// φ's energy forms (k, m, m_b, k_s) (see [`ScaledModel::forms`]).
type FamilyApproximation = ((f64, f64, f64), Vec<f64>, Forms);

/// Energy forms xᵀK̃x, xᵀM̃x, xᵀM̃_beam x, xᵀK̃_spring x of one vector.
type Forms = (f64, f64, f64, f64);

/// One-term modal approximation of family j of a coupled model: with φ the
/// eigenvector of (K + K_spring, M) for λ, the family equation
/// s² + c_φ s + a + b G(s) = 0 with b = φᵀKφ/φᵀMφ, a = λ − b = φᵀK_springφ/φᵀMφ,
/// c_φ = c̃·φᵀM_beamφ/φᵀMφ. Exact when the model decouples.
fn family_approximations(
    model: &ScaledModel,
    count: usize,
    eigen: &mut EigenCache,
) -> Result<Vec<FamilyApproximation>, BeamError> {
    let kt = model.k_total();
    let pairs = eigen.lowest(model.mesh, &model.pencil_params(), &kt, &model.m, model.point_mass.as_ref(), count)?;
    Ok(pairs
        .iter()
        .map(|p| {
            let forms @ (k, m, mb, ks) = model.forms(&p.vector);
            ((ks / m, k / m, model.c * mb / m), p.vector.clone(), forms)
        })
        .collect())
}

/// Path (c): the poles of T̃(s̃) = s̃²M̃ + s̃c̃M̃_beam + K̃_spring + G(s̃)K̃ one by
/// one, each by nonlinear Rayleigh-quotient iteration from the one-term
/// approximation of its family (root and eigenvector of (K̃ + K̃_spring, M̃)).
/// Any failure → the caller falls back to (a).
fn general_path(
    model: &ScaledModel,
    n_modes: usize,
    eigen: &mut EigenCache,
    poles: Poles,
) -> Result<ModalResult, BeamError> {
    {
        let count = n_modes;
        let approx = family_approximations(model, count, eigen)?;
        let mut found: Vec<Complex64> = Vec::new();
        let mut families = Vec::with_capacity(count);
        for ((a, b, c), phi, forms) in &approx {
            let starts = family_roots(*a, *b, *c, &model.ivs)?;
            let mut fam = Vec::with_capacity(starts.len());
            let wanted = |s: &Complex64| s.im > 0.0 || (s.im == 0.0 && poles == Poles::All);
            for s0 in starts.iter().copied().filter(wanted) {
                // Real poles cluster (one per family within [−Ωᵢ, −Ωᵢ/(1+Δᵢ)]) next
                // next to the n-fold poles of det T at −Ωᵢ, where methods on det T crawl;
                // nonlinear Rayleigh-quotient iteration from the family's vector
                // φ picks the family's own root instead.
                let s =
                    if s0.im == 0.0 { nonlinear_rqi(model, s0, phi)? } else { complex_rqi(model, s0, phi, *forms)? };
                // a start from the one-term model is within a few % of its pole;
                // a jump of more than half its size means another pole was hit,
                // and so does landing on a pole found already.
                if (s - s0).norm() > 0.5 * s0.norm() {
                    return Err(BeamError::numerical("RQI left its start's neighbourhood"));
                }
                if found.iter().any(|f| (s - f).norm() <= 1e-8 * s.norm()) {
                    return Err(BeamError::numerical("two starts converged to the same pole"));
                }
                if s0.im == 0.0 {
                    found.push(s);
                    fam.push(s);
                } else {
                    if s.im.abs() <= REAL_TOL * s.norm() {
                        return Err(BeamError::numerical("complex start converged to a real pole"));
                    }
                    let s = Complex64::new(s.re, s.im.abs());
                    found.push(s);
                    found.push(s.conj());
                    fam.push(s);
                    fam.push(s.conj());
                }
            }
            families.push(fam);
        }
        Ok(assemble(&families, n_modes, model.omega_ref))
    }
}

/// The outer stop of [`complex_rqi`]: the same argument as `RQI_TOL` in
/// `eigen.rs` — a move ≤ 1e-6·|s| means the vector was within ~1e-3 before the
/// step, and the cubic rate leaves an error ≲ 1e-18·|s| after it.
const COMPLEX_RQI_TOL: f64 = 1e-6;
const COMPLEX_RQI_MAX_STEPS: usize = 8;

/// Complex nonlinear Rayleigh-quotient iteration for an oscillatory pole:
/// x ← T(s)⁻¹T'(s)x, then s ← the root next to s of the Rayleigh functional
/// xᵀT(s)x = 0 (element-energy forms, so no cancellation of assembled
/// entries). T is complex symmetric, so with the transpose (not the
/// conjugate) the left eigenvector is the right one and the iteration
/// converges cubically, as RQI does for real symmetric pencils. The solves
/// use the unpivoted band LDLᵀ: its result is checked by the convergence of s
/// (and by the caller's neighbourhood tests), with the state space behind it.
///
/// `forms` are φ's (computed with φ): the forms of the real start, which are
/// bitwise those of φ as a complex vector (every imaginary part is 0), and
/// the first step's T'(s)φ skips the products of its zero imaginary part.
fn complex_rqi(model: &ScaledModel, s0: Complex64, phi: &[f64], forms: Forms) -> Result<Complex64, BeamError> {
    let n = model.n();
    let mut x: Vec<Complex64> = phi.iter().map(|&v| Complex64::new(v, 0.0)).collect();
    let c = |v: f64| Complex64::new(v, 0.0);
    let mut s = functional_root(model, (c(forms.0), c(forms.1), c(forms.2), c(forms.3)), s0)?;
    let mut real = true;
    let mut t = Vec::with_capacity(model.k.data.len());
    let (mut re, mut im, mut tmp) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..COMPLEX_RQI_MAX_STEPS {
        let (g, dg) = model.relaxation(s);
        // T(s) in band layout
        t.clear();
        t.extend(
            model
                .m
                .data
                .iter()
                .zip(&model.m_beam.data)
                .zip(&model.k.data)
                .map(|((&m, &mb), &k)| s * s * m + s * (model.c * mb) + g * k),
        );
        if model.has_spring() {
            for &i in &model.spring_dofs {
                t[i * (model.k.kd + 1)] += model.spring;
            }
        }
        if let Some(ka) = &model.k_axial {
            t.iter_mut().zip(&ka.data).for_each(|(ti, &v)| *ti += v);
        }
        let tiny = Complex64::new(f64::EPSILON * (model.k.data[0] + s.norm_sqr() * model.m.data[0]), 0.0);
        if !ldl_factor_for_inverse_iteration(&mut t, n, model.k.kd, tiny) {
            return Err(BeamError::numerical("T(s) factorisation broke down in RQI"));
        }
        // y = T'(s) x = (2s M̃ + c̃ M̃_beam + G'(s) K̃) x, from real products of Re x and Im x
        let mut y = vec![Complex64::new(0.0, 0.0); n];
        re.clear();
        re.extend(x.iter().map(|v| v.re));
        im.clear();
        im.extend(x.iter().map(|v| v.im));
        for (mat, coef) in [(&model.m, 2.0 * s), (&model.m_beam, Complex64::new(model.c, 0.0)), (&*model.k, dg)] {
            mat.mul_vec_into(&re, &mut tmp);
            y.iter_mut().zip(&tmp).for_each(|(yi, v)| *yi += coef * v);
            if !real {
                mat.mul_vec_into(&im, &mut tmp);
                y.iter_mut().zip(&tmp).for_each(|(yi, v)| *yi += coef * Complex64::new(0.0, *v));
            }
        }
        real = false;
        ldl_solve(&t, n, model.k.kd, &mut y);
        let scale = y.iter().fold(0.0f64, |a, v| a.max(v.norm_sqr())).sqrt();
        if !(scale.is_finite() && scale > 0.0) {
            return Err(BeamError::numerical("RQI on T(s) broke down"));
        }
        y.iter_mut().for_each(|v| *v /= scale);
        x = y;
        let next = rayleigh_functional_root(model, &x, s)?;
        let moved = (next - s).norm();
        s = next;
        if moved <= COMPLEX_RQI_TOL * s.norm() {
            return Ok(s);
        }
    }
    Err(BeamError::numerical("complex RQI did not converge"))
}

/// The root next to `start` of the Rayleigh functional
/// f(s) = xᵀT(s)x = s²m + s c̃ m_b + k_s + G(s)k (scalar Newton), with the
/// forms from element energies.
fn rayleigh_functional_root(model: &ScaledModel, x: &[Complex64], start: Complex64) -> Result<Complex64, BeamError> {
    functional_root(model, model.forms(x), start)
}

/// The root next to `start` of s²m + s c̃ m_b + k_s + G(s)k for given forms.
fn functional_root(
    model: &ScaledModel,
    (k, m, mb, ks): (Complex64, Complex64, Complex64, Complex64),
    start: Complex64,
) -> Result<Complex64, BeamError> {
    let mut s = start;
    for _ in 0..50 {
        let (g, dg) = model.relaxation(s);
        let f = s * s * m + s * model.c * mb + ks + g * k;
        let df = 2.0 * s * m + model.c * mb + dg * k;
        let step = f / df;
        if !step.is_finite() {
            return Err(BeamError::numerical("non-finite Rayleigh-functional step"));
        }
        s -= step;
        // quadratic convergence: a step at round-off level (4 eps) ends it
        if step.norm_sqr() <= 16.0 * f64::EPSILON * f64::EPSILON * s.norm_sqr() {
            return Ok(s);
        }
    }
    Err(BeamError::numerical("Rayleigh functional: Newton did not converge"))
}

/// Nonlinear Rayleigh-quotient iteration for a real pole: s ← root of
/// xᵀT(s)x = 0 (scalar Newton, element-energy forms), x ← T(s)⁻¹T'(s)x.
fn nonlinear_rqi(model: &ScaledModel, s0: Complex64, phi: &[f64]) -> Result<Complex64, BeamError> {
    let mut x: Vec<f64> = phi.to_vec();
    let mut s = s0.re;
    let spring = if model.has_spring() { model.spring } else { 0.0 };
    for _ in 0..50 {
        let (k, m, mb, ks) = model.forms(&x);
        let mut moved = 0.0;
        for _ in 0..3 {
            let (g, dg) = model.relaxation(Complex64::new(s, 0.0));
            let f = s * s * m + s * model.c * mb + ks + g.re * k;
            let df = 2.0 * s * m + model.c * mb + dg.re * k;
            let step = f / df;
            if !step.is_finite() {
                return Err(BeamError::numerical("non-finite nonlinear RQI step"));
            }
            s -= step;
            moved += step.abs();
        }
        if moved <= 1e-14 * s.abs() {
            return Ok(Complex64::new(s, 0.0));
        }
        let (g, dg) = model.relaxation(Complex64::new(s, 0.0));
        let lu = BandLu::factor_kd(model.n(), model.k.kd, |i, j| {
            let ks = if i == j && model.spring_dofs.contains(&i) { spring } else { 0.0 };
            let ka = model.k_axial.as_ref().map_or(0.0, |ka| ka.get(i, j));
            s * s * model.m.get(i, j) + s * model.c * model.m_beam.get(i, j) + ks + ka + g.re * model.k.get(i, j)
        });
        let Some(lu) = lu else { return Ok(Complex64::new(s, 0.0)) };
        let (mx, mbx, kx) = (model.m.mul_vec(&x), model.m_beam.mul_vec(&x), model.k.mul_vec(&x));
        let mut y: Vec<f64> = (0..model.n()).map(|i| 2.0 * s * mx[i] + model.c * mbx[i] + dg.re * kx[i]).collect();
        lu.solve(&mut y);
        let norm = y.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if !(norm.is_finite() && norm > 0.0) {
            return Err(BeamError::numerical("nonlinear RQI broke down"));
        }
        x = y.iter().map(|v| v / norm).collect();
    }
    Err(BeamError::numerical("nonlinear RQI did not converge"))
}

/// Path (a) turned into modal parameters with physical numbers: family j
/// (one-term approximation from the dense eigenvectors, exact when
/// decoupled) has a pair or not; the k-th complex pole by |s| goes to the k-th
/// family that has one, each real pole to the family whose one-term equation
/// it satisfies best; the uncoupled poles −Ωᵢ of variables with Δᵢ = 0 are
/// dropped.
fn state_space_modal(model: &ScaledModel, n_modes: usize) -> Result<ModalResult, BeamError> {
    let poles = state_space::scaled_poles(model)?;
    let approx = dense_family_approximations(model)?;
    let mut has_pair = Vec::with_capacity(n_modes);
    for &(a, b, c) in approx.iter().take(n_modes) {
        has_pair.push(family_roots(a, b, c, &model.ivs)?.iter().any(|s| s.im > 0.0));
    }
    let mut complex: Vec<Complex64> = poles.iter().copied().filter(|s| s.im > REAL_TOL * s.norm()).collect();
    complex.sort_by(|a, b| a.norm().total_cmp(&b.norm()));
    let uncoupled = |s: f64| model.ivs_all.iter().any(|&(d, om)| d == 0.0 && (s + om).abs() <= 1e-6 * om);
    let mut families: Vec<Vec<Complex64>> = vec![Vec::new(); n_modes];
    let mut next_pair = complex.iter();
    for (j, &pair) in has_pair.iter().enumerate() {
        if pair {
            let s =
                next_pair.next().ok_or_else(|| BeamError::numerical("state space has fewer pairs than families"))?;
            families[j].push(*s);
        }
    }
    for s in poles.iter().filter(|s| s.im.abs() <= REAL_TOL * s.norm()) {
        let x = s.re;
        if uncoupled(x) {
            continue;
        }
        let sc = Complex64::new(x, 0.0);
        let (g, _) = model.relaxation(sc);
        let best = approx
            .iter()
            .enumerate()
            .map(|(j, &(a, b, c))| (j, ((sc * sc + c * sc + a + b * g).norm() / (x * x + a + b))))
            .min_by(|p, q| p.1.total_cmp(&q.1))
            .map(|p| p.0);
        if let Some(j) = best.filter(|&j| j < n_modes) {
            families[j].push(Complex64::new(x, 0.0));
        }
    }
    Ok(assemble(&families, n_modes, model.omega_ref))
}

/// (a, b, c) of every family from a dense symmetric eigen-decomposition.
fn dense_family_approximations(model: &ScaledModel) -> Result<Vec<(f64, f64, f64)>, BeamError> {
    let kt = model.k_total().to_dense();
    let chol = nalgebra::Cholesky::new(model.m.to_dense())
        .ok_or_else(|| BeamError::numerical("mass matrix is not positive definite"))?;
    let l = chol.l();
    let linv = l.clone().try_inverse().ok_or_else(|| BeamError::numerical("singular Cholesky factor"))?;
    let c = &linv * kt * linv.transpose();
    let eig = nalgebra::SymmetricEigen::new(c);
    let phis = linv.transpose() * &eig.eigenvectors;
    let k = model.k.to_dense();
    let mb = model.m_beam.to_dense();
    let mut out: Vec<(f64, f64, f64)> = (0..model.n())
        .map(|j| {
            let phi = phis.column(j);
            let lam = eig.eigenvalues[j];
            let b = (phi.transpose() * &k * phi)[(0, 0)];
            (((lam - b).max(0.0)), b, model.c * (phi.transpose() * &mb * phi)[(0, 0)])
        })
        .collect();
    out.sort_by(|x, y| (x.0 + x.1).total_cmp(&(y.0 + y.1)));
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::beam::spec::{InternalVariable, PointMass, Support};

    fn beam(support: Support, e0a_nm: f64, spring: f64, mass: Option<(f64, f64)>) -> BeamSpec {
        BeamSpec {
            length_nm: 8.0,
            diameter_nm: 1.0,
            youngs_modulus_pa: 1e12,
            density_kg_m3: 2300.0,
            support,
            elements: 20,
            nonlocal_e0a_nm: e0a_nm,
            viscous_damping_n_s_m2: 0.0,
            internal_variables: vec![InternalVariable { delta: 0.3, omega_rad_s: 4e11 }],
            support_rotational_stiffness_n_m_rad: spring,
            point_mass: mass.map(|(mass_kg, x_nm)| PointMass { mass_kg, x_nm }),
            axial_force_n: 0.0,
            shear_deformation: None,
            section: None,
        }
    }

    /// Every combination the calibrations use: supports × ẽ (including 0 and
    /// grid-cell edges) × point mass × spring.
    fn cases() -> Vec<BeamSpec> {
        let mut out = Vec::new();
        for support in Support::ALL {
            for e0a in [0.0, 0.4, 1.2171, 1.9] {
                for spring in [0.0, 3e-19] {
                    for mass in [None, Some((3e-26, 2.9))] {
                        out.push(beam(support, e0a, spring, mass));
                    }
                }
            }
        }
        out
    }

    #[test]
    fn rqi_refinement_is_used_and_matches_a_scratch_solve() {
        for b in cases() {
            let mut solver = ModalSolver::new();
            solver.modal(&b, 3).unwrap();
            let ModalSolver { mesh, eigen, .. } = &mut solver;
            let mesh = mesh.as_ref().unwrap();
            let model = ScaledModel::new(&b, mesh);
            let kt = model.k_total();
            let params = model.pencil_params();
            // a fresh cache misses the exact key and must refine from its grid pencil
            eigen.exact = None;
            let refined = eigen.lowest(mesh, &params, &kt, &model.m, model.point_mass.as_ref(), 4).unwrap().to_vec();
            assert_eq!(eigen.last_method, Some(EigenMethod::Refined), "{b:?}");
            let scratch =
                lowest_eigenpairs(&kt, &model.m, 4, &mut Vec::new(), &|x| mesh.pencil_stiffness(&params, x)).unwrap();
            for (r, s) in refined.iter().zip(&scratch) {
                // both are Rayleigh quotients of vectors converged far below
                // 1e-6 (error quadratic in it); what remains is the rounding of
                // the quotient itself, ~1e-14 (see UnitMesh::stiffness_form):
                // 1e-12 leaves a 100× margin.
                assert!((r.lambda - s.lambda).abs() <= 1e-12 * s.lambda, "{b:?}: {} vs {}", r.lambda, s.lambda);
            }
        }
    }

    #[test]
    fn results_do_not_depend_on_what_the_solver_saw_before() {
        let all = cases();
        let mut shared = ModalSolver::new();
        for (i, target) in all.iter().enumerate() {
            // a history of other beams of the same mesh, nearby e0a included
            for other in all.iter().filter(|o| o.support == target.support).take(1 + i % 5) {
                let mut near = other.clone();
                near.nonlocal_e0a_nm = target.nonlocal_e0a_nm * 1.003;
                shared.modal(&near, 3).unwrap();
                shared.modal(other, 3).unwrap();
            }
            let seen = shared.modal(target, 3).unwrap();
            let fresh = ModalSolver::new().modal(target, 3).unwrap();
            assert_eq!(seen, fresh, "history changed the bits for {target:?}");
        }
    }

    /// The invariant of [`ModalSolver`] with the issue-13 mechanisms: a
    /// history of other axial forces, shear parameters (a different mesh) and
    /// nearby pencils leaves the bits of every result unchanged.
    #[test]
    fn results_with_axial_force_and_shear_do_not_depend_on_history() {
        use crate::beam::spec::ShearDeformation;
        let shear = |k: f64| Some(ShearDeformation { poisson_ratio: 0.2, shear_coefficient: k });
        let mut all = Vec::new();
        for support in Support::ALL {
            for (axial, sh) in
                [(2e-10, None), (-1e-9, None), (0.0, shear(0.9)), (3e-9, shear(0.7)), (-5e-10, shear(0.9))]
            {
                let mut b = beam(support, 0.8, 0.0, None);
                b.axial_force_n = axial;
                b.shear_deformation = sh;
                all.push(b);
            }
        }
        let mut shared = ModalSolver::new();
        for (i, target) in all.iter().enumerate() {
            for other in all.iter().filter(|o| o.support == target.support).take(1 + i % 5) {
                let mut near = other.clone();
                near.axial_force_n = target.axial_force_n * 0.97;
                near.nonlocal_e0a_nm *= 1.003;
                shared.modal(&near, 3).unwrap();
                shared.modal(other, 3).unwrap();
            }
            let seen = shared.modal(target, 3).unwrap();
            let fresh = ModalSolver::new().modal(target, 3).unwrap();
            assert_eq!(seen, fresh, "history changed the bits for {target:?}");
        }
    }
}
