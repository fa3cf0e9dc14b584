//! The server's primitive body commands.

use serde::{Deserialize, Serialize};

/// One player's body command for one cycle (at most one per player per cycle).
///
/// Powers are clipped to `[min_power, max_power]` and angles to
/// `[min_moment, max_moment]` by the simulator; a command with a non-finite
/// argument is ignored (treated as [`Command::None`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Command {
    /// Do nothing this cycle.
    #[default]
    None,
    /// Kick the ball (only effective when it is within the kickable distance).
    Kick {
        /// Kick power, `[-100, 100]`.
        power: f64,
        /// Direction relative to the body, degrees.
        direction: f64,
    },
    /// Accelerate along the body direction (negative power: backwards).
    Dash {
        /// Dash power, `[-100, 100]`.
        power: f64,
    },
    /// Turn the body; the actual turn shrinks with speed (inertia).
    Turn {
        /// Turn moment in degrees, `[-180, 180]`.
        moment: f64,
    },
}

impl Command {
    /// Whether all arguments are finite numbers.
    pub(crate) fn is_finite(&self) -> bool {
        match *self {
            Command::None => true,
            Command::Kick { power, direction } => power.is_finite() && direction.is_finite(),
            Command::Dash { power } => power.is_finite(),
            Command::Turn { moment } => moment.is_finite(),
        }
    }
}
