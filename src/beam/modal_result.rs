//! The modal result: physical modes (34)–(35), overdamped modes and real
//! poles, built from the roots of the modal families by every path of
//! [`crate::beam::ModalSolver`] alike.
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

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

use crate::beam::error::BeamError;
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

/// Which method produced the last [`crate::beam::ModalSolver::modal`] result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolverPath {
    /// (b) exact decoupling into family polynomials.
    Decoupled,
    /// (c) coupling extensions: nonlinear Rayleigh-quotient iteration on T(s)
    /// from each family's one-term approximation.
    CoupledRqi,
    /// (c), second attempt: the same iteration from the poles of T(s)
    /// projected on the pencil's eigenvectors, because the one-term starts
    /// failed (crowded families; `solve/subspace.rs`).
    CoupledSubspace,
    /// (a) the state-space reference, used because (b)/(c) failed numerically.
    StateSpaceFallback,
}

/// The oscillatory member of a family: the Im > 0 root of largest |s|.
pub(crate) fn oscillatory_pair(family: &[Complex64]) -> Option<Complex64> {
    family.iter().copied().filter(|s| s.im > 0.0).max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
}

pub(crate) fn check_mode_count(n_modes: usize, n: usize) -> Result<(), BeamError> {
    if n_modes == 0 || n_modes > n {
        return Err(InputError::new("n_modes", n_modes, format!("1..={n} (free DOFs of this mesh)")).into());
    }
    Ok(())
}

/// Physical modes 1..=n_modes from the roots of families 1..=n_modes (in
/// eigenpair order): each family's oscillatory pair (largest |s| if there
/// are several) or, without one, an overdamped mode with its real roots.
pub(crate) fn assemble<F: std::ops::Deref<Target = [Complex64]>>(
    families: &[F],
    n_modes: usize,
    omega_ref: f64,
) -> ModalResult {
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
