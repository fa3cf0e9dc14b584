//! A run of the system from the command line, as `learnpnp-supervisor` and
//! `learnpnp-soak` take it: the flags of a run ([`RunArgs`]), the
//! configuration and output directory they make ([`prepare`]), and the run
//! itself with its report printed ([`run_system`]). Each binary includes this
//! file with `#[path]`, so that a soak or a benchmark takes the very flags of
//! a run.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use learnpnp::experiment::options::DomainName;
use learnpnp::experiment::options::ExperimentOptions;
use learnpnp::experiment::result_dir::ResultDir;
use learnpnp::experiment::spec::{Algorithm, DomainSpec};
use learnpnp::named::Named;
use learnpnp_flags::args::named;
use learnpnp_flags::interrupt::Interrupt;
use learnpnp_flags::view::ViewFlags;
use learnpnp_system::hosts::PLAIN_TCP_WARNING;
use learnpnp_system::hosts::certs::HostFiles;
use learnpnp_system::ipc::namespace::clean_stale;
use learnpnp_system::ipc::wait::WaitStrategy;
use learnpnp_system::multiprocess::Clock;
use learnpnp_system::multiprocess::supervisor::launch::{Binaries, Needs};
use learnpnp_system::multiprocess::supervisor::{Cluster, RunObserver, SupervisorConfig, ViewConfig, supervise};

/// The Keepaway experiments the system runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Domain {
    /// Every keeper learns where to stand (thesis 7.3): three learner processes.
    KeepawayPosition,
    /// Keeper 1 learns the pass decision (thesis 7.2); keepers 2 and 3 follow the threshold policy.
    KeepawayPass,
}

/// How this host joins the link between hosts: its certificates, or plain TCP.
#[derive(Args, Debug, Clone)]
pub(crate) struct LinkArgs {
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
    pub(crate) fn certs(&self) -> Result<Option<PathBuf>> {
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

/// A run of the system.
#[derive(Args, Debug, Clone)]
#[command(group(clap::ArgGroup::new("world").args(["world_cmd", "ros2"])))]
pub(crate) struct RunArgs {
    /// The experiment.
    #[arg(long, value_enum, default_value = "keepaway-position")]
    domain: Domain,
    /// Run a world in its own process instead of Keepaway: this command
    /// serves the world (given the run in LEARNPNP_* environment variables;
    /// see shm_layouts/README.md); --plan is every agent's plan, or
    /// --agent-plan gives each agent its own.
    #[arg(long, conflicts_with = "ros2")]
    pub(crate) world_cmd: Option<String>,
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
    pub(crate) flags: ExperimentOptions,
}

/// The experiment's runs when the user gives no --runs: one.
const DEFAULT_RUNS: usize = 1;

/// Learning episodes of a world run when the user gives no --episodes.
pub(crate) const DEFAULT_WORLD_EPISODES: u64 = 1_000;

/// Learning episodes of a soak or benchmark run, which its time limit ends.
pub(crate) const UNBOUNDED_EPISODES: u64 = 1_000_000_000;

/// The world's command: `--world-cmd` as given, or `--ros2 MAPPING` as the
/// ROS 2 world beside this binary (the command is split on whitespace, so
/// its paths may hold none).
fn world_command(args: &RunArgs) -> Result<Option<String>> {
    let Some(mapping) = &args.ros2 else {
        return Ok(args.world_cmd.clone());
    };
    let exe = std::env::current_exe().context("locating this executable")?;
    let world = exe.with_file_name("learnpnp-ros2-world");
    if !world.exists() {
        bail!(
            "--ros2: the ROS 2 world {} is not built (build it: cargo build --release --bin learnpnp-ros2-world)",
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
pub(crate) fn prepare(args: &RunArgs, episodes: u64) -> Result<(SupervisorConfig, ResultDir)> {
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
    let view = (args.view.asked() || args.view_jsonl.is_some()).then(|| ViewConfig {
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
        "{}: {} with {} on {}; {} mode, {} wait; {} run(s) x {} learning episodes, evaluation every {} ({} episodes), seed {}; results in {}",
        env!("CARGO_BIN_NAME"),
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

/// Runs the system with `observer`, prints the report and returns it.
pub(crate) fn run_system(
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
