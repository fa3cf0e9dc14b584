//! `learnpnp experiment`: one domain, one algorithm, many runs.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, ValueEnum};
use learnpnp::domains::parr_russell::ParrRussellConfig;
use learnpnp::domains::penalty_kick::{PenaltyKickConfig, Variant};
use learnpnp::domains::sutton::SuttonConfig;
use learnpnp::experiment::defaults::{
    self, AssessmentArg, Overrides, parse_schedule, parse_step_size, parse_threshold,
};
use learnpnp::experiment::output::write_results;
use learnpnp::experiment::runner::run_experiment;
use learnpnp::experiment::spec::{Algorithm, DomainSpec, ExperimentSpec};
use learnpnp::learning::{Schedule, StepSize, ThresholdRule};

/// The domains of the experiment command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DomainName {
    /// Parr and Russell's 4 x 3 grid.
    ParrRussell,
    /// Sutton's 9 x 6 grid.
    Sutton,
    /// The penalty kick.
    PenaltyKick,
}

#[derive(Args, Debug)]
pub struct ExperimentArgs {
    /// The domain.
    #[arg(value_enum)]
    domain: DomainName,
    /// The learning algorithm.
    #[arg(long, value_enum)]
    algo: Algorithm,
    /// Independent runs (default: the domain's).
    #[arg(long)]
    runs: Option<usize>,
    /// Learning episodes per run.
    #[arg(long)]
    episodes: Option<u64>,
    /// Learning episodes between evaluations.
    #[arg(long)]
    eval_every: Option<u64>,
    /// Episodes per evaluation (values frozen, behaviour as while learning).
    #[arg(long)]
    eval_episodes: Option<usize>,
    /// Episodes of each run's final greedy evaluation.
    #[arg(long)]
    greedy_episodes: Option<usize>,
    /// Base seed (run i uses a seed derived from it and i).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Output directory.
    #[arg(long, default_value = "out/experiment")]
    out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// A label for plots (default: the algorithm).
    #[arg(long)]
    label: Option<String>,

    /// Use this plan file instead of the domain's built-in plan.
    #[arg(long)]
    plan: Option<PathBuf>,
    /// Actions after which an episode is cut (grid worlds).
    #[arg(long)]
    max_actions: Option<u32>,
    /// Penalty kick plan variant.
    #[arg(long, value_enum, default_value = "plain")]
    variant: Variant,

    /// Discount per executor step.
    #[arg(long)]
    gamma: Option<f64>,
    /// Step size.
    #[arg(long)]
    alpha: Option<f64>,
    /// Eligibility trace decay.
    #[arg(long)]
    lambda: Option<f64>,
    /// Epsilon: VALUE or START:END:OVER (TD: over decisions; SoSMC: assessing episodes).
    #[arg(long, value_parser = parse_schedule)]
    epsilon: Option<Schedule>,
    /// Softmax temperature: VALUE or START:END:OVER.
    #[arg(long, value_parser = parse_schedule)]
    tau: Option<Schedule>,
    /// Act greedily (TD; with an optimistic --initial-value).
    #[arg(long)]
    greedy: bool,
    /// Value of unseen markings (a number, or -inf).
    #[arg(long, allow_hyphen_values = true)]
    initial_value: Option<f64>,
    /// SoSMC: episodes of the initial exploratory phase.
    #[arg(long)]
    initial_phase: Option<u64>,
    /// SoSMC: epsilon or temperature of the initial phase (VALUE or START:END:OVER).
    #[arg(long, value_parser = parse_schedule)]
    initial_parameter: Option<Schedule>,
    /// SoSMC: exploration in the assessing phase: never, per-decision, every:N, after:K.
    #[arg(long)]
    assess: Option<AssessmentArg>,
    /// SoSMC: step size of exploiting updates: a number or 'inverse' (1/n).
    #[arg(long, value_parser = parse_step_size)]
    step_size: Option<StepSize>,
    /// SoSMC: suspend exploration while the mean of the last WINDOW exploiting returns is at least THRESHOLD.
    #[arg(long, value_parser = parse_threshold, value_name = "THRESHOLD:WINDOW")]
    threshold: Option<ThresholdRule>,
    /// MCESP: episodes per explored pair.
    #[arg(long)]
    stage_length: Option<u64>,
    /// MCESP: smallest step size.
    #[arg(long)]
    alpha_min: Option<f64>,
    /// TD: repeat the first decision at an observation within an episode.
    #[arg(long)]
    consistent: bool,
}

impl ExperimentArgs {
    fn domain(&self) -> DomainSpec {
        let plan = self.plan.clone();
        match self.domain {
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
        }
    }

    /// The experiment these arguments describe.
    pub fn spec(&self) -> ExperimentSpec {
        let domain = self.domain();
        let mut learner = defaults::default_learner(self.algo, &domain);
        self.overrides().apply(&mut learner);
        let mut protocol = defaults::default_protocol(&domain);
        if let Some(v) = self.runs {
            protocol.runs = v;
        }
        if let Some(v) = self.episodes {
            protocol.episodes = v;
        }
        if let Some(v) = self.eval_every {
            protocol.eval_every = v;
        }
        if let Some(v) = self.eval_episodes {
            protocol.eval_episodes = v;
        }
        if let Some(v) = self.greedy_episodes {
            protocol.greedy_episodes = v;
        }
        ExperimentSpec {
            label: self.label.clone().unwrap_or_else(|| self.algo.name().to_string()),
            domain,
            algorithm: self.algo,
            learner,
            protocol,
            seed: self.seed,
        }
    }
}

/// The default worker count: every core.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

pub fn run(args: &ExperimentArgs) -> Result<()> {
    let spec = args.spec();
    let threads = args.threads.unwrap_or_else(default_threads);
    let output = run_experiment(&spec, threads, true).context("experiment failed")?;
    let summary = write_results(&output, &args.out).context("writing results")?;
    println!(
        "{} on {}: final mean {:.4} (95% CI {:.4} .. {:.4}), greedy {:.4}; {} runs in {:.2} s, {:.0} episodes/s; results in {}",
        spec.label,
        spec.domain.name(),
        summary.final_mean,
        summary.final_ci95[0],
        summary.final_ci95[1],
        summary.final_greedy_mean,
        spec.protocol.runs,
        summary.wall_seconds,
        summary.episodes_per_second,
        args.out.display()
    );
    Ok(())
}
