//! A baseline that chooses uniformly at random and learns nothing.

use rand::RngExt;

use super::{EpisodeStart, Learner, ValueTable};
use crate::executor::{Chooser, PendingReward, PlanKey};
use crate::net::Marking;
use crate::rng::SimRng;

/// Uniform random choices; its value table stays empty.
pub struct RandomLearner {
    rng: SimRng,
    values: ValueTable,
}

impl RandomLearner {
    /// A learner drawing from `rng`.
    pub fn new(rng: SimRng) -> Self {
        RandomLearner {
            rng,
            values: ValueTable::new(0.0),
        }
    }
}

impl Chooser for RandomLearner {
    fn choose(&mut self, _plan: PlanKey, _state: &Marking, options: &[Marking]) -> usize {
        self.rng.random_range(0..options.len())
    }
}

impl Learner for RandomLearner {
    fn begin_episode(&mut self, _start: EpisodeStart) {}
    fn end_episode(&mut self, _tail: PendingReward) {}
    fn exploratory(&self) -> bool {
        false
    }
    fn values(&self) -> &ValueTable {
        &self.values
    }
    fn values_mut(&mut self) -> &mut ValueTable {
        &mut self.values
    }
}
