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
//!
//! A plan constructed from a plan schema ([`Plan::schema_process`]) is run by
//! the schema's own semantics instead (thesis 3.1.1, `crate::schema`), with the
//! same world, actions, registry and chooser.

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
pub(crate) use registry::Entry;
pub use registry::{Registered, RegisteredKind, Registry};

use instance::PlanInstance;

use crate::net::Marking;
use crate::plan::Plan;
use crate::schema::MachineRun;

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
    root: Root<W>,
}

/// The root of the activation tree: a Petri Net Plan, or a schema's root machine.
/// One per executor; the net variant stays inline, off the heap, on the hot path.
#[allow(clippy::large_enum_variant)]
enum Root<W> {
    Net(PlanInstance<W>),
    Schema(MachineRun<W>, Arc<Plan>),
}

impl<W: World> Executor<W> {
    /// Instantiates `plan`'s actions and sub-plans from `registry`, binding every
    /// internal condition its guards use.
    pub fn new(plan: Arc<Plan>, registry: &Registry<W>) -> Result<Self, ExecError> {
        let root = match plan.schema_process() {
            Some(process) => Root::Schema(MachineRun::new(Arc::clone(process), 0, registry)?, plan),
            None => Root::Net(PlanInstance::new(plan, PlanKey::ROOT, registry, &mut Vec::new())?),
        };
        Ok(Executor { root })
    }

    /// Starts a new episode: resets every action, restores the initial marking
    /// and tells `chooser` the plan started.
    pub fn reset<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) {
        match &mut self.root {
            Root::Net(root) => {
                root.reset_actions();
                root.start(world, chooser);
            }
            Root::Schema(root, _) => {
                root.reset_actions();
                root.start(world, chooser);
            }
        }
    }

    /// One execution step (see the module documentation).
    pub fn step<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<Status, ExecError> {
        match &mut self.root {
            Root::Net(root) => {
                if root.status != Status::Running {
                    return Ok(root.status);
                }
                root.act(world);
                let reward = world.take_reward();
                root.accrue(reward);
                root.fire(world, chooser)?;
                Ok(root.status)
            }
            Root::Schema(root, _) => {
                if root.status != Status::Running {
                    return Ok(root.status);
                }
                root.act(world);
                let reward = world.take_reward();
                root.accrue(reward);
                root.fire(world, chooser)?;
                Ok(root.status)
            }
        }
    }

    /// The root plan's status.
    pub fn status(&self) -> Status {
        match &self.root {
            Root::Net(root) => root.status,
            Root::Schema(root, _) => root.status,
        }
    }

    /// The root plan's marking.
    pub fn marking(&self) -> &Marking {
        match &self.root {
            Root::Net(root) => &root.marking,
            Root::Schema(root, _) => &root.marking,
        }
    }

    /// The root plan.
    pub fn plan(&self) -> &Plan {
        match &self.root {
            Root::Net(root) => &root.plan,
            Root::Schema(_, plan) => plan,
        }
    }

    /// Takes the root plan's reward and steps since its last marking change
    /// (at the end of an episode cut short, before the learner closes it).
    pub fn take_pending(&mut self) -> PendingReward {
        let (reward, elapsed) = match &mut self.root {
            Root::Net(root) => (&mut root.pending_reward, &mut root.elapsed),
            Root::Schema(root, _) => (&mut root.pending_reward, &mut root.elapsed),
        };
        let pending = PendingReward {
            reward: *reward,
            elapsed: *elapsed,
        };
        *reward = 0.0;
        *elapsed = 0;
        pending
    }
}
