//! What a domain's task reports: why it cannot run ([`TaskError`]), what an
//! episode earned ([`EpisodeOutcome`]), and the values of named markings it traces.

use std::sync::Arc;

use super::Task;
use crate::agent::PlanAgent;
use crate::executor::{ExecError, Registry, World};
use crate::learning::{EpisodeMode, EpisodeStart, Learner, StateKey};
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

/// A world a [`PlanTask`] runs episodes in: how an episode begins, how long
/// it may last, and what it earned.
pub trait EpisodeWorld: World + Sized {
    /// Readies the world for a new episode.
    fn begin(&mut self);
    /// The most executor steps an episode may take.
    fn step_limit(&self) -> u32;
    /// Whether the world has ended the episode (asked after every step).
    fn over(&self) -> bool {
        false
    }
    /// The undiscounted sum of the episode's rewards so far.
    fn ret(&self) -> f64;
    /// The primitive actions of the episode so far.
    fn actions(&self) -> u32;
}

/// Learning runs of one plan agent in its world, tracing the values of named
/// root-plan markings: the small domains' task.
pub struct PlanTask<W> {
    agent: PlanAgent<W>,
    world: W,
    traced: Vec<(String, StateKey)>,
    /// Primitive actions of every episode run so far.
    actions_played: u64,
}

impl<W: EpisodeWorld> PlanTask<W> {
    /// A run of `plan` with the actions of `registry` in `world`, `learner`
    /// choosing; `traced` names the root-plan markings whose values it reports.
    pub(crate) fn with(
        plan: Arc<Plan>,
        registry: &Registry<W>,
        learner: Box<dyn Learner>,
        world: W,
        traced: Vec<(String, StateKey)>,
    ) -> Result<Self, TaskError> {
        let agent = PlanAgent::new(plan, registry, learner)?;
        Ok(PlanTask {
            agent,
            world,
            traced,
            actions_played: 0,
        })
    }

    /// The world.
    pub(crate) fn world_mut(&mut self) -> &mut W {
        &mut self.world
    }

    /// Runs one episode in `mode` from the world as it stands (without [`EpisodeWorld::begin`]).
    pub(crate) fn run(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        let limit = self.world.step_limit();
        let steps = self
            .agent
            .run(&mut self.world, EpisodeStart::of(mode), limit, W::over)?;
        self.actions_played += u64::from(self.world.actions());
        Ok(EpisodeOutcome {
            ret: self.world.ret(),
            actions: self.world.actions(),
            steps,
            exploratory: self.agent.learner().exploratory(),
        })
    }
}

impl<W: EpisodeWorld> Task for PlanTask<W> {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        self.world.begin();
        self.run(mode)
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        traced(self.agent.learner(), &self.traced)
    }

    fn actions_played(&self) -> Option<u64> {
        Some(self.actions_played)
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        vec![self.agent.learner()]
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
pub(crate) fn traced(learner: &dyn Learner, keys: &[(String, StateKey)]) -> Vec<(String, f64)> {
    keys.iter()
        .map(|(name, k)| (name.clone(), learner.values().value_of(k.plan, &k.marking)))
        .collect()
}
