//! Passing: a multi-cycle skill with a small explicit state.

use super::kick::kick_to;
use crate::keepaway::command::Command;
use crate::keepaway::params::KeepawayConfig;
use crate::keepaway::perception::{PlayerId, PlayerView};
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

/// A pass in progress: the ball is kicked towards the receiver's current position
/// (the framework's `directPass`, normal speed: the ball should arrive at
/// `pass_end_speed`, 1.2 m/cycle) on consecutive cycles until it leaves the
/// kickable range, since accelerating the ball may take several kicks.
///
/// Decision: the receiver is fixed when the pass starts; the framework re-sorts the
/// teammates by distance every cycle and follows the same rank, which only differs
/// if the ranking changes during the two or three cycles of a pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PassState {
    /// Who receives the pass.
    pub receiver: PlayerId,
    /// The cycle of the last kick of this pass.
    pub last_cycle: u32,
}

impl PassState {
    /// Starts a pass to `receiver` at the view's cycle.
    pub fn new(receiver: PlayerId, view: &PlayerView) -> Self {
        PassState {
            receiver,
            last_cycle: view.cycle,
        }
    }

    /// Whether the pass goes on this cycle: the ball is still kickable and the last
    /// kick of the pass was the previous cycle.
    pub fn continues(&self, view: &PlayerView, cfg: &KeepawayConfig) -> bool {
        view.ball_kickable(cfg) && self.last_cycle.checked_add(1) == Some(view.cycle)
    }

    /// This cycle's kick of the pass.
    pub fn kick(&mut self, view: &PlayerView, cfg: &KeepawayConfig) -> Command {
        self.last_cycle = view.cycle;
        let to = view.players[self.receiver.index()].pos;
        kick_to(view, cfg, to, cfg.skills.pass_end_speed)
    }
}
