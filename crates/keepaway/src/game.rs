//! One Keepaway cycle in named stages over plain data, the cycle every driver
//! plays (the in-process [`Keepaway`](crate::episode::Keepaway), the
//! experiment's task and the pass decisions of the root crate's domain):
//!
//! 1. [`Game::views`](crate::game::Game::views): every player's view of the field ([`Cycle::views`](crate::game::Cycle::views));
//! 2. [`Game::decide_taker`](crate::game::Game::decide_taker) / [`Game::decide_takers`](crate::game::Game::decide_takers): the takers' commands,
//!    one at a time if the driver wants to do something in between;
//! 3. [`Game::commands`](crate::game::Game::commands): the keepers' commands in (from the driver), the
//!    takers' not decided yet decided, every command out;
//! 4. [`Game::step`](crate::game::Game::step): the commands sent (the players' perception notes them),
//!    the physics step and the referee's verdict out.
//!
//! A driver may stop between stages and resume later (the stages take and
//! return the [`Cycle`](crate::game::Cycle) in progress).

use super::command::Command;
use super::params::{ConfigError, KeepawayConfig};
use super::perception::Perception;
use super::referee::EndReason;
use super::simulator::Simulator;
use super::taker::{TakerMemory, taker_command};
use super::view::PlayerView;
use super::world::{NUM_KEEPERS, NUM_PLAYERS, NUM_TAKERS};
use crate::rng::SimRng;
use serde::{Deserialize, Serialize};

/// How an episode went.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeSummary {
    /// Duration in cycles.
    pub cycles: u32,
    /// Duration in seconds (the benchmark's measure).
    pub seconds: f64,
    /// Why it ended.
    pub end: EndReason,
}

/// A cycle in progress: the players' views at its start and the takers'
/// commands decided so far.
#[derive(Clone, Copy, Debug)]
pub struct Cycle {
    /// Every player's view, by global index (keepers, then takers).
    pub views: [PlayerView; NUM_PLAYERS],
    takers: [Command; NUM_TAKERS],
    next_taker: usize,
}

impl Cycle {
    /// The keepers' views, in team order.
    pub fn keeper_views(&self) -> [PlayerView; NUM_KEEPERS] {
        std::array::from_fn(|k| self.views[k])
    }
}

/// The simulator, the players' perception and the takers' memories: the
/// Keepaway world a driver supplies the keepers' commands to. The takers'
/// memories and the world models are cleared at every reset.
#[derive(Clone, Debug)]
pub struct Game {
    sim: Simulator,
    perception: Perception,
    takers: [TakerMemory; NUM_TAKERS],
}

impl Game {
    /// A game with a validated configuration, reset for its first episode.
    pub fn new(cfg: KeepawayConfig, seed: u64) -> Result<Self, ConfigError> {
        let sim = Simulator::new(cfg, seed)?;
        let mut perception = Perception::new(&cfg, seed);
        perception.reset(sim.rng());
        Ok(Game {
            sim,
            perception,
            takers: [TakerMemory::default(); NUM_TAKERS],
        })
    }

    /// Starts a new episode.
    pub fn reset(&mut self) {
        self.sim.reset();
        self.perception.reset(self.sim.rng());
        self.takers = [TakerMemory::default(); NUM_TAKERS];
    }

    /// The simulator (world, referee, configuration).
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }

    /// Restores the simulator's random state saved with
    /// [`Simulator::rng`] (between episodes: all a restart needs).
    pub fn set_simulator_rng(&mut self, rng: SimRng) {
        self.sim.set_rng(rng);
    }

    /// Stage 1: every player's view of the current state (which updates the
    /// framework players' world models: once per cycle).
    pub fn views(&mut self) -> Cycle {
        Cycle {
            views: self.perception.views(self.sim.field()),
            takers: [Command::None; NUM_TAKERS],
            next_taker: 0,
        }
    }

    /// Stage 2, one taker at a time: the next taker's command, from its own
    /// view; returns whether a taker is left to decide.
    pub fn decide_taker(&mut self, cycle: &mut Cycle) -> bool {
        let t = cycle.next_taker;
        if let (Some(command), Some(memory), Some(view)) = (
            cycle.takers.get_mut(t),
            self.takers.get_mut(t),
            cycle.views.get(NUM_KEEPERS + t),
        ) {
            *command = taker_command(view, self.sim.config(), memory);
            cycle.next_taker += 1;
        }
        cycle.next_taker < NUM_TAKERS
    }

    /// Stage 2: the commands of the takers not decided yet.
    pub fn decide_takers(&mut self, cycle: &mut Cycle) {
        while self.decide_taker(cycle) {}
    }

    /// Stage 3: the keepers' commands in (in team order), the remaining
    /// takers decided, every player's command out.
    pub fn commands(&mut self, mut cycle: Cycle, keepers: [Command; NUM_KEEPERS]) -> [Command; NUM_PLAYERS] {
        self.decide_takers(&mut cycle);
        let mut commands = [Command::None; NUM_PLAYERS];
        let (k, t) = commands.split_at_mut(NUM_KEEPERS);
        k.copy_from_slice(&keepers);
        t.copy_from_slice(&cycle.takers);
        commands
    }

    /// Stage 4: the commands sent and the simulator stepped; returns why the
    /// episode ended, if it did (further steps then do nothing until
    /// [`Game::reset`]).
    pub fn step(&mut self, commands: &[Command; NUM_PLAYERS]) -> Option<EndReason> {
        if let Some(end) = self.sim.ended() {
            return Some(end);
        }
        self.perception.sent(commands);
        self.sim.step(commands)
    }

    /// The current episode's summary, once it has ended.
    pub fn summary(&self) -> Option<EpisodeSummary> {
        self.sim.ended().map(|end| EpisodeSummary {
            cycles: self.sim.episode_cycles(),
            seconds: self.sim.episode_seconds(),
            end,
        })
    }
}
