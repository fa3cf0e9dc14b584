//! Holding the ball (the framework's `holdBall`).

use super::kick::kick_ball_close_to_body;
use super::movement::turn_body_to_point;
use crate::keepaway::command::Command;
use crate::keepaway::geometry::{Vec2, normalize_deg};
use crate::keepaway::params::KeepawayConfig;
use crate::keepaway::perception::PlayerView;
use crate::keepaway::world::Side;

/// The point a holder turns to once the ball is in place: the framework turns to
/// the opponent goal of a full pitch, 52.5 m away along its own attacking
/// direction, i.e. towards +x for the keepers (the server's left team) and -x for
/// the takers (who play from the right).
pub fn hold_facing_point(side: Side) -> Vec2 {
    match side {
        Side::Keepers => Vec2::new(52.5, 0.0),
        Side::Takers => Vec2::new(-52.5, 0.0),
    }
}

/// Keep the ball within reach for one cycle, shielding it from the opponent
/// closest to the ball.
///
/// If that opponent is within `hold_opponent_radius` (5 m) of the ball, the ball's
/// spot is at ±45 degrees from the line opponent-to-me, on the side away from where
/// the opponent's body points; otherwise it is straight in front of the body. The
/// spot lies `player_size + ball_size + ratio x kickable_margin` from where one will
/// be next cycle (0.875 m for the keepers' ratio 0.7). If the ball is already within
/// `hold_tolerance` (0.3 m) of the spot and will stay within 0.85 x kickable
/// distance, turn towards [`hold_facing_point`]; otherwise kick the ball to the spot
/// (or stop it if one kick cannot).
///
/// Decision: the framework tests "already there" against a point at distance
/// `ratio` (not the spot's distance) and in a direction mixing relative and global
/// angles; this implementation tests against the spot itself, which is what the
/// framework's comments describe.
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
    let me_next = me.pos + me.vel;
    let dist = sp.player_size + sp.ball_size + sp.kickable_margin * ratio;
    let spot = me_next + Vec2::polar(dist, me.body + ang_rel);
    if view.ball.pos.dist(spot) < cfg.skills.hold_tolerance {
        let ball_next = view.ball.pos + view.ball.vel;
        if ball_next.dist(me_next) < 0.85 * sp.kickable_distance() {
            return turn_body_to_point(view, cfg, hold_facing_point(view.side()), 1);
        }
    }
    kick_ball_close_to_body(view, cfg, ang_rel, ratio)
}
