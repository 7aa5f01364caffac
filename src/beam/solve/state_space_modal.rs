//! Path (a), the state-space reference turned into modal parameters: the
//! poles of the state matrix (A15, `state_space.rs`) assigned to physical
//! modes. Used as the reference in tests and as the fallback when the
//! decoupled or coupled path of [`crate::beam::ModalSolver`] fails numerically.

use num_complex::Complex64;

use crate::beam::error::BeamError;
use crate::beam::fe::model::UnitMesh;
use crate::beam::fe::scaling::ScaledModel;
use crate::beam::modal_result::{assemble, check_mode_count, ModalResult};
use crate::beam::solve::family::{family_roots, REAL_TOL};
use crate::beam::solve::state_space;
use crate::beam::spec::BeamSpec;

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

/// Path (a) turned into modal parameters with physical numbers: family j
/// (one-term approximation from the dense eigenvectors, exact when
/// decoupled) has a pair or not; the k-th complex pole by |s| goes to the k-th
/// family that has one, each real pole to the family whose one-term equation
/// it satisfies best; the uncoupled poles −Ωᵢ of variables with Δᵢ = 0 are
/// dropped.
pub(crate) fn state_space_modal(model: &ScaledModel, n_modes: usize) -> Result<ModalResult, BeamError> {
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
    let mut kt = model.k_total().to_dense();
    if model.foundation != 0.0 {
        kt += model.m_beam.to_dense() * model.foundation;
    }
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
