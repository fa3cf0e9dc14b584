//! The field's state ([`FieldState`](crate::world::FieldState)) and the server's physics step (commands, movement, collisions).

use super::command::Command;
use super::geometry::{Vec2, clamp, normalize_deg};
use super::params::ServerParams;
use crate::rng::SimRng;
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// Number of keepers.
pub const NUM_KEEPERS: usize = 3;
/// Number of takers.
pub(crate) const NUM_TAKERS: usize = 2;
/// Number of players; indices `0..NUM_KEEPERS` are keepers, the rest takers.
pub const NUM_PLAYERS: usize = NUM_KEEPERS + NUM_TAKERS;

/// A team.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Side {
    /// The team keeping the ball (the server's left side).
    Keepers,
    /// The team trying to win it (the server's right side).
    Takers,
}

impl Side {
    /// The side of the player with global index `i` (indices past the keepers are takers).
    pub(crate) fn of(i: usize) -> Side {
        if i < NUM_KEEPERS { Side::Keepers } else { Side::Takers }
    }

    /// Global player indices of this side.
    pub(crate) fn indices(self) -> std::ops::Range<usize> {
        match self {
            Side::Keepers => 0..NUM_KEEPERS,
            Side::Takers => NUM_KEEPERS..NUM_PLAYERS,
        }
    }

    /// The other side.
    pub(crate) fn opponent(self) -> Side {
        match self {
            Side::Keepers => Side::Takers,
            Side::Takers => Side::Keepers,
        }
    }

    /// The direction (degrees, simulator coordinates) of this side's own x axis.
    ///
    /// The framework's world model (UvA Trilearn's) always plays towards its own +x:
    /// the server mirrors the field for the right team, so the takers' "global
    /// direction 0" is our 180. Skills that use a fixed global direction (the
    /// heading after an interception, the hold's "already in place" test, the
    /// preference for interception points farther forward) turn it by this angle.
    pub(crate) fn frame_dir(self) -> f64 {
        match self {
            Side::Keepers => 0.0,
            Side::Takers => 180.0,
        }
    }

    /// `p` in this side's own frame (see [`Side::frame_dir`]): unchanged for the
    /// keepers, rotated by 180 degrees for the takers.
    pub(crate) fn own_frame(self, p: Vec2) -> Vec2 {
        match self {
            Side::Keepers => p,
            Side::Takers => -p,
        }
    }
}

/// The ball's state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Ball {
    /// Position.
    pub pos: Vec2,
    /// Velocity (m/cycle).
    pub vel: Vec2,
}

/// A player's state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Player {
    /// Position.
    pub pos: Vec2,
    /// Velocity (m/cycle).
    pub vel: Vec2,
    /// Body direction, degrees.
    pub body: f64,
}

/// The complete simulated state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FieldState {
    /// The ball.
    pub ball: Ball,
    /// Players: keepers first, then takers.
    pub players: [Player; NUM_PLAYERS],
    /// Cycles simulated since the last reset.
    pub cycle: u32,
}

/// Uniform draw in `[-r, r)` (0 for a non-positive or NaN `r`, without consuming less).
fn symmetric(rng: &mut SimRng, r: f64) -> f64 {
    let u: f64 = rng.random();
    if r > 0.0 { (2.0 * u - 1.0) * r } else { 0.0 }
}

/// Effective kick power factor for a ball at `ball` seen from a player at `pos` with
/// body `body`: `1 - 0.25 * dir_diff / 180 - 0.25 * dist_ball / kickable_margin`,
/// where `dir_diff` is the absolute angle of the ball off the body (degrees) and
/// `dist_ball` the gap between ball and body surfaces.
pub(crate) fn kick_rate_factor(params: &ServerParams, pos: Vec2, body: f64, ball: Vec2) -> f64 {
    let rel = ball - pos;
    let dir_diff = normalize_deg(rel.dir() - body).abs();
    let dist_ball = rel.norm() - params.player_size - params.ball_size;
    1.0 - 0.25 * dir_diff / 180.0 - 0.25 * dist_ball / params.kickable_margin
}

/// Moves one object: clip and add the acceleration, clip the speed, add noise,
/// move, decay.
#[allow(clippy::too_many_arguments)]
fn integrate(
    pos: &mut Vec2,
    vel: &mut Vec2,
    accel: Vec2,
    accel_max: f64,
    speed_max: f64,
    decay: f64,
    rand: f64,
    noise: Option<&mut SimRng>,
) {
    if accel.x != 0.0 || accel.y != 0.0 {
        let a = accel.norm();
        let accel = if a > accel_max { accel * (accel_max / a) } else { accel };
        *vel += accel;
        let s = vel.norm();
        if s > speed_max {
            *vel *= speed_max / s;
        }
    }
    if let Some(rng) = noise {
        // The era's rule: each axis gets uniform noise in [-rand*|v|, rand*|v|].
        let r = rand * vel.norm();
        let nx = symmetric(rng, r);
        let ny = symmetric(rng, r);
        *vel += Vec2::new(nx, ny);
    }
    *pos += *vel;
    *vel *= decay;
}

impl FieldState {
    /// Applies one cycle of the server's physics: the players' commands, movement
    /// of every object in a shuffled order, then collisions. Increments `cycle`.
    ///
    /// With `noise` set (the server's behaviour), motion noise, turn noise and the
    /// shuffled movement order draw from `rng`; without it the step is deterministic
    /// and `rng` is only used to separate exactly coincident objects.
    pub fn physics_step(
        &mut self,
        commands: &[Command; NUM_PLAYERS],
        params: &ServerParams,
        noise: bool,
        rng: &mut SimRng,
    ) {
        let kickable_sq = params.kickable_distance() * params.kickable_distance();
        let mut ball_accel = Vec2::ZERO;
        let mut accels = [Vec2::ZERO; NUM_PLAYERS];

        // 1. Commands. The ball's position is the one at the start of the cycle, so
        //    kicks by several players add up regardless of their order.
        for (i, cmd) in commands.iter().enumerate() {
            if !cmd.is_finite() {
                continue;
            }
            let p = &mut self.players[i];
            match *cmd {
                Command::None => {}
                Command::Kick { power, direction } => {
                    if p.pos.dist_sq(self.ball.pos) <= kickable_sq {
                        let power = clamp(power, params.min_power, params.max_power);
                        let dir = clamp(direction, params.min_moment, params.max_moment);
                        let eff =
                            power * params.kick_power_rate * kick_rate_factor(params, p.pos, p.body, self.ball.pos);
                        ball_accel += Vec2::polar(eff, p.body + dir);
                    }
                }
                Command::Dash { power } => {
                    let power = clamp(power, params.min_power, params.max_power);
                    accels[i] += Vec2::polar(params.effort * power * params.dash_power_rate, p.body);
                }
                Command::Turn { moment } => {
                    let moment = clamp(moment, params.min_moment, params.max_moment);
                    let factor = if noise {
                        1.0 + symmetric(rng, params.player_rand)
                    } else {
                        1.0
                    };
                    let turn = factor * moment / (1.0 + params.inertia_moment * p.vel.norm());
                    p.body = normalize_deg(p.body + turn);
                }
            }
        }

        // 2. Movement, in the server's shuffled order (which fixes the order of the
        //    noise draws). Slot 0 is the ball, slot 1 + i player i.
        let mut order = [0usize, 1, 2, 3, 4, 5];
        if noise {
            for k in (1..order.len()).rev() {
                let j = rng.random_range(0..=k);
                order.swap(k, j);
            }
        }
        for &slot in &order {
            let rng_opt = if noise { Some(&mut *rng) } else { None };
            if slot == 0 {
                integrate(
                    &mut self.ball.pos,
                    &mut self.ball.vel,
                    ball_accel,
                    params.ball_accel_max,
                    params.ball_speed_max,
                    params.ball_decay,
                    params.ball_rand,
                    rng_opt,
                );
            } else {
                let p = &mut self.players[slot - 1];
                integrate(
                    &mut p.pos,
                    &mut p.vel,
                    accels[slot - 1],
                    params.player_accel_max,
                    params.player_speed_max,
                    params.player_decay,
                    params.player_rand,
                    rng_opt,
                );
            }
        }

        // 3. Collisions.
        self.resolve_collisions(params, rng);
        self.cycle = self.cycle.saturating_add(1);
    }

    /// The server's collision model: overlapping pairs (ball-player closer than the
    /// sum of radii, 0.385 m; player-player closer than 0.6 m) are pushed apart
    /// symmetrically about their midpoint to touching distance (positions from
    /// several collisions are averaged), repeated up to 10 times while overlaps
    /// remain; finally every object that collided has its velocity multiplied by -0.1.
    pub fn resolve_collisions(&mut self, params: &ServerParams, rng: &mut SimRng) {
        const EPS: f64 = 1e-10;
        const SLOTS: usize = NUM_PLAYERS + 1;
        let mut collided = [false; SLOTS];
        let sizes = |slot: usize| {
            if slot == 0 {
                params.ball_size
            } else {
                params.player_size
            }
        };
        let pos_of = |w: &FieldState, slot: usize| {
            if slot == 0 { w.ball.pos } else { w.players[slot - 1].pos }
        };
        // Ball against each player, then every pair of players (the server's order).
        let mut pairs = [(0usize, 0usize); NUM_PLAYERS + NUM_PLAYERS * (NUM_PLAYERS - 1) / 2];
        let mut n = 0;
        for p in 1..SLOTS {
            pairs[n] = (0, p);
            n += 1;
        }
        for a in 1..SLOTS {
            for b in (a + 1)..SLOTS {
                pairs[n] = (a, b);
                n += 1;
            }
        }
        for _ in 0..10 {
            let mut sum = [Vec2::ZERO; SLOTS];
            let mut count = [0u32; SLOTS];
            let mut any = false;
            for &(a, b) in &pairs[..n] {
                let pa = pos_of(self, a);
                let pb = pos_of(self, b);
                let r = sizes(a) + sizes(b);
                if pa.dist_sq(pb) >= r * r {
                    continue;
                }
                any = true;
                collided[a] = true;
                collided[b] = true;
                let mid = (pa + pb) * 0.5;
                let half = r * 0.5 + EPS;
                let (mut to_a, mut to_b) = if (pa - mid).norm() < EPS && (pb - mid).norm() < EPS {
                    let ang = (2.0 * rng.random::<f64>() - 1.0) * 180.0;
                    (Vec2::polar(half, ang), Vec2::polar(half, ang + 180.0))
                } else {
                    ((pa - mid).with_norm(half), (pb - mid).with_norm(half))
                };
                let mut k = 0;
                while (mid + to_a).dist_sq(mid + to_b) < r * r && k < 10 {
                    to_a *= 1.0001;
                    to_b *= 1.0001;
                    k += 1;
                }
                sum[a] += mid + to_a;
                count[a] += 1;
                sum[b] += mid + to_b;
                count[b] += 1;
            }
            for slot in 0..SLOTS {
                if count[slot] > 0 {
                    let p = sum[slot] / f64::from(count[slot]);
                    if slot == 0 {
                        self.ball.pos = p;
                    } else {
                        self.players[slot - 1].pos = p;
                    }
                }
            }
            if !any {
                break;
            }
        }
        for (slot, &c) in collided.iter().enumerate() {
            if c {
                if slot == 0 {
                    self.ball.vel *= -0.1;
                } else {
                    self.players[slot - 1].vel *= -0.1;
                }
            }
        }
    }
}
