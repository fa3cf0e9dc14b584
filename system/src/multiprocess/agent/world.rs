//! An agent of a world in its own process: its plan, run by a
//! [`StepwiseAgent`](learnpnp::agent::stepwise::StepwiseAgent) with its learner, against the world's snapshots.
//!
//! Before the first episode it reads the world's vocabulary and checks its
//! plan against it (a plan naming an atom or action the world lacks is
//! refused with both lists: exit code [`EXIT_PLAN_DOES_NOT_FIT`](crate::multiprocess::agent::world::EXIT_PLAN_DOES_NOT_FIT)). The agent
//! runs the experiment's protocol itself ([`run_protocol`](learnpnp::experiment::runner::run_protocol)): each episode the
//! world plays is the protocol's next one, learning or evaluated. Every whole
//! episode is journaled, so that a restarted agent (values from its last
//! checkpoint) resumes the protocol where the run is; the world discards the
//! episode in flight. Each snapshot: credit the reward, set the atoms, step
//! the plan, answer with the action's index in the world's vocabulary.

use std::collections::VecDeque;
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};
use shm_layouts::MAX_ARGS;

use crate::ipc::convert::{Rejection, read_control};
use crate::ipc::protocol::{Order, ProcessState, Role};
use crate::ipc::services::{WorldAgentPorts, node, receive, send};
use crate::ipc::wait::{Idle, MAX_BLOCK};
use crate::ipc::world::{
    ActionStatus, EpisodeStatus, Vocabulary, VocabularyReader, WorldOrder, WorldView, floor_pong, read_world_snapshot,
    world_command,
};
use crate::latency::Latency;
use crate::multiprocess::agent::chassis::{Chassis, load_checkpoint, report};
use crate::multiprocess::host::simulator::{ROUND_TRIP, SimTotals, SimulatorResult};
use crate::multiprocess::journal::{self, Journal};
use crate::multiprocess::{Clock, HEARTBEAT_EVERY, Pacemaker, ProcessError, RunContext};
use learnpnp::agent::stepwise::{ActionOutcome, StepError, StepwiseAgent, action_names, atom_table};
use learnpnp::domains::{EpisodeOutcome, Task, TaskError};
use learnpnp::experiment::runner::{RunOutput, learner_for, run_protocol};
use learnpnp::experiment::spec::{DomainSpec, ExperimentError};
use learnpnp::learning::persist::SavedValues;
use learnpnp::learning::{EpisodeMode, Learner};
use learnpnp::named::Named;
use learnpnp::plan_file::load_plan;

/// The exit code of an agent whose plan does not fit the world's
/// vocabulary: it is not restarted, and the run stops.
pub const EXIT_PLAN_DOES_NOT_FIT: i32 = 4;

/// How long the agent's journal gathers entries before it writes them.
const JOURNAL_GATHERING: Duration = Duration::from_millis(10);

/// How often an agent, busy or idle, looks at the supervisor's commands and sends its heartbeat.
const HOUSEKEEPING_EVERY: Duration = Duration::from_millis(1);

/// How long an agent waits for the world's vocabulary before it gives up.
pub(crate) const VOCABULARY_TIMEOUT: Duration = Duration::from_secs(60);

/// The histogram of the world's turnaround as the agents see it: from the
/// world's reading of an agent's command to its publishing that agent's
/// next snapshot (both on the world's clock). With one agent it is the
/// world's own time per cycle; with more, it includes waiting for the others.
pub const WORLD_TURNAROUND: &str = "world-turnaround";

/// The name of agent `a`'s compute-time histogram.
pub fn agent_compute_histogram(a: usize) -> String {
    format!("compute-agent{}", a + 1)
}

/// Agent `a`'s result file in the run's work directory.
pub fn agent_result_file(a: usize) -> String {
    format!("agent{}.json", a + 1)
}

/// Agent `a`'s journal of whole episodes.
fn journal_file(a: usize) -> String {
    format!("agent{}.journal", a + 1)
}

/// An agent's settings beyond the run's.
#[derive(Debug, Clone, PartialEq)]
pub struct WorldAgentSettings {
    /// The agent (0-based).
    pub agent: usize,
    /// Checkpoint every this many learning episodes (0: only on request and at the end).
    pub checkpoint_every: u64,
    /// Start from the checkpoint and journal in the work directory (a restart).
    pub resume: bool,
}

/// A plan that names what the world does not have.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Misfit {
    /// Atoms the plan tests that the world lacks.
    pub atoms: Vec<String>,
    /// Actions the plan runs that the world lacks.
    pub actions: Vec<String>,
    /// The world's vocabulary.
    pub world: Vocabulary,
}

impl std::fmt::Display for Misfit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let list = |names: &[String]| {
            if names.is_empty() {
                "none".to_string()
            } else {
                names.join(", ")
            }
        };
        write!(
            f,
            "the plan does not fit the world: atoms it lacks: {}; actions it lacks: {} (the world's atoms: {}; its actions: {})",
            list(&self.atoms),
            list(&self.actions),
            list(&self.world.atoms),
            list(&self.world.actions)
        )
    }
}

/// Where each of the plan's atoms and actions is in the world's vocabulary.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Binding {
    /// World atom index of each plan atom.
    atoms: Vec<usize>,
    /// World action index of each plan action.
    actions: Vec<usize>,
}

/// Binds a plan's atoms and actions to the world's vocabulary, or says what is missing.
pub(crate) fn bind(plan_atoms: &[String], plan_actions: &[String], world: &Vocabulary) -> Result<Binding, Box<Misfit>> {
    let find = |names: &[String], within: &[String]| -> (Vec<usize>, Vec<String>) {
        let mut found = Vec::new();
        let mut missing = Vec::new();
        for name in names {
            match within.iter().position(|w| w == name) {
                Some(i) => found.push(i),
                None => missing.push(name.clone()),
            }
        }
        (found, missing)
    };
    let (atoms, missing_atoms) = find(plan_atoms, &world.atoms);
    let (actions, missing_actions) = find(plan_actions, &world.actions);
    if missing_atoms.is_empty() && missing_actions.is_empty() {
        Ok(Binding { atoms, actions })
    } else {
        Err(Box::new(Misfit {
            atoms: missing_atoms,
            actions: missing_actions,
            world: world.clone(),
        }))
    }
}

/// One whole episode, as the agent's journal keeps it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct AgentJournalEntry {
    mode: EpisodeMode,
    outcome: EpisodeOutcome,
    totals: SimTotals,
}

/// The episode the agent is in.
#[derive(Debug, Clone, Copy, Default)]
struct Episode {
    /// The world's number of it.
    number: u64,
    ret: f64,
    actions: u32,
}

/// The agent while it runs.
struct WorldAgent {
    chassis: Chassis,
    ports: WorldAgentPorts,
    stepwise: StepwiseAgent,
    binding: Binding,
    /// The plan's atoms that hold in the snapshot being taken (kept to save
    /// an allocation a cycle).
    holds: Vec<learnpnp::AtomId>,
    atoms: usize,
    fluents: usize,
    algorithm: &'static str,
    round_trip: Latency,
    world_turnaround: Latency,
    /// Journal entries that could not be written.
    journal_failures: u64,
    journal: Journal,
    replay: VecDeque<AgentJournalEntry>,
    totals: SimTotals,
    started: Instant,
    /// No snapshot has come since the agent (re)started or since the world
    /// discarded an episode: it says it is ready.
    announcing: bool,
    announced: Option<Instant>,
    /// The last cycle taken (none after a world restart).
    last_cycle: Option<u64>,
    /// The snapshot last answered: its cycle and when the world sent it.
    answered: Option<(u64, u64)>,
    episode: Option<Episode>,
    backlog: VecDeque<WorldView>,
    stop: bool,
}

impl WorldAgent {
    fn count(&mut self, why: Rejection) {
        self.chassis.count(why);
        self.totals.rejected.count(why);
    }

    fn values(&self) -> SavedValues {
        SavedValues::new(
            self.algorithm,
            self.stepwise.learner().values(),
            &self.stepwise.plan().activation_plans(),
        )
    }

    /// Hands the checkpoint and the histograms to the writer thread; a
    /// failure is reported and counted there, the previous checkpoint stays.
    /// The journal is written first: it never lags the checkpoint.
    fn save(&mut self) {
        let written = self.journal.flush();
        self.count_journal_failure(written);
        let values = self.values();
        self.chassis
            .save(Some(values), &[&self.round_trip, &self.world_turnaround]);
    }

    /// Checkpoints and waits until it is written.
    fn save_now(&mut self) {
        self.save();
        self.chassis.flush();
    }

    /// Reports and counts a journal write that failed.
    fn count_journal_failure(&mut self, written: Result<(), journal::JournalError>) {
        if let Err(e) = written {
            self.journal_failures += 1;
            report(&format!("error: {e}: episodes not journaled"));
        }
    }

    /// Heartbeat, the supervisor's commands, readiness, floor pings, the
    /// journal's gathered entries.
    fn housekeeping(&mut self) -> Result<(), ProcessError> {
        let written = self.journal.flush_if_due();
        self.count_journal_failure(written);
        self.chassis.pacemaker.pulse.cycles = self.totals.cycles;
        self.chassis.tick(&self.ports.heartbeat, self.journal_failures)?;
        let run_id = self.chassis.context.run_id;
        while let Some(order) = self
            .chassis
            .next_order(&self.ports.control, |why| self.totals.rejected.count(why))?
        {
            match order {
                Order::Stop => self.stop = true,
                Order::Checkpoint => self.save_now(),
                Order::SimulatorRestarted => {
                    // A new world numbers its cycles afresh; the episode in
                    // flight is dropped (the learner is not told its end).
                    self.discard_episode();
                    self.last_cycle = None;
                    self.answered = None;
                    self.backlog.clear();
                    while receive(&self.ports.snapshot, |_| ())?.is_some() {}
                }
                Order::KeeperLost { .. } => {}
            }
        }
        if self.announcing && self.announced.is_none_or(|t| t.elapsed() >= HEARTBEAT_EVERY) {
            self.chassis.announce(&self.ports.report)?;
            self.announced = Some(Instant::now());
        }
        answer_floor(&self.ports, run_id)?;
        Ok(())
    }

    /// Drops the episode in progress and says it is ready for the next.
    fn discard_episode(&mut self) {
        if self.episode.take().is_some() {
            self.stepwise.abort_episode();
            self.totals
                .aborted
                .push(crate::multiprocess::host::simulator::AbortedEpisode {
                    episode: self.totals.episode_seq,
                    mode: self.stepwise.mode(),
                    cycles: 0,
                    keepers: Vec::new(),
                });
        }
        self.announcing = true;
        self.announced = None;
    }

    /// The next snapshot taken (validated, in sequence), if one has come. A
    /// snapshot of a running episode that a newer one of the same episode
    /// follows is skipped, its reward credited to the newer (an agent that
    /// fell behind in real time acts once, on the newest).
    fn next_view(&mut self) -> Result<Option<WorldView>, ProcessError> {
        let (a, run_id, atoms, fluents) = (
            self.chassis.index,
            self.chassis.context.run_id,
            self.atoms,
            self.fluents,
        );
        while let Some(reading) = receive(&self.ports.snapshot, |m| {
            read_world_snapshot(m, a, run_id, atoms, fluents)
        })? {
            match reading {
                Ok(view) => {
                    let stale = self.last_cycle.is_some_and(|c| view.cycle <= c)
                        || self.episode.is_some_and(|e| view.episode < e.number);
                    if stale {
                        self.count(Rejection::Sequence);
                    } else {
                        self.last_cycle = Some(view.cycle);
                        self.backlog.push_back(view);
                    }
                }
                Err(why) => self.count(why),
            }
        }
        while let Some(view) = self.backlog.pop_front() {
            let superseded = view.episode_status == EpisodeStatus::Running
                && self
                    .backlog
                    .front()
                    .is_some_and(|next| next.episode == view.episode && next.episode_status != EpisodeStatus::Aborted);
            if superseded {
                if let Some(next) = self.backlog.front_mut() {
                    next.reward += view.reward;
                }
                continue;
            }
            return Ok(Some(view));
        }
        Ok(None)
    }

    /// Records a command's round trip and the world's turnaround after it.
    fn record_timing(&mut self, timed: Option<(Duration, Duration)>) {
        if let Some((round_trip, turnaround)) = timed {
            self.round_trip.record(round_trip);
            self.world_turnaround.record(turnaround);
        }
    }

    /// Takes one snapshot; returns the episode's outcome when it ended.
    fn take(&mut self, view: WorldView, started: Instant) -> Result<Option<EpisodeOutcome>, ProcessError> {
        self.announcing = false;
        self.chassis.pacemaker.pulse.state = ProcessState::Running;
        // The round trip of the last command and the world's turnaround,
        // recorded once the next command is sent (off the cycle's path).
        let timed = match (view.answered, self.answered) {
            (Some((cycle, received)), Some((sent_cycle, sent_ns))) if cycle == sent_cycle => {
                self.answered = None;
                Some((
                    Duration::from_nanos(received.saturating_sub(sent_ns)),
                    Duration::from_nanos(view.sent_ns.saturating_sub(received)),
                ))
            }
            _ => None,
        };
        if view.episode_status == EpisodeStatus::Aborted {
            self.record_timing(timed);
            self.discard_episode();
            return Ok(None);
        }
        if self.episode.is_none_or(|e| e.number != view.episode) {
            if self.episode.is_some() {
                // A new episode while one was open: the world dropped it.
                self.discard_episode();
                self.announcing = false;
            }
            self.totals.episode_seq += 1;
            self.episode = Some(Episode {
                number: view.episode,
                ..Episode::default()
            });
        }
        let mut episode = self.episode.unwrap_or_default();
        self.stepwise
            .reward(view.reward)
            .map_err(|e| ProcessError::CannotResume(e.to_string()))?;
        episode.ret += view.reward;
        self.totals.cycles += 1;
        self.totals.cycle_seq = view.cycle;
        let (action, ended) = if view.episode_status.ended() {
            self.stepwise.end_episode();
            (None, true)
        } else {
            self.holds.clear();
            self.holds.extend(
                self.binding
                    .atoms
                    .iter()
                    .enumerate()
                    .filter(|&(_, &w)| view.holds(w))
                    .map(|(i, _)| learnpnp::AtomId(i as u32)),
            );
            self.stepwise.set_atoms(&self.holds);
            let outcome = match view.action_status {
                ActionStatus::Running => ActionOutcome::Running,
                ActionStatus::Failed => ActionOutcome::Failed,
                ActionStatus::None | ActionStatus::Finished => ActionOutcome::Finished,
            };
            match self.stepwise.act(outcome) {
                Ok(next) => (next.map(|i| self.binding.actions[i]), false),
                Err(stalled @ StepError::Stalled { .. }) => {
                    report(&format!("warning: {stalled}; the agent answers with no action"));
                    (None, false)
                }
                Err(e) => return Err(ProcessError::CannotResume(e.to_string())),
            }
        };
        if action.is_some() {
            episode.actions += 1;
        }
        let compute = started.elapsed();
        let order = WorldOrder {
            episode: view.episode,
            cycle: view.cycle,
            compute_ns: compute.as_nanos() as u64,
            action,
            args: [0.0; MAX_ARGS],
        };
        self.ports
            .command
            .send(world_command(&order, self.chassis.index, self.chassis.context.run_id))?;
        self.chassis.compute.record(compute);
        self.record_timing(timed);
        self.answered = Some((view.cycle, view.sent_ns));
        if !ended {
            self.episode = Some(episode);
            return Ok(None);
        }
        self.episode = None;
        self.chassis.pacemaker.pulse.episodes += 1;
        Ok(Some(EpisodeOutcome {
            ret: episode.ret,
            actions: episode.actions,
            steps: episode.actions,
            exploratory: self.stepwise.learner().exploratory(),
        }))
    }

    /// Plays the world's next whole episode in `mode`.
    fn play(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, ProcessError> {
        self.stepwise.set_mode(mode);
        let mut idle = Idle::new(self.chassis.context.wait);
        let mut kept: Option<Instant> = None;
        loop {
            // The supervisor's commands, the heartbeat and the journal every
            // HOUSEKEEPING_EVERY, busy or idle (a poll is quicker without
            // them); in real time, floor pings at every idle poll.
            let busy = match self.next_view()? {
                Some(view) => {
                    idle = Idle::new(self.chassis.context.wait);
                    if let Some(outcome) = self.take(view, Instant::now())? {
                        return Ok(outcome);
                    }
                    true
                }
                None => false,
            };
            if kept.is_none_or(|t| t.elapsed() >= HOUSEKEEPING_EVERY) {
                self.housekeeping()?;
                kept = Some(Instant::now());
                if self.stop {
                    return Err(ProcessError::Stopped);
                }
            } else if !busy && self.chassis.context.clock == Clock::Realtime {
                // Real time samples the floor side by side with the run;
                // lock-step measured it before the world started.
                answer_floor(&self.ports, self.chassis.context.run_id)?;
            }
            if !busy {
                idle.pause(&self.ports.wake, MAX_BLOCK)?;
            }
        }
    }

    /// Journals a whole episode and checkpoints if one is due (after the
    /// entry, so that the journal never lags the checkpoint). A journal
    /// entry that cannot be written (a full disk) is reported and counted
    /// with the checkpoint failures: the agent goes on, and a restart would
    /// replay the episodes journaled before it.
    fn record(&mut self, mode: EpisodeMode, outcome: EpisodeOutcome) {
        if mode == EpisodeMode::Learn {
            self.totals.learning_episodes += 1;
            self.chassis.learning_episodes += 1;
        }
        self.totals.seconds += self.started.elapsed().as_secs_f64();
        self.started = Instant::now();
        let entry = AgentJournalEntry {
            mode,
            outcome,
            totals: self.totals.clone(),
        };
        let written = self.journal.append(&entry);
        self.count_journal_failure(written);
        if mode == EpisodeMode::Learn && self.chassis.checkpoint_due() {
            self.save();
        }
    }
}

impl Task for WorldAgent {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        if let Some(entry) = self.replay.pop_front() {
            journal::follows_protocol(entry.mode, mode)?;
            self.totals = entry.totals;
            if entry.mode == EpisodeMode::Learn {
                self.chassis.learning_episodes += 1;
            }
            return Ok(entry.outcome);
        }
        let outcome = self.play(mode).map_err(|e| match e {
            ProcessError::Stopped => TaskError::Stopped,
            other => TaskError::External(Box::new(other)),
        })?;
        self.record(mode, outcome);
        Ok(outcome)
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        Vec::new()
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        vec![self.stepwise.learner()]
    }
}

/// Agent 0 answers the supervisor's floor pings at once.
fn answer_floor(ports: &WorldAgentPorts, run_id: u64) -> Result<(), ProcessError> {
    let Some((pings, pongs)) = &ports.floor else {
        return Ok(());
    };
    while let Some(sequence) = receive(pings, |m| {
        (m.header.run_id == run_id && m.header.sender == shm_layouts::SENDER_SUPERVISOR).then_some(m.cycle)
    })? {
        if let Some(sequence) = sequence {
            send(pongs, floor_pong(run_id, sequence))?;
        }
    }
    Ok(())
}

/// Waits for the world's whole vocabulary (answering the supervisor and
/// floor pings meanwhile); `None` if the supervisor said stop first.
fn await_vocabulary(
    ports: &WorldAgentPorts,
    pacemaker: &mut Pacemaker,
    context: &RunContext,
    agent: usize,
) -> Result<Option<Vocabulary>, ProcessError> {
    let mut reader = VocabularyReader::default();
    let started = Instant::now();
    let mut idle = Idle::new(context.wait);
    let run_id = context.run_id;
    loop {
        pacemaker.tick(&ports.heartbeat)?;
        while let Some(order) = receive(&ports.control, |m| read_control(m, Role::Agent(agent), run_id))? {
            match order {
                Ok(Some(Order::Stop)) => return Ok(None),
                Ok(_) => {}
                Err(why) => pacemaker.pulse.rejected.count(why),
            }
        }
        answer_floor(ports, run_id)?;
        while let Some(part) = receive(&ports.vocabulary, |m| reader.read(m, run_id))? {
            match part {
                Ok(Some(vocabulary)) => return Ok(Some(vocabulary)),
                Ok(None) => {}
                Err(why) => pacemaker.pulse.rejected.count(why),
            }
        }
        if started.elapsed() > VOCABULARY_TIMEOUT {
            return Err(ProcessError::NoVocabulary(VOCABULARY_TIMEOUT.as_secs()));
        }
        idle.pause(&ports.wake, MAX_BLOCK)?;
    }
}

/// Runs agent `settings.agent` of `context`'s world run until its protocol
/// ends or the supervisor stops it; writes its result, journal, histograms
/// and checkpoints into the work directory. A fresh start checkpoints its
/// starting values at once, so that a restart always has a checkpoint.
pub fn run(context: &RunContext, settings: &WorldAgentSettings) -> Result<(), ProcessError> {
    let spec = context.load_spec()?;
    let DomainSpec::World { plans, .. } = &spec.domain else {
        return Err(ProcessError::UnsupportedDomain(spec.domain.name()));
    };
    let (a, agents) = (settings.agent, plans.len());
    let path = plans.get(a).ok_or(ProcessError::NoAgent(a + 1))?;
    let plan = Arc::new(load_plan(path, learnpnp::AllowedAtoms::Open).map_err(ExperimentError::from)?);
    let chassis = Chassis::new(
        context,
        Role::Agent(a),
        a,
        settings.checkpoint_every,
        agent_compute_histogram(a),
    )?;
    let start = if settings.resume {
        Some(load_checkpoint(&chassis.checkpoint, &plan)?)
    } else {
        spec.load_initial_values(Some(&plan))?.into_iter().nth(a)
    };
    let learner = chassis.watched(learner_for(&spec, context.run, a, start.as_ref()), &plan);
    let stepwise = StepwiseAgent::new(Arc::clone(&plan), learner).map_err(|e| ProcessError::Task(e.into()))?;
    let namespace = context.namespace()?;
    let node = node(&namespace, &format!("agent-{a}"))?;
    let ports = WorldAgentPorts::open(&node, a, context.wait)?;
    let mut chassis = chassis;
    chassis.pacemaker.beat(&ports.heartbeat)?;
    let Some(vocabulary) = await_vocabulary(&ports, &mut chassis.pacemaker, context, a)? else {
        return Ok(());
    };
    if vocabulary.agents != agents {
        return Err(ProcessError::CannotResume(format!(
            "the world serves {} agents, the run has {agents}",
            vocabulary.agents
        )));
    }
    let plan_atoms: Vec<String> = atom_table(&plan).names().map(str::to_string).collect();
    let binding = bind(&plan_atoms, &action_names(&plan), &vocabulary).map_err(ProcessError::PlanDoesNotFit)?;
    let journal_path = context.work_dir.join(journal_file(a));
    let replay: Vec<AgentJournalEntry> = if settings.resume {
        journal::read(&journal_path)?
    } else {
        Vec::new()
    };
    let journal = Journal::open(&journal_path, &replay, JOURNAL_GATHERING)?;
    let mut agent = WorldAgent {
        chassis,
        ports,
        stepwise,
        binding,
        holds: Vec::new(),
        atoms: vocabulary.atoms.len(),
        fluents: vocabulary.fluents.len(),
        algorithm: spec.algorithm.name(),
        round_trip: Latency::new(ROUND_TRIP),
        world_turnaround: Latency::new(WORLD_TURNAROUND),
        journal_failures: 0,
        journal,
        replay: replay.into(),
        totals: SimTotals::default(),
        started: Instant::now(),
        announcing: true,
        announced: None,
        last_cycle: None,
        answered: None,
        episode: None,
        backlog: VecDeque::new(),
        stop: false,
    };
    if settings.resume {
        agent.chassis.record_resumed(&agent.values())?;
    } else {
        agent.save_now();
    }
    agent.chassis.beat(&agent.ports.heartbeat, ProcessState::Ready)?;
    let mut output = RunOutput::default();
    let played = run_protocol(&spec, &mut agent, context.run, true, &mut output, |_| {}, || false);
    agent.save_now();
    if let Err(e) = &played
        && agent.stop
    {
        report(&format!("stopped before the protocol ended: {e}"));
    }
    let result = SimulatorResult {
        complete: played.is_ok(),
        error: played.err().map(|e| e.to_string()),
        output,
        totals: agent.totals.clone(),
    };
    let json = serde_json::to_vec_pretty(&result)?;
    let path = context.work_dir.join(agent_result_file(a));
    atomic_file::write_atomic(&path, &json).map_err(|source| ProcessError::Io { path, source })?;
    // The last heartbeat says the agent is done (a supervisor on another
    // host learns it so); a sample its publisher outlives is lost, so the
    // ports stay a moment for it to be read.
    agent.chassis.beat(&agent.ports.heartbeat, ProcessState::Stopping)?;
    std::thread::sleep(STOPPING_LINGER);
    Ok(())
}

/// How long an agent keeps its ports after its last heartbeat.
const STOPPING_LINGER: Duration = Duration::from_millis(100);

#[cfg(test)]
mod tests {
    use super::*;

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn a_plan_binds_to_the_world_names_it_uses() {
        let world = Vocabulary {
            atoms: names(&["a", "b", "c"]),
            fluents: Vec::new(),
            actions: names(&["left", "right", "noop"]),
            agents: 1,
        };
        let binding = bind(&names(&["c", "a"]), &names(&["right"]), &world).unwrap();
        assert_eq!(binding.atoms, vec![2, 0]);
        assert_eq!(binding.actions, vec![1]);
        let misfit = bind(&names(&["a", "z"]), &names(&["jump"]), &world).unwrap_err();
        assert_eq!(misfit.atoms, names(&["z"]));
        assert_eq!(misfit.actions, names(&["jump"]));
        let text = misfit.to_string();
        assert!(text.contains("atoms it lacks: z") && text.contains("the world's atoms: a, b, c"));
    }
}
