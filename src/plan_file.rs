//! Loading plan files of either kind: a Petri Net Plan (PNML read, then labels
//! interpreted) or a plan schema (`.schema`, thesis chapter 3, loaded as its
//! constructed process); errors name the file.
//!
//! It sits above `plan` and `schema`, the one place that knows both file kinds.

use std::path::{Path, PathBuf};

use crate::plan::{AllowedAtoms, Plan, PlanError};
use crate::pnml::{self, PnmlError, PnmlFileError};
use crate::schema::{self, SchemaFileError};

/// A plan file that cannot be loaded; the message starts with its path.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file cannot be read or is not a valid net.
    #[error(transparent)]
    File(#[from] PnmlFileError),
    /// The schema file cannot be read, or is not a valid schema.
    #[error(transparent)]
    Schema(#[from] SchemaFileError),
    /// The net is not a valid plan.
    #[error("{path}: {source}")]
    Plan {
        /// The file.
        path: PathBuf,
        /// What is wrong, naming the element and token.
        source: Box<PlanError>,
    },
}

impl LoadError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            LoadError::File(e) => e.path(),
            LoadError::Schema(SchemaFileError::Io { path, .. } | SchemaFileError::Schema { path, .. }) => path,
            LoadError::Plan { path, .. } => path,
        }
    }

    /// The element at fault (a place, transition or arc id; a schema's
    /// `line N`), where the error names one.
    pub fn element(&self) -> Option<String> {
        match self {
            LoadError::File(PnmlFileError::Pnml { error, .. }) => match error {
                PnmlError::BadCount { id, .. } => Some(id.clone()),
                PnmlError::MissingEnd { arc, .. } => Some(arc.clone()),
                _ => None,
            },
            LoadError::Schema(SchemaFileError::Schema { source, .. }) => source.line.map(|l| format!("line {l}")),
            LoadError::Plan { source, .. } => match source.as_ref() {
                PlanError::PlaceLabel { place, .. } => Some(place.clone()),
                PlanError::TransitionLabel { transition, .. } | PlanError::Guard { transition, .. } => {
                    Some(transition.clone())
                }
                _ => None,
            },
            _ => None,
        }
    }

    /// The offending token as written, where the error names one.
    pub fn token(&self) -> Option<String> {
        match self {
            LoadError::File(PnmlFileError::Pnml {
                error: PnmlError::BadCount { text, .. },
                ..
            }) => Some(text.clone()),
            LoadError::Schema(SchemaFileError::Schema { source, .. }) => Some(source.token.clone()),
            LoadError::Plan { source, .. } => match source.as_ref() {
                PlanError::PlaceLabel { token, .. } | PlanError::TransitionLabel { token, .. } => Some(token.clone()),
                PlanError::Guard { source, .. } => Some(source.token.clone()),
                _ => None,
            },
            _ => None,
        }
    }
}

/// Reads and interprets the plan in `path` (JARP or standard PNML), or the
/// plan schema in `path` if its extension is `.schema`.
pub fn load_plan(path: &Path, vocabulary: AllowedAtoms<'_>) -> Result<Plan, LoadError> {
    if schema::is_schema_path(path) {
        return Ok(schema::load_schema_plan(path, vocabulary)?);
    }
    let net = pnml::read_file(path)?;
    Plan::from_net(net, vocabulary).map_err(|source| LoadError::Plan {
        path: path.to_path_buf(),
        source: Box::new(source),
    })
}
