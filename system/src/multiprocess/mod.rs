//! The multi-process learner system: a host process (the Keepaway simulator
//! or a world) and one agent process per keeper or agent exchange
//! knowledge-base snapshots, commands, episode events and rewards through
//! iceoryx2 shared memory ([`crate::ipc`]), and a supervisor starts, watches
//! and restarts them. One submodule per job:
//!
//! - [`host`](crate::multiprocess::host): the simulator process (the simulator itself is
//!   [`learnpnp_keepaway`]), whose keepers are a
//!   [`learnpnp::domains::keepaway::KeeperTeam`] of remote agents and which runs
//!   the same episode loop as the in-process experiment
//!   ([`learnpnp::experiment::runner::run_protocol`]); a world written in Rust
//!   (the corridor); the chassis both run on (heartbeat, orders, readiness,
//!   lost agents) and their real-time cadence;
//! - [`agent`](crate::multiprocess::agent): one keeper's process (its plan, learner and executor,
//!   or a fixed policy) and an agent of a world on the stepwise executor, on
//!   one chassis that checkpoints their values off the decision loop;
//! - [`supervisor`](crate::multiprocess::supervisor): launching, watching, restarting, stopping and
//!   cleaning up, what a run writes, and the host of remote agents that joins
//!   a run across hosts;
//! - shared by them: [`journal`](crate::multiprocess::journal) (whole episodes),
//!   [`floor_probe`](crate::multiprocess::floor_probe) (the floor of a world run),
//!   [`view_process`](crate::multiprocess::view_process) (a run's view, reading the agents' live feeds).
//!
//! Soaks, fault injection and the benchmarks watch a run from outside, as
//! [`RunObserver`](crate::multiprocess::supervisor::RunObserver)s: they are
//! the crate `learnpnp-harness` (the binary `learnpnp-soak`).
//!
//! See docs/ARCHITECTURE.md for one snapshot's way through the processes.

/// The agents' processes: a keeper, an agent of a world, and their chassis.
pub mod agent;
/// The iceoryx2 floor: the bare round trip of a run's payloads.
pub mod floor_probe;
/// The hosts' processes: the Keepaway simulator, a world written in Rust, and their chassis.
pub mod host;
/// A journal of whole episodes.
pub mod journal;
/// The supervisor of a run's processes: launching, watching, reporting, and a host of remote agents.
pub mod supervisor;
/// The view process of a run with a view.
pub mod view_process;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::ipc::convert::{Rejections, heartbeat};
use crate::ipc::namespace::{Namespace, NamespaceError};
use crate::ipc::protocol::{ProcessState, Pulse, Role};
use crate::ipc::services::{IpcError, Pub, send};
use crate::ipc::wait::WaitStrategy;
use learnpnp::experiment::spec::ExperimentSpec;

/// What every process of a run does first in `main`: freed large blocks go
/// back to the system at once ([`crate::resident_memory`]), and iceoryx2 logs
/// warnings and worse unless its environment variable asks for another level.
pub fn start_process() {
    crate::resident_memory::return_large_blocks_when_freed();
    iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Warn);
}

/// How the simulator's clock advances.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Clock {
    /// A cycle is stepped as soon as every keeper's command for it is in.
    Lockstep,
    /// A cycle is stepped every 100 ms of wall-clock time; a late command is
    /// dropped and counted as a missed deadline, as the soccer server does.
    Realtime,
}

learnpnp::named::impl_named!(
    Clock,
    "clock",
    [
        Lockstep => "lockstep",
        Realtime => "realtime",
    ]
);

/// What every process of a run shares: who the run is and how its processes
/// talk. The supervisor passes it to its children on their command lines
/// ([`RunContext::to_args`], parsed by the binaries as `child_args::RunContextArgs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunContext {
    /// The run's id (every message carries it).
    pub run_id: u64,
    /// The run's index among the experiment's runs (it derives the seeds).
    pub run: usize,
    /// The run's iceoryx2 prefix.
    pub(crate) ipc_prefix: String,
    /// How the simulator's clock advances.
    pub clock: Clock,
    /// How processes wait for messages.
    pub wait: WaitStrategy,
    /// The experiment (as `summary.json` of a run holds it, under `spec`, or on its own).
    pub spec: PathBuf,
    /// Where the process writes its files (histograms, results, checkpoints).
    pub(crate) work_dir: PathBuf,
    /// The run has a view: each agent publishes its live feed
    /// ([`crate::ipc::feed`]); without one nothing of it is created.
    #[serde(default)]
    pub feed: bool,
}

impl RunContext {
    /// The run's namespace.
    pub fn namespace(&self) -> Result<Namespace, NamespaceError> {
        Namespace::from_prefix(&self.ipc_prefix)
    }

    /// Reads and checks the experiment spec ([`ExperimentSpec::from_json`]:
    /// every parameter in its range).
    pub(crate) fn load_spec(&self) -> Result<ExperimentSpec, ProcessError> {
        let text = std::fs::read_to_string(&self.spec).map_err(|source| ProcessError::Io {
            path: self.spec.clone(),
            source,
        })?;
        ExperimentSpec::from_json(&text).map_err(|e| ProcessError::Spec {
            path: self.spec.clone(),
            detail: e.to_string(),
        })
    }
}

/// Why a process of the run fails.
#[derive(Debug, thiserror::Error)]
pub enum ProcessError {
    /// Shared memory failed.
    #[error(transparent)]
    Ipc(#[from] IpcError),
    /// The namespace is unusable.
    #[error(transparent)]
    Namespace(#[from] NamespaceError),
    /// The checkpoint writer thread cannot be started.
    #[error("cannot start the checkpoint writer: {0}")]
    Writer(std::io::Error),
    /// A file cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The experiment spec file is not a valid spec.
    #[error("{path}: not an experiment spec: {detail}")]
    Spec {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        detail: String,
    },
    /// The experiment's domain is not one the system runs.
    #[error("the multi-process system runs keepaway-position and keepaway-pass, not {0}")]
    UnsupportedDomain(&'static str),
    /// The experiment has no plan for its learning keepers.
    #[error("the experiment has no plan for its learning keepers")]
    NoPlan,
    /// There is no such keeper (1-based).
    #[error("there is no keeper {0}")]
    NoKeeper(usize),
    /// There is no such agent of the world (1-based).
    #[error("there is no agent {0}")]
    NoAgent(usize),
    /// A world agent's plan cannot be run by the stepwise executor.
    #[error("the agent's plan cannot run: {0}")]
    Task(learnpnp::domains::TaskError),
    /// A world agent's plan names atoms or actions the world lacks.
    #[error("{0}")]
    PlanDoesNotFit(Box<agent::world::Misfit>),
    /// The world announced no vocabulary.
    #[error("the world announced no vocabulary within {0} s")]
    NoVocabulary(u64),
    /// The supervisor said stop.
    #[error("stopped")]
    Stopped,
    /// The keeper's plan cannot be run in its world.
    #[error("the keeper's plan cannot run: {0}")]
    PlanCannotRun(learnpnp::executor::ExecError),
    /// The keeper's plan failed while it ran.
    #[error("the keeper's plan failed: {0}")]
    PlanFailed(learnpnp::executor::ExecError),
    /// The experiment failed.
    #[error(transparent)]
    Experiment(#[from] learnpnp::experiment::spec::ExperimentError),
    /// A checkpoint cannot be used.
    #[error(transparent)]
    Checkpoint(#[from] learnpnp::learning::persist::PersistError),
    /// A restarted agent cannot resume from its checkpoint.
    #[error("cannot resume: {0}")]
    CannotResume(String),
    /// The simulator's journal cannot be used.
    #[error(transparent)]
    Journal(#[from] journal::JournalError),
    /// The simulator's result cannot be written as JSON.
    #[error("the simulator's result: {0}")]
    Json(#[from] serde_json::Error),
    /// A histogram cannot be serialised.
    #[error(transparent)]
    Latency(#[from] crate::latency::LatencyError),
}

/// How often a process sends its heartbeat.
pub(crate) const HEARTBEAT_EVERY: Duration = Duration::from_millis(100);

/// A process's heartbeat: its pulse, published every [`HEARTBEAT_EVERY`].
#[derive(Debug)]
pub(crate) struct Pacemaker {
    /// What the next heartbeat says.
    pub(crate) pulse: Pulse,
    run_id: u64,
    last: Option<Instant>,
}

impl Pacemaker {
    /// The heartbeat of `role` in run `run_id`.
    pub(crate) fn new(role: Role, run_id: u64) -> Self {
        Pacemaker {
            pulse: Pulse {
                role,
                pid: std::process::id(),
                state: ProcessState::Starting,
                sequence: 0,
                episodes: 0,
                cycles: 0,
                rejected: Rejections::default(),
                missed_deadlines: 0,
                aborted_episodes: 0,
                checkpoints: 0,
                checkpoint_failures: 0,
                late_cycles: 0,
            },
            run_id,
            last: None,
        }
    }

    /// Sends a heartbeat if one is due.
    pub(crate) fn tick(&mut self, publisher: &Pub<shm_layouts::Heartbeat>) -> Result<(), IpcError> {
        if self.last.is_none_or(|t| t.elapsed() >= HEARTBEAT_EVERY) {
            self.beat(publisher)?;
        }
        Ok(())
    }

    /// Sends a heartbeat now (e.g. on a change of state).
    pub(crate) fn beat(&mut self, publisher: &Pub<shm_layouts::Heartbeat>) -> Result<(), IpcError> {
        self.pulse.sequence += 1;
        self.last = Some(Instant::now());
        send(publisher, heartbeat(&self.pulse, self.run_id))
    }
}
