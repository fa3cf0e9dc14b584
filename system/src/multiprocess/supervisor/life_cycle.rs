//! The life cycle of a run's processes: launching the host and the agents,
//! reading their heartbeats, restarting those that die or hang (an agent from
//! its checkpoint, the host from its journal or a new episode), carrying out
//! observers' requests and stopping them all.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::ExitStatus;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use rand::RngExt;

use super::config::{
    EXIT_CANNOT_RESUME, IDENTITY_FILE, RUNS_DIR, RunFailure, SupervisorConfig, SupervisorError, io_error,
};
use super::observe::{Request, RunObserver, RunView};
use super::results::{describe, last_log_line, log_tail};
use super::watch::{Fault, Findings, Fleet, Heard, PendingResume, Restarts, Watch};
use crate::hosts::report::LinkReport;
use crate::ipc::convert::{control_message, read_heartbeat};
use crate::ipc::namespace::Namespace;
use crate::ipc::protocol::{Order, ProcessState, Role, Roster};
use crate::ipc::services::{Ipc, SupervisorPorts, receive};
use crate::multiprocess::agent::chassis::checkpoint_name;
use crate::multiprocess::agent::world::EXIT_PLAN_DOES_NOT_FIT;
use crate::multiprocess::floor_probe::FloorProbe;
use crate::multiprocess::supervisor::launch::{Process, agent_args, set_fifo_priority, spawn, spawn_world};
use crate::multiprocess::view_process::view_args;
use crate::multiprocess::{Clock, RunContext};
use iceoryx2::node::Node;
use learnpnp::learning::persist;

/// Heartbeat timeouts without a lock-step cycle after which a run whose
/// processes all beat is stopped as stalled (three: long enough for a host to
/// notice a hung agent, kill it and start another, here or on another host).
pub const STALL_TIMEOUTS: u32 = 3;

/// How long a view asked to stop may take to write its last counts.
const VIEW_STOP_GRACE: Duration = Duration::from_secs(2);

impl Watch<'_> {
    pub(super) fn log(&self, role: Role) -> PathBuf {
        let name = match role {
            Role::Simulator => "simulator.log".to_string(),
            Role::Keeper(k) => format!("keeper{}.log", k + 1),
            Role::World => "world.log".to_string(),
            Role::Agent(a) => format!("agent{}.log", a + 1),
            Role::Bridge => "bridge.log".to_string(),
            Role::View => "view.log".to_string(),
        };
        self.context.work_dir.join(name)
    }

    pub(super) fn start(&mut self, role: Role, resume: bool) -> Result<(), SupervisorError> {
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
                args.extend(agent_args(role, k, self.config.checkpoint_every));
                &self.config.binaries.agent
            }
            Role::Bridge => {
                let args = self.bridge_args();
                let process = spawn(self.config.binaries.bridge()?, role, &args, &self.log(role))?;
                // The bridge sends no heartbeat: its exit is what is watched.
                self.fleet.processes.insert(role, process);
                return Ok(());
            }
            Role::View => {
                let Some(view) = &self.config.view else {
                    return Ok(());
                };
                // A restarted view resumes nothing but its counts (from its file).
                let mut args = self.context.to_args();
                args.extend(view_args(view, self.context.run));
                let process = spawn(self.config.binaries.view()?, role, &args, &self.log(role))?;
                // The view sends no heartbeat: its exit is what is watched.
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

    /// How many of the run's agents learn (the first ones).
    pub(super) fn learning_agents(&self) -> Result<usize, SupervisorError> {
        Ok(match self.roster {
            Roster::Keepaway => {
                crate::multiprocess::host::simulator::keepaway_config(&self.config.spec)?.learning_keepers()
            }
            Roster::World { agents } => agents,
        })
    }

    /// Takes a started process into the fleet.
    pub(super) fn started(&mut self, role: Role, process: Process) -> Result<(), SupervisorError> {
        if let Some(priority) = self.fifo_priority()
            && let Err(e) = set_fifo_priority(process.pid(), priority)
        {
            self.findings.fifo_refused.get_or_insert(e.to_string());
        }
        self.fleet.processes.insert(role, process);
        self.heard.last.insert(role, Instant::now());
        Ok(())
    }

    /// The SCHED_FIFO priority the run's processes get, if any: only in real
    /// time, and only when they sleep between cycles (`block`, `hybrid`): a
    /// real-time process that spins or yields without end would hold its core
    /// against the rest of the machine.
    pub(super) fn fifo_priority(&self) -> Option<u8> {
        let sleeps = self.config.wait.notifies();
        (self.config.clock == Clock::Realtime && sleeps && self.config.rt_priority > 0)
            .then_some(self.config.rt_priority)
    }

    /// How the run's processes were scheduled, as the report says it.
    pub(super) fn scheduling(&self) -> String {
        match (self.fifo_priority(), &self.findings.fifo_refused) {
            (None, _) => "normal".to_string(),
            (Some(priority), None) => format!("SCHED_FIFO {priority}"),
            (Some(priority), Some(why)) => format!("normal (SCHED_FIFO {priority} refused: {why})"),
        }
    }

    pub(super) fn fault(&mut self, kind: String, outcome: String) {
        self.findings.faults.push(Fault {
            run: self.context.run,
            seconds: self.started.elapsed().as_secs_f64(),
            kind,
            outcome,
        });
    }

    pub(super) fn order(&mut self, order: Order, target: Option<Role>) -> Result<(), SupervisorError> {
        self.control_sequence += 1;
        let message = control_message(order, target, self.control_sequence, self.context.run_id);
        self.ports.control.send(message)?;
        Ok(())
    }

    /// Reads the heartbeats.
    pub(super) fn heartbeats(&mut self) -> Result<(), SupervisorError> {
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
                    self.heard.last.insert(pulse.role, Instant::now());
                    if pulse.role == self.roster.host() {
                        let first = self.heard.host_episodes.map_or(pulse.episodes, |(first, _)| first);
                        self.heard.host_episodes = Some((first, pulse.episodes));
                    }
                }
                if let Role::Agent(a) = pulse.role
                    && self.is_remote(a)
                    && pulse.state == ProcessState::Stopping
                    && !self.heard.agents_done.contains(&a)
                {
                    // A remote world agent has completed its protocol.
                    self.heard.agents_done.push(a);
                    if self.agents_done() {
                        self.order(Order::Stop, Some(Role::World))?;
                    }
                }
                self.heard
                    .pulses
                    .insert((pulse.role, current.unwrap_or(pulse.pid)), pulse);
            }
        }
        Ok(())
    }

    /// Counts one more restart of `role`; returns how many so far.
    pub(super) fn count_restart(&mut self, role: Role) -> u32 {
        self.restarts.last = Some(Instant::now());
        let restarts = self.restarts.counts.entry(role).or_default();
        *restarts += 1;
        *restarts
    }

    /// Replaces agent `k` (a keeper or a world's agent) after it `what` (exited or hung).
    pub(super) fn restart(&mut self, k: usize, what: String) -> Result<(), SupervisorError> {
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
        self.restarts.pending_resumes.push(PendingResume {
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
    pub(super) fn may_restart_host(&self) -> bool {
        let restartable = self.config.restart_simulator || self.roster != Roster::Keepaway;
        restartable && !self.stop_requested && !self.agents_done()
    }

    /// World runs: every agent has completed its protocol.
    pub(super) fn agents_done(&self) -> bool {
        self.roster != Roster::Keepaway && self.heard.agents_done.len() == self.roster.agents()
    }

    /// Replaces the host after it `what`: a new simulator continues from its
    /// journal's last episode boundary, a new world begins a new episode;
    /// the agents drop the episode in progress.
    ///
    /// A host that exits by itself (`own_exit`: not killed) twice the same way
    /// (what happened and its log's last line) before it ends an episode is not
    /// started a third time.
    pub(super) fn restart_host(&mut self, what: String, own_exit: bool) -> Result<(), SupervisorError> {
        let host = self.roster.host();
        let log = last_log_line(&self.log(host));
        let early = own_exit && self.heard.host_episodes.is_none_or(|(first, last)| last <= first);
        self.heard.host_episodes = None;
        let failure = (what.clone(), log.clone());
        if early && self.restarts.early_host_failure.as_ref() == Some(&failure) {
            self.fault(
                what.clone(),
                "not restarted: it failed the same way at its last start".into(),
            );
            return Err(RunFailure::HostFailsAtStart { what, log }.into());
        }
        self.restarts.early_host_failure = early.then_some(failure);
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
    pub(super) fn view(&self) -> RunView<'_> {
        let host = self.roster.host();
        let simulator = self
            .fleet
            .processes
            .get(&host)
            .and_then(|p| self.heard.pulses.get(&(host, p.pid())));
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
                .filter_map(|(role, p)| self.heard.pulses.get(&(*role, p.pid())).copied())
                .collect(),
            simulator,
            roster: self.roster,
        }
    }

    /// Watches until the host exits; restarts agents on the way.
    pub(super) fn watch(
        &mut self,
        stop: &AtomicBool,
        observer: &mut dyn RunObserver,
    ) -> Result<ExitStatus, SupervisorError> {
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
    pub(super) fn stop_if_stalled(&mut self) -> Result<(), SupervisorError> {
        if self.config.clock != Clock::Lockstep || self.stop_requested {
            return Ok(());
        }
        let host = self.roster.host();
        let Some(pulse) = self
            .fleet
            .processes
            .get(&host)
            .and_then(|p| self.heard.pulses.get(&(host, p.pid())))
            .copied()
        else {
            return Ok(());
        };
        let now = Instant::now();
        match self.heard.progress {
            Some((cycles, _)) if cycles == pulse.cycles && pulse.state == ProcessState::Running => {}
            _ => {
                self.heard.progress = Some((pulse.cycles, now));
                return Ok(());
            }
        }
        let limit = self.config.heartbeat_timeout * STALL_TIMEOUTS;
        let quiet_since = self
            .heard
            .progress
            .map(|(_, t)| t)
            .into_iter()
            .chain(self.restarts.last)
            .max()
            .unwrap_or(now);
        if now.duration_since(quiet_since) <= limit {
            return Ok(());
        }
        let cause = match self.config.cluster {
            Some(_) => LinkReport::read(&self.context.work_dir)
                .and_then(|link| link.stall_cause())
                .unwrap_or_else(|| "nothing seen on the link explains it".into()),
            None => "no process reported a cause".into(),
        };
        let what = format!(
            "lock-step stalled: no cycle for {} s while the {host} runs ({cause})",
            limit.as_secs()
        );
        self.fault(what.clone(), "run stopped; every agent checkpoints".into());
        self.findings.stalled = Some(what);
        self.stop_requested = true;
        self.order(Order::Stop, Some(host))
    }

    /// Carries out the observer's requests, and stops the run once on a
    /// signal or the observer's request.
    pub(super) fn consult(&mut self, stop: &AtomicBool, observer: &mut dyn RunObserver) -> Result<(), SupervisorError> {
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
    pub(super) fn reap(&mut self) -> Result<Option<ExitStatus>, SupervisorError> {
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
                // The view is off the learners' path: its failure never stops the run.
                Role::View => {
                    let what = format!("the view exited: {}", describe(status));
                    if self.count_restart(Role::View) > self.config.max_restarts {
                        let outcome = format!("not restarted: {} restarts already", self.config.max_restarts);
                        self.fault(what, outcome);
                    } else if let Err(e) = self.start(Role::View, true) {
                        self.fault(what, format!("not restarted: {e}"));
                    } else {
                        self.fault(what, "restarted".into());
                    }
                }
                Role::Agent(a) if status.success() => {
                    // Its protocol is complete; once every agent's is, the world stops.
                    self.heard.agents_done.push(a);
                    if self.agents_done() {
                        self.order(Order::Stop, Some(Role::World))?;
                    }
                }
                Role::Keeper(k) | Role::Agent(k) => {
                    let what = format!("{role} exited: {}", describe(status));
                    if let Some((note, failure)) = unrestartable(status.code(), &what, || log_tail(&self.log(role))) {
                        self.fault(what, note.into());
                        return Err(failure.into());
                    }
                    self.restart(k, what)?;
                }
            }
        }
        Ok(None)
    }

    /// Kills the processes silent for longer than the heartbeat timeout and
    /// restarts those that may be.
    pub(super) fn kill_hung(&mut self) -> Result<(), SupervisorError> {
        let timeout = self.config.heartbeat_timeout;
        let hung: Vec<Role> = self
            .fleet
            .processes
            .keys()
            .filter(|r| self.heard.last.get(r).is_some_and(|t| t.elapsed() > timeout))
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
                    Role::Bridge | Role::View => {}
                }
            }
        }
        Ok(())
    }

    /// Stops the view, if the run has one (asked, it writes its last counts).
    pub(super) fn stop_view(&mut self) {
        if let Some(mut view) = self.fleet.processes.remove(&Role::View) {
            let _ = view.stop(VIEW_STOP_GRACE);
        }
    }

    /// Asks every agent to stop (each checkpoints) and waits for them, killing
    /// one that does not stop within `grace`.
    pub(super) fn stop_agents(&mut self, grace: Duration) -> Result<(), SupervisorError> {
        self.order(Order::Stop, None)?;
        let deadline = Instant::now() + grace;
        // The bridge carries the stop to the other hosts: it stays; so does
        // the view, which reads the agents' last records.
        let stays = |r: &Role| matches!(r, Role::Bridge | Role::View);
        while self.fleet.processes.keys().any(|r| !stays(r)) {
            let mut done = Vec::new();
            for (role, process) in self.fleet.processes.iter_mut().filter(|(r, _)| !stays(r)) {
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
}

impl<'a> Watch<'a> {
    /// Starts run `run`'s simulator and agents, with their files in
    /// `work_dir` and the experiment in `spec_path`, and names the run's
    /// namespace and id in its [`IDENTITY_FILE`].
    pub(super) fn launch(
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
            feed: config.feeds(),
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
            roster: config.roster(),
            control_sequence: 0,
            floor: None,
            stop_requested: false,
            heard: Heard::default(),
            restarts: Restarts::default(),
            findings: Findings::default(),
        };
        if let Some(cluster) = &config.cluster {
            watch.describe_for_other_hosts(cluster)?;
            watch.start(Role::Bridge, false)?;
        }
        if config.view.is_some() {
            // First, so that it reads the agents' records from their first.
            watch.start(Role::View, false)?;
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

/// The fault note and the failure for an exit code that says a restart cannot
/// help (the process cannot resume, or its plan does not fit the world).
fn unrestartable(code: Option<i32>, what: &str, log: impl FnOnce() -> String) -> Option<(&'static str, RunFailure)> {
    let what = what.to_owned();
    match code {
        Some(EXIT_CANNOT_RESUME) => Some((
            "not restarted: it cannot resume",
            RunFailure::CannotResume { what, log: log() },
        )),
        Some(EXIT_PLAN_DOES_NOT_FIT) => Some((
            "not restarted: its plan does not fit the world",
            RunFailure::PlanDoesNotFit { what, log: log() },
        )),
        _ => None,
    }
}
