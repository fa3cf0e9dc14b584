//! The keepers' fixed procedure around a pluggable decision
//! (the framework's `KeepawayPlayer::keeper`).

use super::command::Command;
use super::game::EpisodeSummary;
use super::geometry::Vec2;
use super::params::KeepawayConfig;
use super::skills::fastest::{BallEstimates, fastest_teammate_with, pass_origin_with};
use super::skills::pass::PassState;
use super::skills::{InterceptMemory, get_open_from, go_to_support_point, hold_ball, intercept};
use super::view::PlayerView;
use super::world_model::believed;
use serde::{Deserialize, Serialize};

/// The choice of the keeper with the ball.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum KeeperAction {
    /// Keep the ball for one cycle.
    Hold,
    /// Pass to the closest teammate (Pass(1)).
    Pass1,
    /// Pass to the second-closest teammate (Pass(2)).
    Pass2,
}

impl KeeperAction {
    /// All actions, in the framework's numbering (0 hold, k pass to the k-th closest).
    pub const ALL: [KeeperAction; 3] = [KeeperAction::Hold, KeeperAction::Pass1, KeeperAction::Pass2];

    /// The framework's action number.
    pub fn index(self) -> usize {
        match self {
            KeeperAction::Hold => 0,
            KeeperAction::Pass1 => 1,
            KeeperAction::Pass2 => 2,
        }
    }

    /// The action with the framework's number `i`, if any.
    pub fn from_index(i: usize) -> Option<KeeperAction> {
        KeeperAction::ALL.get(i).copied()
    }
}

/// What a keeper without the ball, and not the fastest to it, does.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum SupportAction {
    /// The framework's get-open behaviour.
    #[default]
    GetOpen,
    /// Go to (and then wait at, facing the ball) a chosen point, as in the thesis's
    /// multi-agent positioning experiment.
    GoTo(Vec2),
}

/// The pluggable decisions of the keepers. One policy object serves all three
/// keepers; the deciding keeper is `view.me`.
pub trait KeeperPolicy {
    /// The action of a keeper with the ball kickable, at a decision point (not in the
    /// middle of a pass).
    fn decide(&mut self, view: &PlayerView, cfg: &KeepawayConfig) -> KeeperAction;

    /// What a supporting keeper does (default: get open).
    fn support(&mut self, _view: &PlayerView, _cfg: &KeepawayConfig) -> SupportAction {
        SupportAction::GetOpen
    }

    /// Called once when an episode run by a [`Keepaway`](crate::episode::Keepaway) ends.
    fn end_episode(&mut self, _outcome: &EpisodeSummary) {}
}

/// A keeper's memory between cycles: the pass in progress, if any, and the last
/// interception point.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct KeeperMemory {
    /// The pass being kicked.
    pub pass: Option<PassState>,
    /// The interception skill's memory.
    pub intercept: InterceptMemory,
}

/// A keeper's command for this cycle (the framework's `KeepawayPlayer::keeper`),
/// from what it believes (`believed`):
/// - with the ball kickable: continue the pass kicked last cycle if there is one,
///   otherwise ask `policy` and hold the ball (one cycle, ratio 0.7) or start a pass
///   to the k-th closest teammate;
/// - otherwise, if this keeper is the teammate fastest to the ball
///   ([`fastest_teammate`](super::skills::fastest::fastest_teammate)), intercept;
/// - otherwise support as `policy` says (get open for a pass from where the fastest
///   teammate will get the ball, [`pass_origin`](super::skills::fastest::pass_origin), by default).
///
/// The framework first searches for the ball when its world model has lost it
/// (confidence below 0.90); with 360-degree vision it never is (see
/// [`super::world_model`]). The neck, turned to the ball or the region's centre
/// in the framework, does not matter with 360-degree vision.
pub fn keeper_command(
    view: &PlayerView,
    cfg: &KeepawayConfig,
    memory: &mut KeeperMemory,
    policy: &mut dyn KeeperPolicy,
) -> Command {
    let view = &believed(view, cfg);
    if view.ball_kickable(cfg) {
        if let Some(mut pass) = memory.pass.filter(|p| p.continues(view, cfg)) {
            let cmd = pass.kick(view, cfg);
            memory.pass = Some(pass);
            return cmd;
        }
        let action = policy.decide(view, cfg);
        if action == KeeperAction::Hold {
            memory.pass = None;
            return hold_ball(view, cfg, cfg.skills.keeper_hold_ratio);
        }
        let mut pass = PassState::new(action.index(), view);
        let cmd = pass.kick(view, cfg);
        memory.pass = Some(pass);
        return cmd;
    }
    memory.pass = None;
    let mut estimates = BallEstimates::default();
    let fastest = fastest_teammate_with(view, cfg, &mut estimates);
    if fastest == Some(view.me.index()) {
        return intercept(view, cfg, &mut memory.intercept);
    }
    match policy.support(view, cfg) {
        SupportAction::GetOpen => get_open_from(view, cfg, pass_origin_with(view, fastest, cfg, &mut estimates)),
        SupportAction::GoTo(p) => go_to_support_point(view, cfg, p),
    }
}
