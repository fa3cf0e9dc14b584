//! What a framework player believes: the keepaway framework's world model (UvA
//! Trilearn's `WorldModel`, `WorldModelUpdate.cc`, as the framework ships it) fed
//! with the server's messages ([`super::see`](crate::see)), and the corrections it applies
//! to a view in the memoryless vision modes (`believed`).
//!
//! [`WorldModel`](crate::world_model::WorldModel) is one player's model in
//! [`super::params::VisionMode::Framework`](crate::params::VisionMode::Framework): after every body sense it predicts
//! the cycle ([`WorldModel::after_sense`](crate::world_model::WorldModel::after_sense)), after a heard teammate's message it
//! may take the ball from it ([`WorldModel::hear`](crate::world_model::WorldModel::hear)), after a see message it
//! takes what it saw ([`WorldModel::after_see`](crate::world_model::WorldModel::after_see)); [`WorldModel::view`](crate::world_model::WorldModel::view) is what
//! the player's skills then work with, and [`WorldModel::say`](crate::world_model::WorldModel::say) what it tells
//! its teammates. Each rule names the framework function it follows.
//!
//! Not modelled, and why:
//! - self-localisation from flags and lines (`calculateStateAgent`, its particle
//!   filter): after a see, one's own position and body direction are taken
//!   exactly (the simulator has no landmarks; the framework's estimate, from
//!   landmarks quantised ten times finer than players, is close, and every
//!   relative quantity the skills use is seen directly);
//! - the neck: taken as aligned with the body, so the body sense's velocity
//!   direction and every seen direction are relative to the body (with
//!   360-degree vision the neck only changes which directions get rounded);
//! - the ball's velocity from two seen positions (`calculateStateBall` without
//!   change information within 3 m): the server sends change information for
//!   any ball nearer than 20 m, so this branch cannot arise;
//! - the positions heard from teammates (`OurPos`, `OppPos`): they replace a
//!   belief only when it is older than a cycle (confidence below 0.99 or
//!   0.98), and every player is seen at least every other cycle;
//! - a player the model drops (a number-less player it cannot map,
//!   `mapUnknownPlayers`, then `removeGhosts`), or maps to an empty slot: the
//!   view has no place for "unknown", so it keeps its last belief there;
//! - the search for a lost ball (confidence below 0.90): with 360-degree vision
//!   the ball is in every see, and its confidence never falls below 0.99 except
//!   before the first see of an episode, which [`super::perception::Perception`](crate::perception::Perception)
//!   gives every player in the episode's first cycle;
//! - goalie catches, set plays and the kick-off, which keepaway does not have.
//!
//! Where the framework's decisions use the model's times, the skills here do
//! not: a [`PlayerView`](crate::view::PlayerView) carries no cycle of the last see. The framework
//! estimates another player's cycles to a point from its state at the last see,
//! counting the cycles since (`predictNrCyclesToPoint`), and reuses the intercept
//! features (who is fastest to the ball) found after the last see until the
//! next one (`isFeatureRelevant`); the skills work from the model's belief of
//! the current cycle every cycle. The model itself keeps the opponent feature
//! as the framework does, for its own prediction.

use super::command::Command;
use super::geometry::{Vec2, normalize_deg};
use super::params::{KeepawayConfig, ServerParams, VisionMode};
use super::see::{SeeMessage, SenseBody};
use super::skills::fastest::{BallEstimates, fastest_among};
use super::skills::predict::{Kinematics, RunBound, after_command, ball_pos_after};
use super::view::{PlayerId, PlayerView, SeenBall, SeenPlayer};
use super::world::{NUM_PLAYERS, Side};

/// Confidence lost per cycle since an object was last seen
/// (`Object::getConfidence`: `1 - cycles / 100`).
const CONFIDENCE_PER_CYCLE: f64 = 0.01;
/// Below this confidence a player counts as unknown (`PlayerSettings`:
/// `dPlayerConfThr`): it is neither predicted nor in any set the model searches.
pub(crate) const PLAYER_CONFIDENCE_THRESHOLD: f64 = 0.88;
/// Below this confidence the ball counts as lost (`dBallConfThr`; the framework's
/// keepers and takers then search for it).
pub const BALL_CONFIDENCE_THRESHOLD: f64 = 0.90;
/// Largest distance at which a number-less player is mapped to a known one
/// (`dPlayerDistTolerance`).
const PLAYER_DIST_TOLERANCE: f64 = 7.5;
/// `EPSILON` of the framework's geometry (`Geometry.h`).
const EPSILON: f64 = 0.0001;
/// Step an opponent fastest to the ball is moved towards it per predicted cycle
/// (`updateDynamicObjectForNextCycle`).
const FASTEST_OPPONENT_STEP: f64 = 0.3;
/// A heard ball replaces the belief when its velocity differs by more than this
/// (`WMBallInfo::process`, `processPerfectHearInfoBall`).
const HEARD_VELOCITY_DIFFERENCE: f64 = 0.3;
/// Within this distance the framework ignores a heard ball (`WMBallInfo::process`:
/// the visible distance).
const HEARD_BALL_MIN_DISTANCE: f64 = 3.0;
/// The decay the framework applies to a heard ball (`WMBallInfo::process`, a literal).
const HEARD_BALL_DECAY: f64 = 0.94;
/// Largest distance of a seen ball the framework passes on
/// (`KeepawayPlayer::makeSayMessage`).
const SAID_BALL_MAX_DISTANCE: f64 = 20.0;
/// The visible distance (`visible_distance`): a ball this close is "felt".
const VISIBLE_DISTANCE: f64 = 3.0;
/// Extra distance beyond the kickable one at which a kicked ball counts as
/// passed (`makeSayMessage`).
const PASSED_MARGIN: f64 = 0.2;

/// The say message's encoding of one number (`SayMsgDataTypes.h`): 73
/// characters over `[lo, lo + width)`, the value floored into its bin and
/// decoded as the bin's lower edge.
fn say_encoding(v: f64, lo: f64, width: f64) -> f64 {
    const CHARS: f64 = 73.0;
    let bin = ((v - lo) / width * CHARS).trunc().clamp(0.0, CHARS - 1.0);
    bin / CHARS * width + lo
}

/// Confidence of an object last seen at `seen`, at `now` (`Object::getConfidence`).
fn confidence(seen: Option<u32>, now: u32) -> f64 {
    seen.map_or(0.0, |s| {
        (1.0 - f64::from(now.saturating_sub(s)) * CONFIDENCE_PER_CYCLE).max(0.0)
    })
}

/// The world model's record of the ball or another player.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Belief {
    /// Global position.
    pos: Vec2,
    /// Global velocity.
    vel: Vec2,
    /// Global body direction (players).
    body: f64,
    /// Cycle last seen (`None`: never, or forgotten).
    seen: Option<u32>,
    /// Cycle of the position (`getTimeGlobalPosition`).
    at: u32,
    /// Cycle of the last distance and direction change (`getTimeChangeInformation`).
    changed: Option<u32>,
}

impl Belief {
    const UNKNOWN: Belief = Belief {
        pos: Vec2::ZERO,
        vel: Vec2::ZERO,
        body: 0.0,
        seen: None,
        at: 0,
        changed: None,
    };

    fn confidence(&self, now: u32) -> f64 {
        confidence(self.seen, now)
    }
}

/// A ball a teammate said it saw (`BallInfo`): position and velocity as the
/// say message encodes them, and how many cycles old it is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SaidBall {
    /// Global position (encoded to about a metre).
    pub pos: Vec2,
    /// Global velocity (encoded to 0.074 m/cycle).
    pub vel: Vec2,
    /// Cycles between the information and the hearing (0 for a ball just kicked away).
    pub cycles: u32,
}

/// One player's world model (the framework's `WorldModel`, restricted to what
/// keepaway uses), in the simulator's coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldModel {
    me: PlayerId,
    own: SeenPlayer,
    ball: Belief,
    players: [Belief; NUM_PLAYERS],
    /// The agent kicked in the last cycle (`m_bPerformedKick`).
    kicked: bool,
    /// The opponent fastest to the ball, as the model's intercept features last
    /// found it, and the see it was found after (`createInterceptFeatures`).
    fastest_opponent: Option<(Option<usize>, Option<u32>)>,
    /// The cycle of the last see message.
    last_see: Option<u32>,
}

impl WorldModel {
    /// A model that has seen nothing (after the framework's `resetEpisode`).
    pub fn new(me: PlayerId) -> Self {
        WorldModel {
            me,
            own: SeenPlayer::default(),
            ball: Belief::UNKNOWN,
            players: [Belief::UNKNOWN; NUM_PLAYERS],
            kicked: false,
            fastest_opponent: None,
            last_see: None,
        }
    }

    /// The ball's confidence at `now` (its threshold is [`BALL_CONFIDENCE_THRESHOLD`]).
    pub fn ball_confidence(&self, now: u32) -> f64 {
        self.ball.confidence(now)
    }

    /// Player `i`'s confidence at `now` (one's own is 1; the threshold is
    /// [`PLAYER_CONFIDENCE_THRESHOLD`]).
    pub(crate) fn player_confidence(&self, i: usize, now: u32) -> f64 {
        if i == self.me.index() {
            1.0
        } else {
            self.players.get(i).map_or(0.0, |p| p.confidence(now))
        }
    }

    /// Whether player `i` is in the model's sets at `now` (`iterateObjectNext`).
    fn known(&self, i: usize, now: u32) -> bool {
        i != self.me.index() && self.player_confidence(i, now) >= PLAYER_CONFIDENCE_THRESHOLD
    }

    /// The player's own side.
    fn side(&self) -> Side {
        self.me.side()
    }

    /// What the model holds, as the view its player's skills work with.
    pub fn view(&self, cycle: u32) -> PlayerView {
        let mut players = [SeenPlayer::default(); NUM_PLAYERS];
        for (i, (out, b)) in players.iter_mut().zip(self.players.iter()).enumerate() {
            *out = if i == self.me.index() {
                self.own
            } else {
                SeenPlayer {
                    pos: b.pos,
                    vel: b.vel,
                    body: b.body,
                }
            };
        }
        PlayerView {
            cycle,
            me: self.me,
            ball: SeenBall {
                pos: self.ball.pos,
                vel: self.ball.vel,
            },
            players,
        }
    }

    /// The ball after one cycle without a kick (`updateDynamicObjectForNextCycle`
    /// for the ball): it rolls and decays, and stands still if the opponent
    /// closest to where it was has it within the kickable distance of where it goes.
    fn roll_ball(&mut self, now: u32, sp: &ServerParams) {
        let pos = self.ball.pos + self.ball.vel;
        let mut vel = self.ball.vel * sp.ball_decay;
        if let Some(o) = self.closest_opponent_to(self.ball.pos, now)
            && pos.dist(self.players[o].pos) < sp.kickable_distance()
        {
            vel = Vec2::ZERO;
        }
        self.ball.pos = pos;
        self.ball.vel = vel;
        self.ball.at = now;
    }

    /// The known opponent closest to `p` (`getClosestInSetTo`, ties to the first).
    fn closest_opponent_to(&self, p: Vec2, now: u32) -> Option<usize> {
        self.side()
            .opponent()
            .indices()
            .filter(|&o| self.known(o, now))
            .fold(None::<(usize, f64)>, |best, o| {
                let d = self.players[o].pos.dist(p);
                match best {
                    Some((_, bd)) if bd <= d => best,
                    _ => Some((o, d)),
                }
            })
            .map(|(o, _)| o)
    }

    /// The ball after one's own kick `power`, `direction`
    /// (`predictBallInfoAfterCommand`): the kick rate from the believed ball, the
    /// speed capped. The framework truncates the arguments to integers here, as
    /// its command strings do (`SoccerCommand::makeKickCommand`); this simulator
    /// executes commands as sent, so the prediction takes them as sent.
    fn ball_after_kick(&self, power: f64, direction: f64, sp: &ServerParams) -> (Vec2, Vec2) {
        let rel = self.ball.pos - self.own.pos;
        let dir_diff = normalize_deg(rel.dir() - self.own.body).abs();
        let gap = rel.norm() - sp.player_size - sp.ball_size;
        let rate = sp.kick_power_rate * (1.0 - 0.25 * dir_diff / 180.0 - 0.25 * gap / sp.kickable_margin);
        let mut vel = self.ball.vel + Vec2::polar(rate * power, normalize_deg(direction + self.own.body));
        if vel.norm() > sp.ball_speed_max {
            vel = vel.with_norm(sp.ball_speed_max);
        }
        (self.ball.pos + vel, vel * sp.ball_decay)
    }

    /// The body sense of cycle `now`, after `sent` was executed in the cycle
    /// before (`updateAfterSenseMessage`):
    /// - oneself (`updateAgentAndBallAfterSense`): the turn or dash predicted
    ///   (`predictStateAfterCommand`, no noise); unless a collision shows (the
    ///   sensed velocity nearly zero or reversed against the predicted one, near
    ///   the ball), the position moves by the sensed velocity before its decay
    ///   and the velocity is the sensed one, both turned by the predicted body;
    /// - the ball: after one's own kick as the kick predicts it (if the ball was
    ///   within the kickable distance), otherwise rolled
    ///   (`updateDynamicObjectForNextCycle`); after a collision with it, put 0.2
    ///   m from oneself with its velocity times -0.1 (`updateBallForCollision`);
    /// - every other known player, for each cycle since its position
    ///   (`updateDynamicObjectForNextCycle`): a teammate rolls out, except
    ///   teammate number 1 (the goalie slot), which stays; the opponent fastest
    ///   to the ball moves 0.3 m towards it; any other opponent moves 0.25 m
    ///   (0.5 m if the ball is faster than 1 m/cycle along x) along one's own x
    ///   axis, forwards if the ball moves forwards, otherwise backwards.
    pub fn after_sense(&mut self, sense: &SenseBody, sent: Command, now: u32, cfg: &KeepawayConfig) {
        let sp = &cfg.server;
        let start = Kinematics {
            pos: self.own.pos,
            vel: self.own.vel,
            body: self.own.body,
        };
        let mut predicted = start;
        self.kicked = false;
        match sent {
            Command::Turn { .. } | Command::Dash { .. } if sent.is_finite() => {
                predicted = after_command(&start, sent, sp);
            }
            Command::Kick { power, direction } if sent.is_finite() => {
                self.kicked = true;
                if (self.ball.pos - self.own.pos).norm() < sp.kickable_distance() {
                    let (pos, vel) = self.ball_after_kick(power, direction, sp);
                    self.ball.pos = pos;
                    self.ball.vel = vel;
                    self.ball.at = now;
                } else {
                    self.roll_ball(now, sp);
                }
            }
            _ => {}
        }
        if !self.kicked {
            self.roll_ball(now, sp);
        }
        // The sensed velocity, relative to the (predicted) neck.
        let neck = predicted.body.to_radians().sin_cos();
        let relative = sense.velocity();
        let sensed = relative.rotate_by(neck);
        let to_ball = predicted.pos.dist(self.ball.pos);
        let opposite = |p: f64, s: f64| (p > 0.0) != (s > 0.0) || p.abs() < 0.08;
        let collided = (sensed.norm() < EPSILON && predicted.vel.norm() > 0.01 && to_ball < 0.8)
            || (to_ball < sp.player_size + sp.ball_size && sensed.norm() < EPSILON)
            || (to_ball < sp.kickable_distance() + 0.5
                && sensed.norm() > EPSILON
                && opposite(predicted.vel.x, sensed.x)
                && opposite(predicted.vel.y, sensed.y)
                && sensed.norm() < 0.25 * predicted.vel.norm());
        if collided {
            let nearest_player = (0..NUM_PLAYERS)
                .filter(|&i| self.known(i, now))
                .map(|i| self.players[i].pos.dist(start.pos))
                .fold(1000.0, f64::min);
            if to_ball < nearest_player {
                let dir = (self.ball.pos - predicted.pos).dir();
                self.ball.pos = predicted.pos + Vec2::polar(0.2, dir);
                self.ball.vel *= -0.1;
            }
            self.own = SeenPlayer {
                pos: predicted.pos,
                vel: sensed,
                body: predicted.body,
            };
        } else {
            let mut vel = relative.with_norm(sense.speed / sp.player_decay).rotate_by(neck);
            if vel.norm() > sp.player_speed_max {
                vel = vel.with_norm(sp.player_speed_max);
            }
            self.own = SeenPlayer {
                pos: start.pos + vel,
                vel: vel * sp.player_decay,
                body: predicted.body,
            };
        }
        self.predict_players(now, cfg);
    }

    /// The other players' part of [`WorldModel::after_sense`].
    fn predict_players(&mut self, now: u32, cfg: &KeepawayConfig) {
        let sp = &cfg.server;
        let side = self.side();
        let goalie_slot = side.indices().start;
        let fastest = self.fastest_opponent_feature(now, cfg);
        let ball_pos = self.ball.pos;
        // The ball's velocity along one's own x axis.
        let ball_vx = side.own_frame(self.ball.vel).x;
        for i in 0..NUM_PLAYERS {
            if !self.known(i, now) {
                continue;
            }
            let b = self.players[i];
            let cycles = now.saturating_sub(b.at);
            let (mut pos, mut vel) = (b.pos, b.vel);
            if Side::of(i) == side {
                if i != goalie_slot {
                    for _ in 0..cycles {
                        pos += vel;
                        vel *= sp.player_decay;
                    }
                }
            } else {
                let step = if fastest == Some(i) {
                    Vec2::polar(FASTEST_OPPONENT_STEP, (ball_pos - b.pos).dir())
                } else if ball_vx > 0.0 {
                    side.own_frame(Vec2::new(if ball_vx > 1.0 { 0.5 } else { 0.25 }, 0.0))
                } else {
                    side.own_frame(Vec2::new(if ball_vx < -1.0 { -0.5 } else { -0.25 }, 0.0))
                };
                for _ in 0..cycles {
                    pos += step;
                    vel *= sp.player_decay;
                }
            }
            self.players[i].pos = pos;
            self.players[i].vel = vel;
            self.players[i].at = now;
        }
    }

    /// The opponent fastest to the ball (the model's
    /// `FEATURE_FASTEST_OPPONENT_TO_BALL`): found again unless it was found
    /// after the last see and one has not kicked since (`isFeatureRelevant`).
    fn fastest_opponent_feature(&mut self, now: u32, cfg: &KeepawayConfig) -> Option<usize> {
        if let Some((fastest, see)) = self.fastest_opponent
            && see == self.last_see
            && !self.kicked
        {
            return fastest;
        }
        let fastest = fastest_opponent(&self.view(now), |i| self.known(i, now), cfg);
        self.fastest_opponent = Some((fastest, self.last_see));
        fastest
    }

    /// The framework's keepers find the intercept features when they decide
    /// without the ball kickable (`getFastestInSetTo` in `KeepawayPlayer::keeper`);
    /// this records the opponent part for the next body sense.
    pub fn decided(&mut self, now: u32, cfg: &KeepawayConfig) {
        if self.side() != Side::Keepers {
            return;
        }
        let view = self.view(now);
        if view.ball_kickable(cfg) {
            return;
        }
        if self.fastest_opponent.is_some_and(|(_, see)| see == self.last_see) {
            return;
        }
        let fastest = fastest_opponent(&view, |i| self.known(i, now), cfg);
        self.fastest_opponent = Some((fastest, self.last_see));
    }

    /// A teammate's message heard at cycle `now` with `ball` in it
    /// (`WMBallInfo::process`): the ball, rolled over its age, replaces the
    /// belief when the ball was never seen, or farther than 3 m has had no change
    /// information for more than 3 cycles, or for more cycles than the message's
    /// age and moves more than 0.3 m/cycle differently; then
    /// (`processPerfectHearInfoBall`) if the belief's confidence is below the
    /// message's or the velocities differ by more than 0.3 m/cycle.
    pub fn hear(&mut self, ball: &SaidBall, now: u32) {
        let (mut pos, mut vel) = (ball.pos, ball.vel);
        for _ in 0..ball.cycles {
            pos += vel;
            vel *= HEARD_BALL_DECAY;
        }
        let far = self.ball.pos.dist(self.own.pos) > HEARD_BALL_MIN_DISTANCE;
        let changed_before = |cycles: u32| self.ball.changed.is_none_or(|c| c < now.saturating_sub(cycles));
        let differs = vel.dist(self.ball.vel) > HEARD_VELOCITY_DIFFERENCE;
        let take =
            self.ball.seen.is_none() || (changed_before(3) && far) || (changed_before(ball.cycles) && differs && far);
        if !take {
            return;
        }
        // `getConfidenceFromTimeDiff(cycles) - 0.01`, dated by `getTimeFromConfidence`.
        let conf = (1.0 - f64::from(ball.cycles) * CONFIDENCE_PER_CYCLE).max(0.0) - 0.01;
        if self.ball.confidence(now) < conf || differs {
            let age = ((1.0 - conf) * 100.0) as u32;
            self.ball.pos = pos;
            self.ball.vel = vel;
            self.ball.seen = Some(now.saturating_sub(age));
            self.ball.at = now.saturating_sub(age);
            // A heard message makes the intercept features stale.
            self.fastest_opponent = None;
        }
    }

    /// A see message of cycle `now` (`updateAfterSeeMessage`):
    /// - oneself: `own` exactly (see the module's notes), with the body sense's
    ///   velocity turned by the body (`updateAgentObjectAfterSee`);
    /// - each player seen with its number (`calculateStatePlayer`): its position;
    ///   its velocity from the distance and direction changes
    ///   (`calculateVelocityDynamicObject`), capped at `player_speed_max` when
    ///   above `(1 + player_rand) x player_speed_max`; its body direction;
    /// - each player seen without its number (`mapUnknownPlayers`): given to the
    ///   known player of that team, not seen in this message, whose belief is
    ///   closest, if closer than 7.5 m and than 1.2 m per cycle since it was seen
    ///   plus 2 m; it then has that position, no velocity and the unknown body
    ///   direction (-1000 degrees in one's own frame);
    /// - a known player not in the message: see `remove_ghosts`;
    /// - the ball (`calculateStateBall`): its position; with change
    ///   information, its velocity from it, averaged with the predicted one when
    ///   both components are within `2 x ball_rand x` the predicted speed of it;
    ///   without, the predicted velocity; then stopped if a known opponent has it
    ///   within the kickable distance (strictly) while one does not, or else
    ///   capped at `ball_speed_max` above `(1 + ball_rand) x ball_speed_max`.
    pub fn after_see(&mut self, see: &SeeMessage, own: &SeenPlayer, sense: &SenseBody, now: u32, cfg: &KeepawayConfig) {
        let sp = &cfg.server;
        self.last_see = Some(now);
        self.own = SeenPlayer {
            pos: own.pos,
            vel: sense.velocity().rotate(own.body),
            body: own.body,
        };
        let side = self.side();
        let own_vel = self.own.vel;
        // Each seen object's global direction as a unit vector, used for both
        // its position and its velocity (`polar(d, a)` is `polar(1, a) * d`).
        let direction = |dir: f64| Vec2::polar(1.0, dir + own.body);
        let global = |dist: f64, u: Vec2| own.pos + u * dist;
        let velocity = |dist: f64, u: Vec2, (dist_chg, dir_chg): (f64, f64)| {
            let perp = Vec2::new(-u.y, u.x);
            own_vel + u * dist_chg + perp * (dir_chg.to_radians() * dist)
        };
        let seen_at_start = self.players.map(|b| b.seen);
        let mut unnumbered = Vec::new();
        for (i, mate) in see.players.iter().enumerate() {
            let Some(mate) = mate else { continue };
            let s = &mate.seen;
            let u = direction(s.dir);
            if !mate.numbered {
                unnumbered.push((Side::of(i), global(s.dist, u)));
                continue;
            }
            let b = &mut self.players[i];
            b.pos = global(s.dist, u);
            if let Some(chg) = s.change {
                b.vel = velocity(s.dist, u, chg);
                b.changed = Some(now);
            }
            if b.vel.norm() >= (1.0 + sp.player_rand) * sp.player_speed_max {
                b.vel = b.vel.with_norm(sp.player_speed_max);
            }
            if let Some(body) = s.body {
                b.body = normalize_deg(own.body + body);
            }
            b.seen = Some(now);
            b.at = now;
        }
        for (team, pos) in unnumbered {
            let candidate = team
                .indices()
                .filter(|&i| {
                    i != self.me.index()
                        && confidence(seen_at_start[i], now) > PLAYER_CONFIDENCE_THRESHOLD
                        && self.players[i].seen != Some(now)
                })
                .map(|i| (i, pos.dist(self.players[i].pos)))
                .fold(None::<(usize, f64)>, |best, (i, d)| match best {
                    Some((_, bd)) if bd <= d => best,
                    _ => Some((i, d)),
                });
            if let Some((i, d)) = candidate {
                let since = self.players[i].seen.map_or(now, |s| now.saturating_sub(s));
                let max_travel = f64::from(since) * sp.player_speed_max;
                if d < PLAYER_DIST_TOLERANCE && d < max_travel + 2.0 {
                    let b = &mut self.players[i];
                    b.pos = pos;
                    b.vel = Vec2::ZERO;
                    b.body = normalize_deg(side.frame_dir() - 1000.0);
                    b.changed = None;
                    b.seen = Some(now);
                    b.at = now;
                }
            }
        }
        let ball = &see.ball;
        let u = direction(ball.dir);
        let pos = global(ball.dist, u);
        let predicted = self.ball.vel;
        let mut vel = predicted;
        if let Some(chg) = ball.change {
            vel = velocity(ball.dist, u, chg);
            let band = 2.0 * sp.ball_rand * predicted.norm();
            if (vel.x - predicted.x).abs() <= band && (vel.y - predicted.y).abs() <= band {
                vel = (vel + predicted) / 2.0;
            }
            self.ball.changed = Some(now);
        }
        let reach = sp.kickable_distance();
        let opponent_has_it = side
            .opponent()
            .indices()
            .any(|o| self.known(o, now) && self.players[o].pos.dist(pos) < reach);
        if opponent_has_it && ball.dist > reach {
            vel = Vec2::ZERO;
        } else if vel.norm() > (1.0 + sp.ball_rand) * sp.ball_speed_max {
            vel = vel.with_norm(sp.ball_speed_max);
        }
        self.ball.pos = pos;
        self.ball.vel = vel;
        self.ball.seen = Some(now);
        self.ball.at = now;
        self.remove_ghosts(now, sp);
    }

    /// Known players a see message left out (`removeGhosts`). The framework
    /// checks a cone of 0.65 times its normal half view (45 degrees, whatever the
    /// server's `visible_angle`) around the neck: a teammate in it is forgotten;
    /// an opponent in it within 20 degrees of its edge is moved to the edge of the
    /// normal view at its distance, if it could have got there, and one deeper
    /// in is forgotten. An opponent believed within the visible distance is put
    /// at that distance. Players outside the cone keep their belief.
    fn remove_ghosts(&mut self, now: u32, sp: &ServerParams) {
        const HALF_VIEW: f64 = 45.0;
        let cone = HALF_VIEW - 0.35 * HALF_VIEW;
        let own = self.own;
        let neck = own.body;
        for i in 0..NUM_PLAYERS {
            if !self.known(i, now) || self.players[i].seen == Some(now) {
                continue;
            }
            let b = self.players[i];
            let rel = b.pos - own.pos;
            let rel_angle = normalize_deg(rel.dir() - neck);
            if Side::of(i) == self.side() {
                if rel_angle.abs() < cone {
                    self.players[i].seen = None;
                }
                continue;
            }
            if rel_angle.abs() < cone {
                let mut towards = rel.dir();
                if normalize_deg(towards - neck).abs() < 10.0 && b.changed.is_some_and(|c| now.saturating_sub(c) < 4) {
                    towards = (b.pos + Vec2::polar(2.0, b.body) - own.pos).dir();
                }
                let edge = if normalize_deg(towards - neck) > 0.0 {
                    neck + HALF_VIEW
                } else {
                    neck - HALF_VIEW
                };
                if rel_angle.abs() + 20.0 > cone {
                    let moved = own.pos + Vec2::polar(rel.norm(), edge);
                    let since = b.seen.map_or(now, |s| now.saturating_sub(s));
                    if moved.dist(b.pos) < f64::from(since) * sp.player_speed_max {
                        self.players[i].pos = moved;
                        self.players[i].at = now;
                    }
                } else {
                    self.players[i].seen = None;
                }
            }
            let b = self.players[i];
            if b.pos.dist(own.pos) < VISIBLE_DISTANCE {
                self.players[i].pos = own.pos + Vec2::polar(VISIBLE_DISTANCE, (b.pos - own.pos).dir());
                self.players[i].at = now;
            }
        }
    }

    /// What the player tells its teammates about the ball with its command
    /// `sent` (`KeepawayPlayer::makeSayMessage`), if anything: when it saw the
    /// ball this cycle (with change information within 20 m, or within 3 m), or
    /// its kick sends the ball out of its reach. A kick that sends the ball more
    /// than 0.2 m beyond the kickable distance from where the player will be is
    /// told as the ball after the kick (age 0); a ball within reach otherwise as
    /// standing still; any other as believed (age 1). The numbers are encoded as
    /// the say message encodes them, in the player's own frame.
    pub fn say(&self, sent: Command, now: u32, cfg: &KeepawayConfig) -> Option<SaidBall> {
        let sp = &cfg.server;
        let reach = sp.kickable_distance();
        let dist = self.ball.pos.dist(self.own.pos);
        let me = Kinematics {
            pos: self.own.pos,
            vel: self.own.vel,
            body: self.own.body,
        };
        let kick = match sent {
            Command::Kick { power, direction } if sent.is_finite() => Some(self.ball_after_kick(power, direction, sp)),
            _ => None,
        };
        let seen_now = self.ball.seen == Some(now);
        let told = (self.ball.changed == Some(now) && dist < SAID_BALL_MAX_DISTANCE && seen_now)
            || (dist < VISIBLE_DISTANCE && seen_now)
            || (dist < reach && {
                let ball_after = kick.map_or(self.ball.pos + self.ball.vel, |(p, _)| p);
                ball_after.dist(after_command(&me, sent, sp).pos) > reach
            });
        if !told {
            return None;
        }
        let (mut pos, mut vel, mut cycles) = (self.ball.pos, self.ball.vel, 1);
        if dist < reach {
            match kick {
                Some((p, v)) if p.dist(self.own.pos + own_roll(&me, sp)) > reach + PASSED_MARGIN => {
                    (pos, vel, cycles) = (p, v, 0);
                }
                _ => vel = Vec2::ZERO,
            }
        }
        let side = self.side();
        let (p, v) = (side.own_frame(pos), side.own_frame(vel));
        let encoded_pos = Vec2::new(say_encoding(p.x, -53.0, 106.0), say_encoding(p.y, -34.0, 68.0));
        let encoded_vel = Vec2::new(say_encoding(v.x, -2.7, 5.4), say_encoding(v.y, -2.7, 5.4));
        Some(SaidBall {
            pos: side.own_frame(encoded_pos),
            vel: side.own_frame(encoded_vel),
            cycles,
        })
    }
}

/// Where one's own position moves in one cycle without a command
/// (`predictAgentPos(1, 0)`: the velocity, capped at `player_speed_max`).
fn own_roll(me: &Kinematics, sp: &ServerParams) -> Vec2 {
    if me.vel.norm() > sp.player_speed_max {
        me.vel.with_norm(sp.player_speed_max)
    } else {
        me.vel
    }
}

/// The opponent of `view`'s player fastest to the ball, as the framework's
/// `createInterceptFeatures` finds `FEATURE_FASTEST_OPPONENT_TO_BALL`: for `i =
/// 0, 1, ...` up to the interception horizon, the ball's position after `i`
/// cycles and, among the known opponents who may reach it in `i` cycles, the one
/// with the fewest estimated cycles (ties to the first); the first `i` at which
/// that estimate is at most `i` decides, else the last one found at the horizon.
///
/// Only the estimates that can decide are made: at each `i`, those of the
/// opponents who could possibly arrive within `i` cycles ([`RunBound`]; any other
/// estimates more than `i`, so can neither end the search nor be the fewest
/// where it ends); and if none ends it, those of the last `i` at which any
/// opponent was estimated, found from the horizon down. A test compares this
/// with the framework's search, every estimate made.
pub(crate) fn fastest_opponent(
    view: &PlayerView,
    known: impl Fn(usize) -> bool,
    cfg: &KeepawayConfig,
) -> Option<usize> {
    let sp = &cfg.server;
    let horizon = cfg.skills.intercept_horizon.min(1000);
    let reach = sp.kickable_distance();
    let opponents = view.side().opponent().indices();
    let mut known_opponent = [false; NUM_PLAYERS];
    let mut bounds = [None; NUM_PLAYERS];
    for j in opponents.clone().filter(|&j| known(j)) {
        known_opponent[j] = true;
        bounds[j] = RunBound::new(view.players[j].vel);
    }
    let may_reach = |j: usize, target: Vec2, i: u32| {
        known_opponent[j] && view.players[j].pos.dist(target) / sp.player_speed_max < f64::from(i) + 1.0
    };
    let mut estimates = BallEstimates::default();
    for i in 0..=horizon {
        let target = ball_pos_after(&view.ball, i, sp);
        let may_arrive = |j: usize| {
            may_reach(j, target, i) && bounds[j].is_none_or(|b| b.may_arrive(view.players[j].pos.dist(target), reach))
        };
        let fastest = fastest_among(opponents.clone().filter(|&j| may_arrive(j)), |j| {
            estimates.cycles_to_ball_after(view, j, i, cfg)
        });
        if let Some((j, c)) = fastest
            && c <= i
        {
            return Some(j);
        }
        for b in bounds.iter_mut().flatten() {
            b.advance(sp);
        }
    }
    (0..=horizon).rev().find_map(|i| {
        let target = ball_pos_after(&view.ball, i, sp);
        fastest_among(opponents.clone().filter(|&j| may_reach(j, target, i)), |j| {
            estimates.cycles_to_ball_after(view, j, i, cfg)
        })
        .map(|(j, _)| j)
    })
}

/// The view as the framework's world model holds it after a see message, for
/// the memoryless vision modes (full state and quantised):
/// - a ball within the kickable distance of an opponent (strictly closer), while
///   not within one's own, is taken to stand still ("opponent has it": the
///   opponent will stop or keep it, so its roll-out is no target);
/// - a ball seen faster than `(1 + ball_rand) x ball_speed_max` is slowed to
///   `ball_speed_max`.
///
/// In [`VisionMode::Framework`] views come from a [`WorldModel`], which applies
/// these rules itself (`calculateStateBall`), so the view is returned unchanged.
pub fn believed(view: &PlayerView, cfg: &KeepawayConfig) -> PlayerView {
    if cfg.vision == VisionMode::Framework {
        return *view;
    }
    let sp = &cfg.server;
    let reach = sp.kickable_distance();
    let ball = view.ball.pos;
    let mut out = *view;
    if view.opponents().any(|(_, o)| o.pos.dist(ball) < reach) && view.own().pos.dist(ball) > reach {
        out.ball.vel = Vec2::ZERO;
    } else if view.ball.vel.norm() > (1.0 + sp.ball_rand) * sp.ball_speed_max {
        out.ball.vel = view.ball.vel.with_norm(sp.ball_speed_max);
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::view::{PlayerId, SeenBall, SeenPlayer};

    fn view(me: usize, ball: Vec2, taker: Vec2) -> PlayerView {
        let mut players = [SeenPlayer::default(); 5];
        for (i, p) in players.iter_mut().enumerate() {
            p.pos = Vec2::new(10.0 * i as f64 - 20.0, 8.0);
        }
        players[3].pos = taker;
        PlayerView {
            cycle: 0,
            me: PlayerId::new(me).expect("valid id"),
            ball: SeenBall {
                pos: ball,
                vel: Vec2::new(1.0, 0.0),
            },
            players,
        }
    }

    fn full_state() -> KeepawayConfig {
        KeepawayConfig {
            vision: VisionMode::FullState,
            ..KeepawayConfig::default()
        }
    }

    #[test]
    fn a_ball_an_opponent_controls_stands_still() {
        let cfg = full_state();
        // Keeper 0 far away, taker 3 next to the ball: the keeper takes it as still.
        let v = view(0, Vec2::new(0.5, 0.0), Vec2::ZERO);
        assert_eq!(believed(&v, &cfg).ball.vel, Vec2::ZERO);
        // The taker itself sees the ball move (no opponent has it).
        let t = view(3, Vec2::new(0.5, 0.0), Vec2::ZERO);
        assert_eq!(believed(&t, &cfg).ball.vel, t.ball.vel);
        // Out of the taker's reach: the ball moves.
        let far = view(0, Vec2::new(2.0, 0.0), Vec2::ZERO);
        assert_eq!(believed(&far, &cfg).ball.vel, far.ball.vel);
        // The framework's world model has done this already.
        let fw = KeepawayConfig::default();
        assert_eq!(fw.vision, VisionMode::Framework);
        assert_eq!(believed(&v, &fw), v);
    }

    /// The framework's search for the fastest opponent, every estimate made
    /// (what [`fastest_opponent`] prunes).
    pub(crate) fn fastest_opponent_exhaustive(
        view: &PlayerView,
        known: impl Fn(usize) -> bool,
        cfg: &KeepawayConfig,
    ) -> Option<usize> {
        let horizon = cfg.skills.intercept_horizon.min(1000);
        let mut fastest = None;
        for i in 0..=horizon {
            let target = ball_pos_after(&view.ball, i, &cfg.server);
            let mut min = 100u32;
            for j in view.side().opponent().indices().filter(|&j| known(j)) {
                if view.players[j].pos.dist(target) / cfg.server.player_speed_max < f64::from(i) + 1.0 {
                    let c = crate::skills::fastest::cycles_of(view, j, target, cfg);
                    if c < min {
                        min = c;
                        fastest = Some(j);
                    }
                }
            }
            if min <= i {
                break;
            }
        }
        fastest
    }

    #[test]
    fn confidence_decays_by_a_hundredth_per_cycle() {
        assert_eq!(confidence(None, 5), 0.0);
        assert_eq!(confidence(Some(5), 5), 1.0);
        assert!((confidence(Some(5), 17) - 0.88).abs() < 1e-12);
        assert!(confidence(Some(5), 18) < PLAYER_CONFIDENCE_THRESHOLD);
        assert!(confidence(Some(5), 15) >= BALL_CONFIDENCE_THRESHOLD);
        assert!(confidence(Some(5), 16) < BALL_CONFIDENCE_THRESHOLD);
        assert_eq!(confidence(Some(0), 500), 0.0);
    }

    /// A model of `me` that knows `world` exactly, as seen at `world.cycle`.
    fn knowing(world: &crate::world::FieldState, me: usize) -> WorldModel {
        let id = PlayerId::new(me).expect("valid id");
        let mut m = WorldModel::new(id);
        let now = world.cycle;
        for (i, (b, p)) in m.players.iter_mut().zip(world.players.iter()).enumerate() {
            if i != me {
                *b = Belief {
                    pos: p.pos,
                    vel: p.vel,
                    body: p.body,
                    seen: Some(now),
                    at: now,
                    changed: Some(now),
                };
            }
        }
        let p = &world.players[me];
        m.own = SeenPlayer {
            pos: p.pos,
            vel: p.vel,
            body: p.body,
        };
        m.ball = Belief {
            pos: world.ball.pos,
            vel: world.ball.vel,
            seen: Some(now),
            at: now,
            changed: Some(now),
            ..Belief::UNKNOWN
        };
        m.last_see = Some(now);
        m
    }

    fn spread_world() -> crate::world::FieldState {
        let mut w = crate::world::FieldState::default();
        for (i, p) in w.players.iter_mut().enumerate() {
            p.pos = Vec2::new(-8.0 + 4.0 * i as f64, 8.0);
        }
        w.ball.pos = Vec2::new(-6.0, -6.0);
        w.ball.vel = Vec2::new(1.5, 0.4);
        w
    }

    #[test]
    fn a_free_rolling_ball_is_predicted_exactly() {
        use crate::see::sense_body;
        let cfg = KeepawayConfig {
            motion_noise: false,
            ..KeepawayConfig::default()
        };
        let mut w = spread_world();
        let mut m = knowing(&w, 1);
        let mut rng = crate::rng::seeded(0);
        for _ in 0..10 {
            w.physics_step(&[Command::None; NUM_PLAYERS], &cfg.server, false, &mut rng);
            m.after_sense(&sense_body(&w, m.me), Command::None, w.cycle, &cfg);
            let v = m.view(w.cycle);
            assert!(v.ball.pos.dist(w.ball.pos) < 1e-12, "cycle {}", w.cycle);
            assert!(v.ball.vel.dist(w.ball.vel) < 1e-12);
            assert_eq!(v.own().pos, w.players[1].pos);
        }
    }

    #[test]
    fn others_are_predicted_as_the_framework_does() {
        use crate::see::sense_body;
        let cfg = KeepawayConfig::default();
        let mut w = spread_world();
        w.players[0].vel = Vec2::new(0.2, 0.0);
        w.players[2].vel = Vec2::new(0.0, -0.3);
        // Taker 3 is nearest the ball and gets there first.
        w.players[3].pos = Vec2::new(-3.0, -5.0);
        let start = w;
        let mut m = knowing(&w, 1);
        w.cycle = 1;
        m.after_sense(&sense_body(&w, m.me), Command::None, 1, &cfg);
        let v = m.view(1);
        // Keeper 0 holds the goalie's slot: not predicted.
        assert_eq!(v.players[0].pos, start.players[0].pos);
        // Keeper 2 rolls out.
        assert!(v.players[2].pos.dist(start.players[2].pos + Vec2::new(0.0, -0.3)) < 1e-12);
        assert!(v.players[2].vel.dist(Vec2::new(0.0, -0.3 * 0.4)) < 1e-12);
        // The fastest taker steps 0.3 m towards the ball; the other 0.5 m along
        // the ball's x direction (faster than 1 m/cycle).
        let towards = (start.ball.pos + start.ball.vel - start.players[3].pos).with_norm(0.3);
        assert!(v.players[3].pos.dist(start.players[3].pos + towards) < 1e-9);
        assert!(v.players[4].pos.dist(start.players[4].pos + Vec2::new(0.5, 0.0)) < 1e-12);
        // A taker's keepers move along the taker's own x axis: ours reversed.
        let mut t = knowing(&start, 4);
        t.after_sense(&sense_body(&w, t.me), Command::None, 1, &cfg);
        let tv = t.view(1);
        let moved: Vec<Vec2> = (0..3).map(|i| tv.players[i].pos - start.players[i].pos).collect();
        assert!(
            moved.iter().filter(|d| d.dist(Vec2::new(0.5, 0.0)) < 1e-12).count() >= 2,
            "{moved:?}"
        );
    }

    #[test]
    fn players_unseen_too_long_are_no_longer_predicted() {
        use crate::see::sense_body;
        let cfg = KeepawayConfig::default();
        let mut w = spread_world();
        w.players[2].vel = Vec2::new(0.0, -0.3);
        let mut m = knowing(&w, 1);
        let mut last = w.players[4].pos;
        for c in 1..=20 {
            w.cycle = c;
            m.after_sense(&sense_body(&w, m.me), Command::None, c, &cfg);
            let conf = m.player_confidence(4, c);
            assert!((conf - (1.0 - f64::from(c) / 100.0)).abs() < 1e-12);
            // Twelve cycles at 0.01 each reach the threshold 0.88; then it stops.
            let pos = m.view(c).players[4].pos;
            assert_eq!(pos != last, c <= 12, "cycle {c}");
            last = pos;
        }
    }

    #[test]
    fn a_heard_pass_replaces_the_ball() {
        let w = spread_world();
        let mut m = knowing(&w, 0);
        let said = SaidBall {
            pos: Vec2::new(0.0, 0.0),
            vel: Vec2::new(2.0, 0.0),
            cycles: 0,
        };
        // Seen with change information this cycle: the message is not used.
        m.hear(&said, 0);
        assert_eq!(m.view(0).ball.pos, w.ball.pos);
        // A cycle later it is: dated a cycle back.
        m.hear(&said, 1);
        assert_eq!(m.view(1).ball.pos, said.pos);
        assert_eq!(m.ball.seen, Some(0));
        assert!((m.ball_confidence(1) - 0.99).abs() < 1e-12);
    }

    #[test]
    fn a_kick_away_is_said_as_the_ball_after_it() {
        let cfg = KeepawayConfig::default();
        let mut w = spread_world();
        w.ball.pos = w.players[0].pos + Vec2::new(0.6, 0.0);
        w.ball.vel = Vec2::ZERO;
        let m = knowing(&w, 0);
        let kick = Command::Kick {
            power: 100.0,
            direction: 0.0,
        };
        let said = m.say(kick, 0, &cfg).expect("a pass is said");
        assert_eq!(said.cycles, 0);
        assert!(said.vel.x > 1.5);
        // Holding (a gentle tap keeping it in reach) is said as a still ball.
        let tap = Command::Kick {
            power: 2.0,
            direction: 0.0,
        };
        let held = m.say(tap, 0, &cfg).expect("a seen ball is said");
        assert_eq!(
            (held.vel, held.cycles),
            (Vec2::new(-2.7 + 36.0 * 5.4 / 73.0, -2.7 + 36.0 * 5.4 / 73.0), 1)
        );
    }

    #[test]
    fn say_encoding_floors_into_73_bins() {
        // 106 m over 73 characters: 1.452 m bins, decoded at their lower edge.
        let x = say_encoding(0.0, -53.0, 106.0);
        assert!(x <= 0.0 && x > -106.0 / 73.0);
        assert_eq!(say_encoding(-60.0, -53.0, 106.0), -53.0);
        assert!(say_encoding(60.0, -53.0, 106.0) < 53.0);
        let v = say_encoding(1.2, -2.7, 5.4);
        assert!(v <= 1.2 && v > 1.2 - 5.4 / 73.0);
    }
}
