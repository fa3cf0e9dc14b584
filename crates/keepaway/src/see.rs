//! What the soccer server tells each player, as the keepaway framework's players
//! received it: what a see message carries, and the body sense of every
//! cycle. This is the server's side of [`super::params::VisionMode::Framework`](crate::params::VisionMode::Framework);
//! [`super::timing`](crate::timing) says when the sees come, and [`super::world_model`](crate::world_model) is
//! the player's side.
//!
//! Sources: rcssserver 11.1, the oldest in its git history (the framework 0.6's
//! README recommends 9.4.5; the NEWS and ChangeLog entries from 9.4.5 to 11.1
//! change nothing used here, and 12 to 19 behave the same), with the
//! framework's `keepaway.sh`, which sets `visible_angle=360` and leaves
//! `send_step` (150 ms) alone, so every see shows the whole field:
//! - content: `VisualSenderPlayerV1::sendHighBall`, `sendHighPlayer` and
//!   `calcVel`, `VisualSenderPlayerV8::serializePlayer` (`visual.cc`; the
//!   server gives protocols 8 to 11 this sender), `calcQuantDist`,
//!   `calcBodyDir` and the rounding `rad2Deg` of protocol 7 and later
//!   (`visual.h`; the framework speaks protocol 9.3, `main.cc`);
//! - body sense: `BodySenderPlayerV6::sendVelocity` (`bodysender.cc`), sent
//!   every `sense_body_step` (100 ms, `stdtimer.cc`).

use super::geometry::{Vec2, normalize_deg, quantize, round_ties_even, sin_cos_deg};
use super::params::{KeepawayConfig, ServerParams};
use super::view::PlayerId;
use super::world::{FieldState, NUM_PLAYERS, Player};
use crate::rng::SimRng;
use rand::RngExt;
use std::sync::LazyLock;

/// Beyond this quantised distance a player's number (and the ball's or a
/// player's velocity) may be left out (`UNUM_FAR_LENGTH`, m).
const UNUM_FAR_LENGTH: f64 = 20.0;
/// Beyond this quantised distance they are always left out (`UNUM_TOOFAR_LENGTH`, m).
const UNUM_TOOFAR_LENGTH: f64 = 40.0;
/// Quantisation of the relative distance change ratio (`calcVel`).
const DIST_CHANGE_STEP: f64 = 0.02;
/// Quantisation of the direction change, degrees (`quantize_step_dir`, `DIR_QSTEP`).
const DIR_CHANGE_STEP: f64 = 0.1;
/// Outer quantisation of distances (`calcQuantDist`).
const DIST_STEP: f64 = 0.1;
/// Quantisation of the body sense's speed (`sendVelocity`).
const SPEED_STEP: f64 = 0.01;

/// One object in a see message, relative to the viewer's neck (taken as
/// aligned with its body).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seen {
    /// Quantised distance, m.
    pub(crate) dist: f64,
    /// Direction, whole degrees.
    pub(crate) dir: f64,
    /// Distance change (m/cycle) and direction change (degrees/cycle), when sent.
    pub(crate) change: Option<(f64, f64)>,
    /// Body direction relative to the viewer's, whole degrees (players with
    /// their number only).
    pub body: Option<f64>,
}

/// A player in a see message.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SeenMate {
    /// What was seen.
    pub(crate) seen: Seen,
    /// Whether the player's number was given (otherwise only its team).
    pub(crate) numbered: bool,
}

/// A see message: the ball and every other player (360-degree vision shows
/// all of them every time).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SeeMessage {
    /// The ball.
    pub ball: Seen,
    /// Players by global index; `None` at the viewer's own index.
    pub(crate) players: [Option<SeenMate>; NUM_PLAYERS],
}

/// The server's quantised distance: `Q(exp(Q(ln(d + EPS), qstep)), 0.1)`.
///
/// The inner quantisation leaves `k x qstep` for a whole `k`; for the server's
/// default `qstep` the rest is read from [`DEFAULT_STEP_DISTANCES`], which holds
/// its computed values for every `k` a distance on a pitch can give.
pub(crate) fn quantised_distance(d: f64, qstep: f64) -> f64 {
    const EPS: f64 = 1e-10;
    let k = round_ties_even((d + EPS).ln() / qstep);
    let table = &*DEFAULT_STEP_DISTANCES;
    if qstep == table.qstep {
        // Saturating; the bit comparison keeps only exact whole steps.
        let whole = k as i32;
        if f64::from(whole).to_bits() == k.to_bits()
            && let Some(&dist) = whole
                .checked_sub(MIN_LOG_STEP)
                .and_then(|i| usize::try_from(i).ok())
                .and_then(|i| table.dists.get(i))
        {
            return dist;
        }
    }
    outer_quantised_distance(k, qstep)
}

/// The outer part of [`quantised_distance`] for the inner step count `k`.
fn outer_quantised_distance(k: f64, qstep: f64) -> f64 {
    quantize((k * qstep).exp(), DIST_STEP)
}

/// The smallest step count in [`DEFAULT_STEP_DISTANCES`]: `ln(EPS) / 0.1` is
/// about -230, at distance 0.
const MIN_LOG_STEP: i32 = -240;
/// Step counts in [`DEFAULT_STEP_DISTANCES`], up to `ln(1800 m) / 0.1`, far
/// beyond any pitch.
const LOG_STEPS: usize = 316;

/// [`outer_quantised_distance`] of every step count from [`MIN_LOG_STEP`], for one `qstep`.
struct StepDistances {
    qstep: f64,
    dists: [f64; LOG_STEPS],
}

/// The step distances of the server's default `quantize_step`.
static DEFAULT_STEP_DISTANCES: LazyLock<StepDistances> = LazyLock::new(|| {
    let qstep = ServerParams::default().quantize_step;
    let mut dists = [0.0; LOG_STEPS];
    for (k, dist) in (MIN_LOG_STEP..).zip(dists.iter_mut()) {
        *dist = outer_quantised_distance(f64::from(k), qstep);
    }
    StepDistances { qstep, dists }
});

/// Direction of `rel` relative to `neck`, rounded to whole degrees.
pub(crate) fn relative_direction(rel: Vec2, neck: f64) -> f64 {
    round_ties_even(normalize_deg(rel.dir() - neck))
}

/// The server's distance and direction changes of an object at `rel` (from the
/// viewer) moving at `vrel` relative to the viewer, seen at quantised distance
/// `dq` (`calcVel`; `(0, 0)` for an object at the viewer's position).
pub(crate) fn change(rel: Vec2, vrel: Vec2, dq: f64) -> (f64, f64) {
    let d = rel.norm();
    if d <= 0.0 {
        return (0.0, 0.0);
    }
    let e = rel / d;
    let radial = vrel.dot(e);
    let tangential_deg = (e.x * vrel.y - e.y * vrel.x) / d * 180.0 / std::f64::consts::PI;
    let dir_chg = if tangential_deg == 0.0 {
        0.0
    } else {
        quantize(tangential_deg, DIR_CHANGE_STEP)
    };
    (dq * quantize(radial / d, DIST_CHANGE_STEP), dir_chg)
}

/// The server's `decide(prob)`: true for `prob >= 1`, false for `prob <= 0`,
/// otherwise a draw. Without a generator only the certain cases are true.
fn decide(prob: f64, rng: Option<&mut SimRng>) -> bool {
    if prob >= 1.0 {
        true
    } else if prob <= 0.0 || prob.is_nan() {
        false
    } else {
        rng.is_some_and(|r| r.random::<f64>() < prob)
    }
}

/// What `viewer` sees of an object at `pos` moving at `vel`.
fn observe(viewer: &Player, pos: Vec2, vel: Vec2, qstep: f64, with_change: bool) -> Seen {
    let rel = pos - viewer.pos;
    let dist = quantised_distance(rel.norm(), qstep);
    Seen {
        dist,
        dir: relative_direction(rel, viewer.body),
        change: with_change.then(|| change(rel, vel - viewer.vel, dist)),
        body: None,
    }
}

/// Player `me`'s see message of `world`. Beyond 20 m (quantised) the server
/// leaves out, with probability `(d - 20) / 20`, the ball's velocity or a
/// player's number, velocity and body direction; `rng` draws these (without
/// it they are left out only where certain, beyond 40 m). Beyond 40 m it
/// leaves out a player's team too, which is not modelled: the region's
/// diagonal is 28 m.
pub fn see(world: &FieldState, me: PlayerId, cfg: &KeepawayConfig, mut rng: Option<&mut SimRng>) -> SeeMessage {
    let viewer = &world.players[me.index()];
    let qstep = cfg.server.quantize_step;
    let far =
        |d: f64, rng: Option<&mut SimRng>| decide((d - UNUM_FAR_LENGTH) / (UNUM_TOOFAR_LENGTH - UNUM_FAR_LENGTH), rng);
    let mut ball = observe(viewer, world.ball.pos, world.ball.vel, qstep, true);
    if far(ball.dist, rng.as_deref_mut()) {
        ball.change = None;
    }
    let mut players = [None; NUM_PLAYERS];
    for (i, (slot, p)) in players.iter_mut().zip(world.players.iter()).enumerate() {
        if i == me.index() {
            continue;
        }
        let mut seen = observe(viewer, p.pos, p.vel, qstep, true);
        let numbered = !far(seen.dist, rng.as_deref_mut());
        if numbered {
            seen.body = Some(round_ties_even(normalize_deg(p.body - viewer.body)));
        } else {
            seen.change = None;
        }
        *slot = Some(SeenMate { seen, numbered });
    }
    SeeMessage { ball, players }
}

/// The body sense's velocity: speed to 0.01 and direction relative to the neck
/// (taken as aligned with the body) in whole degrees, truncated towards zero
/// (`Rad2IDeg`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SenseBody {
    /// Speed, m/cycle.
    pub(crate) speed: f64,
    /// Direction relative to the neck, degrees.
    pub(crate) dir: f64,
}

impl SenseBody {
    /// The velocity relative to the neck as a vector.
    pub(crate) fn velocity(&self) -> Vec2 {
        // `Vec2::polar`, with the sine and cosine of the whole degree from a table.
        let (s, c) = sin_cos_deg(self.dir);
        Vec2::new(self.speed * c, self.speed * s)
    }
}

/// Player `me`'s body sense of `world`.
pub(crate) fn sense_body(world: &FieldState, me: PlayerId) -> SenseBody {
    let p = &world.players[me.index()];
    SenseBody {
        speed: quantize(p.vel.norm(), SPEED_STEP),
        dir: normalize_deg(p.vel.dir() - p.body).trunc(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::seeded;

    fn world() -> FieldState {
        let mut w = FieldState::default();
        w.players[0].pos = Vec2::new(-5.0, 0.0);
        w.players[0].body = 30.0;
        w.players[1].pos = Vec2::new(5.0, 3.0);
        w.players[1].vel = Vec2::new(0.2, -0.1);
        w.players[1].body = -45.0;
        w.players[2].pos = Vec2::new(20.0, 0.0);
        w.players[3].pos = Vec2::new(-5.0, 2.0);
        w.players[4].pos = Vec2::new(40.0, 0.0);
        w.ball.pos = Vec2::new(0.0, 1.0);
        w.ball.vel = Vec2::new(1.0, 0.5);
        w
    }

    #[test]
    fn see_quantises_as_the_server() {
        let w = world();
        let me = PlayerId::keeper(0).expect("keeper 0");
        let m = see(&w, me, &KeepawayConfig::default(), None);
        assert!(m.players[0].is_none());
        let ball = m.ball;
        let d = (26.0f64).sqrt();
        assert!((ball.dist - quantised_distance(d, 0.1)).abs() < 1e-12);
        assert!((ball.dist * 10.0 - (ball.dist * 10.0).round()).abs() < 1e-9);
        assert_eq!(ball.dir, (Vec2::new(5.0, 1.0).dir() - 30.0).round());
        let (dist_chg, dir_chg) = ball.change.expect("change info");
        assert!((dist_chg / ball.dist * 50.0 - (dist_chg / ball.dist * 50.0).round()).abs() < 1e-9);
        assert!((dir_chg * 10.0 - (dir_chg * 10.0).round()).abs() < 1e-9);
        let mate = m.players[1].expect("keeper 1");
        assert!(mate.numbered);
        assert_eq!(mate.seen.body, Some(-75.0));
        // 25 m: the number is left out with probability 0.25; without draws never.
        assert!(m.players[2].is_some_and(|p| p.numbered));
        // 45 m: always left out, with the velocity and the body direction.
        let far = m.players[4].expect("taker 1");
        assert!(!far.numbered && far.seen.change.is_none() && far.seen.body.is_none());
    }

    proptest::proptest! {
        /// The table of the default step gives the server's formula, bit for bit.
        #[test]
        fn quantised_distances_are_the_formulas(d in 0.0..2000.0f64, tiny in 0.0..1e-6f64, qstep in 0.01..0.2f64) {
            let formula = |d: f64, q: f64| quantize(quantize((d + 1e-10).ln(), q).exp(), DIST_STEP);
            for (d, q) in [(d, 0.1), (tiny, 0.1), (d, qstep)] {
                proptest::prop_assert_eq!(quantised_distance(d, q).to_bits(), formula(d, q).to_bits());
            }
        }
    }

    #[test]
    fn far_numbers_are_left_out_at_the_servers_rate() {
        let w = world();
        let me = PlayerId::keeper(0).expect("keeper 0");
        let cfg = KeepawayConfig::default();
        let mut rng = seeded(3);
        let n = 4000;
        let left_out = (0..n)
            .filter(|_| see(&w, me, &cfg, Some(&mut rng)).players[2].is_some_and(|p| !p.numbered))
            .count();
        let q = quantised_distance(25.0, 0.1);
        let p = (q - 20.0) / 20.0;
        let rate = left_out as f64 / f64::from(n);
        assert!((rate - p).abs() < 0.03, "rate {rate}, expected {p}");
    }

    #[test]
    fn body_sense_truncates_the_direction() {
        let mut w = world();
        w.players[0].vel = Vec2::polar(0.456, 30.0 + 12.7);
        let s = sense_body(&w, PlayerId::keeper(0).expect("keeper 0"));
        assert!((s.speed - 0.46).abs() < 1e-12);
        assert_eq!(s.dir, 12.0);
        w.players[0].vel = Vec2::polar(0.3, 30.0 - 12.7);
        assert_eq!(sense_body(&w, PlayerId::keeper(0).expect("keeper 0")).dir, -12.0);
    }
}
