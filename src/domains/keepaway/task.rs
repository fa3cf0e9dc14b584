//! Keepaway episodes with plan-driven keepers: the pass decision learned by
//! one keeper, positioning learned by all three, or fixed baseline policies.

use std::sync::Arc;

use rand::RngExt;
use serde::{Deserialize, Serialize};

use super::agent::PlanKeeper;
use super::world::atoms;
use crate::domains::{EpisodeOutcome, Task, TaskError};
use crate::executor::{ExecError, PlanKey};
use crate::keepaway::command::Command;
use crate::keepaway::features::FeatureThresholds;
use crate::keepaway::keeper::{KeeperMemory, keeper_command};
use crate::keepaway::params::{KeepawayConfig, VisionMode};
use crate::keepaway::perception::{PlayerId, perceive};
use crate::keepaway::policies::{BaselinePolicy, DEFAULT_HOLD_THRESHOLD};
use crate::keepaway::simulator::Simulator;
use crate::keepaway::taker::{TakerMemory, taker_command};
use crate::keepaway::world::{NUM_KEEPERS, NUM_PLAYERS, NUM_TAKERS, Side};
use crate::learning::{EpisodeMode, EpisodeStart, Learner, StateKey};
use crate::plan::{Plan, Vocabulary, catalog};
use crate::rng::{SimRng, derive_seed};

/// The keepers' fixed decision policies (`keepaway-fixed --policy`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum FixedPolicy {
    /// Uniform over hold, pass 1 and pass 2.
    Random,
    /// Always hold.
    AlwaysHold,
    /// The keepaway framework's hand-coded policy.
    Handcoded,
    /// The thesis's simple policy: hold until a taker is near, then pass to the safest lane.
    Threshold,
}

/// Who decides what.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KeepawayMode {
    /// Keeper 1 learns the pass decision; the other two follow the threshold policy (thesis 7.2).
    Pass,
    /// All three keepers learn where to stand, each with its own values (thesis 7.3).
    Position,
    /// All three keepers follow a fixed policy; nothing learns.
    Fixed(FixedPolicy),
}

/// Keepaway's parameters beyond the simulator's defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct KeepawayDomainConfig {
    /// Who learns.
    pub mode: KeepawayMode,
    /// Full state (default) or the server's quantised vision.
    pub vision: VisionMode,
    /// The thresholds of the three binary features.
    pub thresholds: FeatureThresholds,
    /// The distance at which the threshold policy passes.
    pub hold_threshold: f64,
}

impl Default for KeepawayDomainConfig {
    fn default() -> Self {
        KeepawayDomainConfig {
            mode: KeepawayMode::Pass,
            vision: VisionMode::FullState,
            thresholds: FeatureThresholds::default(),
            hold_threshold: DEFAULT_HOLD_THRESHOLD,
        }
    }
}

impl KeepawayDomainConfig {
    /// The defaults of `mode`.
    pub fn for_mode(mode: KeepawayMode) -> Self {
        KeepawayDomainConfig {
            mode,
            ..KeepawayDomainConfig::default()
        }
    }

    /// The simulator's configuration.
    pub fn simulator(&self) -> KeepawayConfig {
        KeepawayConfig {
            vision: self.vision,
            ..KeepawayConfig::default()
        }
    }

    /// How many keepers learn.
    pub fn learning_keepers(&self) -> usize {
        match self.mode {
            KeepawayMode::Pass => 1,
            KeepawayMode::Position => NUM_KEEPERS,
            KeepawayMode::Fixed(_) => 0,
        }
    }

    /// The thesis's plan for the mode (none for fixed policies).
    pub fn default_plan(&self) -> Result<Option<Plan>, TaskError> {
        let net = match self.mode {
            KeepawayMode::Pass => catalog::keepaway_pass(),
            KeepawayMode::Position => catalog::keepaway_position(),
            KeepawayMode::Fixed(_) => return Ok(None),
        }
        .map_err(crate::plan::PlanError::from)?;
        Ok(Some(Plan::from_net(net, Vocabulary::Closed(&atoms()))?))
    }

    fn baseline(&self, seed: u64) -> BaselinePolicy {
        match self.mode {
            KeepawayMode::Fixed(FixedPolicy::Random) => BaselinePolicy::random(seed),
            KeepawayMode::Fixed(FixedPolicy::AlwaysHold) => BaselinePolicy::AlwaysHold,
            KeepawayMode::Fixed(FixedPolicy::Handcoded) => BaselinePolicy::HandCoded,
            _ => BaselinePolicy::Threshold {
                threshold: self.hold_threshold,
            },
        }
    }
}

/// Learning (or fixed) runs of Keepaway 3 vs 2.
pub struct KeepawayTask {
    config: KeepawayDomainConfig,
    sim: Simulator,
    keepers: Vec<PlanKeeper>,
    fixed: BaselinePolicy,
    memories: [KeeperMemory; NUM_KEEPERS],
    takers: [TakerMemory; NUM_TAKERS],
    traced: Vec<(String, usize, StateKey)>,
}

impl KeepawayTask {
    /// A run: `plan` drives the learning keepers (each with a learner from `learner`,
    /// called with the keeper's index); `rng` seeds the simulator.
    pub fn new(
        config: KeepawayDomainConfig,
        plan: Option<Arc<Plan>>,
        learner: &mut dyn FnMut(usize) -> Box<dyn Learner>,
        mut rng: SimRng,
    ) -> Result<Self, TaskError> {
        let sim_config = config.simulator();
        let seed: u64 = rng.random();
        let sim = Simulator::new(sim_config, derive_seed(seed, 0)).map_err(|e| TaskError::Invalid(e.to_string()))?;
        let mut keepers = Vec::new();
        let mut traced = Vec::new();
        if let Some(plan) = plan.filter(|_| config.learning_keepers() > 0) {
            let registry = super::actions::registry(&sim_config);
            for k in 0..config.learning_keepers() {
                keepers.push(PlanKeeper::new(
                    Arc::clone(&plan),
                    &registry,
                    learner(k),
                    sim_config,
                    config.thresholds,
                )?);
                if config.mode == KeepawayMode::Position {
                    for point in catalog::POSITIONS {
                        let at = format!("at{point}");
                        if let Ok(m) = crate::domains::driver::marking_with(&plan, &[&at, "decide"]) {
                            traced.push((
                                format!("keeper{}/{point}", k + 1),
                                k,
                                StateKey {
                                    plan: PlanKey::ROOT,
                                    marking: m,
                                },
                            ));
                        }
                    }
                }
            }
        }
        Ok(KeepawayTask {
            fixed: config.baseline(derive_seed(seed, 1)),
            config,
            sim,
            keepers,
            memories: [KeeperMemory::default(); NUM_KEEPERS],
            takers: [TakerMemory::default(); NUM_TAKERS],
            traced,
        })
    }

    /// Plays one episode; the keepers with a plan learn as `start` says.
    fn play(&mut self, start: EpisodeStart) -> Result<EpisodeOutcome, ExecError> {
        self.sim.reset();
        self.memories = [KeeperMemory::default(); NUM_KEEPERS];
        self.takers = [TakerMemory::default(); NUM_TAKERS];
        for k in &mut self.keepers {
            k.begin_episode(start);
        }
        let cfg = *self.sim.config();
        let seconds_per_cycle = cfg.server.cycle_seconds;
        loop {
            let world = *self.sim.world();
            let mut commands = [Command::None; NUM_PLAYERS];
            for (i, command) in commands.iter_mut().enumerate() {
                let Some(id) = PlayerId::new(i) else { continue };
                let view = perceive(&world, id, &cfg);
                *command = match id.side() {
                    Side::Takers => taker_command(&view, &cfg, &mut self.takers[id.index_in_team()]),
                    Side::Keepers => {
                        let k = id.index_in_team();
                        match self.keepers.get_mut(k) {
                            Some(keeper) => keeper.act(view, seconds_per_cycle)?,
                            None => keeper_command(&view, &cfg, &mut self.memories[k], &mut self.fixed),
                        }
                    }
                };
            }
            if self.sim.step(&commands).is_some() {
                break;
            }
        }
        for k in &mut self.keepers {
            k.end_episode();
        }
        let cycles = self.sim.episode_cycles();
        Ok(EpisodeOutcome {
            ret: self.sim.episode_seconds(),
            actions: cycles,
            steps: cycles,
            exploratory: self.keepers.first().is_some_and(|k| k.learner().exploratory()),
        })
    }

    /// The configuration.
    pub fn config(&self) -> &KeepawayDomainConfig {
        &self.config
    }

    /// Cycles in which a plan-driven keeper issued no command, over the run.
    pub fn idle_cycles(&self) -> u64 {
        self.keepers.iter().map(PlanKeeper::idle_cycles).sum()
    }
}

impl Task for KeepawayTask {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        Ok(self.play(EpisodeStart::of(mode))?)
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        self.traced
            .iter()
            .map(|(name, k, key)| {
                (
                    name.clone(),
                    self.keepers[*k].learner().values().value_of(key.plan, &key.marking),
                )
            })
            .collect()
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        self.keepers.iter().map(|k| k.learner()).collect()
    }
}
