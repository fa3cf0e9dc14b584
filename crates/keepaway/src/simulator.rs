//! The simulator: the field, the referee and the random generator behind one step function.

use super::command::Command;
use super::params::{ConfigError, KeepawayConfig};
use super::referee::{EndReason, Referee, reset_world};
use super::world::{FieldState, NUM_PLAYERS};
use crate::rng::{SimRng, seeded};

/// A keepaway simulator. All randomness (reset, motion noise, turn noise, movement
/// order) comes from its own [`SimRng`], so the same seed and the same commands
/// replay the same episode exactly.
#[derive(Clone, Debug)]
pub struct Simulator {
    cfg: KeepawayConfig,
    field: FieldState,
    referee: Referee,
    rng: SimRng,
    ended: Option<EndReason>,
}

impl Simulator {
    /// A simulator with a validated configuration, reset for its first episode.
    pub fn new(cfg: KeepawayConfig, seed: u64) -> Result<Self, ConfigError> {
        cfg.validate()?;
        let mut sim = Simulator {
            cfg,
            field: FieldState::default(),
            referee: Referee::default(),
            rng: seeded(seed),
            ended: None,
        };
        sim.reset();
        Ok(sim)
    }

    /// Starts a new episode (the referee's field reset).
    pub fn reset(&mut self) {
        reset_world(&mut self.field, &self.cfg, &mut self.rng);
        self.referee = Referee::default();
        self.ended = None;
    }

    /// Replaces the field's state (for tests and scripted scenarios); the referee's
    /// counter and the end flag are cleared.
    pub fn set_field(&mut self, field: FieldState) {
        self.field = field;
        self.referee = Referee::default();
        self.ended = None;
    }

    /// One cycle: the commands, the physics, then the referee. Returns why the
    /// episode ended, if it did this cycle. Once ended, further calls do nothing and
    /// return the same reason until [`Simulator::reset`].
    pub fn step(&mut self, commands: &[Command; NUM_PLAYERS]) -> Option<EndReason> {
        if self.ended.is_some() {
            return self.ended;
        }
        self.field
            .physics_step(commands, &self.cfg.server, self.cfg.motion_noise, &mut self.rng);
        self.ended = self.referee.check(&self.field, &self.cfg);
        self.ended
    }

    /// The random generator's state (between episodes: all a restart needs).
    pub fn rng(&self) -> &SimRng {
        &self.rng
    }

    /// Restores a random state saved with [`Simulator::rng`].
    pub(crate) fn set_rng(&mut self, rng: SimRng) {
        self.rng = rng;
    }

    /// The current state.
    pub fn field(&self) -> &FieldState {
        &self.field
    }

    /// The configuration.
    pub fn config(&self) -> &KeepawayConfig {
        &self.cfg
    }

    /// The referee's state.
    pub fn referee(&self) -> &Referee {
        &self.referee
    }

    /// Why the current episode ended, if it has.
    pub fn ended(&self) -> Option<EndReason> {
        self.ended
    }

    /// Cycles simulated in the current episode.
    pub fn episode_cycles(&self) -> u32 {
        self.field.cycle
    }

    /// Duration of the current episode in seconds (cycles x 0.1 s by default).
    pub fn episode_seconds(&self) -> f64 {
        f64::from(self.field.cycle) * self.cfg.server.cycle_seconds
    }
}
