//! The Keepaway crate's integration tests, one binary: the simulator's
//! physics and referee, the players' skills and interception, whole episodes,
//! and robustness on any input.

use learnpnp_keepaway::world::Player;
use learnpnp_keepaway::{FieldState, KeepawayConfig, Vec2, VisionMode};

mod episodes;
mod interception;
mod physics;
mod referee;
mod robustness;
mod skills;

/// Keepaway's configuration for scripted situations: without the server's
/// movement noise, and with exact views (full state), so that skills can be
/// checked against exact numbers.
pub fn noiseless() -> KeepawayConfig {
    KeepawayConfig {
        motion_noise: false,
        vision: VisionMode::FullState,
        ..KeepawayConfig::default()
    }
}

/// A player standing at `(x, y)`, facing `body` degrees.
pub fn player(x: f64, y: f64, body: f64) -> Player {
    Player {
        pos: Vec2::new(x, y),
        vel: Vec2::ZERO,
        body,
    }
}

/// A field with every player at rest facing +x, in a row along `y` from `x0`,
/// `dx` apart; the ball at rest at the origin.
pub fn players_in_a_row(x0: f64, dx: f64, y: f64) -> FieldState {
    let mut w = FieldState::default();
    for (i, p) in w.players.iter_mut().enumerate() {
        *p = player(x0 + dx * i as f64, y, 0.0);
    }
    w
}
