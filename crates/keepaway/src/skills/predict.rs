//! The framework's world-model predictions (`WorldModelPredict.cc` and the
//! prediction helpers of `WorldModelHighLevel.cc`): where the ball and a player
//! will be, what one dash or turn does, which command moves a player towards a
//! point, and how many cycles a player needs to reach a point.
//!
//! Every prediction is noise-free, as the framework's. Its predictions start
//! from the state of the last see message and count the cycles since; our views
//! are current every cycle, so they start from the present state.

use crate::command::Command;
use crate::geometry::{Vec2, clamp, normalize_deg, round_ties_even};
use crate::params::{KeepawayConfig, ServerParams};
use crate::view::{SeenBall, SeenPlayer};
use std::sync::LazyLock;

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

/// Whose cycles [`cycles_to_point`] estimates: the framework simulates its own
/// agent's run to the end but extrapolates other players' after their turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Estimate {
    /// The viewer itself.
    Own,
    /// Any other player.
    Other,
}

/// Most cycles [`cycles_to_point`] simulates. The framework's loops have no bound;
/// in play they end within the interception horizon, and this bound only stops
/// runaway estimates from absurd views.
const MAX_SIMULATED_CYCLES: u32 = 200;

/// Sum of the first `n` terms of the geometric series `1 + r + r^2 + ...`: term
/// by term for the few terms of most predictions; beyond, in closed form, read
/// from a table for the server's default ball and player decays, which nearly
/// every prediction uses (the tables hold [`closed_form_geom_sum`]'s values, so
/// both give the same bits).
#[inline]
fn geom_sum(r: f64, n: u32) -> f64 {
    if n <= GEOM_TERMS_SUMMED {
        let (mut sum, mut term) = (0.0, 1.0);
        for _ in 0..n {
            sum += term;
            term *= r;
        }
        return sum;
    }
    let tables = &*DEFAULT_DECAY_SUMS;
    let i = n as usize;
    if i < GEOM_TABLE_LEN {
        if r == tables.ball_decay {
            return tables.ball[i];
        }
        if r == tables.player_decay {
            return tables.player[i];
        }
    }
    closed_form_geom_sum(r, n)
}

/// Terms up to which [`geom_sum`] adds the terms one by one.
const GEOM_TERMS_SUMMED: u32 = 8;

/// [`geom_sum`] beyond [`GEOM_TERMS_SUMMED`] terms: `(1 - r^n) / (1 - r)`.
fn closed_form_geom_sum(r: f64, n: u32) -> f64 {
    (1.0 - r.powi(i32::try_from(n).unwrap_or(i32::MAX))) / (1.0 - r)
}

/// Terms covered by the tables of [`geom_sum`].
const GEOM_TABLE_LEN: usize = 64;

/// [`closed_form_geom_sum`] of the server's default ball and player decays for
/// `0..GEOM_TABLE_LEN` terms (only those beyond [`GEOM_TERMS_SUMMED`] are read).
struct DefaultDecaySums {
    ball_decay: f64,
    ball: [f64; GEOM_TABLE_LEN],
    player_decay: f64,
    player: [f64; GEOM_TABLE_LEN],
}

/// The tables of [`geom_sum`], made on first use.
static DEFAULT_DECAY_SUMS: LazyLock<DefaultDecaySums> = LazyLock::new(|| {
    let sp = ServerParams::default();
    let sums = |ratio: f64| {
        let mut sums = [0.0; GEOM_TABLE_LEN];
        for (n, sum) in (0u32..).zip(sums.iter_mut()) {
            *sum = closed_form_geom_sum(ratio, n);
        }
        sums
    };
    DefaultDecaySums {
        ball_decay: sp.ball_decay,
        ball: sums(sp.ball_decay),
        player_decay: sp.player_decay,
        player: sums(sp.player_decay),
    }
});

/// Where the ball will be after `n` cycles (`predictPosAfterNrCycles` for the
/// ball: its velocity decays geometrically).
pub(crate) fn ball_pos_after(ball: &SeenBall, n: u32, sp: &ServerParams) -> Vec2 {
    ball.pos + ball.vel * geom_sum(sp.ball_decay, n)
}

/// A [`Kinematics`] with its body direction also as a unit vector, so that the
/// simulation loops below need trigonometry only when the body turns.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Mover {
    pos: Vec2,
    vel: Vec2,
    body: f64,
    u: Vec2,
}

impl Mover {
    /// The mover at `k`.
    pub(crate) fn new(k: &Kinematics) -> Self {
        Mover {
            pos: k.pos,
            vel: k.vel,
            body: k.body,
            u: Vec2::polar(1.0, k.body),
        }
    }

    /// Position.
    pub(crate) fn pos(&self) -> Vec2 {
        self.pos
    }

    /// The most it can move in any one of the coming cycles, whatever it is
    /// commanded: the next cycle's [`RunBound`] step, or the speed at which
    /// those steps settle if larger (they never pass the larger of the two).
    pub(crate) fn step_limit(&self, sp: &ServerParams) -> f64 {
        let acc = dash_acceleration_limit(sp);
        let settled = if sp.player_decay < 1.0 {
            (acc / (1.0 - sp.player_decay)).min(sp.player_speed_max)
        } else {
            sp.player_speed_max
        };
        (self.vel.norm() + acc).min(sp.player_speed_max).max(settled)
    }

    fn kinematics(&self) -> Kinematics {
        Kinematics {
            pos: self.pos,
            vel: self.vel,
            body: self.body,
        }
    }

    /// `predictStateAfterDash`.
    #[inline]
    fn dash(&self, power: f64, sp: &ServerParams) -> Mover {
        let mut vel = self.vel;
        if power != 0.0 {
            vel += self.u * (power * sp.dash_power_rate * sp.effort);
        }
        let s2 = vel.norm_sq();
        if s2 > sp.player_speed_max * sp.player_speed_max {
            vel *= sp.player_speed_max / s2.sqrt();
        }
        Mover {
            pos: self.pos + vel,
            vel: vel * sp.player_decay,
            ..*self
        }
    }

    /// `predictStateAfterTurn`.
    fn turn(&self, moment: f64, sp: &ServerParams) -> Mover {
        let body = normalize_deg(self.body + moment / (1.0 + sp.inertia_moment * self.vel.norm()));
        Mover {
            body,
            u: Vec2::polar(1.0, body),
            ..*self
        }
        .dash(0.0, sp)
    }

    /// `predictStateAfterCommand`.
    #[inline]
    pub(crate) fn after(&self, cmd: Command, sp: &ServerParams) -> Mover {
        match cmd {
            Command::Dash { power } => self.dash(power, sp),
            Command::Turn { moment } => self.turn(moment, sp),
            Command::Kick { .. } => self.dash(0.0, sp),
            Command::None => self.dash(0.01, sp),
        }
    }

    /// Position after `n` cycles of dashing with `power`.
    #[inline]
    fn pos_after(&self, n: u32, power: f64, sp: &ServerParams) -> Vec2 {
        if power == 0.0 {
            return roll(self.pos, self.vel, n, sp);
        }
        let mut m = *self;
        for _ in 0..n {
            m = m.dash(power, sp);
        }
        m.pos
    }
}

/// Where a player at `pos` moving at `vel` will be after `n` cycles without
/// dashing: within the speed cap the geometric series in closed form, otherwise
/// cycle by cycle (the cap applies as in a dash of power 0, which needs no body
/// direction).
#[inline]
fn roll(pos: Vec2, vel: Vec2, n: u32, sp: &ServerParams) -> Vec2 {
    let max = sp.player_speed_max;
    if vel.norm_sq() <= max * max {
        return pos + vel * geom_sum(sp.player_decay, n);
    }
    let mut m = Mover {
        pos,
        vel,
        body: 0.0,
        u: Vec2::ZERO,
    };
    for _ in 0..n {
        m = m.dash(0.0, sp);
    }
    m.pos
}

/// State after one cycle with a dash of `power` (`predictStateAfterDash`): the
/// acceleration along the body (backwards for a negative power), the speed capped,
/// then one cycle of movement and decay.
pub fn after_dash(k: &Kinematics, power: f64, sp: &ServerParams) -> Kinematics {
    Mover::new(k).dash(power, sp).kinematics()
}

/// State after one cycle with a turn of `moment` (`predictStateAfterTurn`): the
/// body turns by `moment / (1 + inertia_moment x speed)`, then the player rolls.
pub(crate) fn after_turn(k: &Kinematics, moment: f64, sp: &ServerParams) -> Kinematics {
    Mover::new(k).turn(moment, sp).kinematics()
}

/// State after one cycle with `cmd` (`predictStateAfterCommand`): a kick leaves
/// the player rolling; no command counts as the framework's illegal command, a
/// dash of power 0.01.
pub(crate) fn after_command(k: &Kinematics, cmd: Command, sp: &ServerParams) -> Kinematics {
    Mover::new(k).after(cmd, sp).kinematics()
}

/// Where a player will be after `n` cycles dashing with `power` every cycle
/// (`predictPosAfterNrCycles` for a player; power 0 is rolling out).
pub(crate) fn pos_after(k: &Kinematics, n: u32, power: f64, sp: &ServerParams) -> Vec2 {
    if power == 0.0 {
        // Rolling needs no body direction: spare its sine and cosine.
        return roll(k.pos, k.vel, n, sp);
    }
    Mover::new(k).pos_after(n, power, sp)
}

/// Where a player comes to rest without commands (`predictFinalAgentPos`).
pub(crate) fn final_pos(k: &Kinematics, sp: &ServerParams) -> Vec2 {
    k.pos + k.vel / (1.0 - sp.player_decay)
}

/// The moment to send to turn by `desired` degrees at `speed` (`getAngleForTurn`),
/// clipped to the largest moment (then the turn falls short).
pub(crate) fn angle_for_turn(desired: f64, speed: f64, sp: &ServerParams) -> f64 {
    clamp(
        desired * (1.0 + sp.inertia_moment * speed),
        sp.min_moment,
        sp.max_moment,
    )
}

/// The turn that faces `point` as seen from where the player will be after
/// `cycles` cycles of rolling (`turnBodyToPoint`).
pub(crate) fn turn_to_point(k: &Kinematics, point: Vec2, cycles: u32, sp: &ServerParams) -> Command {
    let from = pos_after(k, cycles, 0.0, sp);
    Command::Turn {
        moment: angle_for_turn(normalize_deg((point - from).dir() - k.body), k.vel.norm(), sp),
    }
}

/// The dash power to cover the projection of `rel` on the body direction in
/// `cycles` cycles (`getPowerForDash`): the first speed of a geometric series with
/// the player's decay, capped at the top speed, minus the current speed along the
/// body; clipped to the power range.
pub(crate) fn power_for_dash(rel: Vec2, body: f64, vel: Vec2, cycles: u32, sp: &ServerParams) -> f64 {
    power_along(rel, Vec2::polar(1.0, body), vel, cycles, sp)
}

/// [`power_for_dash`] with the body direction as the unit vector `u`.
fn power_along(rel: Vec2, u: Vec2, vel: Vec2, cycles: u32, sp: &ServerParams) -> f64 {
    let n = cycles.max(1);
    let mut speed = rel.dot(u) / geom_sum(sp.player_decay, n);
    if speed > sp.player_speed_max {
        speed = sp.player_speed_max;
    }
    let power = (speed - vel.dot(u)) / (sp.dash_power_rate * sp.effort);
    if power.is_nan() {
        0.0
    } else {
        clamp(power, sp.min_power, sp.max_power)
    }
}

/// The dash towards `point` (`dashToPoint`): the power that covers its
/// projection on the body direction in `cycles` cycles.
pub(crate) fn dash_to_point(k: &Kinematics, point: Vec2, cycles: u32, sp: &ServerParams) -> Command {
    Command::Dash {
        power: power_for_dash(point - k.pos, k.body, k.vel, cycles, sp),
    }
}

/// The first speed a ball needs to cover `dist` and still move at `end_speed`
/// there (the framework's `getKickSpeedToTravel`): the number of decay steps is
/// rounded to an integer, as the framework does.
pub(crate) fn kick_speed_to_travel(dist: f64, end_speed: f64, sp: &ServerParams) -> f64 {
    if end_speed < 1e-4 {
        return dist * (1.0 - sp.ball_decay);
    }
    let r = 1.0 / sp.ball_decay;
    let temp = dist * (r - 1.0) / end_speed + 1.0;
    let steps = if temp <= 0.0 { -1.0 } else { temp.ln() / r.ln() };
    end_speed * r.powf(round_ties_even(steps))
}

/// The turn, if any, that the framework makes before moving to `target` in
/// `cycles` cycles (`predictCommandTurnTowards`, never moving backwards on
/// purpose).
///
/// From where the player will be after `min(cycles, 4)` cycles of rolling, it turns
/// while the target lies more than `0.9 x kickable distance` off the body line
/// (2x beyond 10 m, 3x beyond 20 m), or farther than `dist_back` and more than
/// 90 degrees off the body direction; up to five turns are simulated and the
/// first is returned. After more than one turn, with fewer than four cycles left
/// and the target closer than `dist_back`, it turns its back to the target instead
/// if the body line then passes within `0.9 x kickable distance` of it.
///
/// The framework also requires `angTmp` to exceed the when-to-turn angle, but its
/// `angTo + (bMoveBack) ? 180 : 0` parses as `(angTo + bMoveBack) ? 180 : 0`: the
/// test only fails when the target lies exactly on the body direction, as here.
pub fn turn_towards(k: &Kinematics, target: Vec2, cycles: u32, dist_back: f64, sp: &ServerParams) -> Option<f64> {
    Mover::new(k).turn_towards(target, cycles, dist_back, sp)
}

/// The command that moves a player towards `target`, to be reached in `cycles`
/// cycles (`predictCommandToMoveToPos`): the turn of [`turn_towards`] if it asks
/// for one, otherwise the dash of [`power_for_dash`].
pub(crate) fn move_command(k: &Kinematics, target: Vec2, cycles: u32, dist_back: f64, sp: &ServerParams) -> Command {
    Mover::new(k).move_command(target, cycles, dist_back, sp)
}

/// The framework's test of a body direction when moving towards a target
/// (`predictCommandTurnTowards`): how far off the line to the target, and
/// whether that calls for a turn.
struct TurnNeed {
    /// From the position predicted after up to four cycles to the target.
    to: Vec2,
    /// The kickable distance.
    reach: f64,
    /// How many kickable distances off the line need a turn (3 beyond 20 m, 2 beyond 10 m, else 0.9).
    ratio: f64,
    /// Whether the target is beyond the dash-back distance.
    far: bool,
}

impl TurnNeed {
    /// The test for `m` moving to `target` in `cycles`, dashing back within `dist_back`.
    fn new(m: &Mover, target: Vec2, cycles: u32, dist_back: f64, sp: &ServerParams) -> Self {
        let reach = sp.kickable_distance();
        let pos_pred = m.pos_after(cycles.min(4), 0.0, sp);
        let d2 = m.pos.dist_sq(target);
        let ratio = if d2 > 400.0 {
            3.0
        } else if d2 > 100.0 {
            2.0
        } else {
            0.9
        };
        let to = target - pos_pred;
        let far = to.norm_sq() > dist_back * dist_back;
        TurnNeed { to, reach, ratio, far }
    }

    /// How far the body line along `u` passes from the target.
    fn off(&self, u: Vec2) -> f64 {
        self.to.cross(u).abs()
    }

    /// Whether facing `u` needs a turn: too far off the line, or (far away) more than 90 degrees off.
    fn needs_turn(&self, u: Vec2) -> bool {
        self.off(u) > self.ratio * self.reach || (self.far && self.to.dot(u) < 0.0)
    }

    /// Whether `u` points exactly at the target.
    fn on_direction(&self, u: Vec2) -> bool {
        self.to.cross(u) == 0.0 && self.to.dot(u) > 0.0
    }
}

impl Mover {
    /// [`turn_towards`].
    fn turn_towards(&self, target: Vec2, cycles: u32, dist_back: f64, sp: &ServerParams) -> Option<f64> {
        let need = TurnNeed::new(self, target, cycles, dist_back, sp);
        let (to, reach) = (need.to, need.reach);
        if need.on_direction(self.u) || !need.needs_turn(self.u) {
            return None;
        }
        let dir_to = to.dir();
        let first = angle_for_turn(normalize_deg(dir_to - self.body), self.vel.norm(), sp);
        // The framework simulates up to five turns, but only the first is sent,
        // and the others only tell whether more than one is needed, which matters
        // only close to the target with fewer than four cycles left.
        if cycles < 4 && to.norm_sq() < dist_back * dist_back && need.needs_turn(self.turn(first, sp).u) {
            let moment = angle_for_turn(normalize_deg(dir_to + 180.0 - self.body), self.vel.norm(), sp);
            if need.off(self.turn(moment, sp).u) < 0.9 * reach {
                return Some(moment);
            }
        }
        Some(first)
    }

    /// [`move_command`].
    pub(crate) fn move_command(&self, target: Vec2, cycles: u32, dist_back: f64, sp: &ServerParams) -> Command {
        match self.turn_towards(target, cycles, dist_back, sp) {
            Some(moment) => Command::Turn { moment },
            None => Command::Dash {
                power: power_along(target - self.pos, self.u, self.vel, cycles, sp),
            },
        }
    }
}

/// Cycles to run `dist` straight ahead at full power, starting at `speed` along
/// the body, until within the kickable distance (the framework's
/// `predictNrCyclesForDistance`): simulated until the speed settles, then
/// extrapolated. Unlike the framework, a zero final speed or an absurd distance
/// gives a large count instead of an overflow.
pub(crate) fn cycles_for_distance(dist: f64, speed: f64, sp: &ServerParams) -> u32 {
    let min_dist = sp.kickable_distance();
    let acc = sp.max_power * sp.dash_power_rate * sp.effort;
    let mut dist = dist;
    let mut speed = speed;
    let mut prev = -1.0;
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
        let more = ((dist - min_dist) / speed).ceil();
        cycles = cycles.saturating_add(if (0.0..1e6).contains(&more) {
            more as u32
        } else {
            1_000_000
        });
    }
    cycles
}

/// The largest change of velocity one dash can make (either direction).
fn dash_acceleration_limit(sp: &ServerParams) -> f64 {
    sp.max_power.abs().max(sp.min_power.abs()) * sp.dash_power_rate * sp.effort
}

/// How far a player can at most get from where it stands in each of the next
/// cycles, whatever it is commanded: a cycle's displacement is the velocity
/// after its command, at most the last cycle's bound decayed plus the largest
/// dash acceleration (either direction), capped at the top speed; the bounds are
/// kept non-decreasing, so that a constant step extrapolated from one of them
/// is covered too. [`cycles_to_point`] can then only give `n` cycles or fewer
/// (`n` below its cap on simulated cycles) for a target within the bound after
/// `n` cycles plus the kickable distance: each simulated command moves the
/// player at most one bound, and `cycles_for_distance` takes off at most one
/// per cycle (its speed follows the same recursion from no more than the
/// player's speed) and extrapolates with its last.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RunBound {
    covered: f64,
    step: f64,
    cycles: u32,
}

impl RunBound {
    /// Slack for rounding in the simulated runs (m): far more than their
    /// accumulated error, far less than anything a decision depends on.
    const ROUNDING: f64 = 1e-6;

    /// The bound for a player moving at `vel` now (no cycle run yet); `None`
    /// for a velocity that is not finite (then the estimates bound nothing).
    pub(crate) fn new(vel: Vec2) -> Option<Self> {
        let speed = vel.norm();
        speed.is_finite().then_some(RunBound {
            covered: 0.0,
            step: speed,
            cycles: 0,
        })
    }

    /// One more cycle.
    pub(crate) fn advance(&mut self, sp: &ServerParams) {
        let acc = dash_acceleration_limit(sp);
        self.step = if self.cycles == 0 {
            (self.step + acc).min(sp.player_speed_max)
        } else {
            self.step
                .max((self.step * sp.player_decay + acc).min(sp.player_speed_max))
        };
        self.cycles = self.cycles.saturating_add(1);
        self.covered += self.step;
    }

    /// Whether a target `dist` from the player could be reached (within the
    /// kickable distance `reach`) in the cycles run so far: if not,
    /// [`cycles_to_point`] estimates more cycles for it.
    pub(crate) fn may_arrive(&self, dist: f64, reach: f64) -> bool {
        self.cycles >= MAX_SIMULATED_CYCLES || !(dist.is_finite() && dist > self.covered + reach + Self::ROUNDING)
    }
}

/// Estimated cycles for a player at `k` to get within kickable distance of `target`
/// (the framework's `predictNrCyclesToPoint`).
///
/// The turns that `move_command` asks for (and braking dashes while facing more
/// than 20 degrees away) are simulated; then the framework's own agent
/// ([`Estimate::Own`]) simulates the rest of its run command by command, while
/// another player's run ([`Estimate::Other`]) is extrapolated with
/// `cycles_for_distance`. Both loops are bounded (see `MAX_SIMULATED_CYCLES`).
pub fn cycles_to_point(k: &Kinematics, target: Vec2, whose: Estimate, cfg: &KeepawayConfig) -> u32 {
    cycles_to_point_from(Mover::new(k), target, whose, cfg)
}

/// [`cycles_to_point`] from a player already made a [`Mover`] (whose body
/// direction's sine and cosine are then not computed again for every target).
pub(crate) fn cycles_to_point_from(start: Mover, target: Vec2, whose: Estimate, cfg: &KeepawayConfig) -> u32 {
    let sp = &cfg.server;
    let back = cfg.skills.intercept_dist_back;
    let reach = sp.kickable_distance();
    if target.dist(start.pos) < reach {
        return 0;
    }
    // The direction to the target matters only for a backward dash: computed then.
    let dir_des = || (target - start.pos).dir();
    let mut cur = start;
    let mut cycles = 0u32;
    loop {
        let cmd = cur.move_command(target, 1, back, sp);
        let turning = match cmd {
            Command::Turn { .. } => true,
            Command::Dash { power } => power < 0.0 && normalize_deg(cur.body - dir_des()).abs() > 20.0,
            _ => false,
        };
        if !turning || cycles >= MAX_SIMULATED_CYCLES {
            break;
        }
        cycles += 1;
        cur = cur.after(cmd, sp);
        if target.dist(cur.pos) < reach {
            return cycles;
        }
    }
    match whose {
        Estimate::Other => {
            let speed = cur.vel.dot(cur.u);
            cycles.saturating_add(cycles_for_distance(cur.pos.dist(target), speed, sp))
        }
        Estimate::Own => {
            while cur.pos.dist(target) > reach && cycles < MAX_SIMULATED_CYCLES {
                cur = cur.after(cur.move_command(target, 1, back, sp), sp);
                cycles += 1;
            }
            cycles
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tabled_geometric_sums_are_the_closed_form() {
        let sp = ServerParams::default();
        for r in [sp.ball_decay, sp.player_decay, 0.5] {
            for n in GEOM_TERMS_SUMMED + 1..100 {
                assert_eq!(
                    geom_sum(r, n).to_bits(),
                    closed_form_geom_sum(r, n).to_bits(),
                    "{r} {n}"
                );
            }
            // The term-by-term sums and the closed form agree to rounding.
            for n in 0..=GEOM_TERMS_SUMMED {
                assert!((geom_sum(r, n) - closed_form_geom_sum(r, n)).abs() < 1e-12, "{r} {n}");
            }
        }
    }

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

    #[test]
    fn turn_towards_a_point_behind() {
        let sp = ServerParams::default();
        let k = Kinematics::default();
        // Straight ahead: no turn; straight behind and far: a full turn.
        assert_eq!(turn_towards(&k, Vec2::new(5.0, 0.0), 1, 2.5, &sp), None);
        let t = turn_towards(&k, Vec2::new(-5.0, 0.0), 1, 2.5, &sp).expect("a turn");
        assert!((t.abs() - 180.0).abs() < 1e-9);
        // Just behind, within the dash-back distance: no turn (dash backwards).
        assert_eq!(turn_towards(&k, Vec2::new(-2.0, 0.0), 1, 2.5, &sp), None);
    }

    /// `predictCommandTurnTowards` as the framework writes it: up to five turns
    /// simulated, their count deciding the turn of the back to a close target.
    fn five_turn_loop(m: &Mover, target: Vec2, cycles: u32, dist_back: f64, sp: &ServerParams) -> Option<f64> {
        let need = TurnNeed::new(m, target, cycles, dist_back, sp);
        let (to, reach) = (need.to, need.reach);
        if need.on_direction(m.u) || !need.needs_turn(m.u) {
            return None;
        }
        let dir_to = to.dir();
        let (mut cur, mut first, mut turns) = (*m, None, 0);
        while need.needs_turn(cur.u) && turns < 5 {
            let moment = angle_for_turn(normalize_deg(dir_to - cur.body), cur.vel.norm(), sp);
            first.get_or_insert(moment);
            cur = cur.turn(moment, sp);
            turns += 1;
        }
        if turns > 1 && cycles < 4 && to.norm_sq() < dist_back * dist_back {
            let moment = angle_for_turn(normalize_deg(dir_to + 180.0 - m.body), m.vel.norm(), sp);
            if need.off(m.turn(moment, sp).u) < 0.9 * reach {
                return Some(moment);
            }
        }
        first
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4000))]
        /// Simulating only the turns whose count can matter gives exactly the
        /// framework's command (targets near and far, fast and slow players).
        #[test]
        fn turn_towards_is_the_framework_loop(
            x in -12.0..12.0f64, y in -12.0..12.0f64, body in -180.0..180.0f64,
            speed in 0.0..1.2f64, heading in -180.0..180.0f64,
            dx in -6.0..6.0f64, dy in -6.0..6.0f64, far in 0u8..4, cycles in 0u32..8, back in 0.0..5.0f64,
        ) {
            let sp = ServerParams::default();
            let k = Kinematics { pos: Vec2::new(x, y), vel: Vec2::polar(speed, heading), body };
            let m = Mover::new(&k);
            let scale = [0.5, 1.0, 2.0, 4.0][usize::from(far)];
            let target = k.pos + Vec2::new(dx, dy) * scale;
            let got = m.turn_towards(target, cycles, back, &sp);
            let want = five_turn_loop(&m, target, cycles, back, &sp);
            proptest::prop_assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits));
        }
    }

    #[test]
    fn own_and_other_estimates_agree_on_a_straight_run() {
        let cfg = KeepawayConfig::default();
        let k = Kinematics::default();
        let target = Vec2::new(8.0, 0.0);
        let own = cycles_to_point(&k, target, Estimate::Own, &cfg);
        let other = cycles_to_point(&k, target, Estimate::Other, &cfg);
        assert!(own.abs_diff(other) <= 1, "own {own}, other {other}");
    }
}
