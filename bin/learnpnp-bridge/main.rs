//! `learnpnp-bridge`: one host's bridge of a run across hosts (started by
//! that host's `learnpnp-supervisor`, which passes every argument): it
//! carries the run's services between the host's iceoryx2 namespace and the
//! other hosts over Zenoh (TCP only, multicast scouting off).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, ValueEnum};
use learnpnp_cli::interrupt::Interrupt;
use learnpnp_system::bridge::link::Endpoints;
use learnpnp_system::bridge::{BridgeConfig, Side, run};

/// Which host the bridge serves.
#[derive(Debug, Clone, Copy, ValueEnum)]
enum Host {
    /// Host A: the simulator or world; it serves the run's description.
    Host,
    /// A host of remote agents; it fetches the run's description.
    Remote,
}

/// One host's bridge of a run across hosts.
#[derive(Parser)]
#[command(name = "learnpnp-bridge", version)]
struct Args {
    /// This host's iceoryx2 prefix.
    #[arg(long)]
    ipc_prefix: String,
    /// Which host this is.
    #[arg(long, value_enum)]
    side: Host,
    /// Endpoints to listen on (tcp/ADDRESS:PORT).
    #[arg(long)]
    listen: Vec<String>,
    /// Endpoints to connect to (tcp/ADDRESS:PORT).
    #[arg(long)]
    connect: Vec<String>,
    /// The run's description: served (host A) or written once fetched.
    #[arg(long)]
    run_info: PathBuf,
    /// This host's work directory.
    #[arg(long)]
    work_dir: PathBuf,
}

fn main() -> ExitCode {
    learnpnp_system::resident_memory::return_large_blocks_when_freed();
    iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Warn);
    let args = Args::parse();
    let interrupt = match Interrupt::install() {
        Ok(interrupt) => interrupt,
        Err(e) => {
            eprintln!("error: bridge: installing the signal handlers: {e}");
            return ExitCode::FAILURE;
        }
    };
    let config = BridgeConfig {
        ipc_prefix: args.ipc_prefix,
        side: match args.side {
            Host::Host => Side::Host,
            Host::Remote => Side::Remote,
        },
        endpoints: Endpoints {
            listen: args.listen,
            connect: args.connect,
        },
        run_info: args.run_info,
        work_dir: args.work_dir,
    };
    match run(&config, interrupt.flag()) {
        Ok(traffic) => {
            let m = traffic.messages;
            eprintln!(
                "bridge: {} messages sent, {} received, {} refused; {} files",
                m.sent, m.received, m.refused, traffic.files
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: bridge: {e}");
            ExitCode::FAILURE
        }
    }
}
