//! What a Keepaway experiment is: who learns, what the agents perceive, and
//! the thresholds of the abstraction.

use serde::{Deserialize, Serialize};

use super::world::atoms;
use crate::domains::TaskError;
use crate::plan::{AllowedAtoms, Plan, catalog};
use learnpnp_keepaway::features::{DEFAULT_HOLD_THRESHOLD, FeatureThresholds};
use learnpnp_keepaway::params::{KeepawayConfig, RefereeRule, ServerTimer, VisionMode};
use learnpnp_keepaway::policies::BaselinePolicy;
use learnpnp_keepaway::world::NUM_KEEPERS;

/// The keepers' fixed decision policies (`keepaway-fixed --policy`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FixedPolicy {
    /// Uniform over hold, pass 1 and pass 2.
    Random,
    /// Always hold.
    AlwaysHold,
    /// The keepaway framework's hand-coded policy.
    #[default]
    Handcoded,
    /// The thesis's simple policy: hold until a taker is near, then pass to the safest lane.
    Threshold,
}

crate::named::impl_named!(
    FixedPolicy,
    "policy",
    [
        Random => "random",
        AlwaysHold => "always-hold",
        Handcoded => "handcoded",
        Threshold => "threshold",
    ]
);

/// Who decides what.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KeepawayMode {
    /// Keeper 1 learns the pass decision; the other two follow the threshold policy (thesis 7.2).
    Pass,
    /// All three keepers learn where to stand, each with its own values (thesis 7.3).
    Position,
    /// All three keepers follow a fixed policy; nothing learns.
    Fixed(FixedPolicy),
}

/// Keepaway's parameters beyond the simulator's defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct KeepawayDomainConfig {
    /// Who learns.
    pub mode: KeepawayMode,
    /// What the agents perceive: the framework players' perception (default),
    /// full state, or quantised vision without memory.
    pub vision: VisionMode,
    /// The soccer server's timer: real time (default) or synchronous mode.
    #[serde(default)]
    pub timer: ServerTimer,
    /// The referee's turnover rule: rcssserver 11's (default) or 9.4.5's.
    #[serde(default)]
    pub referee: RefereeRule,
    /// The thresholds of the three binary features.
    pub thresholds: FeatureThresholds,
    /// The distance at which the threshold policy passes.
    pub hold_threshold: f64,
    /// Evaluation episodes of run 0, played after its last evaluation and
    /// saved as RoboCup game logs (they change no result).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub record: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Default for KeepawayDomainConfig {
    fn default() -> Self {
        KeepawayDomainConfig {
            mode: KeepawayMode::Pass,
            vision: VisionMode::Framework,
            timer: ServerTimer::RealTime,
            referee: RefereeRule::Rcssserver11,
            thresholds: FeatureThresholds::default(),
            hold_threshold: DEFAULT_HOLD_THRESHOLD,
            record: 0,
        }
    }
}

impl KeepawayDomainConfig {
    /// The defaults of `mode`.
    pub fn for_mode(mode: KeepawayMode) -> Self {
        KeepawayDomainConfig {
            mode,
            ..KeepawayDomainConfig::default()
        }
    }

    /// The simulator's configuration.
    pub fn simulator(&self) -> KeepawayConfig {
        KeepawayConfig {
            vision: self.vision,
            timer: self.timer,
            referee: self.referee,
            ..KeepawayConfig::default()
        }
    }

    /// How many keepers learn.
    pub fn learning_keepers(&self) -> usize {
        match self.mode {
            KeepawayMode::Pass => 1,
            KeepawayMode::Position => NUM_KEEPERS,
            KeepawayMode::Fixed(_) => 0,
        }
    }

    /// The thesis's plan for the mode (none for fixed policies).
    pub fn default_plan(&self) -> Result<Option<Plan>, TaskError> {
        let net = match self.mode {
            KeepawayMode::Pass => catalog::keepaway_pass(),
            KeepawayMode::Position => catalog::keepaway_position(),
            KeepawayMode::Fixed(_) => return Ok(None),
        }
        .map_err(crate::plan::PlanError::from)?;
        Ok(Some(Plan::from_net(net, AllowedAtoms::Closed(&atoms()))?))
    }

    /// The fixed keepers' policy, drawing from `seed` where it is random.
    pub fn baseline(&self, seed: u64) -> BaselinePolicy {
        match self.mode {
            KeepawayMode::Fixed(FixedPolicy::Random) => BaselinePolicy::random(seed),
            KeepawayMode::Fixed(FixedPolicy::AlwaysHold) => BaselinePolicy::AlwaysHold,
            KeepawayMode::Fixed(FixedPolicy::Handcoded) => BaselinePolicy::HandCoded,
            _ => BaselinePolicy::Threshold {
                threshold: self.hold_threshold,
            },
        }
    }
}
