//! Physics only: the beam description, finite elements, poles, modal
//! parameters and FRF. Knows nothing of probability.

pub mod spec;

pub use spec::{BeamSpec, InternalVariable, PointMass, Support};
