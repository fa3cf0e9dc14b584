//! `learnpnp-supervisor`: the multi-process learner system. It starts the
//! Keepaway simulator and one agent process per keeper on iceoryx2 shared
//! memory, watches and restarts them, and reports the learning curve and the
//! latency figures. With no arguments: Keepaway 3 vs 2, three Soft-SoSMC
//! learners positioning themselves, lock-step, one run. `remote` joins a run
//! across hosts, `link-certs` makes its hosts' certificates. (Soaks, chaos
//! and the benchmarks are `learnpnp-soak`'s.)

mod run_args;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_system::hosts::certs::{self, CertRequest};
use learnpnp_system::ipc::namespace::clean_stale;
use learnpnp_system::multiprocess::supervisor::Progress;
use learnpnp_system::multiprocess::supervisor::launch::{Binaries, Needs};
use learnpnp_system::multiprocess::supervisor::remote_host::{RemoteConfig, join};

use run_args::{LinkArgs, RunArgs, prepare, run_system};

/// Runs Keepaway 3 vs 2 as a simulator process and three keeper processes on
/// iceoryx2 shared memory, and reports the learning curve and latencies.
#[derive(Parser, Debug)]
#[command(name = "learnpnp-supervisor", version, args_conflicts_with_subcommands = true)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    run: RunArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the system (what it does with no command).
    Run(Box<RunArgs>),
    /// Join a run across hosts as a host of remote agents: its bridge connects
    /// to the run's host (started with --remote-agents), and it runs those
    /// agents here until that host ends the run.
    Remote(RemoteArgs),
    /// Make the private CA of a run's hosts and their certificates: a
    /// directory each for host A, host B and every monitor (copy each to its
    /// host; `ca/` holds the CA's key and stays with you).
    LinkCerts(LinkCertsArgs),
}

/// The certificates of a run's hosts.
#[derive(Args, Debug)]
struct LinkCertsArgs {
    /// Where to write them (an existing CA in DIR/ca is used, not replaced).
    #[arg(long, default_value = "link-certs")]
    dir: PathBuf,
    /// An address or DNS name host B connects to host A by (repeat for more):
    /// host B's bridge checks that host A's certificate names it.
    #[arg(long = "host-a", required = true)]
    host_a: Vec<String>,
    /// A read-only monitor's directory name (repeat for more): its
    /// certificate may only subscribe to the heartbeats and episode events.
    #[arg(long = "monitor", default_value = "monitor")]
    monitors: Vec<String>,
}

/// A host of remote agents.
#[derive(Args, Debug)]
struct RemoteArgs {
    /// The run's host's bridge (quic/ADDRESS:PORT).
    #[arg(long, required = true)]
    bridge_connect: Vec<String>,
    #[command(flatten)]
    link: LinkArgs,
    /// This host's directory (logs, checkpoints, its summary.json).
    #[arg(long, default_value = "out/remote")]
    out: PathBuf,
    /// Seconds without a heartbeat after which an agent is taken as hung.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(3..=3600))]
    heartbeat_timeout: u64,
    /// Restarts of one agent (or the bridge) before this host gives up.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=1000))]
    max_restarts: u32,
}

/// The main job's learning episodes when the user gives no --episodes: one
/// run of the thesis's length (Figure 7.3: 10,000 learning episodes), about
/// a minute on a 2-core machine.
const DEFAULT_EPISODES: u64 = 10_000;

/// A progress bar over the learning episodes, on a terminal.
fn progress_bar(total: u64) -> Option<indicatif::ProgressBar> {
    std::io::IsTerminal::is_terminal(&std::io::stderr()).then(|| {
        let bar = indicatif::ProgressBar::new(total);
        bar.set_style(
            indicatif::ProgressStyle::with_template("[{bar:40}] {pos}/{len} learning episodes ({eta})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        bar
    })
}

fn run(args: RunArgs) -> Result<ExitCode> {
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let (config, mut out) = prepare(&args, DEFAULT_EPISODES)?;
    let per_run = config.spec.protocol.episodes;
    let bar = progress_bar(per_run * config.spec.protocol.runs as u64);
    let mut progress = Progress(|run: usize, episodes: u64| {
        if let Some(bar) = &bar {
            bar.set_position(run as u64 * per_run + episodes);
        }
    });
    let report = run_system(&config, &mut out, &interrupt, &mut progress)?;
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let summary = report.summary;
    Ok(if let Some(failure) = &summary.failure {
        eprintln!("error: {failure}");
        ExitCode::FAILURE
    } else if !summary.complete {
        eprintln!(
            "stopped before the end: {} of {} runs completed",
            summary.runs_completed, summary.runs
        );
        ExitCode::from(interrupt.exit_status())
    } else {
        ExitCode::SUCCESS
    })
}

fn remote(args: RemoteArgs) -> Result<ExitCode> {
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    for stale in clean_stale().context("cleaning what earlier runs left in shared memory")? {
        eprintln!(
            "removed {} files of a dead run's iceoryx2 namespace {}",
            stale.removed, stale.prefix
        );
    }
    let config = RemoteConfig {
        link_certs: args.link.certs()?,
        connect: args.bridge_connect,
        binaries: Binaries::beside_current_exe(Needs {
            view: false,
            bridge: true,
        })?,
        heartbeat_timeout: Duration::from_secs(args.heartbeat_timeout),
        max_restarts: args.max_restarts,
    };
    let summary = join(&config, &args.out, interrupt.flag())?;
    println!(
        "run {} ({}): agent(s) {:?} here, {} restart(s), files {} host A; summary in {}",
        summary.run_id,
        summary.run_prefix,
        summary.agents,
        summary.restarts,
        if summary.shipped {
            "shipped to"
        } else {
            "NOT shipped to"
        },
        args.out.join("summary.json").display()
    );
    Ok(if summary.shipped {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn link_certs(args: LinkCertsArgs) -> Result<ExitCode> {
    let request = CertRequest {
        host_a: args.host_a,
        monitors: args.monitors,
    };
    let made = certs::make(&args.dir, &request).context("making the link's certificates")?;
    let ca = args.dir.join(certs::CA_DIR);
    if made.new_ca {
        println!(
            "a new private CA in {} (keep its key there, off the hosts)",
            ca.display()
        );
    } else {
        println!("the CA in {} signed them", ca.display());
    }
    for dir in &made.dirs {
        println!("  {}", dir.display());
    }
    println!(
        "copy {} to host A and {} to host B (--link-certs DIR on each)",
        args.dir.join(certs::HOST_A_DIR).display(),
        args.dir.join(certs::HOST_B_DIR).display()
    );
    Ok(ExitCode::SUCCESS)
}

fn main() -> ExitCode {
    learnpnp_system::multiprocess::start_process();
    let cli = Cli::parse();
    let result = match cli.command {
        None => run(cli.run),
        Some(Command::Run(args)) => run(*args),
        Some(Command::Remote(args)) => remote(args),
        Some(Command::LinkCerts(args)) => link_certs(args),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
