//! What can go wrong reading a plan file.

use std::io;
use std::path::{Path, PathBuf};

use crate::net::NetError;

/// A PNML text that does not describe a net: the message names the element id
/// (or, for an element without one, its line and column) and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PnmlError {
    /// The text is not well-formed XML.
    #[error("malformed XML at line {line}, column {column}: {message}")]
    Xml {
        /// 1-based line of the fault.
        line: u32,
        /// 1-based column of the fault.
        column: u32,
        /// The XML parser's description.
        message: String,
    },
    /// Elements nest deeper than [`MAX_NESTING`](super::MAX_NESTING).
    #[error("elements nest deeper than {limit} levels at line {line}, column {column}; no plan file needs that many")]
    TooDeep {
        /// 1-based line of the first element too deep.
        line: u32,
        /// 1-based column of that element.
        column: u32,
        /// The bound.
        limit: usize,
    },
    /// The root element is not `pnml`.
    #[error("the root element is <{found}>, not <pnml>")]
    NotPnml {
        /// The root element's local name.
        found: String,
    },
    /// The `pnml` element holds no `net`.
    #[error("the <pnml> element holds no <net>")]
    NoNet,
    /// A place, transition or arc has no (or an empty) `id` attribute.
    #[error("{element} at line {line}, column {column} has no id")]
    MissingId {
        /// `place`, `transition` or `arc`.
        element: &'static str,
        /// 1-based line of the element.
        line: u32,
        /// 1-based column of the element.
        column: u32,
    },
    /// An arc lacks its `source` or `target` attribute.
    #[error("arc '{arc}' has no {end} attribute")]
    MissingEnd {
        /// The arc id.
        arc: String,
        /// `source` or `target`.
        end: &'static str,
    },
    /// An initial marking or an arc inscription that is not a count from 0 to 255.
    #[error("{element} '{id}': {field} '{text}' is not a token count (an integer from 0 to 255)")]
    BadCount {
        /// `place` or `arc`.
        element: &'static str,
        /// The element id.
        id: String,
        /// `initial marking` or `inscription`.
        field: &'static str,
        /// The offending text, trimmed.
        text: String,
    },
    /// The elements read do not form a valid net (the message names the ids).
    #[error(transparent)]
    Net(#[from] NetError),
}

/// A plan file that could not be read: its Display starts with the file's path.
#[derive(Debug, thiserror::Error)]
pub enum PnmlFileError {
    /// The file could not be read.
    #[error("{}: {error}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        error: io::Error,
    },
    /// The file was read but is not a valid plan.
    #[error("{}: {error}", path.display())]
    Pnml {
        /// The file.
        path: PathBuf,
        /// What is wrong in it.
        error: PnmlError,
    },
}

impl PnmlFileError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            PnmlFileError::Io { path, .. } | PnmlFileError::Pnml { path, .. } => path,
        }
    }
}

/// A dialect name other than `jarp` or `standard`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown PNML dialect '{0}' (expected 'jarp' or 'standard')")]
pub struct UnknownDialect(
    /// The name given.
    pub String,
);
