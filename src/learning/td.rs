//! Temporal-difference learners: Sarsa(lambda), Sarsa(0) and Q-learning on the
//! afterstates of choices (the thesis's baselines), and TD(lambda) / Q-learning
//! on every marking (the reference library's learners).
//!
//! Time is semi-Markov: the reward of an interval is summed, and the value that
//! follows it is discounted by gamma^(steps elapsed). Eligibility traces are
//! replacing and decay by lambda * gamma^elapsed per update.

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use super::selection::{self, Exploration};
use super::{EpisodeStart, KeyId, Learner, ValueTable, discount, level};
use crate::executor::{Chooser, PendingReward, PlanKey};
use crate::net::Marking;
use crate::rng::SimRng;

/// Which markings carry values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Scope {
    /// Only the afterstates of choices (Sarsa / Q-learning over the choice process).
    Choices,
    /// Every marking the plan passes through (TD / Q-learning on markings).
    Markings,
}

/// What a value is moved toward.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Target {
    /// The value of what was actually chosen next (Sarsa, TD).
    OnPolicy,
    /// The best option's value at the next choice (Q-learning).
    Max,
}

/// The parameters of a TD learner.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TdConfig {
    /// Discount per executor step.
    pub gamma: f64,
    /// Step size.
    pub alpha: f64,
    /// Trace decay (0: one-step).
    pub lambda: f64,
    /// On-policy or max target.
    pub target: Target,
    /// Choice afterstates or every marking.
    pub scope: Scope,
    /// How options are drawn; schedules count learning decisions.
    pub exploration: Exploration,
    /// Value of unseen keys.
    #[serde(with = "crate::json_float")]
    pub initial_value: f64,
    /// Repeat the first decision at an observation within an episode.
    pub consistent: bool,
}

#[derive(Debug, Default)]
struct Level {
    prev: Option<KeyId>,
    reward: f64,
    time: u32,
    pending: Option<(KeyId, f64)>,
    traces: Vec<(KeyId, f64)>,
}

/// A TD learner (see the module documentation).
pub struct TdLearner {
    config: TdConfig,
    rng: SimRng,
    values: ValueTable,
    observations: ValueTable,
    levels: Vec<Level>,
    memory: FxHashMap<KeyId, KeyId>,
    decisions: u64,
    learning: bool,
    greedy: bool,
    left_greedy: bool,
    ids: Vec<KeyId>,
    option_values: Vec<f64>,
    scratch: Vec<usize>,
}

impl TdLearner {
    /// A learner drawing from `rng`.
    pub fn new(config: TdConfig, rng: SimRng) -> Self {
        TdLearner {
            values: ValueTable::new(config.initial_value),
            observations: ValueTable::new(0.0),
            config,
            rng,
            levels: Vec::new(),
            memory: FxHashMap::default(),
            decisions: 0,
            learning: true,
            greedy: false,
            left_greedy: false,
            ids: Vec::new(),
            option_values: Vec::new(),
            scratch: Vec::new(),
        }
    }

    /// Learning decisions taken so far (the clock of the exploration schedule).
    pub fn decisions(&self) -> u64 {
        self.decisions
    }

    /// Moves `prev` toward `target`, spreading the error along the traces,
    /// which then decay by `decay`.
    fn update(values: &mut ValueTable, alpha: f64, level: &mut Level, prev: KeyId, target: f64, decay: f64) {
        let old = values.value(prev);
        if !old.is_finite() {
            values.set(prev, target);
        } else {
            let delta = target - old;
            for &(id, e) in &level.traces {
                values.set(id, values.value(id) + alpha * delta * e);
            }
        }
        values.visit(prev);
        for t in &mut level.traces {
            t.1 *= decay;
        }
        level.traces.retain(|t| t.1 > 1e-4);
    }

    fn trace(level: &mut Level, id: KeyId) {
        match level.traces.iter_mut().find(|t| t.0 == id) {
            Some(t) => t.1 = 1.0,
            None => level.traces.push((id, 1.0)),
        }
    }
}

impl Chooser for TdLearner {
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize {
        self.values
            .intern_options(plan, options, &mut self.ids, &mut self.option_values);
        let obs = if self.config.consistent {
            Some(self.observations.intern(plan, state))
        } else {
            None
        };
        let remembered = obs
            .and_then(|o| self.memory.get(&o))
            .and_then(|after| self.ids.iter().position(|id| id == after));
        let index = remembered.unwrap_or_else(|| {
            let strategy = self.config.exploration.unless_greedy(self.greedy, self.decisions);
            let i = selection::select(strategy, &self.option_values, &mut self.rng, &mut self.scratch);
            self.left_greedy |= !selection::is_greedy(&self.option_values, i);
            if let Some(o) = obs {
                self.memory.insert(o, self.ids[i]);
            }
            i
        });
        if self.learning {
            self.decisions += 1;
        }
        let best = self.option_values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let lvl = level(&mut self.levels, plan);
        if self.config.scope == Scope::Markings && lvl.prev.is_none() {
            lvl.prev = Some(self.values.intern(plan, state));
        }
        lvl.pending = Some((self.ids[index], best));
        index
    }

    fn transition(&mut self, plan: PlanKey, marking: &Marking, reward: f64, elapsed: u32) {
        let c = self.config;
        let learning = self.learning;
        match c.scope {
            Scope::Choices => {
                let lvl = level(&mut self.levels, plan);
                lvl.reward += discount(c.gamma, lvl.time) * reward;
                lvl.time += elapsed;
                if let Some((next, best)) = lvl.pending.take() {
                    if let (Some(prev), true) = (lvl.prev, learning) {
                        let follow = if c.target == Target::Max {
                            best
                        } else {
                            self.values.value(next)
                        };
                        let target = lvl.reward + discount(c.gamma, lvl.time) * follow;
                        let decay = c.lambda * discount(c.gamma, lvl.time);
                        Self::update(&mut self.values, c.alpha, lvl, prev, target, decay);
                    }
                    lvl.prev = Some(next);
                    lvl.reward = 0.0;
                    lvl.time = 0;
                    Self::trace(lvl, next);
                }
            }
            Scope::Markings => {
                let current = self.values.intern(plan, marking);
                let lvl = level(&mut self.levels, plan);
                let pending = lvl.pending.take();
                if let (Some(prev), true) = (lvl.prev, learning) {
                    let follow = match (c.target, pending) {
                        (Target::Max, Some((_, best))) => best,
                        _ => self.values.value(current),
                    };
                    let target = reward + discount(c.gamma, elapsed) * follow;
                    let decay = c.lambda * discount(c.gamma, elapsed);
                    Self::trace(lvl, prev);
                    Self::update(&mut self.values, c.alpha, lvl, prev, target, decay);
                }
                lvl.prev = Some(current);
            }
        }
    }

    fn plan_started(&mut self, plan: PlanKey, marking: &Marking) {
        if self.config.scope == Scope::Markings {
            let id = self.values.intern(plan, marking);
            level(&mut self.levels, plan).prev = Some(id);
        }
    }
}

impl Learner for TdLearner {
    fn begin_episode(&mut self, start: EpisodeStart) {
        for lvl in &mut self.levels {
            *lvl = Level::default();
        }
        self.memory.clear();
        self.learning = start.learning();
        self.greedy = start.greedy();
        self.left_greedy = false;
    }

    fn end_episode(&mut self, tail: PendingReward) {
        let c = self.config;
        let root = level(&mut self.levels, PlanKey::ROOT);
        match c.scope {
            Scope::Choices => {
                root.reward += discount(c.gamma, root.time) * tail.reward;
            }
            Scope::Markings => root.reward = tail.reward,
        }
        if self.learning {
            for lvl in &mut self.levels {
                if let Some(prev) = lvl.prev {
                    if c.scope == Scope::Markings {
                        Self::trace(lvl, prev);
                    }
                    let target = lvl.reward;
                    Self::update(&mut self.values, c.alpha, lvl, prev, target, 0.0);
                }
            }
        }
        for lvl in &mut self.levels {
            *lvl = Level::default();
        }
    }

    table_accessors!(left_greedy);
}
