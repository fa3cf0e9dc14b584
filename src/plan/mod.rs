//! Petri Net Plans: the PNP layer over a net (actions, goals, guards), and a
//! builder with the thesis's operators.

mod builder;
pub mod catalog;
mod error;
pub mod labels;
mod definition;

pub use builder::{ActionNet, PlaceRef, PlanBuilder, SensingNet, TransitionRef, Tracker};
pub use error::PlanError;
pub use labels::Function;
pub use definition::{ActionId, ActionInfo, Call, InternalCondition, InternalKind, Plan, TransitionInfo, Vocabulary};
