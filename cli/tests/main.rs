//! The learnpnp command's tests, one binary: every subcommand run as a user runs it, its flags, its files and its errors.

// Each crate's test binary includes the workspace's shared helpers; each uses a subset.
#[allow(dead_code)]
#[path = "../../tests/util.rs"]
mod util;

use std::process::{Command, Output};

/// Runs the `learnpnp` command with `args`.
fn learnpnp(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_learnpnp"))
        .args(args)
        .output()
        .expect("the learnpnp command runs")
}

/// A short experiment's command line, `experiment DOMAIN --algo ALGO --runs RUNS --episodes EPISODES`, to extend.
fn short_experiment<'a>(domain: &'a str, algo: &'a str, runs: &'a str, episodes: &'a str) -> Vec<&'a str> {
    vec![
        "experiment",
        domain,
        "--algo",
        algo,
        "--runs",
        runs,
        "--episodes",
        episodes,
    ]
}

mod bad_input;
mod cli;
mod domain_descriptions;
mod experiment_options;
mod experiment_resume;
mod generate_cli;
mod headless;
mod keepaway_replay;
mod learned_values;
mod pnp_library_plans;
mod replay_browser;
mod reproduce_summary;
mod result_dirs;
mod schema_cli;
mod shards;
mod slurm_cluster;
mod view_browser;
