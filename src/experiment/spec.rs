//! What an experiment runs: a domain, an algorithm with its parameters, and the protocol.

use std::path::PathBuf;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::plot::Reference;
use crate::domains::keepaway::{self, KeepawayDomainConfig, KeepawayMode, KeepawayTask};
use crate::domains::parr_russell::{self, ParrRussell, ParrRussellConfig};
use crate::domains::penalty_kick::{self, PenaltyKick, PenaltyKickConfig};
use crate::domains::sutton::{self, Sutton, SuttonConfig};
use crate::domains::{Task, TaskError};
use crate::learning::persist::{self, PlanLabels, SavedValues};
use crate::learning::{Learner, Mcesp, McespConfig, RandomLearner, SoSmc, SoSmcConfig, TdConfig, TdLearner};
use crate::plan::{LoadError, Plan, Vocabulary, load_plan};
use crate::rng::SimRng;

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
    /// Keepaway 3 vs 2.
    Keepaway {
        /// Who learns, and the abstraction's thresholds.
        config: KeepawayDomainConfig,
        /// A plan file for the learning keepers instead of the thesis's plan.
        plan: Option<PathBuf>,
    },
}

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
    /// Writing results failed.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

impl DomainSpec {
    /// The domain's command-line name.
    pub fn name(&self) -> &'static str {
        match self {
            DomainSpec::ParrRussell { .. } => "parr-russell",
            DomainSpec::Sutton { .. } => "sutton",
            DomainSpec::PenaltyKick { .. } => "penalty-kick",
            DomainSpec::Keepaway { config, .. } => match config.mode {
                KeepawayMode::Pass => "keepaway-pass",
                KeepawayMode::Position => "keepaway-position",
                KeepawayMode::Fixed(_) => "keepaway-fixed",
            },
        }
    }

    /// What an episode's return measures, for axis labels and tables.
    pub fn score_name(&self) -> &'static str {
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
    pub fn is_fixed_policy(&self) -> bool {
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

    /// A known optimum to draw beside the curves: in Parr and Russell's grid
    /// with the thesis's plan, the exact value of the best memoryless policy.
    pub fn reference(&self) -> Option<Reference> {
        match self {
            DomainSpec::ParrRussell { config, plan: None } => {
                parr_russell::optimum::optimum(config).map(|(_, value)| Reference {
                    label: format!("best memoryless policy, exact: {value:.3}"),
                    value,
                })
            }
            _ => None,
        }
    }

    /// Loads the plan once for every run (none for fixed Keepaway policies).
    pub fn load_plan(&self) -> Result<Option<Arc<Plan>>, ExperimentError> {
        let plan = match self {
            DomainSpec::Keepaway { plan: Some(p), .. } => load_plan(p, Vocabulary::Closed(&keepaway::atoms()))?,
            DomainSpec::Keepaway { config, plan: None } => match config.default_plan()? {
                Some(plan) => plan,
                None => return Ok(None),
            },
            DomainSpec::ParrRussell { plan: Some(p), .. } => load_plan(p, Vocabulary::Closed(&parr_russell::atoms()))?,
            DomainSpec::ParrRussell { plan: None, .. } => parr_russell::default_plan()?,
            DomainSpec::Sutton { plan: Some(p), .. } => load_plan(p, Vocabulary::Closed(&sutton::atoms()))?,
            DomainSpec::Sutton { plan: None, .. } => sutton::default_plan()?,
            DomainSpec::PenaltyKick { plan: Some(p), .. } => load_plan(p, Vocabulary::Open)?,
            DomainSpec::PenaltyKick { config, plan: None } => penalty_kick::plan(config.variant)?,
        };
        for w in plan.warnings() {
            eprintln!("warning: {w}");
        }
        Ok(Some(Arc::new(plan)))
    }

    /// A task for one run; `learner` makes the learner of agent i.
    pub fn task(
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
        })
    }
}

/// The algorithms of the experiment command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, clap::ValueEnum)]
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

impl Algorithm {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Algorithm::EpsSosmc => "eps-sosmc",
            Algorithm::SoftSosmc => "soft-sosmc",
            Algorithm::SarsaLambda => "sarsa-lambda",
            Algorithm::Sarsa0 => "sarsa0",
            Algorithm::QLearning => "q-learning",
            Algorithm::Mcesp => "mcesp",
            Algorithm::Random => "random",
        }
    }
}

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

impl LearnerSpec {
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
    pub fn trace_interval(&self) -> u64 {
        self.trace_every.unwrap_or((self.episodes / 1000).max(1))
    }

    /// Checks the numbers.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        if self.runs == 0 || self.episodes == 0 || self.eval_every == 0 {
            return Err(ExperimentError::Invalid(
                "runs, episodes and eval-every must be positive".into(),
            ));
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
    /// Keepaway: evaluation episodes of run 0, played after its last
    /// evaluation, to save as RoboCup game logs (they change no result).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub record: usize,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl ExperimentSpec {
    /// Loads the starting tables, checking each was learned on this plan.
    /// A corrupt file is reported and its previous good version used.
    pub fn load_initial_values(&self, plan: Option<&Plan>) -> Result<Vec<SavedValues>, ExperimentError> {
        let mut tables = Vec::new();
        for path in &self.initial_values {
            let (saved, problem) = persist::load_latest(path).map_err(|e| ExperimentError::Invalid(e.to_string()))?;
            if let Some(problem) = problem {
                eprintln!("warning: {problem}; using {}", persist::prev_path(path).display());
            }
            let expected: Vec<PlanLabels> = plan
                .map(|p| p.activation_plans().into_iter().map(PlanLabels::of).collect())
                .unwrap_or_default();
            if saved.plans != expected {
                return Err(ExperimentError::Invalid(format!(
                    "{}: the values were learned on another plan ({})",
                    path.display(),
                    saved
                        .plans
                        .iter()
                        .map(|p| p.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            }
            tables.push(saved);
        }
        Ok(tables)
    }
}
