//! The typed error of the library's file, search and report layers (`sweep`, `report`,
//! `paper`): a message of its own, a cause with what was being done ("cannot read results
//! file x: …"), or a lower layer's typed error passed through unchanged. Its `source()` chain
//! is what `{:#}` prints ("context: cause"), so messages read as they did before these layers
//! had a typed error.
//! Lower layers keep their own types (`StudyError`, `SimError`, `SolverError`, `RecordError`,
//! `FsError`); this module imports nothing that imports it.

use std::error::Error as StdError;
use std::fmt;

/// A boxed cause.
pub type Source = Box<dyn StdError + Send + Sync + 'static>;

/// The library error of `sweep`, `report` and `paper`.
///
/// `Display` and `Error` are written by hand rather than derived with thiserror because
/// `{:#}` must print the whole chain ("context: cause"), which the derive does not do, and
/// the CLI's and TUI's messages and the sweep's notes are formatted that way.
#[derive(Debug)]
pub enum Error {
    /// A message of its own.
    Message(String),
    /// A cause, and what was being done when it happened.
    Context { context: String, source: Source },
    /// A lower layer's error, shown as it is (its own causes are this error's).
    Other(Source),
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let top: &dyn fmt::Display = match self {
            Error::Message(m) => m,
            Error::Context { context, .. } => context,
            Error::Other(e) => e,
        };
        write!(f, "{top}")?;
        if f.alternate() {
            let mut cause = StdError::source(self);
            while let Some(c) = cause {
                write!(f, ": {c}")?;
                cause = c.source();
            }
        }
        Ok(())
    }
}

impl StdError for Error {
    fn source(&self) -> Option<&(dyn StdError + 'static)> {
        match self {
            Error::Message(_) => None,
            Error::Context { source, .. } => Some(source.as_ref()),
            Error::Other(e) => e.source(),
        }
    }
}

/// The library's result type in `sweep`, `report` and `paper`.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// An error with a message of its own.
    pub fn msg(message: impl fmt::Display) -> Self {
        Error::Message(message.to_string())
    }

    /// This error as the cause of `context`.
    pub fn context(self, context: impl fmt::Display) -> Self {
        Error::Context {
            context: context.to_string(),
            source: Box::new(self),
        }
    }
}

/// Early return with a formatted [`Error::Message`].
macro_rules! bail {
    ($($arg:tt)*) => {
        return Err($crate::error::Error::msg(format!($($arg)*)))
    };
}
pub(crate) use bail;

/// Early return with a formatted [`Error::Message`] unless `cond` holds.
macro_rules! ensure {
    ($cond:expr, $($arg:tt)*) => {
        if !$cond {
            $crate::error::bail!($($arg)*);
        }
    };
}
pub(crate) use ensure;

/// Attach what was being done to an error (`Result`) or to a missing value (`Option`).
pub trait Context<T> {
    fn context(self, context: impl fmt::Display) -> Result<T>;
    fn with_context<C: fmt::Display>(self, context: impl FnOnce() -> C) -> Result<T>;
}

impl<T, E: Into<Source>> Context<T> for std::result::Result<T, E> {
    fn context(self, context: impl fmt::Display) -> Result<T> {
        self.map_err(|e| Error::Context {
            context: context.to_string(),
            source: e.into(),
        })
    }

    fn with_context<C: fmt::Display>(self, context: impl FnOnce() -> C) -> Result<T> {
        self.map_err(|e| Error::Context {
            context: context().to_string(),
            source: e.into(),
        })
    }
}

impl<T> Context<T> for Option<T> {
    fn context(self, context: impl fmt::Display) -> Result<T> {
        self.ok_or_else(|| Error::msg(context))
    }

    fn with_context<C: fmt::Display>(self, context: impl FnOnce() -> C) -> Result<T> {
        self.ok_or_else(|| Error::msg(context()))
    }
}

/// Lower layers' errors pass through `?` unchanged.
macro_rules! pass_through {
    ($($t:ty),* $(,)?) => {
        $(impl From<$t> for Error {
            fn from(e: $t) -> Self {
                Error::Other(Box::new(e))
            }
        })*
    };
}

pass_through!(
    std::io::Error,
    std::fmt::Error,
    serde_json::Error,
    csv::Error,
    csv::IntoInnerError<csv::Writer<Vec<u8>>>,
    crate::study::StudyError,
    crate::sim::SimError,
    crate::excitation::RecordError,
    crate::fsutil::FsError,
    crate::risk::RiskError,
);

/// A formatted [`Error::Message`].
macro_rules! error {
    ($($arg:tt)*) => {
        $crate::error::Error::msg(format!($($arg)*))
    };
}
pub(crate) use error;

#[cfg(test)]
mod tests {
    use super::*;

    /// `{:#}` prints the chain as "context: cause: cause", `{}` only the outermost message;
    /// a passed-through error shows as itself with its own causes.
    #[test]
    fn alternate_display_prints_the_chain() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let read: Result<()> = Err(io).context("cannot read results file r.json");
        let e = read.unwrap_err().context("cannot merge");
        assert_eq!(e.to_string(), "cannot merge");
        assert_eq!(
            format!("{e:#}"),
            "cannot merge: cannot read results file r.json: no such file"
        );
        let passed: Error = std::fmt::Error.into();
        assert_eq!(format!("{passed:#}"), std::fmt::Error.to_string());
        let missing: Result<u8> = None.context("the history has no time column");
        assert_eq!(
            format!("{:#}", missing.unwrap_err()),
            "the history has no time column"
        );
    }
}
