//! MCESP (Perkins 2002), the sample-average (SAA) variant of the reference library.
//!
//! The learner keeps a deterministic policy and a queue of every (observation,
//! option) pair seen. Episodes are grouped in stages of `stage_length`; during a
//! stage the pair at the front of the queue is explored (its option is taken at
//! its observation, the policy everywhere else) and only its value learns, by
//! first-visit Monte Carlo with step max(1/n, alpha_min), n counted within the
//! stage. When the stage ends the policy switches to the explored option if its
//! value beats the policy's option, and the queue rotates.

use std::collections::VecDeque;

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use super::selection;
use super::{EpisodeStart, KeyId, Learner, Trajectory, ValueTable, blend, level};
use crate::executor::{Chooser, PendingReward, PlanKey};
use crate::net::Marking;
use crate::rng::SimRng;

/// The parameters of MCESP-SAA.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct McespConfig {
    /// Discount per executor step.
    pub gamma: f64,
    /// Episodes spent on each explored pair.
    pub stage_length: u64,
    /// Smallest step size.
    pub alpha_min: f64,
    /// Value of unseen pairs.
    #[serde(with = "crate::json_float")]
    pub initial_value: f64,
}

/// The MCESP-SAA learner.
pub struct Mcesp {
    config: McespConfig,
    rng: SimRng,
    values: ValueTable,
    observations: ValueTable,
    levels: Vec<Trajectory>,
    queue: VecDeque<(KeyId, KeyId)>,
    seen: Vec<bool>,
    policy: FxHashMap<KeyId, KeyId>,
    memory: FxHashMap<KeyId, KeyId>,
    stage_count: u32,
    episode: u64,
    learning: bool,
    greedy: bool,
    explored: bool,
    ids: Vec<KeyId>,
    option_values: Vec<f64>,
    scratch: Vec<usize>,
    returns: Vec<(KeyId, f64)>,
}

impl Mcesp {
    /// A learner drawing ties from `rng`.
    pub fn new(config: McespConfig, rng: SimRng) -> Self {
        Mcesp {
            values: ValueTable::new(config.initial_value),
            observations: ValueTable::new(0.0),
            config,
            rng,
            levels: Vec::new(),
            queue: VecDeque::new(),
            seen: Vec::new(),
            policy: FxHashMap::default(),
            memory: FxHashMap::default(),
            stage_count: 0,
            episode: 0,
            learning: true,
            greedy: false,
            explored: false,
            ids: Vec::new(),
            option_values: Vec::new(),
            scratch: Vec::new(),
            returns: Vec::new(),
        }
    }

    fn end_stage(&mut self) {
        if let Some(&(obs, explored)) = self.queue.front() {
            let current = self.policy.get(&obs).copied();
            let better = match current {
                Some(p) => self.values.value(explored) > self.values.value(p),
                None => true,
            };
            if better {
                self.policy.insert(obs, explored);
            }
            self.queue.rotate_left(1);
        }
        self.stage_count = 0;
    }
}

impl Chooser for Mcesp {
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize {
        let obs = self.observations.intern(plan, state);
        self.values
            .intern_options(plan, options, &mut self.ids, &mut self.option_values);
        if self.seen.len() <= obs as usize {
            self.seen.resize(obs as usize + 1, false);
        }
        if !self.seen[obs as usize] {
            self.seen[obs as usize] = true;
            self.queue.extend(self.ids.iter().map(|&id| (obs, id)));
        }
        let position = |target: KeyId| self.ids.iter().position(|&id| id == target);
        let index = if let Some(i) = self.memory.get(&obs).and_then(|&a| position(a)) {
            i
        } else {
            // A greedy episode follows the policy: the explored pair is for
            // learning and evaluation episodes only.
            let front = self
                .queue
                .front()
                .filter(|(o, _)| *o == obs && !self.greedy)
                .and_then(|&(_, a)| position(a));
            let policy = self.policy.get(&obs).and_then(|&a| position(a));
            let i = match (front, policy) {
                (Some(f), p) => {
                    self.explored |= Some(f) != p;
                    f
                }
                (None, Some(p)) => p,
                (None, None) => {
                    let g = selection::greedy(&self.option_values, &mut self.rng, &mut self.scratch);
                    if self.learning {
                        self.policy.insert(obs, self.ids[g]);
                    }
                    g
                }
            };
            self.memory.insert(obs, self.ids[i]);
            i
        };
        level(&mut self.levels, plan).choose(self.ids[index]);
        index
    }

    fn transition(&mut self, plan: PlanKey, _marking: &Marking, reward: f64, elapsed: u32) {
        level(&mut self.levels, plan).advance(reward, elapsed);
    }
}

impl Learner for Mcesp {
    fn begin_episode(&mut self, start: EpisodeStart) {
        self.levels.iter_mut().for_each(Trajectory::clear);
        self.memory.clear();
        self.learning = start.learning();
        self.greedy = start.greedy();
        self.explored = false;
        if self.learning && self.episode > 0 && self.episode.is_multiple_of(self.config.stage_length.max(1)) {
            self.end_stage();
        }
    }

    fn end_episode(&mut self, tail: PendingReward) {
        level(&mut self.levels, PlanKey::ROOT).advance(tail.reward, tail.elapsed);
        if !self.learning {
            return;
        }
        self.episode += 1;
        let Some(&(_, explored)) = self.queue.front() else {
            return;
        };
        let mut counted = false;
        for t in &mut self.levels {
            t.first_visit_returns(self.config.gamma, &mut self.returns);
            for &(id, sample) in &self.returns {
                if id == explored {
                    if !counted {
                        self.stage_count += 1;
                        counted = true;
                    }
                    let alpha = (1.0 / f64::from(self.stage_count)).max(self.config.alpha_min);
                    self.values.set(id, blend(self.values.value(id), sample, alpha));
                    self.values.visit(id);
                }
            }
        }
    }

    table_accessors!(explored);
}
