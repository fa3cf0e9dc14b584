//! The flags of `learnpnp experiment` and of the multi-process supervisor,
//! parsed into the core crate's [`ExperimentOptions`](learnpnp::experiment::options::ExperimentOptions).

use std::path::PathBuf;

use clap::Args;
use clap::builder::{PossibleValuesParser, TypedValueParser};
use learnpnp::domains::keepaway::{FixedPolicy, KeepawayOptions};
use learnpnp::domains::penalty_kick::Variant;
use learnpnp::experiment::defaults::{
    self, AssessmentArg, Overrides, parse_schedule, parse_step_size, parse_threshold,
};
use learnpnp::experiment::options::ExperimentOptions;
use learnpnp::experiment::ranges;
use learnpnp::experiment::spec::Algorithm;
use learnpnp::learning::{ExploitPolicy, Schedule, StepSize, ThresholdRule, Unestimated};
use learnpnp::named::Named;
use learnpnp_keepaway::params::{RefereeRule, ServerTimer, VisionMode};

/// A value parser for an enumeration picked by name: clap lists the names in
/// `--help` and refuses any other.
pub fn named<T: Named + Send + Sync + Clone>() -> impl TypedValueParser<Value = T> {
    PossibleValuesParser::new(T::ALL.iter().map(|v| v.name()))
        .map(|name| T::from_name(&name).expect("clap accepts only the possible values"))
}

/// Every flag of `learnpnp experiment` but the domain and where results go:
/// the algorithm, its parameters, the protocol and the domain's options.
/// The multi-process supervisor takes the same flags.
#[derive(Args, Debug, Clone)]
pub struct ExperimentFlags {
    /// The learning algorithm (not needed for keepaway-fixed).
    #[arg(long, value_parser = named::<Algorithm>())]
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
    #[arg(long, value_parser = named::<Variant>(), default_value = "plain")]
    variant: Variant,
    /// Keepaway: the keepers' policy for keepaway-fixed.
    #[arg(long, value_parser = named::<FixedPolicy>(), default_value = "handcoded")]
    policy: FixedPolicy,
    /// Keepaway: what the agents perceive.
    #[arg(long, value_parser = named::<VisionMode>(), default_value = "framework")]
    vision: VisionMode,
    /// Keepaway: the soccer server's timer, which fixes when the players see
    /// (framework vision): real-time (as keepaway.sh ran it; the players
    /// synchronise their sees) or synchronous (synch_mode, think at 80 ms).
    #[arg(long, value_parser = named::<ServerTimer>(), default_value = "real-time")]
    server_timer: ServerTimer,
    /// Keepaway: the referee's turnover rule: rcssserver-11 (4 cycles of taker
    /// possession) or rcssserver-9.4.5 (5 cycles; its smaller possession area is
    /// not known and not ported).
    #[arg(long, value_parser = named::<RefereeRule>(), default_value = "rcssserver-11")]
    referee: RefereeRule,
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
    /// SoSMC: exploration in the assessing phase: never, per-decision, every:N, after:K, samples:K.
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
    /// Soft-SoSMC: the weight of an option valued -inf (no estimate yet): none
    /// (eq. 1.8 as written: weight 0; the default, where the thesis's domains
    /// start from a finite pessimistic value) or as-best (that of the best
    /// estimated option)
    #[arg(long, value_parser = named::<Unestimated>())]
    unestimated: Option<Unestimated>,
    /// SoSMC: the policy of exploiting episodes: greedy (the default: taken
    /// anew every episode, as the thesis's figures need) or last (Algorithm 1
    /// as written: the last policy chosen, the greedy one taken anew only
    /// after an exploratory episode).
    #[arg(long, value_parser = named::<ExploitPolicy>())]
    exploit_policy: Option<ExploitPolicy>,
}

impl ExperimentFlags {
    /// The options these flags state.
    pub fn options(&self) -> ExperimentOptions {
        self.clone().into()
    }
}

impl From<ExperimentFlags> for ExperimentOptions {
    fn from(args: ExperimentFlags) -> Self {
        ExperimentOptions {
            algo: args.algo,
            runs: args.runs,
            episodes: args.episodes,
            eval_every: args.eval_every,
            eval_episodes: args.eval_episodes,
            greedy_episodes: args.greedy_episodes,
            trace_every: args.trace_every,
            seed: Some(args.seed),
            label: args.label,
            initial_values: args.initial_values,
            initial_values_fallback: args.initial_values_fallback,
            plan: args.plan,
            unchecked: args.unchecked,
            max_actions: args.max_actions,
            variant: args.variant,
            keepaway: KeepawayOptions {
                record: args.record,
                policy: args.policy,
                vision: args.vision,
                timer: args.server_timer,
                referee: args.referee,
                hold_threshold: args.hold_threshold,
                lane_threshold: args.lane_threshold,
                taker_threshold: args.taker_threshold,
            },
            learner: Overrides {
                gamma: args.gamma,
                alpha: args.alpha,
                lambda: args.lambda,
                epsilon: args.epsilon,
                tau: args.tau,
                greedy: args.greedy,
                initial_value: args.initial_value,
                initial_phase: args.initial_phase,
                initial_parameter: args.initial_parameter,
                assessment: args.assess.map(|a| a.0),
                step_size: args.step_size,
                threshold: args.threshold,
                stage_length: args.stage_length,
                alpha_min: args.alpha_min,
                consistent: args.consistent,
                every_marking: args.every_marking,
                unestimated: args.unestimated,
                exploit_policy: args.exploit_policy,
            },
        }
    }
}

/// Parses a schedule whose every value must lie in `range`.
fn parse_schedule_in(text: &str, range: ranges::RealRange) -> Result<Schedule, String> {
    let schedule = parse_schedule(text)?;
    range.check_schedule(&schedule)?;
    Ok(schedule)
}

/// Parses experiment flags (`["--algo", "sarsa0", ...]`, without a program
/// name or domain) as `learnpnp experiment` does.
pub fn parse_experiment_flags(flags: &[&str]) -> Result<ExperimentOptions, clap::Error> {
    #[derive(clap::Parser)]
    struct Flags {
        #[command(flatten)]
        options: ExperimentFlags,
    }
    let flags = <Flags as clap::Parser>::try_parse_from(std::iter::once("learnpnp").chain(flags.iter().copied()))?;
    Ok(flags.options.into())
}
