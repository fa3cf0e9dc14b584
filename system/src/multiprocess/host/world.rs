//! A world written in Rust, served as the world process of a run: the
//! world's side of the protocol of `shm_layouts/README.md` ("A world in its
//! own process"), the same the Python world kit (`learnpnp.world`) speaks.
//! A [`ServedWorld`](crate::multiprocess::host::world::ServedWorld) says what holds and steps; [`serve`](crate::multiprocess::host::world::serve) does the rest:
//! heartbeats, the vocabulary, waiting for the agents, snapshots and
//! commands (lock-step, or real time on the world's own clock), the
//! supervisor's orders, and refusing what does not read.

use std::time::{Duration, Instant};

use iceoryx2::port::listener::Listener;
use shm_layouts::MAX_FLUENTS;

use serde::Serialize;

use crate::ipc::convert::{Rejection, Rejections};
use crate::ipc::namespace::Namespace;
use crate::ipc::protocol::{ProcessState, Role};
use crate::ipc::services::{Ipc, IpcError, WorldPorts, node, receive, send};
use crate::ipc::wait::{Idle, MAX_BLOCK, WaitStrategy};
use crate::ipc::world::{
    ATOM_WORDS, ActionStatus, EpisodeStatus, Vocabulary, VocabularyError, WorldView, monotonic_ns, read_world_command,
    world_snapshot,
};
use crate::multiprocess::host::cadence::{Cadence, SLEEP_SLICE, sleep_until};
use crate::multiprocess::host::chassis::{self, HostChassis, Readiness};
use crate::multiprocess::supervisor::launch::world_env;
use crate::multiprocess::{Clock, HEARTBEAT_EVERY};
use learnpnp::named::Named;

/// What one agent sees: the atoms that hold (by index) and the fluents.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Observation {
    /// Indices of the atoms that hold.
    pub atoms: Vec<usize>,
    /// The fluents' values.
    pub fluents: Vec<f64>,
}

/// What a step did to one agent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepResult {
    /// Its reward.
    pub reward: f64,
    /// What became of its action.
    pub action: ActionStatus,
}

/// A world in Rust, for [`serve`]. A reset or step that waits on something
/// outside the world (a robot's answer) keeps the host's house while it
/// waits ([`Housekeeping`]).
pub trait ServedWorld {
    /// Its atoms, fluents and actions (the agents are the run's).
    fn vocabulary(&self) -> Vocabulary;
    /// Begins an episode; the first one is given the run's seed.
    fn reset(&mut self, seed: Option<u64>, house: &mut Housekeeping<'_>);
    /// What agent `agent` sees now.
    fn observe(&self, agent: usize) -> Observation;
    /// Steps the world with each agent's action (`None`: the agent idles).
    fn step(&mut self, actions: &[Option<usize>], house: &mut Housekeeping<'_>) -> Vec<StepResult>;
    /// Whether the episode reached a terminal state.
    fn terminated(&self) -> bool;
    /// Whether the episode is cut short (a step limit).
    fn truncated(&self) -> bool;
}

/// The host's housekeeping (the heartbeat, the supervisor's orders, the
/// agents' reports), lent to a world's reset and step: a world whose reset
/// or step waits on something outside it (a robot's answer) waits in
/// slices of at most [`Housekeeping::EVERY`] and calls
/// [`keep`](Housekeeping::keep) between them, so it heartbeats on the wall
/// clock however long the robot takes. A world blocked without keeping
/// house (a true hang) sends no heartbeat, and the supervisor kills it.
pub struct Housekeeping<'h> {
    /// The host's housekeeping: false once the run stops.
    keep: Option<&'h mut dyn FnMut() -> bool>,
}

impl<'h> Housekeeping<'h> {
    /// The longest a waiting world goes between two calls of
    /// [`keep`](Housekeeping::keep): half a heartbeat interval.
    pub const EVERY: Duration = SLEEP_SLICE;

    /// Housekeeping by `keep` (the host's; in a world's tests, a stand-in):
    /// false once the run stops.
    pub fn new(keep: &'h mut dyn FnMut() -> bool) -> Self {
        Housekeeping { keep: Some(keep) }
    }

    /// No host to keep: a world driven outside [`serve`] (its own tests).
    pub fn none() -> Self {
        Housekeeping { keep: None }
    }

    /// Keeps the host's house now. False once the run stops (the
    /// supervisor said stop, or the host failed): a wait may end now.
    pub fn keep(&mut self) -> bool {
        self.keep.as_mut().is_none_or(|keep| keep())
    }
}

/// Why a world cannot be served.
#[derive(Debug, thiserror::Error)]
pub enum WorldHostError {
    /// A variable of the run is missing or malformed.
    #[error("environment variable {name}: {problem}")]
    Environment {
        /// The variable.
        name: &'static str,
        /// What is wrong.
        problem: String,
    },
    /// The vocabulary does not fit the layouts.
    #[error("the world's vocabulary: {0}")]
    Vocabulary(#[from] VocabularyError),
    /// Shared memory failed.
    #[error(transparent)]
    Ipc(#[from] IpcError),
    /// The namespace is unusable.
    #[error(transparent)]
    Namespace(#[from] crate::ipc::namespace::NamespaceError),
}

/// What a served world did, for its log or report.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Served {
    /// Snapshots published (every cycle, lock-step or real time).
    pub snapshots: u64,
    /// Real time: cycles ended on the world's clock.
    pub realtime_cycles: u64,
    /// Real time: cycles whose work (stepping the world, publishing) ran
    /// past their deadline (counted; the next cycle kept the grid).
    pub late_cycles: u64,
    /// Real time: seconds on the world's clock (from the agents' readiness).
    pub realtime_seconds: f64,
}

impl Served {
    /// Real time: the cycles kept a second (none in lock-step).
    pub fn rate(&self) -> Option<f64> {
        (self.realtime_seconds > 0.0).then(|| self.realtime_cycles as f64 / self.realtime_seconds)
    }
}

/// How often a world awaiting commands looks at the supervisor's orders.
const HOUSEKEEPING_EVERY: Duration = Duration::from_millis(1);

/// The run as the world process's environment gives it.
#[derive(Debug, Clone)]
pub struct WorldRun {
    /// The run's namespace.
    pub namespace: Namespace,
    /// The run id.
    pub run_id: u64,
    /// The run's index in the experiment (0-based).
    pub run: usize,
    /// How many agents.
    pub agents: usize,
    /// Lock-step or real time.
    pub clock: Clock,
    /// Real time: the cycle.
    pub period: Duration,
    /// How processes wait.
    pub wait: WaitStrategy,
    /// The seed of the first reset.
    pub seed: u64,
}

impl WorldRun {
    /// Reads the run from the environment the supervisor gives a world.
    pub fn from_env() -> Result<Self, WorldHostError> {
        fn var(name: &'static str) -> Result<String, WorldHostError> {
            std::env::var(name).map_err(|_| WorldHostError::Environment {
                name,
                problem: "not set (a world is started by learnpnp-supervisor --world-cmd)".into(),
            })
        }
        fn number<T: std::str::FromStr>(name: &'static str) -> Result<T, WorldHostError> {
            let text = var(name)?;
            text.parse().map_err(|_| WorldHostError::Environment {
                name,
                problem: format!("'{text}' is not a number"),
            })
        }
        fn named<T: Named>(name: &'static str) -> Result<T, WorldHostError> {
            let text = var(name)?;
            T::from_name(&text).map_err(|e| WorldHostError::Environment {
                name,
                problem: e.to_string(),
            })
        }
        let root = var(world_env::ROOT)?;
        let base = std::path::Path::new(root.trim_end_matches('/'))
            .parent()
            .map(std::path::Path::to_path_buf)
            .unwrap_or_default();
        Ok(WorldRun {
            namespace: Namespace::at(&base, &var(world_env::PREFIX)?)?,
            run_id: number(world_env::RUN_ID)?,
            run: number(world_env::RUN)?,
            agents: number(world_env::AGENTS)?,
            clock: named(world_env::CLOCK)?,
            period: Duration::from_millis(number(world_env::PERIOD_MS)?),
            wait: named(world_env::WAIT)?,
            seed: number(world_env::SEED)?,
        })
    }
}

/// The world's side of the run (the world itself is lent to each episode,
/// so that its waits can keep the host's house).
struct Host {
    run: WorldRun,
    ports: WorldPorts,
    /// The heartbeat, the orders, the agents' readiness and losses (since
    /// they were last all ready).
    chassis: HostChassis,
    vocabulary: Vocabulary,
    actions: usize,
    episode: u64,
    cycle: u64,
    step: u32,
    /// Each agent's last command taken: its cycle and when it was read.
    answered: Vec<Option<(u64, u64)>>,
    first_reset: bool,
    /// When the host last kept house.
    housekept: Instant,
    /// When the vocabulary was last announced (in the wait for the agents).
    announced: Option<Instant>,
    /// Real time: the cycle on the world's clock since the agents were last ready.
    cadence: Option<Cadence>,
    /// What was served (real time: the cadences before the current one).
    served: Served,
    /// The process that started the world.
    parent: libc::pid_t,
}

impl chassis::Host for Host {
    type Error = WorldHostError;

    fn chassis(&self) -> &HostChassis {
        &self.chassis
    }

    fn await_round(&mut self) -> Result<(), WorldHostError> {
        self.announce()?;
        self.housekeeping()
    }

    fn wake(&self) -> &Listener<Ipc> {
        &self.ports.host.wake
    }

    fn failure(e: IpcError) -> WorldHostError {
        e.into()
    }
}

/// Each agent's answer in a cycle: `None` if it missed the cycle (real
/// time), else the action it named (`None`: no action).
type Answers = Vec<Option<Option<usize>>>;

/// Why an episode's loop ended early.
enum Interruption {
    /// The supervisor said stop.
    Stop,
    /// An agent was lost: the episode is discarded.
    Lost,
}

impl Host {
    fn count(&mut self, why: Rejection) {
        self.chassis.pacemaker.pulse.rejected.count(why);
    }

    /// Heartbeat, the supervisor's orders, the agents' reports.
    fn housekeeping(&mut self) -> Result<(), WorldHostError> {
        self.housekept = Instant::now();
        let pulse = &mut self.chassis.pacemaker.pulse;
        pulse.cycles = self.cycle;
        pulse.late_cycles = self.served.late_cycles + self.cadence.as_ref().map_or(0, Cadence::late);
        let mut refused = Rejections::default();
        let beat = self
            .chassis
            .keep(&self.ports.host.heartbeat, &self.ports.host.control, &mut refused)?;
        // SAFETY: getppid has no effects.
        if beat && unsafe { libc::getppid() } != self.parent {
            // The process that started the world (the supervisor, or the
            // shell it ran the command with) is gone: so is the run (looked
            // at with each heartbeat).
            self.chassis.stop();
        }
        // The agents' news other than their readiness is not the world's.
        self.chassis
            .read_reports(&self.ports.host.reports, &mut refused, |_, _| Ok(()))?;
        self.chassis.pacemaker.pulse.rejected.add(&refused);
        Ok(())
    }

    /// Runs `f` with the host's housekeeping lent (a world's reset or
    /// step): what `f` made, or the first failure of the housekeeping.
    fn keeping<T>(&mut self, f: impl FnOnce(&mut Housekeeping<'_>) -> T) -> Result<T, WorldHostError> {
        let mut failure = None;
        let mut keep = || match self.housekeeping() {
            Ok(()) => !self.chassis.stopped(),
            Err(e) => {
                failure.get_or_insert(e);
                false
            }
        };
        let made = f(&mut Housekeeping::new(&mut keep));
        failure.map_or(Ok(made), Err)
    }

    /// Announces the vocabulary until every agent is ready; false on stop.
    fn await_agents(&mut self) -> Result<bool, WorldHostError> {
        self.chassis.set_state(ProcessState::Ready);
        self.announced = None;
        match chassis::wait_ready(self, None)? {
            Readiness::Ready => {
                self.chassis.clear_lost();
                self.chassis.set_state(ProcessState::Running);
                self.end_cadence();
                self.cadence = (self.run.clock == Clock::Realtime).then(|| Cadence::new(self.run.period));
                Ok(true)
            }
            // Without a timeout a wait ends ready or stopped.
            Readiness::Stopped | Readiness::TimedOut(_) => Ok(false),
        }
    }

    /// Announces the vocabulary, once every heartbeat interval while the
    /// agents are awaited.
    fn announce(&mut self) -> Result<(), WorldHostError> {
        if self.announced.is_none_or(|t| t.elapsed() >= HEARTBEAT_EVERY) {
            for part in self.vocabulary.parts(self.run.run_id) {
                send(&self.ports.vocabulary, part)?;
            }
            self.announced = Some(Instant::now());
        }
        Ok(())
    }

    /// Publishes each agent's snapshot of the world now (the end of a
    /// cycle's work).
    fn publish(
        &mut self,
        world: &impl ServedWorld,
        status: EpisodeStatus,
        results: &[StepResult],
    ) -> Result<(), WorldHostError> {
        self.cycle += 1;
        for a in 0..self.run.agents {
            let seen = world.observe(a);
            let mut atoms = [0u64; ATOM_WORDS];
            for &i in &seen.atoms {
                atoms[i / 64] |= 1 << (i % 64);
            }
            let mut fluents = [0.0; MAX_FLUENTS];
            for (slot, value) in fluents.iter_mut().zip(&seen.fluents) {
                *slot = *value;
            }
            let (reward, action_status) = results
                .get(a)
                .map_or((0.0, ActionStatus::None), |r| (r.reward, r.action));
            let view = WorldView {
                episode: self.episode,
                cycle: self.cycle,
                sent_ns: monotonic_ns(),
                answered: self.answered[a],
                reward,
                step: self.step,
                episode_status: status,
                action_status,
                atoms,
                fluents,
            };
            self.ports.host.snapshots[a].send(world_snapshot(&view, a, self.run.run_id))?;
        }
        // Real time: the cycle's work is done.
        if let Some(cadence) = &mut self.cadence {
            cadence.worked();
        }
        Ok(())
    }

    /// Real time: adds the cadence under way to what was served.
    fn end_cadence(&mut self) {
        if let Some(cadence) = self.cadence.take() {
            self.served.realtime_cycles += cadence.cycles();
            self.served.late_cycles += cadence.late();
            self.served.realtime_seconds += cadence.seconds();
        }
    }

    /// Real time: sleeps out the cycle, keeping house (the heartbeat, the
    /// supervisor's orders), and begins the next on the grid.
    fn end_cycle(&mut self) -> Result<(), WorldHostError> {
        let Some(deadline) = self.cadence.as_ref().map(Cadence::deadline) else {
            return Ok(());
        };
        sleep_until(deadline, || self.housekeeping())?;
        if let Some(cadence) = &mut self.cadence {
            cadence.next();
        }
        Ok(())
    }

    /// Tells every agent the episode is discarded.
    fn abort(&mut self, world: &impl ServedWorld) -> Result<(), WorldHostError> {
        self.publish(world, EpisodeStatus::Aborted, &[])?;
        self.chassis.pacemaker.pulse.aborted_episodes += 1;
        Ok(())
    }

    /// Collects each agent's command for the current cycle: lock-step until
    /// all are in, real time until the next cycle is due (`deadline`; an
    /// agent whose command is not in by then is `None`).
    fn collect(&mut self, deadline: Option<Instant>) -> Result<Result<Answers, Interruption>, WorldHostError> {
        let agents = self.run.agents;
        let mut commands: Vec<Option<Option<usize>>> = vec![None; agents];
        let mut idle = Idle::new(self.run.wait);
        loop {
            for (a, slot) in commands.iter_mut().enumerate() {
                while slot.is_none() {
                    let read = receive(&self.ports.host.commands[a], |m| {
                        read_world_command(m, a, self.run.run_id, self.actions)
                    })?;
                    let Some(reading) = read else { break };
                    match reading {
                        Ok(order) if order.episode == self.episode && order.cycle == self.cycle => {
                            self.answered[a] = Some((order.cycle, monotonic_ns()));
                            *slot = Some(order.action);
                        }
                        Ok(order) if order.cycle < self.cycle => {
                            if self.run.clock == Clock::Lockstep {
                                self.count(Rejection::Sequence);
                            }
                        }
                        Ok(_) => self.count(Rejection::Sequence),
                        Err(why) => self.count(why),
                    }
                }
            }
            if commands.iter().all(Option::is_some) {
                return Ok(Ok(commands));
            }
            if let Some(deadline) = deadline
                && Instant::now() >= deadline
            {
                self.chassis.pacemaker.pulse.missed_deadlines += commands.iter().filter(|c| c.is_none()).count() as u64;
                return Ok(Ok(commands));
            }
            // The supervisor and the agents' reports every HOUSEKEEPING_EVERY
            // of the wall clock while commands are awaited, not at each poll
            // (however quickly each cycle's commands come).
            if self.housekept.elapsed() >= HOUSEKEEPING_EVERY {
                self.housekeeping()?;
            }
            if self.chassis.stopped() {
                return Ok(Err(Interruption::Stop));
            }
            if self.chassis.any_lost() {
                return Ok(Err(Interruption::Lost));
            }
            match deadline {
                Some(deadline) => idle.pause_until(&self.ports.host.wake, deadline)?,
                None => idle.pause(&self.ports.host.wake, MAX_BLOCK)?,
            }
        }
    }

    /// Plays one episode; `Err` if it was interrupted.
    fn episode(&mut self, world: &mut impl ServedWorld) -> Result<Result<(), Interruption>, WorldHostError> {
        let seed = std::mem::take(&mut self.first_reset).then_some(self.run.seed);
        self.keeping(|house| world.reset(seed, house))?;
        self.episode += 1;
        self.step = 0;
        let mut last: Vec<Option<usize>> = vec![None; self.run.agents];
        self.publish(world, EpisodeStatus::Running, &[])?;
        loop {
            let deadline = self.cadence.as_ref().map(Cadence::deadline);
            let answers = match self.collect(deadline)? {
                Ok(answers) => answers,
                Err(interruption) => return Ok(Err(interruption)),
            };
            self.end_cycle()?;
            if answers.iter().all(Option::is_none) && last.iter().all(Option::is_none) {
                // Real time, nothing told yet: the same state again a cycle later.
                self.publish(world, EpisodeStatus::Running, &[])?;
                continue;
            }
            // A missed command: a robot keeps doing what it was last told.
            let actions: Vec<Option<usize>> = answers.iter().zip(&last).map(|(a, p)| a.unwrap_or(*p)).collect();
            last.clone_from(&actions);
            // A world of one agent whose plan has ended ends the episode unstepped.
            let plan_ended = self.run.agents == 1 && answers[0] == Some(None);
            let results = if plan_ended {
                Vec::new()
            } else {
                self.step += 1;
                self.keeping(|house| world.step(&actions, house))?
            };
            let status = if plan_ended {
                EpisodeStatus::Truncated
            } else if world.terminated() {
                EpisodeStatus::Terminated
            } else if world.truncated() {
                EpisodeStatus::Truncated
            } else {
                EpisodeStatus::Running
            };
            self.publish(world, status, &results)?;
            if status.ended() {
                // Each agent acknowledges the end once it has learned from it.
                let deadline = self.cadence.as_ref().map(Cadence::deadline);
                let acknowledged = self.collect(deadline)?.map(drop);
                if acknowledged.is_ok() {
                    self.end_cycle()?;
                }
                return Ok(acknowledged);
            }
        }
    }
}

/// Serves `world` as the world process of the run in this process's
/// environment until the supervisor says stop: what was served. In real
/// time its last line on stderr is the cycle it kept (cycles, seconds,
/// rate, late cycles).
pub fn serve<W: ServedWorld>(world: &mut W) -> Result<Served, WorldHostError> {
    let run = WorldRun::from_env()?;
    let mut vocabulary = world.vocabulary();
    vocabulary.agents = run.agents;
    vocabulary.validate()?;
    let node = node(&run.namespace, "world")?;
    let ports = WorldPorts::open(&node, run.agents, run.wait)?;
    let agents = run.agents;
    let mut host = Host {
        actions: vocabulary.actions.len(),
        vocabulary,
        chassis: HostChassis::new(Role::World, run.run_id, run.wait, agents),
        ports,
        episode: 0,
        cycle: 0,
        step: 0,
        answered: vec![None; agents],
        first_reset: true,
        housekept: Instant::now(),
        announced: None,
        cadence: None,
        served: Served::default(),
        // SAFETY: getppid has no effects.
        parent: unsafe { libc::getppid() },
        run,
    };
    host.chassis.pacemaker.beat(&host.ports.host.heartbeat)?;
    while host.await_agents()? {
        loop {
            match host.episode(world)? {
                Ok(()) => host.chassis.pacemaker.pulse.episodes += 1,
                Err(Interruption::Stop) => break,
                Err(Interruption::Lost) => {
                    host.abort(world)?;
                    break;
                }
            }
        }
        if host.chassis.stopped() {
            break;
        }
    }
    host.end_cadence();
    host.chassis.pacemaker.pulse.late_cycles = host.served.late_cycles;
    host.chassis.shut_down(&host.ports.host.heartbeat)?;
    host.served.snapshots = host.cycle;
    let served = host.served;
    if let Some(rate) = served.rate() {
        eprintln!(
            "world: real time: {} cycles in {:.1} s: {rate:.3} a second (period {} ms: {:.3}), {} late",
            served.realtime_cycles,
            served.realtime_seconds,
            host.run.period.as_millis(),
            1.0 / host.run.period.as_secs_f64(),
            served.late_cycles
        );
    }
    Ok(served)
}
