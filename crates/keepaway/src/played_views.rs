//! Test support: the players' views of played episodes, and arbitrary
//! views, the situations in which the simulator's pruned searches are
//! compared with exhaustive ones; and those comparisons (here, so that the
//! searches' own modules need not import the episodes that use them).

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

/// The pruned searches give what the exhaustive ones give, in the views of
/// played episodes and in arbitrary views.
mod pruning {
    use super::*;
    use crate::skills::fastest::tests::assert_pruning_changes_nothing;
    use crate::skills::fastest::{
        BallEstimates, fastest_teammate, fastest_teammate_with, pass_origin, pass_origin_with,
    };
    use crate::skills::intercept::{InterceptMemory, intercept_close, search_interception};
    use crate::world_model::fastest_opponent;
    use crate::world_model::tests::fastest_opponent_exhaustive;

    /// Pruning the fastest-teammate search and the cycles to the ball changes
    /// no answer: in every
    /// keeper's and taker's view of every cycle of 40 episodes, with the ball's
    /// velocity (a pass, a deflection) and the players' velocities (up to
    /// beyond the top speed) perturbed at random.
    #[test]
    fn pruning_changes_no_fastest_teammate() {
        let cfg = KeepawayConfig::default();
        let mut rng = crate::rng::seeded(13);
        let mut checked = 0;
        for_each_view(cfg, 0..40, &every_player(), |seed, mut view| {
            perturb_velocities(&mut view, &mut rng);
            if let Err(e) = assert_pruning_changes_nothing(&view, &cfg) {
                panic!("seed {seed}, cycle {}, player {:?}: {e}", view.cycle, view.me);
            }
            checked += 1;
        });
        assert!(checked > 8000, "{checked} views");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// The same over arbitrary views: players and ball anywhere in 60 m x
        /// 60 m, any velocities up to twice the top speeds, any bodies, any
        /// horizon up to 40.
        #[test]
        fn pruning_changes_no_fastest_teammate_anywhere(
            view in arbitrary_view(),
            horizon in 0u32..40,
        ) {
            let mut cfg = KeepawayConfig::default();
            cfg.skills.intercept_horizon = horizon;
            proptest::prop_assert_eq!(assert_pruning_changes_nothing(&view, &cfg), Ok(()));
        }
    }

    /// One memo shared by the fastest teammate and the pass origin gives what
    /// each computes afresh, in every keeper's view of 20 episodes.
    #[test]
    fn shared_estimates_change_nothing() {
        let cfg = KeepawayConfig::default();
        let mut views = 0;
        for_each_view(cfg, 0..20, &PlayerId::KEEPERS, |_, view| {
            let mut memo = BallEstimates::default();
            let fastest = fastest_teammate_with(&view, &cfg, &mut memo);
            assert_eq!(fastest, fastest_teammate(&view, &cfg));
            for j in [fastest, Some(0), Some(1), Some(2)] {
                let shared = pass_origin_with(&view, j, &cfg, &mut memo);
                assert_eq!(shared, pass_origin(&view, j, &cfg));
            }
            views += 1;
        });
        assert!(views > 1000, "{views} views");
    }

    /// Pruning the fastest-opponent search changes no answer: in every
    /// player's view of every cycle of 40 episodes, with the ball's velocity
    /// (a pass, a deflection) and the players' velocities (up to beyond the top
    /// speed) perturbed at random, and a random set of opponents known.
    #[test]
    fn pruning_changes_no_fastest_opponent() {
        let cfg = KeepawayConfig::default();
        let mut rng = crate::rng::seeded(11);
        let (mut checked, mut found) = (0, 0);
        for_each_view(cfg, 0..40, &every_player(), |seed, mut view| {
            perturb_velocities(&mut view, &mut rng);
            let known: [bool; NUM_PLAYERS] = std::array::from_fn(|_| rng.random::<f64>() < 0.9);
            let pruned = fastest_opponent(&view, |j| known[j], &cfg);
            assert_eq!(
                pruned,
                fastest_opponent_exhaustive(&view, |j| known[j], &cfg),
                "seed {seed}, cycle {}, player {:?}",
                view.cycle,
                view.me
            );
            checked += 1;
            found += usize::from(pruned.is_some());
        });
        assert!(checked > 8000 && found > checked / 2, "{checked} views, {found} found");
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(2000))]
        /// The same over arbitrary views: players and ball anywhere in 60 m x
        /// 60 m, any velocities up to twice the top speeds, any bodies, any
        /// horizon up to 40.
        #[test]
        fn pruning_changes_no_fastest_opponent_anywhere(
            view in arbitrary_view(),
            known in proptest::array::uniform5(proptest::bool::weighted(0.9)),
            horizon in 0u32..40,
        ) {
            let mut cfg = KeepawayConfig::default();
            cfg.skills.intercept_horizon = horizon;
            proptest::prop_assert_eq!(
                fastest_opponent(&view, |j| known[j], &cfg),
                fastest_opponent_exhaustive(&view, |j| known[j], &cfg)
            );
        }
    }

    /// The pruning of the interception search (points the viewer cannot reach,
    /// or that can change no choice, are not simulated) changes no decision:
    /// over every player's view of every cycle of 60 episodes, with the ball's
    /// velocity perturbed at random (a pass, a deflection) and a remembered
    /// interception point near the ball half the time, the pruned and the
    /// exhaustive search give the same command and leave the same memory.
    #[test]
    fn pruning_changes_no_interception_decision() {
        let cfg = KeepawayConfig::default();
        let mut rng = crate::rng::seeded(7);
        let (mut checked, mut commanded) = (0, 0);
        for_each_view(cfg, 0..60, &every_player(), |seed, mut view| {
            let kick = Vec2::polar(rng.random_range(0.0..2.7), rng.random_range(-180.0..180.0));
            if rng.random::<f64>() < 0.5 {
                view.ball.vel = kick;
            }
            let memory = if rng.random::<f64>() < 0.5 {
                InterceptMemory {
                    point: Some(
                        view.ball.pos + Vec2::polar(rng.random_range(0.0..3.0), rng.random_range(-180.0..180.0)),
                    ),
                    cycle: view.cycle.checked_sub(rng.random_range(0..4)),
                }
            } else {
                InterceptMemory::default()
            };
            let close = intercept_close(&view, &cfg);
            let (mut pruned, mut exhaustive) = (memory, memory);
            let a = search_interception(&view, &cfg, || close, &mut pruned, true);
            let b = search_interception(&view, &cfg, || close, &mut exhaustive, false);
            assert_eq!(a, b, "seed {seed}, cycle {}, player {:?}", view.cycle, view.me);
            assert_eq!(pruned, exhaustive);
            checked += 1;
            commanded += usize::from(a.is_some());
        });
        assert!(
            checked > 12_000 && commanded > checked / 2,
            "{checked} views, {commanded} commands"
        );
    }
}
