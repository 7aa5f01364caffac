//! Physics only: the beam description, finite elements, poles, modal
//! parameters, FRF and time response. Knows nothing of probability.
//!
//! # Rooms
//! The face (this file) re-exports what the rest of the crate uses:
//! [`BeamSpec`] and its parts, [`modal()`], [`ModalSolver`], [`frf()`],
//! [`impulse_response`], [`buckling_load_n`], and the certificates tests
//! read. Behind it, bottom to top (each room may use those below it only;
//! `tests/tidy.rs` holds every file to ARCHITECTURE.md's rooms table):
//! - `spec` (the YAML contract, field validation), `error` ([`BeamError`]),
//!   `modal_result` ([`ModalResult`], [`Mode`], [`SolverPath`]): plain types;
//! - `linalg`: banded factorisations, dual numbers, small dense solves;
//! - `fe`: the finite-element model (elements, assembly, supports, the
//!   dimensionless scaling);
//! - `solve`: the reference solvers (eigenpairs, pole families, coupled RQI,
//!   state space, FRF, time response, the buckling bound);
//! - `fast`: the exact accelerators, each certified against `solve`
//!   (interpolated spectra, wavenumber blocks, secular paths, continuum
//!   limits);
//! - `eigen_cache`: the eigenpair caches of one mesh;
//! - `modal`: the dispatch ([`ModalSolver`]): which path a model takes, and
//!   the reference behind each. Only it uses `fast`.

mod eigen_cache;
mod error;
mod fast;
mod fe;
mod linalg;
mod modal;
mod modal_result;
mod solve;
pub mod spec;

pub use error::BeamError;
pub use fast::axial_spectrum::{AxialBlocks, INVARIANCE_TOL as AXIAL_INVARIANCE_TOL};
pub use fast::mass_spectrum::{point_mass_direct_eigenvalues, point_mass_eigenvalues, MASS_CERTIFIED_TOL};
pub use fast::shear_spectrum::{
    certificates as shear_spectrum_certificates, direct_eigenvalues as shear_direct_eigenvalues,
    interpolated_eigenvalues as shear_interpolated_eigenvalues, Certificate as ShearSpectrumCertificate,
    SHEAR_CERTIFIED_TOL,
};
pub use fast::spectrum::{
    certificates as spectrum_certificates, direct_eigenvalues, interpolated_eigenvalues,
    Certificate as SpectrumCertificate, CERTIFIED_TOL,
};
pub use fe::element;
pub use modal::{modal, modal_observables, ModalSolver};
pub use modal_result::{ModalResult, Mode, SolverPath};
pub use solve::buckling::buckling_load_n;
pub use solve::frf::{frf, frf_each, frf_points, max_frequency_rad_s, MAX_OMEGA_TILDE};
pub use solve::state_space_modal::{modal_state_space, poles_state_space};
pub use solve::time_response::impulse_response;
pub use spec::{BeamSpec, InternalVariable, PointMass, ShearDeformation, Support};
