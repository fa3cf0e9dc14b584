//! What a keeper's plan sees: its own view of the field as a knowledge base,
//! the time elapsed as reward, and a slot for the command of the cycle.

use crate::condition::{AtomId, AtomTable, KnowledgeBase};
use crate::executor::World;
use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::features::{FeatureThresholds, PassLineDistances};
use learnpnp_keepaway::geometry::Vec2;
use learnpnp_keepaway::params::KeepawayConfig;
use learnpnp_keepaway::skills::InterceptMemory;
use learnpnp_keepaway::skills::fastest::{BallEstimates, fastest_teammate_with, pass_origin_with};
use learnpnp_keepaway::view::PlayerView;
use learnpnp_keepaway::world_model::believed;

/// The atoms of a keeper's knowledge base, in id order.
pub const ATOMS: [&str; 5] = ["HasBall", "Fastest", "Lane1Open", "Lane2Open", "TakerFar"];

/// The knowledge base's atoms.
pub fn atoms() -> AtomTable {
    ATOMS.into_iter().collect()
}

/// A keeper's world for one cycle.
///
/// - `HasBall`: the ball is within kickable distance;
/// - `Fastest`: of the keepers, this one reaches the ball first (the framework's
///   fastest teammate, [`fastest_teammate`](learnpnp_keepaway::skills::fastest::fastest_teammate));
/// - `Lane1Open`, `Lane2Open`: the takers are farther than the pass-line
///   threshold from the line to the closest / second-closest teammate;
/// - `TakerFar`: the closest taker is farther than its threshold.
///
/// The last three are the thesis's abstraction (section 7.2, 8 observations).
#[derive(Debug, Clone)]
pub struct KeeperWorld {
    /// The simulation parameters (shared by every agent).
    pub config: KeepawayConfig,
    /// The feature thresholds.
    pub(crate) thresholds: FeatureThresholds,
    view: Option<PlayerView>,
    facts: [bool; ATOMS.len()],
    fastest: Option<usize>,
    estimates: BallEstimates,
    intercept: InterceptMemory,
    distances: Option<PassLineDistances>,
    command: Option<Command>,
    pending: f64,
}

impl KeeperWorld {
    /// A world with no view yet.
    pub fn new(config: KeepawayConfig, thresholds: FeatureThresholds) -> Self {
        KeeperWorld {
            config,
            thresholds,
            view: None,
            facts: [false; ATOMS.len()],
            fastest: None,
            estimates: BallEstimates::default(),
            intercept: InterceptMemory::default(),
            distances: None,
            command: None,
            pending: 0.0,
        }
    }

    /// A new cycle: the keeper's view (kept as the framework's world model
    /// believes it, `believed`) and the time elapsed since the last one.
    pub fn perceive(&mut self, view: PlayerView, elapsed_seconds: f64) {
        let cfg = &self.config;
        let view = believed(&view, cfg);
        self.estimates.clear();
        self.fastest = fastest_teammate_with(&view, cfg, &mut self.estimates);
        self.distances = PassLineDistances::from_view(&view);
        let observation = self.distances.map(|d| d.observe(&self.thresholds));
        self.facts = [
            view.ball_kickable(cfg),
            self.fastest == Some(view.me.index()),
            observation.is_some_and(|o| o.lane1_open),
            observation.is_some_and(|o| o.lane2_open),
            observation.is_some_and(|o| o.taker_far),
        ];
        self.view = Some(view);
        self.command = None;
        self.pending += elapsed_seconds;
    }

    /// The current view (none before the first cycle).
    pub fn view(&self) -> Option<&PlayerView> {
        self.view.as_ref()
    }

    /// Whether atom `HasBall` holds.
    pub(crate) fn has_ball(&self) -> bool {
        self.facts[0]
    }

    /// Whether atom `Fastest` holds.
    pub fn fastest(&self) -> bool {
        self.facts[1]
    }

    /// Where a supporting keeper expects the next pass from (`pass_origin`), with
    /// this cycle's estimates; none before the first cycle.
    pub(crate) fn pass_origin(&mut self) -> Option<Vec2> {
        let view = self.view?;
        Some(pass_origin_with(&view, self.fastest, &self.config, &mut self.estimates))
    }

    /// The interception skill's memory (the last interception point).
    pub(crate) fn intercept_memory(&mut self) -> &mut InterceptMemory {
        &mut self.intercept
    }

    /// The pass-line and closest-taker distances this cycle.
    pub(crate) fn distances(&self) -> Option<PassLineDistances> {
        self.distances
    }

    /// Sets the cycle's command (the first action to act this cycle wins).
    pub(crate) fn issue(&mut self, command: Command) {
        if self.command.is_none() {
            self.command = Some(command);
        }
    }

    /// The cycle's command, if an action has issued one.
    pub fn command(&self) -> Option<Command> {
        self.command
    }

    /// Forgets the episode (reward not yet taken and the last interception point
    /// included).
    pub fn reset(&mut self) {
        self.view = None;
        self.intercept = InterceptMemory::default();
        self.command = None;
        self.pending = 0.0;
    }
}

impl KnowledgeBase for KeeperWorld {
    fn holds(&self, atom: AtomId) -> bool {
        self.facts.get(atom.index()).copied().unwrap_or(false)
    }
}

impl World for KeeperWorld {
    fn take_reward(&mut self) -> f64 {
        std::mem::take(&mut self.pending)
    }
}
