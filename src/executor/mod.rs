//! The plan executor: the operational semantics of thesis section 5.3.
//!
//! Each [`Executor::step`](crate::executor::Executor::step):
//! 1. returns at once if the root plan is in a goal or fail marking;
//! 2. steps every active action, descending into running sub-plans (an
//!    activation tree, not a stack);
//! 3. asks the world for the reward of the step, credited to every running plan;
//! 4. fires the executable transitions of the root plan, then of each running
//!    sub-plan below it, so a higher plan's interrupt preempts the plans it ends.
//!    Conflicting executable transitions are resolved by a [`Chooser`](crate::executor::Chooser) picking
//!    among the next markings of the maximal non-conflicting sets. Transitions
//!    enabled by this step's firings (and sub-plans started in it) wait for the
//!    next step. Every marking change is reported to the chooser with the reward
//!    and steps elapsed since the previous one.
//!
//! A plan constructed from a plan schema ([`Plan::schema_process`](crate::plan::Plan::schema_process)) is run by
//! the schema's own semantics instead (thesis 3.1.1, `machine`), with the
//! same world, actions, registry and chooser. Both kinds of running plan are
//! nodes of the activation tree behind one trait (`activation`), and share
//! the code binding their actions and internal conditions (`bound`).

/// Implements an activation's `status`, `marking`, `fresh` and `take_pending`
/// from the fields of the same names, which both kinds of running plan hold.
macro_rules! activation_accessors {
    () => {
        fn status(&self) -> Status {
            self.status
        }

        fn marking(&self) -> &Marking {
            &self.marking
        }

        fn fresh(&self) -> bool {
            self.fresh
        }

        fn take_pending(&mut self) -> PendingReward {
            self.pending.take()
        }
    };
}

mod action;
mod activation;
mod bits;
mod bound;
mod chooser;
mod conflict;
mod error;
mod instance;
mod machine;
mod registry;

use std::sync::Arc;

pub use action::{Action, OneStep, World};
pub use activation::{PendingReward, Status};
pub use chooser::{Chooser, PlanKey, RandomChooser};
pub use error::ExecError;
pub use registry::{Registered, RegisteredKind, Registry};

use activation::Activation;
use instance::PlanInstance;
use machine::MachineRun;

use crate::net::Marking;
use crate::plan::Plan;

/// Executes a plan and its sub-plans in a world `W`.
pub struct Executor<W> {
    root: Root<W>,
    plan: Arc<Plan>,
}

/// The root of the activation tree: a Petri Net Plan, or a schema's root machine.
/// One per executor, inline (off the heap); used through [`Activation`].
#[allow(clippy::large_enum_variant)]
enum Root<W> {
    Net(PlanInstance<W>),
    Schema(MachineRun<W>),
}

/// Evaluates `$body` with `$node` bound to the root node of `$root` (a
/// `Root`), whichever its kind: the one dispatch on the kind, static, so the
/// hot path calls the [`Activation`] methods directly.
macro_rules! on_root {
    ($root:expr, |$node:ident| $body:expr) => {
        match $root {
            Root::Net($node) => $body,
            Root::Schema($node) => $body,
        }
    };
}

impl<W: World> Executor<W> {
    /// Instantiates `plan`'s actions and sub-plans from `registry`, binding every
    /// internal condition its guards use.
    pub fn new(plan: Arc<Plan>, registry: &Registry<W>) -> Result<Self, ExecError> {
        let root = match plan.schema_process() {
            Some(process) => Root::Schema(MachineRun::new(process, 0, registry)?),
            None => Root::Net(PlanInstance::new(
                Arc::clone(&plan),
                PlanKey::ROOT,
                registry,
                &mut Vec::new(),
            )?),
        };
        Ok(Executor { root, plan })
    }

    /// Starts a new episode: resets every action, restores the initial marking
    /// and tells `chooser` the plan started.
    pub fn reset<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) {
        on_root!(&mut self.root, |root| {
            root.reset_actions();
            root.start(world, chooser);
        })
    }

    /// One execution step (see the module documentation).
    pub fn step<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<Status, ExecError> {
        on_root!(&mut self.root, |root| root.step(world, chooser))
    }

    /// The root plan's status.
    pub fn status(&self) -> Status {
        on_root!(&self.root, |root| root.status())
    }

    /// The root plan's marking.
    pub fn marking(&self) -> &Marking {
        on_root!(&self.root, |root| root.marking())
    }

    /// The root plan.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Takes the root plan's reward and steps since its last marking change
    /// (at the end of an episode cut short, before the learner closes it).
    pub fn take_pending(&mut self) -> PendingReward {
        on_root!(&mut self.root, |root| root.take_pending())
    }
}
