//! The risk module's errors: a hazard file's problem names the file, line and field and gives
//! a hint; a hazard that cannot meet the study's intensity measure says both.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum RiskError {
    #[error("cannot read {}: {source}", path.display())]
    Read {
        path: PathBuf,
        source: std::io::Error,
    },
    /// A hazard-curve CSV that does not say what rocklab needs.
    #[error("{}:{line}: {field}: {message}\n  hint: {hint}", path.display())]
    Hazard {
        path: PathBuf,
        line: u64,
        field: String,
        message: String,
        hint: String,
    },
    /// The hazard's intensity measure is not one the study's scaling converts from.
    #[error(
        "{}: the hazard's header names `{header}`, but the study scales its records to {scaling}\n  \
         hint: {hint}",
        path.display()
    )]
    ImMismatch {
        path: PathBuf,
        header: String,
        scaling: String,
        hint: String,
    },
    /// Risk options that cannot be used (a non-positive MCE, an unknown rating, …).
    #[error("{field}: {message}\n  hint: {hint}")]
    Option {
        field: String,
        message: String,
        hint: String,
    },
    /// The fragility results the risk is computed from.
    #[error("{}: {message}\n  hint: {hint}", path.display())]
    Results {
        path: PathBuf,
        message: String,
        hint: String,
    },
    #[error("cannot write {}: {message}", path.display())]
    Write { path: PathBuf, message: String },
}

impl RiskError {
    pub(crate) fn option(field: &str, message: impl Into<String>, hint: &str) -> Self {
        RiskError::Option {
            field: field.to_string(),
            message: message.into(),
            hint: hint.to_string(),
        }
    }
}
