//! The simulator process (it runs the simulator itself,
//! [`learnpnp_keepaway::simulator`]): Keepaway with the takers inside,
//! whose keepers are agent processes. Each cycle it publishes each keeper's snapshot, collects
//! each keeper's command (lock-step: as soon as all are in; real time: until
//! the cycle's 100 ms deadline), and steps the world. It runs the in-process
//! experiment's episode loop ([`KeepawayTask`](learnpnp::domains::keepaway::KeepawayTask)) and protocol
//! ([`run_protocol`](learnpnp::experiment::runner::run_protocol)), so with the same seed a lock-step run plays exactly the
//! in-process episodes.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, Instant};

use iceoryx2::port::listener::Listener;
use serde::{Deserialize, Serialize};
use shm_layouts::{Header, KeeperCommand, KeeperSnapshot, PROTOCOL_VERSION, SENDER_SIMULATOR};

use crate::ipc::convert::{Rejection, Rejections, command_message, episode_event, read_command, snapshot};
use crate::ipc::protocol::{AgentNews, CommandReading, EpisodeNews, ProcessState, Role, SnapshotMeta};
use crate::ipc::services::{Ipc, IpcError, SimPorts, node, receive};
use crate::ipc::wait::{Idle, MAX_BLOCK};
use crate::latency::Latency;
use crate::multiprocess::host::cadence::{Cadence, sleep_until};
use crate::multiprocess::host::chassis::{self, Host, HostChassis, Readiness};
use crate::multiprocess::journal::{self, Journal};
use crate::multiprocess::{Clock, ProcessError, RunContext};
use learnpnp::domains::keepaway::{KeepawayDomainConfig, KeepawayTask, KeeperTeam, RunSeeds, TeamStep};
use learnpnp::domains::{EpisodeOutcome, Task, TaskError};
use learnpnp::experiment::runner::{EpisodeRecord, RunOutput, run_protocol, task_rng};
use learnpnp::experiment::spec::{DomainSpec, ExperimentSpec};
use learnpnp::learning::{EpisodeMode, EpisodeStart};
use learnpnp::rng::SimRng;
use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::view::PlayerView;
use learnpnp_keepaway::world::NUM_KEEPERS;

/// File name of the simulator's result in its work directory.
pub const RESULT_FILE: &str = "simulator.json";

/// Histogram of snapshot-to-command round trips (every keeper, every cycle).
pub const ROUND_TRIP: &str = "roundtrip";

/// The name of keeper `k`'s own round-trip histogram (a remote keeper's is
/// the round trip across the link between hosts).
pub(crate) fn keeper_round_trip_histogram(k: usize) -> String {
    format!("{ROUND_TRIP}-keeper{}", k + 1)
}

/// Histogram of the bare iceoryx2 round trip of the same payload.
pub const FLOOR: &str = "floor";

/// How long the simulator waits for its agents to connect, or for a lost
/// keeper's replacement, before it gives up.
pub(crate) const CONNECT_TIMEOUT: Duration = Duration::from_secs(60);

/// An episode discarded because a keeper was lost.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct AbortedEpisode {
    /// The episode's sequence number in the run.
    pub episode: u64,
    /// Its mode.
    pub mode: EpisodeMode,
    /// Cycles played before the abort.
    pub cycles: u32,
    /// The keepers lost (1-based, as the report names them).
    pub(crate) keepers: Vec<usize>,
}

/// The journal's file name in the simulator's work directory.
pub const JOURNAL_FILE: &str = "simulator.journal";

/// One whole episode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(crate) struct JournalEntry {
    /// Learning, evaluation or greedy.
    pub mode: EpisodeMode,
    /// What it earned.
    pub(crate) outcome: EpisodeOutcome,
    /// The simulator's random state after it.
    pub rng: SimRng,
    /// The counters after it.
    pub(crate) totals: SimTotals,
}

/// The simulator's counters. They survive a restart: the journal carries
/// them from one whole episode to the next.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SimTotals {
    /// The last episode's sequence number (every episode played, aborted ones included).
    pub(crate) episode_seq: u64,
    /// The last cycle's sequence number.
    pub(crate) cycle_seq: u64,
    /// Learning episodes completed.
    pub learning_episodes: u64,
    /// Cycles played (every episode, aborted ones included).
    pub cycles: u64,
    /// Wall-clock seconds of the episode loop (from the first episode on).
    pub seconds: f64,
    /// Real time: commands that missed their cycle (counted per keeper and cycle).
    pub missed_deadlines: u64,
    /// Real time: commands that arrived after their cycle was stepped.
    pub(crate) late_commands: u64,
    /// Real time: cycles whose work (the simulator's step, the snapshots)
    /// ran past their deadline (the next cycle kept the grid of absolute deadlines).
    #[serde(default)]
    pub late_cycles: u64,
    /// Episodes discarded because a keeper was lost.
    pub(crate) aborted: Vec<AbortedEpisode>,
    /// Messages refused.
    pub rejected: Rejections,
    /// Cycles in which a keeper's plan issued no command.
    pub(crate) idle_cycles: u64,
    /// Lock-step: commands that answered no cycle awaited (forged, or a
    /// keeper's own displaced by a forged one: its cycle was answered twice).
    #[serde(default)]
    pub displaced_commands: u64,
}

/// What the simulator hands the supervisor when it ends.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct SimulatorResult {
    /// Whether the protocol ran to its end (false: stopped or failed).
    pub complete: bool,
    /// Why it did not complete.
    pub error: Option<String>,
    /// The run's evaluations, episodes and greedy score so far.
    pub output: RunOutput,
    /// The counters.
    #[serde(flatten)]
    pub totals: SimTotals,
}

/// The state the remote team and the simulator's main loop share.
struct Link {
    context: RunContext,
    ports: SimPorts,
    /// The heartbeat, the orders, the keepers' readiness and losses (since
    /// the current episode began).
    chassis: HostChassis,
    /// Each keeper's round trips (merged into the round trip histogram when saved).
    keeper_round_trips: [Latency; NUM_KEEPERS],
    floor: Latency,
    /// Real time: the floor pings sent so far (their sequence numbers).
    floor_pings: u64,
    totals: SimTotals,
}

impl Link {
    fn count(&mut self, why: Rejection) {
        self.totals.rejected.count(why);
    }

    /// Heartbeat if due, then the supervisor's commands.
    fn housekeeping(&mut self) -> Result<(), TaskError> {
        let pulse = &mut self.chassis.pacemaker.pulse;
        let totals = &mut self.totals;
        pulse.episodes = totals.learning_episodes;
        pulse.cycles = totals.cycles;
        pulse.rejected = totals.rejected;
        pulse.missed_deadlines = totals.missed_deadlines;
        pulse.late_cycles = totals.late_cycles;
        pulse.aborted_episodes = totals.aborted.len() as u64;
        self.chassis
            .keep(
                &self.ports.host.heartbeat,
                &self.ports.host.control,
                &mut totals.rejected,
            )
            .map_err(remote)?;
        Ok(())
    }

    /// Reads the agents' reports: readiness goes to the chassis, episode ends to `ended`.
    fn read_reports(&mut self, episode: u64, ended: &mut [Option<bool>; NUM_KEEPERS]) -> Result<(), TaskError> {
        self.chassis
            .read_reports(
                &self.ports.host.reports,
                &mut self.totals.rejected,
                |k, news| match news {
                    AgentNews::Ended {
                        episode: e,
                        exploratory,
                    } if e == episode => {
                        ended[k] = Some(exploratory);
                        Ok(())
                    }
                    _ => Err(Rejection::Sequence),
                },
            )
            .map_err(remote)
    }

    /// Waits until no keeper is awaited (every agent connected and ready).
    fn wait_ready(&mut self) -> Result<(), TaskError> {
        match chassis::wait_ready(self, Some(CONNECT_TIMEOUT))? {
            Readiness::Ready => Ok(()),
            Readiness::Stopped => Err(TaskError::Stopped),
            Readiness::TimedOut(missing) => {
                let missing: Vec<String> = missing.iter().map(|k| format!("keeper {}", k + 1)).collect();
                Err(remote(format!(
                    "{} did not connect within {} s",
                    missing.join(", "),
                    CONNECT_TIMEOUT.as_secs()
                )))
            }
        }
    }
}

impl Host for Link {
    type Error = TaskError;

    fn chassis(&self) -> &HostChassis {
        &self.chassis
    }

    fn await_round(&mut self) -> Result<(), TaskError> {
        self.housekeeping()?;
        self.read_reports(0, &mut [None; NUM_KEEPERS])
    }

    fn wake(&self) -> &Listener<Ipc> {
        &self.ports.host.wake
    }

    fn failure(e: IpcError) -> TaskError {
        remote(e)
    }
}

/// A failure of the keeper processes, as the task reports it.
fn remote(e: impl std::fmt::Display) -> TaskError {
    TaskError::External(format!("keeper processes: {e}").into())
}

/// Keepers in agent processes, as the episode loop sees them.
struct RemoteTeam {
    link: Rc<RefCell<Link>>,
    period: Duration,
    seconds_per_cycle: f64,
    start: EpisodeStart,
    cycles: u32,
    /// Real time: the episode's cycles on absolute deadlines.
    cadence: Option<Cadence>,
}

impl RemoteTeam {
    /// Tells the agents the episode is discarded and waits for the lost keepers' replacements.
    fn abort(&self, link: &mut Link) -> Result<TeamStep, TaskError> {
        let run_id = link.context.run_id;
        let news = EpisodeNews::Abort { cycles: self.cycles };
        let episode = link.totals.episode_seq;
        link.ports
            .episode
            .send(episode_event(episode, news, run_id))
            .map_err(remote)?;
        let keepers = (0..NUM_KEEPERS)
            .filter(|&k| link.chassis.lost(k))
            .map(|k| k + 1)
            .collect();
        link.totals.aborted.push(AbortedEpisode {
            episode,
            mode: self.start.mode,
            cycles: self.cycles,
            keepers,
        });
        link.wait_ready()?;
        link.chassis.clear_lost();
        // Commands of the discarded episode still queued are not rejections.
        for k in 0..NUM_KEEPERS {
            while let Some(reading) =
                receive(&link.ports.host.commands[k], |m| read_command(m, k, run_id)).map_err(remote)?
            {
                if let Err(why) = reading {
                    link.count(why);
                }
            }
        }
        Ok(TeamStep::Aborted)
    }
}

impl KeeperTeam for RemoteTeam {
    fn begin_episode(&mut self, start: EpisodeStart) -> Result<(), TaskError> {
        let mut link = self.link.borrow_mut();
        link.wait_ready()?;
        link.chassis.clear_lost();
        link.totals.episode_seq += 1;
        self.start = start;
        self.cycles = 0;
        self.cadence = (link.context.clock == Clock::Realtime).then(|| Cadence::new(self.period));
        let event = episode_event(link.totals.episode_seq, EpisodeNews::Begin(start), link.context.run_id);
        link.ports.episode.send(event).map_err(remote)
    }

    fn act(
        &mut self,
        views: &[PlayerView; NUM_KEEPERS],
        seconds_per_cycle: f64,
        meanwhile: &mut dyn FnMut() -> bool,
    ) -> Result<TeamStep, TaskError> {
        let link = &mut *self.link.borrow_mut();
        link.housekeeping()?;
        if link.chassis.stopped() {
            return Err(TaskError::Stopped);
        }
        if link.chassis.any_lost() {
            return self.abort(link);
        }
        link.totals.cycle_seq += 1;
        self.cycles += 1;
        let (run_id, episode, cycle_seq) = (link.context.run_id, link.totals.episode_seq, link.totals.cycle_seq);
        let meta = SnapshotMeta {
            episode,
            cycle_seq,
            reward: seconds_per_cycle,
            start: self.start,
        };
        let mut published = [Instant::now(); NUM_KEEPERS];
        for (k, view) in views.iter().enumerate() {
            published[k] = Instant::now();
            link.ports.host.snapshots[k]
                .send(snapshot(view, &meta, run_id))
                .map_err(remote)?;
        }
        if let Some(cadence) = &mut self.cadence {
            cadence.worked();
        }
        let deadline = self.cadence.as_ref().map(Cadence::deadline);
        let mut work_left = true;
        let mut commands: [Option<Command>; NUM_KEEPERS] = [None; NUM_KEEPERS];
        let mut idle = Idle::new(link.context.wait);
        loop {
            for k in 0..NUM_KEEPERS {
                while commands[k].is_none() {
                    let Some(reading) =
                        receive(&link.ports.host.commands[k], |m| read_command(m, k, run_id)).map_err(remote)?
                    else {
                        break;
                    };
                    match reading {
                        Ok(c) if c.episode == episode && c.cycle_seq == cycle_seq => {
                            let took = published[k].elapsed();
                            link.keeper_round_trips[k].record(took);
                            if deadline.is_some_and(|d| Instant::now() > d) {
                                // Read after its cycle's deadline (whoever was
                                // late, the keeper or the simulator itself):
                                // dropped, and counted below as missed.
                                break;
                            }
                            link.totals.idle_cycles += u64::from(c.idle);
                            commands[k] = Some(c.command);
                        }
                        Ok(c) if c.cycle_seq < cycle_seq && link.context.clock == Clock::Realtime => {
                            link.totals.late_commands += 1;
                        }
                        Ok(_) => {
                            link.count(Rejection::Sequence);
                            if link.context.clock == Clock::Lockstep {
                                link.totals.displaced_commands += 1;
                            }
                        }
                        Err(why) => link.count(why),
                    }
                }
            }
            if commands.iter().all(Option::is_some) {
                break;
            }
            if let Some(deadline) = deadline
                && Instant::now() >= deadline
            {
                link.totals.missed_deadlines += commands.iter().filter(|c| c.is_none()).count() as u64;
                break;
            }
            if work_left {
                // The takers decide while the keepers think, one between two polls.
                work_left = meanwhile();
                continue;
            }
            link.housekeeping()?;
            if link.chassis.stopped() {
                return Err(TaskError::Stopped);
            }
            if link.chassis.any_lost() {
                return self.abort(link);
            }
            match deadline {
                Some(deadline) => idle.pause_until(&link.ports.host.wake, deadline),
                None => idle.pause(&link.ports.host.wake, MAX_BLOCK),
            }
            .map_err(remote)?;
        }
        while work_left {
            work_left = meanwhile();
        }
        if let Some(deadline) = deadline {
            let halfway = deadline.checked_sub(self.period / 2).unwrap_or(deadline);
            sample_floor(link, halfway, deadline)?;
            sleep_until(deadline, || link.housekeeping())?;
        }
        if let Some(cadence) = &mut self.cadence {
            let late = cadence.late();
            cadence.next();
            link.totals.late_cycles += cadence.late() - late;
        }
        link.totals.cycles += 1;
        Ok(TeamStep::Commands(commands.map(|c| c.unwrap_or(Command::None))))
    }

    fn end_episode(&mut self, cycles: u32) -> Result<bool, TaskError> {
        let link = &mut *self.link.borrow_mut();
        let run_id = link.context.run_id;
        let news = EpisodeNews::End {
            cycles,
            seconds: f64::from(cycles) * self.seconds_per_cycle,
        };
        let episode = link.totals.episode_seq;
        link.ports
            .episode
            .send(episode_event(episode, news, run_id))
            .map_err(remote)?;
        let mut ended = [None; NUM_KEEPERS];
        let mut idle = Idle::new(link.context.wait);
        loop {
            link.housekeeping()?;
            link.read_reports(episode, &mut ended)?;
            if link.chassis.stopped() {
                return Err(TaskError::Stopped);
            }
            // A keeper lost meanwhile will not report; its replacement says it is ready.
            let settled = (0..NUM_KEEPERS).all(|k| ended[k].is_some() || link.chassis.replaced(k));
            if settled {
                break;
            }
            idle.pause(&link.ports.host.wake, MAX_BLOCK).map_err(remote)?;
        }
        if self.start.mode == EpisodeMode::Learn {
            link.totals.learning_episodes += 1;
        }
        Ok(ended[0].unwrap_or(false))
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        Vec::new()
    }

    fn learners(&self) -> Vec<&dyn learnpnp::learning::Learner> {
        Vec::new()
    }

    fn idle_cycles(&self) -> u64 {
        self.link.borrow().totals.idle_cycles
    }
}

/// The cycle sequence number that ends the floor measurement.
pub const FLOOR_END: u64 = u64::MAX;

/// Lock-step floor: how often the measurement beats and reads the supervisor's orders.
const FLOOR_HOUSEKEEPING: Duration = Duration::from_millis(10);

/// Lock-step floor: an echo not back within this ends the measurement.
const FLOOR_ECHO_TIMEOUT: Duration = Duration::from_secs(2);

/// The answer to floor ping `sequence`: the command payload, doing nothing.
pub fn floor_pong(run_id: u64, sequence: u64) -> KeeperCommand {
    let reading = CommandReading {
        episode: 0,
        cycle_seq: sequence,
        command: Command::None,
        idle: false,
    };
    command_message(&reading, 0, run_id)
}

/// A ping of the floor measurement: the snapshot payload, zeroed.
pub fn floor_ping(run_id: u64, sequence: u64) -> KeeperSnapshot {
    KeeperSnapshot {
        header: Header {
            version: PROTOCOL_VERSION,
            sender: SENDER_SIMULATOR,
            run_id,
        },
        episode: 0,
        cycle_seq: sequence,
        reward: 0.0,
        cycle: 0,
        me: 0,
        mode: 0,
        forced_exploration: 0,
        reserved: [0; 6],
        ball: Default::default(),
        players: Default::default(),
    }
}

/// Sends floor ping `sequence` to agent 0 and notifies it; with `alone`, the
/// end marker follows at once, so that the agent answers this one ping and
/// goes back to waiting for its snapshots.
fn send_ping(link: &Link, sequence: u64, alone: bool) -> Result<Instant, TaskError> {
    let run_id = link.context.run_id;
    let sent = Instant::now();
    let ping = floor_ping(run_id, sequence);
    if alone {
        link.ports.floor_ping.send_each([ping, floor_ping(run_id, FLOOR_END)])
    } else {
        link.ports.floor_ping.send(ping)
    }
    .map_err(remote)?;
    Ok(sent)
}

/// Takes the echo of ping `sequence` if it has come (older echoes are dropped).
fn echoed(link: &Link, sequence: u64) -> Result<bool, TaskError> {
    while let Some(echo) = receive(&link.ports.floor_pong, |m| m.cycle_seq).map_err(remote)? {
        if echo == sequence {
            return Ok(true);
        }
    }
    Ok(false)
}

/// Lock-step: measures the bare iceoryx2 round trip of the snapshot payload
/// with agent 0 (which echoes each ping at once), `round_trips` times back to
/// back with the run's wait strategy, before the first episode: the floor our
/// round trips, also back to back, are compared with. It beats and reads the
/// supervisor's orders every [`FLOOR_HOUSEKEEPING`] of the whole measurement,
/// between two pings or while an echo is awaited, however long it takes.
fn measure_floor(link: &mut Link, round_trips: usize) -> Result<(), TaskError> {
    let mut housekept = Instant::now();
    let mut due = || {
        let due = housekept.elapsed() > FLOOR_HOUSEKEEPING;
        if due {
            housekept = Instant::now();
        }
        due
    };
    // The floor stays as measured so far when the run stops or agent 0 is lost.
    let ends = |link: &mut Link| -> Result<bool, TaskError> {
        link.housekeeping()?;
        Ok(link.chassis.stopped() || link.chassis.lost(0))
    };
    for sequence in 1..=round_trips as u64 {
        if due() && ends(link)? {
            return Ok(());
        }
        let sent = send_ping(link, sequence, false)?;
        let mut idle = Idle::new(link.context.wait);
        while !echoed(link, sequence)? {
            if due() && (ends(link)? || sent.elapsed() > FLOOR_ECHO_TIMEOUT) {
                return Ok(());
            }
            idle.pause(&link.ports.host.wake, MAX_BLOCK).map_err(remote)?;
        }
        link.floor.record(sent.elapsed());
    }
    link.ports
        .floor_ping
        .send(floor_ping(link.context.run_id, FLOOR_END))
        .map_err(remote)
}

/// Real time: one floor sample per cycle, at `at` (halfway between two
/// snapshots), while the agents wait for the next cycle. Agent 0 waits for
/// the ping, one cycle after the last one, as every agent waits for its
/// snapshot (see [`crate::multiprocess::agent::keeper::EXPECT_EARLY`]), on the same machine at the
/// same moment of the run: the floor and the round trips are measured side by
/// side over the whole run. An echo not back by the cycle's `deadline` is
/// given up (none is recorded); a cycle that ran past `at` takes no sample.
fn sample_floor(link: &mut Link, at: Instant, deadline: Instant) -> Result<(), TaskError> {
    if Instant::now() > at {
        return Ok(());
    }
    sleep_until(at, || link.housekeeping())?;
    link.floor_pings += 1;
    let sequence = link.floor_pings;
    let sent = send_ping(link, sequence, true)?;
    let mut idle = Idle::new(link.context.wait);
    while !echoed(link, sequence)? {
        if Instant::now() >= deadline {
            return Ok(());
        }
        idle.pause_until(&link.ports.host.wake, deadline).map_err(remote)?;
    }
    link.floor.record(sent.elapsed());
    Ok(())
}

/// The Keepaway configuration of `spec`, if the multi-process system can run it.
pub(crate) fn keepaway_config(spec: &ExperimentSpec) -> Result<KeepawayDomainConfig, ProcessError> {
    use learnpnp::domains::keepaway::KeepawayMode;
    match &spec.domain {
        DomainSpec::Keepaway { config, .. } if matches!(config.mode, KeepawayMode::Pass | KeepawayMode::Position) => {
            Ok(*config)
        }
        other => Err(ProcessError::UnsupportedDomain(other.name())),
    }
}

/// How often the simulator saves its histograms (at the end of a whole
/// episode, once this much time has passed since the last save), so that a
/// killed simulator loses at most about this much of its latencies.
const SAVE_HISTOGRAMS_EVERY: Duration = Duration::from_secs(10);

/// The task the protocol runs: Keepaway with the remote team, journaling each
/// whole episode, and first replaying the journal of a previous incarnation.
struct JournaledTask {
    task: KeepawayTask,
    link: Rc<RefCell<Link>>,
    journal: Journal,
    replay: VecDeque<JournalEntry>,
    /// Episode-loop seconds of earlier incarnations, and when this one's began.
    seconds_before: f64,
    started: Instant,
    /// When the histograms were last saved.
    saved: Instant,
    work_dir: PathBuf,
}

impl JournaledTask {
    /// Seconds of the episode loop over every incarnation so far.
    fn loop_seconds(&self) -> f64 {
        self.seconds_before + self.started.elapsed().as_secs_f64()
    }
}

impl Task for JournaledTask {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        if let Some(entry) = self.replay.pop_front() {
            journal::follows_protocol(entry.mode, mode)?;
            if self.replay.is_empty() {
                // The last whole episode: play on from its state.
                self.task.set_simulator_rng(entry.rng);
                self.replay.shrink_to_fit();
            }
            return Ok(entry.outcome);
        }
        let outcome = self.task.episode(mode)?;
        let mut link = self.link.borrow_mut();
        link.totals.seconds = self.loop_seconds();
        let entry = JournalEntry {
            mode,
            outcome,
            rng: self.task.simulator_rng().clone(),
            totals: link.totals.clone(),
        };
        self.journal.append(&entry).map_err(remote)?;
        if self.saved.elapsed() >= SAVE_HISTOGRAMS_EVERY {
            save_histograms(&self.work_dir, &link).map_err(remote)?;
            self.saved = Instant::now();
        }
        Ok(outcome)
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        Vec::new()
    }

    fn learners(&self) -> Vec<&dyn learnpnp::learning::Learner> {
        Vec::new()
    }
}

/// Runs the simulator of `context`'s run: waits for the agents, measures the
/// floor (lock-step: `floor_round_trips` pings before the first episode; real
/// time: one ping in every cycle), plays the experiment's protocol
/// (journaling every whole episode), and writes [`RESULT_FILE`] and the
/// histograms into the work directory. With `resume` it continues the run of
/// a killed simulator from the journal's last episode boundary (no lock-step
/// floor measurement). A run that is stopped or fails still writes what it completed.
pub fn run(context: &RunContext, floor_round_trips: usize, resume: bool) -> Result<SimulatorResult, ProcessError> {
    let spec = context.load_spec()?;
    let config = keepaway_config(&spec)?;
    let journal_path = context.work_dir.join(JOURNAL_FILE);
    let replay: Vec<JournalEntry> = if resume {
        journal::read(&journal_path)?
    } else {
        Vec::new()
    };
    let journal = Journal::open(&journal_path, &replay, Duration::ZERO)?;
    let totals = replay.last().map(|e| e.totals.clone()).unwrap_or_default();
    let namespace = context.namespace()?;
    let node = node(&namespace, "simulator")?;
    let ports = SimPorts::open(&node, context.wait)?;
    let link = Rc::new(RefCell::new(Link {
        context: context.clone(),
        ports,
        chassis: HostChassis::new(Role::Simulator, context.run_id, context.wait, NUM_KEEPERS),
        keeper_round_trips: std::array::from_fn(|k| Latency::new(keeper_round_trip_histogram(k))),
        floor: Latency::new(FLOOR),
        floor_pings: 0,
        totals,
    }));
    let seconds_per_cycle = config.simulator().server.cycle_seconds;
    let team = RemoteTeam {
        link: Rc::clone(&link),
        period: Duration::from_secs_f64(seconds_per_cycle),
        seconds_per_cycle,
        start: EpisodeStart::LEARN,
        cycles: 0,
        cadence: None,
    };
    let mut output = RunOutput::default();
    let outcome = (|| -> Result<(), TaskError> {
        {
            let mut link = link.borrow_mut();
            link.wait_ready()?;
            if !resume && context.clock == Clock::Lockstep {
                // Ready, not yet running: no cycle is played while the floor
                // is measured, and the supervisor's stall watch waits.
                link.chassis.set_state(ProcessState::Ready);
                measure_floor(&mut link, floor_round_trips)?;
                save_histograms(&context.work_dir, &link).map_err(remote)?;
            }
            link.chassis.set_state(ProcessState::Running);
        }
        let seeds = RunSeeds::draw(&mut task_rng(&spec, context.run));
        let mut task = JournaledTask {
            task: KeepawayTask::with_team(config, Box::new(team), seeds)?,
            link: Rc::clone(&link),
            journal,
            seconds_before: replay.last().map_or(0.0, |e| e.totals.seconds),
            replay: replay.into(),
            started: Instant::now(),
            saved: Instant::now(),
            work_dir: context.work_dir.clone(),
        };
        // Episodes are journaled; `episodes` below reads them back at the end.
        let played = run_protocol(&spec, &mut task, context.run, false, &mut output, |_| {}, || false);
        // The cycles of an unfinished last episode count too.
        link.borrow_mut().totals.seconds = task.loop_seconds();
        played.map(drop).map_err(|e| match e {
            learnpnp::experiment::spec::ExperimentError::Task(t) => t,
            other => remote(other),
        })
    })();
    if context.run == 0 {
        output.episodes = learning_episodes(&journal_path)?;
    }
    let mut link = link.borrow_mut();
    let link = &mut *link;
    link.chassis.shut_down(&link.ports.host.heartbeat)?;
    let result = SimulatorResult {
        complete: outcome.is_ok(),
        error: outcome.err().map(|e| e.to_string()),
        output,
        totals: link.totals.clone(),
    };
    save_histograms(&context.work_dir, link)?;
    let json = serde_json::to_vec_pretty(&result)?;
    let path = context.work_dir.join(RESULT_FILE);
    atomic_file::write_atomic(&path, &json).map_err(|source| ProcessError::Io { path, source })?;
    Ok(result)
}

/// Every learning episode of the journal at `path`, numbered as the protocol
/// numbers them.
fn learning_episodes(path: &Path) -> Result<Vec<EpisodeRecord>, journal::JournalError> {
    let learning = journal::read::<JournalEntry>(path)?
        .into_iter()
        .filter(|e| e.mode == EpisodeMode::Learn);
    Ok((1..)
        .zip(learning)
        .map(|(episode, e)| EpisodeRecord {
            episode,
            outcome: e.outcome,
        })
        .collect())
}

/// The file of histogram `name` recorded by this process: `<name>.<pid>.hdr`
/// (every incarnation of a process writes its own; the supervisor merges them).
pub(crate) fn histogram_file(dir: &Path, name: &str) -> PathBuf {
    dir.join(format!("{name}.{}.hdr", std::process::id()))
}

fn save_histograms(dir: &Path, link: &Link) -> Result<(), ProcessError> {
    let mut round_trip = Latency::new(ROUND_TRIP);
    for keeper in &link.keeper_round_trips {
        round_trip.merge(keeper)?;
    }
    for histogram in [&round_trip, &link.floor].into_iter().chain(&link.keeper_round_trips) {
        let bytes = histogram.to_bytes()?;
        let path = histogram_file(dir, histogram.name());
        atomic_file::write_atomic(&path, &bytes).map_err(|source| ProcessError::Io { path, source })?;
    }
    Ok(())
}
