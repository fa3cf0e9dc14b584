//! Intercepting the ball.

use super::movement::turn_to_ball;
use super::predict::{Interception, Kinematics, fastest_to_ball, move_command_towards, rollout_pos};
use crate::keepaway::command::Command;
use crate::keepaway::params::KeepawayConfig;
use crate::keepaway::perception::PlayerView;

/// The earliest point where the viewer can reach the ball (see
/// [`fastest_to_ball`] with the viewer as the only candidate).
pub fn own_interception(view: &PlayerView, cfg: &KeepawayConfig) -> Option<Interception> {
    let me = view.me.index();
    fastest_to_ball(view, std::iter::once(me), cfg)
}

/// Move to a known interception point `at`, to be reached in `at.cycles` cycles:
/// if one would come to rest within 0.5 m of it anyway, just face the ball;
/// otherwise turn or dash as [`move_command_towards`] decides, with the dash power
/// that arrives in time rather than early.
///
/// Decision: where the framework then turns the body to the global direction 0, this
/// implementation turns to the ball, which serves the next kick better.
pub fn intercept_at(view: &PlayerView, cfg: &KeepawayConfig, at: &Interception) -> Command {
    let sp = &cfg.server;
    let me = Kinematics::from(view.own());
    if at.cycles == 0 || rollout_pos(&me, at.cycles.min(4), sp).dist(at.point) < 0.5 {
        return turn_to_ball(view, cfg);
    }
    move_command_towards(&me, at.point, at.cycles, cfg.skills.intercept_dist_back, sp)
}

/// Intercept the ball: predict its decaying motion, find the earliest cycle at
/// which one can reach it (turning first where needed, then running at full
/// power), and move there.
///
/// Decision: the framework adds a special "close intercept" for balls reachable
/// within two cycles and prefers interception points near the previous one; here
/// the earliest reachable point is always taken.
pub fn intercept(view: &PlayerView, cfg: &KeepawayConfig) -> Command {
    match own_interception(view, cfg) {
        Some(at) => intercept_at(view, cfg, &at),
        None => turn_to_ball(view, cfg),
    }
}
