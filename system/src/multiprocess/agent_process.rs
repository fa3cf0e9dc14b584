//! An agent process: one keeper. A learning keeper runs its plan with its
//! learner and executor (the in-process [`PlanKeeper`]); the others follow
//! the mode's fixed policy. Each cycle it takes its snapshot, credits the
//! reward, thinks until an action issues the cycle's command, and sends it.
//! A learning keeper checkpoints its values every N learning episodes and on
//! the supervisor's request, atomically, in the `persist` format. In real
//! time it sleeps between cycles and is polling again shortly before its next
//! snapshot is due ([`EXPECT_EARLY`]).

use learnpnp::named::Named;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::background_save::{BackgroundSave, CHECKPOINT_SPACING, Checkpoint};
use super::sim_process::{FLOOR_END, floor_pong, histogram_file, keepaway_config};
use super::{Clock, HEARTBEAT_EVERY, Pacemaker, ProcessError, RunContext};
use crate::ipc::convert::{Rejection, agent_report, command_message, read_control, read_episode_event, read_snapshot};
use crate::ipc::protocol::{AgentNews, CommandReading, EpisodeNews, Order, ProcessState, Role, SnapshotMeta};
use crate::ipc::services::{AgentPorts, node, receive};
use crate::ipc::wait::{Idle, MAX_BLOCK, TIMED_WAIT_SLACK};
use crate::latency::Latency;
use learnpnp::domains::keepaway::{KeepawayDomainConfig, PlanKeeper, RunSeeds, registry};
use learnpnp::experiment::runner::{learner_for, task_rng};
use learnpnp::experiment::spec::ExperimentSpec;
use learnpnp::keepaway_sim::command::Command;
use learnpnp::keepaway_sim::keeper::{KeeperMemory, keeper_command};
use learnpnp::keepaway_sim::params::KeepawayConfig;
use learnpnp::keepaway_sim::perception::PlayerView;
use learnpnp::keepaway_sim::policies::BaselinePolicy;
use learnpnp::learning::EpisodeStart;
use learnpnp::learning::persist::{self, PlanLabels, SavedValues};
use learnpnp::plan::Plan;

/// Writes a line to the agent's log (its stderr). Unlike `eprintln!` it does
/// not panic when the write fails: a full disk must not kill the agent.
macro_rules! report {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// Real time: how long before a message is due (a snapshot, or agent 0's
/// floor ping, one cycle after the previous one) the agent stops sleeping and
/// polls, so that the message finds it awake rather than waiting for a
/// wake-up (on a virtual machine a sleeping core can take milliseconds to wake).
pub const EXPECT_EARLY: Duration = Duration::from_millis(1);

/// Real time: how long after a message was due the agent keeps polling for it
/// before it goes back to sleep (the first snapshot of an episode comes after
/// the episode's begin, later than one cycle after the last one).
pub const EXPECT_LATE: Duration = Duration::from_millis(2);

/// The name of keeper `k`'s compute-time histogram.
pub fn compute_histogram(k: usize) -> String {
    format!("compute-keeper{}", k + 1)
}

/// The name of keeper `k`'s checkpoint file: as the in-process experiment names
/// the values of its learning agents (`values.bin`, `values-agent2.bin`, ...).
pub fn checkpoint_name(k: usize) -> String {
    if k == 0 {
        "values.bin".to_string()
    } else {
        format!("values-agent{}.bin", k + 1)
    }
}

/// Where a restarted agent writes the values it resumed with:
/// `resumed-keeper<k>.<pid>.bin` in the run's work directory.
pub fn resumed_file(dir: &Path, k: usize, pid: u32) -> PathBuf {
    dir.join(format!("resumed-keeper{}.{pid}.bin", k + 1))
}

/// An agent's settings beyond the run's.
#[derive(Debug, Clone, PartialEq)]
pub struct AgentSettings {
    /// The keeper (0-based).
    pub keeper: usize,
    /// Checkpoint every this many learning episodes (0: only on request and at the end).
    pub checkpoint_every: u64,
    /// Start from the checkpoint in the work directory (a restart).
    pub resume: bool,
}

/// Who decides this keeper's commands.
enum Brain {
    /// The plan, with its learner.
    Plan {
        keeper: Box<PlanKeeper>,
        plan: Arc<Plan>,
        algorithm: &'static str,
    },
    /// The mode's fixed policy.
    Fixed {
        policy: BaselinePolicy,
        memory: KeeperMemory,
        config: Box<KeepawayConfig>,
    },
}

impl Brain {
    fn begin_episode(&mut self, start: EpisodeStart) {
        match self {
            Brain::Plan { keeper, .. } => keeper.begin_episode(start),
            Brain::Fixed { memory, .. } => *memory = KeeperMemory::default(),
        }
    }

    /// The cycle's command, and whether the plan issued none.
    fn act(&mut self, view: PlayerView, reward: f64) -> Result<(Command, bool), ProcessError> {
        match self {
            Brain::Plan { keeper, .. } => {
                let idle_before = keeper.idle_cycles();
                let command = keeper.act(view, reward).map_err(ProcessError::PlanFailed)?;
                Ok((command, keeper.idle_cycles() > idle_before))
            }
            Brain::Fixed { policy, memory, config } => Ok((keeper_command(&view, config, memory, policy), false)),
        }
    }

    /// Ends the episode; returns whether it explored.
    fn end_episode(&mut self) -> bool {
        match self {
            Brain::Plan { keeper, .. } => {
                keeper.end_episode();
                keeper.learner().exploratory()
            }
            Brain::Fixed { .. } => false,
        }
    }

    /// The values to checkpoint (none for a fixed policy).
    fn values(&self) -> Option<SavedValues> {
        match self {
            Brain::Plan {
                keeper,
                plan,
                algorithm,
                ..
            } => Some(SavedValues::new(
                *algorithm,
                keeper.learner().values(),
                &plan.activation_plans(),
            )),
            Brain::Fixed { .. } => None,
        }
    }
}

/// Loads a checkpoint for a restart: the file, or, if it is unusable, its
/// previous good version, reporting the problem; an error naming the file if
/// neither can be used or the values belong to another plan.
pub(super) fn load_checkpoint(path: &Path, plan: &Plan) -> Result<SavedValues, ProcessError> {
    let saved = match persist::load(path) {
        Ok(saved) => saved,
        Err(problem) => {
            let prev = persist::prev_path(path);
            let saved = persist::load(&prev)
                .map_err(|_| ProcessError::CannotResume(format!("{problem} (and no usable {})", prev.display())))?;
            report!(
                "error: {problem}; resuming from the previous checkpoint {}",
                prev.display()
            );
            saved
        }
    };
    let expected: Vec<PlanLabels> = plan.activation_plans().into_iter().map(PlanLabels::of).collect();
    if saved.plans != expected {
        return Err(ProcessError::CannotResume(format!(
            "{}: the checkpoint was learned on another plan",
            path.display()
        )));
    }
    Ok(saved)
}

/// Whether a begin of `episode` is for the next episode, the last begun
/// being `last_begun`: in lock-step the one after it, in real time any later
/// one (a cut link may have lost some); any, when none was begun since the
/// agent or the simulator started. A replayed or forged begin is not.
fn begins_next(last_begun: Option<u64>, clock: Clock, episode: u64) -> bool {
    match (last_begun, clock) {
        (None, _) => episode > 0,
        (Some(last), Clock::Lockstep) => last.checked_add(1) == Some(episode),
        (Some(last), Clock::Realtime) => episode > last,
    }
}

/// Builds keeper `k`'s brain for run `context.run` of `spec`.
fn brain(
    spec: &ExperimentSpec,
    config: &KeepawayDomainConfig,
    context: &RunContext,
    settings: &AgentSettings,
    checkpoint: &Path,
) -> Result<Brain, ProcessError> {
    let k = settings.keeper;
    let sim_config = config.simulator();
    if k >= config.learning_keepers() {
        let seeds = RunSeeds::draw(&mut task_rng(spec, context.run));
        return Ok(Brain::Fixed {
            policy: config.baseline(seeds.fixed_policy),
            memory: KeeperMemory::default(),
            config: Box::new(sim_config),
        });
    }
    let plan = spec.domain.load_plan()?.ok_or(ProcessError::NoPlan)?;
    let start = if settings.resume {
        Some(load_checkpoint(checkpoint, &plan)?)
    } else {
        spec.load_initial_values(Some(&plan))?.into_iter().nth(k)
    };
    let learner = learner_for(spec, context.run, k, start.as_ref());
    let keeper = PlanKeeper::new(
        Arc::clone(&plan),
        &registry(&sim_config),
        learner,
        sim_config,
        config.thresholds,
    )
    .map_err(ProcessError::PlanCannotRun)?;
    Ok(Brain::Plan {
        keeper: Box::new(keeper),
        plan,
        algorithm: spec.algorithm.name(),
    })
}

/// What the agent tracks while it runs.
struct Agent {
    context: RunContext,
    settings: AgentSettings,
    ports: AgentPorts,
    brain: Brain,
    pacemaker: Pacemaker,
    compute: Latency,
    checkpoint: PathBuf,
    saver: BackgroundSave,
    /// No episode event or ping has come since the agent started: it keeps
    /// saying it is ready (the simulator may have subscribed after the first time).
    announcing: bool,
    /// The episode in progress (0: none) and how it is run.
    episode: u64,
    /// The last episode begun (none since the agent or the simulator
    /// started): a begin is taken for the next episode only.
    last_begun: Option<u64>,
    start: EpisodeStart,
    learning_episodes: u64,
    /// Real time: the cycle's length.
    cycle: Option<Duration>,
    /// Real time: when the next snapshot and the next floor ping are due.
    expected: [Option<Instant>; 2],
    /// A snapshot of an episode whose begin has not come yet.
    early: Option<(SnapshotMeta, PlayerView)>,
}

impl Agent {
    fn count(&mut self, why: Rejection) {
        self.pacemaker.pulse.rejected.count(why);
    }

    /// Hands the checkpoint (and the compute histogram so far) to the writer
    /// thread; a failure is reported and counted there, the previous
    /// checkpoint stays.
    fn save(&mut self) {
        let mut files = Vec::new();
        match self.compute.to_bytes() {
            Ok(bytes) => files.push((histogram_file(&self.context.work_dir, self.compute.name()), bytes)),
            Err(e) => report!("error: {e}"),
        }
        self.saver.submit(Checkpoint {
            values: self.brain.values().map(|values| (self.checkpoint.clone(), values)),
            files,
        });
    }

    /// Checkpoints and waits until it is written.
    fn save_now(&mut self) {
        self.save();
        self.saver.flush();
    }

    /// Handles the supervisor's commands; returns true on stop.
    fn control(&mut self) -> Result<bool, ProcessError> {
        let (me, run_id) = (Role::Keeper(self.settings.keeper), self.context.run_id);
        while let Some(order) = receive(&self.ports.control, |m| read_control(m, me, run_id))? {
            match order {
                Ok(Some(Order::Stop)) => return Ok(true),
                Ok(Some(Order::Checkpoint)) => self.save_now(),
                // The new simulator starts from the last episode boundary: the
                // episode in progress is dropped (the learner is not told its end).
                Ok(Some(Order::SimulatorRestarted)) => {
                    self.episode = 0;
                    self.last_begun = None;
                    self.announcing = true;
                }
                Ok(Some(Order::KeeperLost { .. }) | None) => {}
                Err(why) => self.count(why),
            }
        }
        Ok(false)
    }

    fn is_next(&self, episode: u64) -> bool {
        begins_next(self.last_begun, self.context.clock, episode)
    }

    /// Handles episode events; returns whether one was handled.
    fn episode_events(&mut self) -> Result<bool, ProcessError> {
        let run_id = self.context.run_id;
        let mut handled = false;
        while let Some(event) = receive(&self.ports.episode, |m| read_episode_event(m, run_id))? {
            handled = true;
            match event {
                Ok((episode, EpisodeNews::Begin(start))) if self.is_next(episode) => {
                    self.last_begun = Some(episode);
                    self.announcing = false;
                    self.pacemaker.pulse.state = ProcessState::Running;
                    self.brain.begin_episode(start);
                    self.episode = episode;
                    self.start = start;
                }
                Ok((episode, EpisodeNews::End { .. })) if episode == self.episode => {
                    let exploratory = self.brain.end_episode();
                    self.episode = 0;
                    if self.start.learning() {
                        self.learning_episodes += 1;
                        let every = self.settings.checkpoint_every;
                        if every > 0 && self.learning_episodes.is_multiple_of(every) && self.saver.due() {
                            self.save();
                        }
                    }
                    self.pacemaker.pulse.episodes += 1;
                    let report = agent_report(AgentNews::Ended { episode, exploratory }, self.settings.keeper, run_id);
                    self.ports.report.send(report)?;
                }
                // The episode is discarded: the learner is not told its end,
                // and the next begin starts afresh.
                Ok((episode, EpisodeNews::Abort { .. })) if episode == self.episode => self.episode = 0,
                Ok(_) => self.count(Rejection::Sequence),
                Err(why) => self.count(why),
            }
        }
        Ok(handled)
    }

    /// Acts on the newest snapshot of the current episode; returns whether
    /// any snapshot was read. In real time an agent that fell behind (it was
    /// stopped, or starved of a core) skips to the newest snapshot, crediting
    /// the reward of the skipped ones, and acts once.
    fn snapshots(&mut self) -> Result<bool, ProcessError> {
        let (k, run_id) = (self.settings.keeper, self.context.run_id);
        let mut pending: Option<(SnapshotMeta, PlayerView, f64)> = match self.early.take() {
            Some((meta, view)) if meta.episode == self.episode => Some((meta, view, meta.reward)),
            Some(early) if early.0.episode > self.episode => {
                self.early = Some(early); // its episode's begin is still on its way
                None
            }
            Some(_) => {
                self.count(Rejection::Sequence);
                None
            }
            None => None,
        };
        let mut read = false;
        while let Some(reading) = receive(&self.ports.snapshot, |m| read_snapshot(m, k, run_id))? {
            read = true;
            let (meta, view) = match reading {
                Ok(r) => r,
                Err(why) => {
                    self.count(why);
                    continue;
                }
            };
            if meta.episode != self.episode {
                // Its episode's begin (and the previous one's end) may still be queued.
                if let Some((m, v, reward)) = pending.take() {
                    self.act(m, v, reward)?;
                }
                self.episode_events()?;
                if meta.episode > self.episode {
                    // Over a link between hosts, an episode's first snapshot
                    // can come before its begin: it waits for it.
                    if self.early.replace((meta, view)).is_some() {
                        self.count(Rejection::Sequence);
                    }
                    continue;
                }
                if meta.episode != self.episode {
                    self.count(Rejection::Sequence);
                    continue;
                }
            }
            let reward = pending.map_or(0.0, |(_, _, r)| r) + meta.reward;
            pending = Some((meta, view, reward));
        }
        if let Some((meta, view, reward)) = pending {
            self.act(meta, view, reward)?;
        }
        Ok(read)
    }

    /// Real time: how long until the agent should poll for a message it
    /// expects (zero: now), or none if it expects none.
    fn until_expected(&mut self) -> Option<Duration> {
        self.cycle?;
        let now = Instant::now();
        for due in &mut self.expected {
            if due.is_some_and(|t| now > t + EXPECT_LATE) {
                *due = None;
            }
        }
        self.expected
            .iter()
            .flatten()
            .map(|&t| t.checked_sub(EXPECT_EARLY).unwrap_or(t).saturating_duration_since(now))
            .min()
    }

    /// Thinks about `view` (crediting `reward`) and sends the command.
    fn act(&mut self, meta: SnapshotMeta, view: PlayerView, reward: f64) -> Result<(), ProcessError> {
        let started = Instant::now();
        self.expected[0] = self.cycle.map(|c| started + c);
        let (command, idle) = self.brain.act(view, reward)?;
        self.compute.record(started.elapsed());
        let reading = CommandReading {
            episode: meta.episode,
            cycle_seq: meta.cycle_seq,
            command,
            idle,
        };
        self.ports
            .command
            .send(command_message(&reading, self.settings.keeper, self.context.run_id))?;
        self.pacemaker.pulse.cycles += 1;
        Ok(())
    }

    /// Answers the floor measurement's pings at once (keeper 0), until the
    /// simulator's end marker or a second of silence; returns whether a ping came.
    fn floor(&mut self) -> Result<bool, ProcessError> {
        let run_id = self.context.run_id;
        let ping = |ports: &AgentPorts| {
            receive(&ports.floor_ping, |m| {
                (m.header.run_id == run_id).then_some(m.cycle_seq)
            })
        };
        let Some(first) = ping(&self.ports)? else {
            return Ok(false);
        };
        self.announcing = false;
        let mut next = Some(first);
        let mut last = Instant::now();
        let mut idle = Idle::new(self.context.wait);
        loop {
            match next.take() {
                Some(Some(FLOOR_END)) => return Ok(true),
                Some(Some(sequence)) => {
                    self.ports.floor_pong.send(floor_pong(run_id, sequence))?;
                    last = Instant::now();
                    self.expected[1] = self.cycle.map(|c| last + c);
                    idle = Idle::new(self.context.wait);
                    // Beats however fast the pings come (after the echo: not in the round trip).
                    self.pacemaker.tick(&self.ports.heartbeat)?;
                }
                Some(None) => self.count(Rejection::Run),
                None => {
                    if last.elapsed() > Duration::from_secs(1) {
                        return Ok(true);
                    }
                    self.pacemaker.tick(&self.ports.heartbeat)?;
                    idle.pause(&self.ports.wake, MAX_BLOCK)?;
                }
            }
            next = ping(&self.ports)?;
        }
    }

    /// Says this process is ready for an episode.
    fn announce(&mut self) -> Result<(), ProcessError> {
        let ready = AgentNews::Ready {
            pid: std::process::id(),
        };
        self.ports
            .report
            .send(agent_report(ready, self.settings.keeper, self.context.run_id))?;
        Ok(())
    }

    /// Serves the run until the supervisor says stop; checkpoints at the end.
    fn serve(&mut self) -> Result<(), ProcessError> {
        let mut idle = Idle::new(self.context.wait);
        let mut announced = Instant::now();
        loop {
            self.pacemaker.pulse.checkpoints = self.saver.written();
            self.pacemaker.pulse.checkpoint_failures = self.saver.failed();
            self.pacemaker.tick(&self.ports.heartbeat)?;
            if self.announcing && announced.elapsed() >= HEARTBEAT_EVERY {
                self.announce()?;
                announced = Instant::now();
            }
            if self.control()? {
                break;
            }
            let mut busy = self.episode_events()?;
            busy |= self.snapshots()?;
            if self.settings.keeper == 0 {
                busy |= self.floor()?;
            }
            if busy {
                idle = Idle::new(self.context.wait);
            } else {
                match self.until_expected() {
                    Some(Duration::ZERO) => std::thread::yield_now(),
                    // A timed wait on the listener may overshoot: the last
                    // stretch is slept precisely (nothing is expected in it).
                    Some(wait) if wait <= TIMED_WAIT_SLACK => std::thread::sleep(wait),
                    Some(wait) => idle.pause(&self.ports.wake, wait - TIMED_WAIT_SLACK)?,
                    None => idle.pause(&self.ports.wake, MAX_BLOCK)?,
                }
            }
        }
        self.pacemaker.pulse.state = ProcessState::Stopping;
        self.pacemaker.beat(&self.ports.heartbeat)?;
        self.save_now();
        Ok(())
    }
}

/// Runs keeper `settings.keeper`'s agent in `context`'s run until the
/// supervisor stops it. A fresh start checkpoints its starting values at
/// once, so that a restart always has a checkpoint to resume from.
pub fn run(context: &RunContext, settings: &AgentSettings) -> Result<(), ProcessError> {
    let spec = context.load_spec()?;
    let config = keepaway_config(&spec)?;
    let k = settings.keeper;
    if k >= learnpnp::keepaway_sim::world::NUM_KEEPERS {
        return Err(ProcessError::NoKeeper(k + 1));
    }
    let checkpoint = context.work_dir.join(checkpoint_name(k));
    let brain = brain(&spec, &config, context, settings, &checkpoint)?;
    let namespace = context.namespace()?;
    let node = node(&namespace, &format!("keeper-{k}"))?;
    let ports = AgentPorts::open(&node, k, context.wait)?;
    let mut agent = Agent {
        context: context.clone(),
        settings: settings.clone(),
        ports,
        brain,
        pacemaker: Pacemaker::new(Role::Keeper(k), context.run_id),
        compute: Latency::new(compute_histogram(k)),
        checkpoint,
        saver: BackgroundSave::start(CHECKPOINT_SPACING).map_err(ProcessError::Writer)?,
        announcing: true,
        episode: 0,
        last_begun: None,
        start: EpisodeStart::LEARN,
        learning_episodes: 0,
        cycle: (context.clock == Clock::Realtime)
            .then(|| Duration::from_secs_f64(config.simulator().server.cycle_seconds)),
        expected: [None; 2],
        early: None,
    };
    if settings.resume {
        // What the learner holds now, for the supervisor to compare with the
        // checkpoint it resumed from.
        if let Some(values) = agent.brain.values() {
            let path = resumed_file(&context.work_dir, k, std::process::id());
            persist::save(&path, &values)?;
        }
    } else {
        agent.save_now();
    }
    agent.announce()?;
    agent.pacemaker.pulse.state = ProcessState::Ready;
    agent.pacemaker.beat(&agent.ports.heartbeat)?;
    agent.serve()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_begin_is_taken_for_the_next_episode_only() {
        assert!(
            begins_next(None, Clock::Lockstep, 17),
            "a fresh agent joins at any episode"
        );
        assert!(!begins_next(None, Clock::Lockstep, 0));
        assert!(begins_next(Some(4), Clock::Lockstep, 5));
        assert!(!begins_next(Some(4), Clock::Lockstep, 4), "replayed");
        assert!(!begins_next(Some(4), Clock::Lockstep, 1), "an old episode");
        assert!(!begins_next(Some(4), Clock::Lockstep, 6), "one skipped in lock-step");
        assert!(
            begins_next(Some(4), Clock::Realtime, 6),
            "in real time a lost begin is skipped"
        );
        assert!(!begins_next(Some(4), Clock::Realtime, 3));
        assert!(!begins_next(Some(u64::MAX), Clock::Lockstep, u64::MAX));
    }
}
