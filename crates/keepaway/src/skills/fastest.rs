//! Who gets to the ball first, as the framework's world model decides it
//! (`createInterceptFeatures`, `getFastestInSetTo` and `predictNrCyclesToObject`).

use super::predict::{Estimate, Kinematics, Mover, RunBound, ball_pos_after, cycles_to_point, cycles_to_point_from};
use crate::geometry::Vec2;
use crate::params::KeepawayConfig;
use crate::view::PlayerView;
use crate::world::NUM_PLAYERS;

/// The framework's "unknown" cycle count (`predictNrCyclesToObject` gives 101 for a
/// player more than 40 m from the ball, or for no player at all).
pub(crate) const UNKNOWN_CYCLES: u32 = 101;

/// Cycles for player `j` of `view` to reach `target`: the viewer's own estimate is
/// simulated to the end, every other player's extrapolated ([`Estimate`]).
pub(crate) fn cycles_of(view: &PlayerView, j: usize, target: Vec2, cfg: &KeepawayConfig) -> u32 {
    cycles_to_point(&Kinematics::from(&view.players[j]), target, whose(view, j), cfg)
}

/// Cycle estimates kept for one view: how many cycles player `j` needs to reach
/// where the ball will be after `i` cycles, for the first
/// [`BallEstimates::CYCLES`] values of `i`, and each player's starting state.
/// The fastest teammate and the pass origin ask for many of the same
/// estimates, and the world model's fastest opponent for many of one player's;
/// each is computed once.
///
/// Valid for one view only: make a new one (or [`BallEstimates::clear`] it) when
/// the view changes.
#[derive(Clone, Debug)]
pub struct BallEstimates {
    cycles: [[u32; BallEstimates::CYCLES]; NUM_PLAYERS],
    /// Each player as a [`Mover`], made at its first estimate.
    movers: [Option<Mover>; NUM_PLAYERS],
}

impl Default for BallEstimates {
    fn default() -> Self {
        BallEstimates {
            cycles: [[Self::UNSET; Self::CYCLES]; NUM_PLAYERS],
            movers: [None; NUM_PLAYERS],
        }
    }
}

impl BallEstimates {
    /// Ball cycles kept (the interception horizon, 30, and a little more).
    pub const CYCLES: usize = 40;
    const UNSET: u32 = u32::MAX;

    /// Forgets every estimate (a new view).
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// [`cycles_of`] player `j` to the ball's predicted position after `i` cycles.
    pub(crate) fn cycles_to_ball_after(&mut self, view: &PlayerView, j: usize, i: u32, cfg: &KeepawayConfig) -> u32 {
        let at = usize::try_from(i).ok().filter(|&i| i < Self::CYCLES);
        if let Some(c) = at.and_then(|i| self.cycles.get(j).map(|row| row[i]))
            && c != Self::UNSET
        {
            return c;
        }
        let c = self.cycles_to(view, j, ball_pos_after(&view.ball, i, &cfg.server), cfg);
        if let Some(slot) = at.and_then(|i| self.cycles.get_mut(j).map(|row| &mut row[i])) {
            *slot = c;
        }
        c
    }

    /// [`cycles_of`] player `j` to `target`, with `j`'s [`Mover`] made once.
    pub(crate) fn cycles_to(&mut self, view: &PlayerView, j: usize, target: Vec2, cfg: &KeepawayConfig) -> u32 {
        let (Some(player), Some(slot)) = (view.players.get(j), self.movers.get_mut(j)) else {
            return cycles_of(view, j, target, cfg);
        };
        let mover = *slot.get_or_insert_with(|| Mover::new(&Kinematics::from(player)));
        cycles_to_point_from(mover, target, whose(view, j), cfg)
    }
}

/// Whose estimate player `j`'s is in `view`: the viewer's own is simulated to
/// the end, every other player's extrapolated ([`Estimate`]).
fn whose(view: &PlayerView, j: usize) -> Estimate {
    if j == view.me.index() {
        Estimate::Own
    } else {
        Estimate::Other
    }
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
/// every candidate was skipped. `estimate(j)` is player `j`'s cycles to `target`.
fn fastest_to_point(
    view: &PlayerView,
    candidates: impl IntoIterator<Item = usize>,
    target: Vec2,
    cfg: &KeepawayConfig,
    mut estimate: impl FnMut(usize) -> u32,
) -> Option<(usize, u32)> {
    let mut best: Option<(usize, u32)> = None;
    let mut min = 100u32;
    for j in candidates {
        if j < view.players.len() && view.players[j].pos.dist(target) / cfg.server.player_speed_max < f64::from(min) {
            let c = estimate(j);
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
    fastest_teammate_with(view, cfg, &mut BallEstimates::default())
}

/// [`fastest_teammate`], keeping its estimates in `memo` (made for this view).
///
/// Only the estimates that can decide are made: at each `i` before the
/// horizon, those of the players who could possibly arrive within `i` cycles
/// (a run bound; any other estimates more than `i`, so can neither end the
/// search nor be the fewest where it ends); at the horizon, the teammates' of
/// the last `i` at which any was estimated, found from the horizon down. A test
/// compares this with the framework's search, every estimate made.
pub fn fastest_teammate_with(view: &PlayerView, cfg: &KeepawayConfig, memo: &mut BallEstimates) -> Option<usize> {
    let sp = &cfg.server;
    let horizon = cfg.skills.intercept_horizon.min(1000);
    let reach = sp.kickable_distance();
    let mates = view.side().indices();
    let opponents = view.side().opponent().indices();
    let mut bounds = view.players.map(|p| RunBound::new(p.vel));
    for i in 0..horizon {
        let target = ball_pos_after(&view.ball, i, sp);
        let cycles = f64::from(i);
        let may_arrive = |j: usize| {
            may_reach(view, j, target, cycles, cfg)
                && bounds[j].is_none_or(|b| b.may_arrive(view.players[j].pos.dist(target), reach))
        };
        if let Some((j, c)) = fastest_among(mates.clone().filter(|&j| may_arrive(j)), |j| {
            memo.cycles_to_ball_after(view, j, i, cfg)
        }) && c <= i
        {
            return Some(j);
        }
        if opponents
            .clone()
            .filter(|&j| may_arrive(j))
            .any(|j| memo.cycles_to_ball_after(view, j, i, cfg) <= i)
        {
            return fastest_to_point(view, mates, target, cfg, |j| memo.cycles_to_ball_after(view, j, i, cfg))
                .map(|(j, _)| j);
        }
        for b in bounds.iter_mut().flatten() {
            b.advance(sp);
        }
    }
    (0..=horizon).rev().find_map(|i| {
        let target = ball_pos_after(&view.ball, i, sp);
        fastest_among(
            mates.clone().filter(|&j| may_reach(view, j, target, f64::from(i), cfg)),
            |j| memo.cycles_to_ball_after(view, j, i, cfg),
        )
        .map(|(j, _)| j)
    })
}

/// The candidate with the fewest `cycles`, under 100 (ties to the first), and
/// its cycles; `None` if there is none.
pub(crate) fn fastest_among(
    candidates: impl Iterator<Item = usize>,
    mut cycles: impl FnMut(usize) -> u32,
) -> Option<(usize, u32)> {
    let mut fastest = None;
    let mut min = 100u32;
    for j in candidates {
        let c = cycles(j);
        if c < min {
            min = c;
            fastest = Some((j, c));
        }
    }
    fastest
}

/// Cycles for player `j` (not the viewer) to reach the ball, as the framework's
/// `predictNrCyclesToObject` counts them: [`UNKNOWN_CYCLES`] beyond 40 m; for a
/// ball at rest, the cycles to where it lies; otherwise, following the ball cycle
/// by cycle (up to the interception horizon, or until it stops) and re-estimating
/// whenever the player may reach it, the last estimate once the ball's cycles
/// exceed it. The viewer's own count comes from its interception features in the
/// framework, which keeper support (the only caller) never asks for.
///
/// An estimate the player cannot meet within its `i` cycles ([`RunBound`]) is
/// not made while it only keeps the search going: it is made if the search
/// ends on it, or goes on past the cycle after it without a new estimate.
pub(crate) fn cycles_to_ball(view: &PlayerView, j: usize, cfg: &KeepawayConfig, memo: &mut BallEstimates) -> u32 {
    let Some(p) = view.players.get(j) else {
        return UNKNOWN_CYCLES;
    };
    let ball = &view.ball;
    if p.pos.dist(ball.pos) > 40.0 {
        return UNKNOWN_CYCLES;
    }
    if ball.vel.norm() < 0.01 {
        return memo.cycles_to(view, j, ball.pos, cfg);
    }
    let sp = &cfg.server;
    let reach = sp.kickable_distance();
    let horizon = cfg.skills.intercept_horizon.min(1000);
    let mut bound = RunBound::new(p.vel);
    let mut i = 0u32;
    let mut to_obj = 100u32;
    // The `i` of the last estimate, if it was not made (it is more than `i`).
    let mut skipped: Option<u32> = None;
    let mut prev = Vec2::new(-1000.0, -1000.0);
    let mut at = Vec2::ZERO;
    loop {
        if let Some(s) = skipped.filter(|&s| i > s + 1) {
            to_obj = memo.cycles_to_ball_after(view, j, s, cfg);
            skipped = None;
        }
        if !((skipped.is_some() || i <= to_obj) && i < horizon && at.dist(prev) > 1e-4) {
            break;
        }
        i += 1;
        prev = at;
        at = ball_pos_after(ball, i, sp);
        if let Some(b) = &mut bound {
            b.advance(sp);
        }
        if may_reach(view, j, at, f64::from(i), cfg) {
            if bound.is_none_or(|b| b.may_arrive(p.pos.dist(at), reach)) {
                to_obj = memo.cycles_to_ball_after(view, j, i, cfg);
                skipped = None;
            } else {
                skipped = Some(i);
            }
        }
    }
    skipped.map_or(to_obj, |s| memo.cycles_to_ball_after(view, j, s, cfg))
}

/// Where a supporting keeper expects the next pass to come from (the framework's
/// `keeperSupport`): the ball's predicted position when the fastest teammate
/// `fastest` gets it (`cycles_to_ball`).
pub fn pass_origin(view: &PlayerView, fastest: Option<usize>, cfg: &KeepawayConfig) -> Vec2 {
    pass_origin_with(view, fastest, cfg, &mut BallEstimates::default())
}

/// [`pass_origin`], with the estimates kept in `memo` (made for this view).
pub fn pass_origin_with(
    view: &PlayerView,
    fastest: Option<usize>,
    cfg: &KeepawayConfig,
    memo: &mut BallEstimates,
) -> Vec2 {
    let cycles = fastest.map_or(UNKNOWN_CYCLES, |j| cycles_to_ball(view, j, cfg, memo));
    ball_pos_after(&view.ball, cycles, &cfg.server)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The framework's search for the fastest teammate, every estimate made
    /// (what [`fastest_teammate_with`] prunes).
    fn fastest_teammate_exhaustive(view: &PlayerView, cfg: &KeepawayConfig) -> Option<usize> {
        let horizon = cfg.skills.intercept_horizon.min(1000);
        let mates = view.side().indices();
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
            for j in view.side().opponent().indices() {
                if may_reach(view, j, target, cycles, cfg) {
                    min_opp = min_opp.min(cycles_of(view, j, target, cfg));
                }
            }
            if min_opp <= i {
                return fastest_to_point(view, mates, target, cfg, |j| cycles_of(view, j, target, cfg)).map(|(j, _)| j);
            }
        }
        fastest_mate
    }

    /// The framework's `predictNrCyclesToObject`, every estimate made (what
    /// `cycles_to_ball` prunes).
    fn cycles_to_ball_exhaustive(view: &PlayerView, j: usize, cfg: &KeepawayConfig) -> u32 {
        let ball = &view.ball;
        if view.players[j].pos.dist(ball.pos) > 40.0 {
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

    /// [`fastest_teammate_exhaustive`] and [`cycles_to_ball_exhaustive`] for
    /// every player agree with the pruned searches in `view`.
    pub(crate) fn assert_pruning_changes_nothing(view: &PlayerView, cfg: &KeepawayConfig) -> Result<(), String> {
        let fastest = fastest_teammate(view, cfg);
        let want = fastest_teammate_exhaustive(view, cfg);
        if fastest != want {
            return Err(format!("fastest teammate {fastest:?}, exhaustively {want:?}"));
        }
        let mut memo = BallEstimates::default();
        let _ = fastest_teammate_with(view, cfg, &mut memo);
        for j in 0..view.players.len() {
            let got = cycles_to_ball(view, j, cfg, &mut memo);
            let want = cycles_to_ball_exhaustive(view, j, cfg);
            if got != want {
                return Err(format!("player {j}: {got} cycles to the ball, exhaustively {want}"));
            }
        }
        Ok(())
    }
}
