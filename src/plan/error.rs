//! Why a net is not a valid plan: every message names the element and the token.

use crate::condition::ConditionError;
use crate::net::NetError;

/// A plan that cannot be loaded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PlanError {
    /// The net itself is malformed.
    #[error(transparent)]
    Net(#[from] NetError),
    /// The net has no places: nothing could ever run (an empty file, or XML
    /// whose net holds no place this reader recognises).
    #[error("the net has no places: there is no plan to run")]
    Empty,
    /// A place label is malformed.
    #[error("place '{place}' (label '{label}'): {reason}: '{token}'")]
    PlaceLabel {
        /// The place id.
        place: String,
        /// Its label.
        label: String,
        /// The offending token.
        token: String,
        /// What is wrong.
        reason: String,
    },
    /// A transition label is malformed or names something unknown.
    #[error("transition '{transition}' (label '{label}'): {reason}: '{token}'")]
    TransitionLabel {
        /// The transition id.
        transition: String,
        /// Its label.
        label: String,
        /// The offending token.
        token: String,
        /// What is wrong.
        reason: String,
    },
    /// A guard does not parse.
    #[error("transition '{transition}' (label '{label}'): broken guard: {source}")]
    Guard {
        /// The transition id.
        transition: String,
        /// Its label.
        label: String,
        /// The parse error, with the token.
        source: Box<ConditionError>,
    },
}

/// Something unusual in a plan that the public PNP library accepts, and so do
/// we: the transition, its label and what is unusual.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("transition '{transition}' (label '{label}'): {message}")]
pub struct PlanWarning {
    /// The transition id.
    pub transition: String,
    /// Its label.
    pub label: String,
    /// What is unusual and what it does.
    pub message: String,
}
