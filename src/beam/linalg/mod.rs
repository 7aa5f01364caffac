//! Numerical kernels without physics: symmetric banded storage and its
//! factorisations (`band`: Cholesky, LDLᵀ with inertia counts, shifted
//! solves, complex LU), and forward-mode dual numbers (`dual`) for the
//! derivatives the Newton iterations need.
//!
//! Invariant: nothing here knows a beam; every other room may use it.

pub(crate) mod band;
pub(crate) mod dual;
pub(crate) mod small;
