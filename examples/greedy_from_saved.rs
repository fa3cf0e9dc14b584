//! Load saved values and run the greedy policy: the learned behaviour itself,
//! with no exploration and no learning.
//!
//! `cargo run --example greedy_from_saved [VALUES]`: a table saved by
//! `own_world` (DIR/values.bin); without one, a learner is trained and its
//! table saved to a temporary file first.

#[path = "common/courier.rs"]
mod courier;

use std::path::PathBuf;
use std::sync::Arc;

use learnpnp::PlanAgent;
use learnpnp::learning::EpisodeMode;
use learnpnp::learning::persist::{self, PlanLabels, SavedValues};

/// Greedy episodes to average.
const EPISODES: u32 = 2000;

/// The mean return of the greedy policy from the table in `values`.
fn greedy_mean(values: &std::path::Path) -> Result<f64, Box<dyn std::error::Error>> {
    let (saved, problem) = persist::load_latest(values)?;
    if let Some(problem) = problem {
        eprintln!("warning: {problem}; using the previous good table");
    }
    let plan = Arc::new(courier::plan()?);
    if saved.plans != [PlanLabels::of(&plan)] {
        return Err(format!("{} was not learned on the courier plan", values.display()).into());
    }
    // A fresh learner starting from the saved table.
    let mut learner = courier::learner(99);
    let initial = learner.values().initial_value();
    *learner.values_mut() = saved.to_table(initial);
    let mut agent = PlanAgent::new(plan, &courier::registry(), learner)?;
    let mut world = courier::Courier::new(2024);
    let mut total = 0.0;
    for _ in 0..EPISODES {
        total += courier::episode(&mut agent, &mut world, EpisodeMode::Greedy)?;
    }
    Ok(total / f64::from(EPISODES))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(std::env::args().nth(1))
}

/// The example, given a saved values file (by default, one trained here); the tests call it
/// without the test harness's own arguments.
fn run(arg: Option<String>) -> Result<(), Box<dyn std::error::Error>> {
    let values = match arg {
        Some(path) => PathBuf::from(path),
        None => {
            let agent = courier::train(7, 3000)?;
            let path = std::env::temp_dir().join(format!("learnpnp-greedy-{}.bin", std::process::id()));
            persist::save(
                &path,
                &SavedValues::new("eps-sosmc", agent.learner().values(), &[agent.plan()]),
            )?;
            path
        }
    };
    let mean = greedy_mean(&values)?;
    println!(
        "greedy policy from {}: mean return {mean:.3} over {EPISODES} episodes \
         (the best policy earns -5 on average: two deliveries, -2 when dry, -3 in the rain)",
        values.display()
    );
    Ok(())
}

#[test]
fn the_example_runs() {
    run(None).expect("the example runs");
}

/// The greedy policy from a saved table earns the optimum, -5 per episode:
/// a standard error of about 0.07 over 2000 episodes, so 0.3 is over four.
/// Always taking the short route would earn -9, always the long one -6.
#[test]
fn the_saved_greedy_policy_earns_the_optimum() {
    let agent = courier::train(11, 3000).expect("training runs");
    let path = std::env::temp_dir().join(format!("learnpnp-greedy-test-{}.bin", std::process::id()));
    persist::save(
        &path,
        &SavedValues::new("eps-sosmc", agent.learner().values(), &[agent.plan()]),
    )
    .expect("saved");
    let mean = greedy_mean(&path).expect("the table loads");
    let _ = std::fs::remove_file(&path);
    assert!((mean + 5.0).abs() < 0.3, "greedy mean {mean}");
}
