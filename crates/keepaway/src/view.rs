//! What one agent perceives, as plain data: [`PlayerView`](crate::view::PlayerView) (the ball and every
//! player, seen from one player at the start of a cycle) and its parts. The
//! views are made by [`crate::perception`] and read by the skills, the world
//! model and the policies; they depend on nothing but geometry and the field's
//! constants.

use super::geometry::Vec2;
use super::params::KeepawayConfig;
use super::world::{NUM_PLAYERS, Side};
use serde::{Deserialize, Serialize};

/// A valid global player index (`0..NUM_PLAYERS`; keepers first, then takers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(try_from = "u8", into = "u8")]
pub struct PlayerId(pub(crate) u8);

/// A player index out of range.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("player index {0} out of range")]
pub struct BadPlayerId(pub u8);

impl TryFrom<u8> for PlayerId {
    type Error = BadPlayerId;
    fn try_from(i: u8) -> Result<Self, BadPlayerId> {
        if usize::from(i) < NUM_PLAYERS {
            Ok(PlayerId(i))
        } else {
            Err(BadPlayerId(i))
        }
    }
}

impl From<PlayerId> for u8 {
    fn from(p: PlayerId) -> u8 {
        p.0
    }
}

impl PlayerId {
    /// The keepers, in team order.
    #[cfg(test)]
    pub(crate) const KEEPERS: [PlayerId; super::world::NUM_KEEPERS] = {
        let mut ids = [PlayerId(0); super::world::NUM_KEEPERS];
        let mut k = 0;
        while k < ids.len() {
            ids[k] = PlayerId(k as u8);
            k += 1;
        }
        ids
    };

    /// The id of global index `i`, if it is in range.
    pub fn new(i: usize) -> Option<PlayerId> {
        u8::try_from(i).ok().and_then(|i| PlayerId::try_from(i).ok())
    }

    /// Keeper `k` (`0..3`), if in range.
    pub fn keeper(k: usize) -> Option<PlayerId> {
        if k < Side::Keepers.indices().len() {
            PlayerId::new(k)
        } else {
            None
        }
    }

    /// Taker `t` (`0..2`), if in range.
    pub fn taker(t: usize) -> Option<PlayerId> {
        PlayerId::new(Side::Takers.indices().start + t)
    }

    /// The global index, always `< NUM_PLAYERS`.
    pub fn index(self) -> usize {
        usize::from(self.0)
    }

    /// The player's team.
    pub fn side(self) -> Side {
        Side::of(self.index())
    }

    /// Index within the team.
    pub fn index_in_team(self) -> usize {
        self.index() - self.side().indices().start
    }
}

/// A seen object (the ball).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SeenBall {
    /// Global position.
    pub pos: Vec2,
    /// Global velocity (m/cycle).
    pub vel: Vec2,
}

/// A seen player (or oneself).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SeenPlayer {
    /// Global position.
    pub pos: Vec2,
    /// Global velocity (m/cycle).
    pub vel: Vec2,
    /// Body direction, degrees.
    pub body: f64,
}

/// One agent's perception at the start of a cycle, in global coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlayerView {
    /// Cycles since the episode started.
    pub cycle: u32,
    /// Who is looking.
    pub me: PlayerId,
    /// The ball.
    pub ball: SeenBall,
    /// All players by global index (keepers, then takers); entry `me` is oneself.
    pub players: [SeenPlayer; NUM_PLAYERS],
}

impl PlayerView {
    /// One's own state.
    pub fn own(&self) -> &SeenPlayer {
        &self.players[self.me.index()]
    }

    /// One's team.
    pub fn side(&self) -> Side {
        self.me.side()
    }

    /// Teammates (excluding oneself), with their global indices.
    pub(crate) fn teammates(&self) -> impl Iterator<Item = (usize, &SeenPlayer)> {
        let me = self.me.index();
        self.side()
            .indices()
            .filter(move |&i| i != me)
            .map(move |i| (i, &self.players[i]))
    }

    /// Opponents, with their global indices.
    pub fn opponents(&self) -> impl Iterator<Item = (usize, &SeenPlayer)> {
        self.side().opponent().indices().map(move |i| (i, &self.players[i]))
    }

    /// Whether the ball is within one's kickable distance (the framework's
    /// `isBallKickable`: strictly closer than it; the server itself accepts a kick
    /// at exactly that distance).
    pub fn ball_kickable(&self, cfg: &KeepawayConfig) -> bool {
        self.own().pos.dist(self.ball.pos) < cfg.server.kickable_distance()
    }
}
