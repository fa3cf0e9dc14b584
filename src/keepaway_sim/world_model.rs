//! What a player believes about the ball, from its view: the framework's world
//! model (UvA Trilearn's `WorldModel::calculateStateBall`) corrects the seen ball
//! velocity before any skill uses it.
//!
//! A [`PlayerView`] is what the server tells a player; `believed` is what the
//! framework's player then works with. The keepers and takers of this crate apply
//! it at the start of every decision ([`super::keeper::keeper_command`],
//! [`super::taker::taker_command`], the plan-driven keepers' world).

use super::geometry::Vec2;
use super::params::KeepawayConfig;
use super::perception::PlayerView;

/// The view as the framework's world model holds it after a see message:
/// - a ball within the kickable distance of an opponent (strictly closer), while
///   not within one's own, is taken to stand still ("opponent has it": the
///   opponent will stop or keep it, so its roll-out is no target);
/// - a ball seen faster than `(1 + ball_rand) x ball_speed_max` is slowed to
///   `ball_speed_max`.
///
/// Where this differs from the framework's player, and why:
/// - views here arrive every cycle; the framework's 360-degree see messages come
///   every 150 ms (1.5 cycles), and its world model predicts the cycles between
///   (`updateDynamicObjectForNextCycle`, which stops the ball in the same way,
///   and moves the opponent fastest to the ball 0.3 m towards it), and its
///   estimates count the cycles since the last see (`predictNrCyclesToPoint`);
/// - the players do not talk: the framework's keepers and takers say where the
///   ball and the closest opponent are, which adds nothing to views of the whole
///   field every cycle;
/// - the world model's filtering of noisy velocity estimates and its own
///   localisation are not modelled (full-state views need neither; quantised
///   views are taken as they come, see [`super::perception::perceive`]);
/// - its other corrections concern goalie catches and set plays, which keepaway
///   does not have.
pub(crate) fn believed(view: &PlayerView, cfg: &KeepawayConfig) -> PlayerView {
    let sp = &cfg.server;
    let reach = sp.kickable_distance();
    let ball = view.ball.pos;
    let mut out = *view;
    if view.opponents().any(|(_, o)| o.pos.dist(ball) < reach) && view.own().pos.dist(ball) > reach {
        out.ball.vel = Vec2::ZERO;
    } else if view.ball.vel.norm() > (1.0 + sp.ball_rand) * sp.ball_speed_max {
        out.ball.vel = view.ball.vel.with_norm(sp.ball_speed_max);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::keepaway_sim::perception::{PlayerId, SeenBall, SeenPlayer};

    fn view(me: usize, ball: Vec2, taker: Vec2) -> PlayerView {
        let mut players = [SeenPlayer::default(); 5];
        for (i, p) in players.iter_mut().enumerate() {
            p.pos = Vec2::new(10.0 * i as f64 - 20.0, 8.0);
        }
        players[3].pos = taker;
        PlayerView {
            cycle: 0,
            me: PlayerId::new(me).expect("valid id"),
            ball: SeenBall {
                pos: ball,
                vel: Vec2::new(1.0, 0.0),
            },
            players,
        }
    }

    #[test]
    fn a_ball_an_opponent_controls_stands_still() {
        let cfg = KeepawayConfig::default();
        // Keeper 0 far away, taker 3 next to the ball: the keeper takes it as still.
        let v = view(0, Vec2::new(0.5, 0.0), Vec2::ZERO);
        assert_eq!(believed(&v, &cfg).ball.vel, Vec2::ZERO);
        // The taker itself sees the ball move (no opponent has it).
        let t = view(3, Vec2::new(0.5, 0.0), Vec2::ZERO);
        assert_eq!(believed(&t, &cfg).ball.vel, t.ball.vel);
        // Out of the taker's reach: the ball moves.
        let far = view(0, Vec2::new(2.0, 0.0), Vec2::ZERO);
        assert_eq!(believed(&far, &cfg).ball.vel, far.ball.vel);
    }
}
