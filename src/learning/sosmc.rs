//! Stochastic Search Monte Carlo (thesis Algorithm 1, sections 4.2 - 4.4, and
//! the threshold rule of chapter 7).
//!
//! Values are upper bounds for options outside the current policy and
//! first-visit Monte Carlo averages for the options it takes:
//! - an **exploratory** episode (the initial phase, a scheduled exploration, or
//!   an episode in which a decision left the greedy option) draws its policy
//!   from the strategy Sigma and only raises values: Q = max(Q, R_post-o);
//! - an **exploiting** episode follows the greedy policy and averages:
//!   Q += alpha (R_post-o - Q), alpha constant or 1/n(s, a) counted since the
//!   greedy policy last changed.
//!
//! Exploration is consistent: one decision per observation per episode.

use std::collections::VecDeque;

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use super::selection::{self, Schedule, Strategy};
use super::{EpisodeStart, KeyId, Learner, Trajectory, ValueTable, level};
use crate::executor::{Chooser, PendingReward, PlanKey};
use crate::net::Marking;
use crate::rng::SimRng;

/// When the assessing phase explores.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Assessment {
    /// Never: after the initial phase the greedy policy is only assessed (thesis Figure 6.3).
    Never,
    /// Every episode draws its decisions from Sigma; an episode is exploratory
    /// if one of its decisions left the greedy option (thesis section 4.1.2, Figure 6.4).
    PerDecision,
    /// One exploratory episode every `n`, decided from the episode number alone,
    /// so that several agents agree without talking (section 4.4).
    EveryN(u64),
    /// An exploratory episode once the greedy policy has been assessed for
    /// `k` episodes: exploiting episodes since the last exploratory one
    /// (Figure 4.3's assessment), whatever policies they followed.
    AfterK(u64),
    /// An exploratory episode once the current policy has been sampled `k`
    /// times: exploiting episodes since the last exploratory one or the last
    /// change of the exploited policy, whichever is later (Algorithm 1's "the
    /// current estimate is considered accurate", section 4.2.2's k samples).
    AfterKSamples(u64),
}

/// The step size of exploiting updates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum StepSize {
    /// A constant alpha: estimates blend across policies.
    Constant(f64),
    /// 1/n(s, a), n counted since the last policy change: memoryless estimates.
    InverseCount,
}

/// Chapter 7: exploration is suspended while the mean return of the last
/// `window` exploiting episodes is at least `threshold`, and resumes when it falls below.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ThresholdRule {
    /// The acceptable mean return.
    pub threshold: f64,
    /// How many exploiting episodes the mean covers.
    pub window: usize,
}

/// The strategy Sigma: how exploratory policies are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Sigma {
    /// epsilon-greedy around the greedy policy (epsilon-SoSMC).
    EpsilonGreedy,
    /// Softmax over the values (Soft-SoSMC).
    Softmax,
}

/// Soft-SoSMC: the weight of an option with no estimate yet (its value
/// negative infinity) among estimated ones.
///
/// Algorithm 1 initialises Q "pessimistically" and chapter 6 uses a finite
/// value (-4 in Parr and Russell's grid), so every option has a value and
/// eq. 1.8 weighs an untried one e^((initial - best)/tau): small, never zero,
/// as section 4.2.2's condition 3 requires. The defaults do that, and the
/// default here is eq. 1.8 as written. An initial value of negative infinity
/// ("no estimate") gives an untried option e^(-inf/tau) = 0, never drawn once
/// another has an estimate; `AsBest` is the rule for that representation
/// (docs/results/RESULTS.md has the figures both ways).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Unestimated {
    /// The weight of the best estimated option.
    AsBest,
    /// Softmax exactly as eq. 1.8 writes it: an option valued negative
    /// infinity has weight 0, not drawn while another has an estimate.
    #[default]
    None,
}

impl Unestimated {
    /// The rule of configurations saved before the option existed (read
    /// from files without the field): `AsBest`, the only rule then.
    fn saved_before_option() -> Self {
        Unestimated::AsBest
    }
}

crate::named::impl_named!(
    Unestimated,
    "unestimated weight",
    [
        AsBest => "as-best",
        None => "none",
    ]
);

/// The policy of an exploiting episode.
///
/// Algorithm 1's pseudo-code keeps "the last policy chosen" between
/// exploratory episodes; the thesis's own Figure 6.3 (section 6.1.2: SoSMC
/// with no exploration after the initial phase converging to the optimum
/// shortly after it) needs the greedy policy taken anew, since with the last
/// policy kept that policy is frozen at the end of the initial phase. The
/// default follows the results the thesis reports (docs/results/RESULTS.md
/// has the figures both ways).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ExploitPolicy {
    /// The greedy policy, taken anew in every exploiting episode.
    #[default]
    Greedy,
    /// Algorithm 1 as written: the last policy chosen; the policy that
    /// greedily maximises the values is taken anew only in the episode after
    /// an exploratory one (the initial phase's last included).
    Last,
}

crate::named::impl_named!(
    ExploitPolicy,
    "exploit policy",
    [
        Greedy => "greedy",
        Last => "last",
    ]
);

/// The parameters of SoSMC.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SoSmcConfig {
    /// Discount per executor step.
    pub gamma: f64,
    /// Episodes of the initial exploratory phase (`exp_length`; 0 skips it).
    pub initial_phase: u64,
    /// epsilon-greedy or softmax.
    pub sigma: Sigma,
    /// Epsilon or temperature over the initial phase (by episode).
    pub initial_parameter: Schedule,
    /// Epsilon or temperature in the assessing phase (by episode since it began).
    pub assessing_parameter: Schedule,
    /// When the assessing phase explores.
    pub assessment: Assessment,
    /// Step size of exploiting updates.
    pub step_size: StepSize,
    /// Initial value: a pessimistic bound of the returns (Algorithm 1), an
    /// optimistic one (section 4.2.1: no initial phase), or negative infinity (no estimate).
    #[serde(with = "crate::json_float")]
    pub initial_value: f64,
    /// The optional threshold rule.
    pub threshold: Option<ThresholdRule>,
    /// Softmax: the weight of an option with no estimate.
    #[serde(default = "Unestimated::saved_before_option")]
    pub unestimated: Unestimated,
    /// The policy of exploiting episodes.
    #[serde(default)]
    pub exploit: ExploitPolicy,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Initial,
    Explore,
    Exploit,
    PerDecision,
}

/// The SoSMC learner.
pub struct SoSmc {
    config: SoSmcConfig,
    rng: SimRng,
    values: ValueTable,
    observations: ValueTable,
    levels: Vec<Trajectory>,
    memory: FxHashMap<KeyId, KeyId>,
    decisions: Vec<(KeyId, KeyId)>,
    last_policy: FxHashMap<KeyId, KeyId>,
    counts: Vec<u32>,
    episode: u64,
    kind: Kind,
    parameter: f64,
    learning: bool,
    greedy_mode: bool,
    /// The next exploiting episode takes the greedy policy anew (it follows an
    /// exploratory one).
    repick: bool,
    left_greedy: bool,
    exploratory: bool,
    exploit_streak: u64,
    /// Exploiting episodes of the current policy since the last exploratory
    /// one or the last change of the exploited policy.
    policy_samples: u64,
    window: VecDeque<f64>,
    suspended: bool,
    ids: Vec<KeyId>,
    option_values: Vec<f64>,
    scratch: Vec<usize>,
    returns: Vec<(KeyId, f64)>,
}

impl SoSmc {
    /// A learner drawing from `rng`.
    pub fn new(config: SoSmcConfig, rng: SimRng) -> Self {
        SoSmc {
            values: ValueTable::new(config.initial_value),
            observations: ValueTable::new(0.0),
            config,
            rng,
            levels: Vec::new(),
            memory: FxHashMap::default(),
            decisions: Vec::new(),
            last_policy: FxHashMap::default(),
            counts: Vec::new(),
            episode: 0,
            kind: Kind::Initial,
            parameter: 0.0,
            learning: true,
            greedy_mode: false,
            repick: true,
            left_greedy: false,
            exploratory: false,
            exploit_streak: 0,
            policy_samples: 0,
            window: VecDeque::new(),
            suspended: false,
            ids: Vec::new(),
            option_values: Vec::new(),
            scratch: Vec::new(),
            returns: Vec::new(),
        }
    }

    /// Learning episodes completed.
    pub fn episodes(&self) -> u64 {
        self.episode
    }

    /// Whether the threshold rule currently suspends exploration.
    pub fn suspended(&self) -> bool {
        self.suspended
    }

    /// The kind of the next episode. In order: the initial phase; the threshold
    /// rule (chapter 7: while it suspends exploration, no episode explores, even
    /// one a shared schedule forces to: agents sharing a schedule share the
    /// reward, so their rules suspend and resume together); a forced choice; the
    /// learner's own assessment schedule.
    fn kind_for(&self, forced: Option<bool>) -> Kind {
        let c = &self.config;
        if self.episode < c.initial_phase {
            return Kind::Initial;
        }
        if self.suspended {
            return Kind::Exploit;
        }
        if let Some(explore) = forced {
            return if explore { Kind::Explore } else { Kind::Exploit };
        }
        let since = self.episode - c.initial_phase;
        match c.assessment {
            Assessment::Never => Kind::Exploit,
            Assessment::PerDecision => Kind::PerDecision,
            Assessment::EveryN(n) if n > 0 && (since + 1).is_multiple_of(n) => Kind::Explore,
            Assessment::AfterK(k) if self.exploit_streak >= k => Kind::Explore,
            Assessment::AfterKSamples(k) if self.policy_samples >= k => Kind::Explore,
            _ => Kind::Exploit,
        }
    }

    fn strategy(&self) -> Strategy {
        match self.config.sigma {
            Sigma::EpsilonGreedy => Strategy::EpsilonGreedy(self.parameter),
            Sigma::Softmax => match self.config.unestimated {
                Unestimated::None => Strategy::Softmax(self.parameter),
                Unestimated::AsBest => Strategy::SoftmaxUnestimatedAsBest(self.parameter),
            },
        }
    }

    /// Updates the values from the episode; whether an exploiting episode
    /// took another option than the last exploiting episodes at some observation.
    fn update(&mut self) -> bool {
        let exploit = !self.exploratory;
        let mut switched = false;
        if exploit {
            let mut changed = false;
            for &(obs, after) in &self.decisions {
                let before = self.last_policy.insert(obs, after);
                changed |= before != Some(after);
                switched |= before.is_some_and(|b| b != after);
            }
            if changed {
                self.counts.iter_mut().for_each(|c| *c = 0);
            }
        }
        self.counts.resize(self.values.len(), 0);
        for level in 0..self.levels.len() {
            self.levels[level].first_visit_returns(self.config.gamma, &mut self.returns);
            for &(id, sample) in &self.returns {
                let old = self.values.value(id);
                let new = if exploit {
                    let n = &mut self.counts[id as usize];
                    *n += 1;
                    let alpha = match self.config.step_size {
                        StepSize::Constant(a) => a,
                        StepSize::InverseCount => 1.0 / f64::from(*n),
                    };
                    super::blend(old, sample, alpha)
                } else {
                    old.max(sample)
                };
                self.values.set(id, new);
                self.values.visit(id);
            }
        }
        switched
    }
}

impl SoSmc {
    /// The option of an exploiting episode at observation `obs`: the last
    /// policy's where Algorithm 1 keeps it, else the greedy one.
    fn exploit_choice(&mut self, obs: KeyId) -> usize {
        let keep = self.config.exploit == ExploitPolicy::Last && !self.repick && !self.greedy_mode;
        let last = self
            .last_policy
            .get(&obs)
            .filter(|_| keep)
            .and_then(|after| self.ids.iter().position(|id| id == after));
        last.unwrap_or_else(|| selection::greedy(&self.option_values, &mut self.rng, &mut self.scratch))
    }
}

impl Chooser for SoSmc {
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize {
        let obs = self.observations.intern(plan, state);
        self.values
            .intern_options(plan, options, &mut self.ids, &mut self.option_values);
        let remembered = self
            .memory
            .get(&obs)
            .and_then(|after| self.ids.iter().position(|id| id == after));
        let index = match remembered {
            Some(i) => i,
            None => {
                let i = match self.kind {
                    Kind::Exploit => self.exploit_choice(obs),
                    Kind::Initial | Kind::Explore => {
                        selection::select(self.strategy(), &self.option_values, &mut self.rng, &mut self.scratch)
                    }
                    Kind::PerDecision => {
                        let i =
                            selection::select(self.strategy(), &self.option_values, &mut self.rng, &mut self.scratch);
                        self.left_greedy |= !selection::is_greedy(&self.option_values, i);
                        i
                    }
                };
                self.memory.insert(obs, self.ids[i]);
                self.decisions.push((obs, self.ids[i]));
                i
            }
        };
        level(&mut self.levels, plan).choose(self.ids[index]);
        index
    }

    fn transition(&mut self, plan: PlanKey, _marking: &Marking, reward: f64, elapsed: u32) {
        level(&mut self.levels, plan).advance(reward, elapsed);
    }
}

impl Learner for SoSmc {
    fn begin_episode(&mut self, start: EpisodeStart) {
        self.levels.iter_mut().for_each(Trajectory::clear);
        self.memory.clear();
        self.decisions.clear();
        self.left_greedy = false;
        self.learning = start.learning();
        self.greedy_mode = start.greedy();
        self.kind = if start.greedy() {
            Kind::Exploit
        } else {
            self.kind_for(start.exploratory)
        };
        self.parameter = if self.kind == Kind::Initial {
            self.config.initial_parameter.at(self.episode)
        } else {
            self.config
                .assessing_parameter
                .at(self.episode.saturating_sub(self.config.initial_phase))
        };
    }

    fn end_episode(&mut self, tail: PendingReward) {
        level(&mut self.levels, PlanKey::ROOT).advance(tail.reward, tail.elapsed);
        self.exploratory = match self.kind {
            Kind::Initial | Kind::Explore => true,
            Kind::Exploit => false,
            Kind::PerDecision => self.left_greedy,
        };
        if !self.learning {
            return;
        }
        let changed = self.update();
        self.repick = self.exploratory;
        if self.exploratory {
            self.exploit_streak = 0;
            self.policy_samples = 0;
        } else {
            self.exploit_streak += 1;
            self.policy_samples = if changed { 1 } else { self.policy_samples + 1 };
            if let Some(rule) = self.config.threshold {
                let ret = level(&mut self.levels, PlanKey::ROOT).total_return(self.config.gamma);
                self.window.push_back(ret);
                if self.window.len() > rule.window {
                    self.window.pop_front();
                }
                if self.window.len() == rule.window {
                    let mean = self.window.iter().sum::<f64>() / rule.window as f64;
                    self.suspended = mean >= rule.threshold;
                }
            }
        }
        self.episode += 1;
    }

    table_accessors!(exploratory);
}
