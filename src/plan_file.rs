//! Loading plan files of either kind: a Petri Net Plan (PNML read, then labels
//! interpreted) or a plan schema (`.schema`, thesis chapter 3, loaded as its
//! constructed process); errors name the file.
//!
//! It sits above `plan` and `schema`, the one place that knows both file kinds.

use std::path::{Path, PathBuf};

use crate::plan::{Plan, PlanError, Vocabulary};
use crate::pnml::{self, PnmlFileError};
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

/// Reads and interprets the plan in `path` (JARP or standard PNML), or the
/// plan schema in `path` if its extension is `.schema`.
pub fn load_plan(path: &Path, vocabulary: Vocabulary<'_>) -> Result<Plan, LoadError> {
    if schema::is_schema_path(path) {
        return Ok(schema::load_schema_plan(path, vocabulary)?);
    }
    let net = pnml::read_file(path)?;
    Plan::from_net(net, vocabulary).map_err(|source| LoadError::Plan {
        path: path.to_path_buf(),
        source: Box::new(source),
    })
}
