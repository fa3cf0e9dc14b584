//! The optimal memoryless deterministic policy of Parr and Russell's grid,
//! computed independently by exact evaluation of all 4^4 policies (one linear
//! system per policy), and the policies SoSMC converges to compared with it.

use std::sync::Arc;

use learnpnp::domains::Task;
use learnpnp::domains::parr_russell::{self, ParrRussell, ParrRussellConfig};
use learnpnp::executor::PlanKey;
use learnpnp::experiment::defaults::default_learner;
use learnpnp::experiment::spec::{Algorithm, DomainSpec};
use learnpnp::learning::{EpisodeMode, Learner};
use learnpnp::net::Marking;
use learnpnp::plan::Plan;
use learnpnp::rng::{derive_seed, seeded};

/// Moves in the order N, S, E, W as (dx, dy).
const MOVES: [(i32, i32); 4] = [(0, 1), (0, -1), (1, 0), (-1, 0)];
/// The perpendicular moves of each.
const PERPENDICULAR: [[usize; 2]; 4] = [[2, 3], [2, 3], [0, 1], [0, 1]];

fn free(x: i32, y: i32) -> bool {
    (1..=4).contains(&x) && (1..=3).contains(&y) && (x, y) != (2, 2)
}

fn terminal_reward(x: i32, y: i32) -> Option<f64> {
    match (x, y) {
        (4, 3) => Some(1.0),
        (4, 2) => Some(-1.0),
        _ => None,
    }
}

/// Observation index: 2 * wall west + wall east.
fn observation(x: i32, y: i32) -> usize {
    2 * usize::from(!free(x - 1, y)) + usize::from(!free(x + 1, y))
}

fn cells() -> Vec<(i32, i32)> {
    (1..=4)
        .flat_map(|x| (1..=3).map(move |y| (x, y)))
        .filter(|&(x, y)| free(x, y) && terminal_reward(x, y).is_none())
        .collect()
}

/// Solves A v = b by Gaussian elimination with partial pivoting; None if singular.
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

/// Exact undiscounted value of the start cell under `policy` (observation -> move),
/// or None when some state never terminates (the system is singular).
fn exact_value(policy: [usize; 4]) -> Option<f64> {
    let cells = cells();
    let index = |x: i32, y: i32| cells.iter().position(|&c| c == (x, y));
    let n = cells.len();
    let mut a = vec![vec![0.0; n]; n];
    let mut b = vec![0.0; n];
    for (i, &(x, y)) in cells.iter().enumerate() {
        a[i][i] += 1.0;
        let m = policy[observation(x, y)];
        for (d, p) in [(m, 0.8), (PERPENDICULAR[m][0], 0.1), (PERPENDICULAR[m][1], 0.1)] {
            let (nx, ny) = (x + MOVES[d].0, y + MOVES[d].1);
            let (nx, ny) = if free(nx, ny) { (nx, ny) } else { (x, y) };
            b[i] += p * (-0.04 + terminal_reward(nx, ny).unwrap_or(0.0));
            if let Some(j) = index(nx, ny) {
                a[i][j] -= p;
            }
        }
    }
    solve(a, b).map(|v| v[index(1, 1).unwrap_or(0)])
}

fn all_policies() -> Vec<([usize; 4], Option<f64>)> {
    (0..256)
        .map(|k| [k % 4, (k / 4) % 4, (k / 16) % 4, k / 64])
        .map(|p| (p, exact_value(p)))
        .collect()
}

/// Terminating policies by decreasing exact value.
fn ranked() -> Vec<([usize; 4], f64)> {
    let mut all: Vec<([usize; 4], f64)> = all_policies()
        .into_iter()
        .filter_map(|(p, v)| v.map(|v| (p, v)))
        .collect();
    all.sort_by(|a, b| b.1.total_cmp(&a.1));
    all
}

fn optimum() -> ([usize; 4], f64) {
    ranked()[0]
}

#[test]
fn the_optimal_policy_is_worth_about_a_quarter() {
    let (policy, value) = optimum();
    // Observation order: neither wall, east only, west only, both.
    // N=0 S=1 E=2 W=3: east when no wall, west at the east wall, north otherwise.
    assert_eq!(policy, [2, 3, 0, 0]);
    assert!((value - 0.2635).abs() < 1e-3, "{value}");
    // The thesis: "the optimum is around 0.25".
    assert!((value - 0.25).abs() < 0.02);
}

/// The learned greedy move in each observation, from the values of the afterstates.
fn learned_policy(learner: &dyn Learner, plan: &Plan) -> [usize; 4] {
    let place = |label: &str| plan.net().places_labelled(label).next().expect("plan place");
    let mut policy = [0; 4];
    for (obs, slot) in policy.iter_mut().enumerate() {
        let (west, east) = (obs / 2 == 1, obs % 2 == 1);
        let values: Vec<f64> = ["MoveNorth", "MoveSouth", "MoveEast", "MoveWest"]
            .iter()
            .map(|m| {
                let mut marking = Marking::empty(plan.net().places().len());
                marking.set(place(if west { "WallLeft" } else { "not_WallLeft" }), 1);
                marking.set(place(if east { "WallRight" } else { "not_WallRight" }), 1);
                marking.set(place(&format!("{m}.exec")), 1);
                learner.values().value_of(PlanKey::ROOT, &marking)
            })
            .collect();
        *slot = (0..4).max_by(|&a, &b| values[a].total_cmp(&values[b])).unwrap_or(0);
    }
    policy
}

#[test]
fn eps_sosmc_converges_to_the_optimal_policy_in_most_runs() {
    let ranking = ranked();
    let (best, second) = (ranking[0].1, ranking[1].1);
    // The runner-up differs only in the rarely visited cell by the east wall.
    assert!((second - 0.2227).abs() < 1e-3, "{second}");
    let domain = DomainSpec::ParrRussell {
        config: ParrRussellConfig::default(),
        plan: None,
    };
    let spec = default_learner(Algorithm::EpsSosmc, &domain);
    let plan = Arc::new(parr_russell::default_plan().unwrap());
    let runs: u64 = std::env::var("RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(12);
    let (mut optimal, mut top_two) = (0, 0);
    let mut values = Vec::new();
    for run in 0..runs {
        let seed = derive_seed(42, run);
        let learner = spec.build(seeded(derive_seed(seed, 1)));
        let mut task = ParrRussell::new(
            ParrRussellConfig::default(),
            Arc::clone(&plan),
            learner,
            seeded(derive_seed(seed, 2)),
        )
        .unwrap();
        for _ in 0..1000 {
            task.episode(EpisodeMode::Learn).unwrap();
        }
        let learned = learned_policy(task.learners()[0], &plan);
        // Observation (both walls) is only met from (1,2); compare exact values, not moves.
        let value = exact_value(learned).unwrap_or(-4.0);
        values.push(value);
        optimal += usize::from((value - best).abs() < 1e-9);
        top_two += usize::from(value >= second - 1e-9);
    }
    eprintln!("{optimal} of {runs} runs end in the optimal policy, {top_two} in one of the two best");
    // Measured over 200 runs (RUNS=200): 45% of runs end in the optimal policy and
    // 84% in one of the two best. With 12 runs, at least 2 optimal and at least 7
    // in the top two each fail with probability below 0.01 at those rates.
    assert!(
        optimal >= 2,
        "{optimal} of {runs} runs optimal; exact values {values:?}"
    );
    assert!(
        top_two >= 7,
        "{top_two} of {runs} runs in the two best policies; exact values {values:?}"
    );
}

/// The library's optimum, drawn as the reference line of the grid's curves,
/// is the one computed independently here.
#[test]
fn the_reference_line_is_this_optimum() {
    use learnpnp::domains::grid::Direction;
    let (policy, value) = optimum();
    let (lib_policy, lib_value) =
        parr_russell::optimum::optimum(&ParrRussellConfig::default()).expect("some policy terminates");
    let moves = [Direction::North, Direction::South, Direction::East, Direction::West];
    assert_eq!(lib_policy, policy.map(|m| moves[m]));
    assert!((lib_value - value).abs() < 1e-12, "{lib_value} against {value}");
    let domain = DomainSpec::ParrRussell {
        config: ParrRussellConfig::default(),
        plan: None,
    };
    let reference = domain.reference().expect("a reference");
    assert!((reference.value - value).abs() < 1e-12);
    assert!(reference.label.contains("0.263"), "{}", reference.label);
}
