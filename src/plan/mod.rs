//! Petri Net Plans: the PNP layer over a net (actions, goals, guards), and a
//! builder with the thesis's operators.

mod builder;
/// The thesis's example plans.
pub mod catalog;
mod definition;
mod error;
pub(crate) mod labels;

pub use builder::{ActionNet, PlaceRef, PlanBuilder, SensingNet, Tracker, TransitionRef};
pub(crate) use definition::PlanOrigin;
pub use definition::{ActionId, ActionInfo, AllowedAtoms, Call, InternalCondition, InternalKind, Plan, TransitionInfo};
pub use error::{PlanError, PlanWarning};
pub use labels::Function;
