//! The keepaway referee: episode end conditions and the field reset.

use super::geometry::Vec2;
use super::params::KeepawayConfig;
use super::world::{Ball, FieldState, NUM_KEEPERS, Player, Side};
use crate::rng::SimRng;
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// Consecutive cycles of taker possession that end an episode under the
/// default rule (the server's `TURNOVER_TIME`;
/// [`super::params::RefereeRule::turnover_time`] gives each rule's).
pub const TURNOVER_TIME: u32 = 4;

/// Why an episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum EndReason {
    /// The ball left the region.
    Out,
    /// A taker held the ball for the rule's turnover time (4 cycles by default).
    Taken,
    /// The configured safety cap on the episode length was reached.
    CycleLimit,
}

/// The referee's memory: the taker-possession counter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Referee {
    /// Consecutive cycles (so far) in which a taker had the ball within kickable distance.
    pub take_count: u32,
}

impl Referee {
    /// The server's check after each cycle's movement, in its order:
    /// 1. the ball is outside the region (`|x| >= L/2` or `|y| >= W/2`): [`EndReason::Out`];
    /// 2. the counter has reached the rule's turnover time
    ///    ([`super::params::RefereeRule::turnover_time`], 4 by default): [`EndReason::Taken`];
    /// 3. otherwise the counter is updated: +1 if any taker is within the kickable
    ///    distance of the ball (a taker beats a keeper), reset to 0 if only keepers
    ///    are, unchanged if nobody is.
    ///
    /// As in rcssserver's `KeepawayRef::analyse`, the counter is tested before this
    /// cycle's update, so an episode ends at the first check after a taker has held
    /// the ball for 4 consecutive cycles (the 5th check; 5 and the 6th under
    /// rcssserver 9.4.5's rule).
    pub fn check(&mut self, world: &FieldState, cfg: &KeepawayConfig) -> Option<EndReason> {
        if !cfg.region.contains(world.ball.pos) {
            return Some(EndReason::Out);
        }
        if self.take_count >= cfg.referee.turnover_time() {
            return Some(EndReason::Taken);
        }
        let kick_sq = cfg.server.kickable_distance().powi(2);
        let near = |i: usize| world.players[i].pos.dist_sq(world.ball.pos) < kick_sq;
        if Side::Takers.indices().any(near) {
            self.take_count += 1;
        } else if Side::Keepers.indices().any(near) {
            self.take_count = 0;
        }
        if let Some(limit) = cfg.max_episode_cycles
            && world.cycle >= limit
        {
            return Some(EndReason::CycleLimit);
        }
        None
    }
}

/// Places everything for a new episode, as the server's `KeepawayRef::resetField`:
/// a random rotation `r` in `0..3` gives keeper `i` corner `(r + i) mod 3` of
/// bottom-left `(-L/2 + U[0,3], -W/2 + U[0,3])`, bottom-right
/// `(L/2 - U[0,3], -W/2 + U[0,3])` and top-right `(L/2 - U[0,3], W/2 - U[0,3])`;
/// every taker goes to the remaining top-left corner `(-L/2 + U[0,3], W/2 - U[0,3])`
/// (each player draws its own offsets); the ball goes to `(-L/2 + 4, -W/2 + 4)`
/// (`(-6, -6)`) at rest; all velocities are zero; the cycle counter restarts.
///
/// The server leaves body directions as they were at the end of the previous
/// episode, which is effectively arbitrary; here they are drawn uniformly in
/// `[-180, 180)` so that one episode from a seed stands for a typical one.
pub(crate) fn reset_world(world: &mut FieldState, cfg: &KeepawayConfig, rng: &mut SimRng) {
    let hl = cfg.region.half_length();
    let hw = cfg.region.half_width();
    let mut corner = rng.random_range(0..NUM_KEEPERS);
    let u3 = |rng: &mut SimRng| 3.0 * rng.random::<f64>();
    for i in 0..world.players.len() {
        let pos = match Side::of(i) {
            Side::Keepers => {
                let p = match corner {
                    0 => Vec2::new(-hl + u3(rng), -hw + u3(rng)),
                    1 => Vec2::new(hl - u3(rng), -hw + u3(rng)),
                    _ => Vec2::new(hl - u3(rng), hw - u3(rng)),
                };
                corner = (corner + 1) % NUM_KEEPERS;
                p
            }
            Side::Takers => Vec2::new(-hl + u3(rng), hw - u3(rng)),
        };
        let body = 360.0 * rng.random::<f64>() - 180.0;
        world.players[i] = Player {
            pos,
            vel: Vec2::ZERO,
            body,
        };
    }
    world.ball = Ball {
        pos: Vec2::new(-hl + 4.0, -hw + 4.0),
        vel: Vec2::ZERO,
    };
    world.cycle = 0;
}
