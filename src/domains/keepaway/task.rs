//! Keepaway episodes: the simulator, the takers inside it, and a team of
//! keepers (in this process or in keeper processes) deciding each cycle.

use std::sync::Arc;

use rand::RngExt;

use super::config::KeepawayDomainConfig;
use super::team::{KeeperTeam, LocalTeam, TeamStep};
use crate::domains::{EpisodeOutcome, Task, TaskError};
use crate::keepaway_sim::command::Command;
use crate::keepaway_sim::perception::{Perception, PlayerId};
use crate::keepaway_sim::rcg::GameLogWriter;
use crate::keepaway_sim::simulator::Simulator;
use crate::keepaway_sim::taker::{TakerMemory, taker_command};
use crate::keepaway_sim::world::{NUM_KEEPERS, NUM_PLAYERS, NUM_TAKERS};
use crate::learning::{EpisodeMode, EpisodeStart, Learner};
use crate::plan::Plan;
use crate::rng::{SimRng, derive_seed};

/// The seeds a Keepaway run draws from its random stream: the simulator's and
/// the fixed keepers' policy's. Every process of a run derives the same ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunSeeds {
    /// The simulator's (noise, resets).
    pub simulator: u64,
    /// The fixed keepers' policy (where it is random).
    pub fixed_policy: u64,
}

impl RunSeeds {
    /// The seeds drawn from `rng`, the run's Keepaway stream.
    pub fn draw(rng: &mut SimRng) -> Self {
        let seed: u64 = rng.random();
        RunSeeds {
            simulator: derive_seed(seed, 0),
            fixed_policy: derive_seed(seed, 1),
        }
    }
}

/// Learning (or fixed) runs of Keepaway 3 vs 2.
pub struct KeepawayTask {
    config: KeepawayDomainConfig,
    sim: Simulator,
    perception: Perception,
    team: Box<dyn KeeperTeam>,
    takers: [TakerMemory; NUM_TAKERS],
}

impl KeepawayTask {
    /// A run with the keepers in this process: `plan` drives the learning
    /// keepers (each with a learner from `learner`, called with the keeper's
    /// index); `rng` seeds the simulator and the fixed keepers.
    pub fn new(
        config: KeepawayDomainConfig,
        plan: Option<Arc<Plan>>,
        learner: &mut dyn FnMut(usize) -> Box<dyn Learner>,
        mut rng: SimRng,
    ) -> Result<Self, TaskError> {
        let seeds = RunSeeds::draw(&mut rng);
        let team = LocalTeam::new(&config, plan, learner, config.baseline(seeds.fixed_policy))?;
        Self::with_team(config, Box::new(team), seeds)
    }

    /// A run in which `team` decides for the keepers.
    pub fn with_team(
        config: KeepawayDomainConfig,
        team: Box<dyn KeeperTeam>,
        seeds: RunSeeds,
    ) -> Result<Self, TaskError> {
        let sim = Simulator::new(config.simulator(), seeds.simulator).map_err(|e| TaskError::Invalid(e.to_string()))?;
        let perception = Perception::new(sim.config(), seeds.simulator);
        Ok(KeepawayTask {
            config,
            sim,
            perception,
            team,
            takers: [TakerMemory::default(); NUM_TAKERS],
        })
    }

    /// Plays one episode; an episode the team aborts is discarded and played again.
    fn play(&mut self, start: EpisodeStart) -> Result<EpisodeOutcome, TaskError> {
        loop {
            if let Some(outcome) = self.play_once(start, None)? {
                return Ok(outcome);
            }
        }
    }

    /// Plays one episode in `mode` while writing it as a RoboCup game log
    /// (`.rcg` text, see [`crate::keepaway_sim::rcg`]), with the plan-driven
    /// keepers' current actions and choices where the team knows them.
    pub fn record_episode(&mut self, mode: EpisodeMode) -> Result<(EpisodeOutcome, String), TaskError> {
        self.team.set_noting(true);
        let result = loop {
            let mut log = GameLogWriter::new(self.sim.config());
            match self.play_once(EpisodeStart::of(mode), Some(&mut log)) {
                Ok(Some(outcome)) => break Ok((outcome, log.finish(self.sim.episode_cycles(), self.sim.ended()))),
                Ok(None) => continue,
                Err(e) => break Err(e),
            }
        };
        self.team.set_noting(false);
        result
    }

    /// One episode from a fresh start, or `None` if the team aborted it;
    /// every cycle is written to `log` when one is given.
    fn play_once(
        &mut self,
        start: EpisodeStart,
        mut log: Option<&mut GameLogWriter>,
    ) -> Result<Option<EpisodeOutcome>, TaskError> {
        self.sim.reset();
        self.perception.reset(self.sim.rng());
        self.takers = [TakerMemory::default(); NUM_TAKERS];
        self.team.begin_episode(start)?;
        let cfg = *self.sim.config();
        let seconds_per_cycle = cfg.server.cycle_seconds;
        loop {
            let world = *self.sim.world();
            let views = self.perception.views(&world);
            let keeper_views = PlayerId::KEEPERS.map(|id| views[id.index()]);
            let mut commands = [Command::None; NUM_PLAYERS];
            let (keepers, takers) = commands.split_at_mut(NUM_KEEPERS);
            let memories = &mut self.takers;
            // One taker's decision per step: a remote team polls between them.
            let mut next = 0;
            let mut decide_taker = || {
                if let (Some(command), Some(memory), Some(view)) = (
                    takers.get_mut(next),
                    memories.get_mut(next),
                    views.get(NUM_KEEPERS + next),
                ) {
                    *command = taker_command(view, &cfg, memory);
                    next += 1;
                }
                next < NUM_TAKERS
            };
            let step = self.team.act(&keeper_views, seconds_per_cycle, &mut decide_taker)?;
            let TeamStep::Commands(keeper_commands) = step else {
                return Ok(None);
            };
            keepers.copy_from_slice(&keeper_commands);
            self.perception.sent(&commands);
            if let Some(log) = log.as_deref_mut() {
                log.show(&world, &self.team.notes());
                log.commands(&world, &commands);
            }
            if self.sim.step(&commands).is_some() {
                break;
            }
        }
        if let Some(log) = log {
            log.show(self.sim.world(), &self.team.notes());
        }
        let cycles = self.sim.episode_cycles();
        let exploratory = self.team.end_episode(cycles)?;
        Ok(Some(EpisodeOutcome {
            ret: self.sim.episode_seconds(),
            actions: cycles,
            steps: cycles,
            exploratory,
        }))
    }

    /// The configuration.
    pub fn config(&self) -> &KeepawayDomainConfig {
        &self.config
    }

    /// The simulator's random state (between episodes: what a restart resumes from).
    pub fn simulator_rng(&self) -> &SimRng {
        self.sim.rng()
    }

    /// Restores the simulator's random state.
    pub fn set_simulator_rng(&mut self, rng: SimRng) {
        self.sim.set_rng(rng);
    }

    /// Cycles in which a plan-driven keeper issued no command, over the run.
    pub fn idle_cycles(&self) -> u64 {
        self.team.idle_cycles()
    }
}

impl Task for KeepawayTask {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        self.play(EpisodeStart::of(mode))
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        self.team.traced_values()
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        self.team.learners()
    }

    fn record(&mut self, episodes: usize) -> Result<Vec<String>, TaskError> {
        (0..episodes)
            .map(|_| self.record_episode(EpisodeMode::Evaluate).map(|(_, log)| log))
            .collect()
    }
}
