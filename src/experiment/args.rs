//! The flags of `learnpnp experiment` (and of the multi-process supervisor):
//! a domain, an algorithm with its parameters, and the protocol, turned into
//! an [`ExperimentSpec`].

use std::path::PathBuf;

use clap::{Args, ValueEnum};

use super::defaults::{self, AssessmentArg, Overrides, parse_schedule, parse_step_size, parse_threshold};
use super::ranges;
use super::spec::{Algorithm, DomainSpec, ExperimentError, ExperimentSpec};
use crate::domains::keepaway::{FixedPolicy, KeepawayDomainConfig, KeepawayMode};
use crate::domains::parr_russell::ParrRussellConfig;
use crate::domains::penalty_kick::{PenaltyKickConfig, Variant};
use crate::domains::sutton::SuttonConfig;
use crate::keepaway::params::VisionMode;
use crate::learning::persist;
use crate::learning::{Schedule, StepSize, ThresholdRule};

/// The domains of the experiment command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DomainName {
    /// Parr and Russell's 4 x 3 grid.
    ParrRussell,
    /// Sutton's 9 x 6 grid.
    Sutton,
    /// The penalty kick.
    PenaltyKick,
    /// Keepaway 3 vs 2, one keeper learning the pass decision (thesis 7.2).
    KeepawayPass,
    /// Keepaway 3 vs 2, every keeper learning where to stand (thesis 7.3).
    KeepawayPosition,
    /// Keepaway 3 vs 2 with a fixed policy (`--policy`); nothing learns.
    KeepawayFixed,
}

/// What Keepaway agents perceive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum VisionArg {
    /// Noise-free full state.
    FullState,
    /// The server's quantised vision.
    Quantised,
}

/// Every flag of `learnpnp experiment` but the domain and where results go:
/// the algorithm, its parameters, the protocol and the domain's options.
/// The multi-process supervisor takes the same flags.
#[derive(Args, Debug, Clone)]
pub struct ExperimentOptions {
    /// The learning algorithm (not needed for keepaway-fixed).
    #[arg(long, value_enum)]
    algo: Option<Algorithm>,
    /// Independent runs (default: the domain's; 1 to 100000).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::RUNS.parse_usize(s))]
    runs: Option<usize>,
    /// Learning episodes per run (1 to 10^9).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::EPISODES.parse(s))]
    episodes: Option<u64>,
    /// Learning episodes between evaluations (1 to --episodes).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::eval_every(u64::MAX).parse(s))]
    eval_every: Option<u64>,
    /// Episodes per evaluation (values frozen, behaviour as while learning; 0 to 10^6).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::EVAL_EPISODES.parse_usize(s))]
    eval_episodes: Option<usize>,
    /// Episodes of each run's final greedy evaluation (0 to 10^6).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::EVAL_EPISODES.parse_usize(s))]
    greedy_episodes: Option<usize>,
    /// Record run 0's traced values every N learning episodes (0: never;
    /// default: about a thousand points).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::WHOLE.parse(s))]
    trace_every: Option<u64>,
    /// Base seed (run i uses a seed derived from it and i); the presets' by default.
    #[arg(long, default_value_t = defaults::DEFAULT_SEED, allow_hyphen_values = true, value_parser = |s: &str| ranges::WHOLE.parse(s))]
    seed: u64,
    /// A label for plots (default: the algorithm).
    #[arg(long)]
    label: Option<String>,
    /// Keepaway: save N evaluation episodes of run 0, played after learning,
    /// as RoboCup game logs (DIR/replays/episode-NN.rcg; watch them with
    /// `learnpnp replay` or rcssmonitor).
    #[arg(long, value_name = "N", default_value_t = 0, allow_hyphen_values = true, value_parser = |s: &str| ranges::RECORD.parse_usize(s))]
    record: usize,

    /// Start every run from these saved value tables (values.bin, then
    /// values-agent2.bin, ... for several learning agents) instead of the initial value.
    #[arg(long, num_args = 1..)]
    initial_values: Vec<PathBuf>,
    /// When an --initial-values file is unusable (corrupt, truncated), start
    /// from its previous good version (FILE.prev) instead of refusing; the
    /// summary then names the file used.
    #[arg(long, requires = "initial_values")]
    initial_values_fallback: bool,
    /// Use this plan file instead of the domain's built-in plan.
    #[arg(long)]
    plan: Option<PathBuf>,
    /// Run a --plan that fails the structural checks of `learnpnp check`
    /// (for experts: learning in a plan that can deadlock or run an action
    /// twice at once gives meaningless numbers).
    #[arg(long, requires = "plan")]
    unchecked: bool,
    /// Actions after which an episode is cut (grid worlds; at least 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::MAX_ACTIONS.parse_u32(s))]
    max_actions: Option<u32>,
    /// Penalty kick plan variant.
    #[arg(long, value_enum, default_value = "plain")]
    variant: Variant,
    /// Keepaway: the keepers' policy for keepaway-fixed.
    #[arg(long, value_enum, default_value = "handcoded")]
    policy: FixedPolicy,
    /// Keepaway: what the agents perceive.
    #[arg(long, value_enum, default_value = "full-state")]
    vision: VisionArg,
    /// Keepaway: distance (m) at which the threshold policy passes (0 to 200).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::DISTANCE.parse(s))]
    hold_threshold: Option<f64>,
    /// Keepaway: threshold (m) of the takers' distance to a pass line (0 to 200).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::DISTANCE.parse(s))]
    lane_threshold: Option<f64>,
    /// Keepaway: threshold (m) of the closest taker's distance (0 to 200).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::DISTANCE.parse(s))]
    taker_threshold: Option<f64>,

    /// Discount per executor step (0 to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::GAMMA.parse(s))]
    gamma: Option<f64>,
    /// Step size (above 0, up to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::STEP.parse(s))]
    alpha: Option<f64>,
    /// Eligibility trace decay (0 to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::LAMBDA.parse(s))]
    lambda: Option<f64>,
    /// Epsilon (0 to 1): VALUE or START:END:OVER (TD: over decisions; SoSMC: assessing episodes).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| parse_schedule_in(s, ranges::EPSILON))]
    epsilon: Option<Schedule>,
    /// Softmax temperature (above 0, finite): VALUE or START:END:OVER.
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| parse_schedule_in(s, ranges::TEMPERATURE))]
    tau: Option<Schedule>,
    /// Act greedily (TD; with an optimistic --initial-value).
    #[arg(long)]
    greedy: bool,
    /// Value of unseen markings (a finite number, or -inf).
    #[arg(long, allow_hyphen_values = true, value_parser = ranges::parse_initial_value)]
    initial_value: Option<f64>,
    /// SoSMC: episodes of the initial exploratory phase.
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::WHOLE.parse(s))]
    initial_phase: Option<u64>,
    /// SoSMC: epsilon (0 to 1) or temperature (above 0) of the initial phase
    /// (VALUE or START:END:OVER).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| parse_schedule_in(s, ranges::EXPLORATION))]
    initial_parameter: Option<Schedule>,
    /// SoSMC: exploration in the assessing phase: never, per-decision, every:N, after:K.
    #[arg(long)]
    assess: Option<AssessmentArg>,
    /// SoSMC: step size of exploiting updates: a number above 0, up to 1, or 'inverse' (1/n).
    #[arg(long, value_parser = parse_step_size, allow_hyphen_values = true)]
    step_size: Option<StepSize>,
    /// SoSMC: suspend exploration while the mean of the last WINDOW exploiting returns is at least THRESHOLD.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_threshold, value_name = "THRESHOLD:WINDOW")]
    threshold: Option<ThresholdRule>,
    /// MCESP: episodes per explored pair (at least 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::STAGE_LENGTH.parse(s))]
    stage_length: Option<u64>,
    /// MCESP: smallest step size (above 0, up to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::STEP.parse(s))]
    alpha_min: Option<f64>,
    /// TD: repeat the first decision at an observation within an episode.
    #[arg(long)]
    consistent: bool,
    /// TD: value every marking the plan passes through (one-step methods then
    /// bootstrap at every state of the process, not only at choices).
    #[arg(long)]
    every_marking: bool,
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
            DomainName::KeepawayPass | DomainName::KeepawayPosition | DomainName::KeepawayFixed => {
                let mut config = KeepawayDomainConfig::for_mode(match name {
                    DomainName::KeepawayPass => KeepawayMode::Pass,
                    DomainName::KeepawayPosition => KeepawayMode::Position,
                    _ => KeepawayMode::Fixed(self.policy),
                });
                config.vision = match self.vision {
                    VisionArg::FullState => VisionMode::FullState,
                    VisionArg::Quantised => VisionMode::Quantised,
                };
                if let Some(t) = self.hold_threshold {
                    config.hold_threshold = t;
                }
                if let Some(t) = self.lane_threshold {
                    config.thresholds.pass_line = t;
                }
                if let Some(t) = self.taker_threshold {
                    config.thresholds.closest_taker = t;
                }
                DomainSpec::Keepaway { config, plan }
            }
        }
    }

    fn overrides(&self) -> Overrides {
        Overrides {
            gamma: self.gamma,
            alpha: self.alpha,
            lambda: self.lambda,
            epsilon: self.epsilon,
            tau: self.tau,
            greedy: self.greedy,
            initial_value: self.initial_value,
            initial_phase: self.initial_phase,
            initial_parameter: self.initial_parameter,
            assessment: self.assess.map(|a| a.0),
            step_size: self.step_size,
            threshold: self.threshold,
            stage_length: self.stage_length,
            alpha_min: self.alpha_min,
            consistent: self.consistent,
            every_marking: self.every_marking,
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
        let domain = self.domain(name);
        let algo = match (self.algo, name) {
            (Some(a), _) => a,
            (None, DomainName::KeepawayFixed) => Algorithm::Random,
            (None, _) => {
                return Err(ExperimentError::Invalid(format!(
                    "--algo is needed for {}",
                    domain.name()
                )));
            }
        };
        let mut learner = defaults::default_learner(algo, &domain);
        self.overrides().apply(&mut learner);
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
            seed: self.seed,
            initial_values: self.initial_values_to_use()?,
            record: self.record,
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

/// Parses a schedule whose every value must lie in `range`.
fn parse_schedule_in(text: &str, range: ranges::RealRange) -> Result<Schedule, String> {
    let schedule = parse_schedule(text)?;
    range.check_schedule(&schedule)?;
    Ok(schedule)
}
