//! An agent that drives its world: it runs episodes of a plan whose actions
//! act on the world ([`crate::executor::Action`]s registered by name), with a
//! learner choosing at the plan's choice points.

use std::sync::Arc;

use crate::executor::{ExecError, Executor, Registry, Status, World};
use crate::learning::{EpisodeStart, Learner};
use crate::plan::Plan;

/// An executor with the learner choosing at its choice points.
pub struct PlanAgent<W> {
    executor: Executor<W>,
    learner: Box<dyn Learner>,
}

impl<W: World> PlanAgent<W> {
    /// Instantiates `plan` from `registry` with `learner` choosing.
    pub fn new(plan: Arc<Plan>, registry: &Registry<W>, learner: Box<dyn Learner>) -> Result<Self, ExecError> {
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
    ) -> Result<u32, ExecError> {
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
