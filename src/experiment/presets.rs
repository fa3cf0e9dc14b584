//! The thesis's figures as experiment presets (chapters 4, 6 and 7), with its parameters
//! where it gives them and documented choices where it does not
//! (docs/results/RESULTS.md lists both).

use super::defaults::{default_learner, default_protocol};
use super::spec::{Algorithm, DomainSpec, ExperimentSpec, LearnerSpec, Protocol};
use crate::domains::keepaway::{FixedPolicy, KeepawayDomainConfig, KeepawayMode};
use crate::domains::nmdp::NmdpConfig;
use crate::domains::parr_russell::ParrRussellConfig;
use crate::domains::penalty_kick::{PenaltyKickConfig, Variant};
use crate::domains::sutton::SuttonConfig;
use crate::learning::{Assessment, Exploration, Schedule, Scope, Sigma};

/// What a figure shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FigureKind {
    /// Evaluation curves of several experiments, overlaid.
    Curves,
    /// The values of the options in the initial observation during one run.
    Traces,
    /// Fixed policies: one bar per policy, its mean score with a 95% CI.
    Bars,
}

/// A figure of the thesis and the experiments that draw it.
#[derive(Debug, Clone)]
pub struct Figure {
    /// The thesis's figure number, e.g. `6.3`.
    pub id: &'static str,
    /// What it shows.
    pub title: &'static str,
    /// What the thesis claims from it.
    pub claim: &'static str,
    /// Curves or value traces.
    pub kind: FigureKind,
    /// One experiment per curve (or per traced run).
    pub curves: Vec<ExperimentSpec>,
}

/// The presets' seed, also `learnpnp experiment`'s default: an experiment
/// with a preset's parameters gives the preset's numbers.
pub const SEED: u64 = super::defaults::DEFAULT_SEED;

fn parr_russell() -> DomainSpec {
    DomainSpec::ParrRussell {
        config: ParrRussellConfig::default(),
        plan: None,
    }
}

fn sutton() -> DomainSpec {
    DomainSpec::Sutton {
        config: SuttonConfig::default(),
        plan: None,
    }
}

fn experiment(
    label: &str,
    domain: DomainSpec,
    algorithm: Algorithm,
    learner: LearnerSpec,
    protocol: Protocol,
) -> ExperimentSpec {
    ExperimentSpec {
        label: label.to_string(),
        domain,
        algorithm,
        learner,
        protocol,
        seed: SEED,
        initial_values: Vec::new(),
    }
}

fn with_td(
    algorithm: Algorithm,
    domain: &DomainSpec,
    edit: impl FnOnce(&mut crate::learning::TdConfig),
) -> LearnerSpec {
    let mut spec = default_learner(algorithm, domain);
    if let LearnerSpec::Td(c) = &mut spec {
        edit(c);
    }
    spec
}

fn with_sosmc(
    algorithm: Algorithm,
    domain: &DomainSpec,
    edit: impl FnOnce(&mut crate::learning::SoSmcConfig),
) -> LearnerSpec {
    let mut spec = default_learner(algorithm, domain);
    if let LearnerSpec::Sosmc(c) = &mut spec {
        edit(c);
    }
    spec
}

/// Figure 6.3: short term, every 20 episodes 20 frozen episodes, 200 runs.
fn figure_6_3() -> Figure {
    let d = parr_russell();
    let p = Protocol {
        runs: 200,
        episodes: 1000,
        eval_every: 20,
        eval_episodes: 20,
        greedy_episodes: 100,
        trace_every: Some(0),
    };
    Figure {
        id: "6.3",
        title: "Parr and Russell's grid, short term: Sarsa(0.9) and epsilon-SoSMC without exploration after the initial phase",
        claim: "Optimistic Sarsa(0.9) converges to the optimum much faster than epsilon-greedy Sarsa(0.9); SoSMC with a 100-episode initial phase converges to the optimal policy (about 0.25) shortly after it; with 50 episodes it stabilises around 0.1",
        kind: FigureKind::Curves,
        curves: vec![
            experiment(
                "Sarsa(0.9) e-greedy",
                d.clone(),
                Algorithm::SarsaLambda,
                default_learner(Algorithm::SarsaLambda, &d),
                p,
            ),
            experiment(
                "Sarsa(0.9) optimistic",
                d.clone(),
                Algorithm::SarsaLambda,
                with_td(Algorithm::SarsaLambda, &d, |c| {
                    c.initial_value = 1.0;
                    c.exploration = Exploration::Greedy;
                }),
                p,
            ),
            experiment(
                "e-SoSMC 100",
                d.clone(),
                Algorithm::EpsSosmc,
                default_learner(Algorithm::EpsSosmc, &d),
                p,
            ),
            experiment(
                "e-SoSMC 50",
                d.clone(),
                Algorithm::EpsSosmc,
                with_sosmc(Algorithm::EpsSosmc, &d, |c| c.initial_phase = 50),
                p,
            ),
        ],
    }
}

/// Figure 6.4: long term, exploration allowed in SoSMC's second phase.
fn figure_6_4() -> Figure {
    let d = parr_russell();
    let p = Protocol {
        runs: 200,
        episodes: 10_000,
        eval_every: 100,
        eval_episodes: 20,
        greedy_episodes: 100,
        trace_every: Some(0),
    };
    let exploring = |start: f64| {
        with_sosmc(Algorithm::EpsSosmc, &d, |c| {
            c.initial_phase = 50;
            c.assessment = Assessment::PerDecision;
            c.assessing_parameter = Schedule::linear(start, 0.01, 5000);
        })
    };
    Figure {
        id: "6.4",
        title: "Parr and Russell's grid, long term: epsilon-SoSMC exploring in its second phase",
        claim: "With epsilon from 0.2 (or 0.1) decaying to 0.01 over 5000 episodes after a 50-episode initial phase, SoSMC ends between Sarsa and the optimum reached with a 100-episode initial phase, rising linearly with the decay of epsilon",
        kind: FigureKind::Curves,
        curves: vec![
            experiment(
                "Sarsa(0.9) e-greedy",
                d.clone(),
                Algorithm::SarsaLambda,
                default_learner(Algorithm::SarsaLambda, &d),
                p,
            ),
            experiment(
                "e-SoSMC 100",
                d.clone(),
                Algorithm::EpsSosmc,
                default_learner(Algorithm::EpsSosmc, &d),
                p,
            ),
            experiment(
                "e-SoSMC 50, e 0.2->0.01",
                d.clone(),
                Algorithm::EpsSosmc,
                exploring(0.2),
                p,
            ),
            experiment(
                "e-SoSMC 50, e 0.1->0.01",
                d.clone(),
                Algorithm::EpsSosmc,
                exploring(0.1),
                p,
            ),
        ],
    }
}

/// Figures 6.5 - 6.9: the four values of the initial observation during one run.
fn trace_figure(
    id: &'static str,
    title: &'static str,
    claim: &'static str,
    algorithm: Algorithm,
    exploration: Exploration,
) -> Figure {
    let d = parr_russell();
    let p = Protocol {
        runs: 1,
        episodes: 10_000,
        eval_every: 1000,
        eval_episodes: 20,
        greedy_episodes: 100,
        trace_every: None,
    };
    Figure {
        id,
        title,
        claim,
        kind: FigureKind::Traces,
        curves: vec![experiment(
            title,
            d.clone(),
            algorithm,
            // Section 6.1.2's parameters (alpha 0.01, values from -4); the
            // exploration is the figure's.
            with_td(algorithm, &d, |c| c.exploration = exploration),
            p,
        )],
    }
}

/// The penalty kick with the plan schema of `variant`.
fn kick_schema(variant: Variant) -> DomainSpec {
    DomainSpec::PenaltyKick {
        config: PenaltyKickConfig {
            variant,
            ..PenaltyKickConfig::default()
        },
        plan: None,
    }
}

/// "Q-learning" of the schema demonstrations: one-step Q-learning on every
/// state of the constructed process, behaving uniformly at random (it learns
/// off-policy, so neither option's estimate lags), step size 0.02.
fn kick_q_learning(domain: &DomainSpec) -> LearnerSpec {
    with_td(Algorithm::QLearning, domain, |c| {
        c.scope = Scope::Markings;
        c.exploration = Exploration::EpsilonGreedy(Schedule::constant(1.0));
        c.alpha = 0.02;
    })
}

/// The protocol of the schema demonstrations: 200 runs of 2000 episodes.
fn kick_protocol() -> Protocol {
    Protocol {
        runs: 200,
        episodes: 2000,
        eval_every: 100,
        eval_episodes: 10,
        greedy_episodes: 10,
        trace_every: None,
    }
}

/// Not a thesis experiment: chapter 3 argues (3.2.2) without one that methods
/// bootstrapping from the next state cannot tell WalkStraight from Turn in the
/// schema of Figure 3.6, while a method crediting each choice with the return
/// that followed it can. The project's demonstration, with its own parameters.
fn schema_3_6() -> Figure {
    let d = kick_schema(Variant::Schema);
    Figure {
        id: "3.6",
        title: "Demonstration of 3.2.2 (not a thesis experiment): the penalty kick's schema of Figure 3.6",
        claim: "(3.2.2's argument, demonstrated here) Q-learning gives the edges into WalkStraight and Turn the same value (both lead to the Kick state with no reward between), so its greedy choice is a coin toss; SoSMC, crediting each choice with the return that followed it, learns to walk straight",
        kind: FigureKind::Curves,
        curves: vec![
            experiment(
                "Q-learning",
                d.clone(),
                Algorithm::QLearning,
                kick_q_learning(&d),
                kick_protocol(),
            ),
            experiment(
                "e-SoSMC",
                d.clone(),
                Algorithm::EpsSosmc,
                default_learner(Algorithm::EpsSosmc, &d),
                kick_protocol(),
            ),
        ],
    }
}

/// Not a thesis experiment: Figure 3.7's restructured schema, which 3.2.2
/// says lets Q-learning learn the kick; the project's demonstration.
fn schema_3_7() -> Figure {
    let d = kick_schema(Variant::SchemaRestructured);
    Figure {
        id: "3.7",
        title: "Demonstration of 3.2.2 (not a thesis experiment): the restructured schema of Figure 3.7",
        claim: "(3.2.2's argument, demonstrated here) With a Kick state after each choice the plan lets Q-learning learn to walk straight",
        kind: FigureKind::Curves,
        curves: vec![experiment(
            "Q-learning",
            d.clone(),
            Algorithm::QLearning,
            kick_q_learning(&d),
            kick_protocol(),
        )],
    }
}

/// Figure 4.3: e-SoSMC's values of the four actions of the small N-MDP
/// (section 4.2.1) over one run: 100 uniformly random episodes, then the
/// assessment with k = 50 and memoryless averages (the domain's defaults).
fn figure_4_3() -> Figure {
    let d = DomainSpec::Nmdp {
        config: NmdpConfig::default(),
        plan: None,
    };
    let p = Protocol {
        runs: 1,
        episodes: 600,
        eval_every: 50,
        eval_episodes: 20,
        greedy_episodes: 100,
        trace_every: Some(1),
    };
    Figure {
        id: "4.3",
        title: "e-SoSMC in the N-MDP of Figure 4.3: values of A1, B1 (first state) and A2, B2 (second)",
        claim: "After the exploratory phase A1 and A2 hold the highest upper bounds (A1-A2's high variance, not its mean); the assessment averages them down and finds the policy of the best mean, B1-A2",
        kind: FigureKind::Traces,
        curves: vec![experiment(
            "e-SoSMC",
            d.clone(),
            Algorithm::EpsSosmc,
            default_learner(Algorithm::EpsSosmc, &d),
            p,
        )],
    }
}

/// Figure 6.10: Soft-SoSMC's values of the initial observation, one point per episode.
fn figure_6_10() -> Figure {
    let d = parr_russell();
    let p = Protocol {
        runs: 1,
        episodes: 1000,
        eval_every: 100,
        eval_episodes: 20,
        greedy_episodes: 100,
        trace_every: Some(1),
    };
    Figure {
        id: "6.10",
        title: "Soft-SoSMC: values of the four moves in the initial observation",
        claim: "After the initial phase the upper bounds order the moves; in the assessing phase the averaged value of move north prevails, moves with values close to the best are tried more often, move west is never tried again",
        kind: FigureKind::Traces,
        curves: vec![experiment(
            "Soft-SoSMC",
            d.clone(),
            Algorithm::SoftSosmc,
            with_sosmc(Algorithm::SoftSosmc, &d, |c| {
                c.sigma = Sigma::Softmax;
                c.assessment = Assessment::PerDecision;
            }),
            p,
        )],
    }
}

/// Figure 6.11: Sarsa(lambda)'s values of the initial observation.
fn figure_6_11() -> Figure {
    let d = parr_russell();
    let p = Protocol {
        runs: 1,
        episodes: 10_000,
        eval_every: 1000,
        eval_episodes: 20,
        greedy_episodes: 100,
        trace_every: None,
    };
    Figure {
        id: "6.11",
        title: "Sarsa(0.9): values of the four moves in the initial observation",
        claim: "Sarsa(lambda) needs a scale ten times larger than SoSMC (Loch and Singh's result)",
        kind: FigureKind::Traces,
        curves: vec![experiment(
            "Sarsa(0.9)",
            d.clone(),
            Algorithm::SarsaLambda,
            default_learner(Algorithm::SarsaLambda, &d),
            p,
        )],
    }
}

/// Figure 6.13: Sutton's grid.
fn figure_6_13() -> Figure {
    let d = sutton();
    let p = Protocol {
        runs: 50,
        episodes: 40_000,
        eval_every: 200,
        eval_episodes: 0,
        greedy_episodes: 0,
        trace_every: Some(0),
    };
    Figure {
        id: "6.13",
        title: "Sutton's grid: Soft-SoSMC (tau 4, optimistic, explore every 20 episodes) against Sarsa",
        claim: "Soft-SoSMC finds on average a better policy than Sarsa in the episodes considered; Sarsa's value is slightly but significantly smaller (95% CI)",
        kind: FigureKind::Curves,
        curves: sarsa_against_sosmc(&d, p),
    }
}

/// Sarsa(0.9) against Soft-SoSMC in `d`, each with the domain's defaults.
fn sarsa_against_sosmc(d: &DomainSpec, p: Protocol) -> Vec<ExperimentSpec> {
    [
        ("Sarsa(0.9)", Algorithm::SarsaLambda),
        ("Soft-SoSMC", Algorithm::SoftSosmc),
    ]
    .into_iter()
    .map(|(label, algorithm)| experiment(label, d.clone(), algorithm, default_learner(algorithm, d), p))
    .collect()
}

fn keepaway(mode: KeepawayMode) -> DomainSpec {
    DomainSpec::Keepaway {
        config: KeepawayDomainConfig::for_mode(mode),
        plan: None,
    }
}

/// Figure 7.3: one keeper learns the pass decision, two follow the threshold policy.
fn figure_7_3() -> Figure {
    let d = keepaway(KeepawayMode::Pass);
    let p = Protocol {
        runs: 20,
        episodes: 10_000,
        eval_every: 250,
        eval_episodes: 20,
        greedy_episodes: 50,
        trace_every: Some(0),
    };
    Figure {
        id: "7.3",
        title: "Keepaway, single agent learning the pass decision: Sarsa(0.9) against Soft-SoSMC",
        claim: "Sarsa(0.9) only learns to hold the ball about 9 s; Soft-SoSMC (100-episode initial phase, 18 s threshold over 200 exploiting episodes) reaches 16 s within 1000 episodes and about 20 s by 5000; the hand-coded policy measures about 16 s",
        kind: FigureKind::Curves,
        curves: {
            let mut curves = sarsa_against_sosmc(&d, p);
            // Section 6.1.2's alpha, the only Sarsa step size the text gives;
            // the rest as the preset Sarsa.
            curves.push(experiment(
                "Sarsa(0.9), alpha 0.01 (6.1.2)",
                d.clone(),
                Algorithm::SarsaLambda,
                with_td(Algorithm::SarsaLambda, &d, |c| c.alpha = 0.01),
                p,
            ));
            curves
        },
    }
}

/// Figure 7.5: every keeper learns where to stand.
fn figure_7_5() -> Figure {
    let d = keepaway(KeepawayMode::Position);
    let p = Protocol {
        runs: 20,
        episodes: 6000,
        eval_every: 250,
        eval_episodes: 20,
        greedy_episodes: 50,
        trace_every: Some(0),
    };
    Figure {
        id: "7.5",
        title: "Keepaway, multi-agent learning of positioning: Sarsa (epsilon 0.2 to 0 over 4500 episodes) against Soft-SoSMC",
        claim: "Sarsa improves the keepers' behaviour up to 14.7 +/- 0.35 s; Soft-SoSMC improves it quite above the 18 s threshold",
        kind: FigureKind::Curves,
        curves: sarsa_against_sosmc(&d, p),
    }
}

/// Figure 7.6: the value of every position of every keeper during one run.
fn figure_7_6() -> Figure {
    let d = keepaway(KeepawayMode::Position);
    let p = Protocol {
        runs: 1,
        episodes: 5000,
        eval_every: 500,
        eval_episodes: 20,
        greedy_episodes: 50,
        trace_every: Some(10),
    };
    Figure {
        id: "7.6",
        title: "Keepaway positioning: the value of each point for each keeper during one run of Soft-SoSMC",
        claim: "The second keeper settles on corner 2 (top right); the first and third alternate between corner 3 (bottom right) and middle point 1 (left), never taking the same one",
        kind: FigureKind::Traces,
        curves: vec![experiment(
            "Soft-SoSMC",
            d.clone(),
            Algorithm::SoftSosmc,
            default_learner(Algorithm::SoftSosmc, &d),
            p,
        )],
    }
}

/// The fixed keeper policies of chapter 7, for the RESULTS table: the
/// protocol `learnpnp experiment keepaway-fixed` uses by default, so that both
/// give the same numbers.
fn keepaway_baselines() -> Figure {
    let p = default_protocol(&keepaway(KeepawayMode::Fixed(FixedPolicy::Handcoded)));
    let curve = |label: &str, policy: FixedPolicy| {
        experiment(
            label,
            keepaway(KeepawayMode::Fixed(policy)),
            Algorithm::Random,
            LearnerSpec::Random,
            p,
        )
    };
    Figure {
        id: "7.baselines",
        title: "Keepaway: mean episode duration of the fixed keeper policies",
        claim: "The framework's hand-coded policy measures about 16 s on the thesis's system; the thesis's simple threshold policy, played by all keepers, beats the best published results",
        kind: FigureKind::Bars,
        curves: vec![
            curve("random", FixedPolicy::Random),
            curve("always hold", FixedPolicy::AlwaysHold),
            curve("hand-coded", FixedPolicy::Handcoded),
            curve("threshold", FixedPolicy::Threshold),
        ],
    }
}

/// Every preset, in the thesis's order.
pub fn figures() -> Vec<Figure> {
    let eps = Exploration::EpsilonGreedy(Schedule::constant(0.1));
    let soft = |tau: f64| Exploration::Softmax(Schedule::constant(tau));
    vec![
        schema_3_6(),
        schema_3_7(),
        figure_4_3(),
        figure_6_3(),
        figure_6_4(),
        trace_figure(
            "6.5",
            "Q-learning with epsilon-greedy exploration",
            "Q-learning is unstable under epsilon-greedy and cycles, though the greedy action (north) is right most of the time",
            Algorithm::QLearning,
            eps,
        ),
        trace_figure(
            "6.6",
            "Sarsa with epsilon-greedy exploration",
            "Sarsa is unstable under epsilon-greedy and cycles, though the greedy action (north) is right most of the time",
            Algorithm::Sarsa0,
            eps,
        ),
        trace_figure(
            "6.7",
            "Q-learning with softmax exploration, tau 0.01",
            "Under softmax Q-learning is much more stable, and behaves almost like Sarsa",
            Algorithm::QLearning,
            soft(0.01),
        ),
        trace_figure(
            "6.8",
            "Sarsa with softmax exploration, tau 0.01",
            "Under softmax Sarsa is much more stable, and behaves almost like Q-learning",
            Algorithm::Sarsa0,
            soft(0.01),
        ),
        trace_figure(
            "6.9",
            "Sarsa with softmax exploration, tau 1",
            "With a higher temperature the equilibrium reached conveys no good behaviour",
            Algorithm::Sarsa0,
            soft(1.0),
        ),
        figure_6_10(),
        figure_6_11(),
        figure_6_13(),
        keepaway_baselines(),
        figure_7_3(),
        figure_7_5(),
        figure_7_6(),
    ]
}

/// The preset for figure `id` (`6.3`, `fig6.3` and `6-3` all work;
/// `7.baselines` lists the fixed keepaway policies).
pub fn figure(id: &str) -> Option<Figure> {
    let id = id.trim_start_matches("fig").replace('-', ".");
    figures().into_iter().find(|f| f.id == id)
}
