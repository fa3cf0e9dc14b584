//! The optimal memoryless deterministic policy of Parr and Russell's grid,
//! computed independently of the library (`parr_russell::optimum` solves a
//! linear system per policy): every one of the 4^4 policies evaluated by
//! successive approximation, after a reachability test for termination, and
//! the policies SoSMC converges to compared with it.

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

/// Where `move_` from `(x, y)` ends, with its probability (the intended
/// move 0.8, each perpendicular one 0.1; blocked moves stay put).
fn outcomes(x: i32, y: i32, move_: usize) -> [((i32, i32), f64); 3] {
    [
        (move_, 0.8),
        (PERPENDICULAR[move_][0], 0.1),
        (PERPENDICULAR[move_][1], 0.1),
    ]
    .map(|(d, p)| {
        let (nx, ny) = (x + MOVES[d].0, y + MOVES[d].1);
        (if free(nx, ny) { (nx, ny) } else { (x, y) }, p)
    })
}

/// Whether every cell reaches a terminal under `policy` (then the chain is
/// absorbing and successive approximation converges), by a backward search
/// from the terminals.
fn terminates(policy: [usize; 4]) -> bool {
    let cells = cells();
    let mut reaching: Vec<(i32, i32)> = vec![(4, 3), (4, 2)];
    loop {
        let before = reaching.len();
        for &(x, y) in &cells {
            let m = policy[observation(x, y)];
            if !reaching.contains(&(x, y)) && outcomes(x, y, m).iter().any(|(c, _)| reaching.contains(c)) {
                reaching.push((x, y));
            }
        }
        if reaching.len() == before {
            return cells.iter().all(|c| reaching.contains(c));
        }
    }
}

/// Undiscounted value of the start cell under `policy` (observation -> move)
/// by successive approximation of V = r + P V from zero, or None when some
/// cell never terminates. Independent of the library's linear solve
/// (`parr_russell::optimum`): no system is set up or eliminated.
fn policy_value(policy: [usize; 4]) -> Option<f64> {
    if !terminates(policy) {
        return None;
    }
    let mut value = std::collections::HashMap::new();
    for sweep in 0.. {
        let mut change: f64 = 0.0;
        for (x, y) in cells() {
            let m = policy[observation(x, y)];
            let v: f64 = outcomes(x, y, m)
                .iter()
                .map(|&((nx, ny), p)| {
                    let after = terminal_reward(nx, ny).unwrap_or_else(|| value.get(&(nx, ny)).copied().unwrap_or(0.0));
                    p * (-0.04 + after)
                })
                .sum();
            change = change.max((v - value.insert((x, y), v).unwrap_or(0.0)).abs());
        }
        assert!(sweep < 1_000_000, "successive approximation does not converge");
        if change < 1e-13 {
            break;
        }
    }
    value.get(&(1, 1)).copied()
}

fn all_policies() -> Vec<([usize; 4], Option<f64>)> {
    (0..256)
        .map(|k| [k % 4, (k / 4) % 4, (k / 16) % 4, k / 64])
        .map(|p| (p, policy_value(p)))
        .collect()
}

/// Terminating policies by decreasing value.
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
        let value = policy_value(learned).unwrap_or(-4.0);
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
