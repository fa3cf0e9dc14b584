//! `learnpnp-agent`: one keeper's process in a Keepaway run, or one agent's
//! in the run of a world in its own process, or a remote host's floor echo
//! (started by `learnpnp-supervisor`, which passes every argument).

use std::io::Write as _;
use std::process::ExitCode;

use clap::Parser;
use learnpnp_system::child_args::RunContextArgs;
use learnpnp_system::multiprocess::agent::keeper::{self, AgentSettings};
use learnpnp_system::multiprocess::agent::world::{self, EXIT_PLAN_DOES_NOT_FIT, WorldAgentSettings};
use learnpnp_system::multiprocess::floor_probe;
use learnpnp_system::multiprocess::supervisor::EXIT_CANNOT_RESUME;
use learnpnp_system::multiprocess::{ProcessError, RunContext};

/// One keeper or one world's agent: its plan, learner and executor, behind iceoryx2 services.
#[derive(Parser)]
#[command(name = "learnpnp-agent", version)]
#[command(group = clap::ArgGroup::new("who").required(true).args(["keeper", "world_agent", "floor_echo"]))]
struct Args {
    #[command(flatten)]
    context: RunContextArgs,
    /// The keeper (1, 2 or 3) of a Keepaway run.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=3))]
    keeper: Option<u8>,
    /// The agent (1 to 16) of a world in its own process.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=16))]
    world_agent: Option<u8>,
    /// Echo a remote host's floor pings (its own iceoryx2 floor), then exit.
    #[arg(long)]
    floor_echo: bool,
    /// Checkpoint the values every this many learning episodes (0: only on request and at the end).
    #[arg(long, default_value_t = 100)]
    checkpoint_every: u64,
    /// Resume from the checkpoint in the work directory (a restart).
    #[arg(long)]
    resume: bool,
}

fn main() -> ExitCode {
    learnpnp_system::multiprocess::start_process();
    // A write beyond the file-size limit (a full disk, a quota) fails with an
    // error the checkpointing reports, instead of killing the agent.
    // SAFETY: setting a signal's disposition to "ignore" has no other effect.
    unsafe { libc::signal(libc::SIGXFSZ, libc::SIG_IGN) };
    let args = Args::parse();
    let context = RunContext::from(args.context);
    let (who, outcome) = match (args.keeper, args.world_agent) {
        _ if args.floor_echo => ("floor echo".to_string(), floor_probe::run_echo(&context)),
        (Some(keeper), _) => {
            let settings = AgentSettings {
                keeper: usize::from(keeper) - 1,
                checkpoint_every: args.checkpoint_every,
                resume: args.resume,
            };
            (format!("keeper {keeper}"), keeper::run(&context, &settings))
        }
        (None, agent) => {
            let agent = agent.unwrap_or(1);
            let settings = WorldAgentSettings {
                agent: usize::from(agent) - 1,
                checkpoint_every: args.checkpoint_every,
                resume: args.resume,
            };
            (format!("agent {agent}"), world::run(&context, &settings))
        }
    };
    let Err(e) = outcome else {
        return ExitCode::SUCCESS;
    };
    // Not eprintln!, which panics when the log cannot be written (a full disk).
    let _ = writeln!(std::io::stderr(), "error: {who}: {e}");
    match e {
        ProcessError::CannotResume(_) => ExitCode::from(EXIT_CANNOT_RESUME as u8),
        ProcessError::PlanDoesNotFit(_) => ExitCode::from(EXIT_PLAN_DOES_NOT_FIT as u8),
        _ => ExitCode::FAILURE,
    }
}
