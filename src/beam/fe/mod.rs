//! The finite-element model: the element matrices (`element`: Hermite
//! cubic A3–A7, the axial geometric stiffness, the bending–shear split
//! Timoshenko element with its quintic bending and cubic shear parts, the C²
//! quintic Hermite element of a strain-gradient beam) and their assembly
//! (`model`: the unit mesh, the supports by DOF elimination,
//! rotational springs, a point mass, the dimensionless scaling and the
//! interpolation grid of the eigenpair cache).
//!
//! Invariant: matrices only. Nothing here solves for a pole; the rooms above
//! (`solve`, `fast`, the dispatch in `modal`) read the assembled pencil.

pub mod element;
pub(crate) mod model;
pub(crate) mod scaling;
