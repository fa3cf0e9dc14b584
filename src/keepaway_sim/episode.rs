//! Running episodes: every agent perceives, decides, and the simulator steps.

use super::command::Command;
use super::keeper::{KeeperMemory, KeeperPolicy, keeper_command};
use super::params::{ConfigError, KeepawayConfig};
use super::perception::{Perception, PlayerId};
use super::referee::EndReason;
use super::simulator::Simulator;
use super::taker::{TakerMemory, taker_command};
use super::world::{NUM_KEEPERS, NUM_PLAYERS, NUM_TAKERS, Side};
use serde::{Deserialize, Serialize};

/// How an episode went.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct EpisodeOutcome {
    /// Duration in cycles.
    pub cycles: u32,
    /// Duration in seconds (the benchmark's measure).
    pub seconds: f64,
    /// Why it ended.
    pub end: EndReason,
}

/// A keepaway match: the simulator, the players' perception and the agents'
/// memories. Keepers follow the fixed procedure around a [`KeeperPolicy`]; takers
/// follow the framework's policy. Memories and world models are cleared at every
/// reset.
#[derive(Clone, Debug)]
pub struct Keepaway {
    sim: Simulator,
    perception: Perception,
    memories: [KeeperMemory; NUM_KEEPERS],
    takers: [TakerMemory; NUM_TAKERS],
}

impl Keepaway {
    /// A match with a validated configuration, reset for its first episode.
    pub fn new(cfg: KeepawayConfig, seed: u64) -> Result<Self, ConfigError> {
        let sim = Simulator::new(cfg, seed)?;
        let mut perception = Perception::new(&cfg, seed);
        perception.reset(sim.rng());
        Ok(Keepaway {
            sim,
            perception,
            memories: [KeeperMemory::default(); NUM_KEEPERS],
            takers: [TakerMemory::default(); NUM_TAKERS],
        })
    }

    /// Starts a new episode.
    pub fn reset(&mut self) {
        self.sim.reset();
        self.perception.reset(self.sim.rng());
        self.memories = [KeeperMemory::default(); NUM_KEEPERS];
        self.takers = [TakerMemory::default(); NUM_TAKERS];
    }

    /// The simulator (world, referee, configuration).
    pub fn simulator(&self) -> &Simulator {
        &self.sim
    }

    /// Every player's command for the current state, each computed from its own view.
    /// This updates the players' memories (a pass in progress, the last interception
    /// point) and world models, so it is meant to be called once per cycle, as
    /// [`Keepaway::step`] does.
    pub fn commands(&mut self, policy: &mut dyn KeeperPolicy) -> [Command; NUM_PLAYERS] {
        let cfg = *self.sim.config();
        let views = self.perception.views(self.sim.world());
        let mut commands = [Command::None; NUM_PLAYERS];
        for (i, (cmd, view)) in commands.iter_mut().zip(views.iter()).enumerate() {
            let Some(id) = PlayerId::new(i) else { continue };
            *cmd = match id.side() {
                Side::Keepers => match self.memories.get_mut(id.index_in_team()) {
                    Some(memory) => keeper_command(view, &cfg, memory, policy),
                    None => Command::None,
                },
                Side::Takers => match self.takers.get_mut(id.index_in_team()) {
                    Some(memory) => taker_command(view, &cfg, memory),
                    None => Command::None,
                },
            };
        }
        self.perception.sent(&commands);
        commands
    }

    /// One cycle: all agents act, then the simulator steps. Returns why the episode
    /// ended, if it did (further calls then do nothing until [`Keepaway::reset`]).
    pub fn step(&mut self, policy: &mut dyn KeeperPolicy) -> Option<EndReason> {
        if let Some(end) = self.sim.ended() {
            return Some(end);
        }
        let commands = self.commands(policy);
        self.sim.step(&commands)
    }

    /// The outcome of the current episode, once it has ended.
    pub fn outcome(&self) -> Option<EpisodeOutcome> {
        self.sim.ended().map(|end| EpisodeOutcome {
            cycles: self.sim.episode_cycles(),
            seconds: self.sim.episode_seconds(),
            end,
        })
    }

    /// Resets, plays a whole episode with `policy`, tells the policy the outcome and
    /// returns it. With `max_episode_cycles` set to `None` this only returns when the
    /// referee ends the episode.
    pub fn run_episode(&mut self, policy: &mut dyn KeeperPolicy) -> EpisodeOutcome {
        self.reset();
        let outcome = loop {
            if self.step(policy).is_some()
                && let Some(o) = self.outcome()
            {
                break o;
            }
        };
        policy.end_episode(&outcome);
        outcome
    }
}

/// Runs one episode from `seed` with `policy` deciding for the keeper with the ball.
pub fn run_episode(
    cfg: &KeepawayConfig,
    seed: u64,
    policy: &mut dyn KeeperPolicy,
) -> Result<EpisodeOutcome, ConfigError> {
    let mut game = Keepaway::new(*cfg, seed)?;
    Ok(game.run_episode(policy))
}
