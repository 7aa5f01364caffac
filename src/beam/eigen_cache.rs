//! The eigenpair caches of one mesh behind [`ModalSolver`](crate::beam::ModalSolver):
//! exact reuse for bitwise-equal parameters, Rayleigh-quotient iteration from
//! the nearest grid pencil's eigenvectors (their parameter-free products kept,
//! so a start costs O(n)), Newton–Maehly from scratch otherwise. The grid
//! point is a function of the input alone, so a cache changes speed, never
//! bits.

use std::collections::HashMap;

use crate::beam::error::BeamError;
use crate::beam::fe::model::{PencilParams, UnitMesh};
use crate::beam::linalg::band::{ShiftedLdl, SymBand};
use crate::beam::linalg::dual::Dual;
use crate::beam::solve::eigen::{lowest_eigenpairs, refine_eigenpairs, EigenPair, RqiStart};

/// Grid start pencils kept per solver (≈ 6 kB each for 6 modes of a
/// 20-element mesh). A calibration chain visits a few cells; a TMCMC run of
/// a 3-parameter pencil class (point mass: ẽ, μ̃, x̃) visits thousands while
/// its population still spreads over the prior, then settles in a few.
pub(crate) const GRID_CACHE: usize = 1024;

/// Plain grid pencils (ẽ, g̃) kept per solver. Measured on a 5-mode
/// shear-deformation search (17 models, 1.1 M solves, 2 threads): 2 012
/// distinct plain cells in all, so ≈ 1 000 per thread; with plain and
/// extended cells sharing one cache of 1 024, 18.6 k plain misses (each a
/// Newton–Maehly solve from scratch) for those 2 012 cells.
pub(crate) const PLAIN_GRID_CACHE: usize = 2048;

/// Eigenpair caches of one mesh (see [`ModalSolver`](crate::beam::ModalSolver)).
#[derive(Debug, Default, Clone)]
pub(crate) struct EigenCache {
    pub(crate) work: Vec<Dual<f64>>,
    pub(crate) ldl: ShiftedLdl,
    pub(crate) exact: Option<([u64; 8], Vec<EigenPair>)>,
    /// Grid pencil eigenvectors keyed by [`PencilParams::bits`] of the grid
    /// point: plain pencils (ẽ, g̃) and extended ones apart, so that a
    /// population sweeping an extended grid does not evict the parents every
    /// extended cell is refined from.
    pub(crate) grid: HashMap<[u64; 8], Vec<GridVector>>,
    pub(crate) plain_grid: HashMap<[u64; 8], Vec<GridVector>>,
    /// How the last [`EigenCache::lowest`] call got its answer (for tests).
    pub(crate) last_method: Option<EigenMethod>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum EigenMethod {
    Reused,
    Refined,
    Scratch,
}

/// An eigenvector of a grid pencil with the parameter-free pieces of its
/// products, so that its RQI start on any pencil of the mesh costs O(n):
/// M̃x = M̃₀x + ẽ²M̃₁x + μ̃N(Nᵀx), xᵀM̃x = xᵀM̃₀x + ẽ²xᵀM̃₁x + μ̃(Nᵀx)²,
/// xᵀ(K̃ + K̃_spring + K̃_N)x = xᵀK̃x + Σ_ends k̃_e x_e² + ñ(xᵀG̃₀x + ẽ²xᵀG̃₁x),
/// with xᵀK̃x = xᵀK̃_bx + g̃·xᵀK̃_γx on a Timoshenko mesh and
/// xᵀK̃₂x + l̃²·xᵀK̃₃x on a strain-gradient (C²) mesh.
#[derive(Debug, Clone)]
pub(crate) struct GridVector {
    pub(crate) vector: Vec<f64>,
    m0x: Vec<f64>,
    m1x: Vec<f64>,
    /// xᵀK̃x without shear (Euler–Bernoulli: all of it) and xᵀ(Σ∫γγᵀ)x.
    pub(crate) k_form: f64,
    pub(crate) shear_form: f64,
    /// xᵀ(Σ∫w‴w‴ᵀ)x (0 on a mesh without a strain gradient).
    gradient_form: f64,
    m0_form: f64,
    m1_form: f64,
    /// x_i² on the free rotation at x = 0 and at x = L (0 where the support fixes it).
    pub(crate) spring_sq: [f64; 2],
    /// xᵀG̃₀x and xᵀG̃₁x (axial-force forms; 0 when the mesh pencil has no force).
    pub(crate) g_forms: (f64, f64),
}

impl GridVector {
    pub(crate) fn new(mesh: &UnitMesh, vector: Vec<f64>) -> Self {
        let (mut m0x, mut m1x) = (Vec::new(), Vec::new());
        mesh.m0.mul_vec_into(&vector, &mut m0x);
        mesh.m1.mul_vec_into(&vector, &mut m1x);
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        GridVector {
            k_form: mesh.stiffness_form(&vector, 0.0),
            shear_form: mesh.shear.as_ref().map_or(0.0, |sh| sh.ks.bilinear(&vector, &vector)),
            gradient_form: mesh.gradient_form(&vector),
            m0_form: dot(&vector, &m0x),
            m1_form: dot(&vector, &m1x),
            spring_sq: mesh.spring_dofs.map(|d| d.map_or(0.0, |i| vector[i] * vector[i])),
            g_forms: {
                let f = mesh.energy_forms_ext(&vector, 0.0);
                (f[5], f[6])
            },
            vector,
            m0x,
            m1x,
        }
    }

    pub(crate) fn start(&self, params: &PencilParams, point_mass: Option<&(f64, Vec<f64>)>) -> RqiStart {
        let e2 = params.e_tilde * params.e_tilde;
        let mut mx: Vec<f64> = self.m0x.iter().zip(&self.m1x).map(|(a, b)| a + e2 * b).collect();
        let mut m_form = self.m0_form + e2 * self.m1_form;
        if let Some((mu, nv)) = point_mass {
            let w: f64 = nv.iter().zip(&self.vector).map(|(a, b)| a * b).sum();
            mx.iter_mut().zip(nv).for_each(|(y, a)| *y += mu * w * a);
            m_form += mu * w * w;
        }
        let k_n = if params.axial != 0.0 { params.axial * (self.g_forms.0 + e2 * self.g_forms.1) } else { 0.0 };
        let mut k_form = self.k_form;
        if params.gradient != 0.0 {
            k_form += params.gradient * self.gradient_form;
        }
        let rho = (k_form
            + params.shear * self.shear_form
            + params.spring[0] * self.spring_sq[0]
            + params.spring[1] * self.spring_sq[1]
            + k_n)
            / m_form;
        RqiStart { vector: self.vector.clone(), mx, rho }
    }
}

impl EigenCache {
    /// The `count` lowest eigenpairs of (k, m), the pencil of `params`.
    pub(crate) fn lowest(
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
    pub(crate) fn grid_starts(&mut self, mesh: &UnitMesh, g: PencilParams, count: usize) -> Option<&[GridVector]> {
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
    pub(crate) fn cells(&mut self, plain: bool) -> &mut HashMap<[u64; 8], Vec<GridVector>> {
        if plain {
            &mut self.plain_grid
        } else {
            &mut self.grid
        }
    }
}
