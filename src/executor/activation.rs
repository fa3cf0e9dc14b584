//! What every node of the activation tree does, whichever semantics runs it,
//! and what it reports: its [`Status`] and the [`PendingReward`] of its steps.

use super::{Chooser, ExecError, World};
use crate::net::Marking;

/// Where a plan's execution stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    /// Neither in a goal nor in a fail marking.
    Running,
    /// In a goal marking: the plan has finished.
    Goal,
    /// In a fail marking: the plan has failed.
    Failed,
}

/// Reward and steps since the last marking change that no transition has reported yet.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PendingReward {
    /// Reward collected.
    pub reward: f64,
    /// Steps elapsed.
    pub elapsed: u32,
}

impl PendingReward {
    /// Adds one step that collected `reward`.
    #[inline]
    pub(crate) fn add(&mut self, reward: f64) {
        self.reward += reward;
        self.elapsed += 1;
    }

    /// Takes the reward and steps, leaving none.
    #[inline]
    pub(crate) fn take(&mut self) -> Self {
        std::mem::take(self)
    }
}

/// A running plan, a node of the activation tree: a Petri Net Plan instance
/// (thesis 5.3, `instance`) or a schema machine's run (thesis 3.1.1,
/// `machine`). The [`super::Executor`] drives its root through this trait;
/// a node drives its own sub-plans or sub-machines.
pub(crate) trait Activation<W: World> {
    /// Resets every primitive action of the sub-tree for a new episode.
    fn reset_actions(&mut self);

    /// Starts from the initial marking, starting the initial actions, and
    /// tells `chooser` the plan started.
    fn start<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C);

    /// Steps every active action; running sub-plans step theirs.
    fn act(&mut self, world: &mut W);

    /// Adds one step and its reward to this plan and its running sub-plans.
    fn accrue(&mut self, reward: f64);

    /// Changes the marking if this step's events or executable transitions say
    /// so (asking `chooser` at choice points and telling it every change), then
    /// lets the running sub-plans do the same unless preempted.
    fn fire<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<(), ExecError>;

    /// Where the plan stands.
    fn status(&self) -> Status;

    /// The current marking.
    fn marking(&self) -> &Marking;

    /// Started (or resumed) during the current step: it fires from the next.
    fn fresh(&self) -> bool;

    /// Takes the reward and steps since the last marking change.
    fn take_pending(&mut self) -> PendingReward;

    /// One executor step of a root plan: unless it has ended, act, credit the
    /// world's reward for the step, fire; returns the status after the step.
    fn step<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<Status, ExecError> {
        if self.status() != Status::Running {
            return Ok(self.status());
        }
        self.act(world);
        let reward = world.take_reward();
        self.accrue(reward);
        self.fire(world, chooser)?;
        Ok(self.status())
    }
}
