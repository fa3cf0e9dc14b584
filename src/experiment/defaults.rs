//! The thesis's parameters as defaults, per domain and algorithm, and the
//! overrides a user may give on the command line.

use std::str::FromStr;

use clap::Args;
use serde::{Deserialize, Serialize};

use super::options::named;
use super::ranges;
use super::spec::{Algorithm, DomainSpec, LearnerSpec, Protocol};
use crate::domains::keepaway::KeepawayMode;
use crate::learning::{
    Assessment, ExploitPolicy, Exploration, McespConfig, Schedule, Scope, Sigma, SoSmcConfig, StepSize, Target,
    TdConfig, ThresholdRule, Unestimated,
};
use crate::named::Named;

/// Values of the domains' returns that serve as pessimistic and optimistic initial values.
struct Bounds {
    /// A return most policies get (the thesis's -4 in the 4 x 3 grid).
    low: f64,
    /// No policy gets more.
    high: f64,
}

fn bounds(domain: &DomainSpec) -> Bounds {
    match domain {
        DomainSpec::ParrRussell { .. } => Bounds { low: -4.0, high: 1.0 },
        DomainSpec::Sutton { config, .. } => Bounds {
            low: -f64::from(config.max_actions),
            high: 0.0,
        },
        DomainSpec::PenaltyKick { config, .. } => Bounds {
            low: 0.0,
            high: config.goal_reward,
        },
        // An episode lasts no less than nothing.
        DomainSpec::Keepaway { .. } => Bounds { low: 0.0, high: 60.0 },
        DomainSpec::Nmdp { .. } => Bounds { low: 0.0, high: 20.0 },
        DomainSpec::World { .. } => Bounds { low: 0.0, high: 0.0 },
    }
}

/// The learner `algorithm` names, from a domain's SoSMC and TD parameters
/// (`sosmc(sigma, initial phase's parameter, assessing parameter)`,
/// `td(lambda, target)`): e-SoSMC explores uniformly in its initial phase and
/// with epsilon 0.1 after it, Soft-SoSMC with the temperatures of `soft`;
/// MCESP is the reference library's (stage 10, smallest step 0.01, no estimate).
fn learner_of(
    algorithm: Algorithm,
    sosmc: impl Fn(Sigma, Schedule, Schedule) -> SoSmcConfig,
    td: impl Fn(f64, Target) -> TdConfig,
    soft: (Schedule, Schedule),
) -> LearnerSpec {
    match algorithm {
        Algorithm::EpsSosmc => LearnerSpec::Sosmc(sosmc(
            Sigma::EpsilonGreedy,
            Schedule::constant(1.0),
            Schedule::constant(0.1),
        )),
        Algorithm::SoftSosmc => LearnerSpec::Sosmc(sosmc(Sigma::Softmax, soft.0, soft.1)),
        Algorithm::SarsaLambda => LearnerSpec::Td(td(0.9, Target::OnPolicy)),
        Algorithm::Sarsa0 => LearnerSpec::Td(td(0.0, Target::OnPolicy)),
        Algorithm::QLearning => LearnerSpec::Td(td(0.0, Target::Max)),
        Algorithm::Mcesp => LearnerSpec::Mcesp(McespConfig {
            gamma: 1.0,
            stage_length: 10,
            alpha_min: 0.01,
            initial_value: f64::NEG_INFINITY,
        }),
        Algorithm::Random => LearnerSpec::Random,
    }
}

/// The one-step and eligibility-trace learners over the plan's choices
/// (undiscounted, epsilon-greedy on `epsilon`, values starting at
/// `initial_value`), by their lambda and target.
fn td_over_choices(alpha: f64, epsilon: Schedule, initial_value: f64) -> impl Fn(f64, Target) -> TdConfig {
    move |lambda, target| TdConfig {
        gamma: 1.0,
        alpha,
        lambda,
        target,
        scope: Scope::Choices,
        exploration: Exploration::EpsilonGreedy(epsilon),
        initial_value,
        consistent: false,
    }
}

/// Keepaway's defaults (thesis chapter 7; choices documented in RESULTS.md).
/// Returns are episode durations in seconds.
fn keepaway_learner(algorithm: Algorithm, mode: KeepawayMode) -> LearnerSpec {
    let position = mode == KeepawayMode::Position;
    let sosmc = |sigma: Sigma, initial: Schedule, assessing: Schedule| SoSmcConfig {
        gamma: 1.0,
        initial_phase: 100,
        sigma,
        initial_parameter: initial,
        assessing_parameter: assessing,
        // Exploration from the episode number alone, so that agents agree (4.4).
        assessment: Assessment::EveryN(20),
        step_size: StepSize::Constant(0.05),
        // Algorithm 1: "initialize Q(s, a) pessimistically"; no episode lasts
        // less than 0 s. Eq. 1.8 then weighs an untried option
        // e^((0 - best)/tau), as the text writes it.
        initial_value: 0.0,
        threshold: Some(ThresholdRule {
            threshold: 18.0,
            window: 200,
        }),
        unestimated: Unestimated::None,
        exploit: ExploitPolicy::Greedy,
    };
    let td = td_over_choices(
        if position { 0.1 } else { 0.125 },
        if position {
            // One decision per episode: 4500 decisions are 4500 episodes.
            Schedule::linear(0.2, 0.0, 4500)
        } else {
            Schedule::constant(0.01)
        },
        0.0,
    );
    learner_of(
        algorithm,
        sosmc,
        td,
        (Schedule::linear(5.0, 3.0, 100), Schedule::constant(3.0)),
    )
}

/// The thesis's parameters for `algorithm` in `domain` (chapter 6; where the
/// thesis is silent, the choice documented in docs/results/RESULTS.md).
pub fn default_learner(algorithm: Algorithm, domain: &DomainSpec) -> LearnerSpec {
    match domain {
        DomainSpec::Keepaway { config, .. } => return keepaway_learner(algorithm, config.mode),
        DomainSpec::World { .. } => return plan_learner(algorithm),
        _ => {}
    }
    let b = bounds(domain);
    let sutton = matches!(domain, DomainSpec::Sutton { .. });
    // Figure 4.3: the assessment with k = 50, memoryless averages (4.2.2, 4.3).
    let nmdp = matches!(domain, DomainSpec::Nmdp { .. });
    let td = td_over_choices(
        if sutton { 0.1 } else { 0.01 },
        if sutton {
            Schedule::constant(0.1)
        } else {
            Schedule::linear(0.2, 0.0, 80_000)
        },
        if sutton { b.high } else { b.low },
    );
    let sosmc = |sigma: Sigma, initial: Schedule, assessing: Schedule| SoSmcConfig {
        gamma: 1.0,
        initial_phase: if sutton { 0 } else { 100 },
        sigma,
        initial_parameter: initial,
        assessing_parameter: assessing,
        assessment: if sutton {
            Assessment::EveryN(20)
        } else if nmdp {
            Assessment::AfterK(50)
        } else {
            Assessment::Never
        },
        step_size: if nmdp {
            StepSize::InverseCount
        } else {
            StepSize::Constant(0.01)
        },
        // Algorithm 1 initialises Q pessimistically; chapter 6 (6.1.2): "when
        // not differently specified the Q-function has been initialised at
        // -4" in Parr and Russell's grid. Sutton's grid has no initial phase
        // and optimistic values (6.4, as section 4.2.1 allows). The N-MDP's
        // returns are normally distributed, unbounded below: only negative
        // infinity is pessimistic there (its e-greedy draws never weigh it).
        initial_value: if sutton {
            b.high
        } else if nmdp {
            f64::NEG_INFINITY
        } else {
            b.low
        },
        threshold: None,
        unestimated: Unestimated::None,
        exploit: ExploitPolicy::Greedy,
    };
    learner_of(
        algorithm,
        sosmc,
        td,
        (
            Schedule::linear(1.0, 0.05, 100),
            Schedule::constant(if sutton { 4.0 } else { 0.05 }),
        ),
    )
}

/// The parameters of `algorithm` for a plan outside the thesis's domains (a
/// user's plan, driven from Python or by a world in its own process), whose
/// returns are unknown: TD with Sutton and Barto's usual alpha 0.1 and a
/// constant epsilon 0.1 from values of 0; SoSMC and MCESP as in the grid worlds
/// (chapter 6: a 100-episode exploratory phase, then exploitation). The
/// returns' range is unknown, so no finite value is known to be pessimistic:
/// SoSMC starts from no estimate (negative infinity) and Soft-SoSMC weighs an
/// untried option as the best estimated one (`Unestimated::AsBest`), so every
/// policy keeps a chance (section 4.2.2's condition 3). A user who knows a
/// return no policy falls below gives it as `initial_value` with
/// `unestimated="none"` for the thesis's rule.
pub fn plan_learner(algorithm: Algorithm) -> LearnerSpec {
    let td = td_over_choices(0.1, Schedule::constant(0.1), 0.0);
    let sosmc = |sigma: Sigma, initial: Schedule, assessing: Schedule| SoSmcConfig {
        gamma: 1.0,
        initial_phase: 100,
        sigma,
        initial_parameter: initial,
        assessing_parameter: assessing,
        assessment: Assessment::Never,
        step_size: StepSize::Constant(0.01),
        initial_value: f64::NEG_INFINITY,
        threshold: None,
        unestimated: Unestimated::AsBest,
        exploit: ExploitPolicy::Greedy,
    };
    learner_of(
        algorithm,
        sosmc,
        td,
        (Schedule::linear(1.0, 0.05, 100), Schedule::constant(0.05)),
    )
}

/// The base seed of experiments and of the thesis's presets.
pub const DEFAULT_SEED: u64 = 2011;

/// A default protocol for interactive runs of `domain` (presets set the
/// thesis's; fixed Keepaway policies use the baselines preset's).
pub(crate) fn default_protocol(domain: &DomainSpec) -> Protocol {
    match domain {
        // Nothing learns: 50 episodes, then 1000 evaluated ones, in each of
        // 20 runs (the interval is over the runs' means).
        DomainSpec::Keepaway { .. } if domain.is_fixed_policy() => Protocol {
            runs: 20,
            episodes: 50,
            eval_every: 50,
            eval_episodes: 1000,
            greedy_episodes: 0,
            trace_every: Some(0),
        },
        DomainSpec::ParrRussell { .. } => Protocol {
            runs: 20,
            episodes: 1000,
            eval_every: 20,
            eval_episodes: 20,
            greedy_episodes: 100,
            trace_every: None,
        },
        DomainSpec::Sutton { .. } => Protocol {
            runs: 20,
            episodes: 4000,
            eval_every: 200,
            eval_episodes: 0,
            greedy_episodes: 0,
            trace_every: None,
        },
        DomainSpec::Keepaway { .. } => Protocol {
            runs: 4,
            episodes: 1000,
            eval_every: 100,
            eval_episodes: 20,
            greedy_episodes: 50,
            trace_every: None,
        },
        DomainSpec::PenaltyKick { .. } => Protocol {
            runs: 20,
            episodes: 200,
            eval_every: 10,
            eval_episodes: 10,
            greedy_episodes: 10,
            trace_every: None,
        },
        DomainSpec::Nmdp { .. } => Protocol {
            runs: 20,
            episodes: 600,
            eval_every: 50,
            eval_episodes: 20,
            greedy_episodes: 100,
            trace_every: None,
        },
        // One run (a world process may be a robot); the greedy policy at the end.
        DomainSpec::World { .. } => Protocol {
            runs: 1,
            episodes: 1000,
            eval_every: 100,
            eval_episodes: 0,
            greedy_episodes: 100,
            trace_every: Some(0),
        },
    }
}

/// How the assessing phase of SoSMC explores, as written on the command line:
/// `never`, `per-decision`, `every:N`, `after:K` (K exploiting episodes since
/// the last exploratory one) or `samples:K` (K samples of the current policy).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AssessmentArg(pub Assessment);

impl FromStr for AssessmentArg {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Ok(AssessmentArg(match s.split_once(':') {
            None if s == "never" => Assessment::Never,
            None if s == "per-decision" => Assessment::PerDecision,
            Some(("every", n)) => Assessment::EveryN(ranges::WINDOW.parse(n)?),
            Some(("after", k)) => Assessment::AfterK(ranges::WHOLE.parse(k)?),
            Some(("samples", k)) => Assessment::AfterKSamples(ranges::WHOLE.parse(k)?),
            _ => {
                return Err(format!(
                    "'{s}': expected never, per-decision, every:N, after:K or samples:K"
                ));
            }
        }))
    }
}

/// Parses a schedule `START`, or `START:END:OVER` (a linear ramp over OVER units).
pub fn parse_schedule(s: &str) -> Result<Schedule, String> {
    let number = |n: &str| n.trim().parse::<f64>().map_err(|_| format!("'{n}' is not a number"));
    let parts: Vec<&str> = s.split(':').collect();
    match parts.as_slice() {
        [v] => Ok(Schedule::constant(number(v)?)),
        [start, end, over] => {
            let over = over
                .trim()
                .parse::<u64>()
                .map_err(|_| format!("'{over}' is not a whole number"))?;
            Ok(Schedule::linear(number(start)?, number(end)?, over))
        }
        _ => Err(format!("'{s}': expected VALUE or START:END:OVER")),
    }
}

/// Parses a step size: a number in [`ranges::STEP`], or `inverse` for 1/n.
pub fn parse_step_size(s: &str) -> Result<StepSize, String> {
    if s == "inverse" {
        return Ok(StepSize::InverseCount);
    }
    ranges::STEP
        .parse(s)
        .map(StepSize::Constant)
        .map_err(|e| format!("{e}, or 'inverse'"))
}

/// Parses the threshold rule `THRESHOLD:WINDOW` (a finite return, a window of at least one episode).
pub fn parse_threshold(s: &str) -> Result<ThresholdRule, String> {
    let (t, w) = s
        .split_once(':')
        .ok_or_else(|| format!("'{s}': expected THRESHOLD:WINDOW"))?;
    Ok(ThresholdRule {
        threshold: ranges::RETURN.parse(t)?,
        window: ranges::WINDOW.parse_usize(w)?,
    })
}

/// The learner's parameters a user gives (the flags of `learnpnp experiment`,
/// the keyword arguments from Python); each replaces the default when set.
#[derive(Args, Debug, Clone, Copy, PartialEq)]
pub struct Overrides {
    /// Discount per executor step (0 to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::GAMMA.parse(s))]
    pub gamma: Option<f64>,
    /// Step size (above 0, up to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::STEP.parse(s))]
    pub alpha: Option<f64>,
    /// Eligibility trace decay (0 to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::LAMBDA.parse(s))]
    pub lambda: Option<f64>,
    /// Epsilon (0 to 1): VALUE or START:END:OVER (TD: over decisions; SoSMC: assessing episodes).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| parse_schedule_in(s, ranges::EPSILON))]
    pub epsilon: Option<Schedule>,
    /// Softmax temperature (above 0, finite): VALUE or START:END:OVER.
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| parse_schedule_in(s, ranges::TEMPERATURE))]
    pub tau: Option<Schedule>,
    /// Act greedily (TD; with an optimistic --initial-value).
    #[arg(long)]
    pub greedy: bool,
    /// Value of unseen markings (a finite number, or -inf).
    #[arg(long, allow_hyphen_values = true, value_parser = ranges::parse_initial_value)]
    pub initial_value: Option<f64>,
    /// SoSMC: episodes of the initial exploratory phase.
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::WHOLE.parse(s))]
    pub initial_phase: Option<u64>,
    /// SoSMC: epsilon (0 to 1) or temperature (above 0) of the initial phase
    /// (VALUE or START:END:OVER).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| parse_schedule_in(s, ranges::EXPLORATION))]
    pub initial_parameter: Option<Schedule>,
    /// SoSMC: exploration in the assessing phase: never, per-decision, every:N, after:K, samples:K.
    #[arg(long = "assess", value_name = "ASSESS", value_parser = |s: &str| s.parse::<AssessmentArg>().map(|a| a.0))]
    pub assessment: Option<Assessment>,
    /// SoSMC: step size of exploiting updates: a number above 0, up to 1, or 'inverse' (1/n).
    #[arg(long, value_parser = parse_step_size, allow_hyphen_values = true)]
    pub step_size: Option<StepSize>,
    /// SoSMC: suspend exploration while the mean of the last WINDOW exploiting returns is at least THRESHOLD.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_threshold, value_name = "THRESHOLD:WINDOW")]
    pub threshold: Option<ThresholdRule>,
    /// MCESP: episodes per explored pair (at least 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::STAGE_LENGTH.parse(s))]
    pub stage_length: Option<u64>,
    /// MCESP: smallest step size (above 0, up to 1).
    #[arg(long, allow_hyphen_values = true, value_parser = |s: &str| ranges::STEP.parse(s))]
    pub alpha_min: Option<f64>,
    /// TD: repeat the first decision at an observation within an episode.
    #[arg(long)]
    pub consistent: bool,
    /// TD: value every marking the plan passes through (one-step methods then
    /// bootstrap at every state of the process, not only at choices).
    #[arg(long)]
    pub every_marking: bool,
    /// Soft-SoSMC: the weight of an option valued -inf (no estimate yet): none
    /// (eq. 1.8 as written: weight 0; the default, where the thesis's domains
    /// start from a finite pessimistic value) or as-best (that of the best
    /// estimated option)
    #[arg(long, value_parser = named::<Unestimated>())]
    pub unestimated: Option<Unestimated>,
    /// SoSMC: the policy of exploiting episodes: greedy (the default: taken
    /// anew every episode, as the thesis's figures need) or last (Algorithm 1
    /// as written: the last policy chosen, the greedy one taken anew only
    /// after an exploratory episode).
    #[arg(long, value_parser = named::<ExploitPolicy>())]
    pub exploit_policy: Option<ExploitPolicy>,
}

/// Parses a schedule (see [`parse_schedule`]) whose every value must lie in `range`.
fn parse_schedule_in(text: &str, range: ranges::RealRange) -> Result<Schedule, String> {
    let schedule = parse_schedule(text)?;
    range.check_schedule(&schedule)?;
    Ok(schedule)
}

impl Default for Overrides {
    fn default() -> Self {
        Self::NONE
    }
}

impl Overrides {
    /// No parameter set: every default stays.
    pub const NONE: Overrides = Overrides {
        gamma: None,
        alpha: None,
        lambda: None,
        epsilon: None,
        tau: None,
        greedy: false,
        initial_value: None,
        initial_phase: None,
        initial_parameter: None,
        assessment: None,
        step_size: None,
        threshold: None,
        stage_length: None,
        alpha_min: None,
        consistent: false,
        every_marking: false,
        unestimated: None,
        exploit_policy: None,
    };

    /// The parameter names [`Overrides::set`] takes: the flags of `learnpnp
    /// experiment`, without dashes.
    pub const NAMES: &'static [&'static str] = &[
        "gamma",
        "alpha",
        "lambda",
        "epsilon",
        "tau",
        "greedy",
        "initial_value",
        "initial_phase",
        "initial_parameter",
        "assess",
        "step_size",
        "threshold",
        "stage_length",
        "alpha_min",
        "consistent",
        "every_marking",
        "unestimated",
        "exploit_policy",
    ];

    /// Sets parameter `name` (a flag of `learnpnp experiment`, with `_` or
    /// `-` between words) from `text` as the flag would read it, checked against
    /// the same range; switches (`greedy`, `consistent`, `every_marking`) take
    /// `true` or `false`.
    pub fn set(&mut self, name: &str, text: &str) -> Result<(), String> {
        let schedule_in = |range| parse_schedule_in(text, range);
        let switch = || match text {
            "true" | "True" => Ok(true),
            "false" | "False" => Ok(false),
            _ => Err(format!("'{text}' is not a switch: it must be true or false")),
        };
        let result: Result<(), String> = (|| {
            match name.replace('-', "_").as_str() {
                "gamma" => self.gamma = Some(ranges::GAMMA.parse(text)?),
                "alpha" => self.alpha = Some(ranges::STEP.parse(text)?),
                "lambda" => self.lambda = Some(ranges::LAMBDA.parse(text)?),
                "epsilon" => self.epsilon = Some(schedule_in(ranges::EPSILON)?),
                "tau" => self.tau = Some(schedule_in(ranges::TEMPERATURE)?),
                "greedy" => self.greedy = switch()?,
                "initial_value" => self.initial_value = Some(ranges::parse_initial_value(text)?),
                "initial_phase" => self.initial_phase = Some(ranges::WHOLE.parse(text)?),
                "initial_parameter" => self.initial_parameter = Some(schedule_in(ranges::EXPLORATION)?),
                "assess" => self.assessment = Some(text.parse::<AssessmentArg>()?.0),
                "step_size" => self.step_size = Some(parse_step_size(text)?),
                "threshold" => self.threshold = Some(parse_threshold(text)?),
                "stage_length" => self.stage_length = Some(ranges::STAGE_LENGTH.parse(text)?),
                "alpha_min" => self.alpha_min = Some(ranges::STEP.parse(text)?),
                "consistent" => self.consistent = switch()?,
                "every_marking" => self.every_marking = switch()?,
                "unestimated" => self.unestimated = Some(Unestimated::from_name(text).map_err(|e| e.to_string())?),
                "exploit_policy" => {
                    self.exploit_policy = Some(ExploitPolicy::from_name(text).map_err(|e| e.to_string())?)
                }
                _ => {
                    return Err(format!(
                        "unknown parameter: the parameters are {}",
                        Self::NAMES.join(", ")
                    ));
                }
            }
            Ok(())
        })();
        result.map_err(|e| format!("{name}: {e}"))
    }

    /// Applies the overrides to `spec`.
    pub fn apply(&self, spec: &mut LearnerSpec) {
        match spec {
            LearnerSpec::Td(c) => {
                set(&mut c.gamma, self.gamma);
                set(&mut c.alpha, self.alpha);
                set(&mut c.lambda, self.lambda);
                set(&mut c.initial_value, self.initial_value);
                if let Some(e) = self.epsilon {
                    c.exploration = Exploration::EpsilonGreedy(e);
                }
                if let Some(t) = self.tau {
                    c.exploration = Exploration::Softmax(t);
                }
                if self.greedy {
                    c.exploration = Exploration::Greedy;
                }
                c.consistent |= self.consistent;
                if self.every_marking {
                    c.scope = Scope::Markings;
                }
            }
            LearnerSpec::Sosmc(c) => {
                set(&mut c.gamma, self.gamma);
                if let Some(a) = self.alpha {
                    c.step_size = StepSize::Constant(a);
                }
                set(&mut c.step_size, self.step_size);
                set(&mut c.initial_value, self.initial_value);
                set(&mut c.initial_phase, self.initial_phase);
                set(&mut c.initial_parameter, self.initial_parameter);
                set(&mut c.assessing_parameter, self.epsilon.or(self.tau));
                set(&mut c.assessment, self.assessment);
                if self.threshold.is_some() {
                    c.threshold = self.threshold;
                }
                set(&mut c.unestimated, self.unestimated);
                set(&mut c.exploit, self.exploit_policy);
            }
            LearnerSpec::Mcesp(c) => {
                set(&mut c.gamma, self.gamma);
                set(&mut c.initial_value, self.initial_value);
                set(&mut c.stage_length, self.stage_length);
                set(&mut c.alpha_min, self.alpha_min);
            }
            LearnerSpec::Random => {}
        }
    }
}

fn set<T: Copy>(slot: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *slot = v;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_arguments() {
        assert_eq!(parse_schedule("0.2").unwrap(), Schedule::constant(0.2));
        assert_eq!(
            parse_schedule("0.2:0:80000").unwrap(),
            Schedule::linear(0.2, 0.0, 80000)
        );
        assert!(parse_schedule("0.2:0").is_err());
        assert_eq!("every:20".parse::<AssessmentArg>().unwrap().0, Assessment::EveryN(20));
        assert_eq!("after:5".parse::<AssessmentArg>().unwrap().0, Assessment::AfterK(5));
        assert_eq!(
            "samples:5".parse::<AssessmentArg>().unwrap().0,
            Assessment::AfterKSamples(5)
        );
        assert!("often".parse::<AssessmentArg>().is_err());
        assert_eq!(parse_step_size("inverse").unwrap(), StepSize::InverseCount);
        assert_eq!(
            parse_threshold("180:200").unwrap(),
            ThresholdRule {
                threshold: 180.0,
                window: 200
            }
        );
    }

    #[test]
    fn the_parameter_names_are_the_flags() {
        let command = Overrides::augment_args(clap::Command::new("parameters"));
        let flags: Vec<String> = command
            .get_arguments()
            .filter_map(|arg| arg.get_long())
            .map(|long| long.replace('-', "_"))
            .collect();
        assert_eq!(flags, Overrides::NAMES);
    }

    #[test]
    fn overrides_replace_defaults() {
        let domain = DomainSpec::ParrRussell {
            config: Default::default(),
            plan: None,
        };
        let mut spec = default_learner(Algorithm::SarsaLambda, &domain);
        Overrides {
            alpha: Some(0.5),
            greedy: true,
            initial_value: Some(1.0),
            ..Overrides::default()
        }
        .apply(&mut spec);
        let LearnerSpec::Td(c) = spec else {
            panic!("TD expected")
        };
        assert_eq!(
            (c.alpha, c.initial_value, c.exploration),
            (0.5, 1.0, Exploration::Greedy)
        );
    }
}
