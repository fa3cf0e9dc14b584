//! An agent process: one keeper. A learning keeper runs its plan with its
//! learner and executor (the in-process [`PlanKeeper`](learnpnp::domains::keepaway::PlanKeeper)); the others follow
//! the mode's fixed policy. Each cycle it takes its snapshot, credits the
//! reward, thinks until an action issues the cycle's command, and sends it.
//! A learning keeper checkpoints its values every N learning episodes and on
//! the supervisor's request, atomically, in the `persist` format. In real
//! time it sleeps between cycles and is polling again shortly before its next
//! snapshot is due ([`EXPECT_EARLY`](crate::multiprocess::agent::keeper::EXPECT_EARLY)).

use learnpnp::named::Named;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::ipc::convert::{Rejection, agent_report, command_message, read_episode_event, read_snapshot};
use crate::ipc::protocol::{AgentNews, CommandReading, EpisodeNews, Order, ProcessState, Role, Roster, SnapshotMeta};
use crate::ipc::services::{AgentPorts, node, receive};
use crate::ipc::wait::{Idle, MAX_BLOCK, TIMED_WAIT_SLACK};
use crate::multiprocess::agent::chassis::{Chassis, load_checkpoint};
use crate::multiprocess::agent::world::agent_compute_histogram;
use crate::multiprocess::host::simulator::{FLOOR_END, floor_pong, keepaway_config};
use crate::multiprocess::{Clock, HEARTBEAT_EVERY, ProcessError, RunContext};
use learnpnp::domains::keepaway::{KeepawayDomainConfig, PlanKeeper, RunSeeds, registry};
use learnpnp::experiment::runner::{learner_for, task_rng};
use learnpnp::experiment::spec::ExperimentSpec;
use learnpnp::learning::EpisodeStart;
use learnpnp::learning::persist::SavedValues;
use learnpnp::plan::Plan;
use learnpnp_keepaway::command::Command;
use learnpnp_keepaway::keeper::{KeeperMemory, keeper_command};
use learnpnp_keepaway::params::KeepawayConfig;
use learnpnp_keepaway::policies::BaselinePolicy;
use learnpnp_keepaway::view::PlayerView;

/// Real time: how long before a message is due (a snapshot, or agent 0's
/// floor ping, one cycle after the previous one) the agent stops sleeping and
/// polls, so that the message finds it awake rather than waiting for a
/// wake-up (on a virtual machine a sleeping core can take milliseconds to wake).
pub const EXPECT_EARLY: Duration = Duration::from_millis(1);

/// Real time: how long after a message was due the agent keeps polling for it
/// before it goes back to sleep (the first snapshot of an episode comes after
/// the episode's begin, later than one cycle after the last one).
pub(crate) const EXPECT_LATE: Duration = Duration::from_millis(2);

/// The name of keeper `k`'s compute-time histogram.
pub fn compute_histogram(k: usize) -> String {
    format!("compute-keeper{}", k + 1)
}

/// The name of agent `k`'s compute-time histogram in a run of `roster`
/// (a keeper's, or a world's agent's).
pub(crate) fn roster_compute_histogram(roster: Roster, k: usize) -> String {
    match roster {
        Roster::Keepaway => compute_histogram(k),
        Roster::World { .. } => agent_compute_histogram(k),
    }
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

/// Builds keeper `k`'s brain for run `context.run` of `spec` (its learner
/// watched by the run's view, if it has one).
fn brain(
    spec: &ExperimentSpec,
    config: &KeepawayDomainConfig,
    context: &RunContext,
    settings: &AgentSettings,
    chassis: &Chassis,
) -> Result<Brain, ProcessError> {
    let checkpoint = &chassis.checkpoint;
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
    let learner = chassis.watched(learner_for(spec, context.run, k, start.as_ref()), &plan);
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
    chassis: Chassis,
    ports: AgentPorts,
    brain: Brain,
    /// No episode event or ping has come since the agent started: it keeps
    /// saying it is ready (the simulator may have subscribed after the first time).
    announcing: bool,
    /// The episode in progress (0: none) and how it is run.
    episode: u64,
    /// The last episode begun (none since the agent or the simulator
    /// started): a begin is taken for the next episode only.
    last_begun: Option<u64>,
    start: EpisodeStart,
    /// Real time: the cycle's length.
    cycle: Option<Duration>,
    /// Real time: when the next snapshot and the next floor ping are due.
    expected: [Option<Instant>; 2],
    /// A snapshot of an episode whose begin has not come yet.
    early: Option<(SnapshotMeta, PlayerView)>,
}

impl Agent {
    fn count(&mut self, why: Rejection) {
        self.chassis.count(why);
    }

    /// Hands the checkpoint (and the compute histogram so far) to the writer
    /// thread; a failure is reported and counted there, the previous
    /// checkpoint stays.
    fn save(&mut self) {
        self.chassis.save(self.brain.values(), &[]);
    }

    /// Checkpoints and waits until it is written.
    fn save_now(&mut self) {
        self.save();
        self.chassis.flush();
    }

    /// Handles the supervisor's commands; returns true on stop.
    fn control(&mut self) -> Result<bool, ProcessError> {
        while let Some(order) = self.chassis.next_order(&self.ports.control, |_| {})? {
            match order {
                Order::Stop => return Ok(true),
                Order::Checkpoint => self.save_now(),
                // The new simulator starts from the last episode boundary: the
                // episode in progress is dropped (the learner is not told its end).
                Order::SimulatorRestarted => {
                    self.episode = 0;
                    self.last_begun = None;
                    self.announcing = true;
                }
                Order::KeeperLost { .. } => {}
            }
        }
        Ok(false)
    }

    fn is_next(&self, episode: u64) -> bool {
        begins_next(self.last_begun, self.chassis.context.clock, episode)
    }

    /// Handles episode events; returns whether one was handled.
    fn episode_events(&mut self) -> Result<bool, ProcessError> {
        let run_id = self.chassis.context.run_id;
        let mut handled = false;
        while let Some(event) = receive(&self.ports.episode, |m| read_episode_event(m, run_id))? {
            handled = true;
            match event {
                Ok((episode, EpisodeNews::Begin(start))) if self.is_next(episode) => {
                    self.last_begun = Some(episode);
                    self.announcing = false;
                    self.chassis.pacemaker.pulse.state = ProcessState::Running;
                    self.brain.begin_episode(start);
                    self.episode = episode;
                    self.start = start;
                }
                Ok((episode, EpisodeNews::End { .. })) if episode == self.episode => {
                    let exploratory = self.brain.end_episode();
                    self.episode = 0;
                    if self.start.learning() {
                        self.chassis.learning_episodes += 1;
                        if self.chassis.checkpoint_due() {
                            self.save();
                        }
                    }
                    self.chassis.pacemaker.pulse.episodes += 1;
                    let report = agent_report(AgentNews::Ended { episode, exploratory }, self.chassis.index, run_id);
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
        let (k, run_id) = (self.chassis.index, self.chassis.context.run_id);
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
        self.chassis.compute.record(started.elapsed());
        let reading = CommandReading {
            episode: meta.episode,
            cycle_seq: meta.cycle_seq,
            command,
            idle,
        };
        self.ports.command.send(command_message(
            &reading,
            self.chassis.index,
            self.chassis.context.run_id,
        ))?;
        self.chassis.pacemaker.pulse.cycles += 1;
        Ok(())
    }

    /// Answers the floor measurement's pings at once (keeper 0), until the
    /// simulator's end marker or a second of silence; returns whether a ping came.
    fn floor(&mut self) -> Result<bool, ProcessError> {
        let run_id = self.chassis.context.run_id;
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
        let mut idle = Idle::new(self.chassis.context.wait);
        loop {
            match next.take() {
                Some(Some(FLOOR_END)) => return Ok(true),
                Some(Some(sequence)) => {
                    self.ports.floor_pong.send(floor_pong(run_id, sequence))?;
                    last = Instant::now();
                    self.expected[1] = self.cycle.map(|c| last + c);
                    idle = Idle::new(self.chassis.context.wait);
                    // Beats however fast the pings come (after the echo: not in the round trip).
                    self.chassis.pacemaker.tick(&self.ports.heartbeat)?;
                }
                Some(None) => self.count(Rejection::Run),
                None => {
                    if last.elapsed() > Duration::from_secs(1) {
                        return Ok(true);
                    }
                    self.chassis.pacemaker.tick(&self.ports.heartbeat)?;
                    idle.pause(&self.ports.wake, MAX_BLOCK)?;
                }
            }
            next = ping(&self.ports)?;
        }
    }

    /// Serves the run until the supervisor says stop; checkpoints at the end.
    fn serve(&mut self) -> Result<(), ProcessError> {
        let mut idle = Idle::new(self.chassis.context.wait);
        let mut announced = Instant::now();
        loop {
            self.chassis.tick(&self.ports.heartbeat, 0)?;
            if self.announcing && announced.elapsed() >= HEARTBEAT_EVERY {
                self.chassis.announce(&self.ports.report)?;
                announced = Instant::now();
            }
            if self.control()? {
                break;
            }
            let mut busy = self.episode_events()?;
            busy |= self.snapshots()?;
            if self.chassis.index == 0 {
                busy |= self.floor()?;
            }
            if busy {
                idle = Idle::new(self.chassis.context.wait);
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
        self.chassis.beat(&self.ports.heartbeat, ProcessState::Stopping)?;
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
    if k >= learnpnp_keepaway::world::NUM_KEEPERS {
        return Err(ProcessError::NoKeeper(k + 1));
    }
    let chassis = Chassis::new(
        context,
        Role::Keeper(k),
        k,
        settings.checkpoint_every,
        compute_histogram(k),
    )?;
    let brain = brain(&spec, &config, context, settings, &chassis)?;
    let namespace = context.namespace()?;
    let node = node(&namespace, &format!("keeper-{k}"))?;
    let ports = AgentPorts::open(&node, k, context.wait)?;
    let mut agent = Agent {
        chassis,
        ports,
        brain,
        announcing: true,
        episode: 0,
        last_begun: None,
        start: EpisodeStart::LEARN,
        cycle: (context.clock == Clock::Realtime)
            .then(|| Duration::from_secs_f64(config.simulator().server.cycle_seconds)),
        expected: [None; 2],
        early: None,
    };
    if settings.resume {
        // What the learner holds now, for the supervisor to compare with the
        // checkpoint it resumed from.
        if let Some(values) = agent.brain.values() {
            agent.chassis.record_resumed(&values)?;
        }
    } else {
        agent.save_now();
    }
    agent.chassis.announce(&agent.ports.report)?;
    agent.chassis.beat(&agent.ports.heartbeat, ProcessState::Ready)?;
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
