//! The error type of the presentation layer.

use std::path::PathBuf;

/// Why a figure, table, template or output directory could not be produced.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// The data handed to a plotting function is unusable (mismatched
    /// lengths, no finite values, ...). `what` names the offending input.
    #[error("invalid plot data in {what}: {reason}")]
    InvalidData { what: String, reason: String },
    /// plotters failed while drawing (message of the backend error).
    #[error("drawing failed: {0}")]
    Drawing(String),
    /// A template could not be parsed or rendered; `file` is the template file.
    #[error("template {}: {message}", file.display())]
    Template { file: PathBuf, message: String },
    /// The output path cannot take an output directory (an existing file, a
    /// foreign non-empty directory, an unwritable parent): a bad `--out`.
    #[error("invalid --out = {}: allowed a new path, an empty directory or a directory written by nanobeam; {reason}", path.display())]
    OutPath { path: PathBuf, reason: String },
    /// A file-system operation failed on `path`.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl ReportError {
    pub(crate) fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Self {
        ReportError::InvalidData { what: what.into(), reason: reason.into() }
    }

    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        ReportError::Io { path: path.into(), source }
    }
}

/// Result alias of the presentation layer.
pub type Result<T> = std::result::Result<T, ReportError>;
