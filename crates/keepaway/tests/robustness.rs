//! No panics and no stalls on any input: arbitrary commands, arbitrary views.

use learnpnp_keepaway::features::{FeatureThresholds, observe};
use learnpnp_keepaway::keeper::{KeeperMemory, keeper_command};
use learnpnp_keepaway::skills::{InterceptMemory, get_open, go_to_point, hold_ball, intercept, turn_to_ball};
use learnpnp_keepaway::state_vars::StateVars;
use learnpnp_keepaway::taker::{TakerMemory, taker_command};
use learnpnp_keepaway::view::{PlayerId, SeenBall, SeenPlayer};
use learnpnp_keepaway::world::NUM_PLAYERS;
use learnpnp_keepaway::{
    BaselinePolicy, Command, FieldState, KeepawayConfig, PlayerView, Simulator, Vec2, VisionMode, perceive,
};
use proptest::prelude::*;

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -30.0..30.0f64,
        1 => any::<f64>(),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(0.0),
    ]
}

fn any_vec() -> impl Strategy<Value = Vec2> {
    (any_f64(), any_f64()).prop_map(|(x, y)| Vec2::new(x, y))
}

fn any_command() -> impl Strategy<Value = Command> {
    prop_oneof![
        Just(Command::None),
        (any_f64(), any_f64()).prop_map(|(power, direction)| Command::Kick { power, direction }),
        any_f64().prop_map(|power| Command::Dash { power }),
        any_f64().prop_map(|moment| Command::Turn { moment }),
    ]
}

fn any_player() -> impl Strategy<Value = SeenPlayer> {
    (any_vec(), any_vec(), any_f64()).prop_map(|(pos, vel, body)| SeenPlayer { pos, vel, body })
}

fn any_view() -> impl Strategy<Value = PlayerView> {
    (
        0..NUM_PLAYERS,
        any::<u32>(),
        any_vec(),
        any_vec(),
        proptest::array::uniform5(any_player()),
    )
        .prop_map(|(me, cycle, pos, vel, players)| PlayerView {
            cycle,
            me: PlayerId::new(me).unwrap_or_else(|| unreachable!()),
            ball: SeenBall { pos, vel },
            players,
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn simulator_survives_any_commands(
        seed in any::<u64>(),
        cmds in proptest::collection::vec(proptest::array::uniform5(any_command()), 1..40),
    ) {
        let mut sim = Simulator::new(KeepawayConfig::default(), seed).expect("valid config");
        for c in &cmds {
            if sim.step(c).is_some() {
                sim.reset();
            }
            let w = sim.field();
            prop_assert!(w.ball.pos.is_finite() && w.ball.vel.is_finite());
            for p in &w.players {
                prop_assert!(p.pos.is_finite() && p.vel.is_finite() && p.body.is_finite());
                prop_assert!(p.body > -180.0 && p.body <= 180.0);
            }
        }
    }

    #[test]
    fn skills_survive_any_view(view in any_view()) {
        let cfg = KeepawayConfig::default();
        let _ = intercept(&view, &cfg, &mut InterceptMemory::default());
        let _ = hold_ball(&view, &cfg, 0.7);
        let _ = get_open(&view, &cfg);
        let _ = go_to_point(&view, &cfg, Vec2::new(1.0, 2.0));
        let _ = turn_to_ball(&view, &cfg);
        let _ = taker_command(&view, &cfg, &mut TakerMemory::default());
        let _ = StateVars::from_view(&view);
        let _ = observe(&view, &FeatureThresholds::default());
        let mut memory = KeeperMemory::default();
        for mut policy in [BaselinePolicy::HandCoded, BaselinePolicy::threshold(), BaselinePolicy::random(1)] {
            let _ = keeper_command(&view, &cfg, &mut memory, &mut policy);
        }
    }

    #[test]
    fn perception_survives_any_world(view in any_view(), me in 0..NUM_PLAYERS) {
        let mut w = FieldState::default();
        w.ball.pos = view.ball.pos;
        w.ball.vel = view.ball.vel;
        for (p, s) in w.players.iter_mut().zip(view.players.iter()) {
            p.pos = s.pos;
            p.vel = s.vel;
            p.body = s.body;
        }
        let cfg = KeepawayConfig { vision: VisionMode::Quantised, ..KeepawayConfig::default() };
        let id = PlayerId::new(me).unwrap_or_else(|| unreachable!());
        let v = perceive(&w, id, &cfg);
        prop_assert_eq!(v.me, id);
    }
}
