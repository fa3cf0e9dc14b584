//! What an experiment runs: a domain, an algorithm with its parameters, and the protocol.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::plot::Reference;
use super::ranges;
use crate::analysis;
use crate::domains::keepaway::{self, KeepawayDomainConfig, KeepawayMode, KeepawayTask};
use crate::domains::nmdp::{self, Nmdp, NmdpConfig};
use crate::domains::parr_russell::{self, ParrRussell, ParrRussellConfig};
use crate::domains::penalty_kick::{self, PenaltyKick, PenaltyKickConfig};
use crate::domains::sutton::{self, Sutton, SuttonConfig};
use crate::domains::{Task, TaskError};
use crate::experiment::result_dir::ResultDirError;
use crate::learning::migrate::{self, MigrationReport};
use crate::learning::persist::{self, PlanLabels, SavedValues};
use crate::learning::{
    Assessment, Exploration, Learner, Mcesp, McespConfig, RandomLearner, Sigma, SoSmc, SoSmcConfig, StepSize, TdConfig,
    TdLearner,
};
use crate::named::Named;
use crate::plan::{AllowedAtoms, Plan};
use crate::plan_file::{LoadError, load_plan};
use crate::rng::SimRng;
use crate::schema;

/// A domain and its parameters; `plan` replaces the built-in plan with a file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "domain", rename_all = "kebab-case")]
pub enum DomainSpec {
    /// Parr and Russell's 4 x 3 grid.
    ParrRussell {
        /// Its parameters.
        config: ParrRussellConfig,
        /// A plan file to use instead of the thesis's plan.
        plan: Option<PathBuf>,
    },
    /// Sutton's 9 x 6 grid.
    Sutton {
        /// Its parameters.
        config: SuttonConfig,
        /// A plan file to use instead of the thesis's plan.
        plan: Option<PathBuf>,
    },
    /// The penalty kick.
    PenaltyKick {
        /// Its parameters (the variant picks the built-in plan).
        config: PenaltyKickConfig,
        /// A plan file to use instead of the variant's plan.
        plan: Option<PathBuf>,
    },
    /// The small N-MDP of thesis Figure 4.3.
    Nmdp {
        /// The four policies' return distributions.
        config: NmdpConfig,
        /// A plan file to use instead of the figure's plan.
        plan: Option<PathBuf>,
    },
    /// Keepaway 3 vs 2.
    Keepaway {
        /// Who learns, and the abstraction's thresholds.
        config: KeepawayDomainConfig,
        /// A plan file for the learning keepers instead of the thesis's plan.
        plan: Option<PathBuf>,
    },
    /// A world in a process of its own (a robot, a user's simulator, a
    /// gymnasium environment), played only by `learnpnp-supervisor --world-cmd`.
    World {
        /// The command that starts the world process.
        command: String,
        /// Each agent's plan (one agent per entry, each in its own process).
        plans: Vec<PathBuf>,
    },
}

/// The most agents a world serves (as `shm_layouts::MAX_AGENTS`).
pub(crate) const MAX_WORLD_AGENTS: usize = 16;

/// Why an experiment cannot be set up or run.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// A plan file does not load.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The task fails.
    #[error(transparent)]
    Task(#[from] TaskError),
    /// A parameter is out of range.
    #[error("invalid experiment: {0}")]
    Invalid(String),
    /// The result directory cannot be used.
    #[error(transparent)]
    ResultDir(#[from] ResultDirError),
    /// A plan file fails the structural checks of `learnpnp check`.
    #[error(
        "{}: the plan fails the structural checks (`learnpnp check {}` explains; --unchecked runs it anyway):\n  - {}",
        path.display(),
        path.display(),
        failures.join("\n  - ")
    )]
    FailsCheck {
        /// The plan file.
        path: PathBuf,
        /// Each failure, as `check` words it.
        failures: Vec<String>,
    },
}

impl DomainSpec {
    /// Checks the parameters the command line sets, and the grids' numbers.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        match self {
            DomainSpec::ParrRussell { config, .. } => {
                field("max-actions", ranges::MAX_ACTIONS.check(u64::from(config.max_actions)))?;
                field("success probability", ranges::EPSILON.check(config.success))?;
                field("step reward", ranges::RETURN.check(config.step_reward))?;
            }
            DomainSpec::Sutton { config, .. } => {
                field("max-actions", ranges::MAX_ACTIONS.check(u64::from(config.max_actions)))?;
            }
            DomainSpec::PenaltyKick { config, .. } => {
                field("goal reward", ranges::RETURN.check(config.goal_reward))?;
            }
            DomainSpec::Nmdp { config, .. } => {
                for d in config.returns.iter().flatten() {
                    field("return mean", ranges::RETURN.check(d.mean))?;
                    field("return deviation", ranges::DISTANCE.check(d.sd))?;
                }
            }
            DomainSpec::World { plans, command } => {
                if !(1..=MAX_WORLD_AGENTS).contains(&plans.len()) {
                    return Err(ExperimentError::Invalid(format!(
                        "agents: {} is not between 1 and {MAX_WORLD_AGENTS}",
                        plans.len()
                    )));
                }
                if command.trim().is_empty() {
                    return Err(ExperimentError::Invalid("the world command is empty".into()));
                }
            }
            DomainSpec::Keepaway { config, .. } => {
                field("record", ranges::RECORD.check(config.record as u64))?;
                field("hold-threshold", ranges::DISTANCE.check(config.hold_threshold))?;
                field("lane-threshold", ranges::DISTANCE.check(config.thresholds.pass_line))?;
                field(
                    "taker-threshold",
                    ranges::DISTANCE.check(config.thresholds.closest_taker),
                )?;
            }
        }
        Ok(())
    }

    /// Evaluation episodes of run 0 it records for replay (Keepaway's
    /// `--record`); none in the other domains.
    pub fn replays(&self) -> usize {
        match self {
            DomainSpec::Keepaway { config, .. } => config.record,
            _ => 0,
        }
    }

    /// The domain's command-line name.
    pub fn name(&self) -> &'static str {
        match self {
            DomainSpec::ParrRussell { .. } => "parr-russell",
            DomainSpec::Sutton { .. } => "sutton",
            DomainSpec::PenaltyKick { .. } => "penalty-kick",
            DomainSpec::Nmdp { .. } => "nmdp",
            DomainSpec::Keepaway { config, .. } => match config.mode {
                KeepawayMode::Pass => "keepaway-pass",
                KeepawayMode::Position => "keepaway-position",
                KeepawayMode::Fixed(_) => "keepaway-fixed",
            },
            DomainSpec::World { .. } => "world",
        }
    }

    /// What an episode's return measures, for axis labels and tables.
    pub(crate) fn score_name(&self) -> &'static str {
        match self {
            DomainSpec::Keepaway { .. } => "episode duration",
            _ => "return",
        }
    }

    /// The unit of the score: seconds in Keepaway, none elsewhere.
    pub fn score_unit(&self) -> &'static str {
        match self {
            DomainSpec::Keepaway { .. } => "s",
            _ => "",
        }
    }

    /// Whether nothing learns: the keepers follow a fixed policy.
    pub(crate) fn is_fixed_policy(&self) -> bool {
        matches!(
            self,
            DomainSpec::Keepaway {
                config: KeepawayDomainConfig {
                    mode: KeepawayMode::Fixed(_),
                    ..
                },
                ..
            }
        )
    }

    /// Whether an evaluation measures the policy with no evaluation episode:
    /// in Sutton's grid it runs the greedy policy from every start cell
    /// whatever `eval_episodes` says (`Sutton`'s [`crate::domains::Task::evaluate`]);
    /// elsewhere it is the mean return of `eval_episodes` episodes.
    pub(crate) fn evaluates_without_episodes(&self) -> bool {
        matches!(self, DomainSpec::Sutton { .. })
    }

    /// A known optimum to draw beside the curves: in Parr and Russell's and
    /// in Sutton's grid with the thesis's plan, the exact value of the best
    /// memoryless (deterministic) policy.
    pub fn reference(&self) -> Option<Reference> {
        let best = |value: f64| Reference {
            label: format!("best memoryless policy, exact: {value:.3}"),
            value,
        };
        match self {
            DomainSpec::ParrRussell { config, plan: None } => {
                parr_russell::optimum::optimum(config).map(|(_, value)| best(value))
            }
            DomainSpec::Sutton { config, plan: None } => Some(best(sutton::optimum::optimum(config).1)),
            _ => None,
        }
    }

    /// The plan file replacing the built-in plan, if any.
    pub fn plan_file(&self) -> Option<&Path> {
        match self {
            DomainSpec::ParrRussell { plan, .. }
            | DomainSpec::Sutton { plan, .. }
            | DomainSpec::PenaltyKick { plan, .. }
            | DomainSpec::Nmdp { plan, .. }
            | DomainSpec::Keepaway { plan, .. } => plan.as_deref(),
            DomainSpec::World { plans, .. } => plans.first().map(PathBuf::as_path),
        }
    }

    /// Every plan file of the experiment: a world's agents' plans, or the
    /// plan file replacing the built-in plan.
    pub fn plan_files(&self) -> Vec<&Path> {
        match self {
            DomainSpec::World { plans, .. } => plans.iter().map(PathBuf::as_path).collect(),
            other => other.plan_file().into_iter().collect(),
        }
    }

    /// Loads the plan once for every run (none for fixed Keepaway policies).
    pub fn load_plan(&self) -> Result<Option<Arc<Plan>>, ExperimentError> {
        let plan = match self {
            DomainSpec::Keepaway { plan: Some(p), .. } => load_plan(p, AllowedAtoms::Closed(&keepaway::atoms()))?,
            DomainSpec::Keepaway { config, plan: None } => match config.default_plan()? {
                Some(plan) => plan,
                None => return Ok(None),
            },
            DomainSpec::ParrRussell { plan: Some(p), .. } => {
                load_plan(p, AllowedAtoms::Closed(&parr_russell::atoms()))?
            }
            DomainSpec::ParrRussell { plan: None, .. } => parr_russell::default_plan()?,
            DomainSpec::Sutton { plan: Some(p), .. } => load_plan(p, AllowedAtoms::Closed(&sutton::atoms()))?,
            DomainSpec::Sutton { plan: None, .. } => sutton::default_plan()?,
            DomainSpec::PenaltyKick { plan: Some(p), .. } => load_plan(p, AllowedAtoms::Open)?,
            DomainSpec::PenaltyKick { config, plan: None } => penalty_kick::plan(config.variant)?,
            DomainSpec::Nmdp { plan: Some(p), .. } => load_plan(p, AllowedAtoms::Open)?,
            DomainSpec::Nmdp { plan: None, .. } => nmdp::plan()?,
            DomainSpec::World { plans, .. } => match plans.first() {
                Some(plan) => load_plan(plan, AllowedAtoms::Open)?,
                None => return Ok(None),
            },
        };
        for w in plan.warnings() {
            eprintln!("warning: {w}");
        }
        Ok(Some(Arc::new(plan)))
    }

    /// A task for one run; `learner` makes the learner of agent i.
    pub(crate) fn task(
        &self,
        plan: Option<Arc<Plan>>,
        learner: &mut dyn FnMut(usize) -> Box<dyn Learner>,
        rng: SimRng,
    ) -> Result<Box<dyn Task>, ExperimentError> {
        let needs_plan = || ExperimentError::Invalid(format!("{} needs a plan", self.name()));
        Ok(match self {
            DomainSpec::Keepaway { config, .. } => Box::new(KeepawayTask::new(*config, plan, learner, rng)?),
            DomainSpec::ParrRussell { config, .. } => Box::new(ParrRussell::new(
                *config,
                plan.ok_or_else(needs_plan)?,
                learner(0),
                rng,
            )?),
            DomainSpec::Sutton { config, .. } => {
                Box::new(Sutton::new(*config, plan.ok_or_else(needs_plan)?, learner(0), rng)?)
            }
            DomainSpec::PenaltyKick { config, .. } => {
                Box::new(PenaltyKick::new(*config, plan.ok_or_else(needs_plan)?, learner(0))?)
            }
            DomainSpec::Nmdp { config, .. } => {
                Box::new(Nmdp::new(*config, plan.ok_or_else(needs_plan)?, learner(0), rng)?)
            }
            DomainSpec::World { .. } => {
                return Err(ExperimentError::Invalid(
                    "a world in its own process is played by learnpnp-supervisor --world-cmd".into(),
                ));
            }
        })
    }
}

/// The algorithms of the experiment command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Algorithm {
    /// SoSMC with epsilon-greedy exploration.
    EpsSosmc,
    /// SoSMC with softmax exploration.
    SoftSosmc,
    /// Sarsa(lambda) with replacing traces.
    SarsaLambda,
    /// One-step Sarsa.
    Sarsa0,
    /// One-step Q-learning.
    QLearning,
    /// MCESP, sample-average variant.
    Mcesp,
    /// Uniform random choices, no learning (a baseline).
    Random,
}

crate::named::impl_named!(
    Algorithm,
    "algorithm",
    [
        EpsSosmc => "eps-sosmc",
        SoftSosmc => "soft-sosmc",
        SarsaLambda => "sarsa-lambda",
        Sarsa0 => "sarsa0",
        QLearning => "q-learning",
        Mcesp => "mcesp",
        Random => "random",
    ]
);

/// The learner's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "learner", rename_all = "kebab-case")]
pub enum LearnerSpec {
    /// A SoSMC learner.
    Sosmc(SoSmcConfig),
    /// A TD learner (Sarsa, Q-learning).
    Td(TdConfig),
    /// An MCESP learner.
    Mcesp(McespConfig),
    /// Uniform random choices.
    Random,
}

/// An out-of-range parameter as an [`ExperimentError`] naming it.
fn field<T>(name: &str, result: Result<T, String>) -> Result<(), ExperimentError> {
    result
        .map(drop)
        .map_err(|e| ExperimentError::Invalid(format!("{name}: {e}")))
}

/// The range of an exploration parameter: epsilon or temperature.
fn exploration_range(softmax: bool) -> (&'static str, ranges::RealRange) {
    if softmax {
        ("temperature", ranges::TEMPERATURE)
    } else {
        ("epsilon", ranges::EPSILON)
    }
}

impl LearnerSpec {
    /// Checks every parameter against its range ([`ranges`]).
    pub fn validate(&self) -> Result<(), ExperimentError> {
        match self {
            LearnerSpec::Sosmc(c) => {
                field("gamma", ranges::GAMMA.check(c.gamma))?;
                if let StepSize::Constant(a) = c.step_size {
                    field("step size", ranges::STEP.check(a))?;
                }
                field("initial value", ranges::check_initial_value(c.initial_value))?;
                let (name, range) = exploration_range(c.sigma == Sigma::Softmax);
                field(
                    &format!("initial-phase {name}"),
                    range.check_schedule(&c.initial_parameter),
                )?;
                field(
                    &format!("assessing {name}"),
                    range.check_schedule(&c.assessing_parameter),
                )?;
                if let Assessment::EveryN(n) = c.assessment {
                    field("assess every:N", ranges::WINDOW.check(n))?;
                }
                if let Some(rule) = c.threshold {
                    field("threshold", ranges::RETURN.check(rule.threshold))?;
                    field("threshold window", ranges::WINDOW.check(rule.window as u64))?;
                }
            }
            LearnerSpec::Td(c) => {
                field("gamma", ranges::GAMMA.check(c.gamma))?;
                field("alpha", ranges::STEP.check(c.alpha))?;
                field("lambda", ranges::LAMBDA.check(c.lambda))?;
                field("initial value", ranges::check_initial_value(c.initial_value))?;
                match c.exploration {
                    Exploration::Greedy => {}
                    Exploration::EpsilonGreedy(s) => field("epsilon", ranges::EPSILON.check_schedule(&s))?,
                    Exploration::Softmax(s) => field("temperature", ranges::TEMPERATURE.check_schedule(&s))?,
                }
            }
            LearnerSpec::Mcesp(c) => {
                field("gamma", ranges::GAMMA.check(c.gamma))?;
                field("stage length", ranges::STAGE_LENGTH.check(c.stage_length))?;
                field("alpha-min", ranges::STEP.check(c.alpha_min))?;
                field("initial value", ranges::check_initial_value(c.initial_value))?;
            }
            LearnerSpec::Random => {}
        }
        Ok(())
    }

    /// Whether this learner is the one `algorithm` names.
    fn is_for(&self, algorithm: Algorithm) -> bool {
        matches!(
            (self, algorithm),
            (LearnerSpec::Sosmc(_), Algorithm::EpsSosmc | Algorithm::SoftSosmc)
                | (
                    LearnerSpec::Td(_),
                    Algorithm::SarsaLambda | Algorithm::Sarsa0 | Algorithm::QLearning
                )
                | (LearnerSpec::Mcesp(_), Algorithm::Mcesp)
                | (LearnerSpec::Random, Algorithm::Random)
        )
    }

    /// A learner drawing from `rng`.
    pub fn build(&self, rng: SimRng) -> Box<dyn Learner> {
        match self {
            LearnerSpec::Sosmc(c) => Box::new(SoSmc::new(*c, rng)),
            LearnerSpec::Td(c) => Box::new(TdLearner::new(*c, rng)),
            LearnerSpec::Mcesp(c) => Box::new(Mcesp::new(*c, rng)),
            LearnerSpec::Random => Box::new(RandomLearner::new(rng)),
        }
    }
}

/// The thesis's evaluation protocol: every `eval_every` learning episodes,
/// learning pauses and `eval_episodes` episodes run with values frozen.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Protocol {
    /// Independent runs.
    pub runs: usize,
    /// Learning episodes per run.
    pub episodes: u64,
    /// Learning episodes between evaluations.
    pub eval_every: u64,
    /// Episodes per evaluation.
    pub eval_episodes: usize,
    /// Episodes of the final greedy evaluation of each run.
    pub greedy_episodes: usize,
    /// Record the traced values of run 0 every this many learning episodes
    /// (0: never); `None` picks about a thousand points over the run.
    #[serde(default)]
    pub trace_every: Option<u64>,
}

impl Protocol {
    /// Learning episodes between two recordings of the traced values (0: none).
    pub(crate) fn trace_interval(&self) -> u64 {
        self.trace_every.unwrap_or((self.episodes / 1000).max(1))
    }

    /// Checks every number against its range ([`ranges`]).
    pub fn validate(&self) -> Result<(), ExperimentError> {
        field("runs", ranges::RUNS.check(self.runs as u64))?;
        field("episodes", ranges::EPISODES.check(self.episodes))?;
        field(
            "eval-every",
            ranges::eval_every(self.episodes).check(self.eval_every).map_err(|e| {
                format!("{e} (an evaluation interval longer than the run evaluates only the initial policy)")
            }),
        )?;
        field("eval-episodes", ranges::EVAL_EPISODES.check(self.eval_episodes as u64))?;
        field(
            "greedy-episodes",
            ranges::EVAL_EPISODES.check(self.greedy_episodes as u64),
        )?;
        if let Some(every) = self.trace_every {
            field("trace-every", ranges::WHOLE.check(every))?;
        }
        Ok(())
    }

    /// The learning episode counts after which evaluations happen (0 first).
    pub fn eval_points(&self) -> Vec<u64> {
        (0..=self.episodes / self.eval_every)
            .map(|i| i * self.eval_every)
            .collect()
    }
}

/// One experiment: a curve of a figure.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExperimentSpec {
    /// A label for plots and tables.
    pub label: String,
    /// The domain.
    pub domain: DomainSpec,
    /// The algorithm's name.
    pub algorithm: Algorithm,
    /// Its parameters.
    pub learner: LearnerSpec,
    /// The protocol.
    pub protocol: Protocol,
    /// The base seed; run i uses a seed derived from it and i.
    pub seed: u64,
    /// Value tables every run starts from (one per learning agent, as an
    /// experiment saves them), instead of the initial value.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub initial_values: Vec<PathBuf>,
}

impl ExperimentSpec {
    /// Checks every parameter against its range and the learner against the
    /// algorithm: what the command line's flags guarantee as they are parsed,
    /// for specs from anywhere else.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        self.protocol.validate()?;
        self.domain.validate()?;
        self.learner.validate()?;
        if !self.learner.is_for(self.algorithm) {
            return Err(ExperimentError::Invalid(format!(
                "the learner's parameters are not those of {}",
                self.algorithm.name()
            )));
        }
        Ok(())
    }

    /// Refuses a plan file that fails the structural checks of `learnpnp
    /// check` (thesis 2.3: an execution place marked twice, a transition that
    /// never fires, a marking from which no goal is reachable, a dead marking
    /// that is neither goal nor fail), exploring at most
    /// [`analysis::DEFAULT_LIMIT`] markings; a plan schema, the checks of its
    /// process ([`schema::check_report`]). A check left inconclusive by that
    /// limit is no refusal. The built-in plans are not checked here (their
    /// tests check them).
    pub(crate) fn check_plan(&self) -> Result<(), ExperimentError> {
        if let DomainSpec::World { plans, .. } = &self.domain {
            for path in plans {
                check_plan_file(path, &load_plan(path, AllowedAtoms::Open)?)?;
            }
            return Ok(());
        }
        let Some(path) = self.domain.plan_file() else {
            return Ok(());
        };
        let Some(plan) = self.domain.load_plan()? else {
            return Ok(());
        };
        check_plan_file(path, &plan)
    }
}

/// Runs `learnpnp check` on `plan`, loaded from `path`: an error listing
/// the failures if it fails.
fn check_plan_file(path: &Path, plan: &Plan) -> Result<(), ExperimentError> {
    let failures: Vec<String> = if schema::is_schema_path(path) {
        // A schema's process has checks of its own (`learnpnp check x.schema`).
        let process =
            schema::load_process(path, AllowedAtoms::Open).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
        let (report, passed) = schema::check_report(&process);
        if passed {
            Vec::new()
        } else {
            schema::check_failures(&report)
        }
    } else {
        let report = analysis::check(plan, analysis::DEFAULT_LIMIT);
        report.failures.iter().map(|f| f.to_string()).collect()
    };
    if failures.is_empty() {
        return Ok(());
    }
    Err(ExperimentError::FailsCheck {
        path: path.to_path_buf(),
        failures,
    })
}

impl ExperimentSpec {
    /// Reads a spec from JSON (as `summary.json` holds it, under `spec`) and
    /// validates it: the way to load a spec from a file.
    pub fn from_json(text: &str) -> Result<ExperimentSpec, ExperimentError> {
        let spec: ExperimentSpec =
            serde_json::from_str(text).map_err(|e| ExperimentError::Invalid(format!("not an experiment spec: {e}")))?;
        spec.validate()?;
        Ok(spec)
    }

    /// Loads the starting tables, carried into this plan: a table learned on
    /// this very plan is used as saved; one learned on an earlier revision of
    /// it is mapped onto its places ([`migrate::migrate`]); one that shares
    /// nothing with it is an error saying what differs. A file that cannot be
    /// used is an error (see [`persist::load_latest`] for reading its previous
    /// good version instead).
    pub fn load_initial_values(&self, plan: Option<&Plan>) -> Result<Vec<SavedValues>, ExperimentError> {
        Ok(self
            .migrate_initial_values(plan)?
            .into_iter()
            .map(|(_, values, _)| values)
            .collect())
    }

    /// The starting tables as [`ExperimentSpec::load_initial_values`] loads
    /// them, each with its path and what its migration did.
    pub fn migrate_initial_values(
        &self,
        plan: Option<&Plan>,
    ) -> Result<Vec<(PathBuf, SavedValues, MigrationReport)>, ExperimentError> {
        let mut tables = Vec::new();
        for path in &self.initial_values {
            let saved = persist::load(path).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
            let Some(plan) = plan else {
                if let Some(difference) = plan_difference(&saved.plans, &[]) {
                    return Err(ExperimentError::Invalid(format!(
                        "{}: the values were learned on another plan: {difference}",
                        path.display()
                    )));
                }
                let report = MigrationReport {
                    unchanged: true,
                    kept: saved.entries.len(),
                    ..MigrationReport::default()
                };
                tables.push((path.clone(), saved, report));
                continue;
            };
            let (values, report) = migrate::migrate(&saved, &plan.activation_plans())
                .map_err(|e| ExperimentError::Invalid(format!("{}: {e}", path.display())))?;
            tables.push((path.clone(), values, report));
        }
        Ok(tables)
    }
}

/// How the plans a table was learned on differ from the plans it is loaded
/// into, in words; `None` when they are the same.
fn plan_difference(saved: &[PlanLabels], expected: &[PlanLabels]) -> Option<String> {
    let names = |plans: &[PlanLabels]| plans.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ");
    if saved.len() != expected.len() {
        return Some(format!(
            "the table has {} plan(s) ({}), the experiment {} ({})",
            saved.len(),
            names(saved),
            expected.len(),
            names(expected)
        ));
    }
    for (s, e) in saved.iter().zip(expected) {
        if s.name != e.name {
            return Some(format!(
                "the table's plan is '{}', the experiment's '{}'",
                s.name, e.name
            ));
        }
        if s.places.len() != e.places.len() {
            return Some(format!(
                "plan '{}' has {} place(s) in the table and {} in the experiment",
                s.name,
                s.places.len(),
                e.places.len()
            ));
        }
        if let Some(i) = (0..s.places.len()).find(|&i| s.places[i] != e.places[i]) {
            let mut sorted_saved = s.places.clone();
            let mut sorted_expected = e.places.clone();
            sorted_saved.sort();
            sorted_expected.sort();
            let reordered = if sorted_saved == sorted_expected {
                " (the same places in another order: the plan file was edited or re-saved)"
            } else {
                ""
            };
            return Some(format!(
                "in plan '{}', place {i} is '{}' in the table but '{}' in the experiment{reordered}",
                s.name, s.places[i], e.places[i]
            ));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn labels(name: &str, places: &[&str]) -> PlanLabels {
        PlanLabels {
            name: name.into(),
            places: places.iter().map(|p| p.to_string()).collect(),
        }
    }

    #[test]
    fn a_value_table_for_another_plan_is_told_apart_by_its_difference() {
        let plan = [labels("kick", &["start", "Turn.exec", "goal"])];
        assert_eq!(plan_difference(&plan, &plan), None);
        let reordered = [labels("kick", &["Turn.exec", "start", "goal"])];
        let text = plan_difference(&reordered, &plan).expect("differs");
        assert!(
            text.contains("place 0 is 'Turn.exec' in the table but 'start' in the experiment")
                && text.contains("same places in another order"),
            "{text}"
        );
        let renamed = [labels("kick", &["start", "Walk.exec", "goal"])];
        let text = plan_difference(&renamed, &plan).expect("differs");
        assert!(text.contains("place 1") && !text.contains("another order"), "{text}");
        let text = plan_difference(&[labels("grid", &["a"])], &plan).expect("differs");
        assert!(text.contains("'grid'") && text.contains("'kick'"), "{text}");
        let text = plan_difference(&[labels("kick", &["start"])], &plan).expect("differs");
        assert!(text.contains("1 place(s) in the table and 3"), "{text}");
        let text = plan_difference(&[], &plan).expect("differs");
        assert!(text.contains("0 plan(s)"), "{text}");
    }
}
