//! Chaos: faults injected at seeded random times during a soak, each
//! reported with what came of it.
//!
//! - SIGKILL of a random agent, and of the simulator (the supervisor restarts
//!   both: the agent from its checkpoint, the simulator from its journal);
//! - SIGSTOP of an agent for two seconds (real time only: the others go on,
//!   its missed deadlines are counted, it catches up);
//! - a burst of garbage on every service (wrong version, NaN, ids out of
//!   range, a keeper's command on another's service), which every process
//!   must refuse and count;
//! - a checkpoint write that fails: the agent's file-size limit is set to zero
//!   (as a full disk would refuse the write) and it is asked to checkpoint; its
//!   last good checkpoint must be kept and the run go on;
//! - CPU load beside the run: a busy thread per core for ten seconds.
//!
//! The schedule depends only on the seed and the soak's length: one round of
//! every fault per ten minutes (or, for a soak of so many cycles, per eight
//! simulated hours), at uniform random points in the middle 70% of the round.

use std::collections::VecDeque;
use std::process::{Child, Stdio};
use std::time::Duration;

use rand::RngExt;

use crate::garbage::Garbage;
use crate::load::CpuLoad;
use learnpnp::learning::persist;
use learnpnp::rng::{SimRng, seeded};
use learnpnp_system::ipc::namespace::Namespace;
use learnpnp_system::ipc::protocol::{Order, Role, Roster};
use learnpnp_system::ipc::services::{IpcError, node};
use learnpnp_system::multiprocess::Clock;
use learnpnp_system::multiprocess::agent::chassis::checkpoint_name;
use learnpnp_system::multiprocess::supervisor::{Request, RunRecord, RunView};

/// How long an agent stays stopped.
const STOP_FOR: Duration = Duration::from_secs(2);

/// How long a resumed agent has to show it caught up (acted again).
const CATCH_UP: Duration = Duration::from_secs(3);

/// How long the CPU load lasts.
const LOAD_FOR: Duration = Duration::from_secs(10);

/// How long a checkpoint write is made to fail.
const FAIL_WRITES_FOR: Duration = Duration::from_secs(2);

/// How long the garbage publishers live (their samples live in their memory).
const GARBAGE_FOR: Duration = Duration::from_millis(500);

/// Soak seconds per round of faults.
const ROUND_SECONDS: f64 = 600.0;

/// Soak cycles per round of faults (eight simulated hours).
const ROUND_CYCLES: u64 = 288_000;

/// How long a soak lasts, which its faults are spread over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SoakLength {
    /// Wall-clock time.
    Time(Duration),
    /// Simulated cycles (over every run).
    Cycles(u64),
}

impl SoakLength {
    fn rounds(self) -> usize {
        match self {
            SoakLength::Time(d) => (d.as_secs_f64() / ROUND_SECONDS).ceil().max(1.0) as usize,
            SoakLength::Cycles(c) => c.div_ceil(ROUND_CYCLES).max(1) as usize,
        }
    }
}

/// Where a soak stands: its wall-clock seconds and cycles so far.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SoakClock {
    /// Seconds since the soak began.
    pub seconds: f64,
    /// Cycles simulated so far (over every run).
    pub cycles: u64,
}

/// A fault to inject.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FaultKind {
    /// SIGKILL a random agent.
    KillAgent,
    /// SIGKILL the simulator.
    KillSimulator,
    /// SIGSTOP a random agent for two seconds (real time).
    StopAgent,
    /// Garbage on every service.
    Garbage,
    /// A learning agent's checkpoint write fails.
    CheckpointFailure,
    /// Busy threads on every core.
    CpuLoad,
}

impl FaultKind {
    /// The faults of a soak in `clock` mode.
    pub fn all(clock: Clock) -> Vec<FaultKind> {
        let mut kinds = vec![
            FaultKind::KillAgent,
            FaultKind::KillSimulator,
            FaultKind::Garbage,
            FaultKind::CheckpointFailure,
            FaultKind::CpuLoad,
        ];
        if clock == Clock::Realtime {
            kinds.push(FaultKind::StopAgent);
        }
        kinds
    }
}

/// An injected fault and what came of it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ChaosRecord {
    /// What was done (e.g. "SIGKILL keeper 2 (pid 123)").
    pub(crate) kind: String,
    /// Seconds since the soak began.
    pub time: f64,
    /// When it was over (a stop, load or failing writes last a while).
    pub(crate) ended: f64,
    /// What came of it.
    pub(crate) outcome: String,
    /// The system survived it.
    pub(crate) survived: bool,
    check: Check,
}

/// How a fault's outcome is judged at the end, from what the supervisor recorded.
#[derive(Debug, Clone, PartialEq)]
enum Check {
    /// Judged when it ended (stops, garbage, failing writes, load).
    Done,
    /// The n-th restart of this keeper (0-based) must have resumed with its values.
    AgentRestart { keeper: usize, nth: usize },
    /// The simulator must have been restarted from its journal.
    SimulatorRestart,
}

/// An agent stopped with SIGSTOP.
struct Stopped {
    record: usize,
    pid: u32,
    until: f64,
    missed_before: u64,
    cycles_before: u64,
}

/// A stopped agent, continued: judged once it has had time to act again.
struct Resumed {
    record: usize,
    pid: u32,
    until: f64,
    acted_before: u64,
    while_stopped: String,
}

/// The garbage publisher at work.
struct GarbageBurst {
    record: usize,
    until: f64,
    refused_before: u64,
    publisher: Child,
}

/// An agent whose checkpoint writes fail.
struct FailingWrites {
    record: usize,
    keeper: usize,
    pid: u32,
    until: f64,
    failures_before: u64,
}

/// CPU load beside the run.
struct Load {
    record: usize,
    until: f64,
    missed_before: u64,
    _load: CpuLoad,
}

/// A fault in progress.
enum Active {
    Stopped(Stopped),
    Resumed(Resumed),
    Garbage(GarbageBurst),
    FailingWrites(FailingWrites),
    Load(Load),
}

/// The fault injector (driven by the soak observer).
pub struct Chaos {
    rng: SimRng,
    length: SoakLength,
    /// (share of the soak's length, fault), in order.
    schedule: VecDeque<(f64, FaultKind)>,
    records: Vec<ChaosRecord>,
    active: Vec<Active>,
    agent_kills: [usize; shm_layouts::MAX_AGENTS],
    /// The run's processes (learned from the first view).
    roster: Roster,
}

impl std::fmt::Debug for Chaos {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Chaos")
            .field("schedule", &self.schedule)
            .field("records", &self.records)
            .finish_non_exhaustive()
    }
}

/// Messages refused by every process so far (their heartbeats' counters).
fn refused(view: &RunView<'_>) -> u64 {
    view.pulses.iter().map(|p| p.rejected.total()).sum()
}

fn missed(view: &RunView<'_>) -> u64 {
    view.simulator.map_or(0, |p| p.missed_deadlines)
}

/// Cycles process `pid` has reported acting in (its heartbeat's counter).
fn acted(view: &RunView<'_>, pid: u32) -> u64 {
    view.pulses.iter().find(|p| p.pid == pid).map_or(0, |p| p.cycles)
}

fn pid_of(view: &RunView<'_>, role: Role) -> Option<u32> {
    view.processes.iter().find(|(r, _)| *r == role).map(|(_, pid)| *pid)
}

fn signal(pid: u32, signal: i32) -> bool {
    // SAFETY: kill has no memory effects.
    unsafe { libc::kill(pid as i32, signal) == 0 }
}

/// Sets the file-size limit of process `pid` (`None`: unlimited).
fn limit_file_size(pid: u32, bytes: Option<u64>) -> bool {
    let value = bytes.unwrap_or(libc::RLIM_INFINITY);
    let limit = libc::rlimit {
        rlim_cur: value,
        rlim_max: libc::RLIM_INFINITY,
    };
    // SAFETY: prlimit reads `limit` and writes nothing (old limit: null).
    unsafe { libc::prlimit(pid as i32, libc::RLIMIT_FSIZE, &limit, std::ptr::null_mut()) == 0 }
}

impl Chaos {
    /// The faults of a soak of `length` in `clock` mode, at points drawn from `seed`.
    pub fn new(seed: u64, length: SoakLength, clock: Clock) -> Self {
        let mut rng = seeded(seed);
        let rounds = length.rounds();
        let mut schedule: Vec<(f64, FaultKind)> = Vec::new();
        for round in 0..rounds {
            for kind in FaultKind::all(clock) {
                let at = (round as f64 + 0.15 + 0.7 * rng.random::<f64>()) / rounds as f64;
                schedule.push((at, kind));
            }
        }
        schedule.sort_by(|a, b| a.0.total_cmp(&b.0));
        Chaos {
            rng,
            length,
            schedule: schedule.into(),
            records: Vec::new(),
            active: Vec::new(),
            agent_kills: [0; shm_layouts::MAX_AGENTS],
            roster: Roster::Keepaway,
        }
    }

    /// The planned faults: (share of the soak's length, from 0 to 1; kind).
    pub fn schedule(&self) -> impl Iterator<Item = &(f64, FaultKind)> {
        self.schedule.iter()
    }

    /// The share of the soak's length behind it at `now`.
    fn progress(&self, now: SoakClock) -> f64 {
        match self.length {
            SoakLength::Time(d) => now.seconds / d.as_secs_f64().max(f64::MIN_POSITIVE),
            SoakLength::Cycles(c) => now.cycles as f64 / c.max(1) as f64,
        }
    }

    fn record(&mut self, kind: String, time: f64, check: Check) -> usize {
        self.records.push(ChaosRecord {
            kind,
            time,
            ended: time,
            outcome: String::new(),
            survived: false,
            check,
        });
        self.records.len() - 1
    }

    fn conclude(&mut self, record: usize, outcome: String, survived: bool) {
        let r = &mut self.records[record];
        r.outcome = outcome;
        r.survived = survived;
    }

    /// Injects the faults that are due at `now` and ends those whose time
    /// is up; returns what the supervisor must do for them.
    pub(crate) fn tick(&mut self, now: SoakClock, view: &RunView<'_>) -> Vec<Request> {
        self.roster = view.roster;
        let seconds = now.seconds;
        let progress = self.progress(now);
        let mut requests = Vec::new();
        while self.schedule.front().is_some_and(|(at, _)| *at <= progress) {
            if let Some((_, kind)) = self.schedule.pop_front() {
                requests.extend(self.inject(kind, seconds, view));
            }
        }
        let (due, waiting): (Vec<Active>, Vec<Active>) = std::mem::take(&mut self.active)
            .into_iter()
            .partition(|a| seconds >= until(a));
        self.active = waiting;
        for active in due {
            self.records[record_of(&active)].ended = seconds;
            self.end(active, view);
        }
        requests
    }

    fn random_keeper(&mut self, view: &RunView<'_>, learning_only: bool) -> Option<(usize, u32)> {
        let keepers: Vec<(usize, u32)> = view
            .processes
            .iter()
            .filter_map(|(role, pid)| role.agent_index().map(|k| (k, *pid)))
            .filter(|(k, _)| !learning_only || view.work_dir.join(checkpoint_name(*k)).exists())
            .collect();
        if keepers.is_empty() {
            return None;
        }
        Some(keepers[self.rng.random_range(0..keepers.len())])
    }

    /// Injects a fault of `kind` now; returns what the supervisor must do for it.
    fn inject(&mut self, kind: FaultKind, seconds: f64, view: &RunView<'_>) -> Option<Request> {
        match kind {
            FaultKind::KillAgent => self.kill_agent(seconds, view),
            FaultKind::KillSimulator => self.kill_simulator(seconds, view),
            FaultKind::StopAgent => self.stop_agent(seconds, view),
            FaultKind::Garbage => self.start_garbage(seconds, view),
            FaultKind::CheckpointFailure => return self.fail_checkpoint_writes(seconds, view),
            FaultKind::CpuLoad => self.load_cpu(seconds, view),
        }
        None
    }

    /// SIGKILL of a random agent (judged at the end from its restart).
    fn kill_agent(&mut self, seconds: f64, view: &RunView<'_>) {
        let Some((k, pid)) = self.random_keeper(view, false) else {
            return;
        };
        let nth = self.agent_kills[k];
        self.agent_kills[k] += 1;
        let record = self.record(
            format!("SIGKILL {} (pid {pid})", self.roster.agent(k)),
            seconds,
            Check::AgentRestart { keeper: k, nth },
        );
        if !signal(pid, libc::SIGKILL) {
            self.conclude(record, "the signal could not be sent".into(), false);
        }
    }

    /// SIGKILL of the host, the simulator or the world (judged at the end
    /// from its restart).
    fn kill_simulator(&mut self, seconds: f64, view: &RunView<'_>) {
        let host = self.roster.host();
        let Some(pid) = pid_of(view, host) else {
            return;
        };
        let record = self.record(format!("SIGKILL {host} (pid {pid})"), seconds, Check::SimulatorRestart);
        if !signal(pid, libc::SIGKILL) {
            self.conclude(record, "the signal could not be sent".into(), false);
        }
    }

    /// SIGSTOP of a random agent, continued after [`STOP_FOR`].
    fn stop_agent(&mut self, seconds: f64, view: &RunView<'_>) {
        let Some((k, pid)) = self.random_keeper(view, false) else {
            return;
        };
        let record = self.record(
            format!(
                "SIGSTOP {} (pid {pid}) for {} s",
                self.roster.agent(k),
                STOP_FOR.as_secs()
            ),
            seconds,
            Check::Done,
        );
        signal(pid, libc::SIGSTOP);
        self.active.push(Active::Stopped(Stopped {
            record,
            pid,
            until: seconds + STOP_FOR.as_secs_f64(),
            missed_before: missed(view),
            cycles_before: view.simulator.map_or(0, |p| p.cycles),
        }));
    }

    /// Starts the foreign garbage publisher.
    fn start_garbage(&mut self, seconds: f64, view: &RunView<'_>) {
        let record = self.record(
            "a foreign process publishes garbage on every service".into(),
            seconds,
            Check::Done,
        );
        match start_garbage_publisher(view) {
            Ok(publisher) => self.active.push(Active::Garbage(GarbageBurst {
                record,
                until: seconds + 2.0 * GARBAGE_FOR.as_secs_f64(),
                refused_before: refused(view),
                publisher,
            })),
            Err(e) => self.conclude(record, format!("could not start the publisher: {e}"), false),
        }
    }

    /// Makes a random learning agent's checkpoint writes fail for
    /// [`FAIL_WRITES_FOR`]; returns the order to checkpoint now.
    fn fail_checkpoint_writes(&mut self, seconds: f64, view: &RunView<'_>) -> Option<Request> {
        let (k, pid) = self.random_keeper(view, true)?;
        let record = self.record(
            format!("checkpoint write of {} fails (file-size limit 0)", self.roster.agent(k)),
            seconds,
            Check::Done,
        );
        let failures_before = view
            .pulses
            .iter()
            .find(|p| p.pid == pid)
            .map_or(0, |p| p.checkpoint_failures);
        if !limit_file_size(pid, Some(0)) {
            self.conclude(record, "the file-size limit could not be set".into(), false);
            return None;
        }
        self.active.push(Active::FailingWrites(FailingWrites {
            record,
            keeper: k,
            pid,
            until: seconds + FAIL_WRITES_FOR.as_secs_f64(),
            failures_before,
        }));
        Some(Request::Order(Order::Checkpoint, self.roster.agent(k)))
    }

    /// Busy threads on every core for [`LOAD_FOR`].
    fn load_cpu(&mut self, seconds: f64, view: &RunView<'_>) {
        let load = CpuLoad::on_every_core();
        let record = self.record(
            format!("CPU load: {} busy threads for {} s", load.threads(), LOAD_FOR.as_secs()),
            seconds,
            Check::Done,
        );
        self.active.push(Active::Load(Load {
            record,
            until: seconds + LOAD_FOR.as_secs_f64(),
            missed_before: missed(view),
            _load: load,
        }));
    }

    /// Ends a fault whose time is up.
    fn end(&mut self, active: Active, view: &RunView<'_>) {
        match active {
            Active::Stopped(stopped) => self.continue_agent(stopped, view),
            Active::Resumed(resumed) => self.judge_catch_up(resumed, view),
            Active::Garbage(burst) => self.judge_garbage(burst, view),
            Active::FailingWrites(failing) => self.judge_failing_writes(failing, view),
            Active::Load(load) => self.judge_load(load, view),
        }
    }

    /// Continues a stopped agent; it is judged once it has had time to catch up.
    fn continue_agent(&mut self, stopped: Stopped, view: &RunView<'_>) {
        let Stopped {
            record,
            pid,
            until,
            missed_before,
            cycles_before,
        } = stopped;
        signal(pid, libc::SIGCONT);
        let cycles = view.simulator.map_or(0, |p| p.cycles).saturating_sub(cycles_before);
        let missed = missed(view).saturating_sub(missed_before);
        self.active.push(Active::Resumed(Resumed {
            record,
            pid,
            until: until + CATCH_UP.as_secs_f64(),
            acted_before: acted(view, pid),
            while_stopped: format!("{missed} missed deadlines while it was stopped; the others played {cycles} cycles"),
        }));
        if cycles == 0 {
            self.conclude(record, "the others stopped too".into(), false);
        }
    }

    /// A continued agent survived if it acted again.
    fn judge_catch_up(&mut self, resumed: Resumed, view: &RunView<'_>) {
        let Resumed {
            record,
            pid,
            acted_before,
            while_stopped,
            ..
        } = resumed;
        if !self.records[record].outcome.is_empty() {
            return;
        }
        let alive = view.processes.iter().any(|(_, p)| *p == pid);
        let acted = acted(view, pid).saturating_sub(acted_before);
        let caught_up = if !alive {
            "it did not come back (replaced)".to_string()
        } else if acted == 0 {
            format!("it has not acted in the {} s since", CATCH_UP.as_secs())
        } else {
            format!(
                "it caught up: {acted} cycles acted in the {} s since",
                CATCH_UP.as_secs()
            )
        };
        self.conclude(record, format!("{while_stopped}; {caught_up}"), alive && acted > 0);
    }

    /// The garbage was survived if it was published and refused.
    fn judge_garbage(&mut self, burst: GarbageBurst, view: &RunView<'_>) {
        let GarbageBurst {
            record,
            refused_before,
            mut publisher,
            ..
        } = burst;
        let published = match publisher.try_wait() {
            Ok(Some(status)) => status.success(),
            _ => {
                let _ = publisher.kill();
                let _ = publisher.wait();
                false
            }
        };
        let refused = refused(view).saturating_sub(refused_before);
        self.conclude(
            record,
            format!("{refused} messages refused and counted, none applied"),
            published && refused > 0,
        );
    }

    /// Lifts the file-size limit; survived if the failures were reported, the
    /// last good checkpoint kept and the agent went on.
    fn judge_failing_writes(&mut self, failing: FailingWrites, view: &RunView<'_>) {
        let FailingWrites {
            record,
            keeper,
            pid,
            failures_before,
            ..
        } = failing;
        limit_file_size(pid, None);
        let failures = view
            .pulses
            .iter()
            .find(|p| p.pid == pid)
            .map_or(0, |p| p.checkpoint_failures)
            .saturating_sub(failures_before);
        let path = view.work_dir.join(checkpoint_name(keeper));
        let kept = persist::load(&path).is_ok();
        let alive = view.processes.iter().any(|(_, p)| *p == pid);
        self.conclude(
            record,
            format!(
                "{failures} failed writes reported; the last good checkpoint {}; the agent {}",
                if kept { "was kept" } else { "was lost" },
                if alive { "went on" } else { "died" }
            ),
            failures > 0 && kept && alive,
        );
    }

    /// The load was survived if the host (simulator or world) is still running.
    fn judge_load(&mut self, load: Load, view: &RunView<'_>) {
        let missed = missed(view).saturating_sub(load.missed_before);
        let alive = pid_of(view, self.roster.host()).is_some();
        self.conclude(
            load.record,
            format!("{missed} missed deadlines under load; the run went on"),
            alive,
        );
    }

    /// Ends what is still in progress and judges the kills from what the
    /// supervisor recorded; returns every injected fault.
    pub(crate) fn finish(&mut self, records: &[RunRecord]) -> Vec<ChaosRecord> {
        for active in std::mem::take(&mut self.active) {
            match active {
                Active::Stopped(Stopped { record, pid, .. }) => {
                    signal(pid, libc::SIGCONT);
                    self.conclude(record, "the soak ended while it was stopped".into(), true);
                }
                Active::FailingWrites(FailingWrites { record, pid, .. }) => {
                    limit_file_size(pid, None);
                    self.conclude(record, "the soak ended while writes failed".into(), true);
                }
                Active::Garbage(GarbageBurst {
                    record, mut publisher, ..
                }) => {
                    let _ = publisher.kill();
                    let _ = publisher.wait();
                    self.conclude(record, "the soak ended meanwhile".into(), true);
                }
                Active::Load(Load { record, .. }) => {
                    self.conclude(record, "the soak ended meanwhile".into(), true);
                }
                Active::Resumed(Resumed {
                    record, while_stopped, ..
                }) => {
                    if self.records[record].outcome.is_empty() {
                        let outcome = format!("{while_stopped}; the soak ended before it could catch up");
                        self.conclude(record, outcome, true);
                    }
                }
            }
        }
        let failed = records.iter().find_map(|r| r.failure.clone());
        let resumes: Vec<_> = records.iter().flat_map(|r| &r.resumes).collect();
        let host = self.roster.host();
        let host_exited = format!("the {host} exited");
        let sim_restarts = records
            .iter()
            .flat_map(|r| &r.faults)
            .filter(|f| f.kind.starts_with(&host_exited) && f.outcome.starts_with("restarted"))
            .count();
        let mut sim_kills = 0;
        for r in &mut self.records {
            match r.check {
                Check::Done => {}
                Check::AgentRestart { keeper, nth } => {
                    let resume = resumes.iter().filter(|c| c.keeper == keeper + 1).nth(nth);
                    (r.outcome, r.survived) = match (resume, &failed) {
                        (_, Some(f)) => (format!("the run failed: {f}"), false),
                        (Some(c), None) => (
                            format!(
                                "restarted as pid {}; resumed from its {} {}",
                                c.pid,
                                c.source,
                                if c.survived {
                                    "with every value"
                                } else {
                                    "but the values differ"
                                }
                            ),
                            c.survived,
                        ),
                        (None, None) => ("restarted (a keeper without values to resume)".into(), true),
                    };
                }
                Check::SimulatorRestart => {
                    sim_kills += 1;
                    let restarted = sim_kills <= sim_restarts;
                    (r.outcome, r.survived) = match &failed {
                        Some(f) => (format!("the run failed: {f}"), false),
                        None if restarted && host == Role::World => {
                            ("restarted; the agents dropped the episode in flight".into(), true)
                        }
                        None if restarted => ("restarted from its journal's last episode boundary".into(), true),
                        None => ("not restarted".into(), false),
                    };
                }
            }
        }
        self.records.clone()
    }
}

/// The record of the fault in progress.
fn record_of(active: &Active) -> usize {
    match active {
        Active::Stopped(Stopped { record, .. })
        | Active::Resumed(Resumed { record, .. })
        | Active::Garbage(GarbageBurst { record, .. })
        | Active::FailingWrites(FailingWrites { record, .. })
        | Active::Load(Load { record, .. }) => *record,
    }
}

/// When the fault in progress is over (soak seconds).
fn until(active: &Active) -> f64 {
    match active {
        Active::Stopped(Stopped { until, .. })
        | Active::Resumed(Resumed { until, .. })
        | Active::Garbage(GarbageBurst { until, .. })
        | Active::FailingWrites(FailingWrites { until, .. })
        | Active::Load(Load { until, .. }) => *until,
    }
}

/// `learnpnp-soak`'s command that runs [`publish_garbage`] in a process of
/// its own (a foreign process, as far as the run can tell).
pub const GARBAGE_COMMAND: &str = "publish-garbage";

/// Starts the garbage publisher: this executable with [`GARBAGE_COMMAND`].
fn start_garbage_publisher(view: &RunView<'_>) -> std::io::Result<Child> {
    let mut command = std::process::Command::new(std::env::current_exe()?);
    command
        .args([GARBAGE_COMMAND, "--ipc-prefix", view.namespace.prefix()])
        .args(["--run-id", &view.run_id.to_string()]);
    if let Roster::World { agents } = view.roster {
        command.args(["--world-agents", &agents.to_string()]);
    }
    command
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
}

/// Publishes garbage of every kind on every service of run `run_id` in
/// `namespace` (a Keepaway run's, [`Garbage::every_kind`], or with
/// `world_agents`, a world run's, [`Garbage::every_world_kind`]), and keeps
/// the publishers (which hold the samples) until it has been read.
pub fn publish_garbage(namespace: &Namespace, run_id: u64, world_agents: Option<usize>) -> Result<(), IpcError> {
    let node = node(namespace, "garbage")?;
    let garbage = match world_agents {
        Some(agents) => Garbage::every_world_kind(run_id, agents),
        None => Garbage::every_kind(run_id),
    };
    garbage.publish(&node, GARBAGE_FOR)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_schedule_depends_on_the_seed_alone() {
        let points = |seed| {
            Chaos::new(seed, SoakLength::Time(Duration::from_secs(120)), Clock::Realtime)
                .schedule()
                .copied()
                .collect::<Vec<_>>()
        };
        assert_eq!(points(3), points(3));
        assert_ne!(points(3), points(4));
        let plan = points(3);
        assert_eq!(plan.len(), FaultKind::all(Clock::Realtime).len());
        assert!(plan.iter().all(|(at, _)| (0.15..=0.85).contains(at)), "{plan:?}");
        let lockstep = Chaos::new(3, SoakLength::Time(Duration::from_secs(1800)), Clock::Lockstep);
        assert_eq!(lockstep.schedule().count(), 3 * FaultKind::all(Clock::Lockstep).len());
        assert!(!lockstep.schedule().any(|(_, k)| *k == FaultKind::StopAgent));
        let day = Chaos::new(3, SoakLength::Cycles(864_000), Clock::Lockstep);
        assert_eq!(day.schedule().count(), 3 * FaultKind::all(Clock::Lockstep).len());
    }

    #[test]
    fn faults_fall_due_by_the_soaks_own_measure() {
        let day = Chaos::new(5, SoakLength::Cycles(1000), Clock::Lockstep);
        let at = |seconds, cycles| day.progress(SoakClock { seconds, cycles });
        assert_eq!(at(1e6, 500), 0.5);
        let hour = Chaos::new(5, SoakLength::Time(Duration::from_secs(100)), Clock::Lockstep);
        assert_eq!(
            hour.progress(SoakClock {
                seconds: 25.0,
                cycles: 7
            }),
            0.25
        );
    }
}
