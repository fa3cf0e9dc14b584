//! `learnpnp-supervisor`: the multi-process learner system. It starts the
//! Keepaway simulator and one agent process per keeper on iceoryx2 shared
//! memory, watches and restarts them, and reports the learning curve and the
//! latency figures. With no arguments: Keepaway 3 vs 2, three Soft-SoSMC
//! learners positioning themselves, lock-step, one run.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result};
use clap::{Parser, ValueEnum};
use learnpnp::experiment::args::{DomainName, ExperimentOptions};
use learnpnp::experiment::spec::Algorithm;
use learnpnp::interrupt::Interrupt;
use learnpnp::ipc::namespace::clean_stale;
use learnpnp::ipc::wait::WaitStrategy;
use learnpnp::multiprocess::Clock;
use learnpnp::multiprocess::launch::Binaries;
use learnpnp::multiprocess::supervisor::{Progress, SupervisorConfig, supervise};
use learnpnp::result_dir::ResultDir;

/// The Keepaway experiments the system runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Domain {
    /// Every keeper learns where to stand (thesis 7.3): three learner processes.
    KeepawayPosition,
    /// Keeper 1 learns the pass decision (thesis 7.2); keepers 2 and 3 follow the threshold policy.
    KeepawayPass,
}

/// Runs Keepaway 3 vs 2 as a simulator process and three keeper processes on
/// iceoryx2 shared memory, and reports the learning curve and latencies.
#[derive(Parser, Debug)]
#[command(name = "learnpnp-supervisor", version)]
struct Args {
    /// The experiment.
    #[arg(long, value_enum, default_value = "keepaway-position")]
    domain: Domain,
    /// lockstep: step as soon as every command is in; realtime: every 100 ms.
    #[arg(long, value_enum, default_value = "lockstep")]
    mode: Clock,
    /// How processes wait for messages (default: yield in lock-step, hybrid in real time).
    #[arg(long, value_enum)]
    wait: Option<WaitStrategy>,
    /// Output directory.
    #[arg(long, default_value = "out/system")]
    out: PathBuf,
    /// Agents checkpoint their values every this many learning episodes.
    #[arg(long, default_value_t = 100)]
    checkpoint_every: u64,
    /// Round trips of the iceoryx2 floor measurement in every run (default:
    /// 20,000 in lock-step, 1,000 five milliseconds apart in real time).
    #[arg(long)]
    floor_round_trips: Option<usize>,
    /// Seconds without a heartbeat after which a process is taken as hung.
    #[arg(long, default_value_t = 10)]
    heartbeat_timeout: u64,
    /// Restarts of one keeper in one run before the run is given up.
    #[arg(long, default_value_t = 5)]
    max_restarts: u32,
    #[command(flatten)]
    options: ExperimentOptions,
}

/// The main job's run when the user gives no --runs or --episodes: about one
/// to two minutes on a 2-core machine.
const DEFAULT_RUNS: usize = 1;
const DEFAULT_EPISODES: u64 = 3000;

fn run(args: Args) -> Result<ExitCode> {
    let domain = match args.domain {
        Domain::KeepawayPosition => DomainName::KeepawayPosition,
        Domain::KeepawayPass => DomainName::KeepawayPass,
    };
    let spec = args
        .options
        .clone()
        .or_defaults(Algorithm::SoftSosmc, DEFAULT_RUNS, DEFAULT_EPISODES)
        .spec(domain)?;
    spec.protocol.validate()?;
    // Checked and locked before any work.
    let mut out = ResultDir::open(&args.out)?;
    let wait = args.wait.unwrap_or(match args.mode {
        Clock::Lockstep => WaitStrategy::Yield,
        Clock::Realtime => WaitStrategy::Hybrid,
    });
    for stale in clean_stale().context("cleaning what earlier runs left in shared memory")? {
        eprintln!(
            "removed {} files of a dead run's iceoryx2 namespace {}",
            stale.removed, stale.prefix
        );
    }
    let config = SupervisorConfig {
        spec,
        clock: args.mode,
        wait,
        checkpoint_every: args.checkpoint_every,
        floor_round_trips: args.floor_round_trips.unwrap_or(match args.mode {
            Clock::Lockstep => 20_000,
            Clock::Realtime => 1_000,
        }),
        heartbeat_timeout: Duration::from_secs(args.heartbeat_timeout),
        max_restarts: args.max_restarts,
        restart_simulator: false,
        binaries: Binaries::beside_current_exe()?,
    };
    let p = config.spec.protocol;
    eprintln!(
        "learnpnp-supervisor: {} with {} on simulator + 3 keeper processes; {} mode, {} wait; {} run(s) x {} learning episodes, evaluation every {} ({} episodes), seed {}; results in {}",
        config.spec.domain.name(),
        config.spec.algorithm.name(),
        args.mode.name(),
        wait.name(),
        p.runs,
        p.episodes,
        p.eval_every,
        p.eval_episodes,
        config.spec.seed,
        args.out.display()
    );
    // A second signal while stopping ends the supervisor at once (its
    // children die with it; the next launch removes their shared memory).
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let bar = if std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        let bar = indicatif::ProgressBar::new(p.episodes * p.runs as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template("[{bar:40}] {pos}/{len} learning episodes ({eta})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        Some(bar)
    } else {
        None
    };
    let per_run = p.episodes;
    let mut progress = Progress(|run: usize, episodes: u64| {
        if let Some(bar) = &bar {
            bar.set_position(run as u64 * per_run + episodes);
        }
    });
    let report = supervise(&config, &mut out, interrupt.flag(), &mut progress)?;
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
    let summary = &report.summary;
    print!("{}", report.latency_table());
    if let Some(e) = &summary.experiment {
        println!(
            "learning: final evaluation {:.2} s of possession (95% CI {:.2} .. {:.2}), greedy {}, mean episode {:.2} s",
            e.final_mean,
            e.final_ci95[0],
            e.final_ci95[1],
            learnpnp::experiment::output::greedy_text(e),
            summary.mean_episode_seconds
        );
    }
    println!(
        "results in {}: summary.json, curve.csv, curve.svg, episodes.csv, latency.svg, latency/*.hgrm, values*.bin, runs/*/ (logs, checkpoints)",
        args.out.display()
    );
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

fn main() -> ExitCode {
    iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Warn);
    match run(Args::parse()) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
