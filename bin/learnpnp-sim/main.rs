//! `learnpnp-sim`: the Keepaway simulator process of a multi-process run
//! (started by `learnpnp-supervisor`, which passes every argument).

use std::process::ExitCode;

use anyhow::Context;
use clap::Parser;
use learnpnp_system::child_args::RunContextArgs;
use learnpnp_system::multiprocess::RunContext;
use learnpnp_system::multiprocess::host::simulator;

/// The Keepaway simulator behind iceoryx2 services.
#[derive(Parser)]
#[command(name = "learnpnp-sim", version)]
struct Args {
    #[command(flatten)]
    context: RunContextArgs,
    /// Round trips of the floor measurement before the first episode.
    #[arg(long, default_value_t = 20_000)]
    floor_round_trips: usize,
    /// Continue a killed simulator's run from its journal (the last episode boundary).
    #[arg(long)]
    resume: bool,
}

fn main() -> ExitCode {
    learnpnp_system::multiprocess::start_process();
    let args = Args::parse();
    let context = RunContext::from(args.context);
    match simulator::run(&context, args.floor_round_trips, args.resume).context("simulator") {
        Ok(result) => {
            if let Some(error) = &result.error {
                eprintln!("simulator: the run ended early: {error}");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
