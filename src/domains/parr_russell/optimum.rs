//! The exact value of Parr and Russell's grid under each memoryless
//! deterministic policy (one move per observation, the policies the thesis's
//! plan can express greedily), and the best of them: the reference the
//! learning curves are drawn against.
//!
//! A policy's value is the expected undiscounted return from the start cell,
//! found by solving the linear system of its Markov chain (one equation per
//! non-terminal cell); a policy some cell of which never terminates has none.

use super::{GOAL, PENALTY, ParrRussellConfig, START, free, observe, step_cell};
use crate::domains::grid::Direction;

/// A memoryless policy: the move for each observation, indexed by
/// `2 * wall west + wall east`.
pub(crate) type Policy = [Direction; 4];

/// The index of `cell`'s observation in a [`Policy`].
fn observation(cell: (i8, i8)) -> usize {
    let (west, east) = observe(cell);
    2 * usize::from(west) + usize::from(east)
}

/// The cells where the agent may stand and the episode goes on.
fn cells() -> Vec<(i8, i8)> {
    (1..=4)
        .flat_map(|x| (1..=3).map(move |y| (x, y)))
        .filter(|&c| free(c) && c != GOAL && c != PENALTY)
        .collect()
}

/// Solves `a v = b` by Gaussian elimination with partial pivoting; `None` when singular.
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for col in 0..n {
        let pivot = (col..n).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[pivot][col].abs() < 1e-9 {
            return None;
        }
        a.swap(col, pivot);
        b.swap(col, pivot);
        let pivot_row = a[col].clone();
        for row in (0..n).filter(|&r| r != col) {
            let f = a[row][col] / pivot_row[col];
            for (x, p) in a[row].iter_mut().zip(&pivot_row).skip(col) {
                *x -= f * p;
            }
            b[row] -= f * b[col];
        }
    }
    Some((0..n).map(|i| b[i] / a[i][i]).collect())
}

/// The exact expected return of `policy` from the start cell, `None` when
/// some cell it reaches never ends an episode (no episode cap counted).
pub fn value(config: &ParrRussellConfig, policy: &Policy) -> Option<f64> {
    let cells = cells();
    let index = |c: (i8, i8)| cells.iter().position(|&d| d == c);
    let n = cells.len();
    let mut a = vec![vec![0.0; n]; n];
    let mut b = vec![0.0; n];
    let slip = (1.0 - config.success) / 2.0;
    for (i, &cell) in cells.iter().enumerate() {
        a[i][i] += 1.0;
        let intended = policy[observation(cell)];
        let [left, right] = intended.perpendicular();
        for (d, p) in [(intended, config.success), (left, slip), (right, slip)] {
            let next = step_cell(cell, d);
            let payoff = match next {
                GOAL => 1.0,
                PENALTY => -1.0,
                _ => 0.0,
            };
            b[i] += p * (config.step_reward + payoff);
            if let Some(j) = index(next) {
                a[i][j] -= p;
            }
        }
    }
    solve(a, b).and_then(|v| index(START).map(|s| v[s]))
}

/// The best memoryless deterministic policy and its exact value.
pub fn optimum(config: &ParrRussellConfig) -> Option<(Policy, f64)> {
    let moves = Direction::ALL;
    (0..256usize)
        .map(|k| [moves[k % 4], moves[(k / 4) % 4], moves[(k / 16) % 4], moves[k / 64]])
        .filter_map(|p| value(config, &p).map(|v| (p, v)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
}
