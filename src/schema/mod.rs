//! Plan schemas (thesis chapter 3): a partially specified plan written as a
//! hierarchy of state machines, turned into the controllable process a learner
//! controls.
//!
//! - [`Schema`](crate::schema::Schema) is the designer's plan (Definition 4): plan states labelled
//!   with parallel actions (an action may be a machine of the schema), an
//!   initial state, final states, and edges `(state, event, condition) -> state`.
//!   It is read from a file ([`parse_schema`](crate::schema::parse_schema), [`read_schema`](crate::schema::read_schema); the format is
//!   documented in `docs/guide/src/schemas.md`), written back ([`write_schema`](crate::schema::write_schema)) or built
//!   in code ([`SchemaBuilder`](crate::schema::SchemaBuilder)).
//! - [`DecisionProcess`](crate::schema::DecisionProcess) is the construction of section 3.2.1 for every machine:
//!   action states, condition constituents, zero-time plan-actions and
//!   time-extended events ([`condition_constituents`](crate::schema::condition_constituents) is C_cnd).
//! - [`load_schema_plan`](crate::schema::load_schema_plan) gives the root machine's process as a [`Plan`](crate::plan::Plan), so
//!   that the executor, the learners, the domains and the experiments use a
//!   schema wherever they use a Petri Net Plan; the executor runs it with the
//!   schema's semantics (section 3.1.1, [`Plan::schema_process`](crate::plan::Plan::schema_process)).
//!
//! `docs/guide/src/schemas.md` describes the format and the semantics for designers.

mod builder;
mod construct;
mod error;
mod model;
mod report;
mod text;

use std::path::Path;

pub use builder::{MachineBuilder, SchemaBuilder};
pub use construct::{
    Constituent, Counts, DecisionProcess, DecisionState, DecisionStateId, EventGroup, MAX_ATOMS, MAX_CONDITIONS,
    MachineProcess, PlanAction, ProcessAction, ProcessTransition, condition_constituents,
};
pub use error::{SchemaError, SchemaFileError};
pub use model::{Edge, KEYWORDS, Machine, PlanState, Schema, StateKind};
pub use report::{check_failures, check_report, describe, to_dot};
pub use text::{parse_schema, write_schema};

use crate::plan::{AllowedAtoms, Plan};

/// The extension of schema files.
pub(crate) const EXTENSION: &str = "schema";

/// Whether `path` names a schema file (by its extension, `.schema`).
pub fn is_schema_path(path: &Path) -> bool {
    path.extension().is_some_and(|e| e == EXTENSION)
}

/// Reads the schema in `path`.
pub fn read_schema(path: &Path) -> Result<Schema, SchemaFileError> {
    let text = std::fs::read_to_string(path).map_err(|source| SchemaFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_schema(&text).map_err(|source| SchemaFileError::Schema {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads the schema in `path` and constructs its process, resolving atoms against `vocabulary`.
pub fn load_process(path: &Path, vocabulary: AllowedAtoms<'_>) -> Result<DecisionProcess, SchemaFileError> {
    let schema = read_schema(path)?;
    DecisionProcess::new(&schema, vocabulary).map_err(|source| SchemaFileError::Schema {
        path: path.to_path_buf(),
        source,
    })
}

/// The schema in `path` as a plan: its root machine's process, executed with
/// the schema's semantics.
pub fn load_schema_plan(path: &Path, vocabulary: AllowedAtoms<'_>) -> Result<Plan, SchemaFileError> {
    Ok(load_process(path, vocabulary)?.into_plan())
}
