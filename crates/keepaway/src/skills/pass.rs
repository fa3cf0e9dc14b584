//! Passing: a multi-cycle skill with a small explicit state.

use super::kick::kick_to;
use crate::command::Command;
use crate::params::KeepawayConfig;
use crate::view::PlayerView;
use serde::{Deserialize, Serialize};

/// The teammates (global indices) sorted by increasing distance from the viewer;
/// ties keep index order. For a keeper in 3 vs 2 both entries are filled; for a
/// taker only the first one is meaningful (the second repeats it).
pub fn teammates_by_distance(view: &PlayerView) -> [usize; 2] {
    let me = view.own().pos;
    let mut out = [view.me.index(); 2];
    let mut n = 0;
    for (i, _) in view.teammates() {
        if n < out.len() {
            out[n] = i;
            n += 1;
        }
    }
    if n == 2 && view.players[out[1]].pos.dist(me) < view.players[out[0]].pos.dist(me) {
        out.swap(0, 1);
    } else if n == 1 {
        out[1] = out[0];
    }
    out
}

/// A pass in progress: the ball is kicked towards the teammate of the chosen rank
/// (the framework's `directPass`, normal speed: the ball should arrive at
/// `pass_end_speed`, 1.2 m/cycle) on consecutive cycles until it leaves the
/// kickable range, since accelerating the ball may take several kicks. As in the
/// framework's `keeperWithBall`, the rank is kept and the teammates are sorted by
/// distance again at every kick.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PassState {
    /// The receiver's rank among the teammates by distance: 1 for the closest
    /// (Pass(1)), 2 for the second closest (Pass(2)).
    pub(crate) rank: usize,
    /// The cycle of the last kick of this pass.
    pub(crate) last_cycle: u32,
}

impl PassState {
    /// Starts a pass to the teammate of `rank` (1 or 2; anything else counts as 2)
    /// at the view's cycle.
    pub fn new(rank: usize, view: &PlayerView) -> Self {
        PassState {
            rank: rank.clamp(1, 2),
            last_cycle: view.cycle,
        }
    }

    /// The receiver this cycle: the teammate of the pass's rank.
    pub(crate) fn receiver(&self, view: &PlayerView) -> usize {
        teammates_by_distance(view)[self.rank.clamp(1, 2) - 1]
    }

    /// Whether the pass goes on this cycle: the ball is still kickable and the last
    /// kick of the pass was the previous cycle.
    pub fn continues(&self, view: &PlayerView, cfg: &KeepawayConfig) -> bool {
        view.ball_kickable(cfg) && self.last_cycle.checked_add(1) == Some(view.cycle)
    }

    /// This cycle's kick of the pass.
    pub fn kick(&mut self, view: &PlayerView, cfg: &KeepawayConfig) -> Command {
        self.last_cycle = view.cycle;
        let to = view.players[self.receiver(view)].pos;
        kick_to(view, cfg, to, cfg.skills.pass_end_speed)
    }
}
