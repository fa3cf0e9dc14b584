//! `summary.json`'s `cycles_per_second` counts every primitive action (every
//! simulated cycle in Keepaway) of every episode played, evaluations
//! included, in every domain; `actions_per_second` only the learning episodes'.

use learnpnp::domains::keepaway::{FixedPolicy, KeepawayDomainConfig, KeepawayMode};
use learnpnp::experiment::output::summary;
use learnpnp::experiment::presets;
use learnpnp::experiment::spec::{DomainSpec, ExperimentSpec, LearnerSpec, Protocol};

use crate::util::run_quietly;

fn protocol(eval_episodes: usize, greedy_episodes: usize) -> Protocol {
    Protocol {
        runs: 2,
        episodes: 40,
        eval_every: 20,
        eval_episodes,
        greedy_episodes,
        trace_every: Some(0),
    }
}

/// The first curve of `figure`'s preset with `protocol`.
fn preset(figure: &str, protocol: Protocol) -> ExperimentSpec {
    let mut spec = presets::figure(figure).expect("a preset").curves.remove(0);
    spec.protocol = protocol;
    spec
}

#[test]
fn without_evaluations_every_action_is_a_learning_action() {
    let output = run_quietly(&preset("6.3", protocol(0, 0)), 1);
    for run in &output.runs {
        assert_eq!(run.actions_played, Some(run.actions));
    }
}

#[test]
fn evaluations_count_in_every_domain() {
    for figure in ["6.3", "6.13", "3.6", "4.3"] {
        let output = run_quietly(&preset(figure, protocol(5, 5)), 1);
        for run in &output.runs {
            let played = run.actions_played.expect("the domain counts its actions");
            assert!(played > run.actions, "figure {figure}: {played} <= {}", run.actions);
        }
        let s = summary(&output);
        let total: u64 = output.runs.iter().filter_map(|r| r.actions_played).sum();
        assert_eq!(s.cycles_per_second, Some(total as f64 / output.wall_seconds.max(1e-9)));
    }
}

#[test]
fn fixed_keepers_count_the_evaluations_cycles() {
    let spec = ExperimentSpec {
        label: "hand-coded".into(),
        domain: DomainSpec::Keepaway {
            config: KeepawayDomainConfig::for_mode(KeepawayMode::Fixed(FixedPolicy::Handcoded)),
            plan: None,
        },
        algorithm: learnpnp::experiment::spec::Algorithm::Random,
        learner: LearnerSpec::Random,
        protocol: Protocol {
            runs: 1,
            episodes: 2,
            eval_every: 2,
            eval_episodes: 10,
            greedy_episodes: 0,
            trace_every: Some(0),
        },
        seed: 3,
        initial_values: Vec::new(),
    };
    let output = run_quietly(&spec, 1);
    let run = &output.runs[0];
    // Twenty evaluated episodes beside two learning ones: every episode lasts
    // some cycles, so the evaluations' cycles dominate.
    let played = run.actions_played.expect("Keepaway counts its cycles");
    assert!(
        played > 5 * run.actions,
        "{played} cycles played, {} learning",
        run.actions
    );
}
