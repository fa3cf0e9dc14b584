//! First-visit Monte Carlo on every marking (the reference library's Monte Carlo learner).

use serde::{Deserialize, Serialize};

use super::selection::{self, Exploration};
use super::{EpisodeStart, Learner, Trajectory, ValueTable, blend, level};
use crate::executor::{Chooser, PendingReward, PlanKey};
use crate::net::Marking;
use crate::rng::SimRng;

/// The parameters of Monte Carlo on markings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MonteCarloConfig {
    /// Discount per executor step.
    pub gamma: f64,
    /// Step size toward each return.
    pub alpha: f64,
    /// How options are drawn; schedules count learning decisions.
    pub exploration: Exploration,
    /// Value of unseen markings.
    #[serde(with = "crate::json_float")]
    pub initial_value: f64,
}

/// Moves the value of every marking visited toward the return from its first visit.
pub struct MonteCarlo {
    config: MonteCarloConfig,
    rng: SimRng,
    values: ValueTable,
    levels: Vec<Trajectory>,
    decisions: u64,
    learning: bool,
    greedy: bool,
    left_greedy: bool,
    option_values: Vec<f64>,
    scratch: Vec<usize>,
    returns: Vec<(u32, f64)>,
}

impl MonteCarlo {
    /// A learner drawing from `rng`.
    pub fn new(config: MonteCarloConfig, rng: SimRng) -> Self {
        MonteCarlo {
            values: ValueTable::new(config.initial_value),
            config,
            rng,
            levels: Vec::new(),
            decisions: 0,
            learning: true,
            greedy: false,
            left_greedy: false,
            option_values: Vec::new(),
            scratch: Vec::new(),
            returns: Vec::new(),
        }
    }
}

impl Chooser for MonteCarlo {
    fn choose(&mut self, plan: PlanKey, _state: &Marking, options: &[Marking]) -> usize {
        self.option_values.clear();
        self.option_values
            .extend(options.iter().map(|m| self.values.value_of(plan, m)));
        let strategy = self.config.exploration.unless_greedy(self.greedy, self.decisions);
        let i = selection::select(strategy, &self.option_values, &mut self.rng, &mut self.scratch);
        self.left_greedy |= !selection::is_greedy(&self.option_values, i);
        if self.learning {
            self.decisions += 1;
        }
        i
    }

    fn transition(&mut self, plan: PlanKey, marking: &Marking, reward: f64, elapsed: u32) {
        let id = self.values.intern(plan, marking);
        let t = level(&mut self.levels, plan);
        t.advance(reward, elapsed);
        t.visit(id);
    }

    fn plan_started(&mut self, plan: PlanKey, marking: &Marking) {
        let id = self.values.intern(plan, marking);
        level(&mut self.levels, plan).visit(id);
    }
}

impl Learner for MonteCarlo {
    fn begin_episode(&mut self, start: EpisodeStart) {
        self.levels.iter_mut().for_each(Trajectory::clear);
        self.learning = start.learning();
        self.greedy = start.greedy();
        self.left_greedy = false;
    }

    fn end_episode(&mut self, tail: PendingReward) {
        level(&mut self.levels, PlanKey::ROOT).advance(tail.reward, tail.elapsed);
        if !self.learning {
            return;
        }
        for t in &mut self.levels {
            t.first_visit_returns(self.config.gamma, &mut self.returns);
            for &(id, sample) in &self.returns {
                self.values
                    .set(id, blend(self.values.value(id), sample, self.config.alpha));
                self.values.visit(id);
            }
        }
    }

    table_accessors!(left_greedy);
}
