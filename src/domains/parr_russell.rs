//! Parr and Russell's 4 x 3 grid (thesis 6.1, Figure 6.1).
//!
//! Columns 1..4, rows 1..3 from the bottom-left; an obstacle at (2,2); +1 at
//! (4,3) and -1 at (4,2), both absorbing. Moves go the intended way with
//! probability 0.8 and each perpendicular way with 0.1; a move into the
//! obstacle or the border stays. Every action costs 0.04. The agent observes
//! only whether a wall (obstacle or border) is immediately west and east.

/// The exact value of each memoryless policy in Parr and Russell's grid.
pub mod optimum;

use std::sync::Arc;

use rand::RngExt;

use super::grid::{Direction, Mover};
use super::task::{EpisodeWorld, PlanTask, TaskError, root_key};
use crate::condition::{AtomId, AtomTable, KnowledgeBase};
use crate::executor::{Registry, World};
use crate::learning::Learner;
use crate::plan::{AllowedAtoms, Plan, catalog};
use crate::rng::SimRng;

/// The atoms the grid's knowledge base answers.
pub const ATOMS: [&str; 3] = ["WallLeft", "WallRight", "Terminal"];

/// The grid's parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ParrRussellConfig {
    /// Actions after which an episode is cut (the thesis's -4 initial value implies 100).
    pub max_actions: u32,
    /// Reward of every action.
    pub step_reward: f64,
    /// Probability of the intended direction.
    pub(crate) success: f64,
}

impl Default for ParrRussellConfig {
    fn default() -> Self {
        ParrRussellConfig {
            max_actions: 100,
            step_reward: -0.04,
            success: 0.8,
        }
    }
}

/// The cell of the obstacle.
pub(crate) const OBSTACLE: (i8, i8) = (2, 2);
/// The cell paying +1.
pub(crate) const GOAL: (i8, i8) = (4, 3);
/// The cell paying -1.
pub(crate) const PENALTY: (i8, i8) = (4, 2);
/// The start cell.
pub(crate) const START: (i8, i8) = (1, 1);

/// Whether an agent can stand in `cell`.
pub(crate) fn free(cell: (i8, i8)) -> bool {
    (1..=4).contains(&cell.0) && (1..=3).contains(&cell.1) && cell != OBSTACLE
}

/// Where a move from `cell` in `d` ends (staying when blocked).
pub(crate) fn step_cell(cell: (i8, i8), d: Direction) -> (i8, i8) {
    let next = match d {
        Direction::North => (cell.0, cell.1 + 1),
        Direction::South => (cell.0, cell.1 - 1),
        Direction::East => (cell.0 + 1, cell.1),
        Direction::West => (cell.0 - 1, cell.1),
    };
    if free(next) { next } else { cell }
}

/// The observation of `cell`: (wall west, wall east).
pub fn observe(cell: (i8, i8)) -> (bool, bool) {
    (!free((cell.0 - 1, cell.1)), !free((cell.0 + 1, cell.1)))
}

/// The grid as the plan's world.
pub struct Grid {
    config: ParrRussellConfig,
    cell: (i8, i8),
    rng: SimRng,
    pending: f64,
    ret: f64,
    actions: u32,
}

impl Grid {
    fn new(config: ParrRussellConfig, rng: SimRng) -> Self {
        Grid {
            config,
            cell: START,
            rng,
            pending: 0.0,
            ret: 0.0,
            actions: 0,
        }
    }

    fn reset(&mut self) {
        self.cell = START;
        self.pending = 0.0;
        self.ret = 0.0;
        self.actions = 0;
    }

    fn terminal(&self) -> bool {
        self.cell == GOAL || self.cell == PENALTY
    }
}

impl KnowledgeBase for Grid {
    fn holds(&self, atom: AtomId) -> bool {
        let (west, east) = observe(self.cell);
        match atom.0 {
            0 => west,
            1 => east,
            2 => self.terminal(),
            _ => false,
        }
    }
}

impl World for Grid {
    fn take_reward(&mut self) -> f64 {
        std::mem::take(&mut self.pending)
    }
}

impl Mover for Grid {
    fn apply_move(&mut self, direction: Direction) {
        if self.terminal() {
            return;
        }
        let u: f64 = self.rng.random();
        let slip = (1.0 - self.config.success) / 2.0;
        let [left, right] = direction.perpendicular();
        let actual = if u < self.config.success {
            direction
        } else if u < self.config.success + slip {
            left
        } else {
            right
        };
        self.cell = step_cell(self.cell, actual);
        let mut r = self.config.step_reward;
        if self.cell == GOAL {
            r += 1.0;
        } else if self.cell == PENALTY {
            r -= 1.0;
        }
        self.pending += r;
        self.ret += r;
        self.actions += 1;
    }
}

/// The domain's atoms.
pub fn atoms() -> AtomTable {
    ATOMS.into_iter().collect()
}

/// The thesis's plan (Figure 6.2), loaded against the domain's atoms.
pub fn default_plan() -> Result<Plan, TaskError> {
    let net = catalog::parr_russell().map_err(crate::plan::PlanError::from)?;
    Ok(Plan::from_net(net, AllowedAtoms::Closed(&atoms()))?)
}

/// The actions the grid provides.
pub fn registry() -> Registry<Grid> {
    super::grid::registry()
}

impl EpisodeWorld for Grid {
    fn begin(&mut self) {
        self.reset();
    }
    fn step_limit(&self) -> u32 {
        self.config.max_actions.saturating_mul(4).saturating_add(8)
    }
    fn over(&self) -> bool {
        self.actions >= self.config.max_actions || self.terminal()
    }
    fn ret(&self) -> f64 {
        self.ret
    }
    fn actions(&self) -> u32 {
        self.actions
    }
}

/// Learning runs in Parr and Russell's grid.
pub type ParrRussell = PlanTask<Grid>;

impl ParrRussell {
    /// A run of `plan` (whose atoms must be [`ATOMS`]) with `learner`; `rng` drives the moves.
    pub fn new(
        config: ParrRussellConfig,
        plan: Arc<Plan>,
        learner: Box<dyn Learner>,
        rng: SimRng,
    ) -> Result<Self, TaskError> {
        let mut traced = Vec::new();
        // The initial observation: a wall west only.
        for name in catalog::MOVES {
            if let Some(key) = root_key(&plan, &["WallLeft", "not_WallRight", &format!("{name}.exec")]) {
                traced.push((name.to_string(), key));
            }
        }
        PlanTask::with(plan, &registry(), learner, Grid::new(config, rng), traced)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn observations_match_the_reference() {
        let west_only = [(1, 1), (1, 3), (3, 2)];
        for c in west_only {
            assert_eq!(observe(c), (true, false), "{c:?}");
        }
        assert_eq!(observe((4, 1)), (false, true));
        assert_eq!(observe((1, 2)), (true, true));
        for c in [(2, 1), (3, 1), (2, 3), (3, 3)] {
            assert_eq!(observe(c), (false, false), "{c:?}");
        }
    }

    #[test]
    fn blocked_moves_stay() {
        assert_eq!(step_cell((1, 1), Direction::West), (1, 1));
        assert_eq!(step_cell((2, 1), Direction::North), (2, 1));
        assert_eq!(step_cell((1, 1), Direction::North), (1, 2));
    }
}
