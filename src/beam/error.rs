//! The error type of the forward model.

use crate::error::InputError;

/// Everything the forward model can refuse or fail at. Never a panic.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BeamError {
    /// A value outside its documented range (spec field, position, mode count).
    #[error("{0}")]
    Input(#[from] InputError),
    /// A numerical method did not converge or met a singular matrix.
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl BeamError {
    pub(crate) fn numerical(msg: impl Into<String>) -> Self {
        BeamError::Numerical(msg.into())
    }
}
