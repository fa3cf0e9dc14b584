//! Running one episode of a plan with a learner.

use std::sync::Arc;

use crate::executor::{ExecError, Executor, Registry, Status, World};
use crate::learning::{EpisodeStart, Learner, StateKey};
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
    /// Keepers in other processes cannot be reached.
    #[error("keeper processes: {0}")]
    Remote(String),
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

/// An executor with the learner choosing at its choice points.
pub struct PlanAgent<W> {
    executor: Executor<W>,
    learner: Box<dyn Learner>,
}

impl<W: World> PlanAgent<W> {
    /// Instantiates `plan` from `registry` with `learner` choosing.
    pub fn new(plan: Arc<Plan>, registry: &Registry<W>, learner: Box<dyn Learner>) -> Result<Self, TaskError> {
        Ok(PlanAgent {
            executor: Executor::new(plan, registry)?,
            learner,
        })
    }

    /// Runs an episode until the plan ends, `over` says the world has ended it,
    /// or `step_limit` steps pass; returns the steps taken.
    pub fn run(
        &mut self,
        world: &mut W,
        start: EpisodeStart,
        step_limit: u32,
        mut over: impl FnMut(&W) -> bool,
    ) -> Result<u32, TaskError> {
        let learner = self.learner.as_mut();
        learner.begin_episode(start);
        self.executor.reset(world, learner);
        let mut steps = 0;
        while steps < step_limit {
            let status = self.executor.step(world, learner)?;
            steps += 1;
            if status != Status::Running || over(world) {
                break;
            }
        }
        learner.end_episode(self.executor.take_pending());
        Ok(steps)
    }

    /// The learner.
    pub fn learner(&self) -> &dyn Learner {
        self.learner.as_ref()
    }

    /// The plan.
    pub fn plan(&self) -> &Plan {
        self.executor.plan()
    }
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
pub fn traced(learner: &dyn Learner, keys: &[(String, StateKey)]) -> Vec<(String, f64)> {
    keys.iter()
        .map(|(name, k)| (name.clone(), learner.values().value_of(k.plan, &k.marking)))
        .collect()
}
