//! The server's physics against closed forms (motion noise off).

use crate::players_in_a_row;
use learnpnp_common::rng::seeded;
use learnpnp_keepaway::world::NUM_PLAYERS;
use learnpnp_keepaway::{Command, FieldState, ServerParams, Vec2};

const NONE: [Command; NUM_PLAYERS] = [Command::None; NUM_PLAYERS];

/// Players far apart and away from the origin, at rest, facing +x; ball at rest at the origin.
fn spread_world() -> FieldState {
    players_in_a_row(-40.0, 10.0, 30.0)
}

fn step(w: &mut FieldState, cmds: &[Command; NUM_PLAYERS]) {
    let mut rng = seeded(0);
    w.physics_step(cmds, &ServerParams::default(), false, &mut rng);
}

#[test]
fn full_speed_ball_travels_45_m() {
    let sp = ServerParams::default();
    let mut w = spread_world();
    // Two players right behind the ball kick it together: the accelerations add up
    // (about 2 x 2.6) and are capped at ball_accel_max = ball_speed_max = 2.7.
    w.players[0].pos = Vec2::new(-0.5, 0.0);
    w.players[1].pos = Vec2::new(-0.5, 0.1);
    w.players[1].body = (Vec2::ZERO - w.players[1].pos).dir();
    let mut cmds = NONE;
    cmds[0] = Command::Kick {
        power: 100.0,
        direction: 0.0,
    };
    cmds[1] = Command::Kick {
        power: 100.0,
        direction: -w.players[1].body,
    };
    step(&mut w, &cmds);
    let first = w.ball.pos.norm();
    assert!((first - 2.7).abs() < 1e-9, "first cycle moved {first}");
    let mut prev = w.ball.pos;
    let mut travelled = first;
    for _ in 0..600 {
        step(&mut w, &NONE);
        travelled += w.ball.pos.dist(prev);
        prev = w.ball.pos;
    }
    let limit = sp.ball_speed_max / (1.0 - sp.ball_decay);
    assert!((limit - 45.0).abs() < 1e-9);
    assert!((travelled - limit).abs() < 1e-6, "travelled {travelled}");
    assert!((w.ball.pos.x - limit).abs() < 1e-6 && w.ball.pos.y.abs() < 1e-9);
}

#[test]
fn dashing_player_tops_out_at_one_metre_per_cycle() {
    let mut w = spread_world();
    w.players[2].pos = Vec2::new(-20.0, -30.0); // a free lane
    let mut cmds = NONE;
    cmds[2] = Command::Dash { power: 100.0 };
    let mut prev = w.players[2].pos;
    let mut last = 0.0;
    for _ in 0..60 {
        step(&mut w, &cmds);
        last = w.players[2].pos.dist(prev);
        prev = w.players[2].pos;
    }
    assert!((last - 1.0).abs() < 1e-9, "displacement per cycle {last}");
    // What is left after the decay is 0.4 m/cycle.
    assert!((w.players[2].vel.norm() - 0.4).abs() < 1e-9);
    // Over-range powers are clipped to 100.
    let mut w2 = spread_world();
    cmds[2] = Command::Dash { power: 1e6 };
    step(&mut w2, &cmds);
    assert!((w2.players[2].pos.dist(spread_world().players[2].pos) - 0.6).abs() < 1e-9);
}

#[test]
fn kick_effective_power_depends_on_distance_and_angle() {
    let sp = ServerParams::default();
    let mut w = spread_world();
    // Ball 0.8 m away at 90 degrees off the body (body faces +x, ball along +y).
    w.players[0].pos = Vec2::new(0.0, -0.8);
    let mut cmds = NONE;
    cmds[0] = Command::Kick {
        power: 50.0,
        direction: 30.0,
    };
    step(&mut w, &cmds);
    let dist_ball = 0.8 - sp.player_size - sp.ball_size;
    let eff = 50.0 * sp.kick_power_rate * (1.0 - 0.25 * 0.5 - 0.25 * dist_ball / sp.kickable_margin);
    let moved = w.ball.pos;
    assert!(
        (moved.norm() - eff).abs() < 1e-9,
        "moved {} expected {eff}",
        moved.norm()
    );
    // Along body + kick direction, i.e. 30 degrees.
    assert!((moved.dir() - 30.0).abs() < 1e-9);
    assert!((w.ball.vel.norm() - eff * sp.ball_decay).abs() < 1e-9);

    // Out of reach (1.085 m): no effect.
    let mut w = spread_world();
    w.players[0].pos = Vec2::new(-1.1, 0.0);
    step(&mut w, &cmds);
    assert_eq!(w.ball.pos, Vec2::ZERO);
}

#[test]
fn turns_shrink_with_speed() {
    let mut w = spread_world();
    let mut cmds = NONE;
    cmds[3] = Command::Turn { moment: 90.0 };
    step(&mut w, &cmds);
    assert!((w.players[3].body - 90.0).abs() < 1e-9);

    // Moving at 1 m/cycle: a 180 moment turns 180 / (1 + 5 x 1) = 30 degrees.
    let mut w = spread_world();
    w.players[3].vel = Vec2::new(1.0, 0.0);
    cmds[3] = Command::Turn { moment: 180.0 };
    step(&mut w, &cmds);
    assert!((w.players[3].body - 30.0).abs() < 1e-9, "{}", w.players[3].body);

    // Moments beyond 180 are clipped.
    let mut w = spread_world();
    cmds[3] = Command::Turn { moment: 400.0 };
    step(&mut w, &cmds);
    assert!((w.players[3].body - 180.0).abs() < 1e-9);
}

#[test]
fn turn_noise_stays_within_player_rand() {
    let sp = ServerParams::default();
    let mut rng = seeded(3);
    let mut cmds = NONE;
    cmds[0] = Command::Turn { moment: 100.0 };
    let mut seen_low = false;
    let mut seen_high = false;
    for _ in 0..200 {
        let mut w = spread_world();
        w.physics_step(&cmds, &sp, true, &mut rng);
        let b = w.players[0].body;
        assert!((90.0..=110.0).contains(&b), "turned {b}");
        seen_low |= b < 95.0;
        seen_high |= b > 105.0;
    }
    assert!(seen_low && seen_high);
}

#[test]
fn motion_noise_is_bounded_per_axis() {
    let sp = ServerParams::default();
    let mut rng = seeded(5);
    for _ in 0..200 {
        let mut w = spread_world();
        w.ball.vel = Vec2::new(2.0, 0.0);
        w.physics_step(&NONE, &sp, true, &mut rng);
        // Moved by the velocity plus at most ball_rand x |v| on each axis.
        let d = w.ball.pos - Vec2::new(2.0, 0.0);
        assert!(d.x.abs() <= 0.1 + 1e-12 && d.y.abs() <= 0.1 + 1e-12, "{d:?}");
    }
}

#[test]
fn collisions_push_apart_and_reverse_velocities() {
    let sp = ServerParams::default();
    let mut rng = seeded(0);

    // Two players 0.4 m apart: pushed to 0.6 m about their midpoint.
    let mut w = spread_world();
    w.players[0].pos = Vec2::new(1.0, 2.0);
    w.players[1].pos = Vec2::new(1.4, 2.0);
    w.players[0].vel = Vec2::new(0.5, 0.0);
    w.players[1].vel = Vec2::new(-0.3, 0.2);
    w.resolve_collisions(&sp, &mut rng);
    let (a, b) = (w.players[0], w.players[1]);
    assert!((a.pos.dist(b.pos) - 0.6).abs() < 1e-6);
    assert!(a.pos.dist(b.pos) >= 0.6);
    assert!(((a.pos + b.pos) * 0.5).dist(Vec2::new(1.2, 2.0)) < 1e-12);
    assert!(a.vel.dist(Vec2::new(-0.05, 0.0)) < 1e-12);
    assert!(b.vel.dist(Vec2::new(0.03, -0.02)) < 1e-12);
    // Bystanders are untouched.
    assert_eq!(w.players[2], spread_world().players[2]);

    // Ball and player 0.2 m apart: pushed to 0.385 m.
    let mut w = spread_world();
    w.players[4].pos = Vec2::new(0.2, 0.0);
    w.players[4].vel = Vec2::new(-1.0, 0.0);
    w.ball.vel = Vec2::new(1.0, 0.0);
    w.resolve_collisions(&sp, &mut rng);
    assert!((w.ball.pos.dist(w.players[4].pos) - 0.385).abs() < 1e-6);
    assert!(w.ball.vel.dist(Vec2::new(-0.1, 0.0)) < 1e-12);
    assert!(w.players[4].vel.dist(Vec2::new(0.1, 0.0)) < 1e-12);

    // Exactly touching is not a collision.
    let mut w = spread_world();
    w.players[0].pos = Vec2::new(0.0, 5.0);
    w.players[1].pos = Vec2::new(0.6, 5.0);
    w.players[0].vel = Vec2::new(0.5, 0.0);
    w.resolve_collisions(&sp, &mut rng);
    assert_eq!(w.players[0].vel, Vec2::new(0.5, 0.0));
}

#[test]
fn collision_during_a_step() {
    // A player dashing into a resting ball stops it and bounces back.
    let mut w = spread_world();
    w.players[0].pos = Vec2::new(-1.0, 0.0);
    w.players[0].vel = Vec2::new(0.5, 0.0);
    let mut cmds = NONE;
    cmds[0] = Command::Dash { power: 100.0 };
    step(&mut w, &cmds);
    assert!(w.players[0].pos.dist(w.ball.pos) >= 0.385 - 1e-9);
    assert!(w.players[0].vel.x < 0.0, "{:?}", w.players[0].vel);
}
