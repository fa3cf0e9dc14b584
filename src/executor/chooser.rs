//! Who decides at a choice point, and what they are told between choices.

use rand::RngExt;

use crate::net::Marking;
use crate::rng::SimRng;

/// Identifies the plan a marking belongs to: 0 is the root plan, sub-plans
/// follow in the order they were registered. Value tables key on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub struct PlanKey(pub u16);

impl PlanKey {
    /// The root plan.
    pub const ROOT: PlanKey = PlanKey(0);
}

/// Resolves conflicts between executable transitions.
///
/// The executor enumerates the maximal non-conflicting sets of executable
/// transitions, computes the marking each would lead to, and asks the chooser to
/// pick one of those next markings (a choice over afterstates). Between choices
/// it reports every marking change with the reward collected and the steps
/// elapsed since the previous change (semi-Markov time; discounting is the
/// learner's business).
pub trait Chooser {
    /// Picks the index of one of `options`, the next markings reachable from `state`.
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize;

    /// `plan` moved to `marking` after `elapsed` steps that collected `reward`.
    fn transition(&mut self, _plan: PlanKey, _marking: &Marking, _reward: f64, _elapsed: u32) {}

    /// `plan` (re)started in its initial `marking`.
    fn plan_started(&mut self, _plan: PlanKey, _marking: &Marking) {}
}

/// The default chooser: a seeded uniform random choice.
#[derive(Debug, Clone)]
pub struct RandomChooser {
    rng: SimRng,
}

impl RandomChooser {
    /// A chooser drawing from `rng`.
    pub fn new(rng: SimRng) -> Self {
        RandomChooser { rng }
    }
}

impl Chooser for RandomChooser {
    fn choose(&mut self, _plan: PlanKey, _state: &Marking, options: &[Marking]) -> usize {
        self.rng.random_range(0..options.len())
    }
}
