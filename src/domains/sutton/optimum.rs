//! The exact value of Sutton's grid under the best memoryless deterministic
//! policy (one move per observation, the policies the thesis's plan can
//! express greedily): the ceiling Figure 6.13's learners are judged against.
//!
//! Moves are deterministic, so a policy's value is found by following it from
//! every start cell (the evaluation protocol of Sutton's grid): entering
//! the goal after `k` moves returns `-(k - 1)`, an episode cut after
//! `max_actions` moves returns `-max_actions`. The best policy is found by
//! branch and bound over the observations: a partial policy is bounded by the
//! shortest paths in which the cells of unassigned observations may take any
//! move the plan offers (a relaxation, so the bound is never below the value
//! of any completion), and the search is exhaustive, so the result is exact.

use super::{GOAL, SuttonConfig, free, observe, offset, start_cells};
use crate::domains::grid::Direction;

/// A memoryless deterministic policy: a move for each observation of a start cell.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Policy {
    /// Each observation (the bits of [`observe`]) and its move.
    pub moves: Vec<(u8, Direction)>,
}

impl Policy {
    /// The move for `observation`, if the policy has one.
    pub fn move_for(&self, observation: u8) -> Option<Direction> {
        self.moves.iter().find(|(o, _)| *o == observation).map(|(_, d)| *d)
    }
}

/// The cell one move from `cell` in `direction` (every move the plan offers
/// leads to a free cell).
fn step(cell: (i8, i8), direction: Direction) -> (i8, i8) {
    let (dr, dc) = offset(direction);
    (cell.0 + dr, cell.1 + dc)
}

/// The moves the plan offers in `cell`: those into a free cell.
fn offered(cell: (i8, i8)) -> Vec<Direction> {
    Direction::ALL.into_iter().filter(|&d| free(step(cell, d))).collect()
}

/// The return of an episode that enters the goal after `moves` moves, or is cut.
fn episode_return(config: &SuttonConfig, moves: Option<u32>) -> f64 {
    match moves {
        Some(k) if k <= config.max_actions => -(f64::from(k) - 1.0),
        _ => -f64::from(config.max_actions),
    }
}

/// The exact mean return of `policy` over the start cells (each once, as the
/// evaluation protocol plays them); `None` if it has no move for the
/// observation of some start cell, or a move the plan does not offer there.
pub fn value(config: &SuttonConfig, policy: &Policy) -> Option<f64> {
    let starts = start_cells();
    let mut total = 0.0;
    for &start in &starts {
        let mut cell = start;
        let mut moves = None;
        for k in 1..=config.max_actions {
            let d = policy.move_for(observe(cell))?;
            if !offered(cell).contains(&d) {
                return None;
            }
            cell = step(cell, d);
            if cell == GOAL {
                moves = Some(k);
                break;
            }
        }
        total += episode_return(config, moves);
    }
    Some(total / starts.len() as f64)
}

/// The search's fixed data: the start cells, their observations, and each
/// observation's offered moves.
struct Search<'a> {
    config: &'a SuttonConfig,
    cells: Vec<(i8, i8)>,
    /// The observation index of each cell.
    cell_observation: Vec<usize>,
    /// Each observation's bits and offered moves, most cells first.
    observations: Vec<(u8, Vec<Direction>)>,
    /// Each cell's successor under each of its offered moves (`None`: the goal).
    successors: Vec<Vec<(Direction, Option<usize>)>>,
    best: f64,
    best_policy: Vec<usize>,
}

impl Search<'_> {
    /// The relaxed bound of a partial policy (`assigned[o]`: the index of
    /// observation o's move in its offered moves, if assigned): the mean
    /// return when each cell of an unassigned observation takes its best move.
    fn bound(&self, assigned: &[Option<usize>]) -> f64 {
        let n = self.cells.len();
        let mut distance: Vec<Option<u32>> = vec![None; n];
        // Bellman-Ford on moves to the goal: at most n rounds.
        for _ in 0..n {
            let mut changed = false;
            for c in 0..n {
                let choice = assigned[self.cell_observation[c]];
                let (_, moves) = &self.observations[self.cell_observation[c]];
                let best = self.successors[c]
                    .iter()
                    .filter(|(d, _)| choice.is_none_or(|i| moves[i] == *d))
                    .filter_map(|(_, next)| match next {
                        None => Some(1),
                        Some(j) => distance[*j].map(|k| k + 1),
                    })
                    .min();
                if best.is_some() && (distance[c].is_none() || best < distance[c]) {
                    distance[c] = best;
                    changed = true;
                }
            }
            if !changed {
                break;
            }
        }
        distance.iter().map(|&k| episode_return(self.config, k)).sum::<f64>() / n as f64
    }

    /// Depth-first over the observations in order, pruning by the bound.
    fn explore(&mut self, assigned: &mut Vec<Option<usize>>, depth: usize) {
        if self.bound(assigned) <= self.best + 1e-12 {
            return;
        }
        if depth == self.observations.len() {
            // Every observation assigned: the bound is the policy's value.
            self.best = self.bound(assigned);
            self.best_policy = assigned.iter().map(|a| a.unwrap_or(0)).collect();
            return;
        }
        for i in 0..self.observations[depth].1.len() {
            assigned[depth] = Some(i);
            self.explore(assigned, depth + 1);
        }
        assigned[depth] = None;
    }
}

/// The best memoryless deterministic policy and its exact mean return over
/// the start cells.
pub fn optimum(config: &SuttonConfig) -> (Policy, f64) {
    let cells = start_cells();
    let mut observations: Vec<(u8, Vec<Direction>)> = Vec::new();
    for &c in &cells {
        if !observations.iter().any(|(o, _)| *o == observe(c)) {
            observations.push((observe(c), offered(c)));
        }
    }
    let count = |o: u8| cells.iter().filter(|&&c| observe(c) == o).count();
    observations.sort_by_key(|(o, _)| (std::cmp::Reverse(count(*o)), *o));
    let cell_observation: Vec<usize> = cells
        .iter()
        .map(|&c| observations.iter().position(|(o, _)| *o == observe(c)).unwrap_or(0))
        .collect();
    let successors = cells
        .iter()
        .map(|&c| {
            offered(c)
                .into_iter()
                .map(|d| {
                    let next = step(c, d);
                    (
                        d,
                        if next == GOAL {
                            None
                        } else {
                            cells.iter().position(|&x| x == next)
                        },
                    )
                })
                .collect()
        })
        .collect();
    let mut search = Search {
        config,
        cells,
        cell_observation,
        observations,
        successors,
        best: f64::NEG_INFINITY,
        best_policy: Vec::new(),
    };
    let mut assigned = vec![None; search.observations.len()];
    search.explore(&mut assigned, 0);
    let policy = Policy {
        moves: search
            .observations
            .iter()
            .zip(&search.best_policy)
            .map(|((o, moves), &i)| (*o, moves[i]))
            .collect(),
    };
    (policy, search.best)
}

/// The mean return over the start cells when every cell may take its own
/// move (full observability): the shortest paths, an upper bound on every
/// memoryless policy.
pub fn fully_observable(config: &SuttonConfig) -> f64 {
    let cells = start_cells();
    let mut distance: Vec<Option<u32>> = vec![None; cells.len()];
    for _ in 0..cells.len() {
        for (c, &cell) in cells.iter().enumerate() {
            let best = offered(cell)
                .into_iter()
                .filter_map(|d| {
                    let next = step(cell, d);
                    if next == GOAL {
                        Some(1)
                    } else {
                        cells
                            .iter()
                            .position(|&x| x == next)
                            .and_then(|j| distance[j])
                            .map(|k| k + 1)
                    }
                })
                .min();
            if best.is_some() && (distance[c].is_none() || best < distance[c]) {
                distance[c] = best;
            }
        }
    }
    distance.iter().map(|&k| episode_return(config, k)).sum::<f64>() / cells.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::RngExt;

    #[test]
    fn the_optimum_is_a_policy_of_that_value_below_full_observability() {
        let config = SuttonConfig::default();
        let (policy, best) = optimum(&config);
        assert_eq!(value(&config, &policy), Some(best));
        assert_eq!(policy.moves.len(), 30);
        assert!(best <= fully_observable(&config) + 1e-12);
    }

    #[test]
    fn no_random_policy_beats_the_optimum() {
        let config = SuttonConfig::default();
        let (best_policy, best) = optimum(&config);
        let mut rng = crate::rng::seeded(7);
        for _ in 0..500 {
            // The optimum with some observations' moves redrawn.
            let mut policy = best_policy.clone();
            for (o, d) in &mut policy.moves {
                if rng.random_bool(0.3) {
                    let cell = start_cells().into_iter().find(|&c| observe(c) == *o).unwrap();
                    let moves = offered(cell);
                    *d = moves[rng.random_range(0..moves.len())];
                }
            }
            let v = value(&config, &policy).unwrap();
            assert!(v <= best + 1e-12, "{v} > {best}");
        }
    }
}
