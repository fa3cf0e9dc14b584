//! `learnpnp-soak`: the test and measurement harness around the
//! multi-process system (the crate `learnpnp-harness`). `soak` runs the
//! system for a set time or number of cycles while sampling every process
//! (with `--chaos`, injecting faults); `bench-latency` measures the round
//! trips per wait strategy; `bench-world` how a world run's cycles per second
//! and round trip grow with the agents. Each takes the flags of
//! `learnpnp-supervisor`'s run.

#[path = "../learnpnp-supervisor/run_args.rs"]
mod run_args;

use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand};
use learnpnp_flags::args::named;
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_harness::bench_latency::{bench_latency, configurations};
use learnpnp_harness::bench_world::bench_world;
use learnpnp_harness::chaos::{Chaos, GARBAGE_COMMAND, SoakLength, publish_garbage};
use learnpnp_harness::soak::{Soak, SoakLimits};
use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::ipc::wait::WaitStrategy;

use run_args::{DEFAULT_WORLD_EPISODES, RunArgs, UNBOUNDED_EPISODES, prepare, run_system};

/// Soaks, chaos and benchmarks of the multi-process system.
#[derive(Parser, Debug)]
#[command(name = "learnpnp-soak", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run the system for a set time or number of cycles while sampling every
    /// process (memory, descriptors, shared-memory files); --chaos injects faults.
    Soak(SoakArgs),
    /// Measure floor, round trip and compute time per wait strategy, idle and under load.
    BenchLatency(BenchArgs),
    /// Measure how a world run's cycles/s and round trip grow with the agents
    /// (default: the corridor world beside this binary, lock-step).
    BenchWorld(BenchWorldArgs),
    /// (Chaos soaks) Publish garbage on every service of a run, as a foreign process.
    #[command(name = GARBAGE_COMMAND, hide = true)]
    PublishGarbage(GarbageArgs),
}

/// The run a garbage publisher joins.
#[derive(Args, Debug)]
struct GarbageArgs {
    /// The run's iceoryx2 prefix.
    #[arg(long)]
    ipc_prefix: String,
    /// The run's id.
    #[arg(long)]
    run_id: u64,
    /// A world run with this many agents (its services, not Keepaway's).
    #[arg(long)]
    world_agents: Option<usize>,
}

/// A soak: the system for a set time, sampled once a second.
#[derive(Args, Debug)]
struct SoakArgs {
    /// Stop after this many seconds.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=30 * 86_400))]
    duration: Option<u64>,
    /// Stop after this many cycles (864,000 cycles: one simulated day).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    cycles: Option<u64>,
    /// Inject faults at points drawn from this seed, spread over the soak's
    /// --duration (or its --cycles); a killed simulator is restarted from its
    /// last episode boundary.
    #[arg(long)]
    chaos: Option<u64>,
    #[command(flatten)]
    run: RunArgs,
}

/// The latency benchmark.
#[derive(Args, Debug)]
struct BenchArgs {
    /// Seconds each configuration runs.
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(2..=3600))]
    seconds: u64,
    /// The wait strategies measured.
    #[arg(long, value_parser = named::<WaitStrategy>(), value_delimiter = ',', default_value = "spin,yield,block,hybrid")]
    strategies: Vec<WaitStrategy>,
    #[command(flatten)]
    run: RunArgs,
}

/// The world benchmark.
#[derive(Args, Debug)]
struct BenchWorldArgs {
    /// The numbers of agents measured.
    #[arg(long = "agent-counts", value_delimiter = ',', default_value = "1,2,4,8,16", value_parser = clap::value_parser!(u8).range(1..=16))]
    agent_counts: Vec<u8>,
    #[command(flatten)]
    run: RunArgs,
}

fn soak(args: SoakArgs) -> Result<ExitCode> {
    let length = match (args.duration, args.cycles) {
        (Some(seconds), _) => SoakLength::Time(Duration::from_secs(seconds)),
        (None, Some(cycles)) => SoakLength::Cycles(cycles),
        (None, None) => bail!("a soak needs --duration SECONDS or --cycles N"),
    };
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let (mut config, mut out) = prepare(&args.run, UNBOUNDED_EPISODES)?;
    let chaos = match args.chaos {
        Some(seed) => {
            config.restart_simulator = true;
            let chaos = Chaos::new(seed, length, config.clock);
            for (at, kind) in chaos.schedule() {
                eprintln!("chaos: {kind:?} at {:.1}% of the soak", 100.0 * at);
            }
            Some(chaos)
        }
        None => None,
    };
    let limits = SoakLimits {
        duration: args.duration.map(Duration::from_secs),
        cycles: args.cycles,
    };
    let mut observer = Soak::new(limits, chaos);
    run_system(&config, &mut out, &interrupt, &mut observer)?;
    let Some(report) = observer.report() else {
        bail!("the soak ended without a report");
    };
    for fault in &report.faults {
        println!(
            "fault at {:.1} s: {}: {} ({})",
            fault.time,
            fault.kind,
            fault.outcome,
            if fault.survived { "survived" } else { "NOT survived" }
        );
    }
    println!("soak verdict: {}", report.verdict);
    Ok(if report.passed {
        ExitCode::SUCCESS
    } else {
        ExitCode::FAILURE
    })
}

fn bench(args: BenchArgs) -> Result<ExitCode> {
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let (config, mut out) = prepare(&args.run, UNBOUNDED_EPISODES)?;
    let table = bench_latency(
        &config,
        &configurations(&args.strategies),
        Duration::from_secs(args.seconds),
        &mut out,
        interrupt.flag(),
    )?;
    print!("{table}");
    println!(
        "results in {}: latency.json, latency.txt, latency.svg, latency/*.hgrm",
        out.path().display()
    );
    Ok(ExitCode::SUCCESS)
}

fn bench_world_cmd(args: BenchWorldArgs) -> Result<ExitCode> {
    let interrupt = Interrupt::install().context("installing the signal handlers")?;
    let mut run = args.run;
    if run.flags.plan.is_none() {
        bail!("bench-world needs the agents' plan: --plan plans/corridor.pnml");
    }
    if run.world_cmd.is_none() {
        let exe = std::env::current_exe().context("locating learnpnp-soak")?;
        run.world_cmd = Some(exe.with_file_name("learnpnp-corridor").display().to_string());
    }
    let (config, out) = prepare(&run, DEFAULT_WORLD_EPISODES)?;
    let out = out.path().to_path_buf();
    let counts: Vec<usize> = args.agent_counts.iter().map(|&n| usize::from(n)).collect();
    let (table, _) = bench_world(&config, &counts, &out, interrupt.flag())?;
    print!("{table}");
    println!(
        "results in {}: bench-world.csv, bench-world.svg, agents-N/",
        out.display()
    );
    Ok(ExitCode::SUCCESS)
}

fn main() -> ExitCode {
    learnpnp_system::multiprocess::start_process();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Soak(args) => soak(args),
        Command::BenchLatency(args) => bench(args),
        Command::BenchWorld(args) => bench_world_cmd(args),
        Command::PublishGarbage(args) => Namespace::from_prefix(&args.ipc_prefix)
            .context("the run's namespace")
            .and_then(|ns| publish_garbage(&ns, args.run_id, args.world_agents).context("publishing garbage"))
            .map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}
