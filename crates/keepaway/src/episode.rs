//! Running episodes in this process: the [`Game`](crate::game::Game)'s cycle with the keepers
//! deciding by a [`KeeperPolicy`](crate::keeper::KeeperPolicy).

use super::command::Command;
use super::game::{EpisodeSummary, Game};
use super::keeper::{KeeperMemory, KeeperPolicy, keeper_command};
use super::params::{ConfigError, KeepawayConfig};
use super::referee::EndReason;
use super::simulator::Simulator;
use super::world::{NUM_KEEPERS, NUM_PLAYERS};

/// A keepaway match played in this process: a [`Game`] whose keepers follow
/// the fixed procedure around a [`KeeperPolicy`] (the takers follow the
/// framework's policy inside the game). The keepers' memories are cleared at
/// every reset.
#[derive(Clone, Debug)]
pub struct Keepaway {
    game: Game,
    memories: [KeeperMemory; NUM_KEEPERS],
}

impl Keepaway {
    /// A match with a validated configuration, reset for its first episode.
    pub fn new(cfg: KeepawayConfig, seed: u64) -> Result<Self, ConfigError> {
        Ok(Keepaway {
            game: Game::new(cfg, seed)?,
            memories: [KeeperMemory::default(); NUM_KEEPERS],
        })
    }

    /// Starts a new episode.
    pub fn reset(&mut self) {
        self.game.reset();
        self.memories = [KeeperMemory::default(); NUM_KEEPERS];
    }

    /// The simulator (world, referee, configuration).
    pub fn simulator(&self) -> &Simulator {
        self.game.simulator()
    }

    /// Every player's command for the current state, each computed from its own view.
    /// This updates the players' memories (a pass in progress, the last interception
    /// point) and world models, so it is meant to be called once per cycle, as
    /// [`Keepaway::step`] does.
    pub(crate) fn commands(&mut self, policy: &mut dyn KeeperPolicy) -> [Command; NUM_PLAYERS] {
        let cfg = *self.game.simulator().config();
        let cycle = self.game.views();
        let mut keepers = [Command::None; NUM_KEEPERS];
        for ((command, memory), view) in keepers.iter_mut().zip(&mut self.memories).zip(&cycle.views) {
            *command = keeper_command(view, &cfg, memory, policy);
        }
        self.game.commands(cycle, keepers)
    }

    /// One cycle: all agents act, then the simulator steps. Returns why the episode
    /// ended, if it did (further calls then do nothing until [`Keepaway::reset`]).
    pub fn step(&mut self, policy: &mut dyn KeeperPolicy) -> Option<EndReason> {
        if let Some(end) = self.game.simulator().ended() {
            return Some(end);
        }
        let commands = self.commands(policy);
        self.game.step(&commands)
    }

    /// The summary of the current episode, once it has ended.
    pub fn summary(&self) -> Option<EpisodeSummary> {
        self.game.summary()
    }

    /// Resets, plays a whole episode with `policy`, tells the policy the outcome and
    /// returns it. With `max_episode_cycles` set to `None` this only returns when the
    /// referee ends the episode.
    pub fn run_episode(&mut self, policy: &mut dyn KeeperPolicy) -> EpisodeSummary {
        self.reset();
        let outcome = loop {
            if self.step(policy).is_some()
                && let Some(o) = self.summary()
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
) -> Result<EpisodeSummary, ConfigError> {
    let mut game = Keepaway::new(*cfg, seed)?;
    Ok(game.run_episode(policy))
}
