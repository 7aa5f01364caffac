//! Bodies of the `nanobeam` subcommands; `main.rs` only parses arguments.

use std::path::Path;

use crate::error::InputError;

pub mod calibrate;

/// What a command can fail with; the exit code follows the kind.
#[derive(Debug)]
pub enum CliError {
    /// Bad input (exit code 2): one line naming the field, value and allowed range.
    Input(InputError),
    /// A file could not be read (exit code 2).
    Read(String),
    /// Writing outputs failed (exit code 1).
    Output(String),
    /// The model or a solver failed (exit code 1).
    Failure(String),
}

impl CliError {
    pub fn read(path: &Path, e: std::io::Error) -> Self {
        CliError::Read(format!("cannot read {}: {e}", path.display()))
    }

    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::Input(_) | CliError::Read(_) => 2,
            CliError::Output(_) | CliError::Failure(_) => 1,
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CliError::Input(e) => write!(f, "{e}"),
            CliError::Read(s) | CliError::Output(s) | CliError::Failure(s) => write!(f, "{s}"),
        }
    }
}

impl From<InputError> for CliError {
    fn from(e: InputError) -> Self {
        CliError::Input(e)
    }
}
