//! The supervisor: for each run of an experiment it picks a run-unique
//! iceoryx2 namespace, creates the services, starts the host (the Keepaway
//! simulator, or a world in its own process) and one agent process per
//! keeper or agent, watches their exit status and heartbeats, restarts an
//! agent that dies or hangs (from its last checkpoint; the host aborts the
//! episode in flight) and a world that dies, stops everything on request with
//! a final checkpoint, and removes every shared-memory file of the run.

use learnpnp::experiment::result_dir::{self, ResultDir, ResultDirError};
use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitStatus;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use rand::RngExt;
use serde::Serialize;

use super::agent_process::{checkpoint_name, compute_histogram, resumed_file};
use super::floor_probe::{FloorProbe, REMOTE_HOST_FLOOR, WorldFloor};
use super::launch::{Binaries, LaunchError, Process, set_fifo_priority, spawn, spawn_world};
use super::sim_process::{FLOOR, RESULT_FILE, ROUND_TRIP, SimulatorResult, keeper_round_trip_histogram};
use super::world_agent::{EXIT_PLAN_DOES_NOT_FIT, WORLD_TURNAROUND, agent_compute_histogram, agent_result_file};
use super::{Clock, ProcessError, RunContext};
use crate::bridge::refusals::LinkReport;
use crate::ipc::convert::{Rejections, control_message, read_heartbeat};
use crate::ipc::namespace::{Namespace, NamespaceError, NamespaceOwner};
use crate::ipc::protocol::{Order, ProcessState, Pulse, Role, Roster};
use crate::ipc::services::{Ipc, IpcError, RunServices, SupervisorPorts, node, receive};
use crate::ipc::wait::WaitStrategy;
use crate::latency::plot::PlotFailure;
use crate::latency::{Latency, LatencyError};
use iceoryx2::node::Node;
use learnpnp::experiment::spec::{ExperimentError, ExperimentSpec};
use learnpnp::learning::persist::{self, PersistError, SavedValues};

/// The file in a run's work directory naming its iceoryx2 prefix and run id
/// (for diagnostic tools that join the run).
pub const IDENTITY_FILE: &str = "ipc.json";

/// The exit code of an agent that cannot resume from its checkpoint: it is
/// not restarted again.
pub const EXIT_CANNOT_RESUME: i32 = 3;

/// The variables that give a world process its run (`shm_layouts/README.md`).
pub mod world_env {
    /// The run's iceoryx2 prefix.
    pub const PREFIX: &str = "LEARNPNP_IPC_PREFIX";
    /// The run's iceoryx2 root directory, ending in `/`.
    pub const ROOT: &str = "LEARNPNP_IPC_ROOT";
    /// The run id.
    pub const RUN_ID: &str = "LEARNPNP_RUN_ID";
    /// How many agents.
    pub const AGENTS: &str = "LEARNPNP_AGENTS";
    /// `lockstep` or `realtime`.
    pub const CLOCK: &str = "LEARNPNP_CLOCK";
    /// Real time: the cycle in milliseconds.
    pub const PERIOD_MS: &str = "LEARNPNP_PERIOD_MS";
    /// The wait strategy.
    pub const WAIT: &str = "LEARNPNP_WAIT";
    /// The world's seed for the run.
    pub const SEED: &str = "LEARNPNP_SEED";
}

/// How the supervisor runs the system.
#[derive(Debug, Clone)]
pub struct SupervisorConfig {
    /// The experiment.
    pub spec: ExperimentSpec,
    /// Lock-step or real time.
    pub clock: Clock,
    /// How processes wait for messages.
    pub wait: WaitStrategy,
    /// Agents checkpoint every this many learning episodes.
    pub checkpoint_every: u64,
    /// Round trips of the floor measurement before each lock-step run (real
    /// time samples the floor in every cycle).
    pub floor_round_trips: usize,
    /// Real time: the SCHED_FIFO priority of the simulator and the agents
    /// when they sleep between cycles (`block`, `hybrid`; 0: normal
    /// scheduling). Lock-step runs, and real-time ones that spin or yield, are
    /// always scheduled normally: real-time processes that never sleep would
    /// starve the rest of the machine.
    pub rt_priority: u8,
    /// A process silent for this long is taken as hung and killed.
    pub heartbeat_timeout: Duration,
    /// Restarts of one keeper (or of the simulator) in one run before the run is given up.
    pub max_restarts: u32,
    /// Restart a simulator that dies, from its journal's last episode boundary
    /// (chaos soaks); otherwise a dead simulator ends the run.
    pub restart_simulator: bool,
    /// The simulator's and agents' binaries.
    pub binaries: Binaries,
    /// A world run in real time: the cycle the world is told to keep.
    pub world_period: Duration,
    /// A run across hosts: the agents on other hosts and this host's bridge.
    pub cluster: Option<Cluster>,
}

/// A run across hosts, seen from host A (the simulator's or world's).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cluster {
    /// The agents (0-based) that run on other hosts, under their own supervisors.
    pub remote: Vec<usize>,
    /// Where this host's bridge listens (`quic/ADDRESS:PORT`).
    pub listen: Vec<String>,
    /// Host A's certificates (made by `learnpnp-supervisor link-certs`);
    /// `None`: plain TCP, which gives up encryption, authentication and
    /// access control.
    pub link_certs: Option<PathBuf>,
}

/// How often host A tells the other hosts again to stop while it waits for their files.
const RESTOP_EVERY: Duration = Duration::from_secs(1);

/// How long a bridge asked to stop may take to write its last link report.
pub const BRIDGE_STOP_GRACE: Duration = Duration::from_secs(2);

/// The file of a run's work directory describing it to the other hosts.
pub const RUN_INFO_FILE: &str = "run-info.json";

/// How long host A waits, once the run is over, for the remote agents' files.
pub const REMOTE_FILES_TIMEOUT: Duration = Duration::from_secs(30);

impl SupervisorConfig {
    /// The run's processes: Keepaway's, or a world's and its agents.
    pub fn roster(&self) -> Roster {
        Roster::of(&self.spec.domain)
    }
}

/// Why a run of the system failed.
#[derive(Debug, thiserror::Error)]
pub enum SupervisorError {
    /// A process cannot be started.
    #[error(transparent)]
    Launch(#[from] LaunchError),
    /// Shared memory failed.
    #[error(transparent)]
    Ipc(#[from] IpcError),
    /// The namespace cannot be set up or cleaned.
    #[error(transparent)]
    Namespace(#[from] NamespaceError),
    /// A file cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A histogram file is unreadable.
    #[error(transparent)]
    Latency(#[from] LatencyError),
    /// A process failed in a way the run cannot survive.
    #[error(transparent)]
    Run(#[from] RunFailure),
    /// The output directory cannot be used.
    #[error(transparent)]
    ResultDir(#[from] ResultDirError),
    /// A file's JSON cannot be written or read.
    #[error("{what}: {source}")]
    Json {
        /// The file or value.
        what: String,
        /// The error.
        source: serde_json::Error,
    },
    /// A plot cannot be drawn.
    #[error(transparent)]
    Plot(#[from] PlotFailure),
    /// The experiment's results cannot be staged, or it cannot run.
    #[error(transparent)]
    Experiment(#[from] ExperimentError),
    /// The experiment cannot run in this system.
    #[error(transparent)]
    Process(#[from] ProcessError),
    /// A learning keeper's checkpoint is unusable at the end of a run.
    #[error(transparent)]
    Checkpoint(#[from] PersistError),
    /// The soak's sample log cannot be written or read back.
    #[error(transparent)]
    SampleLog(#[from] super::soak::SampleLogError),
    /// A run across hosts cannot be set up.
    #[error("the link to the other hosts: {0}")]
    Bridge(String),
}

/// How a run ends when a process fails in a way it cannot survive (what the
/// report's `failure` says).
#[derive(Debug, thiserror::Error)]
pub enum RunFailure {
    /// An agent exited because it cannot resume from its checkpoint.
    #[error("{what}: {log}")]
    CannotResume {
        /// What happened (e.g. "keeper 2 exited: exit code 3").
        what: String,
        /// The last lines of its log.
        log: String,
    },
    /// A keeper's agent was lost once more than the restarts allowed.
    #[error("{what}, {restarts} times: run given up ({log})")]
    TooManyRestarts {
        /// What happened the last time.
        what: String,
        /// How many times it happened.
        restarts: u32,
        /// The last lines of its log.
        log: String,
    },
    /// An agent's plan names atoms or actions the world lacks.
    #[error("{what}: {log}")]
    PlanDoesNotFit {
        /// What happened.
        what: String,
        /// The last lines of its log (the lists).
        log: String,
    },
    /// The simulator (or world) was lost once more than the restarts allowed.
    #[error("{what}: run given up ({log})")]
    SimulatorGivenUp {
        /// What happened the last time.
        what: String,
        /// The last line of its log (for a Python world, the exception).
        log: String,
    },
    /// The simulator (or world) failed twice the same way before it ended an
    /// episode: a third start would fail again.
    #[error("{what}, the same way twice before its first episode: run given up ({log})")]
    HostFailsAtStart {
        /// What happened.
        what: String,
        /// The last line of its log (for a Python world, the exception).
        log: String,
    },
    /// The simulator hung and is not restarted.
    #[error("{what}")]
    SimulatorHung {
        /// What happened (how long it was silent).
        what: String,
    },
}

/// Heartbeat timeouts without a lock-step cycle after which a run whose
/// processes all beat is stopped as stalled (three: long enough for a host to
/// notice a hung agent, kill it and start another, here or on another host).
pub const STALL_TIMEOUTS: u32 = 3;

/// A JSON error about `what`.
pub(crate) fn json_error(what: impl std::fmt::Display) -> impl FnOnce(serde_json::Error) -> SupervisorError {
    move |source| SupervisorError::Json {
        what: what.to_string(),
        source,
    }
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> SupervisorError + '_ {
    move |source| SupervisorError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// A fault and what the supervisor did about it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fault {
    /// The run (0-based).
    pub run: usize,
    /// Seconds since the run's processes started.
    pub seconds: f64,
    /// What happened (e.g. "keeper 2 exited: signal 9 (SIGKILL)").
    pub kind: String,
    /// What the supervisor did, and with what result.
    pub outcome: String,
}

/// Whether a restarted agent resumed with exactly the values checkpointed
/// before it was lost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResumeCheck {
    /// The run.
    pub run: usize,
    /// The keeper (1-based).
    pub keeper: usize,
    /// The replacement's process id.
    pub pid: u32,
    /// What it should have loaded: "checkpoint", or "previous checkpoint" when
    /// the last one was unusable.
    pub source: String,
    /// It loaded exactly those values.
    pub survived: bool,
}

/// The checkpoint a replacement agent is to resume from, as it was when the
/// supervisor started the replacement.
#[derive(Debug)]
struct PendingResume {
    keeper: usize,
    pid: u32,
    expected: Option<(SavedValues, &'static str)>,
}

/// What one run of the system produced.
#[derive(Debug)]
pub struct RunRecord {
    /// The run's index.
    pub run: usize,
    /// The simulator's result (protocol output, counters); empty if it died.
    pub sim: SimulatorResult,
    /// Why the run did not complete normally (a process the run cannot do
    /// without died, or could not be restarted).
    pub failure: Option<String>,
    /// Faults and restarts, in order.
    pub faults: Vec<Fault>,
    /// Processes restarted (agents and, in chaos soaks, the simulator).
    pub restarts: u32,
    /// For each agent restart: did it resume with the checkpointed values?
    pub resumes: Vec<ResumeCheck>,
    /// The run's histograms: round trip, floor, and each keeper's compute time.
    pub histograms: Vec<Latency>,
    /// Messages refused, by process (the simulator and each keeper, all incarnations).
    pub rejected: BTreeMap<String, Rejections>,
    /// Checkpoint writes that failed, over every agent.
    pub checkpoint_failures: u64,
    /// The learning keepers' final values (their last checkpoints).
    pub values: Vec<SavedValues>,
    /// Wall-clock seconds of the run.
    pub seconds: f64,
    /// Files of the run's namespace left after cleanup (0 unless cleanup failed).
    pub leftover_files: usize,
    /// The run's iceoryx2 prefix.
    pub prefix: String,
    /// How the simulator and the agents were scheduled.
    pub scheduling: String,
    /// A run across hosts: what this host's bridge carried and refused.
    pub link: Option<LinkReport>,
}

/// How an exit status reads in a report.
fn describe(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (status.code(), status.signal()) {
        (Some(code), _) => format!("exit code {code}"),
        (None, Some(signal)) => format!("signal {signal} ({})", signal_name(signal)),
        _ => status.to_string(),
    }
}

fn signal_name(signal: i32) -> &'static str {
    match signal {
        libc::SIGKILL => "SIGKILL",
        libc::SIGTERM => "SIGTERM",
        libc::SIGSEGV => "SIGSEGV",
        libc::SIGABRT => "SIGABRT",
        libc::SIGINT => "SIGINT",
        _ => "signal",
    }
}

/// The processes of a run; whatever is still running when this is dropped is killed.
struct Fleet {
    processes: BTreeMap<Role, Process>,
}

impl Fleet {
    fn kill_all(&mut self) {
        for process in self.processes.values_mut() {
            let _ = process.kill();
        }
        self.processes.clear();
    }
}

impl Drop for Fleet {
    fn drop(&mut self) {
        self.kill_all();
    }
}

/// The last lines of a log, for an error message.
/// The last non-empty line of the log at `path` ("(empty log)" if none).
fn last_log_line(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap_or_default();
    text.lines()
        .rev()
        .find(|l| !l.trim().is_empty())
        .map_or_else(|| "(empty log)".to_string(), |l| l.trim().to_string())
}

fn log_tail(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap_or_default();
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    lines[lines.len().saturating_sub(3)..].join(" | ")
}

/// A supervised run at a moment, as an observer sees it.
#[derive(Debug)]
pub struct RunView<'a> {
    /// The run's index.
    pub run: usize,
    /// Seconds since its processes were started.
    pub seconds: f64,
    /// Its iceoryx2 namespace.
    pub namespace: &'a Namespace,
    /// Its working directory (checkpoints, logs, histograms).
    pub work_dir: &'a Path,
    /// Its id (every message carries it).
    pub run_id: u64,
    /// The processes alive now, with their ids.
    pub processes: Vec<(Role, u32)>,
    /// The last heartbeat of each process alive now.
    pub pulses: Vec<Pulse>,
    /// The current host's (simulator's or world's) last heartbeat.
    pub simulator: Option<&'a Pulse>,
    /// The run's processes.
    pub roster: Roster,
}

/// What an observer asks of the supervisor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Request {
    /// Stop the run (as Ctrl-C does).
    Stop,
    /// Send `order` to `target` on the supervisor's control port.
    Order(Order, Role),
}

/// Watches supervised runs from the supervisor's loop (about every 10 ms):
/// progress bars, soak sampling, fault injection.
pub trait RunObserver {
    /// Looks at the run; returns what it asks of the supervisor (usually nothing).
    fn observe(&mut self, view: &RunView<'_>) -> Vec<Request>;

    /// Called once before the first run, with the result set the observer may
    /// claim files in (to write them as it goes).
    fn start(
        &mut self,
        _files: &mut learnpnp::experiment::result_dir::ResultWriter<'_>,
    ) -> Result<(), SupervisorError> {
        Ok(())
    }

    /// Adds the observer's files to the result set before it is published.
    fn finish(
        &mut self,
        _files: &mut learnpnp::experiment::result_dir::ResultWriter<'_>,
        _records: &[RunRecord],
    ) -> Result<(), SupervisorError> {
        Ok(())
    }
}

/// An observer that only reports the learning episodes done in each run.
pub struct Progress<F: Fn(usize, u64)>(pub F);

impl<F: Fn(usize, u64)> RunObserver for Progress<F> {
    fn observe(&mut self, view: &RunView<'_>) -> Vec<Request> {
        if let Some(pulse) = view.simulator {
            (self.0)(view.run, pulse.episodes);
        }
        Vec::new()
    }
}

/// One run being supervised.
struct Watch<'a> {
    config: &'a SupervisorConfig,
    namespace: &'a Namespace,
    context: RunContext,
    ports: SupervisorPorts,
    fleet: Fleet,
    started: Instant,
    last_heard: BTreeMap<Role, Instant>,
    pulses: BTreeMap<(Role, u32), Pulse>,
    faults: Vec<Fault>,
    roster: Roster,
    /// Restarts of each process so far.
    restarts: BTreeMap<Role, u32>,
    /// World runs: agents that completed their protocol and exited.
    done: Vec<usize>,
    /// World runs: the floor measurement's ports (pings to agent 0).
    floor: Option<FloorProbe<WorldFloor>>,
    /// The run was asked to stop (a signal, or an observer).
    stop_requested: bool,
    /// Lock-step: the host's cycle count and when it last moved.
    progress: Option<(u64, Instant)>,
    /// When a process was last restarted.
    last_restart: Option<Instant>,
    /// The episodes the current host reported first and last (`None` before its first heartbeat).
    host_episodes: Option<(u64, u64)>,
    /// The host's last failure and its log's last line, if it came before the host ended an episode.
    early_host_failure: Option<(String, String)>,
    /// Why the run was stopped as stalled, if it was.
    stalled: Option<String>,
    resumes: Vec<PendingResume>,
    control_sequence: u64,
    /// Why the real-time priority could not be given (the first refusal).
    fifo_refused: Option<String>,
}

impl Watch<'_> {
    fn log(&self, role: Role) -> PathBuf {
        let name = match role {
            Role::Simulator => "simulator.log".to_string(),
            Role::Keeper(k) => format!("keeper{}.log", k + 1),
            Role::World => "world.log".to_string(),
            Role::Agent(a) => format!("agent{}.log", a + 1),
            Role::Bridge => "bridge.log".to_string(),
        };
        self.context.work_dir.join(name)
    }

    fn start(&mut self, role: Role, resume: bool) -> Result<(), SupervisorError> {
        let mut args = self.context.to_args();
        if resume {
            args.push("--resume".into());
        }
        let binary = match role {
            Role::Simulator => {
                args.push("--floor-round-trips".into());
                args.push(self.config.floor_round_trips.to_string().into());
                &self.config.binaries.sim
            }
            Role::Keeper(k) | Role::Agent(k) => {
                args.push(
                    if role == Role::Keeper(k) {
                        "--keeper"
                    } else {
                        "--world-agent"
                    }
                    .into(),
                );
                args.push((k + 1).to_string().into());
                args.push("--checkpoint-every".into());
                args.push(self.config.checkpoint_every.to_string().into());
                &self.config.binaries.agent
            }
            Role::Bridge => {
                let args = self.bridge_args();
                let process = spawn(&self.config.binaries.bridge, role, &args, &self.log(role))?;
                // The bridge sends no heartbeat: its exit is what is watched.
                self.fleet.processes.insert(role, process);
                return Ok(());
            }
            Role::World => {
                let log = self.log(role);
                let process = spawn_world(
                    &self.config.spec,
                    &self.context,
                    self.namespace,
                    &log,
                    self.config.world_period,
                )?;
                return self.started(role, process);
            }
        };
        let process = spawn(binary, role, &args, &self.log(role))?;
        self.started(role, process)
    }

    /// The bridge's command line: this host's namespace, the link, the run's description.
    fn bridge_args(&self) -> Vec<std::ffi::OsString> {
        let mut args: Vec<std::ffi::OsString> = vec![
            "--ipc-prefix".into(),
            self.context.ipc_prefix.clone().into(),
            "--side".into(),
            "host".into(),
            "--run-info".into(),
            self.context.work_dir.join(RUN_INFO_FILE).into(),
            "--work-dir".into(),
            self.context.work_dir.clone().into(),
        ];
        if let Some(cluster) = &self.config.cluster {
            for endpoint in &cluster.listen {
                args.push("--listen".into());
                args.push(endpoint.into());
            }
            match &cluster.link_certs {
                Some(dir) => args.extend(["--link-certs".into(), dir.clone().into_os_string()]),
                None => args.push("--insecure-plain-tcp".into()),
            }
        }
        args
    }

    /// Writes the run's description the bridge gives the other hosts.
    fn describe_for_other_hosts(&self, cluster: &Cluster) -> Result<(), SupervisorError> {
        let info = crate::bridge::remote::RunInfo {
            prefix: self.context.ipc_prefix.clone(),
            run_id: self.context.run_id,
            run: self.context.run,
            roster: self.roster,
            remote: cluster.remote.clone(),
            clock: self.config.clock,
            wait: self.config.wait,
            checkpoint_every: self.config.checkpoint_every,
            floor_round_trips: self.config.floor_round_trips,
            spec: serde_json::to_value(&self.config.spec).map_err(json_error("the experiment spec"))?,
        };
        let path = self.context.work_dir.join(RUN_INFO_FILE);
        info.write(&path).map_err(|e| SupervisorError::Bridge(e.to_string()))
    }

    /// Whether agent `k` runs on another host.
    fn is_remote(&self, k: usize) -> bool {
        self.config.cluster.as_ref().is_some_and(|c| c.remote.contains(&k))
    }

    /// Host A, once the run is over: waits for the remote agents' files
    /// (their last checkpoints and histograms, shipped by their host's
    /// bridge), then stops the bridge.
    fn await_remote_files(&mut self) -> Result<(), SupervisorError> {
        let Some(cluster) = &self.config.cluster else {
            return Ok(());
        };
        let learning = self.learning_agents()?;
        let mut expected: Vec<PathBuf> = cluster
            .remote
            .iter()
            .filter(|&&k| k < learning)
            .map(|&k| self.context.work_dir.join(checkpoint_name(k)))
            .collect();
        if self.roster != Roster::Keepaway && cluster.remote.contains(&0) {
            // A world run's report is agent 1's result.
            expected.push(self.context.work_dir.join(agent_result_file(0)));
        }
        let deadline = Instant::now() + REMOTE_FILES_TIMEOUT;
        let arrived = |expected: &[PathBuf]| expected.iter().all(|p| p.is_file());
        let mut ordered = Instant::now();
        while !arrived(&expected) && Instant::now() < deadline {
            // The stop is told again: a host B whose link was down when it
            // was first told (its peer's bridge restarted; over QUIC a dead
            // peer is noticed only when its lease expires) hears it once
            // the link is back.
            if ordered.elapsed() >= RESTOP_EVERY {
                self.order(Order::Stop, None)?;
                ordered = Instant::now();
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        if !arrived(&expected) {
            self.fault(
                format!(
                    "the remote agents' checkpoints did not arrive within {} s",
                    REMOTE_FILES_TIMEOUT.as_secs()
                ),
                "the report lacks their values".into(),
            );
        }
        // The histograms come in the same shipment, just after the checkpoints.
        std::thread::sleep(Duration::from_millis(500));
        if let Some(mut bridge) = self.fleet.processes.remove(&Role::Bridge) {
            // Asked to stop, it writes its last link report.
            let _ = bridge.stop(BRIDGE_STOP_GRACE);
        }
        Ok(())
    }

    /// How many of the run's agents learn (the first ones).
    fn learning_agents(&self) -> Result<usize, SupervisorError> {
        Ok(match self.roster {
            Roster::Keepaway => super::sim_process::keepaway_config(&self.config.spec)?.learning_keepers(),
            Roster::World { agents } => agents,
        })
    }

    /// Takes a started process into the fleet.
    fn started(&mut self, role: Role, process: Process) -> Result<(), SupervisorError> {
        if let Some(priority) = self.fifo_priority()
            && let Err(e) = set_fifo_priority(process.pid(), priority)
        {
            self.fifo_refused.get_or_insert(e.to_string());
        }
        self.fleet.processes.insert(role, process);
        self.last_heard.insert(role, Instant::now());
        Ok(())
    }

    /// The SCHED_FIFO priority the run's processes get, if any: only in real
    /// time, and only when they sleep between cycles (`block`, `hybrid`): a
    /// real-time process that spins or yields without end would hold its core
    /// against the rest of the machine.
    fn fifo_priority(&self) -> Option<u8> {
        let sleeps = self.config.wait.notifies();
        (self.config.clock == Clock::Realtime && sleeps && self.config.rt_priority > 0)
            .then_some(self.config.rt_priority)
    }

    /// How the run's processes were scheduled, as the report says it.
    fn scheduling(&self) -> String {
        match (self.fifo_priority(), &self.fifo_refused) {
            (None, _) => "normal".to_string(),
            (Some(priority), None) => format!("SCHED_FIFO {priority}"),
            (Some(priority), Some(why)) => format!("normal (SCHED_FIFO {priority} refused: {why})"),
        }
    }

    fn fault(&mut self, kind: String, outcome: String) {
        self.faults.push(Fault {
            run: self.context.run,
            seconds: self.started.elapsed().as_secs_f64(),
            kind,
            outcome,
        });
    }

    fn order(&mut self, order: Order, target: Option<Role>) -> Result<(), SupervisorError> {
        self.control_sequence += 1;
        let message = control_message(order, target, self.control_sequence, self.context.run_id);
        self.ports.control.send(message)?;
        Ok(())
    }

    /// Reads the heartbeats.
    fn heartbeats(&mut self) -> Result<(), SupervisorError> {
        let (run_id, roster) = (self.context.run_id, self.roster);
        while let Some(reading) = receive(&self.ports.heartbeats, |m| read_heartbeat(m, run_id, roster))? {
            // Heartbeats that do not read are a foreign process's: ignored here,
            // counted by the processes that must act on such messages.
            if let Ok(pulse) = reading {
                // Keyed by the process the supervisor started (a world a
                // shell runs is that shell's child, in its process group).
                let current = self
                    .fleet
                    .processes
                    .get(&pulse.role)
                    .filter(|p| p.leads(pulse.pid))
                    .map(Process::pid);
                if current.is_some() {
                    self.last_heard.insert(pulse.role, Instant::now());
                    if pulse.role == self.roster.host() {
                        let first = self.host_episodes.map_or(pulse.episodes, |(first, _)| first);
                        self.host_episodes = Some((first, pulse.episodes));
                    }
                }
                if let Role::Agent(a) = pulse.role
                    && self.is_remote(a)
                    && pulse.state == ProcessState::Stopping
                    && !self.done.contains(&a)
                {
                    // A remote world agent has completed its protocol.
                    self.done.push(a);
                    if self.agents_done() {
                        self.order(Order::Stop, Some(Role::World))?;
                    }
                }
                self.pulses.insert((pulse.role, current.unwrap_or(pulse.pid)), pulse);
            }
        }
        Ok(())
    }

    /// Counts one more restart of `role`; returns how many so far.
    fn count_restart(&mut self, role: Role) -> u32 {
        self.last_restart = Some(Instant::now());
        let restarts = self.restarts.entry(role).or_default();
        *restarts += 1;
        *restarts
    }

    /// Replaces agent `k` (a keeper or a world's agent) after it `what` (exited or hung).
    fn restart(&mut self, k: usize, what: String) -> Result<(), SupervisorError> {
        let role = self.roster.agent(k);
        let restarts = self.count_restart(role);
        if restarts > self.config.max_restarts {
            let outcome = format!("not restarted: {} restarts already", self.config.max_restarts);
            self.fault(what.clone(), outcome);
            return Err(RunFailure::TooManyRestarts {
                what,
                restarts,
                log: log_tail(&self.log(role)),
            }
            .into());
        }
        let checkpoint = self.context.work_dir.join(checkpoint_name(k));
        // What the replacement must load: the checkpoint, or the previous one if it is unusable.
        let expected = match persist::load(&checkpoint) {
            Ok(values) => Some((values, "checkpoint")),
            Err(_) => persist::load(&persist::prev_path(&checkpoint))
                .ok()
                .map(|values| (values, "previous checkpoint")),
        };
        self.namespace.remove_dead_nodes()?;
        self.start(role, true)?;
        let pid = self.fleet.processes.get(&role).map_or(0, Process::pid);
        self.order(Order::KeeperLost { keeper: k, pid }, Some(self.roster.host()))?;
        self.resumes.push(PendingResume {
            keeper: k,
            pid,
            expected,
        });
        // Named as in the result directory (the staging path is gone once it is committed).
        let run_dir = self.context.work_dir.file_name().unwrap_or_default().to_string_lossy();
        self.fault(
            what,
            format!(
                "restarted from its checkpoint {RUNS_DIR}/{run_dir}/{}",
                checkpoint_name(k)
            ),
        );
        Ok(())
    }

    /// Whether a host that died is restarted: a world always (the agents
    /// keep the protocol), the simulator in chaos soaks.
    fn may_restart_host(&self) -> bool {
        let restartable = self.config.restart_simulator || self.roster != Roster::Keepaway;
        restartable && !self.stop_requested && !self.agents_done()
    }

    /// World runs: every agent has completed its protocol.
    fn agents_done(&self) -> bool {
        self.roster != Roster::Keepaway && self.done.len() == self.roster.agents()
    }

    /// Replaces the host after it `what`: a new simulator continues from its
    /// journal's last episode boundary, a new world begins a new episode;
    /// the agents drop the episode in progress.
    ///
    /// A host that exits by itself (`own_exit`: not killed) twice the same way
    /// (what happened and its log's last line) before it ends an episode is not
    /// started a third time.
    fn restart_host(&mut self, what: String, own_exit: bool) -> Result<(), SupervisorError> {
        let host = self.roster.host();
        let log = last_log_line(&self.log(host));
        let early = own_exit && self.host_episodes.is_none_or(|(first, last)| last <= first);
        self.host_episodes = None;
        let failure = (what.clone(), log.clone());
        if early && self.early_host_failure.as_ref() == Some(&failure) {
            self.fault(
                what.clone(),
                "not restarted: it failed the same way at its last start".into(),
            );
            return Err(RunFailure::HostFailsAtStart { what, log }.into());
        }
        self.early_host_failure = early.then_some(failure);
        if self.count_restart(host) > self.config.max_restarts {
            self.fault(
                what.clone(),
                format!("not restarted: {} restarts already", self.config.max_restarts),
            );
            return Err(RunFailure::SimulatorGivenUp { what, log }.into());
        }
        self.order(Order::SimulatorRestarted, None)?;
        self.namespace.remove_dead_nodes()?;
        self.start(host, true)?;
        let outcome = match host {
            Role::World => "restarted; the agents dropped the episode in flight",
            _ => "restarted from its journal's last episode boundary",
        };
        self.fault(what, outcome.into());
        Ok(())
    }

    /// What an observer sees now.
    fn view(&self) -> RunView<'_> {
        let host = self.roster.host();
        let simulator = self
            .fleet
            .processes
            .get(&host)
            .and_then(|p| self.pulses.get(&(host, p.pid())));
        RunView {
            run: self.context.run,
            seconds: self.started.elapsed().as_secs_f64(),
            namespace: self.namespace,
            work_dir: &self.context.work_dir,
            run_id: self.context.run_id,
            processes: self.fleet.processes.iter().map(|(role, p)| (*role, p.pid())).collect(),
            pulses: self
                .fleet
                .processes
                .iter()
                .filter_map(|(role, p)| self.pulses.get(&(*role, p.pid())).copied())
                .collect(),
            simulator,
            roster: self.roster,
        }
    }

    /// Watches until the host exits; restarts agents on the way.
    fn watch(&mut self, stop: &AtomicBool, observer: &mut dyn RunObserver) -> Result<ExitStatus, SupervisorError> {
        loop {
            self.heartbeats()?;
            self.consult(stop, observer)?;
            if let Some(floor) = &mut self.floor {
                floor.sample()?;
            }
            if let Some(status) = self.reap()? {
                return Ok(status);
            }
            self.kill_hung()?;
            self.stop_if_stalled()?;
            std::thread::sleep(Duration::from_millis(10));
        }
    }

    /// Lock-step: stops the run (cleanly: every agent checkpoints) when the
    /// host runs but its cycle count has not moved for [`STALL_TIMEOUTS`]
    /// heartbeat timeouts with no process restarted meanwhile. Every process
    /// beats, yet no cycle is played: a message was lost (between hosts, a
    /// bridge that died with it in flight), and lock-step would wait forever.
    fn stop_if_stalled(&mut self) -> Result<(), SupervisorError> {
        if self.config.clock != Clock::Lockstep || self.stop_requested {
            return Ok(());
        }
        let host = self.roster.host();
        let Some(pulse) = self
            .fleet
            .processes
            .get(&host)
            .and_then(|p| self.pulses.get(&(host, p.pid())))
            .copied()
        else {
            return Ok(());
        };
        let now = Instant::now();
        match self.progress {
            Some((cycles, _)) if cycles == pulse.cycles && pulse.state == ProcessState::Running => {}
            _ => {
                self.progress = Some((pulse.cycles, now));
                return Ok(());
            }
        }
        let limit = self.config.heartbeat_timeout * STALL_TIMEOUTS;
        let quiet_since = self
            .progress
            .map(|(_, t)| t)
            .into_iter()
            .chain(self.last_restart)
            .max()
            .unwrap_or(now);
        if now.duration_since(quiet_since) <= limit {
            return Ok(());
        }
        let what = format!(
            "lock-step stalled: no cycle for {} s while the {host} runs (a message lost between hosts?)",
            limit.as_secs()
        );
        self.fault(what.clone(), "run stopped; every agent checkpoints".into());
        self.stalled = Some(what);
        self.stop_requested = true;
        self.order(Order::Stop, Some(host))
    }

    /// Carries out the observer's requests, and stops the run once on a
    /// signal or the observer's request.
    fn consult(&mut self, stop: &AtomicBool, observer: &mut dyn RunObserver) -> Result<(), SupervisorError> {
        let mut go_on = true;
        for request in observer.observe(&self.view()) {
            match request {
                Request::Stop => go_on = false,
                Request::Order(order, target) => self.order(order, Some(target))?,
            }
        }
        if !self.stop_requested && (stop.load(Ordering::Relaxed) || !go_on) {
            self.stop_requested = true;
            self.order(Order::Stop, Some(self.roster.host()))?;
            let why = if go_on {
                "stop requested (signal)"
            } else {
                "stop requested (observer)"
            };
            self.fault(why.into(), format!("the {} ends the run", self.roster.host()));
        }
        Ok(())
    }

    /// Reaps the processes that exited, restarting those that may be;
    /// returns the simulator's status once it has exited for good.
    fn reap(&mut self) -> Result<Option<ExitStatus>, SupervisorError> {
        let mut exited = Vec::new();
        for (role, process) in &mut self.fleet.processes {
            if let Some(status) = process.exited().map_err(io_error(Path::new("waitpid")))? {
                exited.push((*role, status));
            }
        }
        for (role, status) in exited {
            self.fleet.processes.remove(&role);
            match role {
                Role::Simulator if !status.success() && self.may_restart_host() => {
                    let what = format!("the simulator exited: {}", describe(status));
                    self.restart_host(what, status.code().is_some())?;
                }
                // A world ends when its agents are done and the supervisor says stop.
                Role::World if self.may_restart_host() => {
                    let what = format!("the world exited: {}", describe(status));
                    self.restart_host(what, status.code().is_some())?;
                }
                Role::Simulator | Role::World => return Ok(Some(status)),
                Role::Bridge => {
                    let what = format!("the bridge exited: {}", describe(status));
                    let restarts = self.count_restart(Role::Bridge);
                    if restarts > self.config.max_restarts {
                        self.fault(
                            what.clone(),
                            format!("not restarted: {} restarts already", self.config.max_restarts),
                        );
                        let log = last_log_line(&self.log(Role::Bridge));
                        return Err(RunFailure::SimulatorGivenUp { what, log }.into());
                    }
                    self.start(Role::Bridge, true)?;
                    self.fault(what, "restarted; the link is joined again".into());
                }
                Role::Agent(a) if status.success() => {
                    // Its protocol is complete; once every agent's is, the world stops.
                    self.done.push(a);
                    if self.agents_done() {
                        self.order(Order::Stop, Some(Role::World))?;
                    }
                }
                Role::Keeper(k) | Role::Agent(k) => {
                    let what = format!("{role} exited: {}", describe(status));
                    if status.code() == Some(EXIT_CANNOT_RESUME) {
                        self.fault(what.clone(), "not restarted: it cannot resume".into());
                        return Err(RunFailure::CannotResume {
                            what,
                            log: log_tail(&self.log(role)),
                        }
                        .into());
                    }
                    if status.code() == Some(EXIT_PLAN_DOES_NOT_FIT) {
                        self.fault(what.clone(), "not restarted: its plan does not fit the world".into());
                        return Err(RunFailure::PlanDoesNotFit {
                            what,
                            log: log_tail(&self.log(role)),
                        }
                        .into());
                    }
                    self.restart(k, what)?;
                }
            }
        }
        Ok(None)
    }

    /// Kills the processes silent for longer than the heartbeat timeout and
    /// restarts those that may be.
    fn kill_hung(&mut self) -> Result<(), SupervisorError> {
        let timeout = self.config.heartbeat_timeout;
        let hung: Vec<Role> = self
            .fleet
            .processes
            .keys()
            .filter(|r| self.last_heard.get(r).is_some_and(|t| t.elapsed() > timeout))
            .copied()
            .collect();
        for role in hung {
            if let Some(mut process) = self.fleet.processes.remove(&role) {
                let status = process.kill().map_err(io_error(Path::new("kill")))?;
                let what = format!(
                    "{role} silent for {} s: killed ({})",
                    timeout.as_secs(),
                    describe(status)
                );
                match role {
                    Role::Simulator | Role::World if self.may_restart_host() => self.restart_host(what, false)?,
                    Role::Simulator | Role::World => {
                        self.fault(what.clone(), "run given up".into());
                        return Err(RunFailure::SimulatorHung { what }.into());
                    }
                    Role::Keeper(k) | Role::Agent(k) => self.restart(k, what)?,
                    Role::Bridge => {}
                }
            }
        }
        Ok(())
    }

    /// Asks every agent to stop (each checkpoints) and waits for them, killing
    /// one that does not stop within `grace`.
    fn stop_agents(&mut self, grace: Duration) -> Result<(), SupervisorError> {
        self.order(Order::Stop, None)?;
        let deadline = Instant::now() + grace;
        // The bridge carries the stop to the other hosts: it stays.
        while self.fleet.processes.keys().any(|r| *r != Role::Bridge) {
            let mut done = Vec::new();
            for (role, process) in self.fleet.processes.iter_mut().filter(|(r, _)| **r != Role::Bridge) {
                if let Some(status) = process.exited().map_err(io_error(Path::new("waitpid")))? {
                    done.push((*role, status));
                }
            }
            for (role, status) in done {
                self.fleet.processes.remove(&role);
                if !status.success() {
                    self.fault(
                        format!("{role} exited while stopping: {}", describe(status)),
                        "its last checkpoint is kept".into(),
                    );
                }
            }
            if Instant::now() > deadline {
                let stuck: Vec<Role> = self.fleet.processes.keys().copied().collect();
                for role in stuck {
                    if let Some(mut process) = self.fleet.processes.remove(&role) {
                        let _ = process.kill();
                        self.fault(
                            format!("{role} did not stop within {} s", grace.as_secs()),
                            "killed; its last checkpoint is kept".into(),
                        );
                    }
                }
            }
            self.heartbeats()?;
            std::thread::sleep(Duration::from_millis(10));
        }
        Ok(())
    }

    /// Messages refused, summed over every incarnation of each process
    /// (the simulator's from its result, the others' from their last heartbeats).
    fn rejected(&self, sim: &SimulatorResult) -> BTreeMap<String, Rejections> {
        let mut by_process: BTreeMap<String, Rejections> = BTreeMap::new();
        if self.roster == Roster::Keepaway {
            by_process.insert(Role::Simulator.to_string(), sim.totals.rejected);
        }
        for ((role, _), pulse) in &self.pulses {
            if *role != Role::Simulator {
                let entry = by_process.entry(role.to_string()).or_default();
                *entry = entry.plus(&pulse.rejected);
            }
        }
        by_process
    }

    /// World runs: the deadlines the world's incarnations missed.
    fn world_missed_deadlines(&self) -> u64 {
        self.pulses
            .iter()
            .filter(|((role, _), _)| *role == Role::World)
            .map(|(_, pulse)| pulse.missed_deadlines)
            .sum()
    }
}

/// Reads every histogram the processes of a run of `roster` wrote into
/// `dir`, the incarnations of each process merged (`<name>.<pid>.hdr`).
fn read_histograms(dir: &Path, roster: Roster) -> Result<Vec<Latency>, SupervisorError> {
    let mut files: Vec<PathBuf> = fs::read_dir(dir)
        .map_err(io_error(dir))?
        .flatten()
        .map(|e| e.path())
        .collect();
    files.sort();
    let compute = |k| match roster {
        Roster::Keepaway => compute_histogram(k),
        Roster::World { .. } => agent_compute_histogram(k),
    };
    let per_roster: Vec<String> = match roster {
        Roster::Keepaway => (0..roster.agents()).map(keeper_round_trip_histogram).collect(),
        Roster::World { .. } => vec![WORLD_TURNAROUND.to_string()],
    };
    let names = [ROUND_TRIP.to_string(), FLOOR.to_string(), REMOTE_HOST_FLOOR.to_string()]
        .into_iter()
        .chain((0..roster.agents()).map(compute))
        .chain(per_roster);
    let mut histograms = Vec::new();
    for name in names {
        let mut merged = Latency::new(name.clone());
        for path in &files {
            let file = path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            if file.starts_with(&format!("{name}.")) && file.ends_with(".hdr") {
                let bytes = fs::read(path).map_err(io_error(path))?;
                merged.merge(&Latency::from_bytes(name.clone(), &bytes)?)?;
            }
        }
        histograms.push(merged);
    }
    Ok(histograms)
}

/// Runs run `run` of `config`'s experiment with its files in `work_dir`
/// (created): returns what it produced once the simulator has ended and every
/// process has stopped, also when the run failed ([`RunRecord::failure`]).
/// The run's namespace is removed in every case.
pub fn supervise_run(
    config: &SupervisorConfig,
    run: usize,
    work_dir: &Path,
    stop: &AtomicBool,
    observer: &mut dyn RunObserver,
) -> Result<RunRecord, SupervisorError> {
    fs::create_dir_all(work_dir).map_err(io_error(work_dir))?;
    let spec_path = work_dir.join("spec.json");
    let spec_json = serde_json::to_vec_pretty(&config.spec).map_err(json_error("the experiment spec"))?;
    atomic_file::write_atomic(&spec_path, &spec_json).map_err(io_error(&spec_path))?;
    let owner = Namespace::claim_unique()?;
    let outcome = run_in(config, run, work_dir, &spec_path, &owner, stop, observer);
    let prefix = owner.namespace().prefix().to_string();
    let namespace = owner.namespace().clone();
    let released = owner.release();
    let mut record = outcome?;
    released?;
    record.leftover_files = namespace.files().len();
    record.prefix = prefix;
    Ok(record)
}

fn run_in(
    config: &SupervisorConfig,
    run: usize,
    work_dir: &Path,
    spec_path: &Path,
    owner: &NamespaceOwner,
    stop: &AtomicBool,
    observer: &mut dyn RunObserver,
) -> Result<RunRecord, SupervisorError> {
    let namespace = owner.namespace();
    let node = node(namespace, "supervisor")?;
    let _services = RunServices::create(&node, config.roster())?;
    let mut watch = Watch::launch(config, namespace, &node, run, work_dir, spec_path)?;
    let watched = watch.watch(stop, observer);
    watch.stop_agents(Duration::from_secs(10))?;
    watch.await_remote_files()?;
    watch.collect(watched)
}

impl<'a> Watch<'a> {
    /// Starts run `run`'s simulator and agents, with their files in
    /// `work_dir` and the experiment in `spec_path`, and names the run's
    /// namespace and id in its [`IDENTITY_FILE`].
    fn launch(
        config: &'a SupervisorConfig,
        namespace: &'a Namespace,
        node: &Node<Ipc>,
        run: usize,
        work_dir: &Path,
        spec_path: &Path,
    ) -> Result<Self, SupervisorError> {
        let context = RunContext {
            run_id: rand::rng().random(),
            run,
            ipc_prefix: namespace.prefix().to_string(),
            clock: config.clock,
            wait: config.wait,
            spec: spec_path.to_path_buf(),
            work_dir: work_dir.to_path_buf(),
        };
        let identity = serde_json::json!({ "ipc_prefix": context.ipc_prefix, "run_id": context.run_id });
        let identity_path = work_dir.join(IDENTITY_FILE);
        atomic_file::write_atomic(&identity_path, identity.to_string().as_bytes()).map_err(io_error(&identity_path))?;
        let mut watch = Watch {
            config,
            namespace,
            ports: SupervisorPorts::open(node, config.wait, config.roster())?,
            context,
            fleet: Fleet {
                processes: BTreeMap::new(),
            },
            started: Instant::now(),
            last_heard: BTreeMap::new(),
            pulses: BTreeMap::new(),
            faults: Vec::new(),
            roster: config.roster(),
            restarts: BTreeMap::new(),
            done: Vec::new(),
            floor: None,
            stop_requested: false,
            progress: None,
            last_restart: None,
            host_episodes: None,
            early_host_failure: None,
            stalled: None,
            resumes: Vec::new(),
            control_sequence: 0,
            fifo_refused: None,
        };
        if let Some(cluster) = &config.cluster {
            watch.describe_for_other_hosts(cluster)?;
            watch.start(Role::Bridge, false)?;
        }
        let local: Vec<usize> = (0..watch.roster.agents()).filter(|&k| !watch.is_remote(k)).collect();
        if watch.roster == Roster::Keepaway {
            watch.start(Role::Simulator, false)?;
            for &k in &local {
                watch.start(Role::Keeper(k), false)?;
            }
            return Ok(watch);
        }
        // A world run: the agents first; agent 0 answers the floor
        // measurement (lock-step: before the world starts; real time: a
        // ping every cycle, side by side with the run), then the world.
        for &a in &local {
            watch.start(Role::Agent(a), false)?;
        }
        let mut floor = FloorProbe::world(node, config.wait, watch.context.run_id, work_dir, config.world_period)?;
        match config.clock {
            Clock::Lockstep => floor.measure(config.floor_round_trips)?,
            Clock::Realtime => watch.floor = Some(floor),
        }
        watch.start(Role::World, false)?;
        Ok(watch)
    }
}

impl Watch<'_> {
    /// What the stopped run produced, given how watching it ended.
    fn collect(mut self, watched: Result<ExitStatus, SupervisorError>) -> Result<RunRecord, SupervisorError> {
        let failure = self.failure(watched)?;
        let seconds = self.started.elapsed().as_secs_f64();
        let mut sim = self.simulator_result(failure.is_some())?;
        sim.totals.missed_deadlines += self.world_missed_deadlines();
        let host = match self.roster {
            Roster::Keepaway => "the simulator",
            Roster::World { .. } => "agent 1",
        };
        let failure = failure.or_else(|| self.stalled.clone()).or_else(|| {
            let stopped = self.stop_requested;
            sim.error
                .clone()
                .filter(|_| !stopped)
                .map(|e| format!("{host} ended the run early: {e}"))
        });
        let learning = match self.roster {
            Roster::Keepaway => super::sim_process::keepaway_config(&self.config.spec)?.learning_keepers(),
            Roster::World { agents } => agents,
        };
        let values = self.final_values(learning, failure.is_some())?;
        let checkpoint_failures = self.pulses.values().map(|p| p.checkpoint_failures).sum();
        let link = self.link_faults(&sim);
        let work_dir = &self.context.work_dir;
        Ok(RunRecord {
            run: self.context.run,
            rejected: self.rejected(&sim),
            sim,
            failure,
            restarts: self.restarts.values().sum::<u32>(),
            resumes: self.resume_checks(learning),
            faults: std::mem::take(&mut self.faults),
            histograms: {
                if let Some(floor) = &self.floor {
                    floor.save()?;
                }
                read_histograms(work_dir, self.roster)?
            },
            checkpoint_failures,
            values,
            seconds,
            leftover_files: 0,
            prefix: String::new(),
            scheduling: self.scheduling(),
            link,
        })
    }

    /// A run across hosts: the bridge's link report, and as faults what
    /// must not pass for a clean run (plain TCP, refusals on the link, a
    /// stop ordered from another host); in lock-step, commands out of
    /// sequence (forged or displaced: a cycle answered twice).
    fn link_faults(&mut self, sim: &SimulatorResult) -> Option<LinkReport> {
        if sim.totals.displaced_commands > 0 {
            self.fault(
                format!(
                    "{} keeper commands out of sequence in lock-step (forged, or displaced by a forged one)",
                    sim.totals.displaced_commands
                ),
                "the episodes may not be the keepers' own".into(),
            );
        }
        self.config.cluster.as_ref()?;
        let link = LinkReport::read(&self.context.work_dir).unwrap_or_default();
        if let Some(warning) = &link.warning {
            self.fault(warning.clone(), "run as asked".into());
        }
        if link.refused.total() > 0 {
            self.fault(
                format!(
                    "the bridge refused {} messages or peers on the link: {:?}",
                    link.refused.total(),
                    link.refused
                ),
                "none of them reached the run".into(),
            );
        }
        if link.stop_requests > 0 {
            self.fault(
                "host B's supervisor ordered the run to stop".into(),
                "the run was stopped".into(),
            );
        }
        Some(link)
    }

    /// Why the run failed, if it did, from how watching it ended (an error
    /// other than a process's failure is the supervisor's own, returned).
    fn failure(&mut self, watched: Result<ExitStatus, SupervisorError>) -> Result<Option<String>, SupervisorError> {
        Ok(match watched {
            Ok(status) if status.success() => None,
            Ok(status) => {
                let host = self.roster.host();
                let what = format!("the {host} exited: {}", describe(status));
                self.fault(what.clone(), "agents stopped; run given up".into());
                Some(format!("{what} ({})", log_tail(&self.log(host))))
            }
            Err(SupervisorError::Run(failure)) => Some(failure.to_string()),
            Err(other) => return Err(other),
        })
    }

    /// The simulator's result file, or in a world run agent 1's (empty if
    /// the run failed before it was written).
    fn simulator_result(&self, failed: bool) -> Result<SimulatorResult, SupervisorError> {
        let file = match self.roster {
            Roster::Keepaway => RESULT_FILE.to_string(),
            Roster::World { .. } => agent_result_file(0),
        };
        let result_path = self.context.work_dir.join(file);
        match fs::read_to_string(&result_path) {
            Ok(text) => serde_json::from_str(&text).map_err(json_error(result_path.display())),
            Err(_) if failed => Ok(SimulatorResult::default()),
            Err(source) => Err(SupervisorError::Io {
                path: result_path,
                source,
            }),
        }
    }

    /// The `learning` keepers' last checkpoints (as many as load, if the run failed).
    fn final_values(&self, learning: usize, failed: bool) -> Result<Vec<SavedValues>, SupervisorError> {
        let mut values = Vec::new();
        for k in 0..learning {
            let path = self.context.work_dir.join(checkpoint_name(k));
            match persist::load(&path) {
                Ok(v) => values.push(v),
                Err(e) if !failed => return Err(e.into()),
                Err(_) => break,
            }
        }
        Ok(values)
    }

    /// For each agent restarted: did it resume with the checkpointed values?
    fn resume_checks(&self, learning: usize) -> Vec<ResumeCheck> {
        self.resumes
            .iter()
            .filter(|r| r.expected.is_some() || r.keeper < learning)
            .map(|r| {
                let loaded = persist::load(&resumed_file(&self.context.work_dir, r.keeper, r.pid)).ok();
                let (source, survived) = match &r.expected {
                    Some((values, source)) => (source.to_string(), loaded.as_ref() == Some(values)),
                    None => ("none usable".to_string(), false),
                };
                ResumeCheck {
                    run: self.context.run,
                    keeper: r.keeper + 1,
                    pid: r.pid,
                    source,
                    survived,
                }
            })
            .collect()
    }
}

/// Where run `run`'s working files (checkpoints, logs, histograms) of the
/// output directory `out` are: in the `runs` directory of the result set being
/// written (inside its hidden staging directory, see [`learnpnp::experiment::result_dir`])
/// while the supervisor works, under `out/runs/` once the set is published.
pub fn run_work_dir(out: &Path, run: usize) -> PathBuf {
    let name = format!("run-{run}");
    result_dir::staging_dirs(out)
        .into_iter()
        .map(|staging| staging.join(RUNS_DIR).join(&name))
        .find(|dir| dir.is_dir())
        .unwrap_or_else(|| out.join(RUNS_DIR).join(name))
}

/// The directory of the result set holding every run's working files.
const RUNS_DIR: &str = "runs";

/// Runs every run of `config`'s experiment one after the other (stopping at
/// the first that fails, or when `stop` is set or `observer` asks) and
/// publishes the report in `out` as one set (the runs' working files under
/// `runs/`, then the observer's files).
pub fn supervise(
    config: &SupervisorConfig,
    out: &mut ResultDir,
    stop: &AtomicBool,
    observer: &mut dyn RunObserver,
) -> Result<super::report::Report, SupervisorError> {
    let started = Instant::now();
    let mut files = out.writer()?;
    let runs_dir = files.scratch_dir(RUNS_DIR)?;
    observer.start(&mut files)?;
    let mut records: Vec<RunRecord> = Vec::new();
    for run in 0..config.spec.protocol.runs {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let work_dir = runs_dir.join(format!("run-{run}"));
        let record = supervise_run(config, run, &work_dir, stop, observer)?;
        let ended = record.failure.is_some() || !record.sim.complete;
        records.push(record);
        if ended {
            break;
        }
    }
    observer.finish(&mut files, &records)?;
    super::report::write_report(files, config, &records, started.elapsed().as_secs_f64())
}
