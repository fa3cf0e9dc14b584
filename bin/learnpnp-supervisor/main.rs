//! `learnpnp-supervisor`: the multi-process learner system. It starts the
//! Keepaway simulator and one agent process per keeper on iceoryx2 shared
//! memory, watches and restarts them, and reports the learning curve and the
//! latency figures. With no arguments: Keepaway 3 vs 2, three Soft-SoSMC
//! learners positioning themselves, lock-step, one run. `soak` runs it for a
//! set time while sampling every process (with `--chaos`, injecting faults);
//! `bench-latency` measures the round trips per wait strategy.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use clap::{Args, Parser, Subcommand, ValueEnum};
use learnpnp::experiment::options::DomainName;
use learnpnp::experiment::options::ExperimentOptions;
use learnpnp::experiment::result_dir::ResultDir;
use learnpnp::experiment::spec::{Algorithm, DomainSpec};
use learnpnp::named::Named;
use learnpnp_cli::args::named;
use learnpnp_cli::interrupt::Interrupt;
use learnpnp_cli::view::ViewFlags;
use learnpnp_system::hosts::PLAIN_TCP_WARNING;
use learnpnp_system::hosts::certs::{self, CertRequest, HostFiles};
use learnpnp_system::ipc::namespace::{Namespace, clean_stale};
use learnpnp_system::ipc::wait::WaitStrategy;
use learnpnp_system::multiprocess::Clock;
use learnpnp_system::multiprocess::bench_latency::{bench_latency, configurations};
use learnpnp_system::multiprocess::bench_world::bench_world;
use learnpnp_system::multiprocess::chaos::{Chaos, GARBAGE_COMMAND, SoakLength, publish_garbage};
use learnpnp_system::multiprocess::soak::{Soak, SoakLimits};
use learnpnp_system::multiprocess::supervisor::launch::{Binaries, Needs};
use learnpnp_system::multiprocess::supervisor::remote_host::{RemoteConfig, join};
use learnpnp_system::multiprocess::supervisor::{
    Cluster, Progress, RunObserver, SupervisorConfig, ViewConfig, supervise,
};

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
    Run(RunArgs),
    /// Run the system for a set time or number of cycles while sampling every
    /// process (memory, descriptors, shared-memory files); --chaos injects faults.
    Soak(SoakArgs),
    /// Measure floor, round trip and compute time per wait strategy, idle and under load.
    BenchLatency(BenchArgs),
    /// Join a run across hosts as a host of remote agents: its bridge connects
    /// to the run's host (started with --remote-agents), and it runs those
    /// agents here until that host ends the run.
    Remote(RemoteArgs),
    /// Make the private CA of a run's hosts and their certificates: a
    /// directory each for host A, host B and every monitor (copy each to its
    /// host; `ca/` holds the CA's key and stays with you).
    LinkCerts(LinkCertsArgs),
    /// Measure how a world run's cycles/s and round trip grow with the agents
    /// (default: the corridor world beside this binary, lock-step).
    BenchWorld(BenchWorldArgs),
    /// (Chaos soaks) Publish garbage on every service of a run, as a foreign process.
    #[command(name = GARBAGE_COMMAND, hide = true)]
    PublishGarbage(GarbageArgs),
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

/// How this host joins the link between hosts: its certificates, or plain TCP.
#[derive(Args, Debug, Clone)]
struct LinkArgs {
    /// This host's certificates: a directory made by `learnpnp-supervisor
    /// link-certs` (host A's `host-a`, host B's `host-b`), for TLS with
    /// mutual authentication and, on host A, access control.
    #[arg(long)]
    link_certs: Option<PathBuf>,
    /// Run the link over plain TCP (tcp/ADDRESS:PORT): no encryption, no
    /// authentication, no access control; anyone who reaches the port can
    /// read the run and take it over.
    #[arg(long, conflicts_with = "link_certs")]
    insecure_plain_tcp: bool,
}

impl LinkArgs {
    /// The certificates' directory, checked; `None` for plain TCP. An error
    /// if neither was chosen.
    fn certs(&self) -> Result<Option<PathBuf>> {
        match (&self.link_certs, self.insecure_plain_tcp) {
            (Some(dir), _) => {
                HostFiles::in_dir(dir)?;
                Ok(Some(dir.clone()))
            }
            (None, true) => {
                eprintln!("warning: {PLAIN_TCP_WARNING}");
                Ok(None)
            }
            (None, false) => bail!(
                "the link between hosts is TLS with mutual authentication: give --link-certs DIR \
                 (made by `learnpnp-supervisor link-certs --host-a ADDRESS`) and quic/ADDRESS:PORT endpoints, \
                 or --insecure-plain-tcp to give up encryption, authentication and access control"
            ),
        }
    }
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

/// A run of the system.
#[derive(Args, Debug, Clone)]
#[command(group(clap::ArgGroup::new("world").args(["world_cmd", "ros2"])))]
struct RunArgs {
    /// The experiment.
    #[arg(long, value_enum, default_value = "keepaway-position")]
    domain: Domain,
    /// Run a world in its own process instead of Keepaway: this command
    /// serves the world (given the run in LEARNPNP_* environment variables;
    /// see shm_layouts/README.md); --plan is every agent's plan, or
    /// --agent-plan gives each agent its own.
    #[arg(long, conflicts_with = "ros2")]
    world_cmd: Option<String>,
    /// Run a ROS 2 robot as the world over rmw_zenoh: the mapping file of
    /// the guide's `docs/guide/src/ros2.md`, served by `learnpnp-ros2-world` beside this binary
    /// (its refusals counted in the world's log); --plan as with --world-cmd.
    #[arg(long, value_name = "MAPPING")]
    ros2: Option<PathBuf>,
    /// With --world-cmd and --plan: how many agents, each in its own process
    /// with its own copy of the plan, learner and checkpoints (1 to 16).
    #[arg(long, default_value_t = 1, requires = "world", value_parser = clap::value_parser!(u8).range(1..=16))]
    agents: u8,
    /// With --world-cmd in real time: the cycle the world is told to keep, in
    /// milliseconds (LEARNPNP_PERIOD_MS; a robot at 10 Hz: 100).
    #[arg(long, default_value_t = 100, requires = "world", value_parser = clap::value_parser!(u64).range(1..=60_000))]
    world_period_ms: u64,
    /// Agents (1-based, e.g. 3 or 2,3) that run on other hosts, each host's
    /// own supervisor started there with `learnpnp-supervisor remote`; this
    /// host's bridge carries their services (needs --bridge-listen).
    #[arg(long, value_delimiter = ',', requires = "bridge_listen", value_parser = clap::value_parser!(u8).range(1..=16))]
    remote_agents: Vec<u8>,
    /// Where this host's bridge listens for the other hosts' (quic/ADDRESS:PORT).
    #[arg(long, requires = "remote_agents")]
    bridge_listen: Vec<String>,
    #[command(flatten)]
    link: LinkArgs,
    /// With --world-cmd: the next agent's plan (repeat it, one per agent,
    /// instead of --plan and --agents).
    #[arg(long = "agent-plan", requires = "world", conflicts_with = "agents")]
    agent_plans: Vec<PathBuf>,
    /// lockstep: step as soon as every command is in; realtime: every 100 ms.
    #[arg(long, value_parser = named::<Clock>(), default_value = "lockstep")]
    mode: Clock,
    /// How processes wait for messages (default: yield in lock-step, hybrid in real time).
    #[arg(long, value_parser = named::<WaitStrategy>())]
    wait: Option<WaitStrategy>,
    /// Output directory.
    #[arg(long, default_value = "out/system")]
    out: PathBuf,
    /// Agents checkpoint their values every this many learning episodes.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(1..=1_000_000_000))]
    checkpoint_every: u64,
    /// Round trips of the iceoryx2 floor measurement before each lock-step
    /// run (in real time the floor is sampled once in every cycle instead).
    #[arg(long, default_value_t = 20_000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    floor_round_trips: u64,
    /// Seconds without a heartbeat after which a process is taken as hung.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(3..=3600))]
    heartbeat_timeout: u64,
    /// Restarts of one process in one run before the run is given up.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=1000))]
    max_restarts: u32,
    /// Real time: the SCHED_FIFO priority of the simulator and the agents, so
    /// that a woken process runs ahead of other work on its core (0: normal
    /// scheduling; only with the block and hybrid waits, which sleep between
    /// cycles). Needs CAP_SYS_NICE or `ulimit -r`; if refused, the run goes on
    /// normally scheduled and its report says why.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u8).range(0..=99))]
    rt_priority: u8,
    /// The live view: a process of its own (`learnpnp-view`, read-only, off
    /// the learners' path, its address in runs/run-N/view.log) serves the
    /// agents' live feeds and every process's health; with several runs,
    /// run r > 0 records to `FILE-run<r>.mcap`.
    #[command(flatten)]
    view: ViewFlags,
    /// Write every record the view serves as a line of JSON to this file (appended).
    #[arg(long, value_name = "FILE")]
    view_jsonl: Option<PathBuf>,
    #[command(flatten)]
    flags: ExperimentOptions,
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

/// The world benchmark.
#[derive(Args, Debug)]
struct BenchWorldArgs {
    /// The numbers of agents measured.
    #[arg(long = "agent-counts", value_delimiter = ',', default_value = "1,2,4,8,16", value_parser = clap::value_parser!(u8).range(1..=16))]
    agent_counts: Vec<u8>,
    #[command(flatten)]
    run: RunArgs,
}

/// The main job's run when the user gives no --runs or --episodes: one run
/// of the thesis's length (Figure 7.3: 10,000 learning episodes), about a
/// minute on a 2-core machine.
const DEFAULT_RUNS: usize = 1;
const DEFAULT_EPISODES: u64 = 10_000;

/// Learning episodes of a world run when the user gives no --episodes.
const DEFAULT_WORLD_EPISODES: u64 = 1_000;

/// Learning episodes of a soak or benchmark run, which its time limit ends.
const UNBOUNDED_EPISODES: u64 = 1_000_000_000;

/// The world's command: `--world-cmd` as given, or `--ros2 MAPPING` as the
/// ROS 2 world beside this binary (the command is split on whitespace, so
/// its paths may hold none).
fn world_command(args: &RunArgs) -> Result<Option<String>> {
    let Some(mapping) = &args.ros2 else {
        return Ok(args.world_cmd.clone());
    };
    let exe = std::env::current_exe().context("locating learnpnp-supervisor")?;
    let world = exe.with_file_name("learnpnp-ros2-world");
    if !world.exists() {
        bail!(
            "--ros2: the ROS 2 world {} is not built (build it: cargo build --release -p learnpnp-ros2)",
            world.display()
        );
    }
    if let Some(spaced) = [world.as_path(), mapping.as_path()]
        .into_iter()
        .find(|p| p.to_string_lossy().chars().any(char::is_whitespace))
    {
        bail!(
            "--ros2: the path {} holds whitespace, which the world's command cannot carry",
            spaced.display()
        );
    }
    Ok(Some(format!("{} {}", world.display(), mapping.display())))
}

/// Everything but the observer: the configuration, and the output directory
/// checked and locked before any work.
fn prepare(args: &RunArgs, episodes: u64) -> Result<(SupervisorConfig, ResultDir)> {
    let domain = match args.domain {
        Domain::KeepawayPosition => DomainName::KeepawayPosition,
        Domain::KeepawayPass => DomainName::KeepawayPass,
    };
    let options = args.flags.clone();
    let spec = match world_command(args)? {
        Some(command) => {
            let plans = match (&options.plan, args.agent_plans.as_slice()) {
                (Some(plan), []) => vec![plan.clone(); usize::from(args.agents)],
                (None, []) => bail!("--world-cmd needs the agents' plans: --plan FILE, or --agent-plan FILE for each"),
                (None, plans) if plans.len() <= 16 => plans.to_vec(),
                (None, plans) => bail!("{} --agent-plan files: a world serves at most 16 agents", plans.len()),
                (Some(_), _) => bail!("--plan and --agent-plan do not go together: one plan for all, or one each"),
            };
            let world = DomainSpec::World { command, plans };
            // A soak's or a benchmark's unbounded run stays unbounded.
            let default = if episodes == UNBOUNDED_EPISODES {
                episodes
            } else {
                DEFAULT_WORLD_EPISODES
            };
            let episodes = options.episodes.unwrap_or(default);
            options
                .or_defaults(Algorithm::EpsSosmc, DEFAULT_RUNS, episodes)
                .spec_for(world)?
        }
        None => options
            .or_defaults(Algorithm::SoftSosmc, DEFAULT_RUNS, episodes)
            .spec(domain)?,
    };
    spec.protocol.validate()?;
    let out = ResultDir::open(&args.out)?;
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
    let view = (args.view.options().is_some() || args.view_jsonl.is_some()).then(|| ViewConfig {
        address: args.view.view,
        record_mcap: args.view.record_mcap.clone(),
        pnp_monitor: args.view.pnp_monitor,
        jsonl: args.view_jsonl.clone(),
    });
    let config = SupervisorConfig {
        spec,
        clock: args.mode,
        wait,
        checkpoint_every: args.checkpoint_every,
        rt_priority: args.rt_priority,
        floor_round_trips: args.floor_round_trips as usize,
        heartbeat_timeout: Duration::from_secs(args.heartbeat_timeout),
        max_restarts: args.max_restarts,
        restart_simulator: false,
        binaries: Binaries::beside_current_exe(Needs {
            view: view.is_some(),
            bridge: !args.remote_agents.is_empty(),
        })?,
        world_period: Duration::from_millis(args.world_period_ms),
        cluster: match args.remote_agents.is_empty() {
            true => None,
            false => Some(Cluster {
                remote: args.remote_agents.iter().map(|&k| usize::from(k) - 1).collect(),
                listen: args.bridge_listen.clone(),
                link_certs: args.link.certs()?,
            }),
        },
        view,
        // A ROS 2 world republishes the agents' feed as the plan's state.
        agents_feed: args.ros2.is_some(),
    };
    let p = config.spec.protocol;
    eprintln!(
        "learnpnp-supervisor: {} with {} on {}; {} mode, {} wait; {} run(s) x {} learning episodes, evaluation every {} ({} episodes), seed {}; results in {}",
        config.spec.domain.name(),
        config.spec.algorithm.name(),
        match &config.spec.domain {
            DomainSpec::World { command, plans } => {
                format!("a world ({command}) and {} agent process(es)", plans.len())
            }
            _ => "a simulator and 3 keeper processes".to_string(),
        },
        args.mode.name(),
        wait.name(),
        p.runs,
        p.episodes,
        p.eval_every,
        p.eval_episodes,
        config.spec.seed,
        args.out.display()
    );
    Ok((config, out))
}

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

/// Runs the system with `observer` and prints the report; the exit code says
/// whether it completed, failed or was stopped.
fn run_system(
    config: &SupervisorConfig,
    out: &mut ResultDir,
    interrupt: &Interrupt,
    observer: &mut dyn RunObserver,
) -> Result<learnpnp_system::multiprocess::supervisor::report::Report> {
    let report = supervise(config, out, interrupt.flag(), observer)?;
    let summary = &report.summary;
    print!("{}", report.latency_table());
    match (&summary.experiment, &config.spec.domain) {
        (Some(e), DomainSpec::World { .. }) => println!(
            "learning: {}, greedy {}",
            learnpnp::experiment::output::final_score_text(e),
            learnpnp::experiment::output::greedy_text(e),
        ),
        (Some(e), _) => println!(
            "learning: {}, greedy {}, mean episode {:.2} s",
            learnpnp::experiment::output::final_score_text(e),
            learnpnp::experiment::output::greedy_text(e),
            summary.mean_episode_seconds
        ),
        (None, _) => {}
    }
    println!(
        "results in {}: summary.json, curve.csv, curve.svg, episodes.csv, latency.svg, latency/*.hgrm, values*.bin, runs/*/ (logs, checkpoints)",
        out.path().display()
    );
    Ok(report)
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
        let exe = std::env::current_exe().context("locating learnpnp-supervisor")?;
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
        Some(Command::Run(args)) => run(args),
        Some(Command::Soak(args)) => soak(args),
        Some(Command::BenchLatency(args)) => bench(args),
        Some(Command::BenchWorld(args)) => bench_world_cmd(args),
        Some(Command::Remote(args)) => remote(args),
        Some(Command::LinkCerts(args)) => link_certs(args),
        Some(Command::PublishGarbage(args)) => Namespace::from_prefix(&args.ipc_prefix)
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
