//! The simulator process: Keepaway with the takers inside, whose keepers are
//! agent processes. Each cycle it publishes each keeper's snapshot, collects
//! each keeper's command (lock-step: as soon as all are in; real time: until
//! the cycle's 100 ms deadline), and steps the world. It runs the in-process
//! experiment's episode loop ([`KeepawayTask`]) and protocol
//! ([`run_protocol`]), so with the same seed a lock-step run plays exactly the
//! in-process episodes.

use std::cell::RefCell;
use std::path::Path;
use std::rc::Rc;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};
use shm_layouts::{Header, KeeperSnapshot, PROTOCOL_VERSION, SENDER_SIMULATOR};

use super::{Clock, Pacemaker, ProcessError, RunContext};
use crate::domains::TaskError;
use crate::domains::keepaway::{KeepawayDomainConfig, KeepawayTask, KeeperTeam, RunSeeds, TeamStep};
use crate::experiment::runner::{RunOutput, run_protocol, task_rng};
use crate::experiment::spec::{DomainSpec, ExperimentSpec};
use crate::ipc::convert::{
    AgentNews, EpisodeNews, Order, ProcessState, Rejection, Rejections, Role, SnapshotMeta, episode_event,
    read_agent_report, read_command, read_control, snapshot,
};
use crate::ipc::services::{IpcError, SimPorts, node, receive, send};
use crate::ipc::wait::{Idle, MAX_BLOCK, wake};
use crate::keepaway::command::Command;
use crate::keepaway::perception::PlayerView;
use crate::keepaway::world::NUM_KEEPERS;
use crate::latency::Latency;
use crate::learning::{EpisodeMode, EpisodeStart};

/// File name of the simulator's result in its work directory.
pub const RESULT_FILE: &str = "simulator.json";

/// Histogram of snapshot-to-command round trips (every keeper, every cycle).
pub const ROUND_TRIP: &str = "roundtrip";

/// Histogram of the bare iceoryx2 round trip of the same payload.
pub const FLOOR: &str = "floor";

/// How long the simulator waits for its agents to connect, or for a lost
/// keeper's replacement, before it gives up.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(60);

/// An episode discarded because a keeper was lost.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AbortedEpisode {
    /// The episode's sequence number in the run.
    pub episode: u64,
    /// Its mode.
    pub mode: EpisodeMode,
    /// Cycles played before the abort.
    pub cycles: u32,
    /// The keepers lost (1-based, as the report names them).
    pub keepers: Vec<usize>,
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
    /// Learning episodes completed.
    pub learning_episodes: u64,
    /// Cycles played (every episode, aborted ones included).
    pub cycles: u64,
    /// Wall-clock seconds of the episode loop (from the first episode on).
    pub seconds: f64,
    /// Real time: commands that missed their cycle (counted per keeper and cycle).
    pub missed_deadlines: u64,
    /// Real time: commands that arrived after their cycle was stepped.
    pub late_commands: u64,
    /// Episodes discarded because a keeper was lost.
    pub aborted: Vec<AbortedEpisode>,
    /// Messages refused.
    pub rejected: Rejections,
    /// Cycles in which a keeper's plan issued no command.
    pub idle_cycles: u64,
}

/// The state the remote team and the simulator's main loop share.
struct Link {
    context: RunContext,
    ports: SimPorts,
    pacemaker: Pacemaker,
    /// Keepers whose (replacement) process has not said it is ready.
    awaiting: [bool; NUM_KEEPERS],
    /// Keepers lost since the current episode began.
    lost: [bool; NUM_KEEPERS],
    /// The process id each keeper's replacement will have (none before the first loss).
    expected: [Option<u32>; NUM_KEEPERS],
    /// The process id of each keeper's last readiness report.
    ready: [Option<u32>; NUM_KEEPERS],
    stop: bool,
    round_trip: Latency,
    floor: Latency,
    result: SimulatorResult,
}

impl Link {
    fn count(&mut self, why: Rejection) {
        self.pacemaker.pulse.rejected.count(why);
    }

    /// Heartbeat if due, then the supervisor's commands.
    fn housekeeping(&mut self) -> Result<(), TaskError> {
        self.pacemaker.tick(&self.ports.heartbeat).map_err(remote)?;
        let run_id = self.context.run_id;
        while let Some(order) =
            receive(&self.ports.control, |m| read_control(m, Role::Simulator, run_id)).map_err(remote)?
        {
            match order {
                Ok(Some(Order::Stop)) => self.stop = true,
                Ok(Some(Order::KeeperLost { keeper, pid })) => {
                    self.lost[keeper] = true;
                    self.expected[keeper] = Some(pid);
                    // The replacement may have said it is ready before this was read.
                    self.awaiting[keeper] = self.ready[keeper] != Some(pid);
                }
                Ok(Some(Order::Checkpoint) | None) => {}
                Err(why) => self.count(why),
            }
        }
        Ok(())
    }

    /// Reads the agents' reports: readiness clears `awaiting`, episode ends go to `ended`.
    fn read_reports(&mut self, episode: u64, ended: &mut [Option<bool>; NUM_KEEPERS]) -> Result<(), TaskError> {
        let run_id = self.context.run_id;
        while let Some(report) = receive(&self.ports.reports, |m| read_agent_report(m, run_id)).map_err(remote)? {
            match report {
                Ok((k, AgentNews::Ready { pid })) => {
                    self.ready[k] = Some(pid);
                    // Only the replacement the supervisor named ends the wait.
                    if self.expected[k].is_none_or(|p| p == pid) {
                        self.awaiting[k] = false;
                    }
                }
                Ok((
                    k,
                    AgentNews::Ended {
                        episode: e,
                        exploratory,
                    },
                )) if e == episode => ended[k] = Some(exploratory),
                Ok(_) => self.count(Rejection::Sequence),
                Err(why) => self.count(why),
            }
        }
        Ok(())
    }

    /// Waits until no keeper is awaited (every agent connected and ready).
    fn wait_ready(&mut self) -> Result<(), TaskError> {
        let started = Instant::now();
        let mut idle = Idle::new(self.context.wait);
        let mut none = [None; NUM_KEEPERS];
        loop {
            self.housekeeping()?;
            self.read_reports(0, &mut none)?;
            if self.stop {
                return Err(TaskError::Stopped);
            }
            if !self.awaiting.contains(&true) {
                return Ok(());
            }
            if started.elapsed() > CONNECT_TIMEOUT {
                let missing: Vec<String> = (0..NUM_KEEPERS)
                    .filter(|&k| self.awaiting[k])
                    .map(|k| format!("keeper {}", k + 1))
                    .collect();
                return Err(TaskError::Remote(format!(
                    "{} did not connect within {} s",
                    missing.join(", "),
                    CONNECT_TIMEOUT.as_secs()
                )));
            }
            idle.pause(&self.ports.wake, MAX_BLOCK).map_err(remote)?;
        }
    }

    fn wake_keepers(&self) -> Result<(), TaskError> {
        for notifier in &self.ports.wake_keepers {
            wake(self.context.wait, notifier).map_err(remote)?;
        }
        Ok(())
    }
}

fn remote(e: IpcError) -> TaskError {
    TaskError::Remote(e.to_string())
}

/// Keepers in agent processes, as the episode loop sees them.
struct RemoteTeam {
    link: Rc<RefCell<Link>>,
    period: Duration,
    seconds_per_cycle: f64,
    episode: u64,
    cycle_seq: u64,
    start: EpisodeStart,
    cycles: u32,
}

impl RemoteTeam {
    /// Tells the agents the episode is discarded and waits for the lost keepers' replacements.
    fn abort(&self, link: &mut Link) -> Result<TeamStep, TaskError> {
        let run_id = link.context.run_id;
        let news = EpisodeNews::Abort { cycles: self.cycles };
        send(&link.ports.episode, episode_event(self.episode, news, run_id)).map_err(remote)?;
        link.wake_keepers()?;
        let keepers = (0..NUM_KEEPERS).filter(|&k| link.lost[k]).map(|k| k + 1).collect();
        link.result.aborted.push(AbortedEpisode {
            episode: self.episode,
            mode: self.start.mode,
            cycles: self.cycles,
            keepers,
        });
        link.pacemaker.pulse.aborted_episodes += 1;
        link.wait_ready()?;
        link.lost = [false; NUM_KEEPERS];
        // Commands of the discarded episode still queued are not rejections.
        for k in 0..NUM_KEEPERS {
            while let Some(reading) =
                receive(&link.ports.commands[k], |m| read_command(m, k, run_id)).map_err(remote)?
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
        link.lost = [false; NUM_KEEPERS];
        self.episode += 1;
        self.start = start;
        self.cycles = 0;
        let event = episode_event(self.episode, EpisodeNews::Begin(start), link.context.run_id);
        send(&link.ports.episode, event).map_err(remote)?;
        link.wake_keepers()
    }

    fn act(&mut self, views: &[PlayerView; NUM_KEEPERS], seconds_per_cycle: f64) -> Result<TeamStep, TaskError> {
        let link = &mut *self.link.borrow_mut();
        link.housekeeping()?;
        if link.stop {
            return Err(TaskError::Stopped);
        }
        if link.lost.contains(&true) {
            return self.abort(link);
        }
        self.cycle_seq += 1;
        self.cycles += 1;
        let run_id = link.context.run_id;
        let meta = SnapshotMeta {
            episode: self.episode,
            cycle_seq: self.cycle_seq,
            reward: seconds_per_cycle,
            start: self.start,
        };
        let mut published = [Instant::now(); NUM_KEEPERS];
        for (k, view) in views.iter().enumerate() {
            published[k] = Instant::now();
            send(&link.ports.snapshots[k], snapshot(view, &meta, run_id)).map_err(remote)?;
            wake(link.context.wait, &link.ports.wake_keepers[k]).map_err(remote)?;
        }
        let deadline = (link.context.clock == Clock::Realtime).then(|| published[0] + self.period);
        let mut commands: [Option<Command>; NUM_KEEPERS] = [None; NUM_KEEPERS];
        let mut idle = Idle::new(link.context.wait);
        loop {
            for k in 0..NUM_KEEPERS {
                while commands[k].is_none() {
                    let Some(reading) =
                        receive(&link.ports.commands[k], |m| read_command(m, k, run_id)).map_err(remote)?
                    else {
                        break;
                    };
                    match reading {
                        Ok(c) if c.episode == self.episode && c.cycle_seq == self.cycle_seq => {
                            link.round_trip.record(published[k].elapsed());
                            link.result.idle_cycles += u64::from(c.idle);
                            commands[k] = Some(c.command);
                        }
                        Ok(c) if c.cycle_seq < self.cycle_seq && link.context.clock == Clock::Realtime => {
                            link.result.late_commands += 1;
                        }
                        Ok(_) => link.count(Rejection::Sequence),
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
                let missed = commands.iter().filter(|c| c.is_none()).count() as u64;
                link.result.missed_deadlines += missed;
                link.pacemaker.pulse.missed_deadlines += missed;
                break;
            }
            link.housekeeping()?;
            if link.stop {
                return Err(TaskError::Stopped);
            }
            if link.lost.contains(&true) {
                return self.abort(link);
            }
            let limit = deadline.map_or(MAX_BLOCK, |d| d.saturating_duration_since(Instant::now()));
            idle.pause(&link.ports.wake, limit).map_err(remote)?;
        }
        if let Some(deadline) = deadline {
            std::thread::sleep(deadline.saturating_duration_since(Instant::now()));
        }
        link.result.cycles += 1;
        link.pacemaker.pulse.cycles += 1;
        Ok(TeamStep::Commands(commands.map(|c| c.unwrap_or(Command::None))))
    }

    fn end_episode(&mut self, cycles: u32) -> Result<bool, TaskError> {
        let link = &mut *self.link.borrow_mut();
        let run_id = link.context.run_id;
        let news = EpisodeNews::End {
            cycles,
            seconds: f64::from(cycles) * self.seconds_per_cycle,
        };
        send(&link.ports.episode, episode_event(self.episode, news, run_id)).map_err(remote)?;
        link.wake_keepers()?;
        let mut ended = [None; NUM_KEEPERS];
        let mut idle = Idle::new(link.context.wait);
        loop {
            link.housekeeping()?;
            link.read_reports(self.episode, &mut ended)?;
            if link.stop {
                return Err(TaskError::Stopped);
            }
            // A keeper lost meanwhile will not report; its replacement says it is ready.
            let settled = (0..NUM_KEEPERS).all(|k| ended[k].is_some() || (link.lost[k] && !link.awaiting[k]));
            if settled {
                break;
            }
            idle.pause(&link.ports.wake, MAX_BLOCK).map_err(remote)?;
        }
        if self.start.mode == EpisodeMode::Learn {
            link.pacemaker.pulse.episodes += 1;
        }
        Ok(ended[0].unwrap_or(false))
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        Vec::new()
    }

    fn learners(&self) -> Vec<&dyn crate::learning::Learner> {
        Vec::new()
    }

    fn idle_cycles(&self) -> u64 {
        self.link.borrow().result.idle_cycles
    }
}

/// The cycle sequence number that ends the floor measurement.
pub const FLOOR_END: u64 = u64::MAX;

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

/// The pause between two pings of the floor measurement in real time: long
/// enough for a waiting agent to block, as it does between two 100 ms cycles.
pub const REALTIME_FLOOR_GAP: Duration = Duration::from_millis(5);

/// Measures the bare iceoryx2 round trip of the snapshot payload with agent 0
/// (which echoes each ping at once), `round_trips` times, with the run's wait
/// strategy: the floor our round trips are compared with, measured side by
/// side. In real time the pings are [`REALTIME_FLOOR_GAP`] apart, so the
/// floor includes waking a process that waits, as every cycle does.
fn measure_floor(link: &mut Link, round_trips: usize) -> Result<(), TaskError> {
    let run_id = link.context.run_id;
    let strategy = link.context.wait;
    let gap = (link.context.clock == Clock::Realtime).then_some(REALTIME_FLOOR_GAP);
    for sequence in 1..=round_trips as u64 {
        if let Some(gap) = gap {
            std::thread::sleep(gap);
        }
        let sent = Instant::now();
        send(&link.ports.floor_ping, floor_ping(run_id, sequence)).map_err(remote)?;
        wake(strategy, &link.ports.wake_keepers[0]).map_err(remote)?;
        let mut idle = Idle::new(strategy);
        let mut checked = sent;
        loop {
            if let Some(echo) = receive(&link.ports.floor_pong, |m| m.cycle_seq).map_err(remote)? {
                if echo == sequence {
                    link.floor.record(sent.elapsed());
                    break;
                }
                continue;
            }
            if checked.elapsed() > Duration::from_millis(10) {
                checked = Instant::now();
                link.housekeeping()?;
                if link.stop || link.lost[0] || sent.elapsed() > Duration::from_secs(2) {
                    return Ok(()); // the floor stays as measured so far
                }
            }
            idle.pause(&link.ports.wake, MAX_BLOCK).map_err(remote)?;
        }
    }
    send(&link.ports.floor_ping, floor_ping(run_id, FLOOR_END)).map_err(remote)?;
    wake(strategy, &link.ports.wake_keepers[0]).map_err(remote)
}

/// The Keepaway configuration of `spec`, if the multi-process system can run it.
pub fn keepaway_config(spec: &ExperimentSpec) -> Result<KeepawayDomainConfig, ProcessError> {
    use crate::domains::keepaway::KeepawayMode;
    match &spec.domain {
        DomainSpec::Keepaway { config, .. } if matches!(config.mode, KeepawayMode::Pass | KeepawayMode::Position) => {
            Ok(*config)
        }
        other => Err(ProcessError::Invalid(format!(
            "the multi-process system runs keepaway-position and keepaway-pass, not {}",
            other.name()
        ))),
    }
}

/// Runs the simulator of `context`'s run: waits for the agents, measures the
/// floor with `floor_round_trips` pings, plays the experiment's protocol, and
/// writes [`RESULT_FILE`] and the histograms into the work directory. A run
/// that is stopped or fails still writes what it completed.
pub fn run(context: &RunContext, floor_round_trips: usize) -> Result<SimulatorResult, ProcessError> {
    let spec = context.load_spec()?;
    let config = keepaway_config(&spec)?;
    let namespace = context.namespace()?;
    let node = node(&namespace, "simulator")?;
    let ports = SimPorts::open(&node)?;
    let link = Rc::new(RefCell::new(Link {
        context: context.clone(),
        ports,
        pacemaker: Pacemaker::new(Role::Simulator, context.run_id),
        awaiting: [true; NUM_KEEPERS],
        lost: [false; NUM_KEEPERS],
        expected: [None; NUM_KEEPERS],
        ready: [None; NUM_KEEPERS],
        stop: false,
        round_trip: Latency::new(ROUND_TRIP),
        floor: Latency::new(FLOOR),
        result: SimulatorResult::default(),
    }));
    let seconds_per_cycle = config.simulator().server.cycle_seconds;
    let team = RemoteTeam {
        link: Rc::clone(&link),
        period: Duration::from_secs_f64(seconds_per_cycle),
        seconds_per_cycle,
        episode: 0,
        cycle_seq: 0,
        start: EpisodeStart::LEARN,
        cycles: 0,
    };
    let mut output = RunOutput::default();
    let mut started = Instant::now();
    let outcome = (|| -> Result<(), TaskError> {
        {
            let mut link = link.borrow_mut();
            link.wait_ready()?;
            link.pacemaker.pulse.state = ProcessState::Running;
            measure_floor(&mut link, floor_round_trips)?;
        }
        started = Instant::now();
        let seeds = RunSeeds::draw(&mut task_rng(&spec, context.run));
        let mut task = KeepawayTask::with_team(config, Box::new(team), seeds)?;
        run_protocol(&spec, &mut task, context.run, &mut output, |_| {}, || false)
            .map(drop)
            .map_err(|e| match e {
                crate::experiment::spec::ExperimentError::Task(t) => t,
                other => TaskError::Remote(other.to_string()),
            })
    })();
    let mut link = link.borrow_mut();
    let link = &mut *link;
    link.result.seconds = started.elapsed().as_secs_f64();
    link.result.output = output;
    link.result.complete = outcome.is_ok();
    link.result.error = outcome.err().map(|e| e.to_string());
    link.result.rejected = link.pacemaker.pulse.rejected;
    link.result.learning_episodes = link.pacemaker.pulse.episodes;
    link.pacemaker.pulse.state = ProcessState::Stopping;
    link.pacemaker.beat(&link.ports.heartbeat)?;
    write_files(&context.work_dir, link)?;
    Ok(link.result.clone())
}

fn write_files(dir: &Path, link: &Link) -> Result<(), ProcessError> {
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.join(name);
        crate::atomic_file::write_atomic(&path, bytes).map_err(|source| ProcessError::Io { path, source })
    };
    let json = serde_json::to_vec_pretty(&link.result).map_err(|e| ProcessError::Invalid(e.to_string()))?;
    write(RESULT_FILE, &json)?;
    for histogram in [&link.round_trip, &link.floor] {
        let bytes = histogram.to_bytes().map_err(|e| ProcessError::Invalid(e.to_string()))?;
        write(&format!("{}.hdr", histogram.name()), &bytes)?;
    }
    Ok(())
}
