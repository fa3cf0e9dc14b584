//! The plan's state as ROS 2 topics, as PNPros published it (its
//! `pnp/currentActivePlaces`): the marked places, the running actions, and
//! each choice with its values, as `std_msgs/msg/String` so that `ros2 topic
//! echo` and Foxglove show them with nothing to install. The ROS 2 world
//! process republishes the agents' live feed through a
//! [`PlanStatePublisher`](crate::plan_state::PlanStatePublisher) per agent ([`Republisher`](crate::plan_state::Republisher)).

use learnpnp_feed::{ChoiceMade, FeedEvent, MarkingSample};
use serde::Serialize;

use crate::node::{Node, Publisher, Ros2Error};
use crate::types::Value;

/// The marked places' names, comma-separated (PNPros's topic name).
pub(crate) const ACTIVE_PLACES: &str = "pnp/currentActivePlaces";
/// The running actions' names, comma-separated.
pub(crate) const RUNNING_ACTIONS: &str = "pnp/runningActions";
/// Each choice as it is made: JSON (`{"choice", "options": [{"name", "value"}], "chosen"}`).
pub(crate) const CHOICES: &str = "pnp/choices";
/// The type of every plan-state topic.
pub(crate) const STRING: &str = "std_msgs/msg/String";

/// A choice as the agent made it.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Choice {
    /// The choice point (its place's name).
    pub choice: String,
    /// Each option and its value.
    pub options: Vec<OptionValue>,
    /// The option taken.
    pub chosen: String,
}

/// An option of a choice and its value.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct OptionValue {
    /// The option (its transition's name).
    pub name: String,
    /// Its value (`null` while the learner has none for it).
    pub value: Option<f64>,
}

/// Publishes the plan's state on a node (one `MP` token per topic).
pub struct PlanStatePublisher {
    places: Publisher,
    actions: Publisher,
    choices: Publisher,
}

fn text(s: String) -> Value {
    Value::fields([("data", Value::Str(s))])
}

impl PlanStatePublisher {
    /// Declares the three publishers on `node` (names relative to its namespace).
    pub fn new(node: &Node) -> Result<Self, Ros2Error> {
        Ok(PlanStatePublisher {
            places: node.publisher(ACTIVE_PLACES, STRING)?,
            actions: node.publisher(RUNNING_ACTIONS, STRING)?,
            choices: node.publisher(CHOICES, STRING)?,
        })
    }

    /// Declares the three publishers on `node` under `namespace` (absolute,
    /// e.g. `/learnpnp/agent1`: its `pnp/currentActivePlaces` and the others).
    pub(crate) fn in_namespace(node: &Node, namespace: &str) -> Result<Self, Ros2Error> {
        let namespace = namespace.trim_end_matches('/');
        let topic = |name: &str| format!("{namespace}/{name}");
        Ok(PlanStatePublisher {
            places: node.publisher(&topic(ACTIVE_PLACES), STRING)?,
            actions: node.publisher(&topic(RUNNING_ACTIONS), STRING)?,
            choices: node.publisher(&topic(CHOICES), STRING)?,
        })
    }

    /// The marked places' names.
    pub fn marking(&self, places: &[&str]) -> Result<(), Ros2Error> {
        self.places.publish(&text(places.join(",")))
    }

    /// The running actions' names.
    pub fn running(&self, actions: &[&str]) -> Result<(), Ros2Error> {
        self.actions.publish(&text(actions.join(",")))
    }

    /// A choice made.
    pub fn choice(&self, choice: &Choice) -> Result<(), Ros2Error> {
        let json = serde_json::to_string(choice).map_err(|e| Ros2Error::Zenoh(e.to_string()))?;
        self.choices.publish(&text(json))
    }
}

/// What the republishing of the agents' feed did.
#[derive(Debug, Default, Clone, Serialize, PartialEq, Eq)]
pub struct Republished {
    /// Markings published (each on the places' and the actions' topics).
    pub markings: u64,
    /// Choices published.
    pub choices: u64,
    /// Records refused here: from an agent the run does not have, or a
    /// choice whose option taken is not among its options.
    pub refused: u64,
    /// Publications that failed (the session's error, said on stderr).
    pub failed: u64,
}

/// The agents' plan state republished as PNPros did: one
/// [`PlanStatePublisher`] per agent, each in its own namespace.
pub struct Republisher {
    agents: Vec<PlanStatePublisher>,
    counts: Republished,
}

impl Republisher {
    /// Agent `a`'s publishers on `node` under `{namespace}/agent{a + 1}`, for `agents` agents.
    pub fn new(node: &Node, namespace: &str, agents: usize) -> Result<Self, Ros2Error> {
        let namespace = namespace.trim_end_matches('/');
        Ok(Republisher {
            agents: (0..agents)
                .map(|a| PlanStatePublisher::in_namespace(node, &format!("{namespace}/agent{}", a + 1)))
                .collect::<Result<_, _>>()?,
            counts: Republished::default(),
        })
    }

    /// What was republished so far.
    pub fn counts(&self) -> &Republished {
        &self.counts
    }

    /// Republishes one record of the feed (markings and choices; the rest is not plan state).
    pub(crate) fn event(&mut self, event: &FeedEvent) {
        let done = match event {
            // The plan's state is the root plan's (a sub-plan's marking is not it).
            FeedEvent::Marking(m) if m.sub_plan.is_none() => self.marking(m),
            FeedEvent::Choice(c) => self.choice(c),
            _ => return,
        };
        if let Err(e) = done {
            self.counts.failed += 1;
            eprintln!("learnpnp-ros2-world: the plan's state: {e}");
        }
    }

    fn publisher(&mut self, agent: u32) -> Option<&PlanStatePublisher> {
        let publisher = self.agents.get(agent as usize);
        if publisher.is_none() {
            self.counts.refused += 1;
        }
        publisher
    }

    fn marking(&mut self, m: &MarkingSample) -> Result<(), Ros2Error> {
        let Some(publisher) = self.publisher(m.source.agent) else {
            return Ok(());
        };
        let places: Vec<&str> = m.marked.iter().map(|p| p.label.as_str()).collect();
        let running: Vec<&str> = m.running.iter().map(String::as_str).collect();
        publisher.marking(&places)?;
        publisher.running(&running)?;
        self.counts.markings += 1;
        Ok(())
    }

    fn choice(&mut self, c: &ChoiceMade) -> Result<(), Ros2Error> {
        let Some(taken) = c.options.get(c.taken as usize) else {
            self.counts.refused += 1;
            return Ok(());
        };
        let choice = Choice {
            choice: c.choice_point.clone(),
            options: c
                .options
                .iter()
                .map(|o| OptionValue {
                    name: o.label.clone(),
                    value: o.value,
                })
                .collect(),
            chosen: taken.label.clone(),
        };
        let Some(publisher) = self.publisher(c.source.agent) else {
            return Ok(());
        };
        publisher.choice(&choice)?;
        self.counts.choices += 1;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use std::sync::{Arc, Mutex};
    use std::time::{Duration, Instant};

    use zenoh::Wait;

    use super::*;
    use crate::keys::{Attachment, topic_key};
    use crate::node::tests::loopback_pair;
    use crate::types::{Registry, dds_name};

    #[test]
    fn the_plan_state_reaches_a_subscriber_as_ros_2_strings() {
        let (a, b) = loopback_pair();
        let registry = Arc::new(Registry::new());
        let node = Node::new(a, Arc::clone(&registry), 0, "/robot1", "learnpnp_agent").unwrap();
        let hash = registry.type_hash(STRING).unwrap();
        let key = topic_key(0, "/robot1/pnp/currentActivePlaces", &dds_name(STRING).unwrap(), &hash);
        assert_eq!(
            key,
            "0/robot1/pnp/currentActivePlaces/std_msgs::msg::dds_::String_/RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
        );
        let got = Arc::new(Mutex::new(Vec::new()));
        let g = Arc::clone(&got);
        let _sub = b
            .declare_subscriber("0/robot1/pnp/**")
            .callback(move |s| {
                let att = Attachment::from_bytes(&s.attachment().map(|a| a.to_bytes().to_vec()).unwrap_or_default());
                g.lock()
                    .unwrap()
                    .push((s.key_expr().to_string(), s.payload().to_bytes().to_vec(), att.is_ok()));
            })
            .wait()
            .unwrap();
        let plan = PlanStatePublisher::new(&node).unwrap();
        let start = Instant::now();
        while got.lock().unwrap().len() < 3 && start.elapsed() < Duration::from_secs(10) {
            plan.marking(&["walk", "choose"]).unwrap();
            plan.running(&["forward"]).unwrap();
            plan.choice(&Choice {
                choice: "choose".into(),
                options: vec![OptionValue {
                    name: "forward".into(),
                    value: Some(-4.0),
                }],
                chosen: "forward".into(),
            })
            .unwrap();
            std::thread::sleep(Duration::from_millis(100));
        }
        let got = got.lock().unwrap();
        let places = got.iter().find(|(k, _, _)| *k == key).expect("marked places published");
        assert!(places.2, "with rmw_zenoh's attachment");
        assert_eq!(
            registry.decode(STRING, &places.1).unwrap().get("data"),
            Some(&Value::Str("walk,choose".into()))
        );
        let choice = got.iter().find(|(k, _, _)| k.contains("/pnp/choices/")).unwrap();
        let json = registry.decode(STRING, &choice.1).unwrap();
        assert!(matches!(json.get("data"), Some(Value::Str(s)) if s.contains("\"chosen\":\"forward\"")));
        drop(got);
        // The node's token, as a graph query sees it (asked until the link has it).
        let mut names = Vec::new();
        let start = Instant::now();
        while !names
            .iter()
            .any(|n: &String| n.ends_with("/NN/%/%robot1/learnpnp_agent"))
            && start.elapsed() < Duration::from_secs(10)
        {
            let replies = b
                .liveliness()
                .get("@ros2_lv/0/**")
                .timeout(Duration::from_millis(500))
                .wait()
                .unwrap();
            while let Ok(r) = replies.recv() {
                names.extend(r.result().ok().map(|s| s.key_expr().to_string()));
            }
        }
        assert!(
            names.iter().any(|n| n.ends_with("/NN/%/%robot1/learnpnp_agent")),
            "{names:?}"
        );
    }
}
