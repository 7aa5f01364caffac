//! The reference solvers, each exact for any model the spec allows:
//! - `eigen`: the lowest eigenpairs of the symmetric pencil (K, M), Newton–
//!   Maehly from scratch or Rayleigh-quotient iteration from a cached
//!   neighbour, certified by an inertia count;
//! - `family`: per-mode pole polynomials of the decoupled model (certified
//!   Newton/Halley, the N = 1 families in interleaved lanes, Aberth
//!   fallback);
//! - `coupled`: Rayleigh-quotient iteration on T(s) when the extensions
//!   couple the modes; `subspace`: its second attempt, from the poles of
//!   T(s) projected on the pencil's eigenvectors, where crowded families
//!   defeat the one-term starts;
//! - `state_space` (A15) and `state_space_modal` (its poles as modal
//!   parameters: the reference of every path and the fallback on a
//!   numerical failure);
//! - `frf` (direct banded solves, streamed), `time_response` (the exact
//!   state-space exponential);
//! - `buckling`: the buckling bound of a compressive force from the
//!   assembled pencil, and `BeamSpec::validate` (fields + bound), so that
//!   `spec` never reaches into the assembly.
//!
//! Invariant: uses `linalg` and `fe`, never `fast`: every accelerator is
//! checked against these, so they may not lean on one.

pub(crate) mod buckling;
pub(crate) mod coupled;
pub(crate) mod eigen;
pub(crate) mod family;
pub(crate) mod frf;
pub(crate) mod state_space;
pub(crate) mod state_space_modal;
pub(crate) mod subspace;
pub(crate) mod time_response;
