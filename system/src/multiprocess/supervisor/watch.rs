//! One run being supervised ([`Watch`]): its configuration, namespace,
//! ports and processes, and what the supervisor has seen of it. Its jobs are
//! implemented in the sibling modules: the life cycle, the hand-off to other
//! hosts and the collection of results.

use std::collections::BTreeMap;
use std::time::Instant;

use super::config::SupervisorConfig;
use crate::ipc::namespace::Namespace;
use crate::ipc::protocol::{Pulse, Role, Roster};
use crate::ipc::services::SupervisorPorts;
use crate::multiprocess::RunContext;
use crate::multiprocess::floor_probe::{FloorProbe, WorldFloor};
use crate::multiprocess::launch::Process;
use learnpnp::learning::persist::SavedValues;
use serde::Serialize;

/// The processes of a run; whatever is still running when this is dropped is killed.
pub(super) struct Fleet {
    pub(super) processes: BTreeMap<Role, Process>,
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

/// One run being supervised.
pub(super) struct Watch<'a> {
    pub(super) config: &'a SupervisorConfig,
    pub(super) namespace: &'a Namespace,
    pub(super) context: RunContext,
    pub(super) ports: SupervisorPorts,
    pub(super) fleet: Fleet,
    pub(super) started: Instant,
    pub(super) last_heard: BTreeMap<Role, Instant>,
    pub(super) pulses: BTreeMap<(Role, u32), Pulse>,
    pub(super) faults: Vec<Fault>,
    pub(super) roster: Roster,
    /// Restarts of each process so far.
    pub(super) restarts: BTreeMap<Role, u32>,
    /// World runs: agents that completed their protocol and exited.
    pub(super) done: Vec<usize>,
    /// World runs: the floor measurement's ports (pings to agent 0).
    pub(super) floor: Option<FloorProbe<WorldFloor>>,
    /// The run was asked to stop (a signal, or an observer).
    pub(super) stop_requested: bool,
    /// Lock-step: the host's cycle count and when it last moved.
    pub(super) progress: Option<(u64, Instant)>,
    /// When a process was last restarted.
    pub(super) last_restart: Option<Instant>,
    /// The episodes the current host reported first and last (`None` before its first heartbeat).
    pub(super) host_episodes: Option<(u64, u64)>,
    /// The host's last failure and its log's last line, if it came before the host ended an episode.
    pub(super) early_host_failure: Option<(String, String)>,
    /// Why the run was stopped as stalled, if it was.
    pub(super) stalled: Option<String>,
    pub(super) resumes: Vec<PendingResume>,
    pub(super) control_sequence: u64,
    /// Why the real-time priority could not be given (the first refusal).
    pub(super) fifo_refused: Option<String>,
}

/// A fault and what the supervisor did about it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fault {
    /// The run (0-based).
    pub run: usize,
    /// Seconds since the run's processes started.
    pub seconds: f64,
    /// What happened (e.g. "keeper 2 exited: signal 9 (SIGKILL)").
    pub(crate) kind: String,
    /// What the supervisor did, and with what result.
    pub(crate) outcome: String,
}

/// The checkpoint a replacement agent is to resume from, as it was when the
/// supervisor started the replacement.
#[derive(Debug)]
pub(super) struct PendingResume {
    pub(super) keeper: usize,
    pub(super) pid: u32,
    pub(super) expected: Option<(SavedValues, &'static str)>,
}
