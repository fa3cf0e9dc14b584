//! What one agent perceives: a plain, serialisable [`PlayerView`].
//!
//! Agents act only from their own view, so views (and [`super::command::Command`])
//! are `Copy` data that can cross a process boundary.

use super::geometry::{Vec2, normalize_deg, quantize};
use super::params::{KeepawayConfig, VisionMode};
use super::see::{change, quantised_distance, relative_direction};
use super::world::{FieldState, NUM_KEEPERS, NUM_PLAYERS, Side};
use serde::{Deserialize, Serialize};

/// A valid global player index (`0..NUM_PLAYERS`; keepers first, then takers).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(try_from = "u8", into = "u8")]
pub struct PlayerId(u8);

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
    pub(crate) const KEEPERS: [PlayerId; NUM_KEEPERS] = {
        let mut ids = [PlayerId(0); NUM_KEEPERS];
        let mut k = 0;
        while k < NUM_KEEPERS {
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
    pub fn teammates(&self) -> impl Iterator<Item = (usize, &SeenPlayer)> {
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

/// Builds player `me`'s view of `world` in the configured vision mode.
///
/// - [`VisionMode::FullState`]: exact values.
/// - [`VisionMode::Quantised`]: the era's visual quantisation, relative to the viewer
///   (whose neck is taken as aligned with the body), converted back to global
///   coordinates: distance `d' = Q(exp(Q(ln(d + 1e-10), 0.1)), 0.1)`, direction
///   rounded to whole degrees, velocity from the server's quantised distance change
///   `d' * Q(v_r / d, 0.02)` and direction change `Q(v_t / d in degrees, 0.1)`, body
///   direction in whole degrees. One's own velocity comes from the body sense
///   (speed to 0.01, direction to whole degrees). One's own position and body
///   direction are given exactly (the framework localises from landmarks, quantised
///   ten times finer; this simulator does not model landmarks).
pub fn perceive(world: &FieldState, me: PlayerId, cfg: &KeepawayConfig) -> PlayerView {
    let mut view = PlayerView {
        cycle: world.cycle,
        me,
        ball: SeenBall {
            pos: world.ball.pos,
            vel: world.ball.vel,
        },
        players: [SeenPlayer::default(); NUM_PLAYERS],
    };
    for (seen, p) in view.players.iter_mut().zip(world.players.iter()) {
        *seen = SeenPlayer {
            pos: p.pos,
            vel: p.vel,
            body: p.body,
        };
    }
    if cfg.vision == VisionMode::Quantised {
        let q = Quantiser::new(world, me, cfg);
        let own = q.own_vel();
        view.players[me.index()].vel = own;
        let (pos, vel) = q.object(world.ball.pos, world.ball.vel, own);
        view.ball = SeenBall { pos, vel };
        for (i, p) in world.players.iter().enumerate() {
            if i == me.index() {
                continue;
            }
            let (pos, vel) = q.object(p.pos, p.vel, own);
            let body = q.body + normalize_deg(p.body - q.body).round_ties_even();
            view.players[i] = SeenPlayer {
                pos,
                vel,
                body: normalize_deg(body),
            };
        }
    }
    view
}

/// The quantised-vision computations for one viewer.
struct Quantiser {
    pos: Vec2,
    vel: Vec2,
    body: f64,
    qstep: f64,
}

impl Quantiser {
    fn new(world: &FieldState, me: PlayerId, cfg: &KeepawayConfig) -> Self {
        let p = &world.players[me.index()];
        Quantiser {
            pos: p.pos,
            vel: p.vel,
            body: p.body,
            qstep: cfg.server.quantize_step,
        }
    }

    /// The body sense of one's own velocity.
    fn own_vel(&self) -> Vec2 {
        let speed = quantize(self.vel.norm(), 0.01);
        let dir = normalize_deg(self.vel.dir() - self.body).round_ties_even();
        Vec2::polar(speed, self.body + dir)
    }

    /// Seen position and velocity of an object at `pos` moving at `vel`, given the
    /// viewer's own perceived velocity.
    fn object(&self, pos: Vec2, vel: Vec2, own_vel: Vec2) -> (Vec2, Vec2) {
        let rel = pos - self.pos;
        let dq = quantised_distance(rel.norm(), self.qstep);
        let seen_dir = self.body + relative_direction(rel, self.body);
        let seen_pos = self.pos + Vec2::polar(dq, seen_dir);
        if rel.norm() <= 0.0 {
            return (seen_pos, own_vel);
        }
        let (dist_chg, dir_chg) = change(rel, vel - self.vel, dq);
        let u = Vec2::polar(1.0, seen_dir);
        let perp = Vec2::new(-u.y, u.x);
        let seen_vel = own_vel + u * dist_chg + perp * (dir_chg.to_radians() * dq);
        (seen_pos, seen_vel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keepaway_sim::world::Player;

    fn world() -> FieldState {
        let mut w = FieldState::default();
        w.ball.pos = Vec2::new(3.0, 4.0);
        w.ball.vel = Vec2::new(1.0, -0.5);
        for (i, p) in w.players.iter_mut().enumerate() {
            *p = Player {
                pos: Vec2::new(i as f64 * 2.0 - 4.0, 1.0 - i as f64),
                vel: Vec2::new(0.1, 0.2),
                body: 10.0 * i as f64,
            };
        }
        w
    }

    #[test]
    fn full_state_is_exact() {
        let w = world();
        let me = PlayerId::keeper(1).expect("keeper 1");
        let v = perceive(&w, me, &KeepawayConfig::default());
        assert_eq!(v.ball.pos, w.ball.pos);
        assert_eq!(v.players[4].pos, w.players[4].pos);
        assert_eq!(v.teammates().count(), 2);
        assert_eq!(v.opponents().count(), 2);
    }

    #[test]
    fn quantised_is_close_and_coarse() {
        let w = world();
        let cfg = KeepawayConfig {
            vision: VisionMode::Quantised,
            ..KeepawayConfig::default()
        };
        let me = PlayerId::keeper(0).expect("keeper 0");
        let v = perceive(&w, me, &cfg);
        let d = w.ball.pos.dist(w.players[0].pos);
        // ln-quantisation of 0.1 is at most a 5% error, plus a 1-degree direction.
        assert!(v.ball.pos.dist(w.ball.pos) < 0.06 * d + d * 1f64.to_radians());
        assert!(v.ball.vel.dist(w.ball.vel) < 0.2);
        let seen_d = v.ball.pos.dist(v.own().pos);
        assert!((seen_d * 10.0 - (seen_d * 10.0).round()).abs() < 1e-6);
        assert_eq!(v.own().pos, w.players[0].pos);
    }

    #[test]
    fn player_id_rejects_out_of_range() {
        assert!(PlayerId::try_from(5u8).is_err());
        assert!(PlayerId::taker(2).is_none());
        assert_eq!(PlayerId::taker(1).map(PlayerId::index), Some(4));
    }
}
