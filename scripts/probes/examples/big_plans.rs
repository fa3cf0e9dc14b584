//! Plans of ten thousand places, as tools write them, for `learnpnp check`:
//!
//! - `grid_SxS`: the navigation plan of `plans/python/grid.py` on an S x S
//!   grid: sense the cell (`[at_N]`), then choose one of four moves, each an
//!   action back to sensing; the last cell leads to the goal.
//! - `grid_SxS_tracked`: the same with an environment-tracking sub-net for
//!   every `at_N` atom (thesis Figure 5.9): 2^(S x S) combinations of trackers.
//! - `conditional_D`: a conditional plan as the PNP project's generator writes
//!   one: a tree of depth D whose every node runs two actions and then senses
//!   a condition, one branch for each outcome; every leaf reaches the goal.
//! - `parallel_BxD`: B such trees of depth D in parallel, joined into the
//!   goal: few places, and markings that multiply (the product of the trees').
//!
//! `cargo run --release -p learnpnp-probes --example big_plans [DIR]` writes `grid_30x30`,
//! `grid_45x45` (10,122 places), `grid_30x30_tracked`, `conditional_10`
//! (10,235 places), `parallel_3x3` and `parallel_4x4` as PNML into DIR (default: a temporary directory), to be
//! checked with `learnpnp check DIR/grid_45x45.pnml`.

use std::path::PathBuf;

use learnpnp::plan::{PlaceRef, PlanBuilder};
use learnpnp::pnml::{self, Dialect};

/// The four moves, in CliffWalking's order (as `grid.py` names them).
const MOVES: [&str; 4] = ["up", "right", "down", "left"];

/// `grid.py`'s plan on a `side` x `side` grid (the last cell is the goal),
/// with a tracker for every cell's atom when `tracked`.
fn grid(side: usize, tracked: bool) -> PlanBuilder {
    let suffix = if tracked { "_tracked" } else { "" };
    let mut b = PlanBuilder::new(format!("grid_{side}x{side}{suffix}"));
    let cells = side * side;
    if tracked {
        for cell in 0..cells {
            b.tracker(&format!("at_{cell}"));
        }
    }
    let sense = b.initial_place("sense");
    let goal = b.goal_place();
    for cell in 0..cells {
        let guard = format!("[at_{cell}]");
        if cell == cells - 1 {
            b.transition(guard, &[(sense, 1)], &[(goal, 1)]);
            continue;
        }
        let here = b.place(format!("cell_{cell}"));
        b.transition(guard, &[(sense, 1)], &[(here, 1)]);
        for action in MOVES {
            b.action_into(here, action, sense);
        }
    }
    b
}

/// A conditional plan: a binary tree of sensing actions of depth `depth`,
/// two actions before each sensing, the leaves into one goal place.
fn conditional(depth: u32) -> PlanBuilder {
    let mut b = PlanBuilder::new(format!("conditional_{depth}"));
    let start = b.initial_place("start");
    let goal = b.goal_place();
    tree(&mut b, start, depth, goal, "");
    b
}

/// The tree of [`conditional`] from `start`, its leaves into `end`, its
/// actions and conditions named with `prefix`.
fn tree(b: &mut PlanBuilder, start: PlaceRef, depth: u32, end: PlaceRef, prefix: &str) {
    // (place where a node starts, its level)
    let mut nodes = vec![(start, 0)];
    while let Some((from, level)) = nodes.pop() {
        let mut at = b.action(from, &format!("{prefix}goto_{level}")).done;
        if level == depth {
            b.action_into(at, &format!("{prefix}deliver_{level}"), end);
            continue;
        }
        at = b.action(at, &format!("{prefix}look_{level}")).done;
        let condition = format!("{prefix}found_{level}");
        let sensed = b.sensing(
            at,
            &format!("{prefix}check_{level}"),
            &[&condition, &format!("not {condition}")],
        );
        nodes.extend(sensed.outcomes.into_iter().map(|out| (out, level + 1)));
    }
}

/// `branches` conditional trees of depth `depth` run in parallel (a fork,
/// then a join into the goal): their markings multiply.
fn parallel(branches: usize, depth: u32) -> PlanBuilder {
    let mut b = PlanBuilder::new(format!("parallel_{branches}x{depth}"));
    let start = b.initial_place("start");
    let goal = b.goal_place();
    let ends: Vec<PlaceRef> = b
        .fork(start, branches)
        .into_iter()
        .enumerate()
        .map(|(i, from)| {
            let end = b.place(format!("done_{i}"));
            tree(&mut b, from, depth, end, &format!("b{i}_"));
            end
        })
        .collect();
    let joined = b.join(&ends);
    b.transition("finish", &[(joined, 1)], &[(goal, 1)]);
    b
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(std::env::args().nth(1))
}

/// Writes the plans into the directory `arg` (a temporary one by default).
fn run(arg: Option<String>) -> Result<(), Box<dyn std::error::Error>> {
    let dir = arg.map_or_else(|| std::env::temp_dir().join("learnpnp-big-plans"), PathBuf::from);
    std::fs::create_dir_all(&dir)?;
    let plans = [
        grid(30, false),
        grid(45, false),
        grid(30, true),
        conditional(10),
        parallel(3, 3),
        parallel(4, 4),
    ];
    for b in plans {
        let net = b.build_net()?;
        let file = dir.join(format!("{}.pnml", net.name()));
        pnml::write_file(&net, Dialect::Jarp, &file)?;
        println!(
            "wrote {} ({} places, {} transitions)",
            file.display(),
            net.places().len(),
            net.transitions().len()
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use learnpnp::analysis::{DEFAULT_LIMIT, check};
    use learnpnp::plan::AllowedAtoms;

    #[test]
    fn a_generated_grid_of_thousands_of_places_is_checked_conclusively() {
        let plan = grid(20, false).build(AllowedAtoms::Open).expect("a plan");
        assert_eq!(plan.net().places().len(), 2 + 399 * 5);
        let report = check(&plan, DEFAULT_LIMIT);
        assert!(report.complete && report.passed(), "{}", report.summary(4));
        // sense, every cell, every move's execution place, the goal.
        assert_eq!(report.markings, 2 + 399 * 5);
        assert_eq!(report.choice_points.len(), 1 + 399);
    }

    #[test]
    fn trackers_of_every_cell_do_not_multiply_what_is_stored() {
        let plan = grid(10, true).build(AllowedAtoms::Open).expect("a plan");
        let report = check(&plan, DEFAULT_LIMIT);
        assert!(report.complete && report.passed(), "{}", report.summary(4));
        // 2^100 combinations of trackers: counted (saturated), not stored.
        assert_eq!(report.markings, usize::MAX);
        assert_eq!((report.parts, report.stored), (101, 2 + 99 * 5 + 200));
        assert!(
            report
                .to_string()
                .contains("at least 18446744073709551615 reachable marking(s)")
        );
    }

    #[test]
    fn a_generated_conditional_plan_of_thousands_of_places_is_checked_conclusively() {
        let plan = conditional(8).build(AllowedAtoms::Open).expect("a plan");
        assert_eq!(plan.net().places().len(), 2_555);
        let report = check(&plan, DEFAULT_LIMIT);
        assert!(report.complete && report.passed(), "{}", report.summary(4));
        assert_eq!(report.markings, plan.net().places().len());
        // Sensing outcomes are no choices.
        assert!(report.choice_points.is_empty());
    }

    #[test]
    fn the_example_writes_the_plans() {
        let dir = std::env::temp_dir().join(format!("learnpnp-big-plans-{}", std::process::id()));
        run(Some(dir.to_string_lossy().into_owned())).expect("the example runs");
        assert!(dir.join("grid_45x45.pnml").exists() && dir.join("conditional_10.pnml").exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
