//! Intercepting the ball (the framework's `BasicPlayer::intercept`, with
//! `interceptClose`, `collideWithBall` and `WorldModel::predictCommandToInterceptBall`).

use super::predict::{
    Kinematics, Mover, after_command, after_turn, angle_for_turn, ball_pos_after, dash_to_point, move_command,
    pos_after, power_for_dash, turn_to_point,
};
use crate::command::Command;
use crate::geometry::{Vec2, normalize_deg};
use crate::params::{KeepawayConfig, ServerParams};
use crate::view::PlayerView;
use crate::world::Side;
use serde::{Deserialize, Serialize};

/// Half the pitch's length and width (105 m x 68 m), and the x of the penalty
/// line, in the framework's coordinates (its `PITCH_LENGTH`, `PITCH_WIDTH`,
/// `PENALTY_X`).
const HALF_PITCH_LENGTH: f64 = 52.5;
const HALF_PITCH_WIDTH: f64 = 34.0;
const PENALTY_X: f64 = HALF_PITCH_LENGTH - 16.5;

/// Whether `p` lies on the pitch less its 1 m margin (`isInField`).
fn in_field(p: Vec2) -> bool {
    p.x.abs() <= HALF_PITCH_LENGTH - 1.0 && p.y.abs() <= HALF_PITCH_WIDTH - 1.0
}

/// What an interceptor remembers between cycles: the interception point it chose
/// last, and when (the static variables of `predictCommandToInterceptBall`, one
/// set per player process). The point is forgotten when the player has not
/// intercepted for more than two cycles. Players here start every episode with
/// an empty memory; the framework's outlives the reset by up to two cycles, when
/// the ball has jumped to its start point and the old point no longer matters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct InterceptMemory {
    /// The interception point chosen at the last call.
    pub point: Option<Vec2>,
    /// The cycle of the last call.
    pub cycle: Option<u32>,
}

/// `collideWithBall`: a command after which the player overlaps the ball's next
/// position (the collision stops both), if the ball is close enough: first a turn
/// to the own-frame direction 0, else a dash to the ball's next position.
pub(crate) fn collide_with_ball(view: &PlayerView, cfg: &KeepawayConfig) -> Option<Command> {
    let sp = &cfg.server;
    let me = Kinematics::from(view.own());
    if me.pos.dist(view.ball.pos) > view.ball.vel.norm() + sp.player_speed_max {
        return None;
    }
    let ball1 = ball_pos_after(&view.ball, 1, sp);
    let radii = sp.ball_size + sp.player_size;
    let turn = turn_to_point(&me, me.pos + Vec2::polar(1.0, view.side().frame_dir()), 1, sp);
    if after_command(&me, turn, sp).pos.dist(ball1) < radii {
        return Some(turn);
    }
    let dash = dash_to_point(&me, ball1, 1, sp);
    (after_command(&me, dash, sp).pos.dist(ball1) < radii).then_some(dash)
}

/// The points where the line through `from` with direction `dir` crosses the circle
/// of radius `r` around `centre`, the one farther forward in `side`'s own frame
/// first (`Line::getCircleIntersectionPoints` orders a non-vertical line's
/// solutions by decreasing x, and `interceptClose` keeps the larger x; for a
/// vertical line, by decreasing y). A tangent line gives its touching point twice
/// (the framework's second point is then left unset).
fn line_circle(from: Vec2, dir: f64, centre: Vec2, r: f64, side: Side) -> Option<(Vec2, Vec2)> {
    let u = Vec2::polar(1.0, dir);
    let rel = from - centre;
    let b = u.dot(rel);
    let disc = b * b - (rel.norm_sq() - r * r);
    if disc.is_nan() || disc < 0.0 {
        return None;
    }
    let root = disc.sqrt();
    let (p, q) = (from + u * (-b + root), from + u * (-b - root));
    let (po, qo) = (side.own_frame(p), side.own_frame(q));
    let p_first = if u.x.abs() < 1e-4 { po.y >= qo.y } else { po.x >= qo.x };
    Some(if p_first { (p, q) } else { (q, p) })
}

/// `interceptClose`: a command that gets the ball within reach in one or two
/// cycles, if there is one.
///
/// The desired heading afterwards is the own-frame direction 0 (towards the
/// opponents' goal once past the penalty line less 5 m, which keepaway's region
/// never reaches). One dash is tried first, to the points of the body line at
/// `player_size + ball_size + kickable_margin / 6` from the ball's next position
/// (the farther-forward one first), then straight at it; it must end within
/// 0.95 x the kickable distance. Within 9.9 m of the ball (three cycles of the
/// player's and two of the ball's top speed, plus the kickable distance), the
/// framework then prefers, in order: that dash when an opponent is within 3 m;
/// turning to the heading when the ball stays within 0.8 x the kickable distance
/// after one turn, or after two (the first turn), ending within 25 degrees of it;
/// colliding with the ball, or stopping with a dash when that keeps the ball in
/// reach after two cycles, when the heading is more than 25 degrees off; then any
/// turn that keeps the ball in reach; then the dash. Farther away it turns to the
/// heading when the ball will be within 0.7 x the kickable distance after one or
/// two cycles anyway (without an opponent within 3 m), or collides, or dashes.
pub fn intercept_close(view: &PlayerView, cfg: &KeepawayConfig) -> Option<Command> {
    let sp = &cfg.server;
    let reach = sp.kickable_distance();
    let side = view.side();
    let me = Kinematics::from(view.own());
    let ball = &view.ball;
    let far = me.pos.dist(ball.pos) > 3.0 * sp.player_speed_max + (1.0 + sp.ball_decay) * sp.ball_speed_max + reach;
    let collide = collide_with_ball(view, cfg);
    let heading = if side.own_frame(me.pos).x > PENALTY_X - 5.0 {
        (super::hold::hold_facing_point(side) - me.pos).dir()
    } else {
        side.frame_dir()
    };
    let opp_close = view.opponents().any(|(_, o)| o.pos.dist(me.pos) < 3.0);
    let ang_turn = normalize_deg(heading - me.body);
    let pos1 = pos_after(&me, 1, 0.0, sp);
    let pos2 = pos_after(&me, 2, 0.0, sp);
    let ball1 = ball_pos_after(ball, 1, sp);
    let ball2 = ball_pos_after(ball, 2, sp);
    let turn_to_heading = |from: Vec2, cycles: u32| turn_to_point(&me, from + Vec2::polar(1.0, heading), cycles, sp);

    // One dash: to a point of the body line next to the ball, else straight at it.
    let mut dash1 = None;
    let r = sp.player_size + sp.ball_size + sp.kickable_margin / 6.0;
    if let Some((s1, s2)) = line_circle(pos1, me.body, ball1, r, side) {
        for s in [s1, s2] {
            let power = power_for_dash(s - me.pos, me.body, me.vel, 1, sp);
            // The framework predicts with the power truncated to an integer.
            if pos_after(&me, 1, power.trunc(), sp).dist(ball1) < 0.95 * reach {
                dash1 = Some(Command::Dash { power });
                break;
            }
        }
    }
    if dash1.is_none() {
        let dash = dash_to_point(&me, ball1, 1, sp);
        if after_command(&me, dash, sp).pos.dist(ball1) < 0.95 * reach {
            dash1 = Some(dash);
        }
    }

    if far {
        return if ang_turn.abs() > 25.0 && !opp_close && pos1.dist(ball1) < 0.7 * reach {
            Some(turn_to_heading(pos1, 1))
        } else if !opp_close && pos2.dist(ball2) < 0.7 * reach {
            Some(turn_to_heading(pos2, 2))
        } else if collide.is_some() && ang_turn.abs() > 25.0 {
            collide
        } else {
            dash1
        };
    }
    if opp_close && dash1.is_some() {
        return dash1;
    }
    let turn = turn_to_heading(pos1, 1);
    let mut keep_in_reach = None;
    let after1 = after_command(&me, turn, sp);
    if after1.pos.dist(ball1) < 0.8 * reach {
        keep_in_reach = Some(turn);
        if normalize_deg(heading - after1.body).abs() < 25.0 {
            return Some(turn);
        }
    }
    let ang = normalize_deg(heading - after1.body);
    let after2 = after_turn(&after1, angle_for_turn(ang, after1.vel.norm(), sp), sp);
    if after2.pos.dist(ball2) < 0.8 * reach {
        keep_in_reach = Some(turn);
        if normalize_deg(heading - after2.body).abs() < 25.0 {
            return Some(turn);
        }
    }
    if ang_turn.abs() > 25.0 {
        if collide.is_some() {
            return collide;
        }
        let stop = dash_to_point(&me, me.pos, 1, sp);
        if after_command(&me, stop, sp).pos.dist(ball2) < 0.8 * reach {
            return Some(stop);
        }
    }
    keep_in_reach.or(dash1)
}

/// `predictCommandToInterceptBall` for the viewer: the command towards its chosen
/// interception point, `None` for "already there" (the framework's illegal
/// command), with `close` giving the result of [`intercept_close`] (asked for
/// only when it can be the command).
///
/// For `i = 0, 1, ...` while `i` is within the interception horizon (30), at most
/// 20 past the first reachable cycle, and the ball on the pitch, the ball's
/// position after `i` cycles is predicted, and the viewer's `i` commands of
/// [`move_command`] towards it simulated; it is reachable if they end within the
/// kickable distance. Among the reachable points, the framework keeps one close
/// (within 1 m) to last cycle's interception point if the ball arrives there
/// faster than 0.6 m/cycle and would end within 0.7 x the kickable distance
/// (`iOldIntercept`), and tracks a "safer" point that ends closer to the ball
/// within 3 cycles of the best so far. It then moves to the old point unless
/// the safer one is more than 2 cycles earlier, otherwise to the first reachable
/// point. The chosen point is remembered. If it is less than 3 cycles away and a
/// close interception exists, that is the command; if one will roll to within
/// 0.5 m of it anyway, none; otherwise [`move_command`] towards it.
pub(crate) fn interception_command(
    view: &PlayerView,
    cfg: &KeepawayConfig,
    close: impl FnOnce() -> Option<Command>,
    memory: &mut InterceptMemory,
) -> Option<Command> {
    search_interception(view, cfg, close, memory, true)
}

/// [`interception_command`]; with `prune`, the runs to points that can change
/// no choice are not simulated (a test compares it with the exhaustive search).
pub(crate) fn search_interception(
    view: &PlayerView,
    cfg: &KeepawayConfig,
    close: impl FnOnce() -> Option<Command>,
    memory: &mut InterceptMemory,
    prune: bool,
) -> Option<Command> {
    let sp = &cfg.server;
    let reach = sp.kickable_distance();
    let back = cfg.skills.intercept_dist_back;
    let horizon = i64::from(cfg.skills.intercept_horizon.min(1000));
    let me = Kinematics::from(view.own());
    let mover = Mover::new(&me);
    let ball = &view.ball;
    if memory
        .cycle
        .is_none_or(|c| view.cycle.checked_sub(c).is_none_or(|d| d > 2))
    {
        memory.point = None;
    }
    memory.cycle = Some(view.cycle);
    let old_point = memory.point;

    const NONE: i64 = -1000;
    let (mut min_cycles, mut first) = (100i64, 100i64);
    let mut old_cycles = NONE;
    let (mut min_old_dist, mut intercept_dist) = (100.0f64, 10.0f64);
    let mut at = Vec2::ZERO;
    // An upper bound on how far the viewer can run in `i` cycles (each cycle's
    // displacement is at most the previous speed decayed plus one full dash,
    // capped at the top speed), used to skip points it cannot reach: skipping
    // them changes nothing, as an unreachable point changes no choice.
    let acc = sp.max_power * sp.dash_power_rate * sp.effort;
    let (mut step_bound, mut run_bound) = (me.vel.norm() / sp.player_decay, 0.0f64);
    let mut rolling = ball.vel;
    let mut i = 0i64;
    while i <= horizon && i <= first + 20 && in_field(at) {
        let n = u32::try_from(i).unwrap_or(0);
        if i > 0 {
            step_bound = (step_bound * sp.player_decay + acc).min(sp.player_speed_max);
            run_bound += step_bound;
        }
        // The ball's position after `i` cycles, and the velocity it arrived with.
        let ball_vel = if i == 0 {
            at = ball.pos;
            ball.vel
        } else {
            let v = rolling;
            at += v;
            rolling *= sp.ball_decay;
            v
        };
        let pred = pos_after(&me, n.min(4), 0.0, sp);
        if pred.dist(at) / sp.player_speed_max > i as f64 + reach || !in_field(at) {
            i += 1;
            continue;
        }
        // Once the first reachable point is known and no point close to the old
        // one has been taken, only a later such point could change the choice; if
        // none can come (no old point, or the ball already too slow, and it only
        // slows down), the choice is the first reachable point: stop.
        let ball_slows = (0.0..=1.0).contains(&sp.ball_decay);
        let old_impossible = old_point.is_none() || (ball_slows && ball_vel.norm() <= 0.6);
        if prune && min_cycles != 100 && old_cycles == NONE && old_impossible {
            break;
        }
        let near_old = old_point.map(|o| at.dist(o));
        let old_possible = near_old.is_some_and(|o| o < min_old_dist.min(1.0)) && ball_vel.norm() > 0.6;
        let safer_possible = intercept_dist > 0.5 * reach
            && (i <= min_cycles + 3 || i <= old_cycles + 3)
            && at.y.abs() < 32.0
            && at.x.abs() < 50.0;
        let unreachable = me.pos.dist(at) > run_bound + reach + 1e-9;
        if prune && (unreachable || (min_cycles != 100 && !old_possible && !safer_possible)) {
            // Nothing this point could change: skip simulating the run to it.
            i += 1;
            continue;
        }
        let Some(d) = run_to(mover, at, n, back, prune, sp) else {
            i += 1;
            continue;
        };
        if d < reach {
            if min_cycles == 100 {
                first = i;
                min_cycles = i;
            }
            if old_possible && d < 0.7 * reach {
                old_cycles = i;
                intercept_dist = d;
                min_old_dist = near_old.unwrap_or(min_old_dist);
            } else if safer_possible && d < intercept_dist {
                min_cycles = i;
                intercept_dist = d;
                if old_cycles == min_cycles - 1 {
                    old_cycles = min_cycles;
                }
            }
        }
        i += 1;
    }
    let chosen = if old_cycles != NONE && min_cycles <= old_cycles + 2 {
        old_cycles
    } else {
        first
    };
    let n = u32::try_from(chosen).unwrap_or(0);
    let point = ball_pos_after(ball, n, sp);
    memory.point = Some(point);
    let close = if chosen < 3 { close() } else { None };
    if close.is_some() {
        close
    } else if pos_after(&me, n.min(4), 0.0, sp).dist(point) < 0.5 {
        None
    } else {
        Some(move_command(&me, point, n, back, sp))
    }
}

/// The distance from `at` at which the viewer ends after `n` commands of
/// [`Mover::move_command`] towards it, each aiming to arrive in the cycles
/// left. With `prune`, `None` as soon as the point is out of reach: farther
/// than the cycles left at the player's [`Mover::step_limit`] (no cycle moves
/// it farther) plus the kickable distance, so the run could only end out of
/// reach.
fn run_to(mover: Mover, at: Vec2, n: u32, back: f64, prune: bool, sp: &ServerParams) -> Option<f64> {
    let out_of_reach = sp.kickable_distance() + 1e-9;
    let mut m = mover;
    for step in 0..n {
        // Squared: no square root of the distance on the run's critical path.
        let bound = f64::from(n - step) * m.step_limit(sp) + out_of_reach;
        if prune && m.pos().dist_sq(at) > bound * bound {
            return None;
        }
        m = m.after(m.move_command(at, n - step, back, sp), sp);
    }
    Some(m.pos().dist(at))
}

/// Intercept the ball (`intercept`, not as a goalie): the command of
/// `interception_command` given [`intercept_close`]; when there is none (already
/// where the ball will be), turn to the own-frame direction 0.
pub fn intercept(view: &PlayerView, cfg: &KeepawayConfig, memory: &mut InterceptMemory) -> Command {
    interception_command(view, cfg, || intercept_close(view, cfg), memory).unwrap_or_else(|| {
        let me = Kinematics::from(view.own());
        turn_to_point(&me, me.pos + Vec2::polar(1.0, view.side().frame_dir()), 1, &cfg.server)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_intersection_first() {
        let c = Vec2::new(2.0, 0.0);
        let (a, b) = line_circle(Vec2::ZERO, 0.0, c, 0.5, Side::Keepers).expect("crosses");
        assert!((a.x - 2.5).abs() < 1e-9 && (b.x - 1.5).abs() < 1e-9);
        // The takers' own frame is mirrored: their forward point is the smaller x.
        let (a, _) = line_circle(Vec2::ZERO, 0.0, c, 0.5, Side::Takers).expect("crosses");
        assert!((a.x - 1.5).abs() < 1e-9);
        assert!(line_circle(Vec2::ZERO, 90.0, c, 0.5, Side::Keepers).is_none());
    }

    #[test]
    fn in_field_is_the_pitch_less_a_metre() {
        assert!(in_field(Vec2::new(51.0, -32.5)));
        assert!(!in_field(Vec2::new(52.0, 0.0)));
    }
}
