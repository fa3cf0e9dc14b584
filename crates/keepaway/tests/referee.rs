//! The keepaway referee: end conditions, the possession counter, the reset.

use crate::{noiseless, players_in_a_row};
use learnpnp_keepaway::referee::{Referee, TURNOVER_TIME};
use learnpnp_keepaway::world::NUM_PLAYERS;
use learnpnp_keepaway::{Command, EndReason, FieldState, KeepawayConfig, RefereeRule, Simulator, Vec2};

/// Everybody at rest in a row far from the ball at the origin.
fn quiet_world() -> FieldState {
    players_in_a_row(-8.0, 4.0, 8.0)
}

const NONE: [Command; NUM_PLAYERS] = [Command::None; NUM_PLAYERS];

#[test]
fn ball_out_in_x_and_in_y() {
    for vel in [
        Vec2::new(0.5, 0.0),
        Vec2::new(-0.5, 0.0),
        Vec2::new(0.0, 0.5),
        Vec2::new(0.0, -0.5),
    ] {
        let mut sim = Simulator::new(noiseless(), 1).expect("valid config");
        let mut w = quiet_world();
        w.ball.pos = vel.with_norm(9.8);
        w.ball.vel = vel;
        sim.set_field(w);
        assert_eq!(sim.step(&NONE), Some(EndReason::Out), "ball moving {vel:?}");
        assert_eq!(sim.episode_cycles(), 1);
        assert!((sim.episode_seconds() - 0.1).abs() < 1e-12);
        // Ended episodes stay ended until reset.
        assert_eq!(sim.step(&NONE), Some(EndReason::Out));
        assert_eq!(sim.episode_cycles(), 1);
    }
    // The boundary itself is out (|x| >= 10), just inside is not.
    let c = noiseless();
    let mut w = quiet_world();
    w.ball.pos = Vec2::new(10.0, 0.0);
    assert_eq!(Referee::default().check(&w, &c), Some(EndReason::Out));
    w.ball.pos = Vec2::new(0.0, -10.0);
    assert_eq!(Referee::default().check(&w, &c), Some(EndReason::Out));
    w.ball.pos = Vec2::new(9.999, -9.999);
    assert_eq!(Referee::default().check(&w, &c), None);
}

#[test]
fn taken_after_four_cycles_of_taker_possession() {
    let c = noiseless();
    let mut w = quiet_world();
    w.players[3].pos = Vec2::new(1.0, 0.0); // a taker within 1.085 of the ball
    let mut r = Referee::default();
    for k in 1..=TURNOVER_TIME {
        assert_eq!(r.check(&w, &c), None, "check {k}");
        assert_eq!(r.take_count, k);
    }
    // The server tests the counter before updating it: the episode ends at the
    // first check after four consecutive cycles of possession.
    assert_eq!(r.check(&w, &c), Some(EndReason::Taken));

    // Through the simulator: a taker standing by a resting ball.
    let mut sim = Simulator::new(c, 2).expect("valid config");
    sim.set_field(w);
    let mut ends = Vec::new();
    for _ in 0..6 {
        ends.push(sim.step(&NONE));
    }
    assert_eq!(ends[..4], [None; 4]);
    assert_eq!(ends[4], Some(EndReason::Taken));
    assert_eq!(sim.episode_cycles(), 5);
}

#[test]
fn a_taker_beats_a_keeper() {
    let c = noiseless();
    let mut w = quiet_world();
    w.players[0].pos = Vec2::new(-0.8, 0.0); // keeper within reach
    w.players[4].pos = Vec2::new(0.8, 0.0); // taker within reach
    let mut r = Referee::default();
    assert_eq!(r.check(&w, &c), None);
    assert_eq!(r.take_count, 1);
}

#[test]
fn counter_reset_by_a_lone_keeper_and_kept_when_nobody_is_near() {
    let c = noiseless();
    let mut taker_near = quiet_world();
    taker_near.players[3].pos = Vec2::new(0.0, 1.0);
    let mut keeper_near = quiet_world();
    keeper_near.players[1].pos = Vec2::new(0.0, -1.0);
    let nobody = quiet_world();

    let mut r = Referee::default();
    for _ in 0..3 {
        assert_eq!(r.check(&taker_near, &c), None);
    }
    assert_eq!(r.take_count, 3);
    assert_eq!(r.check(&nobody, &c), None);
    assert_eq!(r.take_count, 3, "unchanged when nobody is near");
    assert_eq!(r.check(&keeper_near, &c), None);
    assert_eq!(r.take_count, 0, "reset by a lone keeper");
    // Three more cycles of taker possession are then not enough.
    for _ in 0..3 {
        assert_eq!(r.check(&taker_near, &c), None);
    }
    assert_eq!(r.check(&nobody, &c), None);
    assert_eq!(r.take_count, 3);
}

#[test]
fn rcssserver_9_4_5_takes_after_five_cycles() {
    let c = KeepawayConfig {
        referee: RefereeRule::Rcssserver9_4_5,
        ..noiseless()
    };
    assert_eq!(RefereeRule::Rcssserver11.turnover_time(), TURNOVER_TIME);
    assert_eq!(c.referee.turnover_time(), 5);
    let mut w = quiet_world();
    w.players[3].pos = Vec2::new(1.0, 0.0);
    let mut r = Referee::default();
    for k in 1..=5 {
        assert_eq!(r.check(&w, &c), None, "check {k}");
    }
    assert_eq!(r.check(&w, &c), Some(EndReason::Taken));
}

#[test]
fn cycle_limit() {
    let c = KeepawayConfig {
        max_episode_cycles: Some(3),
        ..noiseless()
    };
    let mut sim = Simulator::new(c, 3).expect("valid config");
    sim.set_field(quiet_world());
    assert_eq!(sim.step(&NONE), None);
    assert_eq!(sim.step(&NONE), None);
    assert_eq!(sim.step(&NONE), Some(EndReason::CycleLimit));
}

#[test]
fn reset_distribution() {
    let c = KeepawayConfig::default();
    let mut sim = Simulator::new(c, 4).expect("valid config");
    let in_range = |v: f64, lo: f64, hi: f64| v >= lo && v <= hi;
    // Corners 0: bottom-left, 1: bottom-right, 2: top-right.
    let corner_of = |p: Vec2| -> Option<usize> {
        let low = |v: f64| in_range(v, -10.0, -7.0);
        let high = |v: f64| in_range(v, 7.0, 10.0);
        if low(p.x) && low(p.y) {
            Some(0)
        } else if high(p.x) && low(p.y) {
            Some(1)
        } else if high(p.x) && high(p.y) {
            Some(2)
        } else {
            None
        }
    };
    let mut rotations = [0usize; 3];
    for _ in 0..300 {
        sim.reset();
        let w = sim.field();
        assert_eq!(w.cycle, 0);
        assert_eq!(w.ball.pos, Vec2::new(-6.0, -6.0));
        assert_eq!(w.ball.vel, Vec2::ZERO);
        let mut corners = [false; 3];
        let mut first = None;
        for (k, p) in w.players[..3].iter().enumerate() {
            let corner = corner_of(p.pos).unwrap_or_else(|| panic!("keeper {k} at {:?}", p.pos));
            assert!(!corners[corner], "two keepers in corner {corner}");
            corners[corner] = true;
            // Keepers take consecutive corners.
            let start = *first.get_or_insert(corner);
            assert_eq!(corner, (start + k) % 3);
            assert_eq!(p.vel, Vec2::ZERO);
            assert!(in_range(p.body, -180.0, 180.0));
        }
        rotations[first.unwrap_or(0)] += 1;
        for t in &w.players[3..] {
            assert!(
                in_range(t.pos.x, -10.0, -7.0) && in_range(t.pos.y, 7.0, 10.0),
                "taker at {:?}",
                t.pos
            );
            assert_eq!(t.vel, Vec2::ZERO);
        }
        // Offsets are drawn per player.
        assert_ne!(w.players[3].pos, w.players[4].pos);
    }
    assert!(rotations.iter().all(|&n| n > 50), "rotations {rotations:?}");
}
