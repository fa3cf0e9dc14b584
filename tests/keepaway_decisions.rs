//! Keepaway paused at pass decisions (`PassDecisions`, behind the Python
//! environments) plays the in-process task's episodes when answered as its
//! fixed policy would answer.

use learnpnp::domains::Task;
use learnpnp::domains::keepaway::{FixedPolicy, KeepawayDomainConfig, KeepawayMode, KeepawayTask, PassDecisions, Stop};
use learnpnp::learning::EpisodeMode;
use learnpnp::rng::seeded;
use learnpnp_keepaway::{BaselinePolicy, KeeperAction};

/// Episode durations of `keepaway-fixed --policy handcoded` on the task's stream `seed`.
fn task_durations(seed: u64, episodes: usize) -> Vec<f64> {
    let config = KeepawayDomainConfig::for_mode(KeepawayMode::Fixed(FixedPolicy::Handcoded));
    let mut task = KeepawayTask::new(config, None, &mut |_| unreachable!("nothing learns"), seeded(seed)).unwrap();
    (0..episodes)
        .map(|_| task.episode(EpisodeMode::Learn).unwrap().ret)
        .collect()
}

/// The same with `deciders` keepers answered from outside by the hand-coded
/// choice each decision reports; also checks that the steps' seconds add up.
fn answered_durations(seed: u64, episodes: usize, deciders: usize) -> (Vec<f64>, usize) {
    let config = KeepawayDomainConfig::for_mode(KeepawayMode::Fixed(FixedPolicy::Handcoded)).simulator();
    let mut game = PassDecisions::new(config, deciders, |_| BaselinePolicy::HandCoded, seeded(seed)).unwrap();
    let (mut durations, mut decisions) = (Vec::new(), 0);
    while durations.len() < episodes {
        let start = game.reset();
        durations.extend(start.skipped);
        let (mut decision, mut total) = (start.decision, start.seconds_before);
        loop {
            assert!(decision.keeper < deciders);
            decisions += 1;
            let (stop, seconds) = game.step(decision.handcoded);
            total += seconds;
            match stop {
                Stop::Decide(next) => decision = next,
                Stop::Ended { seconds } => {
                    assert!(
                        (total - seconds).abs() < 1e-9,
                        "steps add up to the episode: {total} vs {seconds}"
                    );
                    durations.push(seconds);
                    break;
                }
            }
        }
    }
    durations.truncate(episodes);
    (durations, decisions)
}

#[test]
fn answered_as_the_handcoded_policy_it_plays_the_tasks_episodes() {
    for seed in [3, 11] {
        let expected = task_durations(seed, 40);
        for deciders in [1, 3] {
            let (played, decisions) = answered_durations(seed, 40, deciders);
            assert_eq!(played, expected, "seed {seed}, {deciders} decider(s)");
            assert!(decisions > 40, "decisions were asked: {decisions}");
        }
    }
}

#[test]
fn other_answers_play_other_episodes_and_after_the_end_nothing_plays() {
    let config = KeepawayDomainConfig::default().simulator();
    let mut game = PassDecisions::new(config, 1, |_| BaselinePolicy::HandCoded, seeded(5)).unwrap();
    game.reset();
    let mut ended = None;
    for _ in 0..10_000 {
        if let (Stop::Ended { seconds }, _) = game.step(KeeperAction::Pass2) {
            ended = Some(seconds);
            break;
        }
    }
    let seconds = ended.expect("an episode ends");
    assert_eq!(game.step(KeeperAction::Hold), (Stop::Ended { seconds }, 0.0));
}
