//! `learnpnp-agent`: one keeper's process in a multi-process run (started by
//! `learnpnp-supervisor`, which passes every argument).

use std::process::ExitCode;

use clap::Parser;
use learnpnp_system::cli::RunContextArgs;
use learnpnp_system::multiprocess::agent_process::{self, AgentSettings};
use learnpnp_system::multiprocess::supervisor::EXIT_CANNOT_RESUME;
use learnpnp_system::multiprocess::{ProcessError, RunContext};

/// One keeper: its plan, learner and executor, behind iceoryx2 services.
#[derive(Parser)]
#[command(name = "learnpnp-agent", version)]
struct Args {
    #[command(flatten)]
    context: RunContextArgs,
    /// The keeper (1, 2 or 3).
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=3))]
    keeper: u8,
    /// Checkpoint the values every this many learning episodes (0: only on request and at the end).
    #[arg(long, default_value_t = 100)]
    checkpoint_every: u64,
    /// Resume from the checkpoint in the work directory (a restart).
    #[arg(long)]
    resume: bool,
}

fn main() -> ExitCode {
    iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Warn);
    // A write beyond the file-size limit (a full disk, a quota) fails with an
    // error the checkpointing reports, instead of killing the agent.
    // SAFETY: setting a signal's disposition to "ignore" has no other effect.
    unsafe { libc::signal(libc::SIGXFSZ, libc::SIG_IGN) };
    let args = Args::parse();
    let settings = AgentSettings {
        keeper: usize::from(args.keeper) - 1,
        checkpoint_every: args.checkpoint_every,
        resume: args.resume,
    };
    match agent_process::run(&RunContext::from(args.context), &settings) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e @ ProcessError::CannotResume(_)) => {
            eprintln!("error: keeper {}: {e}", args.keeper);
            ExitCode::from(EXIT_CANNOT_RESUME as u8)
        }
        Err(e) => {
            eprintln!("error: keeper {}: {e}", args.keeper);
            ExitCode::FAILURE
        }
    }
}
