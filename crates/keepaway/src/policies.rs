//! Baseline decisions for the keeper with the ball.

use super::features::{DEFAULT_HOLD_THRESHOLD, FRAMEWORK_NEAR_RADIUS, PassLineDistances};
use super::keeper::{KeeperAction, KeeperPolicy};
use super::params::KeepawayConfig;
use super::state_vars::StateVars;
use super::view::PlayerView;
use crate::rng::{SimRng, seeded};
use rand::RngExt;

/// The reference keeper policies.
#[derive(Clone, Debug)]
pub enum BaselinePolicy {
    /// Uniform over hold, pass 1, pass 2, drawing from its own generator.
    Random(SimRng),
    /// Always hold.
    AlwaysHold,
    /// The framework's hand-coded policy (Stone, Sutton, Kuhlmann 2005): hold if
    /// d(K1, T1) > 5 m; otherwise the highest score among hold = 90 and, for
    /// teammate i, pass_i = 4 x min_j d(Ki, Tj) + min_j ang(Ki, K1, Tj) (degrees).
    HandCoded,
    /// The thesis's simple policy (section 7.2): hold until the closest taker is
    /// nearer than `threshold` metres, then pass to the teammate whose pass line is
    /// farthest from the takers.
    Threshold {
        /// The distance that triggers the pass (m).
        threshold: f64,
    },
}

impl BaselinePolicy {
    /// The random policy with its own generator seeded from `seed`.
    pub fn random(seed: u64) -> Self {
        BaselinePolicy::Random(seeded(seed))
    }

    /// The threshold policy with [`DEFAULT_HOLD_THRESHOLD`].
    pub fn threshold() -> Self {
        BaselinePolicy::Threshold {
            threshold: DEFAULT_HOLD_THRESHOLD,
        }
    }
}

/// The hand-coded policy's choice from the 13 state variables.
pub fn hand_coded(s: &StateVars) -> KeeperAction {
    if s.d_k1_t[0] > FRAMEWORK_NEAR_RADIUS {
        return KeeperAction::Hold;
    }
    let mut best = KeeperAction::Hold;
    let mut best_score = 90.0;
    for (i, action) in [KeeperAction::Pass1, KeeperAction::Pass2].into_iter().enumerate() {
        let score = 4.0 * s.min_d_k_t[i] + s.min_ang_k_t[i];
        if score > best_score {
            best = action;
            best_score = score;
        }
    }
    best
}

/// The threshold policy's choice from the pass-line distances.
pub fn threshold_policy(d: &PassLineDistances, threshold: f64) -> KeeperAction {
    if d.closest_taker >= threshold {
        KeeperAction::Hold
    } else if d.line[1] > d.line[0] {
        KeeperAction::Pass2
    } else {
        KeeperAction::Pass1
    }
}

impl KeeperPolicy for BaselinePolicy {
    fn decide(&mut self, view: &PlayerView, _cfg: &KeepawayConfig) -> KeeperAction {
        match self {
            BaselinePolicy::Random(rng) => {
                KeeperAction::from_index(rng.random_range(0..KeeperAction::ALL.len())).unwrap_or(KeeperAction::Hold)
            }
            BaselinePolicy::AlwaysHold => KeeperAction::Hold,
            BaselinePolicy::HandCoded => StateVars::from_view(view).map_or(KeeperAction::Hold, |s| hand_coded(&s)),
            BaselinePolicy::Threshold { threshold } => {
                PassLineDistances::from_view(view).map_or(KeeperAction::Hold, |d| threshold_policy(&d, *threshold))
            }
        }
    }
}
