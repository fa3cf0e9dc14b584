//! The agents' live feed, read in the ROS 2 world process and republished
//! as the plan's state ([`Republisher`](crate::plan_state::Republisher)).
//!
//! The world only reads the feed (`learnpnp_system::ipc::feed::FeedReader`:
//! every record checked, garbage refused and counted), on a thread of its
//! own: it is not on the learner's path, and a world that cannot read the
//! feed says why and runs its episodes all the same.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::thread::JoinHandle;
use std::time::Duration;

use learnpnp_system::ipc::feed::{FeedCounts, FeedReader};
use learnpnp_system::ipc::services::node;
use learnpnp_system::multiprocess::host::world::WorldRun;
use serde::Serialize;

use crate::plan_state::{Republished, Republisher};

/// How often the feed is read: a marking sampled at 30 a second
/// (`learnpnp_feed::MARKINGS_PER_SECOND`) waits at most this long.
pub const READ_EVERY: Duration = Duration::from_millis(20);

/// What the plan state's republishing did, for the world's report.
#[derive(Debug, Default, Clone, Serialize, PartialEq, Eq)]
pub struct PlanStateCounts {
    /// The feed as read: records received, refused (by reason) and lost.
    pub feed: FeedCounts,
    /// What was republished and refused here.
    pub republished: Republished,
    /// Why the feed could not be read (the world ran on without it).
    pub unreadable: Option<String>,
}

/// The thread reading the feed.
pub struct FeedRepublisher {
    stop: Arc<AtomicBool>,
    thread: JoinHandle<PlanStateCounts>,
}

impl FeedRepublisher {
    /// Reads `run`'s agents' feeds every [`READ_EVERY`] and republishes
    /// them through `republisher` until [`FeedRepublisher::stop`].
    pub fn start(run: WorldRun, mut republisher: Republisher) -> std::io::Result<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        let thread = std::thread::Builder::new().name("plan-state".into()).spawn(move || {
            let mut counts = PlanStateCounts::default();
            let opened = node(&run.namespace, "ros2-plan-state")
                .and_then(|n| FeedReader::open(&n, run.agents, run.run_id, run.run).map(|r| (n, r)));
            let (_node, mut reader) = match opened {
                Ok(opened) => opened,
                Err(e) => {
                    eprintln!("learnpnp-ros2-world: the agents' feed cannot be read ({e}); no plan state");
                    counts.unreadable = Some(e.to_string());
                    return counts;
                }
            };
            loop {
                // The last read after the stop takes what came before it.
                let last = stopped.load(Ordering::Relaxed);
                if let Err(e) = reader.read(|event| republisher.event(&event)) {
                    eprintln!("learnpnp-ros2-world: reading the agents' feed: {e}; no more plan state");
                    counts.unreadable = Some(e.to_string());
                    break;
                }
                if last {
                    break;
                }
                std::thread::sleep(READ_EVERY);
            }
            counts.feed = reader.counts().clone();
            counts.republished = republisher.counts().clone();
            counts
        })?;
        Ok(FeedRepublisher { stop, thread })
    }

    /// Stops reading: what was read and republished.
    pub fn stop(self) -> PlanStateCounts {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.join().unwrap_or_else(|_| PlanStateCounts {
            unreadable: Some("the plan state's thread panicked".into()),
            ..PlanStateCounts::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;
    use std::time::Instant;

    use learnpnp_feed::{ChoiceMade, FeedEvent, FeedSink, MarkingSample, OptionValue, PlaceTokens, Source};
    use learnpnp_system::ipc::feed::{FeedPublisher, FeedServices};
    use learnpnp_system::ipc::namespace::Namespace;
    use learnpnp_system::ipc::wait::WaitStrategy;
    use learnpnp_system::multiprocess::Clock;
    use zenoh::Wait;

    use super::*;
    use crate::node::Node;
    use crate::node::tests::loopback_pair;
    use crate::plan_state::STRING;
    use crate::types::{Registry, Value};

    fn marking(agent: u32) -> FeedEvent {
        FeedEvent::Marking(MarkingSample {
            source: Source { run: 0, agent },
            sub_plan: None,
            episode: 0,
            step: 3,
            tokens: vec![1, 0],
            marked: vec![PlaceTokens {
                label: "walk".into(),
                tokens: 1,
            }],
            running: vec!["forward".into()],
        })
    }

    fn choice(taken: u32) -> FeedEvent {
        let option = |label: &str, value| OptionValue {
            label: label.into(),
            value,
            updates: 0,
        };
        FeedEvent::Choice(ChoiceMade {
            source: Source { run: 0, agent: 0 },
            episode: 0,
            step: 4,
            choice_point: "choose".into(),
            options: vec![option("forward", Some(-4.0)), option("back", None)],
            taken,
            greedy: 0,
            explored: false,
        })
    }

    #[test]
    fn the_agents_feed_is_republished_and_garbage_refused() {
        let owner = Namespace::claim_unique().unwrap();
        let namespace = owner.namespace().clone();
        let supervisor = node(&namespace, "supervisor").unwrap();
        let services = FeedServices::create(&supervisor, 1).unwrap();
        let (a, b) = loopback_pair();
        let registry = Arc::new(Registry::new());
        let world = Node::new(a, Arc::clone(&registry), 0, "/", "learnpnp_world").unwrap();
        let got = Arc::new(Mutex::new(Vec::new()));
        let g = Arc::clone(&got);
        let _sub = b
            .declare_subscriber("0/plan/agent1/pnp/**")
            .callback(move |s| {
                let name = s.key_expr().as_str().split('/').nth(4).unwrap_or_default().to_string();
                g.lock().unwrap().push((name, s.payload().to_bytes().to_vec()));
            })
            .wait()
            .unwrap();
        let run = WorldRun {
            namespace: namespace.clone(),
            run_id: 7,
            run: 0,
            agents: 1,
            clock: Clock::Lockstep,
            period: Duration::from_millis(100),
            wait: WaitStrategy::Yield,
            seed: 1,
        };
        let thread = FeedRepublisher::start(run, Republisher::new(&world, "/plan", 1).unwrap()).unwrap();
        let agent = FeedPublisher::open(&namespace, 0, 7).unwrap();
        // Garbage: another run's agent, and a choice whose option taken is not among its options.
        let other = FeedPublisher::open(&namespace, 0, 8).unwrap();
        other.publish(&marking(0));
        agent.publish(&choice(5));
        let start = Instant::now();
        while got.lock().unwrap().len() < 3 && start.elapsed() < Duration::from_secs(10) {
            agent.publish(&marking(0));
            agent.publish(&choice(1));
            std::thread::sleep(Duration::from_millis(50));
        }
        let counts = thread.stop();
        let got = got.lock().unwrap();
        let data = |topic: &str| {
            let (_, bytes) = got
                .iter()
                .find(|(t, _)| t == topic)
                .unwrap_or_else(|| panic!("{topic}: {got:?}"));
            match registry.decode(STRING, bytes).unwrap().get("data") {
                Some(Value::Str(s)) => s.clone(),
                other => panic!("{other:?}"),
            }
        };
        assert_eq!(data("currentActivePlaces"), "walk");
        assert_eq!(data("runningActions"), "forward");
        assert_eq!(
            data("choices"),
            r#"{"choice":"choose","options":[{"name":"forward","value":-4.0},{"name":"back","value":null}],"chosen":"back"}"#
        );
        assert_eq!(counts.feed.rejected.run, 1, "{counts:?}");
        assert_eq!(counts.republished.refused, 1, "{counts:?}");
        assert!(
            counts.republished.markings >= 1 && counts.republished.choices >= 1,
            "{counts:?}"
        );
        assert_eq!(counts.unreadable, None);
        drop(got);
        drop((agent, other, services, supervisor));
        owner.release().unwrap();
    }
}
