//! What a domain's task reports: why it cannot run ([`TaskError`]), what an
//! episode earned ([`EpisodeOutcome`]), and the values of named markings it traces.

use crate::executor::ExecError;
use crate::learning::{Learner, StateKey};
use crate::net::Marking;
use crate::plan::{Plan, PlanError};

/// Why a task cannot run.
#[derive(Debug, thiserror::Error)]
pub enum TaskError {
    /// The plan cannot be executed.
    #[error(transparent)]
    Exec(#[from] ExecError),
    /// The plan does not load.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// A domain's parameters are invalid.
    #[error("invalid domain parameters: {0}")]
    Invalid(String),
    /// A plan lacks a place a domain needs.
    #[error("plan '{plan}' has no place labelled '{label}'")]
    MissingPlace {
        /// The plan.
        plan: String,
        /// The label looked for.
        label: String,
    },
    /// The run was asked to stop before it ended.
    #[error("the run was stopped before it ended")]
    Stopped,
    /// Something the task depends on outside this library failed (another
    /// process, a link, a device): its own error, which says what.
    #[error(transparent)]
    External(Box<dyn std::error::Error + Send + Sync>),
}

/// What one episode earned.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct EpisodeOutcome {
    /// Undiscounted sum of rewards.
    pub ret: f64,
    /// Primitive actions (moves, cycles) the domain counted.
    pub actions: u32,
    /// Executor steps.
    pub steps: u32,
    /// Whether the learner treated it as exploratory.
    pub exploratory: bool,
}

/// The root plan's marking with one token in the first place carrying each
/// label, as a key of a value table (the values a domain traces); `None` if
/// `plan` lacks one of the labels.
pub(crate) fn root_key(plan: &Plan, labels: &[&str]) -> Option<StateKey> {
    marking_with(plan, labels).ok().map(|marking| StateKey {
        plan: crate::executor::PlanKey::ROOT,
        marking,
    })
}

/// The marking of `plan` with one token in the first place carrying each label.
pub(crate) fn marking_with(plan: &Plan, labels: &[&str]) -> Result<Marking, TaskError> {
    let mut m = Marking::empty(plan.net().places().len());
    for label in labels {
        let place = plan
            .net()
            .places_labelled(label)
            .next()
            .ok_or_else(|| TaskError::MissingPlace {
                plan: plan.name().to_string(),
                label: label.to_string(),
            })?;
        m.set(place, 1);
    }
    Ok(m)
}

/// Values of named root-plan markings in a learner's table.
pub(crate) fn traced(learner: &dyn Learner, keys: &[(String, StateKey)]) -> Vec<(String, f64)> {
    keys.iter()
        .map(|(name, k)| (name.clone(), learner.values().value_of(k.plan, &k.marking)))
        .collect()
}
