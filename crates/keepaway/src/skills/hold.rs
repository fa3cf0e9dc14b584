//! Holding the ball (the framework's `holdBall`).

use super::kick::kick_ball_close_to_body;
use super::predict::{Kinematics, after_command, turn_to_point};
use crate::command::Command;
use crate::geometry::{Vec2, normalize_deg};
use crate::params::KeepawayConfig;
use crate::view::PlayerView;
use crate::world::Side;

/// The point a holder turns to once the ball is in place: the framework turns to
/// the opponent goal of a full pitch, 52.5 m away along its own attacking
/// direction, i.e. towards +x for the keepers (the server's left team) and -x for
/// the takers (who play from the right).
pub(crate) fn hold_facing_point(side: Side) -> Vec2 {
    match side {
        Side::Keepers => Vec2::new(52.5, 0.0),
        Side::Takers => Vec2::new(-52.5, 0.0),
    }
}

/// Keep the ball within reach for one cycle, shielding it from the opponent
/// closest to the ball (the framework's `holdBall(ratio)`).
///
/// If that opponent is within `hold_opponent_radius` (5 m) of the ball, the ball's
/// spot is at ±45 degrees from the line opponent-to-me, on the side away from where
/// the opponent's body points; otherwise it is straight in front of the body. The
/// spot lies `player_size + ball_size + ratio x kickable_margin` from where one will
/// be next cycle (0.875 m for the keepers' ratio 0.7), and the ball is kicked there
/// (`kick_ball_close_to_body`), unless it is already in place: then the holder
/// turns towards `hold_facing_point`, provided the ball will still be within
/// 0.85 x the kickable distance after the turn.
///
/// "In place", as the framework writes it, means within `hold_tolerance` (0.3 m) of
/// the point `ratio` metres from one's current position in the direction of the
/// spot's angle relative to the body, read as a direction of one's own frame (see
/// `Side::frame_dir`): not the spot itself. The two agree when the holder faces
/// its own direction 0, which the turn brings about.
pub fn hold_ball(view: &PlayerView, cfg: &KeepawayConfig, ratio: f64) -> Command {
    let sp = &cfg.server;
    let me = view.own();
    let closest = view
        .opponents()
        .map(|(_, o)| (o, o.pos.dist(view.ball.pos)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let mut ang_rel = 0.0;
    if let Some((opp, d)) = closest
        && d < cfg.skills.hold_opponent_radius
    {
        let away = (me.pos - opp.pos).dir();
        let sign = if normalize_deg(opp.body - away) > 0.0 {
            -1.0
        } else {
            1.0
        };
        ang_rel = normalize_deg(away + sign * 45.0 - me.body);
    }
    let in_place = me.pos + Vec2::polar(ratio, view.side().frame_dir() + ang_rel);
    if view.ball.pos.dist(in_place) < cfg.skills.hold_tolerance {
        let k = Kinematics::from(me);
        let turn = turn_to_point(&k, hold_facing_point(view.side()), 1, sp);
        let ball_next = view.ball.pos + view.ball.vel;
        if ball_next.dist(after_command(&k, turn, sp).pos) < 0.85 * sp.kickable_distance() {
            return turn;
        }
    }
    kick_ball_close_to_body(view, cfg, ang_rel, ratio)
}
