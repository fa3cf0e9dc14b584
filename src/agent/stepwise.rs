//! A plan agent stepped from outside: the caller says what holds and what was
//! earned, the agent answers with the action its plan runs next.
//!
//! [`PlanAgent`](crate::PlanAgent) drives a world through registered
//! [`Action`](crate::executor::Action)s. An environment that drives itself (a gymnasium environment, a
//! robot's control loop, a world in another process) needs the inverse: the
//! caller owns the loop, and at each of its steps tells the agent the atoms that
//! hold and whether the action in progress finished; the agent fires the plan's
//! transitions, lets its learner resolve the choice points, and names the
//! action to run. Every action of the plan is bound to an action that only
//! records that it started; the caller reports its outcome.
//!
//! Durative actions: an action lasts until the caller reports it finished or
//! failed. [`StepwiseAgent::act`](crate::agent::stepwise::StepwiseAgent::act) with [`ActionOutcome::Running`](crate::agent::stepwise::ActionOutcome::Running) takes one
//! executor step with the action still running (its guards and the plan's
//! interrupts are evaluated on the new atoms) and names the action running
//! after it: the same one, or another if an interrupt ended it.
//!
//! Time: the learner sees the executor's steps as semi-Markov time (thesis
//! 5.3); one [`StepwiseAgent::act`](crate::agent::stepwise::StepwiseAgent::act) may take several steps (an action's end,
//! then the next choice and start).

use std::sync::Arc;

use crate::condition::{AtomId, AtomTable, BitKnowledgeBase, KnowledgeBase};
use crate::executor::{Action, ExecError, Executor, PendingReward, Registry, Status, World};
use crate::learning::{EpisodeMode, EpisodeStart, Learner};
use crate::plan::Plan;

/// Executor steps one [`StepwiseAgent::act`] may take without an action
/// starting before the plan counts as stalled (waiting on atoms that never
/// change while no action runs).
pub(crate) const STALL_STEPS: u32 = 1000;

/// The names of the primitive actions `plan` runs, in order of appearance: a
/// Petri Net Plan's, or those of every machine of a plan schema (a machine
/// called by another is not primitive).
pub fn action_names(plan: &Plan) -> Vec<String> {
    let mut names: Vec<String> = Vec::new();
    let mut add = |name: &str| {
        if !names.iter().any(|n| n == name) {
            names.push(name.to_string());
        }
    };
    match plan.schema_process() {
        Some(process) => process
            .machines()
            .iter()
            .flat_map(|m| m.actions())
            .filter(|a| a.machine.is_none())
            .for_each(|a| add(&a.name)),
        None => plan.actions().iter().for_each(|a| add(&a.name)),
    }
    names
}

/// The atoms `plan` tests: its guards', or a plan schema's events and conditions.
pub fn atom_table(plan: &Plan) -> AtomTable {
    match plan.schema_process() {
        Some(process) => process.atoms().clone(),
        None => plan.atoms().clone(),
    }
}

/// What became of the action in progress since the previous call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ActionOutcome {
    /// It ended normally (its `finished` guard holds).
    Finished,
    /// It goes on (a durative action).
    Running,
    /// It failed (its `failed` guard holds).
    Failed,
}

/// Why a step of a [`StepwiseAgent`] is refused.
#[derive(Debug, thiserror::Error)]
pub enum StepError {
    /// An atom the plan does not know.
    #[error("unknown atom '{atom}': the plan's atoms are {known}")]
    UnknownAtom {
        /// The name given.
        atom: String,
        /// The plan's atoms, comma-separated.
        known: String,
    },
    /// A reward that is not a finite number.
    #[error("reward {0} is not a finite number")]
    BadReward(f64),
    /// The plan waits on atoms with no action running.
    #[error(
        "the plan started no action in {steps} steps and is waiting in {marking}: the atoms its guards test there do not hold"
    )]
    Stalled {
        /// Steps taken.
        steps: u32,
        /// The root plan's marking, by place names.
        marking: String,
    },
    /// The executor refused the plan.
    #[error(transparent)]
    Exec(#[from] crate::executor::ExecError),
}

/// The world as the caller reports it: atoms, reward, and each action's state.
#[derive(Debug, Default)]
struct ReportedWorld {
    truth: BitKnowledgeBase,
    reward: f64,
    actions: Vec<ReportedAction>,
    started: Vec<usize>,
}

/// One action's state as the caller reported it.
#[derive(Debug, Default, Clone, Copy)]
struct ReportedAction {
    running: bool,
    finished: bool,
    failed: bool,
}

impl KnowledgeBase for ReportedWorld {
    fn holds(&self, atom: AtomId) -> bool {
        self.truth.holds(atom)
    }
}

impl World for ReportedWorld {
    fn take_reward(&mut self) -> f64 {
        std::mem::take(&mut self.reward)
    }
}

/// An action of the plan whose outcome the caller reports: it records that it
/// started and is finished or failed when told so.
#[derive(Debug)]
struct StepwiseAction {
    index: usize,
}

impl StepwiseAction {
    fn state<'w>(&self, world: &'w mut ReportedWorld) -> &'w mut ReportedAction {
        &mut world.actions[self.index]
    }
}

impl Action<ReportedWorld> for StepwiseAction {
    fn start(&mut self, world: &mut ReportedWorld) {
        *self.state(world) = ReportedAction {
            running: true,
            ..Default::default()
        };
        world.started.push(self.index);
    }
    fn resume(&mut self, world: &mut ReportedWorld) {
        self.start(world);
    }
    fn end(&mut self, world: &mut ReportedWorld) {
        *self.state(world) = ReportedAction::default();
    }
    fn interrupt(&mut self, world: &mut ReportedWorld) {
        *self.state(world) = ReportedAction::default();
    }
    fn fail(&mut self, world: &mut ReportedWorld) {
        *self.state(world) = ReportedAction::default();
    }
    fn finished(&self, world: &ReportedWorld) -> bool {
        world.actions[self.index].finished
    }
    fn failed(&self, world: &ReportedWorld) -> bool {
        world.actions[self.index].failed
    }
}

/// A plan and its learner, stepped by the caller (see the module documentation).
pub struct StepwiseAgent {
    executor: Executor<ReportedWorld>,
    learner: Box<dyn Learner>,
    world: ReportedWorld,
    actions: Vec<String>,
    atoms: AtomTable,
    mode: EpisodeMode,
    in_episode: bool,
}

impl StepwiseAgent {
    /// Binds every action of `plan` (and of a schema's machines) to an action
    /// whose outcome the caller reports, with `learner` at the choice points.
    pub fn new(plan: Arc<Plan>, learner: Box<dyn Learner>) -> Result<Self, ExecError> {
        let actions = action_names(&plan);
        let atoms = atom_table(&plan);
        let mut registry = Registry::new();
        for (index, name) in actions.iter().enumerate() {
            registry.action(name, &[], move |_| StepwiseAction { index });
        }
        let world = ReportedWorld {
            truth: BitKnowledgeBase::new(atoms.len()),
            actions: vec![ReportedAction::default(); actions.len()],
            ..Default::default()
        };
        Ok(StepwiseAgent {
            executor: Executor::new(plan, &registry)?,
            learner,
            world,
            actions,
            atoms,
            mode: EpisodeMode::Learn,
            in_episode: false,
        })
    }

    /// The plan.
    pub fn plan(&self) -> &Plan {
        self.executor.plan()
    }

    /// The names of the plan's actions, in the order [`Self::act`] indexes them.
    pub fn action_names(&self) -> &[String] {
        &self.actions
    }

    /// The learner.
    pub fn learner(&self) -> &dyn Learner {
        self.learner.as_ref()
    }

    /// The learner, to load values into.
    pub fn learner_mut(&mut self) -> &mut dyn Learner {
        self.learner.as_mut()
    }

    /// What the next episodes are for (learning by default); an episode in
    /// progress keeps its mode.
    pub fn set_mode(&mut self, mode: EpisodeMode) {
        self.mode = mode;
    }

    /// The mode of the next episodes.
    pub fn mode(&self) -> EpisodeMode {
        self.mode
    }

    /// Whether an episode is in progress.
    pub fn in_episode(&self) -> bool {
        self.in_episode
    }

    /// The root plan's status.
    pub fn status(&self) -> Status {
        self.executor.status()
    }

    /// The atoms the plan tests.
    pub fn atoms(&self) -> &AtomTable {
        &self.atoms
    }

    /// The atom called `name`.
    pub fn atom(&self, name: &str) -> Result<AtomId, StepError> {
        let atoms = &self.atoms;
        atoms.get(name).ok_or_else(|| StepError::UnknownAtom {
            atom: name.to_string(),
            known: atoms.names().collect::<Vec<_>>().join(", "),
        })
    }

    /// Sets what holds now: exactly the atoms `true` (all others false).
    pub fn set_atoms(&mut self, true_atoms: &[AtomId]) {
        self.world.truth.clear();
        for &a in true_atoms {
            self.world.truth.set(a, true);
        }
    }

    /// Adds `reward` to what the plan earned since the previous step.
    pub fn reward(&mut self, reward: f64) -> Result<(), StepError> {
        if !reward.is_finite() {
            return Err(StepError::BadReward(reward));
        }
        self.world.reward += reward;
        Ok(())
    }

    /// The names of the actions running now.
    pub fn running(&self) -> Vec<&str> {
        self.world
            .actions
            .iter()
            .zip(&self.actions)
            .filter(|(a, _)| a.running)
            .map(|(_, name)| name.as_str())
            .collect()
    }

    /// Reports `outcome` for every running action, runs the plan on the atoms
    /// set, and returns the index (into [`Self::action_names`]) of the action
    /// the plan runs next, or `None` when the plan has ended (goal or fail).
    /// Starts an episode if none is in progress.
    pub fn act(&mut self, outcome: ActionOutcome) -> Result<Option<usize>, StepError> {
        if !self.in_episode {
            self.learner.begin_episode(EpisodeStart::of(self.mode));
            self.world
                .actions
                .iter_mut()
                .for_each(|a| *a = ReportedAction::default());
            self.executor.reset(&mut self.world, self.learner.as_mut());
            self.in_episode = true;
        }
        for a in self.world.actions.iter_mut().filter(|a| a.running) {
            match outcome {
                ActionOutcome::Finished => a.finished = true,
                ActionOutcome::Failed => a.failed = true,
                ActionOutcome::Running => {}
            }
        }
        self.world.started.clear();
        for _ in 0..STALL_STEPS {
            let status = self.executor.step(&mut self.world, self.learner.as_mut())?;
            if status != Status::Running {
                return Ok(None);
            }
            if let Some(&last) = self.world.started.last() {
                return Ok(Some(last));
            }
            if outcome == ActionOutcome::Running
                && let Some(running) = self.world.actions.iter().rposition(|a| a.running)
            {
                return Ok(Some(running));
            }
        }
        Err(StepError::Stalled {
            steps: STALL_STEPS,
            marking: self.plan().describe(self.executor.marking()),
        })
    }

    /// Discards the episode in progress (if any), as when the world lost an
    /// agent: the learner is not told its end, and the next step begins a new
    /// episode.
    pub fn abort_episode(&mut self) {
        self.world.reward = 0.0;
        self.in_episode = false;
    }

    /// Ends the episode in progress (if any): the reward reported since the
    /// last step and the steps since the last marking change go to the learner.
    pub fn end_episode(&mut self) {
        if !self.in_episode {
            return;
        }
        let mut tail: PendingReward = self.executor.take_pending();
        let reward = self.world.take_reward();
        if reward != 0.0 {
            tail.add(reward);
        }
        self.learner.end_episode(tail);
        self.in_episode = false;
    }
}
