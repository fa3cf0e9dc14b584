//! Agents running a plan with a learner at its choice points: one that drives
//! its world through the plan's registered actions ([`PlanAgent`](crate::agent::PlanAgent)), and one
//! stepped by a world that drives itself ([`StepwiseAgent`](crate::agent::StepwiseAgent): the caller says
//! what holds and what was earned, the agent names the action to run).

mod driving;
/// A plan agent stepped from outside.
pub mod stepwise;

pub use driving::PlanAgent;
pub use stepwise::{ActionOutcome, StepError, StepwiseAgent};
