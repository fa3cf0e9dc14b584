//! The options of an experiment as a user states them (the flags of
//! `learnpnp experiment` and of the multi-process supervisor, the keyword
//! arguments from Python): a domain, an algorithm with its parameters, and the
//! protocol, turned into an [`ExperimentSpec`](crate::experiment::spec::ExperimentSpec). Each value is checked where it
//! is parsed, against the ranges of [`super::ranges`](crate::experiment::ranges).

use std::path::PathBuf;

use super::defaults::{self, Overrides};
use super::spec::{Algorithm, DomainSpec, ExperimentError, ExperimentSpec};
use crate::domains::keepaway::{KeepawayDomainConfig, KeepawayMode, KeepawayOptions};
use crate::domains::nmdp::NmdpConfig;
use crate::domains::parr_russell::ParrRussellConfig;
use crate::domains::penalty_kick::{PenaltyKickConfig, Variant};
use crate::domains::sutton::SuttonConfig;
use crate::learning::persist;
use crate::named::Named;

/// The domains of the experiment command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DomainName {
    /// Parr and Russell's 4 x 3 grid.
    ParrRussell,
    /// Sutton's 9 x 6 grid.
    Sutton,
    /// The penalty kick.
    PenaltyKick,
    /// The small N-MDP of thesis Figure 4.3.
    Nmdp,
    /// Keepaway 3 vs 2, one keeper learning the pass decision (thesis 7.2).
    KeepawayPass,
    /// Keepaway 3 vs 2, every keeper learning where to stand (thesis 7.3).
    KeepawayPosition,
    /// Keepaway 3 vs 2 with a fixed policy (`--policy`); nothing learns.
    KeepawayFixed,
}

crate::named::impl_named!(
    DomainName,
    "domain",
    [
        ParrRussell => "parr-russell",
        Sutton => "sutton",
        PenaltyKick => "penalty-kick",
        Nmdp => "nmdp",
        KeepawayPass => "keepaway-pass",
        KeepawayPosition => "keepaway-position",
        KeepawayFixed => "keepaway-fixed",
    ]
);

/// Everything about an experiment but the domain and where results go: the
/// algorithm, its parameters, the protocol and the domain's options. `None`
/// (or the [`Default`]) leaves the domain's or algorithm's default.
#[derive(Debug, Clone, Default)]
pub struct ExperimentOptions {
    /// The learning algorithm (not needed for keepaway-fixed).
    pub algo: Option<Algorithm>,
    /// Independent runs.
    pub runs: Option<usize>,
    /// Learning episodes per run.
    pub episodes: Option<u64>,
    /// Learning episodes between evaluations.
    pub eval_every: Option<u64>,
    /// Episodes per evaluation (values frozen, behaviour as while learning).
    pub eval_episodes: Option<usize>,
    /// Episodes of each run's final greedy evaluation.
    pub greedy_episodes: Option<usize>,
    /// Record run 0's traced values every N learning episodes (0: never).
    pub trace_every: Option<u64>,
    /// Base seed (run i uses a seed derived from it and i); `None`: the presets' seed.
    pub seed: Option<u64>,
    /// A label for plots (default: the algorithm).
    pub label: Option<String>,
    /// Value tables every run starts from instead of the initial value.
    pub initial_values: Vec<PathBuf>,
    /// Start from an unusable initial-values file's previous good version.
    pub initial_values_fallback: bool,
    /// A plan file in place of the domain's built-in plan.
    pub plan: Option<PathBuf>,
    /// Run a plan that fails the structural checks.
    pub unchecked: bool,
    /// Grid worlds: actions after which an episode is cut.
    pub max_actions: Option<u32>,
    /// Penalty kick plan variant.
    pub variant: Variant,
    /// Keepaway's options.
    pub keepaway: KeepawayOptions,
    /// The learner's parameters the user set.
    pub learner: Overrides,
}

impl ExperimentOptions {
    /// The domain `name` with these options.
    pub fn domain(&self, name: DomainName) -> DomainSpec {
        let plan = self.plan.clone();
        match name {
            DomainName::ParrRussell => {
                let mut config = ParrRussellConfig::default();
                if let Some(m) = self.max_actions {
                    config.max_actions = m;
                }
                DomainSpec::ParrRussell { config, plan }
            }
            DomainName::Sutton => {
                let mut config = SuttonConfig::default();
                if let Some(m) = self.max_actions {
                    config.max_actions = m;
                }
                DomainSpec::Sutton { config, plan }
            }
            DomainName::PenaltyKick => DomainSpec::PenaltyKick {
                config: PenaltyKickConfig {
                    variant: self.variant,
                    ..Default::default()
                },
                plan,
            },
            DomainName::Nmdp => DomainSpec::Nmdp {
                config: NmdpConfig::default(),
                plan,
            },
            DomainName::KeepawayPass => DomainSpec::Keepaway {
                config: self.keepaway.config(KeepawayMode::Pass),
                plan,
            },
            DomainName::KeepawayPosition => DomainSpec::Keepaway {
                config: self.keepaway.config(KeepawayMode::Position),
                plan,
            },
            DomainName::KeepawayFixed => DomainSpec::Keepaway {
                config: self.keepaway.config(KeepawayMode::Fixed(self.keepaway.policy)),
                plan,
            },
        }
    }

    /// These options with `algo`, `runs` and `episodes` where the user gave none.
    pub fn or_defaults(mut self, algo: Algorithm, runs: usize, episodes: u64) -> Self {
        self.algo.get_or_insert(algo);
        self.runs.get_or_insert(runs);
        self.episodes.get_or_insert(episodes);
        self
    }

    /// The experiment these options describe in domain `name`.
    pub fn spec(&self, name: DomainName) -> Result<ExperimentSpec, ExperimentError> {
        self.spec_for(self.domain(name))
    }

    /// The experiment these options describe in `domain` (a world in its
    /// own process, which has no name of its own on the command line).
    pub fn spec_for(&self, domain: DomainSpec) -> Result<ExperimentSpec, ExperimentError> {
        if self.keepaway.record > 0 && !matches!(domain, DomainSpec::Keepaway { .. }) {
            return Err(ExperimentError::Invalid(format!(
                "--record saves Keepaway episodes as game logs; {} has none",
                domain.name()
            )));
        }
        let algo = match self.algo {
            Some(a) => a,
            None if domain.is_fixed_policy() => Algorithm::Random,
            None => {
                return Err(ExperimentError::Invalid(format!(
                    "--algo is needed for {}",
                    domain.name()
                )));
            }
        };
        let mut learner = defaults::default_learner(algo, &domain);
        self.learner.apply(&mut learner);
        let mut protocol = defaults::default_protocol(&domain);
        if let Some(v) = self.runs {
            protocol.runs = v;
        }
        if let Some(v) = self.episodes {
            protocol.episodes = v;
        }
        match self.eval_every {
            Some(v) => protocol.eval_every = v,
            // The domain's interval, but no longer than the run.
            None => protocol.eval_every = protocol.eval_every.min(protocol.episodes),
        }
        if let Some(v) = self.eval_episodes {
            protocol.eval_episodes = v;
        }
        if let Some(v) = self.greedy_episodes {
            protocol.greedy_episodes = v;
        }
        if self.trace_every.is_some() {
            protocol.trace_every = self.trace_every;
        }
        let label = match domain {
            DomainSpec::Keepaway {
                config:
                    KeepawayDomainConfig {
                        mode: KeepawayMode::Fixed(p),
                        ..
                    },
                ..
            } => format!("{p:?}").to_lowercase(),
            _ => algo.name().to_string(),
        };
        let spec = ExperimentSpec {
            label: self.label.clone().unwrap_or(label),
            domain,
            algorithm: algo,
            learner,
            protocol,
            seed: self.seed.unwrap_or(defaults::DEFAULT_SEED),
            initial_values: self.initial_values_to_use()?,
        };
        spec.validate()?;
        if !self.unchecked {
            spec.check_plan()?;
        }
        Ok(spec)
    }

    /// The `--initial-values` files, each replaced by its previous good
    /// version when it is unusable and `--initial-values-fallback` allows it.
    fn initial_values_to_use(&self) -> Result<Vec<PathBuf>, ExperimentError> {
        self.initial_values
            .iter()
            .map(|path| match persist::load(path) {
                Ok(_) => Ok(path.clone()),
                Err(problem) if self.initial_values_fallback => {
                    let prev = persist::prev_path(path);
                    persist::load(&prev).map_err(|e| {
                        ExperimentError::Invalid(format!("{problem}; its previous version is unusable too: {e}"))
                    })?;
                    eprintln!("warning: {problem}; starting from {} instead", prev.display());
                    Ok(prev)
                }
                Err(problem) => Err(ExperimentError::Invalid(format!(
                    "{problem} (--initial-values-fallback starts from its previous good version, {}, if there is one)",
                    persist::prev_path(path).display()
                ))),
            })
            .collect()
    }
}
