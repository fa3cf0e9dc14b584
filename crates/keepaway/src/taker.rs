//! The takers' fixed policy (the framework's `KeepawayPlayer::taker`).

use super::command::Command;
use super::params::KeepawayConfig;
use super::skills::{InterceptMemory, hold_ball, intercept, turn_to_ball};
use super::view::PlayerView;
use super::world_model::believed;
use serde::{Deserialize, Serialize};

/// A taker's memory between cycles: the interception skill's.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct TakerMemory {
    /// The interception skill's memory.
    pub intercept: InterceptMemory,
}

/// A taker's command for this cycle, from what it believes (`believed`):
/// 1. if the ball is kickable and this taker is the taker closest to the ball, hold
///    it (`holdBall` with the takers' ratio 0.3: the ball kept 0.595 m away);
/// 2. if the player closest to the ball is a fellow taker who has it within the
///    kickable distance, turn to the ball ("don't mess with it");
/// 3. otherwise intercept (`intercept`, with its close interception and its memory
///    of the last interception point).
///
/// The framework's marking rule for a third taker does not arise in 3 vs 2: both
/// takers go for the ball. Its search for a lost ball does not arise either (with
/// 360-degree vision the ball is never lost, see [`super::world_model`]). Ties in
/// distance go to the first in the framework's
/// iteration order: the viewer's teammates (itself included) by index, then the
/// opponents.
pub fn taker_command(view: &PlayerView, cfg: &KeepawayConfig, memory: &mut TakerMemory) -> Command {
    let view = &believed(view, cfg);
    let me = view.me.index();
    let ball = view.ball.pos;
    let closest_of = |it: &mut dyn Iterator<Item = usize>| {
        it.fold(None::<(usize, f64)>, |best, i| {
            let d = view.players[i].pos.dist(ball);
            match best {
                Some((_, bd)) if bd <= d => best,
                _ => Some((i, d)),
            }
        })
    };
    let mates = view.side().indices();
    if view.ball_kickable(cfg) && closest_of(&mut mates.clone()).map(|c| c.0) == Some(me) {
        return hold_ball(view, cfg, cfg.skills.taker_hold_ratio);
    }
    let mut players = mates.clone().chain(view.side().opponent().indices());
    if let Some((closest, d)) = closest_of(&mut players)
        && closest != me
        && mates.contains(&closest)
        && d < cfg.server.kickable_distance()
    {
        return turn_to_ball(view, cfg);
    }
    intercept(view, cfg, &mut memory.intercept)
}
