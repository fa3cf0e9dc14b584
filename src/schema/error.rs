//! Why a plan schema cannot be read or used: every message names the line
//! (when the schema came from a file) and the offending token.

use std::fmt;
use std::path::PathBuf;

/// A schema that is malformed or inconsistent.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub struct SchemaError {
    /// The line of the schema file (1-based); `None` for schemas built in code.
    pub line: Option<usize>,
    /// What is wrong.
    pub message: String,
    /// The offending token as written (`<end>` when a line ran out).
    pub token: String,
}

impl SchemaError {
    /// An error at `line` about `token`.
    pub(crate) fn new(line: Option<usize>, message: impl Into<String>, token: impl Into<String>) -> Self {
        SchemaError {
            line,
            message: message.into(),
            token: token.into(),
        }
    }
}

impl fmt::Display for SchemaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(line) = self.line {
            write!(f, "line {line}: ")?;
        }
        write!(f, "{}: '{}'", self.message, self.token)
    }
}

/// A schema file that cannot be loaded; the message starts with its path.
#[derive(Debug, thiserror::Error)]
pub enum SchemaFileError {
    /// The file cannot be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The file is not a valid schema, or its process cannot be built.
    #[error("{path}: {source}")]
    Schema {
        /// The file.
        path: PathBuf,
        /// What is wrong, with the line and token.
        source: SchemaError,
    },
}
