//! Sutton's 9 x 6 grid (thesis 6.4, Figure 6.12, from Sutton 1990).
//!
//! Deterministic moves; the agent observes its eight neighbouring cells
//! (blocked: obstacle or outside), 30 distinct observations over the cells it
//! can start from; the plan only offers moves that do not hit an obstacle.
//! Each action costs 1, except the one entering the goal (0). An episode starts
//! in a uniformly random cell and lasts at most 20 actions.

use std::sync::Arc;

use rand::RngExt;

use super::Task;
use super::grid::{Direction, Mover};
use super::task::{EpisodeOutcome, EpisodeWorld, PlanTask, TaskError};
use crate::condition::{AtomId, AtomTable, KnowledgeBase};
use crate::executor::{Registry, World};
use crate::learning::{EpisodeMode, Learner};
use crate::plan::{AllowedAtoms, Plan, catalog};
use crate::rng::SimRng;

pub mod optimum;

/// Rows of the grid.
pub(crate) const ROWS: i8 = 6;
/// Columns of the grid.
pub(crate) const COLS: i8 = 9;
/// The goal cell (row from the top, column).
pub(crate) const GOAL: (i8, i8) = (0, 8);
/// The obstacles.
pub(crate) const OBSTACLES: [(i8, i8); 7] = [(1, 2), (2, 2), (3, 2), (0, 7), (1, 7), (2, 7), (4, 5)];

/// The grid's parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SuttonConfig {
    /// Actions after which an episode is cut.
    pub max_actions: u32,
}

impl Default for SuttonConfig {
    fn default() -> Self {
        SuttonConfig { max_actions: 20 }
    }
}

/// Whether `cell` is inside the grid and not an obstacle.
pub(crate) fn free(cell: (i8, i8)) -> bool {
    (0..ROWS).contains(&cell.0) && (0..COLS).contains(&cell.1) && !OBSTACLES.contains(&cell)
}

/// The free cells an episode may start in (every free cell but the goal).
pub(crate) fn start_cells() -> Vec<(i8, i8)> {
    (0..ROWS)
        .flat_map(|r| (0..COLS).map(move |c| (r, c)))
        .filter(|&c| free(c) && c != GOAL)
        .collect()
}

/// Neighbour offsets clockwise from north, matching [`catalog::NEIGHBOURS`].
const OFFSETS: [(i8, i8); 8] = [(-1, 0), (-1, 1), (0, 1), (1, 1), (1, 0), (1, -1), (0, -1), (-1, -1)];

/// The observation of `cell`: one bit per neighbour, set when blocked.
pub fn observe(cell: (i8, i8)) -> u8 {
    OFFSETS.iter().enumerate().fold(0, |bits, (i, (dr, dc))| {
        if free((cell.0 + dr, cell.1 + dc)) {
            bits
        } else {
            bits | 1 << i
        }
    })
}

fn offset(d: Direction) -> (i8, i8) {
    match d {
        Direction::North => (-1, 0),
        Direction::South => (1, 0),
        Direction::East => (0, 1),
        Direction::West => (0, -1),
    }
}

/// The grid as the plan's world.
pub struct Maze {
    config: SuttonConfig,
    cell: (i8, i8),
    observation: u8,
    starts: Vec<(i8, i8)>,
    rng: SimRng,
    pending: f64,
    ret: f64,
    actions: u32,
}

impl Maze {
    fn reset_to(&mut self, cell: (i8, i8)) {
        self.cell = cell;
        self.observation = observe(cell);
        self.pending = 0.0;
        self.ret = 0.0;
        self.actions = 0;
    }
}

impl KnowledgeBase for Maze {
    fn holds(&self, atom: AtomId) -> bool {
        match atom.0 {
            0..=7 => self.observation & (1 << atom.0) != 0,
            8 => self.cell == GOAL,
            _ => false,
        }
    }
}

impl World for Maze {
    fn take_reward(&mut self) -> f64 {
        std::mem::take(&mut self.pending)
    }
}

impl Mover for Maze {
    fn apply_move(&mut self, direction: Direction) {
        if self.cell == GOAL {
            return;
        }
        let (dr, dc) = offset(direction);
        let next = (self.cell.0 + dr, self.cell.1 + dc);
        if free(next) {
            self.cell = next;
            self.observation = observe(next);
        }
        let r = if self.cell == GOAL { 0.0 } else { -1.0 };
        self.pending += r;
        self.ret += r;
        self.actions += 1;
    }
}

/// The domain's atoms: the eight neighbours, then `AtGoal`.
pub fn atoms() -> AtomTable {
    catalog::NEIGHBOURS.into_iter().chain(["AtGoal"]).collect()
}

/// The plan of thesis 6.4, loaded against the domain's atoms.
pub(crate) fn default_plan() -> Result<Plan, TaskError> {
    let net = catalog::sutton().map_err(crate::plan::PlanError::from)?;
    Ok(Plan::from_net(net, AllowedAtoms::Closed(&atoms()))?)
}

/// The actions the grid provides.
pub fn registry() -> Registry<Maze> {
    super::grid::registry()
}

impl EpisodeWorld for Maze {
    /// A start cell drawn at random.
    fn begin(&mut self) {
        let i = self.rng.random_range(0..self.starts.len());
        self.reset_to(self.starts[i]);
    }
    fn step_limit(&self) -> u32 {
        self.config.max_actions.saturating_mul(4).saturating_add(8)
    }
    fn over(&self) -> bool {
        self.actions >= self.config.max_actions || self.cell == GOAL
    }
    fn ret(&self) -> f64 {
        self.ret
    }
    fn actions(&self) -> u32 {
        self.actions
    }
}

/// Learning runs in Sutton's grid.
pub(crate) struct Sutton {
    task: PlanTask<Maze>,
}

impl Sutton {
    /// A run of `plan` (whose atoms must be [`atoms`]) with `learner`; `rng` draws start cells.
    pub(crate) fn new(
        config: SuttonConfig,
        plan: Arc<Plan>,
        learner: Box<dyn Learner>,
        rng: SimRng,
    ) -> Result<Self, TaskError> {
        let starts = start_cells();
        let maze = Maze {
            config,
            cell: starts[0],
            observation: 0,
            starts,
            rng,
            pending: 0.0,
            ret: 0.0,
            actions: 0,
        };
        let task = PlanTask::with(plan, &registry(), learner, maze, Vec::new())?;
        Ok(Sutton { task })
    }
}

impl Task for Sutton {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        self.task.episode(mode)
    }

    /// The thesis's protocol: the current best (greedy) policy from every start cell.
    fn evaluate(&mut self, _episodes: usize) -> Result<f64, TaskError> {
        self.greedy_score(0)
    }

    /// The greedy policy from every start cell, once each (moves are deterministic).
    fn greedy_score(&mut self, _episodes: usize) -> Result<f64, TaskError> {
        let starts = self.task.world_mut().starts.clone();
        let mut total = 0.0;
        for &cell in &starts {
            self.task.world_mut().reset_to(cell);
            total += self.task.run(EpisodeMode::Greedy)?.ret;
        }
        Ok(total / starts.len() as f64)
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        Vec::new()
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        self.task.learners()
    }

    fn actions_played(&self) -> Option<u64> {
        self.task.actions_played()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thirty_observations_over_the_start_cells() {
        let mut seen: Vec<u8> = start_cells().iter().map(|&c| observe(c)).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), 30);
        assert_eq!(start_cells().len(), 46);
    }
}
