//! Why a reproduction stopped: the one error type of `reproduce`, in a file
//! of its own so that every stage can return it without importing the
//! pipeline that runs the stages.

use crate::report::ReportError;

/// Why a reproduction stopped.
#[derive(Debug)]
pub enum ReproduceError {
    Input(String),
    Failure(String),
}

impl std::fmt::Display for ReproduceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ReproduceError::Input(s) | ReproduceError::Failure(s) => write!(f, "{s}"),
        }
    }
}

impl std::error::Error for ReproduceError {}

impl From<ReportError> for ReproduceError {
    fn from(e: ReportError) -> Self {
        ReproduceError::Failure(e.to_string())
    }
}
