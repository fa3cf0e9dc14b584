//! The thesis's figures as experiment presets (chapters 4, 6 and 7), with its parameters
//! where it gives them and documented choices where it does not
//! (docs/results/RESULTS.md lists both).
//!
//! The presets are one table, `FIGURES`: a row per figure with its domain,
//! its protocol and its curves, each curve an algorithm with the domain's
//! defaults and the parameters it changes, stated as `learnpnp experiment`'s
//! flags state them ([`Overrides`](crate::experiment::defaults::Overrides)). [`figures`](crate::experiment::presets::figures) builds every figure from it.

use super::defaults::{Overrides, default_learner, default_protocol};
use super::spec::{Algorithm, DomainSpec, ExperimentSpec, Protocol};
use crate::domains::keepaway::{FixedPolicy, KeepawayDomainConfig, KeepawayMode};
use crate::domains::nmdp::NmdpConfig;
use crate::domains::parr_russell::ParrRussellConfig;
use crate::domains::penalty_kick::{PenaltyKickConfig, Variant};
use crate::domains::sutton::SuttonConfig;
use crate::learning::{Assessment, Schedule};

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

/// A domain of the presets, in its default configuration.
#[derive(Debug, Clone, Copy)]
enum World {
    /// Parr and Russell's 4 x 3 grid.
    ParrRussell,
    /// Sutton's 9 x 6 grid.
    Sutton,
    /// The small N-MDP of section 4.2.1.
    Nmdp,
    /// The penalty kick with the plan schema of the variant.
    Kick(Variant),
    /// Keepaway 3 vs 2 in a mode.
    Keepaway(KeepawayMode),
}

impl World {
    /// The domain, with its built-in plan.
    fn spec(self) -> DomainSpec {
        match self {
            World::ParrRussell => DomainSpec::ParrRussell {
                config: ParrRussellConfig::default(),
                plan: None,
            },
            World::Sutton => DomainSpec::Sutton {
                config: SuttonConfig::default(),
                plan: None,
            },
            World::Nmdp => DomainSpec::Nmdp {
                config: NmdpConfig::default(),
                plan: None,
            },
            World::Kick(variant) => DomainSpec::PenaltyKick {
                config: PenaltyKickConfig {
                    variant,
                    ..PenaltyKickConfig::default()
                },
                plan: None,
            },
            World::Keepaway(mode) => DomainSpec::Keepaway {
                config: KeepawayDomainConfig::for_mode(mode),
                plan: None,
            },
        }
    }
}

/// One curve of a figure: `algorithm` with its defaults in the domain, but
/// for the parameters in `learner`.
#[derive(Debug, Clone, Copy)]
struct Curve {
    /// The curve's label in the plot and its result directory's name.
    label: &'static str,
    /// The learning algorithm.
    algorithm: Algorithm,
    /// The parameters that differ from the algorithm's defaults in the domain.
    learner: Overrides,
    /// The domain, when it is not the figure's (the fixed keeper policies).
    world: Option<World>,
}

/// A curve of `algorithm` with its defaults.
const fn curve(label: &'static str, algorithm: Algorithm) -> Curve {
    tuned(label, algorithm, Overrides::NONE)
}

/// A curve of `algorithm` with the parameters of `learner`.
const fn tuned(label: &'static str, algorithm: Algorithm, learner: Overrides) -> Curve {
    Curve {
        label,
        algorithm,
        learner,
        world: None,
    }
}

/// A curve of the fixed keeper `policy`: nothing learns.
const fn fixed(label: &'static str, policy: FixedPolicy) -> Curve {
    Curve {
        world: Some(World::Keepaway(KeepawayMode::Fixed(policy))),
        ..curve(label, Algorithm::Random)
    }
}

/// A protocol, its fields in [`Protocol`]'s order.
const fn protocol(
    runs: usize,
    episodes: u64,
    eval_every: u64,
    eval_episodes: usize,
    greedy_episodes: usize,
    trace_every: Option<u64>,
) -> Option<Protocol> {
    Some(Protocol {
        runs,
        episodes,
        eval_every,
        eval_episodes,
        greedy_episodes,
        trace_every,
    })
}

/// A figure of the table.
#[derive(Debug)]
struct Row {
    /// The thesis's figure number.
    id: &'static str,
    /// What it shows.
    title: &'static str,
    /// What the thesis claims from it.
    claim: &'static str,
    /// Curves, traces or bars.
    kind: FigureKind,
    /// The domain of every curve that names none.
    world: World,
    /// The protocol of every curve; `None`: the domain's default protocol,
    /// `learnpnp experiment`'s.
    protocol: Option<Protocol>,
    /// The curves.
    curves: &'static [Curve],
}

/// The protocol of the value traces of Figures 6.5 - 6.9 and 6.11: one run of
/// 10000 episodes.
const TRACE_RUN: Option<Protocol> = protocol(1, 10_000, 1000, 20, 100, None);

/// The protocol of the schema demonstrations: 200 runs of 2000 episodes.
const KICK: Option<Protocol> = protocol(200, 2000, 100, 10, 10, None);

/// "Q-learning" of the schema demonstrations: one-step Q-learning on every
/// state of the constructed process, behaving uniformly at random (it learns
/// off-policy, so neither option's estimate lags), step size 0.02.
const KICK_Q_LEARNING: Curve = tuned(
    "Q-learning",
    Algorithm::QLearning,
    Overrides {
        every_marking: true,
        epsilon: Some(Schedule::constant(1.0)),
        alpha: Some(0.02),
        ..Overrides::NONE
    },
);

/// e-SoSMC exploring in its second phase (Figure 6.4): a 50-episode initial
/// phase, then epsilon from `start` down to 0.01 over 5000 episodes, per decision.
const fn exploring(label: &'static str, start: f64) -> Curve {
    tuned(
        label,
        Algorithm::EpsSosmc,
        Overrides {
            initial_phase: Some(50),
            assessment: Some(Assessment::PerDecision),
            epsilon: Some(Schedule::linear(start, 0.01, 5000)),
            ..Overrides::NONE
        },
    )
}

/// Epsilon-greedy exploration with a constant `epsilon` (`--epsilon`).
const fn epsilon_greedy(epsilon: f64) -> Overrides {
    Overrides {
        epsilon: Some(Schedule::constant(epsilon)),
        ..Overrides::NONE
    }
}

/// Softmax exploration with a constant temperature `tau` (`--tau`).
const fn softmax(tau: f64) -> Overrides {
    Overrides {
        tau: Some(Schedule::constant(tau)),
        ..Overrides::NONE
    }
}

/// Sarsa(0.9) against Soft-SoSMC, each with the domain's defaults.
const SARSA_AGAINST_SOFT_SOSMC: [Curve; 2] = [
    curve("Sarsa(0.9)", Algorithm::SarsaLambda),
    curve("Soft-SoSMC", Algorithm::SoftSosmc),
];

/// Every preset, in the thesis's order.
static FIGURES: &[Row] = &[
    // Not a thesis experiment: chapter 3 argues (3.2.2) without one that methods
    // bootstrapping from the next state cannot tell WalkStraight from Turn in the
    // schema of Figure 3.6, while a method crediting each choice with the return
    // that followed it can. The project's demonstration, with its own parameters.
    Row {
        id: "3.6",
        title: "Demonstration of 3.2.2 (not a thesis experiment): the penalty kick's schema of Figure 3.6",
        claim: "(3.2.2's argument, demonstrated here) Q-learning gives the edges into WalkStraight and Turn the same value (both lead to the Kick state with no reward between), so its greedy choice is a coin toss; SoSMC, crediting each choice with the return that followed it, learns to walk straight",
        kind: FigureKind::Curves,
        world: World::Kick(Variant::Schema),
        protocol: KICK,
        curves: &[KICK_Q_LEARNING, curve("e-SoSMC", Algorithm::EpsSosmc)],
    },
    // Not a thesis experiment: Figure 3.7's restructured schema, which 3.2.2
    // says lets Q-learning learn the kick; the project's demonstration.
    Row {
        id: "3.7",
        title: "Demonstration of 3.2.2 (not a thesis experiment): the restructured schema of Figure 3.7",
        claim: "(3.2.2's argument, demonstrated here) With a Kick state after each choice the plan lets Q-learning learn to walk straight",
        kind: FigureKind::Curves,
        world: World::Kick(Variant::SchemaRestructured),
        protocol: KICK,
        curves: &[KICK_Q_LEARNING],
    },
    // Figure 4.3: e-SoSMC's values of the four actions of the small N-MDP
    // (section 4.2.1) over one run: 100 uniformly random episodes, then the
    // assessment with k = 50 and memoryless averages (the domain's defaults).
    Row {
        id: "4.3",
        title: "e-SoSMC in the N-MDP of Figure 4.3: values of A1, B1 (first state) and A2, B2 (second)",
        claim: "After the exploratory phase A1 and A2 hold the highest upper bounds (A1-A2's high variance, not its mean); the assessment averages them down and finds the policy of the best mean, B1-A2",
        kind: FigureKind::Traces,
        world: World::Nmdp,
        protocol: protocol(1, 600, 50, 20, 100, Some(1)),
        curves: &[curve("e-SoSMC", Algorithm::EpsSosmc)],
    },
    // Figure 6.3: short term, every 20 episodes 20 frozen episodes, 200 runs.
    Row {
        id: "6.3",
        title: "Parr and Russell's grid, short term: Sarsa(0.9) and epsilon-SoSMC without exploration after the initial phase",
        claim: "Optimistic Sarsa(0.9) converges to the optimum much faster than epsilon-greedy Sarsa(0.9); SoSMC with a 100-episode initial phase converges to the optimal policy (about 0.25) shortly after it; with 50 episodes it stabilises around 0.1",
        kind: FigureKind::Curves,
        world: World::ParrRussell,
        protocol: protocol(200, 1000, 20, 20, 100, Some(0)),
        curves: &[
            curve("Sarsa(0.9) e-greedy", Algorithm::SarsaLambda),
            tuned(
                "Sarsa(0.9) optimistic",
                Algorithm::SarsaLambda,
                Overrides {
                    initial_value: Some(1.0),
                    greedy: true,
                    ..Overrides::NONE
                },
            ),
            curve("e-SoSMC 100", Algorithm::EpsSosmc),
            tuned(
                "e-SoSMC 50",
                Algorithm::EpsSosmc,
                Overrides {
                    initial_phase: Some(50),
                    ..Overrides::NONE
                },
            ),
        ],
    },
    // Figure 6.4: long term, exploration allowed in SoSMC's second phase.
    Row {
        id: "6.4",
        title: "Parr and Russell's grid, long term: epsilon-SoSMC exploring in its second phase",
        claim: "With epsilon from 0.2 (or 0.1) decaying to 0.01 over 5000 episodes after a 50-episode initial phase, SoSMC ends between Sarsa and the optimum reached with a 100-episode initial phase, rising linearly with the decay of epsilon",
        kind: FigureKind::Curves,
        world: World::ParrRussell,
        protocol: protocol(200, 10_000, 100, 20, 100, Some(0)),
        curves: &[
            curve("Sarsa(0.9) e-greedy", Algorithm::SarsaLambda),
            curve("e-SoSMC 100", Algorithm::EpsSosmc),
            exploring("e-SoSMC 50, e 0.2->0.01", 0.2),
            exploring("e-SoSMC 50, e 0.1->0.01", 0.1),
        ],
    },
    // Figures 6.5 - 6.9: the four values of the initial observation during
    // one run, with section 6.1.2's parameters (alpha 0.01, values from -4);
    // the exploration is the figure's. Each curve is labelled with its title.
    Row {
        id: "6.5",
        title: "Q-learning with epsilon-greedy exploration",
        claim: "Q-learning is unstable under epsilon-greedy and cycles, though the greedy action (north) is right most of the time",
        kind: FigureKind::Traces,
        world: World::ParrRussell,
        protocol: TRACE_RUN,
        curves: &[tuned(
            "Q-learning with epsilon-greedy exploration",
            Algorithm::QLearning,
            epsilon_greedy(0.1),
        )],
    },
    Row {
        id: "6.6",
        title: "Sarsa with epsilon-greedy exploration",
        claim: "Sarsa is unstable under epsilon-greedy and cycles, though the greedy action (north) is right most of the time",
        kind: FigureKind::Traces,
        world: World::ParrRussell,
        protocol: TRACE_RUN,
        curves: &[tuned(
            "Sarsa with epsilon-greedy exploration",
            Algorithm::Sarsa0,
            epsilon_greedy(0.1),
        )],
    },
    Row {
        id: "6.7",
        title: "Q-learning with softmax exploration, tau 0.01",
        claim: "Under softmax Q-learning is much more stable, and behaves almost like Sarsa",
        kind: FigureKind::Traces,
        world: World::ParrRussell,
        protocol: TRACE_RUN,
        curves: &[tuned(
            "Q-learning with softmax exploration, tau 0.01",
            Algorithm::QLearning,
            softmax(0.01),
        )],
    },
    Row {
        id: "6.8",
        title: "Sarsa with softmax exploration, tau 0.01",
        claim: "Under softmax Sarsa is much more stable, and behaves almost like Q-learning",
        kind: FigureKind::Traces,
        world: World::ParrRussell,
        protocol: TRACE_RUN,
        curves: &[tuned(
            "Sarsa with softmax exploration, tau 0.01",
            Algorithm::Sarsa0,
            softmax(0.01),
        )],
    },
    Row {
        id: "6.9",
        title: "Sarsa with softmax exploration, tau 1",
        claim: "With a higher temperature the equilibrium reached conveys no good behaviour",
        kind: FigureKind::Traces,
        world: World::ParrRussell,
        protocol: TRACE_RUN,
        curves: &[tuned(
            "Sarsa with softmax exploration, tau 1",
            Algorithm::Sarsa0,
            softmax(1.0),
        )],
    },
    // Figure 6.10: Soft-SoSMC's values of the initial observation, one point
    // per episode; softmax (Soft-SoSMC's sigma), exploring per decision.
    Row {
        id: "6.10",
        title: "Soft-SoSMC: values of the four moves in the initial observation",
        claim: "After the initial phase the upper bounds order the moves; in the assessing phase the averaged value of move north prevails, moves with values close to the best are tried more often, move west is never tried again",
        kind: FigureKind::Traces,
        world: World::ParrRussell,
        protocol: protocol(1, 1000, 100, 20, 100, Some(1)),
        curves: &[tuned(
            "Soft-SoSMC",
            Algorithm::SoftSosmc,
            Overrides {
                assessment: Some(Assessment::PerDecision),
                ..Overrides::NONE
            },
        )],
    },
    // Figure 6.11: Sarsa(lambda)'s values of the initial observation.
    Row {
        id: "6.11",
        title: "Sarsa(0.9): values of the four moves in the initial observation",
        claim: "Sarsa(lambda) needs a scale ten times larger than SoSMC (Loch and Singh's result)",
        kind: FigureKind::Traces,
        world: World::ParrRussell,
        protocol: TRACE_RUN,
        curves: &[curve("Sarsa(0.9)", Algorithm::SarsaLambda)],
    },
    // Figure 6.13: Sutton's grid.
    Row {
        id: "6.13",
        title: "Sutton's grid: Soft-SoSMC (tau 4, optimistic, explore every 20 episodes) against Sarsa",
        claim: "Soft-SoSMC finds on average a better policy than Sarsa in the episodes considered; Sarsa's value is slightly but significantly smaller (95% CI)",
        kind: FigureKind::Curves,
        world: World::Sutton,
        protocol: protocol(50, 40_000, 200, 0, 0, Some(0)),
        curves: &SARSA_AGAINST_SOFT_SOSMC,
    },
    // The fixed keeper policies of chapter 7, for the RESULTS table, with the
    // protocol `learnpnp experiment keepaway-fixed` uses by default, so that
    // both give the same numbers.
    Row {
        id: "7.baselines",
        title: "Keepaway: mean episode duration of the fixed keeper policies",
        claim: "The framework's hand-coded policy measures about 16 s on the thesis's system; the thesis's simple threshold policy, played by all keepers, beats the best published results",
        kind: FigureKind::Bars,
        world: World::Keepaway(KeepawayMode::Fixed(FixedPolicy::Handcoded)),
        protocol: None,
        curves: &[
            fixed("random", FixedPolicy::Random),
            fixed("always hold", FixedPolicy::AlwaysHold),
            fixed("hand-coded", FixedPolicy::Handcoded),
            fixed("threshold", FixedPolicy::Threshold),
        ],
    },
    // Figure 7.3: one keeper learns the pass decision, two follow the threshold policy.
    Row {
        id: "7.3",
        title: "Keepaway, single agent learning the pass decision: Sarsa(0.9) against Soft-SoSMC",
        claim: "Sarsa(0.9) only learns to hold the ball about 9 s; Soft-SoSMC (100-episode initial phase, 18 s threshold over 200 exploiting episodes) reaches 16 s within 1000 episodes and about 20 s by 5000; the hand-coded policy measures about 16 s",
        kind: FigureKind::Curves,
        world: World::Keepaway(KeepawayMode::Pass),
        protocol: protocol(20, 10_000, 250, 20, 50, Some(0)),
        curves: &[
            SARSA_AGAINST_SOFT_SOSMC[0],
            SARSA_AGAINST_SOFT_SOSMC[1],
            // Section 6.1.2's alpha, the only Sarsa step size the text gives;
            // the rest as the preset Sarsa.
            tuned(
                "Sarsa(0.9), alpha 0.01 (6.1.2)",
                Algorithm::SarsaLambda,
                Overrides {
                    alpha: Some(0.01),
                    ..Overrides::NONE
                },
            ),
        ],
    },
    // Figure 7.5: every keeper learns where to stand.
    Row {
        id: "7.5",
        title: "Keepaway, multi-agent learning of positioning: Sarsa (epsilon 0.2 to 0 over 4500 episodes) against Soft-SoSMC",
        claim: "Sarsa improves the keepers' behaviour up to 14.7 +/- 0.35 s; Soft-SoSMC improves it quite above the 18 s threshold",
        kind: FigureKind::Curves,
        world: World::Keepaway(KeepawayMode::Position),
        protocol: protocol(20, 6000, 250, 20, 50, Some(0)),
        curves: &SARSA_AGAINST_SOFT_SOSMC,
    },
    // Figure 7.6: the value of every position of every keeper during one run.
    Row {
        id: "7.6",
        title: "Keepaway positioning: the value of each point for each keeper during one run of Soft-SoSMC",
        claim: "The second keeper settles on corner 2 (top right); the first and third alternate between corner 3 (bottom right) and middle point 1 (left), never taking the same one",
        kind: FigureKind::Traces,
        world: World::Keepaway(KeepawayMode::Position),
        protocol: protocol(1, 5000, 500, 20, 50, Some(10)),
        curves: &[curve("Soft-SoSMC", Algorithm::SoftSosmc)],
    },
];

impl Row {
    /// The figure: each curve's experiment built from the table.
    fn figure(&self) -> Figure {
        let protocol = self.protocol.unwrap_or_else(|| default_protocol(&self.world.spec()));
        let curves = self
            .curves
            .iter()
            .map(|curve| {
                let domain = curve.world.unwrap_or(self.world).spec();
                let mut learner = default_learner(curve.algorithm, &domain);
                curve.learner.apply(&mut learner);
                ExperimentSpec {
                    label: curve.label.to_string(),
                    domain,
                    algorithm: curve.algorithm,
                    learner,
                    protocol,
                    seed: SEED,
                    initial_values: Vec::new(),
                }
            })
            .collect();
        Figure {
            id: self.id,
            title: self.title,
            claim: self.claim,
            kind: self.kind,
            curves,
        }
    }
}

/// Every preset, in the thesis's order.
pub fn figures() -> Vec<Figure> {
    FIGURES.iter().map(Row::figure).collect()
}

/// The preset for figure `id` (`6.3`, `fig6.3` and `6-3` all work;
/// `7.baselines` lists the fixed keepaway policies).
pub fn figure(id: &str) -> Option<Figure> {
    let id = id.trim_start_matches("fig").replace('-', ".");
    FIGURES.iter().find(|row| row.id == id).map(Row::figure)
}

#[cfg(test)]
mod tests {
    use std::collections::HashSet;

    use super::*;
    use crate::experiment::spec::LearnerSpec;

    #[test]
    fn every_row_builds_a_valid_figure_found_by_its_id() {
        let mut ids = HashSet::new();
        for row in FIGURES {
            assert!(ids.insert(row.id), "figure {} twice", row.id);
            let figure = figure(&format!("fig{}", row.id.replace('.', "-"))).expect("found by id");
            assert_eq!((figure.id, figure.curves.len()), (row.id, row.curves.len()));
            let mut labels = HashSet::new();
            for spec in &figure.curves {
                assert!(labels.insert(&spec.label), "{}: curve {} twice", row.id, spec.label);
                spec.validate()
                    .unwrap_or_else(|e| panic!("{}: {}: {e}", row.id, spec.label));
            }
        }
        assert_eq!(figures().len(), FIGURES.len());
    }

    #[test]
    fn a_curve_changes_only_the_parameters_it_names() {
        let row = FIGURES.iter().find(|row| row.id == "7.3").expect("7.3");
        let figure = row.figure();
        let [sarsa, _, slow] = figure.curves.as_slice() else {
            panic!("three curves")
        };
        let (LearnerSpec::Td(sarsa), LearnerSpec::Td(slow)) = (&sarsa.learner, &slow.learner) else {
            panic!("TD learners")
        };
        assert_ne!(sarsa.alpha, 0.01);
        assert_eq!(
            crate::learning::TdConfig {
                alpha: sarsa.alpha,
                ..*slow
            },
            *sarsa
        );
    }
}
