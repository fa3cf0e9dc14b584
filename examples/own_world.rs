//! Learn in a world of your own: a small gymnasium-style environment
//! (`examples/common/courier.rs`: `reset`, `step(action)`), its atoms as a
//! knowledge base, its actions registered by name, a plan with choice points,
//! and SoSMC learning at them. The learned values are saved for
//! `learnpnp values FILE --plan PLAN` and for `greedy_from_saved`.
//!
//! `cargo run --example own_world [DIR]` (default: a temporary directory).

#[path = "common/courier.rs"]
mod courier;

use std::path::PathBuf;

use learnpnp::learning::persist::{self, SavedValues};
use learnpnp::pnml::{self, Dialect};

/// Learning episodes.
const EPISODES: u64 = 3000;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(std::env::args().nth(1))
}

/// The example, given the directory to write into (a temporary one by default); the tests call it
/// without the test harness's own arguments.
fn run(arg: Option<String>) -> Result<(), Box<dyn std::error::Error>> {
    let dir = arg.map_or_else(|| std::env::temp_dir().join("learnpnp-own-world"), PathBuf::from);
    std::fs::create_dir_all(&dir)?;
    let agent = courier::train(7, EPISODES)?;
    let plan = agent.plan();

    // What was learned, at each choice point: the value of each route.
    let saved = SavedValues::new("eps-sosmc", agent.learner().values(), &[plan]);
    let learned = learnpnp::learning::by_choice::group_by_choice(&[plan], &saved)?;
    for choice in &learned.choices {
        for option in &choice.options {
            println!(
                "at [{}]: {:<12} value {:>6.2} ({} updates){}",
                choice.at_text,
                option.name,
                option.value.unwrap_or(f64::NEG_INFINITY),
                option.visits,
                if option.greedy { "  <- greedy" } else { "" }
            );
        }
    }

    let values = dir.join("values.bin");
    persist::save(&values, &saved)?;
    let plan_file = dir.join("courier.pnml");
    pnml::write_file(plan.net(), Dialect::Jarp, &plan_file)?;
    println!(
        "saved {}; see it with: learnpnp values {} --plan {}",
        values.display(),
        values.display(),
        plan_file.display()
    );
    Ok(())
}

/// The route the learned values prefer in each weather.
#[cfg(test)]
fn greedy_routes(seed: u64) -> Vec<(String, String)> {
    let agent = courier::train(seed, EPISODES).expect("training runs");
    let plan = agent.plan();
    let saved = SavedValues::new("eps-sosmc", agent.learner().values(), &[plan]);
    let learned = learnpnp::learning::by_choice::group_by_choice(&[plan], &saved).expect("the same plan");
    learned
        .choices
        .iter()
        .map(|c| {
            let best = c.options.iter().find(|o| o.greedy).map_or("none", |o| o.name.as_str());
            (c.at_text.clone(), best.to_string())
        })
        .collect()
}

#[test]
fn the_example_runs() {
    run(None).expect("the example runs");
}

/// Short is best when dry (-2 against -3), long in the rain (-3 against -7):
/// SoSMC finds both, whatever the seed (five seeds tried).
#[test]
fn sosmc_learns_the_best_route_in_each_weather() {
    for seed in [1, 2, 3, 4, 5] {
        let routes = greedy_routes(seed);
        assert_eq!(
            routes,
            [
                ("wet".to_string(), "Long.start".to_string()),
                ("dry".to_string(), "Short.start".to_string())
            ],
            "seed {seed}"
        );
    }
}
