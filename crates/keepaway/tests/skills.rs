//! Skills, views and abstractions on scripted situations (motion noise off).

use crate::{noiseless, player};
use learnpnp_keepaway::features::{FeatureThresholds, Observation, PassLineDistances, observe};
use learnpnp_keepaway::policies::{hand_coded, threshold_policy};
use learnpnp_keepaway::skills::get_open::{congestion, grid_points, in_cone, least_congested_point};
use learnpnp_keepaway::skills::pass::{PassState, teammates_by_distance};
use learnpnp_keepaway::skills::predict::{Estimate, Kinematics, cycles_to_point};
use learnpnp_keepaway::skills::{InterceptMemory, go_to_point, hold_ball, intercept};
use learnpnp_keepaway::state_vars::StateVars;
use learnpnp_keepaway::view::PlayerId;
use learnpnp_keepaway::world::{Ball, NUM_PLAYERS};
use learnpnp_keepaway::{
    Command, FieldState, KeepawayConfig, KeeperAction, PlayerView, Simulator, Vec2, VisionMode, perceive,
};

/// Keeper 0 at the origin with the ball in front; keepers 1, 2 at (6, 0) and (0, -8);
/// takers at (3, 4) and (-7, 7).
fn scene() -> FieldState {
    FieldState {
        ball: Ball {
            pos: Vec2::new(0.7, 0.0),
            vel: Vec2::ZERO,
        },
        players: [
            player(0.0, 0.0, 0.0),
            player(6.0, 0.0, 180.0),
            player(0.0, -8.0, 90.0),
            player(3.0, 4.0, -120.0),
            player(-7.0, 7.0, -45.0),
        ],
        cycle: 0,
    }
}

fn view(w: &FieldState, i: usize) -> PlayerView {
    perceive(w, PlayerId::new(i).expect("valid id"), &noiseless())
}

fn id(i: usize) -> PlayerId {
    PlayerId::new(i).expect("valid id")
}

#[test]
fn state_variables_of_a_known_scene() {
    let s = StateVars::from_view(&view(&scene(), 0)).expect("keeper view");
    assert_eq!(s.keepers, [0, 1, 2]);
    assert_eq!(s.takers, [3, 4]);
    let v = s.to_array();
    let expect = [
        0.0,
        6.0,
        8.0,
        5.0,
        98f64.sqrt(),
        6.0,
        8.0,
        5.0,
        98f64.sqrt(),
        5.0,             // K2 (6,0) to T1 (3,4)
        153f64.sqrt(),   // K3 (0,-8) to T1 (3,4), closer than T2 (-7,7) at sqrt(274)
        53.130102354156, // angle at K1 between (6,0) and (3,4)
        135.0,           // between (0,-8) and (-7,7); (3,4) is 143.13 degrees off
    ];
    for (k, (a, b)) in v.iter().zip(expect.iter()).enumerate() {
        assert!((a - b).abs() < 1e-6, "variable {k}: {a} vs {b}");
    }
    assert!(StateVars::from_view(&view(&scene(), 3)).is_none());
}

#[test]
fn hand_coded_and_threshold_choices() {
    let w = scene();
    let s = StateVars::from_view(&view(&w, 0)).expect("keeper view");
    // Closest taker at exactly 5 m: not > 5, so scores decide:
    // pass1 = 4 x 5 + 53.1 = 73.1, pass2 = 4 x 12.4 + 135 = 184.5 > hold 90.
    assert_eq!(hand_coded(&s), KeeperAction::Pass2);
    let d = PassLineDistances::from_view(&view(&w, 0)).expect("keeper view");
    assert_eq!(d.teammates, [1, 2]);
    assert!((d.closest_taker - 5.0).abs() < 1e-9);
    // Lane to (6,0): T1 (3,4) is 4 m off; lane to (0,-8): T1 is 5 m from its end (0,0).
    assert!((d.line[0] - 4.0).abs() < 1e-9 && (d.line[1] - 5.0).abs() < 1e-9);
    assert_eq!(threshold_policy(&d, 3.0), KeeperAction::Hold);
    assert_eq!(threshold_policy(&d, 6.0), KeeperAction::Pass2);
    let obs = d.observe(&FeatureThresholds {
        pass_line: 4.5,
        closest_taker: 4.0,
    });
    assert_eq!(
        obs,
        Observation {
            lane1_open: false,
            lane2_open: true,
            taker_far: true
        }
    );
    assert_eq!(obs.index(), 6);
    assert_eq!(Observation::from_index(6), Some(obs));
    assert_eq!(Observation::from_index(8), None);
    assert!(observe(&view(&w, 4), &FeatureThresholds::default()).is_none());
    let all: std::collections::BTreeSet<usize> = (0..8)
        .filter_map(Observation::from_index)
        .map(Observation::index)
        .collect();
    assert_eq!(all.len(), Observation::COUNT);
}

#[test]
fn teammates_sorted_by_distance() {
    let w = scene();
    assert_eq!(teammates_by_distance(&view(&w, 0)), [1, 2]);
    assert_eq!(teammates_by_distance(&view(&w, 2)), [0, 1]);
    assert_eq!(teammates_by_distance(&view(&w, 3))[0], 4);
}

#[test]
fn hold_keeps_the_ball_for_many_cycles() {
    let c = noiseless();
    let mut sim = Simulator::new(c, 1).expect("valid config");
    let mut w = scene();
    // Takers far away and standing still.
    w.players[3] = player(-8.0, 8.0, 0.0);
    w.players[4] = player(8.0, 8.0, 0.0);
    sim.set_field(w);
    for t in 0..100 {
        let v = view(sim.field(), 0);
        assert!(v.ball_kickable(&c), "lost the ball at cycle {t}");
        let mut cmds = [Command::None; NUM_PLAYERS];
        cmds[0] = hold_ball(&v, &c, c.skills.keeper_hold_ratio);
        assert_eq!(sim.step(&cmds), None);
    }
    // Settled: ball within the hold tolerance (0.3 m) of the spot 0.875 m in front
    // of the body, body facing +x (the framework's "opponent goal").
    let w = sim.field();
    let me = w.players[0];
    let spot = me.pos + Vec2::polar(0.875, me.body);
    assert!(w.ball.pos.dist(spot) < c.skills.hold_tolerance, "{w:?}");
    assert!(me.body.abs() < 1.0);
    assert!(w.ball.vel.norm() < 1e-9);
}

#[test]
fn hold_shields_the_ball_from_a_close_taker() {
    let c = noiseless();
    let mut w = scene();
    w.players[3] = player(2.5, 0.0, 180.0); // right in front, facing the keeper
    let v = view(&w, 0);
    match hold_ball(&v, &c, c.skills.keeper_hold_ratio) {
        Command::Kick { .. } => {}
        other => panic!("expected a kick, got {other:?}"),
    }
    let mut sim = Simulator::new(c, 1).expect("valid config");
    sim.set_field(w);
    let mut cmds = [Command::None; NUM_PLAYERS];
    cmds[0] = hold_ball(&v, &c, c.skills.keeper_hold_ratio);
    sim.step(&cmds);
    let b = sim.field().ball.pos;
    // The ball goes behind the keeper, away from the taker (x < 0), 0.875 m away.
    assert!(b.x < 0.0, "ball at {b:?}");
    assert!((b.norm() - 0.875).abs() < 1e-6);
}

#[test]
fn pass_reaches_the_receiver() {
    let c = noiseless();
    let mut sim = Simulator::new(c, 1).expect("valid config");
    let mut w = scene();
    w.players[3] = player(-8.0, 8.0, 0.0);
    w.players[4] = player(-8.0, -8.0, 0.0);
    w.players[1] = player(9.0, 0.0, 180.0);
    sim.set_field(w);
    // Keeper 1 at 9 m is the second closest (keeper 2 is 8 m away).
    let mut pass = PassState::new(2, &view(sim.field(), 0));
    let mut kicks = 0;
    loop {
        let v = view(sim.field(), 0);
        if !(kicks == 0 || pass.continues(&v, &c)) {
            break;
        }
        let mut cmds = [Command::None; NUM_PLAYERS];
        cmds[0] = pass.kick(&v, &c);
        sim.step(&cmds);
        kicks += 1;
        assert!(kicks < 5, "pass never left the kicker");
    }
    // Let the ball roll to the receiver (who stands still).
    let receiver = sim.field().players[1].pos;
    let mut best = f64::INFINITY;
    let mut speed_there = 0.0;
    for _ in 0..40 {
        let w = *sim.field();
        let d = w.ball.pos.dist(receiver);
        if d < best {
            best = d;
            speed_there = w.ball.vel.norm() / c.server.ball_decay;
        }
        sim.step(&[Command::None; NUM_PLAYERS]);
    }
    assert!(best < 1.085, "ball passed {best:.2} m from the receiver");
    assert!((0.6..=1.8).contains(&speed_there), "arrival speed {speed_there:.2}");
}

#[test]
fn intercept_runs_to_a_rolling_ball() {
    let c = noiseless();
    let mut sim = Simulator::new(c, 1).expect("valid config");
    let mut w = scene();
    w.players[0] = player(-5.0, -5.0, 90.0); // facing away from the ball's path
    w.players[3] = player(-8.0, 8.0, 0.0);
    w.players[4] = player(8.0, 8.0, 0.0);
    w.ball.pos = Vec2::new(-6.0, 2.0);
    w.ball.vel = Vec2::new(0.8, -0.2);
    sim.set_field(w);
    let mut memory = InterceptMemory::default();
    let first = intercept(&view(sim.field(), 0), &c, &mut memory);
    assert!(matches!(first, Command::Turn { .. }), "{first:?}");
    for t in 0..40 {
        let v = view(sim.field(), 0);
        if v.ball_kickable(&c) {
            assert!(t > 2);
            return;
        }
        let mut cmds = [Command::None; NUM_PLAYERS];
        cmds[0] = intercept(&v, &c, &mut memory);
        sim.step(&cmds);
    }
    panic!("never reached the ball");
}

#[test]
fn go_to_point_gets_there() {
    let c = noiseless();
    let mut sim = Simulator::new(c, 1).expect("valid config");
    let mut w = scene();
    w.players[2] = player(0.0, -8.0, -170.0);
    sim.set_field(w);
    let target = Vec2::new(-6.0, -2.0);
    for _ in 0..30 {
        let mut cmds = [Command::None; NUM_PLAYERS];
        cmds[2] = go_to_point(&view(sim.field(), 2), &c, target);
        sim.step(&cmds);
    }
    assert!(sim.field().players[2].pos.dist(target) < 1.0);
}

#[test]
fn get_open_avoids_blocked_lanes() {
    let c = noiseless();
    let w = scene();
    let v = view(&w, 1);
    let from = w.ball.pos;
    let p = least_congested_point(&v, &c, from);
    assert!(grid_points(&c).any(|g| g == p));
    for (_, t) in v.opponents() {
        assert!(!in_cone(t.pos, from, p, c.skills.pass_cone_width));
    }
    // No open grid point is less congested.
    let open = |g: Vec2| {
        !v.opponents()
            .any(|(_, t)| in_cone(t.pos, from, g, c.skills.pass_cone_width))
    };
    let best = congestion(&v, p);
    assert!(grid_points(&c).filter(|&g| open(g)).all(|g| congestion(&v, g) >= best));
}

#[test]
fn cycles_to_reach_a_point() {
    let c = noiseless();
    let at_rest = Kinematics {
        pos: Vec2::ZERO,
        vel: Vec2::ZERO,
        body: 0.0,
    };
    for whose in [Estimate::Own, Estimate::Other] {
        // Within reach: 0. Straight ahead 10 m (+1.085 reach): 10 to 11 cycles at 1 m/cycle.
        assert_eq!(cycles_to_point(&at_rest, Vec2::new(1.0, 0.0), whose, &c), 0);
        let ahead = cycles_to_point(&at_rest, Vec2::new(11.085, 0.0), whose, &c);
        assert!((10..=11).contains(&ahead), "{ahead}");
        // Behind: one more cycle to turn first.
        let behind = cycles_to_point(&at_rest, Vec2::new(-11.085, 0.0), whose, &c);
        assert_eq!(behind, ahead + 1);
    }
}

#[test]
fn views_serialise_and_reject_bad_ids() {
    let w = scene();
    let v = view(&w, 2);
    let bytes = bincode::serde::encode_to_vec(v, bincode::config::standard()).expect("encode");
    let (back, _): (PlayerView, usize) =
        bincode::serde::decode_from_slice(&bytes, bincode::config::standard()).expect("decode");
    assert_eq!(back, v);
    let cmd = Command::Kick {
        power: 55.0,
        direction: -20.0,
    };
    let bytes = bincode::serde::encode_to_vec(cmd, bincode::config::standard()).expect("encode");
    let (back, _): (Command, usize) =
        bincode::serde::decode_from_slice(&bytes, bincode::config::standard()).expect("decode");
    assert_eq!(back, cmd);
    let bad = bincode::serde::encode_to_vec(7u8, bincode::config::standard()).expect("encode");
    let r: Result<(PlayerId, usize), _> = bincode::serde::decode_from_slice(&bad, bincode::config::standard());
    assert!(r.is_err());
}

#[test]
fn quantised_views_are_close_to_the_truth() {
    let c = KeepawayConfig {
        vision: VisionMode::Quantised,
        ..noiseless()
    };
    let mut w = scene();
    w.ball.vel = Vec2::new(1.2, 0.4);
    w.players[3].vel = Vec2::new(-0.5, 0.3);
    for i in 0..NUM_PLAYERS {
        let v = perceive(&w, id(i), &c);
        assert_eq!(v.own().pos, w.players[i].pos);
        for (j, p) in v.players.iter().enumerate() {
            let d = w.players[j].pos.dist(w.players[i].pos);
            assert!(
                p.pos.dist(w.players[j].pos) <= 0.06 * d + 0.05,
                "player {j} seen by {i}"
            );
            assert!(p.vel.dist(w.players[j].vel) < 0.1 + 0.02 * d);
        }
        let d = w.ball.pos.dist(w.players[i].pos);
        assert!(v.ball.pos.dist(w.ball.pos) <= 0.06 * d + 0.05);
        assert!(v.ball.vel.dist(w.ball.vel) < 0.1 + 0.02 * d);
    }
}
