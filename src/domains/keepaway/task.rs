//! Keepaway episodes: the simulator, the takers inside it, and a team of
//! keepers (in this process or in keeper processes) deciding each cycle.

use std::sync::Arc;

use rand::RngExt;

use super::config::KeepawayDomainConfig;
use super::team::{KeeperTeam, LocalTeam, TeamStep};
use crate::domains::{EpisodeOutcome, Task, TaskError};
use crate::learning::{EpisodeMode, EpisodeStart, Learner};
use crate::plan::Plan;
use crate::rng::{SimRng, derive_seed};
use learnpnp_keepaway::game::Game;
use learnpnp_keepaway::rcg::GameLogWriter;

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
    game: Game,
    team: Box<dyn KeeperTeam>,
    /// Simulated cycles of every episode played, aborted ones included.
    cycles_played: u64,
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
        let game = Game::new(config.simulator(), seeds.simulator).map_err(|e| TaskError::Invalid(e.to_string()))?;
        Ok(KeepawayTask {
            config,
            game,
            team,
            cycles_played: 0,
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
    /// (`.rcg` text, see [`learnpnp_keepaway::rcg`]), with the plan-driven
    /// keepers' current actions and choices where the team knows them.
    pub fn record_episode(&mut self, mode: EpisodeMode) -> Result<(EpisodeOutcome, String), TaskError> {
        self.team.set_noting(true);
        let result = loop {
            let mut log = GameLogWriter::new(self.game.simulator().config());
            match self.play_once(EpisodeStart::of(mode), Some(&mut log)) {
                Ok(Some(outcome)) => {
                    let sim = self.game.simulator();
                    break Ok((outcome, log.finish(sim.episode_cycles(), sim.ended())));
                }
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
        self.game.reset();
        self.team.begin_episode(start)?;
        let seconds_per_cycle = self.game.simulator().config().server.cycle_seconds;
        loop {
            let mut cycle = self.game.views();
            let game = &mut self.game;
            // One taker's decision per step: a remote team polls between them.
            let step = self.team.act(&cycle.keeper_views(), seconds_per_cycle, &mut || {
                game.decide_taker(&mut cycle)
            })?;
            let TeamStep::Commands(keepers) = step else {
                return Ok(None);
            };
            let commands = self.game.commands(cycle, keepers);
            self.cycles_played += 1;
            if let Some(log) = log.as_deref_mut() {
                let world = self.game.simulator().field();
                log.show(world, &self.team.notes());
                log.commands(world, &commands);
            }
            if self.game.step(&commands).is_some() {
                break;
            }
        }
        let sim = self.game.simulator();
        if let Some(log) = log {
            log.show(sim.field(), &self.team.notes());
        }
        let cycles = sim.episode_cycles();
        let seconds = sim.episode_seconds();
        let exploratory = self.team.end_episode(cycles)?;
        Ok(Some(EpisodeOutcome {
            ret: seconds,
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
        self.game.simulator().rng()
    }

    /// Restores the simulator's random state.
    pub fn set_simulator_rng(&mut self, rng: SimRng) {
        self.game.set_simulator_rng(rng);
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

    fn actions_played(&self) -> Option<u64> {
        Some(self.cycles_played)
    }

    fn replays(&mut self) -> Result<Vec<String>, TaskError> {
        (0..self.config().record)
            .map(|_| self.record_episode(EpisodeMode::Evaluate).map(|(_, log)| log))
            .collect()
    }
}
