//! The supervisor's configuration ([`SupervisorConfig`], [`Cluster`]), the
//! variables and exit codes it shares with its children, and how a run fails
//! ([`SupervisorError`], [`RunFailure`]).

use learnpnp::experiment::result_dir::ResultDirError;
use std::path::{Path, PathBuf};
use std::time::Duration;

use crate::ipc::namespace::NamespaceError;
use crate::ipc::protocol::Roster;
use crate::ipc::services::IpcError;
use crate::ipc::wait::WaitStrategy;
use crate::latency::LatencyError;
use crate::latency::plot::PlotFailure;
use crate::multiprocess::supervisor::launch::{Binaries, LaunchError};
use crate::multiprocess::{Clock, ProcessError};
use learnpnp::experiment::spec::{ExperimentError, ExperimentSpec};
use learnpnp::learning::persist::PersistError;

/// The file in a run's work directory naming its iceoryx2 prefix and run id
/// (for diagnostic tools that join the run).
pub const IDENTITY_FILE: &str = "ipc.json";

/// The exit code of an agent that cannot resume from its checkpoint: it is
/// not restarted again.
pub const EXIT_CANNOT_RESUME: i32 = 3;

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
    /// The run's view (`learnpnp-view`, fed by the agents' live feeds); none: nothing of it is created.
    pub view: Option<ViewConfig>,
    /// The agents publish their live feed even without a view: a ROS 2
    /// world (`--ros2`) republishes it as the plan's state.
    pub agents_feed: bool,
}

/// A run's view: where it serves and what it records.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ViewConfig {
    /// Where it serves the page and the Foxglove WebSocket protocol (`None`: it only records).
    pub address: Option<std::net::SocketAddr>,
    /// An MCAP recording of the feed (run `r` > 0: `NAME-run<r>.mcap` beside it).
    pub record_mcap: Option<PathBuf>,
    /// PNP's monitor line, on this address.
    pub pnp_monitor: Option<std::net::SocketAddr>,
    /// Every record served, as lines of JSON appended to this file.
    pub jsonl: Option<PathBuf>,
}

impl ViewConfig {
    /// The recording of run `run`, if there is one.
    pub(crate) fn recording(&self, run: usize) -> Option<PathBuf> {
        let file = self.record_mcap.as_ref()?;
        if run == 0 {
            return Some(file.clone());
        }
        let stem = file.file_stem().unwrap_or_default().to_string_lossy();
        let name = match file.extension() {
            Some(ext) => format!("{stem}-run{run}.{}", ext.to_string_lossy()),
            None => format!("{stem}-run{run}"),
        };
        Some(file.with_file_name(name))
    }
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

impl SupervisorConfig {
    /// The run's processes: Keepaway's, or a world's and its agents.
    pub(crate) fn roster(&self) -> Roster {
        Roster::of(&self.spec.domain)
    }

    /// Whether the agents publish their live feed (a view, or a world that reads it).
    pub(crate) fn feeds(&self) -> bool {
        self.view.is_some() || self.agents_feed
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
    SampleLog(#[from] SampleLogError),
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

/// A JSON error about `what`.
pub(crate) fn json_error(what: impl std::fmt::Display) -> impl FnOnce(serde_json::Error) -> SupervisorError {
    move |source| SupervisorError::Json {
        what: what.to_string(),
        source,
    }
}

pub(super) fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> SupervisorError + '_ {
    move |source| SupervisorError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The directory of the result set holding every run's working files.
pub(super) const RUNS_DIR: &str = "runs";

/// Why the soak's sample log cannot be written or read back.
#[derive(Debug, thiserror::Error)]
pub enum SampleLogError {
    /// The file cannot be written or read.
    #[error("{path}: {source}")]
    Io {
        /// The log.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A line of it is not a sample.
    #[error("{path}: unreadable sample {line:?}")]
    Unreadable {
        /// The log.
        path: PathBuf,
        /// The line.
        line: String,
    },
}
