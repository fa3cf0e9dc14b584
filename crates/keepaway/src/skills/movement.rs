//! Turning and moving: turn to a point or the ball, dash to a point, go to a point.

use super::predict::{Kinematics, after_turn, angle_for_turn, final_pos, turn_to_point};
use crate::command::Command;
use crate::geometry::{Vec2, normalize_deg};
use crate::params::KeepawayConfig;
use crate::view::PlayerView;

/// Turn the body towards `point`, seen from where one will be after `cycles`
/// cycles of rolling (the framework's `turnBodyToPoint`); the moment compensates
/// for the inertia at the current speed.
pub(crate) fn turn_body_to_point(view: &PlayerView, cfg: &KeepawayConfig, point: Vec2, cycles: u32) -> Command {
    turn_to_point(&Kinematics::from(view.own()), point, cycles, &cfg.server)
}

/// Turn the body towards where the ball will be next cycle (`turnBodyToObject`).
pub fn turn_to_ball(view: &PlayerView, cfg: &KeepawayConfig) -> Command {
    let next = view.ball.pos + view.ball.vel;
    turn_body_to_point(view, cfg, next, 1)
}

/// Dash so as to cover the distance to `point` (projected on the body direction)
/// in `cycles` cycles (`dashToPoint`).
pub(crate) fn dash_to_point(view: &PlayerView, cfg: &KeepawayConfig, point: Vec2, cycles: u32) -> Command {
    super::predict::dash_to_point(&Kinematics::from(view.own()), point, cycles, &cfg.server)
}

/// Go to `point` (the framework's `moveToPos` with its defaults: no backward
/// dashing, one-cycle dash target): if the point, seen from where one comes to rest,
/// is within `when_to_turn_deg` (7 degrees) of the body direction, dash; otherwise
/// simulate the turns needed (`directTowards`): one or two, turn now (seen from two
/// cycles ahead); more (moving too fast to turn), brake first.
pub fn go_to_point(view: &PlayerView, cfg: &KeepawayConfig, point: Vec2) -> Command {
    let sp = &cfg.server;
    let when = cfg.skills.when_to_turn_deg;
    let me = Kinematics::from(view.own());
    let rest = final_pos(&me, sp);
    let ang_to = (point - rest).dir();
    let mut ang = normalize_deg(ang_to - me.body);
    if ang.abs() < when {
        return dash_to_point(view, cfg, point, 1);
    }
    let mut k = me;
    let mut turns = 0;
    while ang.abs() > when && turns < 5 {
        turns += 1;
        k = after_turn(&k, angle_for_turn(ang, k.vel.norm(), sp), sp);
        ang = normalize_deg(ang_to - k.body);
    }
    if turns <= 2 {
        turn_body_to_point(view, cfg, point, 2)
    } else {
        dash_to_point(view, cfg, me.pos, 1)
    }
}
