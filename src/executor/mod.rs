//! The plan executor: the operational semantics of thesis section 5.3.
//!
//! Each [`Executor::step`]:
//! 1. returns at once if the root plan is in a goal or fail marking;
//! 2. steps every active action, descending into running sub-plans (an
//!    activation tree, not a stack);
//! 3. asks the world for the reward of the step, credited to every running plan;
//! 4. fires the executable transitions of the root plan, then of each running
//!    sub-plan below it, so a higher plan's interrupt preempts the plans it ends.
//!    Conflicting executable transitions are resolved by a [`Chooser`] picking
//!    among the next markings of the maximal non-conflicting sets. Transitions
//!    enabled by this step's firings (and sub-plans started in it) wait for the
//!    next step. Every marking change is reported to the chooser with the reward
//!    and steps elapsed since the previous one.

mod action;
mod bits;
mod chooser;
mod conflict;
mod error;
mod instance;
mod registry;

use std::sync::Arc;

pub use action::{Action, World};
pub use chooser::{Chooser, PlanKey, RandomChooser};
pub use error::ExecError;
pub use instance::Status;
pub use registry::{Registered, RegisteredKind, Registry};

use instance::PlanInstance;

use crate::net::Marking;
use crate::plan::Plan;

/// Reward and steps since the last marking change that no transition has reported yet.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PendingReward {
    /// Reward collected.
    pub reward: f64,
    /// Steps elapsed.
    pub elapsed: u32,
}

/// Executes a plan and its sub-plans in a world `W`.
pub struct Executor<W> {
    root: PlanInstance<W>,
}

impl<W: World> Executor<W> {
    /// Instantiates `plan`'s actions and sub-plans from `registry`, binding every
    /// internal condition its guards use.
    pub fn new(plan: Arc<Plan>, registry: &Registry<W>) -> Result<Self, ExecError> {
        Ok(Executor {
            root: PlanInstance::new(plan, PlanKey::ROOT, registry, &mut Vec::new())?,
        })
    }

    /// Starts a new episode: resets every action, restores the initial marking
    /// and tells `chooser` the plan started.
    pub fn reset<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) {
        self.root.reset_actions();
        self.root.start(world, chooser);
    }

    /// One execution step (see the module documentation).
    pub fn step<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<Status, ExecError> {
        if self.root.status != Status::Running {
            return Ok(self.root.status);
        }
        self.root.act(world);
        let reward = world.take_reward();
        self.root.accrue(reward);
        self.root.fire(world, chooser)?;
        Ok(self.root.status)
    }

    /// The root plan's status.
    pub fn status(&self) -> Status {
        self.root.status
    }

    /// The root plan's marking.
    pub fn marking(&self) -> &Marking {
        &self.root.marking
    }

    /// The root plan.
    pub fn plan(&self) -> &Plan {
        &self.root.plan
    }

    /// Takes the root plan's reward and steps since its last marking change
    /// (at the end of an episode cut short, before the learner closes it).
    pub fn take_pending(&mut self) -> PendingReward {
        let pending = PendingReward {
            reward: self.root.pending_reward,
            elapsed: self.root.elapsed,
        };
        self.root.pending_reward = 0.0;
        self.root.elapsed = 0;
        pending
    }
}
