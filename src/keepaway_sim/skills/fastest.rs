//! Who gets to the ball first, as the framework's world model decides it
//! (`createInterceptFeatures`, `getFastestInSetTo` and `predictNrCyclesToObject`).

use super::predict::{Estimate, Kinematics, ball_pos_after, cycles_to_point};
use crate::keepaway_sim::geometry::Vec2;
use crate::keepaway_sim::params::KeepawayConfig;
use crate::keepaway_sim::perception::PlayerView;

/// The framework's "unknown" cycle count (`predictNrCyclesToObject` gives 101 for a
/// player more than 40 m from the ball, or for no player at all).
pub(crate) const UNKNOWN_CYCLES: u32 = 101;

/// Cycles for player `j` of `view` to reach `target`: the viewer's own estimate is
/// simulated to the end, every other player's extrapolated ([`Estimate`]).
pub(crate) fn cycles_of(view: &PlayerView, j: usize, target: Vec2, cfg: &KeepawayConfig) -> u32 {
    let whose = if j == view.me.index() {
        Estimate::Own
    } else {
        Estimate::Other
    };
    cycles_to_point(&Kinematics::from(&view.players[j]), target, whose, cfg)
}

/// Whether player `j` could possibly reach `target` within `cycles` (the
/// framework's cut-off: distance over top speed below `cycles + 1`).
fn may_reach(view: &PlayerView, j: usize, target: Vec2, cycles: f64, cfg: &KeepawayConfig) -> bool {
    view.players[j].pos.dist(target) / cfg.server.player_speed_max < cycles + 1.0
}

/// The player among `candidates` who reaches a standing object at `target` first,
/// with its cycles (`getFastestInSetTo` for a position, velocity 0): candidates
/// whose distance over top speed is not below the best count so far are skipped;
/// ties go to the earlier candidate. `None` (the framework's illegal object) if
/// every candidate was skipped.
pub(crate) fn fastest_to_point(
    view: &PlayerView,
    candidates: impl IntoIterator<Item = usize>,
    target: Vec2,
    cfg: &KeepawayConfig,
) -> Option<(usize, u32)> {
    let mut best: Option<(usize, u32)> = None;
    let mut min = 100u32;
    for j in candidates {
        if j < view.players.len() && view.players[j].pos.dist(target) / cfg.server.player_speed_max < f64::from(min) {
            let c = cycles_of(view, j, target, cfg);
            if c < min {
                min = c;
                best = Some((j, c));
            }
        }
    }
    best
}

/// The viewer's teammate (itself included) fastest to the ball: the framework's
/// `FEATURE_FASTEST_TEAMMATE_TO_BALL`, as `createInterceptFeatures` finds it.
///
/// For `i = 0, 1, ...` up to the interception horizon (30 cycles), the ball's
/// position after `i` cycles is predicted and every player who may reach it in
/// `i` cycles gets an estimate (`cycles_of`; teammates first, then opponents,
/// ties to the earlier). At the first `i` at which a teammate's estimate is at
/// most `i`, that teammate is the fastest. If an opponent's estimate is at most
/// `i` first, the fastest teammate is the one fastest to that point, where the
/// opponent will have stopped the ball (`fastest_to_point`). At the horizon the
/// teammate of the last estimate made stands; `None` if there never was one.
pub fn fastest_teammate(view: &PlayerView, cfg: &KeepawayConfig) -> Option<usize> {
    let horizon = cfg.skills.intercept_horizon.min(1000);
    let mates = view.side().indices();
    let opponents = view.side().opponent().indices();
    let mut fastest_mate = None;
    for i in 0..=horizon {
        let target = ball_pos_after(&view.ball, i, &cfg.server);
        let (mut min_mate, mut min_opp) = (100u32, 100u32);
        let cycles = f64::from(i);
        for j in mates.clone() {
            if may_reach(view, j, target, cycles, cfg) {
                let c = cycles_of(view, j, target, cfg);
                if c < min_mate {
                    min_mate = c;
                    fastest_mate = Some(j);
                }
            }
        }
        if i == horizon || min_mate <= i {
            return fastest_mate;
        }
        for j in opponents.clone() {
            if may_reach(view, j, target, cycles, cfg) {
                min_opp = min_opp.min(cycles_of(view, j, target, cfg));
            }
        }
        if min_opp <= i {
            return fastest_to_point(view, mates, target, cfg).map(|(j, _)| j);
        }
    }
    fastest_mate
}

/// Cycles for player `j` (not the viewer) to reach the ball, as the framework's
/// `predictNrCyclesToObject` counts them: [`UNKNOWN_CYCLES`] beyond 40 m; for a
/// ball at rest, the cycles to where it lies; otherwise, following the ball cycle
/// by cycle (up to the interception horizon, or until it stops) and re-estimating
/// whenever the player may reach it, the last estimate once the ball's cycles
/// exceed it. The viewer's own count comes from its interception features in the
/// framework, which keeper support (the only caller) never asks for.
pub(crate) fn cycles_to_ball(view: &PlayerView, j: usize, cfg: &KeepawayConfig) -> u32 {
    let Some(p) = view.players.get(j) else {
        return UNKNOWN_CYCLES;
    };
    let ball = &view.ball;
    if p.pos.dist(ball.pos) > 40.0 {
        return UNKNOWN_CYCLES;
    }
    if ball.vel.norm() < 0.01 {
        return cycles_of(view, j, ball.pos, cfg);
    }
    let horizon = cfg.skills.intercept_horizon.min(1000);
    let mut i = 0u32;
    let mut to_obj = 100u32;
    let mut prev = Vec2::new(-1000.0, -1000.0);
    let mut at = Vec2::ZERO;
    while i <= to_obj && i < horizon && at.dist(prev) > 1e-4 {
        i += 1;
        prev = at;
        at = ball_pos_after(ball, i, &cfg.server);
        if may_reach(view, j, at, f64::from(i), cfg) {
            to_obj = cycles_of(view, j, at, cfg);
        }
    }
    to_obj
}

/// Where a supporting keeper expects the next pass to come from (the framework's
/// `keeperSupport`): the ball's predicted position when the fastest teammate
/// `fastest` gets it (`cycles_to_ball`).
pub fn pass_origin(view: &PlayerView, fastest: Option<usize>, cfg: &KeepawayConfig) -> Vec2 {
    let cycles = fastest.map_or(UNKNOWN_CYCLES, |j| cycles_to_ball(view, j, cfg));
    ball_pos_after(&view.ball, cycles, &cfg.server)
}
