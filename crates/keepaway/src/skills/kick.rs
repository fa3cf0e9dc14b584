//! Ball-kicking skills: accelerate the ball to a velocity, stop it, place it next to
//! the body, and kick it to a point with a given arrival speed.

use super::predict::kick_speed_to_travel;
use crate::command::Command;
use crate::geometry::{Vec2, clamp, normalize_deg};
use crate::params::KeepawayConfig;
use crate::view::PlayerView;
use crate::world::kick_rate_factor;

/// Kick ratio the framework uses when it repositions the ball before a kick
/// (`kickBallCloseToBody`'s default: the ball ends 0.497 m from the centre).
pub(crate) const REPOSITION_RATIO: f64 = 0.16;

/// Acceleration per unit of kick power for the ball where it lies now.
pub(crate) fn kick_rate(view: &PlayerView, cfg: &KeepawayConfig) -> f64 {
    let me = view.own();
    cfg.server.kick_power_rate * kick_rate_factor(&cfg.server, me.pos, me.body, view.ball.pos)
}

fn kick(view: &PlayerView, power: f64, global_dir: f64) -> Command {
    Command::Kick {
        power,
        direction: normalize_deg(global_dir - view.own().body),
    }
}

/// The largest kick component that keeps the ball moving along `dir`: full power,
/// aimed so as to cancel the ball's current velocity across `dir` (the framework's
/// fallback when the wanted velocity is out of reach).
fn max_kick_along(view: &PlayerView, cfg: &KeepawayConfig, rate: f64, dir: f64) -> f64 {
    let speed = rate * cfg.server.max_power;
    let across = view.ball.vel.rotate(-dir).y;
    let ratio = if speed > 0.0 {
        clamp(across / speed, -1.0, 1.0)
    } else {
        0.0
    };
    dir - ratio.asin().to_degrees()
}

/// Kick so that the ball's velocity becomes `vel_des` (`accelerateBallToVelocity`);
/// if that needs more than one kick can give, kick at full power so that the ball at
/// least moves along `vel_des`.
pub(crate) fn accelerate_ball_to_velocity(view: &PlayerView, cfg: &KeepawayConfig, vel_des: Vec2) -> Command {
    let sp = &cfg.server;
    let rate = kick_rate(view, cfg);
    if rate <= 0.0 {
        return Command::None;
    }
    let acc = vel_des - view.ball.vel;
    if acc.norm() < sp.ball_accel_max {
        let power = acc.norm() / rate;
        if power <= sp.max_power {
            return kick(view, power, acc.dir());
        }
    }
    let dir = max_kick_along(view, cfg, rate, vel_des.dir());
    kick(view, sp.max_power, dir)
}

/// Stop the ball dead (`freezeBall`); if stopping it would leave it out of easy
/// reach (beyond 0.8 x kickable distance of where one will be), pull it closer instead.
pub(crate) fn freeze_ball(view: &PlayerView, cfg: &KeepawayConfig) -> Command {
    let sp = &cfg.server;
    let me = view.own();
    let rate = kick_rate(view, cfg);
    if rate <= 0.0 {
        return Command::None;
    }
    let me_next = me.pos + me.vel;
    let power = (view.ball.vel.norm() / rate).min(sp.max_power);
    let dir = view.ball.vel.dir() + 180.0;
    let mut vel = view.ball.vel + Vec2::polar(rate * power, dir);
    if vel.norm() > sp.ball_speed_max {
        vel = vel.with_norm(sp.ball_speed_max);
    }
    if (view.ball.pos + vel).dist(me_next) < 0.8 * sp.kickable_distance() {
        return kick(view, power, dir);
    }
    let keep = (0.7 * sp.kickable_distance()).min(view.ball.pos.dist(me_next) - 0.1);
    let to = me_next + Vec2::polar(keep, (view.ball.pos - me_next).dir());
    accelerate_ball_to_velocity(view, cfg, to - view.ball.pos)
}

/// Put the ball next to the body at `ang_rel` degrees from the body direction, at
/// `player_size + ball_size + ratio x kickable_margin` from where one will be next
/// cycle (`kickBallCloseToBody`); if one kick cannot do it and the ball is moving,
/// stop it instead. (The framework also pulls a spot that would lie off the
/// 105 m x 68 m pitch back onto it; keepaway's region lies well inside the pitch,
/// so that never happens here and is left out.)
pub(crate) fn kick_ball_close_to_body(view: &PlayerView, cfg: &KeepawayConfig, ang_rel: f64, ratio: f64) -> Command {
    let sp = &cfg.server;
    let me = view.own();
    let dist = sp.player_size + sp.ball_size + sp.kickable_margin * ratio;
    let target = me.pos + me.vel + Vec2::polar(dist, me.body + ang_rel);
    let shoot = target - view.ball.pos - view.ball.vel;
    let rate = kick_rate(view, cfg);
    if rate <= 0.0 {
        return Command::None;
    }
    let power = shoot.norm() / rate;
    if power > sp.max_power && view.ball.vel.norm() > 0.1 {
        return freeze_ball(view, cfg);
    }
    kick(view, power.min(sp.max_power), shoot.dir())
}

/// Kick the ball towards `target` so that it arrives with speed `end_speed`
/// (`kickTo`), possibly over several cycles:
/// - the wanted first speed comes from the geometric series of the ball's decay;
///   if kicking straight would run the ball through one's own body, the speed is
///   adjusted to pass by it;
/// - if that speed exceeds the ball's maximum: kick anyway when a full kick along
///   the line still reaches 0.85 x the maximum acceleration; else stop the ball if it
///   lies well for kicking (rate above 0.85 x the best), else reposition it close
///   in front of the body;
/// - if reachable: kick when the power needed is at most 105% of the maximum (130%
///   with an opponent within 2 m of the ball), else reposition the ball first.
pub(crate) fn kick_to(view: &PlayerView, cfg: &KeepawayConfig, target: Vec2, end_speed: f64) -> Command {
    let sp = &cfg.server;
    let me = view.own();
    let ball = view.ball;
    let traj = target - ball.pos;
    let mut vel_des = Vec2::polar(kick_speed_to_travel(traj.norm(), end_speed, sp), traj.dir());
    let me_next = me.pos + me.vel;
    let radii = sp.player_size + sp.ball_size;
    if me_next.dist(ball.pos + vel_des) < radii {
        let u = vel_des.with_norm(1.0);
        let along = (me.pos - ball.pos).dot(u).abs();
        let d = if vel_des.norm() < along {
            along - radii
        } else {
            along + radii
        };
        vel_des = Vec2::polar(d, vel_des.dir());
    }
    let rate = kick_rate(view, cfg);
    if rate <= 0.0 {
        return Command::None;
    }
    let when = cfg.skills.when_to_kick;
    if vel_des.norm() > sp.ball_speed_max {
        let dir = max_kick_along(view, cfg, rate, vel_des.dir());
        let speed_pred = (ball.vel + Vec2::polar(rate * sp.max_power, dir)).norm();
        if speed_pred > when * sp.ball_accel_max {
            accelerate_ball_to_velocity(view, cfg, vel_des)
        } else if rate > when * sp.kick_power_rate {
            freeze_ball(view, cfg)
        } else {
            kick_ball_close_to_body(view, cfg, 0.0, REPOSITION_RATIO)
        }
    } else {
        let power = (vel_des - ball.vel).norm() / rate;
        let opp_near = view.opponents().any(|(_, o)| o.pos.dist(ball.pos) < 2.0);
        if power <= 1.05 * sp.max_power || (opp_near && power <= 1.30 * sp.max_power) {
            accelerate_ball_to_velocity(view, cfg, vel_des)
        } else {
            kick_ball_close_to_body(view, cfg, 0.0, REPOSITION_RATIO)
        }
    }
}
