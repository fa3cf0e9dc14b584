//! The best memoryless policy of Sutton's grid (`sutton::optimum`), the
//! ceiling of Figure 6.13, against the domain itself: no greedy policy a
//! learner reaches scores above it in the task's own evaluation, the
//! fully observable optimum is no lower, and the reference drawn beside
//! the figure is it.

use learnpnp::domains::sutton::{SuttonConfig, optimum};
use learnpnp::experiment::presets;
use learnpnp::experiment::spec::Protocol;

use crate::util::run_quietly;

#[test]
fn no_learned_greedy_policy_scores_above_the_ceiling() {
    let config = SuttonConfig::default();
    let (_, ceiling) = optimum::optimum(&config);
    assert!(ceiling <= optimum::fully_observable(&config));
    let figure = presets::figure("6.13").expect("the preset");
    for mut spec in figure.curves {
        spec.protocol = Protocol {
            runs: 8,
            episodes: 2000,
            eval_every: 100,
            eval_episodes: 0,
            greedy_episodes: 0,
            trace_every: Some(0),
        };
        let output = run_quietly(&spec, 2);
        for run in &output.runs {
            for &score in &run.evals {
                assert!(score <= ceiling + 1e-9, "{}: {score} above {ceiling}", spec.label);
            }
        }
        let reference = spec.domain.reference().expect("Sutton's grid has its reference");
        assert_eq!(reference.value, ceiling);
    }
}
