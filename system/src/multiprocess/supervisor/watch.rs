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
use crate::multiprocess::supervisor::launch::Process;
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

/// One run being supervised: what it is, the processes, and what the
/// supervisor has heard, restarted and found, each job's state apart.
pub(super) struct Watch<'a> {
    pub(super) config: &'a SupervisorConfig,
    pub(super) namespace: &'a Namespace,
    pub(super) context: RunContext,
    pub(super) roster: Roster,
    pub(super) started: Instant,
    pub(super) ports: SupervisorPorts,
    /// The sequence number of the last order sent.
    pub(super) control_sequence: u64,
    pub(super) fleet: Fleet,
    /// World runs in real time: the floor measurement's ports (pings to agent 0).
    pub(super) floor: Option<FloorProbe<WorldFloor>>,
    /// The run was asked to stop (a signal, an observer, a stall).
    pub(super) stop_requested: bool,
    pub(super) heard: Heard,
    pub(super) restarts: Restarts,
    pub(super) findings: Findings,
}

/// What the processes' heartbeats told (the life cycle's input).
#[derive(Default)]
pub(super) struct Heard {
    /// When each process was last heard from.
    pub(super) last: BTreeMap<Role, Instant>,
    /// The last pulse of each process, by role and pid.
    pub(super) pulses: BTreeMap<(Role, u32), Pulse>,
    /// The episodes the current host reported first and last (`None` before its first heartbeat).
    pub(super) host_episodes: Option<(u64, u64)>,
    /// Lock-step: the host's cycle count and when it last moved.
    pub(super) progress: Option<(u64, Instant)>,
    /// World runs: agents that completed their protocol and exited.
    pub(super) agents_done: Vec<usize>,
}

/// The processes restarted, and what a restart must be checked against.
#[derive(Default)]
pub(super) struct Restarts {
    /// Restarts of each process so far.
    pub(super) counts: BTreeMap<Role, u32>,
    /// When a process was last restarted.
    pub(super) last: Option<Instant>,
    /// The host's last failure and its log's last line, if it came before the host ended an episode.
    pub(super) early_host_failure: Option<(String, String)>,
    /// The checkpoints the replacement agents are to resume from.
    pub(super) pending_resumes: Vec<PendingResume>,
}

/// What the supervisor found that the run's record reports.
#[derive(Default)]
pub(super) struct Findings {
    pub(super) faults: Vec<Fault>,
    /// Why the run was stopped as stalled, if it was.
    pub(super) stalled: Option<String>,
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
    pub kind: String,
    /// What the supervisor did, and with what result.
    pub outcome: String,
}

/// The checkpoint a replacement agent is to resume from, as it was when the
/// supervisor started the replacement.
#[derive(Debug)]
pub(super) struct PendingResume {
    pub(super) keeper: usize,
    pub(super) pid: u32,
    pub(super) expected: Option<(SavedValues, &'static str)>,
}
