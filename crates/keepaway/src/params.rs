//! Parameters: the soccer server's physics (2005-era defaults), the keepaway
//! framework's skill settings, and the task configuration.

use super::geometry::Vec2;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A configuration value that cannot be simulated.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// A parameter is NaN or infinite.
    #[error("parameter `{0}` must be finite")]
    NotFinite(&'static str),
    /// A parameter that must be strictly positive is not.
    #[error("parameter `{0}` must be > 0")]
    NotPositive(&'static str),
    /// A parameter that must be non-negative is negative.
    #[error("parameter `{0}` must be >= 0")]
    Negative(&'static str),
    /// A decay or ratio lies outside its open interval.
    #[error("parameter `{name}` must lie in ({lo}, {hi})")]
    OutOfRange {
        /// The parameter.
        name: &'static str,
        /// Exclusive lower bound.
        lo: f64,
        /// Exclusive upper bound.
        hi: f64,
    },
    /// A minimum exceeds its maximum.
    #[error("range `{0}` is empty (min > max)")]
    EmptyRange(&'static str),
    /// An integer setting is zero or too large.
    #[error("setting `{0}` is out of its allowed range")]
    BadCount(&'static str),
}

fn finite(name: &'static str, v: f64) -> Result<f64, ConfigError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(ConfigError::NotFinite(name))
    }
}

fn positive(name: &'static str, v: f64) -> Result<(), ConfigError> {
    if finite(name, v)? > 0.0 {
        Ok(())
    } else {
        Err(ConfigError::NotPositive(name))
    }
}

fn non_negative(name: &'static str, v: f64) -> Result<(), ConfigError> {
    if finite(name, v)? >= 0.0 {
        Ok(())
    } else {
        Err(ConfigError::Negative(name))
    }
}

fn open_unit(name: &'static str, v: f64) -> Result<(), ConfigError> {
    let v = finite(name, v)?;
    if v > 0.0 && v < 1.0 {
        Ok(())
    } else {
        Err(ConfigError::OutOfRange { name, lo: 0.0, hi: 1.0 })
    }
}

/// The soccer server's parameters used by keepaway, with the 2005-era defaults
/// (rcssserver 9.x/10.x, the keepaway framework's settings; see
/// `/work/shared/reference/keepaway.md`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ServerParams {
    /// Ball radius (m).
    pub ball_size: f64,
    /// Ball velocity decay per cycle.
    pub ball_decay: f64,
    /// Ball motion noise ratio.
    pub(crate) ball_rand: f64,
    /// Ball speed cap (m/cycle).
    pub ball_speed_max: f64,
    /// Ball acceleration cap (m/cycle²).
    pub(crate) ball_accel_max: f64,
    /// Player radius (m).
    pub player_size: f64,
    /// Player velocity decay per cycle.
    pub player_decay: f64,
    /// Player motion (and turn) noise ratio.
    pub(crate) player_rand: f64,
    /// Player speed cap (m/cycle).
    pub(crate) player_speed_max: f64,
    /// Player acceleration cap (m/cycle²).
    pub(crate) player_accel_max: f64,
    /// Inertia moment: a turn is divided by `1 + inertia_moment * speed`.
    pub(crate) inertia_moment: f64,
    /// Dash power to acceleration rate.
    pub(crate) dash_power_rate: f64,
    /// Kick power to acceleration rate (before the position penalty).
    pub kick_power_rate: f64,
    /// Kickable margin beyond the two radii (m).
    pub kickable_margin: f64,
    /// Effort (1 in keepaway: stamina is effectively unlimited).
    pub(crate) effort: f64,
    /// Largest dash/kick power.
    pub(crate) max_power: f64,
    /// Smallest dash/kick power.
    pub(crate) min_power: f64,
    /// Largest turn moment and kick direction (degrees).
    pub(crate) max_moment: f64,
    /// Smallest turn moment and kick direction (degrees).
    pub(crate) min_moment: f64,
    /// Quantisation step of seen distances to moving objects.
    pub(crate) quantize_step: f64,
    /// Duration of one cycle in seconds.
    pub cycle_seconds: f64,
}

impl Default for ServerParams {
    fn default() -> Self {
        ServerParams {
            ball_size: 0.085,
            ball_decay: 0.94,
            ball_rand: 0.05,
            ball_speed_max: 2.7,
            ball_accel_max: 2.7,
            player_size: 0.3,
            player_decay: 0.4,
            player_rand: 0.1,
            player_speed_max: 1.2,
            player_accel_max: 1.0,
            inertia_moment: 5.0,
            dash_power_rate: 0.006,
            kick_power_rate: 0.027,
            kickable_margin: 0.7,
            effort: 1.0,
            max_power: 100.0,
            min_power: -100.0,
            max_moment: 180.0,
            min_moment: -180.0,
            quantize_step: 0.1,
            cycle_seconds: 0.1,
        }
    }
}

impl ServerParams {
    /// Largest ball distance (centre to centre) at which a player can kick:
    /// `player_size + ball_size + kickable_margin` (1.085 by default).
    pub fn kickable_distance(&self) -> f64 {
        self.player_size + self.ball_size + self.kickable_margin
    }

    /// Checks that every value can be simulated.
    pub fn validate(&self) -> Result<(), ConfigError> {
        positive("ball_size", self.ball_size)?;
        open_unit("ball_decay", self.ball_decay)?;
        non_negative("ball_rand", self.ball_rand)?;
        positive("ball_speed_max", self.ball_speed_max)?;
        positive("ball_accel_max", self.ball_accel_max)?;
        positive("player_size", self.player_size)?;
        open_unit("player_decay", self.player_decay)?;
        non_negative("player_rand", self.player_rand)?;
        if self.player_rand >= 1.0 {
            return Err(ConfigError::OutOfRange {
                name: "player_rand",
                lo: 0.0,
                hi: 1.0,
            });
        }
        positive("player_speed_max", self.player_speed_max)?;
        positive("player_accel_max", self.player_accel_max)?;
        non_negative("inertia_moment", self.inertia_moment)?;
        positive("dash_power_rate", self.dash_power_rate)?;
        positive("kick_power_rate", self.kick_power_rate)?;
        positive("kickable_margin", self.kickable_margin)?;
        positive("effort", self.effort)?;
        finite("max_power", self.max_power)?;
        finite("min_power", self.min_power)?;
        if self.min_power > self.max_power || self.max_power <= 0.0 {
            return Err(ConfigError::EmptyRange("power"));
        }
        finite("max_moment", self.max_moment)?;
        finite("min_moment", self.min_moment)?;
        if self.min_moment > self.max_moment {
            return Err(ConfigError::EmptyRange("moment"));
        }
        positive("quantize_step", self.quantize_step)?;
        positive("cycle_seconds", self.cycle_seconds)?;
        Ok(())
    }
}

/// The play region: a `length` x `width` rectangle centred at the origin.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Region {
    /// Extent along x (m); keepaway_length, 20 by default.
    pub length: f64,
    /// Extent along y (m); keepaway_width, 20 by default.
    pub width: f64,
}

impl Default for Region {
    fn default() -> Self {
        Region {
            length: 20.0,
            width: 20.0,
        }
    }
}

impl Region {
    /// Half the length.
    pub(crate) fn half_length(&self) -> f64 {
        self.length * 0.5
    }

    /// Half the width.
    pub(crate) fn half_width(&self) -> f64 {
        self.width * 0.5
    }

    /// The centre (the origin).
    pub(crate) fn centre(&self) -> Vec2 {
        Vec2::ZERO
    }

    /// Whether `p` is strictly inside (the referee's test: `|x| < L/2 && |y| < W/2`).
    pub(crate) fn contains(&self, p: Vec2) -> bool {
        p.x.abs() < self.half_length() && p.y.abs() < self.half_width()
    }
}

/// How agents perceive the world.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum VisionMode {
    /// What the keepaway framework's players knew, as the thesis's system ran
    /// them: the server's see messages (360 degrees, quantised, every 150 ms, so
    /// in two cycles of three) and body senses, the framework's world model
    /// between sees, and the ball heard from teammates
    /// ([`super::perception::Perception`], [`super::see`], [`super::world_model`]).
    #[default]
    Framework,
    /// Exact positions and velocities of everything, every cycle (the server's
    /// noise-free full state).
    FullState,
    /// The era's quantised vision every cycle (360 degrees), without memory.
    Quantised,
}

crate::named::impl_named!(
    VisionMode,
    "vision",
    [
        Framework => "framework",
        FullState => "full-state",
        Quantised => "quantised",
    ]
);

/// The soccer server's timer (its `synch_mode` parameter): when the players'
/// see messages arrive within a step and when they act
/// ([`super::timing`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ServerTimer {
    /// Real time (`synch_mode=0`, rcssserver's `StandardTimer`), as the
    /// framework's `keepaway.sh` runs the server by default: the players
    /// synchronise their sees before the first kick-off and act at 70% or 85%
    /// of the step.
    #[default]
    RealTime,
    /// Synchronous mode (`synch_mode=1`, `SyncTimer`, with `keepaway.sh`'s
    /// `synch_offset=80`): the players act on the server's think message, 80
    /// ms into the step, and do not synchronise their sees.
    Synchronous,
}

crate::named::impl_named!(
    ServerTimer,
    "server timer",
    [
        RealTime => "real-time",
        Synchronous => "synchronous",
    ]
);

/// The keepaway referee's turnover rule (rcssserver's `KeepawayRef`), named by
/// the server version whose rule it is ([`super::referee::Referee::check`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum RefereeRule {
    /// rcssserver 10.0.4 and later (the oldest source in the server's history,
    /// 11.1's `src/referee.cc`): a turnover after 4 cycles of taker possession
    /// (`KeepawayRef::TURNOVER_TIME = 4`), possession within
    /// `ServerParam::kickableArea()` (player_size + ball_size + kickable_margin).
    #[default]
    Rcssserver11,
    /// rcssserver 9.4.5, the server keepaway 0.6's README names: a turnover after
    /// 5 cycles. The server's NEWS for 10.0.4: "Fixed defect #1222134 in which
    /// the kickable area used to decide possession in KeepawayRef was too small.
    /// Also changed the number of consecutive cycles in which a taker must touch
    /// the ball to declare a turnover from 5 to 4." The 9.4.5 source is not in
    /// the server's history (it starts at 11.1) nor in any public source found,
    /// so its smaller possession area is not known: the area stays the kickable
    /// area, and only the count is 9.4.5's.
    Rcssserver9_4_5,
}

impl RefereeRule {
    /// Cycles of taker possession that end an episode (the server's `TURNOVER_TIME`).
    pub fn turnover_time(self) -> u32 {
        match self {
            RefereeRule::Rcssserver11 => super::referee::TURNOVER_TIME,
            RefereeRule::Rcssserver9_4_5 => 5,
        }
    }
}

crate::named::impl_named!(
    RefereeRule,
    "referee",
    [
        Rcssserver11 => "rcssserver-11",
        Rcssserver9_4_5 => "rcssserver-9.4.5",
    ]
);

/// The keepaway framework's skill settings (its `PlayerSettings` defaults and the
/// constants of its keepaway skills).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SkillParams {
    /// Turn instead of dash when a target is more than this many degrees off (7).
    pub(crate) when_to_turn_deg: f64,
    /// Fraction of the best kick rate/speed above which a too-far kick is still
    /// taken or the ball frozen instead of repositioned (0.85).
    pub(crate) when_to_kick: f64,
    /// Horizon, in cycles, of interception searches (30).
    pub(crate) intercept_horizon: u32,
    /// Target dash-back distance used when moving to an interception point (2.5 m).
    pub(crate) intercept_dist_back: f64,
    /// Speed at which a pass should arrive at the receiver (1.2 m/cycle).
    pub(crate) pass_end_speed: f64,
    /// Keepers' hold: ball kept at `player_size + ball_size + ratio * kickable_margin`
    /// (0.7, i.e. 0.875 m).
    pub keeper_hold_ratio: f64,
    /// Takers' hold ratio (0.3, i.e. 0.595 m).
    pub(crate) taker_hold_ratio: f64,
    /// Hold: an opponent closer than this to the ball makes the holder shield it (5 m).
    pub(crate) hold_opponent_radius: f64,
    /// Hold: ball considered in place when this close to the framework's test point
    /// (see [`crate::skills::hold_ball`]) (0.3 m).
    pub hold_tolerance: f64,
    /// Get open: within this distance of the chosen point, just face the ball (1.5 m).
    pub(crate) get_open_buffer: f64,
    /// Get open: border of the candidate grid as a fraction of the region (0.15).
    pub(crate) get_open_border: f64,
    /// Get open: candidate points per axis (5).
    pub(crate) get_open_grid: u32,
    /// Pass cone: half-width ratio (width = ratio x distance along the line) (0.3).
    pub pass_cone_width: f64,
}

impl Default for SkillParams {
    fn default() -> Self {
        SkillParams {
            when_to_turn_deg: 7.0,
            when_to_kick: 0.85,
            intercept_horizon: 30,
            intercept_dist_back: 2.5,
            pass_end_speed: 1.2,
            keeper_hold_ratio: 0.7,
            taker_hold_ratio: 0.3,
            hold_opponent_radius: 5.0,
            hold_tolerance: 0.3,
            get_open_buffer: 1.5,
            get_open_border: 0.15,
            get_open_grid: 5,
            pass_cone_width: 0.3,
        }
    }
}

impl SkillParams {
    /// Checks that every value is usable.
    pub fn validate(&self) -> Result<(), ConfigError> {
        non_negative("when_to_turn_deg", self.when_to_turn_deg)?;
        open_unit("when_to_kick", self.when_to_kick)?;
        if self.intercept_horizon == 0 || self.intercept_horizon > 1000 {
            return Err(ConfigError::BadCount("intercept_horizon"));
        }
        non_negative("intercept_dist_back", self.intercept_dist_back)?;
        non_negative("pass_end_speed", self.pass_end_speed)?;
        non_negative("keeper_hold_ratio", self.keeper_hold_ratio)?;
        non_negative("taker_hold_ratio", self.taker_hold_ratio)?;
        if self.keeper_hold_ratio > 1.0 || self.taker_hold_ratio > 1.0 {
            return Err(ConfigError::OutOfRange {
                name: "hold_ratio",
                lo: 0.0,
                hi: 1.0,
            });
        }
        non_negative("hold_opponent_radius", self.hold_opponent_radius)?;
        non_negative("hold_tolerance", self.hold_tolerance)?;
        non_negative("get_open_buffer", self.get_open_buffer)?;
        non_negative("get_open_border", self.get_open_border)?;
        if self.get_open_border >= 0.5 {
            return Err(ConfigError::OutOfRange {
                name: "get_open_border",
                lo: 0.0,
                hi: 0.5,
            });
        }
        if self.get_open_grid < 2 || self.get_open_grid > 64 {
            return Err(ConfigError::BadCount("get_open_grid"));
        }
        non_negative("pass_cone_width", self.pass_cone_width)?;
        Ok(())
    }
}

/// Everything that defines a keepaway task. 3 keepers vs 2 takers is fixed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct KeepawayConfig {
    /// Server physics.
    pub server: ServerParams,
    /// The play region.
    pub region: Region,
    /// How agents perceive the world.
    pub vision: VisionMode,
    /// The server's timer, which fixes when see messages arrive
    /// ([`VisionMode::Framework`] only).
    #[serde(default)]
    pub timer: ServerTimer,
    /// The referee's turnover rule.
    #[serde(default)]
    pub referee: RefereeRule,
    /// Motion and turn noise on (the server's behaviour) or off.
    pub motion_noise: bool,
    /// The framework's skill settings.
    pub skills: SkillParams,
    /// A safety cap: an episode reaching this many cycles ends with
    /// [`super::referee::EndReason::CycleLimit`]. `None` means no cap.
    pub max_episode_cycles: Option<u32>,
}

impl Default for KeepawayConfig {
    fn default() -> Self {
        KeepawayConfig {
            server: ServerParams::default(),
            region: Region::default(),
            vision: VisionMode::Framework,
            timer: ServerTimer::RealTime,
            referee: RefereeRule::Rcssserver11,
            motion_noise: true,
            skills: SkillParams::default(),
            max_episode_cycles: Some(100_000),
        }
    }
}

impl KeepawayConfig {
    /// Checks the whole configuration.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.server.validate()?;
        self.skills.validate()?;
        positive("region.length", self.region.length)?;
        positive("region.width", self.region.width)?;
        // The reset places players up to 3 m inside the corners and the ball 4 m inside.
        if self.region.length <= 8.0 || self.region.width <= 8.0 {
            return Err(ConfigError::OutOfRange {
                name: "region",
                lo: 8.0,
                hi: f64::INFINITY,
            });
        }
        if self.region.length > 1000.0 || self.region.width > 1000.0 {
            return Err(ConfigError::OutOfRange {
                name: "region",
                lo: 8.0,
                hi: 1000.0,
            });
        }
        if self.max_episode_cycles == Some(0) {
            return Err(ConfigError::BadCount("max_episode_cycles"));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        assert_eq!(KeepawayConfig::default().validate(), Ok(()));
        assert!((ServerParams::default().kickable_distance() - 1.085).abs() < 1e-12);
    }

    #[test]
    fn bad_values_are_rejected() {
        let mut c = KeepawayConfig::default();
        c.server.ball_decay = 1.0;
        assert!(c.validate().is_err());
        let mut c = KeepawayConfig::default();
        c.server.player_size = f64::NAN;
        assert_eq!(c.validate(), Err(ConfigError::NotFinite("player_size")));
        let mut c = KeepawayConfig::default();
        c.region.width = 5.0;
        assert!(c.validate().is_err());
        let mut c = KeepawayConfig::default();
        c.skills.intercept_horizon = 0;
        assert!(c.validate().is_err());
    }
}
