//! Test support: the players' views of played episodes, and arbitrary
//! views, the situations in which the simulator's pruned searches are
//! compared with exhaustive ones.

use std::ops::Range;

use rand::RngExt;

use super::episode::Keepaway;
use super::geometry::Vec2;
use super::params::KeepawayConfig;
use super::perception::perceive;
use super::policies::BaselinePolicy;
use super::view::{PlayerId, PlayerView, SeenBall, SeenPlayer};
use super::world::NUM_PLAYERS;
use crate::rng::SimRng;

/// Every player, keepers first.
pub(crate) fn every_player() -> Vec<PlayerId> {
    (0..NUM_PLAYERS).filter_map(PlayerId::new).collect()
}

/// Calls `check(seed, view)` with each of `players`' views of every cycle
/// of the episodes with `seeds`, played by random keepers under `cfg`.
pub(crate) fn for_each_view(
    cfg: KeepawayConfig,
    seeds: Range<u64>,
    players: &[PlayerId],
    mut check: impl FnMut(u64, PlayerView),
) {
    for seed in seeds {
        let mut game = Keepaway::new(cfg, seed).expect("valid config");
        let mut policy = BaselinePolicy::random(seed);
        while game.step(&mut policy).is_none() {
            for &id in players {
                check(seed, perceive(game.simulator().field(), id, &cfg));
            }
        }
    }
}

/// Perturbs `view` at random: the ball's velocity half the time (a pass, a
/// deflection), each player's 30% of the time (up to beyond the top speed).
pub(crate) fn perturb_velocities(view: &mut PlayerView, rng: &mut SimRng) {
    if rng.random::<f64>() < 0.5 {
        view.ball.vel = Vec2::polar(rng.random_range(0.0..2.7), rng.random_range(-180.0..180.0));
    }
    for p in &mut view.players {
        if rng.random::<f64>() < 0.3 {
            p.vel = Vec2::polar(rng.random_range(0.0..1.5), rng.random_range(-180.0..180.0));
        }
    }
}

/// Arbitrary views: the players and the ball anywhere in 60 m x 60 m, any
/// velocities up to twice the top speeds, any bodies, any viewer.
pub(crate) fn arbitrary_view() -> impl proptest::strategy::Strategy<Value = PlayerView> {
    use proptest::array::{uniform5, uniform6};
    use proptest::strategy::Strategy;
    (
        0..NUM_PLAYERS,
        uniform6(-30.0..30.0f64),
        uniform6(-30.0..30.0f64),
        uniform6(0.0..2.0f64),
        uniform6(-180.0..180.0f64),
        uniform5(-180.0..180.0f64),
        0.0..5.4f64,
    )
        .prop_map(|(me, xs, ys, speeds, headings, bodies, ball_speed)| PlayerView {
            cycle: 0,
            me: PlayerId::new(me).expect("valid id"),
            ball: SeenBall {
                pos: Vec2::new(xs[NUM_PLAYERS], ys[NUM_PLAYERS]),
                vel: Vec2::polar(ball_speed, headings[NUM_PLAYERS]),
            },
            players: std::array::from_fn(|i| SeenPlayer {
                pos: Vec2::new(xs[i], ys[i]),
                vel: Vec2::polar(speeds[i], headings[i]),
                body: bodies[i],
            }),
        })
}
