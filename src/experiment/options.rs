//! The options of an experiment as a user states them (the flags of
//! `learnpnp experiment` and of the multi-process supervisor, the keyword
//! arguments from Python): a domain, an algorithm with its parameters, and the
//! protocol, turned into an [`ExperimentSpec`](crate::experiment::spec::ExperimentSpec). Each value is checked where it
//! is parsed, against the ranges of [`super::ranges`](crate::experiment::ranges).

use std::path::PathBuf;

use clap::Args;
use clap::builder::{PossibleValuesParser, TypedValueParser};

use super::defaults::{self, Overrides};
use super::ranges;
use super::spec::{Algorithm, DomainSpec, ExperimentError, ExperimentSpec};
use crate::domains::keepaway::{FixedPolicy, KeepawayDomainConfig, KeepawayMode};
use crate::domains::nmdp::NmdpConfig;
use crate::domains::parr_russell::ParrRussellConfig;
use crate::domains::penalty_kick::{PenaltyKickConfig, Variant};
use crate::domains::sutton::SuttonConfig;
use crate::learning::persist;
use crate::named::Named;
use learnpnp_keepaway::params::{RefereeRule, ServerTimer, VisionMode};

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
/// algorithm, its parameters, the protocol and the domain's options, each
/// declared once with its flag of `learnpnp experiment` (the multi-process
/// supervisor takes the same flags). `None` (or the [`Default`]) leaves the
/// domain's or algorithm's default.
#[derive(Args, Debug, Clone, Default)]
pub struct ExperimentOptions {
    /// The learning algorithm (not needed for keepaway-fixed).
    #[arg(long, value_parser = named::<Algorithm>())]
    pub algo: Option<Algorithm>,
    /// Independent runs (default: the domain's; 1 to 100000).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::RUNS.parse_usize(s))]
    pub runs: Option<usize>,
    /// Learning episodes per run (1 to 10^9).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::EPISODES.parse(s))]
    pub episodes: Option<u64>,
    /// Learning episodes between evaluations (1 to --episodes).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::eval_every(u64::MAX).parse(s))]
    pub eval_every: Option<u64>,
    /// Episodes per evaluation (values frozen, behaviour as while learning; 0 to 10^6).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::EVAL_EPISODES.parse_usize(s))]
    pub eval_episodes: Option<usize>,
    /// Episodes of each run's final greedy evaluation (0 to 10^6).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::EVAL_EPISODES.parse_usize(s))]
    pub greedy_episodes: Option<usize>,
    /// Record run 0's traced values every N learning episodes (0: never;
    /// default: about a thousand points).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::WHOLE.parse(s))]
    pub trace_every: Option<u64>,
    /// Base seed (run i uses a seed derived from it and i); the presets' by default.
    // The default is `defaults::DEFAULT_SEED` (a test holds them equal): clap
    // shows an `Option`'s default only as text.
    #[arg(long, default_value = "2011", allow_hyphen_values = true, value_parser = |s: &str| ranges::WHOLE.parse(s))]
    pub seed: Option<u64>,
    /// A label for plots (default: the algorithm).
    #[arg(long)]
    pub label: Option<String>,
    /// Start every run from these saved value tables (values.bin, then
    /// values-agent2.bin, ... for several learning agents) instead of the initial value.
    #[arg(long, num_args = 1..)]
    pub initial_values: Vec<PathBuf>,
    /// When an --initial-values file is unusable (corrupt, truncated), start
    /// from its previous good version (FILE.prev) instead of refusing; the
    /// summary then names the file used.
    #[arg(long, requires = "initial_values")]
    pub initial_values_fallback: bool,
    /// Use this plan file instead of the domain's built-in plan.
    #[arg(long)]
    pub plan: Option<PathBuf>,
    /// Run a --plan that fails the structural checks of `learnpnp check`
    /// (for experts: learning in a plan that can deadlock or run an action
    /// twice at once gives meaningless numbers).
    #[arg(long, requires = "plan")]
    pub unchecked: bool,
    /// Actions after which an episode is cut (grid worlds; at least 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::MAX_ACTIONS.parse_u32(s))]
    pub max_actions: Option<u32>,
    /// Penalty kick plan variant.
    #[arg(long, value_parser = named::<Variant>(), default_value = "plain")]
    pub variant: Variant,
    /// Keepaway's options.
    #[command(flatten)]
    pub keepaway: KeepawayOptions,
    /// The learner's parameters the user set.
    #[command(flatten)]
    pub learner: Overrides,
}

/// Keepaway's options of an experiment as a user states them (its flags of
/// `learnpnp experiment` and of the supervisor); `None` leaves the domain's default.
#[derive(Args, Debug, Clone, Copy, Default, PartialEq)]
pub struct KeepawayOptions {
    /// Keepaway: save N evaluation episodes of run 0, played after learning,
    /// as RoboCup game logs (DIR/replays/episode-NN.rcg; watch them with
    /// `learnpnp replay` or rcssmonitor).
    #[arg(long, value_name = "N", default_value_t = 0, allow_hyphen_values = true, value_parser = |s: &str| ranges::RECORD.parse_usize(s))]
    pub record: usize,
    /// Keepaway: the keepers' policy for keepaway-fixed.
    #[arg(long, value_parser = named::<FixedPolicy>(), default_value = "handcoded")]
    pub policy: FixedPolicy,
    /// Keepaway: what the agents perceive.
    #[arg(long, value_parser = named::<VisionMode>(), default_value = "framework")]
    pub vision: VisionMode,
    /// Keepaway: the soccer server's timer, which fixes when the players see
    /// (framework vision): real-time (as keepaway.sh ran it; the players
    /// synchronise their sees) or synchronous (synch_mode, think at 80 ms).
    #[arg(long = "server-timer", value_name = "SERVER_TIMER", value_parser = named::<ServerTimer>(), default_value = "real-time")]
    pub timer: ServerTimer,
    /// Keepaway: the referee's turnover rule: rcssserver-11 (4 cycles of taker
    /// possession) or rcssserver-9.4.5 (5 cycles; its smaller possession area is
    /// not known and not ported).
    #[arg(long, value_parser = named::<RefereeRule>(), default_value = "rcssserver-11")]
    pub referee: RefereeRule,
    /// Keepaway: distance (m) at which the threshold policy passes (0 to 200).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::DISTANCE.parse(s))]
    pub hold_threshold: Option<f64>,
    /// Keepaway: threshold (m) of the takers' distance to a pass line (0 to 200).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::DISTANCE.parse(s))]
    pub lane_threshold: Option<f64>,
    /// Keepaway: threshold (m) of the closest taker's distance (0 to 200).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::DISTANCE.parse(s))]
    pub taker_threshold: Option<f64>,
}

impl KeepawayOptions {
    /// The configuration of `mode` with these options.
    pub fn config(&self, mode: KeepawayMode) -> KeepawayDomainConfig {
        let mut config = KeepawayDomainConfig::for_mode(mode);
        config.vision = self.vision;
        config.timer = self.timer;
        config.referee = self.referee;
        config.record = self.record;
        if let Some(t) = self.hold_threshold {
            config.hold_threshold = t;
        }
        if let Some(t) = self.lane_threshold {
            config.thresholds.pass_line = t;
        }
        if let Some(t) = self.taker_threshold {
            config.thresholds.closest_taker = t;
        }
        config
    }
}

/// A value parser for an enumeration picked by name: clap lists the names in
/// `--help` and refuses any other.
pub fn named<T: Named + Send + Sync + Clone>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|v| v.name()))
        .map(|name| T::from_name(&name).expect("clap accepts only the possible values"))
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

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Flags {
        #[command(flatten)]
        options: ExperimentOptions,
    }

    #[test]
    fn flags_left_out_take_the_defaults() {
        let options = Flags::try_parse_from(["learnpnp"]).expect("no flags").options;
        assert_eq!(options.seed, Some(defaults::DEFAULT_SEED));
        assert_eq!(options.keepaway, KeepawayOptions::default());
        assert_eq!(options.learner, Overrides::NONE);
        assert_eq!(options.variant, Variant::default());
    }
}
