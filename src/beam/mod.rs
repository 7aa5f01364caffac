//! Physics only: the beam description, finite elements, poles, modal
//! parameters and FRF. Knows nothing of probability.
//!
//! Map: `spec` (YAML contract) → `element` (A3–A7) → `model` (assembly,
//! supports, extensions, nondimensional scaling) → poles by `state_space`
//! (A15, reference; `state_space_modal` turns them into modes) or `modal`
//! (exact decoupled families via `eigen` + `family`, with certified eigenvalue
//! interpolants from `spectrum` (Euler–Bernoulli) and `shear_spectrum`
//! (Timoshenko), a point mass by the secular equation of `mass_spectrum`, the axial force on a simply
//! supported mesh by the wavenumber blocks of `axial_spectrum`, support springs
//! on it by the rank ≤ 2 secular equation of `spring_spectrum` and a point mass
//! with damping or an axial force by the rank-1 one of `mass_blocks`, springs and
//! a point mass together by the order ≤ 3 secular determinant of `spring_mass`, or, in `coupled`,
//! Rayleigh-quotient iteration on T(s) when the extensions couple the modes;
//! the result types in `modal_result`) →
//! `frf` (direct banded solves); `time_response` (impulse response by the
//! exact matrix exponential of the state space).

mod axial_spectrum;
pub(crate) mod band;
mod buckling;
mod continuum_tail;
mod coupled;
pub(crate) mod dual;
pub(crate) mod eigen;
pub mod element;
mod error;
pub(crate) mod family;
mod frf;
mod jet;
mod mass_blocks;
mod mass_spectrum;
mod modal;
mod modal_result;
pub(crate) mod model;
mod shear_blocks;
mod shear_continuum;
mod shear_spectrum;
pub mod spec;
mod spectrum;
mod spring_mass;
mod spring_spectrum;
mod state_space;
mod state_space_modal;
mod time_response;

pub use axial_spectrum::{AxialBlocks, INVARIANCE_TOL as AXIAL_INVARIANCE_TOL};
pub use buckling::buckling_load_n;
pub use error::BeamError;
pub use frf::{frf, frf_each, frf_points, max_frequency_rad_s, MAX_OMEGA_TILDE};
pub use mass_spectrum::{point_mass_direct_eigenvalues, point_mass_eigenvalues, MASS_CERTIFIED_TOL};
pub use modal::{modal, modal_observables, ModalSolver};
pub use modal_result::{ModalResult, Mode, SolverPath};
pub use shear_spectrum::{
    certificates as shear_spectrum_certificates, direct_eigenvalues as shear_direct_eigenvalues,
    interpolated_eigenvalues as shear_interpolated_eigenvalues, Certificate as ShearSpectrumCertificate,
    SHEAR_CERTIFIED_TOL,
};
pub use spec::{BeamSpec, InternalVariable, PointMass, ShearDeformation, Support};
pub use spectrum::{
    certificates as spectrum_certificates, direct_eigenvalues, interpolated_eigenvalues,
    Certificate as SpectrumCertificate, CERTIFIED_TOL,
};
pub use state_space_modal::{modal_state_space, poles_state_space};
pub use time_response::impulse_response;
