//! Input validation errors shared by every module that reads user files.

use std::fmt;

/// A value that breaks a documented rule of an input file or flag: the one
/// input error of every layer (the user can fix it; the CLI exits with 2).
///
/// Displayed as one line: `invalid <field> = <value>: allowed <allowed>`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid {field} = {value}: allowed {allowed}")]
pub struct InputError {
    /// Dotted path of the offending field, e.g. `beam.length_nm` or `modes[2].zeta_sd`.
    pub field: String,
    /// The offending value as written (or a short description of it).
    pub value: String,
    /// The allowed range or set, e.g. `> 0` or `one of: simply-supported, clamped-clamped`.
    pub allowed: String,
}

impl InputError {
    pub fn new(field: impl Into<String>, value: impl fmt::Display, allowed: impl Into<String>) -> Self {
        Self { field: field.into(), value: value.to_string(), allowed: allowed.into() }
    }

    /// The same error with `prefix.` put in front of the field path.
    pub fn within(mut self, prefix: &str) -> Self {
        self.field = if self.field.is_empty() { prefix.to_string() } else { format!("{prefix}.{}", self.field) };
        self
    }
}

/// Checks `value > 0` and finite.
pub fn positive(field: &str, value: f64) -> Result<(), InputError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(InputError::new(field, value, "> 0 (finite)"))
    }
}

/// Checks `value >= 0` and finite.
pub fn non_negative(field: &str, value: f64) -> Result<(), InputError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(InputError::new(field, value, ">= 0 (finite)"))
    }
}

/// Parses YAML into `T`, turning serde's message (unknown field, missing field,
/// unknown variant, wrong type) into an [`InputError`] that names the field.
pub fn parse_yaml<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, InputError> {
    serde_yaml::from_str(text).map_err(|e| {
        let msg = e.to_string();
        let field = serde_field_of(&msg).unwrap_or_else(|| "<document>".to_string());
        InputError::new(field, "(see message)", msg)
    })
}

/// Extracts the field named in a serde error message ("unknown field `x`",
/// "missing field `x`", or the "path.to.field:" prefix serde_yaml adds).
fn serde_field_of(msg: &str) -> Option<String> {
    for key in ["unknown field `", "missing field `"] {
        if let Some(start) = msg.find(key) {
            let rest = &msg[start + key.len()..];
            let name = rest.split('`').next()?;
            let prefix = msg.split(": ").next().filter(|p| !p.contains(' ') && !p.is_empty());
            return Some(match prefix {
                Some(p) if p != name => format!("{p}.{name}"),
                _ => name.to_string(),
            });
        }
    }
    let prefix = msg.split(": ").next()?;
    (!prefix.contains(' ') && !prefix.is_empty()).then(|| prefix.to_string())
}
