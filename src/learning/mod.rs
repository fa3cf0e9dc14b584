//! Learners: they choose at the executor's choice points and learn from rewards.
//!
//! Values are kept per marking of the plan (afterstates, as the reference
//! library does): the marking after a choice already encodes the option taken
//! (its output places) and the observation (the environment-tracking part), so
//! it identifies the thesis's observation-action pair, while plans that lead to
//! the same marking deliberately share one value (see docs/ARCHITECTURE.md).

/// Implements a learner's `exploratory`, `values` and `values_mut` for a learner
/// that keeps its table in a field `values` and its exploration flag in the
/// named field (the three accessors every table learner writes alike).
macro_rules! table_accessors {
    ($explored:ident) => {
        fn exploratory(&self) -> bool {
            self.$explored
        }

        fn values(&self) -> &ValueTable {
            &self.values
        }

        fn values_mut(&mut self) -> &mut ValueTable {
            &mut self.values
        }
    };
}

/// A saved value table read against its plan, by choice point.
pub mod by_choice;
mod mcesp;
/// Values carried into a revised plan.
pub mod migrate;
mod monte_carlo;
/// Saving and loading learned value tables, safely.
pub mod persist;
mod random;
pub(crate) mod selection;
mod sosmc;
mod td;
mod trajectory;
mod values;
mod watched;

pub use mcesp::{Mcesp, McespConfig};
pub use monte_carlo::{MonteCarlo, MonteCarloConfig};
pub use random::RandomLearner;
pub use selection::{Exploration, Schedule, Strategy};
pub use sosmc::{Assessment, ExploitPolicy, Sigma, SoSmc, SoSmcConfig, StepSize, ThresholdRule, Unestimated};
pub use td::{Scope, Target, TdConfig, TdLearner};
pub use trajectory::{Trajectory, discount};
pub use values::{KeyId, StateKey, ValueTable, blend};
pub use watched::{WatchedLearner, plan_shape};

use crate::executor::{Chooser, PendingReward};

/// What an episode is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum EpisodeMode {
    /// Values learn from it.
    Learn,
    /// Values are frozen; the learner behaves exactly as it would while learning
    /// (the thesis's evaluation protocol).
    Evaluate,
    /// Values are frozen and every choice is greedy (the learned policy itself).
    Greedy,
}

/// How an episode is to be run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EpisodeStart {
    /// Learning, evaluation or greedy.
    pub mode: EpisodeMode,
    /// Forces the episode to be exploratory or not (a schedule shared by several
    /// agents); `None` lets the learner decide by its own rule. SoSMC's initial
    /// phase and its threshold rule take precedence: a suspended learner does not
    /// explore even when forced to.
    pub exploratory: Option<bool>,
}

impl EpisodeStart {
    /// A learning episode decided by the learner's own rule.
    pub const LEARN: EpisodeStart = EpisodeStart {
        mode: EpisodeMode::Learn,
        exploratory: None,
    };
    /// An evaluation episode decided by the learner's own rule.
    pub const EVALUATE: EpisodeStart = EpisodeStart {
        mode: EpisodeMode::Evaluate,
        exploratory: None,
    };
    /// A greedy episode without learning.
    pub const GREEDY: EpisodeStart = EpisodeStart {
        mode: EpisodeMode::Greedy,
        exploratory: Some(false),
    };

    /// An episode of `mode` decided by the learner's own rule.
    pub const fn of(mode: EpisodeMode) -> Self {
        EpisodeStart {
            mode,
            exploratory: None,
        }
    }

    /// Whether values learn.
    pub fn learning(&self) -> bool {
        self.mode == EpisodeMode::Learn
    }

    /// Whether every choice must be greedy.
    pub fn greedy(&self) -> bool {
        self.mode == EpisodeMode::Greedy
    }
}

/// A learner serving an executor: a [`Chooser`] that is told where episodes start and end.
pub trait Learner: Chooser + Send {
    /// A new episode begins.
    fn begin_episode(&mut self, start: EpisodeStart);
    /// The episode ends; `tail` is the reward and steps after the last marking change.
    fn end_episode(&mut self, tail: PendingReward);
    /// Whether the current (or just ended) episode explores.
    fn exploratory(&self) -> bool;
    /// What has been learned.
    fn values(&self) -> &ValueTable;
    /// What has been learned, for loading a saved table.
    fn values_mut(&mut self) -> &mut ValueTable;
}

/// Per-plan-level state, indexed by [`crate::executor::PlanKey`].
pub(crate) fn level<T: Default>(levels: &mut Vec<T>, plan: crate::executor::PlanKey) -> &mut T {
    let i = usize::from(plan.0);
    if levels.len() <= i {
        levels.resize_with(i + 1, T::default);
    }
    &mut levels[i]
}
