//! A keeper driven by a plan, with a learner at its choice points.

use std::sync::Arc;

use crate::executor::{ExecError, Executor, Registry};
use crate::keepaway::command::Command;
use crate::keepaway::features::FeatureThresholds;
use crate::keepaway::params::KeepawayConfig;
use crate::keepaway::perception::PlayerView;
use crate::learning::{EpisodeStart, Learner};
use crate::plan::Plan;

use super::world::KeeperWorld;

/// Most executor steps a keeper takes in one cycle before it must have acted.
/// A decision needs about four (end the last action, read the situation, choose,
/// act); a plan that thinks longer without acting sends no command that cycle.
pub const MAX_STEPS_PER_CYCLE: u32 = 16;

/// A keeper executing a plan: each cycle it perceives, then steps its plan
/// until an action has issued the cycle's command.
pub struct PlanKeeper {
    executor: Executor<KeeperWorld>,
    learner: Box<dyn Learner>,
    world: KeeperWorld,
    idle_cycles: u64,
}

impl PlanKeeper {
    /// A keeper running `plan` with actions from `registry` and `learner` at its choices.
    pub fn new(
        plan: Arc<Plan>,
        registry: &Registry<KeeperWorld>,
        learner: Box<dyn Learner>,
        config: KeepawayConfig,
        thresholds: FeatureThresholds,
    ) -> Result<Self, ExecError> {
        Ok(PlanKeeper {
            executor: Executor::new(plan, registry)?,
            learner,
            world: KeeperWorld::new(config, thresholds),
            idle_cycles: 0,
        })
    }

    /// A new episode: the learner is told, the plan restarts.
    pub fn begin_episode(&mut self, start: EpisodeStart) {
        self.learner.begin_episode(start);
        self.world.reset();
        self.executor.reset(&mut self.world, self.learner.as_mut());
    }

    /// One cycle: perceive `view` (crediting `elapsed_seconds` of reward), think
    /// until an action issues a command, and return it.
    pub fn act(&mut self, view: PlayerView, elapsed_seconds: f64) -> Result<Command, ExecError> {
        self.world.perceive(view, elapsed_seconds);
        for _ in 0..MAX_STEPS_PER_CYCLE {
            self.executor.step(&mut self.world, self.learner.as_mut())?;
            if self.world.command().is_some() {
                break;
            }
        }
        Ok(self.world.command().unwrap_or_else(|| {
            self.idle_cycles += 1;
            Command::None
        }))
    }

    /// The episode is over: the learner gets the reward after the last marking change.
    pub fn end_episode(&mut self) {
        self.learner.end_episode(self.executor.take_pending());
    }

    /// The learner.
    pub fn learner(&self) -> &dyn Learner {
        self.learner.as_ref()
    }

    /// Cycles in which the plan issued no command (a sign of a plan that never acts).
    pub fn idle_cycles(&self) -> u64 {
        self.idle_cycles
    }
}
