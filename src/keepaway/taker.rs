//! The takers' fixed policy (the framework's `KeepawayPlayer::taker`).

use super::command::Command;
use super::params::KeepawayConfig;
use super::perception::PlayerView;
use super::skills::{hold_ball, intercept, turn_to_ball};

/// A taker's command for this cycle:
/// 1. if the ball is kickable and this taker is the taker closest to the ball, hold
///    it (with the takers' hold ratio 0.3: the ball kept 0.595 m away);
/// 2. if the player closest to the ball is a fellow taker who has it kickable, turn
///    to the ball;
/// 3. otherwise intercept. (The framework's marking rule for a third taker does not
///    arise in 3 vs 2: both takers go for the ball.)
///
/// Ties in distance go to the lower player index.
pub fn taker_command(view: &PlayerView, cfg: &KeepawayConfig) -> Command {
    let me = view.me.index();
    let ball = view.ball.pos;
    let dist = |i: usize| view.players[i].pos.dist(ball);
    let closest_of = |it: &mut dyn Iterator<Item = usize>| {
        it.fold(None::<(usize, f64)>, |best, i| {
            let d = dist(i);
            match best {
                Some((_, bd)) if bd <= d => best,
                _ => Some((i, d)),
            }
        })
    };
    let my_side = view.side().indices();
    if view.ball_kickable(cfg) && closest_of(&mut my_side.clone()).map(|c| c.0) == Some(me) {
        return hold_ball(view, cfg, cfg.skills.taker_hold_ratio);
    }
    if let Some((closest, d)) = closest_of(&mut (0..view.players.len()))
        && closest != me
        && my_side.contains(&closest)
        && d < cfg.server.kickable_distance()
    {
        return turn_to_ball(view, cfg);
    }
    intercept(view, cfg)
}
