//! Noise-free predictions of ball and player motion, as the framework's world model
//! makes them: ball roll-out, the effect of a dash or turn, dash powers, and
//! estimated cycles for a player to reach a point or the ball.

use crate::keepaway::command::Command;
use crate::keepaway::geometry::{Vec2, clamp, normalize_deg};
use crate::keepaway::params::{KeepawayConfig, ServerParams};
use crate::keepaway::perception::{PlayerView, SeenBall, SeenPlayer};
use crate::keepaway::world::NUM_PLAYERS;

/// A player's kinematic state, as used in predictions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Kinematics {
    /// Position.
    pub pos: Vec2,
    /// Velocity (m/cycle).
    pub vel: Vec2,
    /// Body direction, degrees.
    pub body: f64,
}

impl From<&SeenPlayer> for Kinematics {
    fn from(p: &SeenPlayer) -> Self {
        Kinematics {
            pos: p.pos,
            vel: p.vel,
            body: p.body,
        }
    }
}

/// Sum of the first `n` terms of the geometric series `1 + r + r^2 + ...`.
fn geom_sum(r: f64, n: u32) -> f64 {
    (1.0 - r.powi(i32::try_from(n).unwrap_or(i32::MAX))) / (1.0 - r)
}

/// A player's position after `n` cycles without commands.
pub fn rollout_pos(k: &Kinematics, n: u32, sp: &ServerParams) -> Vec2 {
    k.pos + k.vel * geom_sum(sp.player_decay, n)
}

/// Where a player comes to rest without commands.
pub fn final_pos(k: &Kinematics, sp: &ServerParams) -> Vec2 {
    k.pos + k.vel / (1.0 - sp.player_decay)
}

/// State after one cycle with a dash of `power` (noise-free), the body direction
/// given as the unit vector `u`.
fn after_dash(k: &Kinematics, power: f64, u: Vec2, sp: &ServerParams) -> Kinematics {
    let power = clamp(power, sp.min_power, sp.max_power);
    let mut vel = k.vel + u * (power * sp.dash_power_rate * sp.effort);
    let s = vel.norm();
    if s > sp.player_speed_max {
        vel *= sp.player_speed_max / s;
    }
    Kinematics {
        pos: k.pos + vel,
        vel: vel * sp.player_decay,
        body: k.body,
    }
}

/// State after one cycle with a turn of `moment` (noise-free).
pub fn after_turn(k: &Kinematics, moment: f64, sp: &ServerParams) -> Kinematics {
    let moment = clamp(moment, sp.min_moment, sp.max_moment);
    Kinematics {
        pos: k.pos + k.vel,
        vel: k.vel * sp.player_decay,
        body: normalize_deg(k.body + moment / (1.0 + sp.inertia_moment * k.vel.norm())),
    }
}

/// The moment to send to turn by `desired` degrees at `speed`, clipped to the
/// largest moment (then the turn falls short).
pub fn angle_for_turn(desired: f64, speed: f64, sp: &ServerParams) -> f64 {
    clamp(
        desired * (1.0 + sp.inertia_moment * speed),
        sp.min_moment,
        sp.max_moment,
    )
}

/// The dash power to cover the projection of `rel` on the body direction in
/// `cycles` cycles (speed capped at the maximum), allowing for the current
/// velocity; clipped to the power range.
pub fn power_for_dash(rel: Vec2, body: f64, vel: Vec2, cycles: u32, sp: &ServerParams) -> f64 {
    power_for_dash_along(rel, Vec2::polar(1.0, body), vel, cycles, sp)
}

/// [`power_for_dash`] with the body direction given as the unit vector `u`.
fn power_for_dash_along(rel: Vec2, u: Vec2, vel: Vec2, cycles: u32, sp: &ServerParams) -> f64 {
    let dist = rel.dot(u);
    let n = cycles.max(1);
    let mut speed = dist / geom_sum(sp.player_decay, n);
    if speed > sp.player_speed_max {
        speed = sp.player_speed_max;
    }
    let acc = speed - vel.dot(u);
    let power = acc / (sp.dash_power_rate * sp.effort);
    if power.is_nan() {
        0.0
    } else {
        clamp(power, sp.min_power, sp.max_power)
    }
}

/// The first speed a ball needs to cover `dist` and still move at `end_speed`
/// there (the framework's `getKickSpeedToTravel`): the number of decay steps is
/// rounded to an integer, as the framework does.
pub fn kick_speed_to_travel(dist: f64, end_speed: f64, sp: &ServerParams) -> f64 {
    if end_speed < 1e-4 {
        return dist * (1.0 - sp.ball_decay);
    }
    let r = 1.0 / sp.ball_decay;
    let temp = dist * (r - 1.0) / end_speed + 1.0;
    let steps = if temp <= 0.0 { -1.0 } else { temp.ln() / r.ln() };
    end_speed * r.powf(steps.round_ties_even())
}

/// The framework's turn-or-dash decision for moving towards `target`
/// (`predictCommandToMoveToPos`), used while intercepting: turn towards the target
/// when it lies more than `0.9 x kickable distance` off the body line (2x beyond
/// 10 m, 3x beyond 20 m), or lies behind and farther than `dist_back`; otherwise
/// dash with the power that covers the distance in `cycles` cycles (backwards if
/// the target is behind).
///
/// Decision: the framework's extra "turn around and run backwards" special case
/// for targets just behind is not reproduced.
pub fn move_command_towards(k: &Kinematics, target: Vec2, cycles: u32, dist_back: f64, sp: &ServerParams) -> Command {
    let u = Vec2::polar(1.0, k.body);
    match move_decision(k, u, target, cycles, dist_back, sp) {
        MoveDecision::Turn { from } => Command::Turn {
            moment: turn_moment_towards(k, from, target, sp),
        },
        MoveDecision::Dash { power } => Command::Dash { power },
    }
}

/// The outcome of [`move_command_towards`] before any angle is computed.
enum MoveDecision {
    /// Turn towards the target as seen from `from`.
    Turn { from: Vec2 },
    /// Dash with this power.
    Dash { power: f64 },
}

/// The moment turning a player at `k` to face `target` as seen from `from`.
fn turn_moment_towards(k: &Kinematics, from: Vec2, target: Vec2, sp: &ServerParams) -> f64 {
    let ang_to = normalize_deg((target - from).dir() - k.body);
    angle_for_turn(ang_to, k.vel.norm(), sp)
}

/// [`move_command_towards`] with the body direction as the unit vector `u`,
/// avoiding trigonometry on the common paths.
fn move_decision(
    k: &Kinematics,
    u: Vec2,
    target: Vec2,
    cycles: u32,
    dist_back: f64,
    sp: &ServerParams,
) -> MoveDecision {
    let pos_pred = rollout_pos(k, cycles.min(4), sp);
    let to = target - pos_pred;
    let offset = to.cross(u).abs();
    let d = k.pos.dist(target);
    let ratio = if d > 20.0 {
        3.0
    } else if d > 10.0 {
        2.0
    } else {
        0.9
    };
    // Behind: more than 90 degrees off the body direction.
    let behind = to.dot(u) < 0.0 && to.norm_sq() > dist_back * dist_back;
    if offset > ratio * sp.kickable_distance() || behind {
        MoveDecision::Turn { from: pos_pred }
    } else {
        MoveDecision::Dash {
            power: power_for_dash_along(target - k.pos, u, k.vel, cycles, sp),
        }
    }
}

/// Cycles to run `dist` straight ahead at full power, starting at `speed` along
/// the body, until within the kickable distance (the framework's
/// `predictNrCyclesForDistance`): simulated until the speed settles, then extrapolated.
pub fn cycles_for_distance(dist: f64, speed: f64, sp: &ServerParams) -> u32 {
    let min_dist = sp.kickable_distance();
    let acc = sp.max_power * sp.dash_power_rate * sp.effort;
    let mut dist = dist;
    let mut speed = speed;
    let mut prev = f64::NEG_INFINITY;
    let mut cycles = 0u32;
    while dist > min_dist && ((speed - prev).abs() > 1e-4 || speed < 0.3) && cycles < 40 {
        prev = speed;
        speed = (speed + acc).min(sp.player_speed_max);
        dist = (dist - speed).max(0.0);
        speed *= sp.player_decay;
        cycles += 1;
    }
    speed /= sp.player_decay;
    if dist > min_dist {
        if speed > 1e-6 {
            let more = ((dist - min_dist) / speed).ceil();
            cycles = cycles.saturating_add(if more < 1e6 { more as u32 } else { 1_000_000 });
        } else {
            cycles = cycles.saturating_add(1_000_000);
        }
    }
    cycles
}

/// Estimated cycles for a player to get within kickable distance of `target`
/// (the framework's `predictNrCyclesToPoint`): simulate the turns (and braking
/// dashes) that [`move_command_towards`] asks for, then count full-power running.
pub fn cycles_to_point(k: &Kinematics, target: Vec2, cfg: &KeepawayConfig) -> u32 {
    cycles_to_point_along(k, Vec2::polar(1.0, k.body), target, cfg)
}

/// [`cycles_to_point`] with the body direction given as the unit vector `u`.
fn cycles_to_point_along(k: &Kinematics, u: Vec2, target: Vec2, cfg: &KeepawayConfig) -> u32 {
    let sp = &cfg.server;
    let reach = sp.kickable_distance();
    let to = target - k.pos;
    let d = to.norm();
    if d < reach {
        return 0;
    }
    let want = to / d;
    let cos20 = 20f64.to_radians().cos();
    let mut k = *k;
    let mut u = u;
    let mut cycles = 0u32;
    for _ in 0..8 {
        match move_decision(&k, u, target, 1, cfg.skills.intercept_dist_back, sp) {
            MoveDecision::Turn { from } => {
                let moment = turn_moment_towards(&k, from, target, sp);
                k = after_turn(&k, moment, sp);
                u = Vec2::polar(1.0, k.body);
            }
            // A braking (backward) dash while facing more than 20 degrees away.
            MoveDecision::Dash { power } if power < 0.0 && u.dot(want) < cos20 => {
                k = after_dash(&k, power, u, sp);
            }
            MoveDecision::Dash { .. } => break,
        }
        cycles += 1;
        if k.pos.dist(target) < reach {
            return cycles;
        }
    }
    cycles.saturating_add(cycles_for_distance(k.pos.dist(target), k.vel.dot(u), sp))
}

/// The ball as an interceptor should predict it: as seen, except that a ball within
/// the kickable distance of an opponent is taken to stay where it is.
///
/// Decision (deviation from the framework, whose prediction always lets the ball
/// roll on): an opponent who controls the ball keeps it next to himself, so its
/// free roll-out is the wrong target. Without this, a keeper holding the ball
/// flips it from one side of his body to the other, each flip sends the takers'
/// predicted interception point several metres to the other side, and the takers
/// keep turning instead of running in: an always-hold team then keeps the ball
/// for ever, which contradicts every published keepaway result.
pub fn ball_to_chase(view: &PlayerView, cfg: &KeepawayConfig) -> SeenBall {
    let reach = cfg.server.kickable_distance();
    let controlled = view.opponents().any(|(_, o)| o.pos.dist(view.ball.pos) <= reach);
    if controlled {
        SeenBall {
            pos: view.ball.pos,
            vel: Vec2::ZERO,
        }
    } else {
        view.ball
    }
}

/// Result of an interception estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interception {
    /// Global index of the player.
    pub player: usize,
    /// Cycles until the ball can be reached.
    pub cycles: u32,
    /// Where the ball will be then.
    pub point: Vec2,
}

/// The player among `candidates` (global indices, in priority order for ties) who
/// reaches the ball first, by the framework's scheme (`createInterceptFeatures`):
/// for `i = 0, 1, ...` up to the interception horizon, predict the ball after `i`
/// cycles (see [`ball_to_chase`]) and estimate, for each candidate close enough,
/// the cycles to reach it ([`cycles_to_point`]); the first `i` at which the best
/// estimate is `<= i` gives the fastest player. If nobody makes it within the
/// horizon, the candidate with the smallest estimate to the horizon's ball
/// position is returned with the horizon as its time. Indices that are out of
/// range, and candidates beyond the first [`NUM_PLAYERS`], are ignored; `None` if
/// no candidate is left.
pub fn fastest_to_ball(
    view: &PlayerView,
    candidates: impl IntoIterator<Item = usize>,
    cfg: &KeepawayConfig,
) -> Option<Interception> {
    let sp = &cfg.server;
    let reach = sp.kickable_distance();
    let ball = ball_to_chase(view, cfg);
    let mut ball_pos = ball.pos;
    let mut ball_vel = ball.vel;
    // Capped as in `SkillParams::validate`, so that an unvalidated value cannot stall.
    let horizon = cfg.skills.intercept_horizon.min(1000);
    // Each candidate's state and body direction, computed once.
    let mut movers = [(usize::MAX, Kinematics::default(), Vec2::ZERO); NUM_PLAYERS];
    let mut n = 0;
    for j in candidates {
        if let (Some(p), Some(slot)) = (view.players.get(j), movers.get_mut(n)) {
            let k = Kinematics::from(p);
            *slot = (j, k, Vec2::polar(1.0, k.body));
            n += 1;
        }
    }
    let movers = &movers[..n];
    for i in 0..=horizon {
        let mut best: Option<(usize, u32)> = None;
        for &(j, k, u) in movers {
            // Nobody covers more than `player_speed_max` per cycle, so a candidate
            // farther than this cannot make it in `i` cycles (the framework's own
            // cut-off, `d / speed_max < i + 1`, is looser; the result is the same).
            if k.pos.dist(ball_pos) - reach > sp.player_speed_max * f64::from(i) {
                continue;
            }
            let c = cycles_to_point_along(&k, u, ball_pos, cfg);
            if best.is_none_or(|(_, b)| c < b) {
                best = Some((j, c));
            }
        }
        if let Some((player, c)) = best
            && c <= i
        {
            return Some(Interception {
                player,
                cycles: i,
                point: ball_pos,
            });
        }
        if i < horizon {
            ball_pos += ball_vel;
            ball_vel *= sp.ball_decay;
        }
    }
    let mut best: Option<(usize, u32)> = None;
    for &(j, k, u) in movers {
        let c = cycles_to_point_along(&k, u, ball_pos, cfg);
        if best.is_none_or(|(_, b)| c < b) {
            best = Some((j, c));
        }
    }
    best.map(|(player, _)| Interception {
        player,
        cycles: horizon,
        point: ball_pos,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dash_power_for_far_points_is_full() {
        let sp = ServerParams::default();
        let p = power_for_dash(Vec2::new(10.0, 0.0), 0.0, Vec2::ZERO, 1, &sp);
        assert_eq!(p, 100.0);
        let back = power_for_dash(Vec2::new(-10.0, 0.0), 0.0, Vec2::ZERO, 1, &sp);
        assert_eq!(back, -100.0);
    }

    #[test]
    fn pass_speed_follows_the_geometric_series() {
        let sp = ServerParams::default();
        let v0 = kick_speed_to_travel(10.0, 1.2, &sp);
        // Travelling from v0 down to about 1.2 covers about 10 m.
        let mut v = v0;
        let mut d = 0.0;
        while v > 1.2 + 1e-9 {
            d += v;
            v *= sp.ball_decay;
        }
        assert!((d - 10.0).abs() < 2.0, "v0 {v0} covers {d}");
        assert!(v0 > 1.2 && v0 < 2.7);
    }

    #[test]
    fn running_distance_estimate() {
        let sp = ServerParams::default();
        // From rest, top speed 1.0 m/cycle is reached quickly: ~10 m in ~10 cycles.
        let c = cycles_for_distance(10.0 + sp.kickable_distance(), 0.0, &sp);
        assert!((10..=12).contains(&c), "{c}");
        assert_eq!(cycles_for_distance(0.5, 0.0, &sp), 0);
    }
}
