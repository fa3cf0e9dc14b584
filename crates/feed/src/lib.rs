//! The live feed of a run: what a view (a browser page, Foxglove, an MCAP
//! recording, PNP's monitor line) shows while a plan learns.
//!
//! Every record is plain data that serialises with serde, so one record type
//! serves every transport: in-process it goes straight to a [`FeedSink`], from
//! an agent process it crosses shared memory, and a view encodes it as JSON on
//! a Foxglove channel named by [`FeedEvent::channel`].
//!
//! Who publishes what:
//! - an agent: its plan's shape once ([`PlanShape`]), then markings (sampled,
//!   at most [`MARKINGS_PER_SECOND`] a second), every choice, rewards and
//!   episode ends;
//! - an experiment: the learning curve ([`CurvePoint`]);
//! - a supervisor: every process's health and latency percentiles.

#![deny(missing_docs)]

use serde::{Deserialize, Serialize};

/// The most markings a second an agent sends to a view; every choice is sent.
pub const MARKINGS_PER_SECOND: u32 = 30;

/// Beyond [`MARKINGS_PER_SECOND`], the most markings a second an agent
/// sends in which the running actions changed to others (an action
/// started): a robot's plan shows each action it runs.
pub const ACTION_MARKINGS_PER_SECOND: u32 = 200;

/// Where a record comes from: the run and the agent within it
/// (for example run 0, agent 2), or a process of the system.
#[derive(Clone, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Source {
    /// The run (0-based) of the experiment.
    pub run: u32,
    /// The agent (0-based) within the run.
    pub agent: u32,
}

/// A place of a plan, as a view draws it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PlaceShape {
    /// The place's index in the plan (the order of PNP's monitor line).
    pub id: u32,
    /// The place's label in the plan file.
    pub label: String,
    /// The place's id in the plan file (PNP's monitor line orders places by it).
    #[serde(default)]
    pub file_id: String,
}

/// A transition of a plan and the places it takes tokens from and gives them to.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct TransitionShape {
    /// The transition's index in the plan.
    pub id: u32,
    /// The transition's label in the plan file.
    pub label: String,
    /// The places it takes a token from.
    pub inputs: Vec<u32>,
    /// The places it puts a token in.
    pub outputs: Vec<u32>,
}

/// A plan's structure, sent once per agent before its first marking.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PlanShape {
    /// The agent running the plan.
    pub source: Source,
    /// The plan's name.
    pub plan: String,
    /// Its places.
    pub places: Vec<PlaceShape>,
    /// Its transitions.
    pub transitions: Vec<TransitionShape>,
}

/// The tokens in one place.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct PlaceTokens {
    /// The place's label.
    pub label: String,
    /// How many tokens it holds.
    pub tokens: u32,
}

/// A plan's marking at one moment (the root plan's or a sub-plan's): the
/// marked places and the actions running.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct MarkingSample {
    /// The agent.
    pub source: Source,
    /// The sub-plan the marking is of, by name; absent for the agent's root
    /// plan (the one its [`PlanShape`] draws). A sub-plan's marking carries
    /// the root plan's `episode` and `step` at the time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sub_plan: Option<String>,
    /// The episode (0-based) within the run.
    pub episode: u64,
    /// The executor's step within the episode.
    pub step: u64,
    /// Token counts in place-id order (PNP's monitor line: `plan[n1,n2,...]`).
    pub tokens: Vec<u32>,
    /// The marked places, by label.
    pub marked: Vec<PlaceTokens>,
    /// The actions running.
    pub running: Vec<String>,
}

/// One option at a choice: what the learner knows of it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct OptionValue {
    /// The option, by the label of the transition or marking it leads to.
    pub label: String,
    /// The learner's value for it; `None` while it has none.
    pub value: Option<f64>,
    /// How many times that value has been updated.
    pub updates: u64,
}

/// A choice the learner made at a choice point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct ChoiceMade {
    /// The agent.
    pub source: Source,
    /// The episode (0-based) within the run.
    pub episode: u64,
    /// The executor's step within the episode.
    pub step: u64,
    /// The choice point: the label of the marked place the options leave from.
    pub choice_point: String,
    /// The options, with their values and update counts.
    pub options: Vec<OptionValue>,
    /// The index in `options` of the one taken.
    pub taken: u32,
    /// The index in `options` of the greedy one (the highest value).
    pub greedy: u32,
    /// Whether the one taken was an exploratory choice (not the greedy one).
    pub explored: bool,
}

/// Rewards the agent received: sent with the marking samples (at most
/// [`MARKINGS_PER_SECOND`] a second) and at an episode's end, each the sum of
/// the rewards since the previous one, so their sum over an episode is its return.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct RewardSample {
    /// The agent.
    pub source: Source,
    /// The episode (0-based) within the run.
    pub episode: u64,
    /// The executor's step within the episode.
    pub step: u64,
    /// The rewards received since the agent's previous reward sample.
    pub reward: f64,
}

/// The end of an episode and what it returned.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct EpisodeEnd {
    /// The agent.
    pub source: Source,
    /// The episode (0-based) within the run.
    pub episode: u64,
    /// The episode's return (the sum of its rewards).
    pub episode_return: f64,
    /// Whether it was an evaluation (greedy, not learning) episode.
    pub evaluation: bool,
}

/// A point of the learning curve, as the experiment records it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct CurvePoint {
    /// The run (0-based).
    pub run: u32,
    /// Learning episodes done when the point was taken.
    pub episode: u64,
    /// The measured performance (the mean return of the evaluation, or of the window).
    pub value: f64,
}

/// One process's health, as its supervisor sees it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct ProcessHealth {
    /// The process's name (`simulator`, `agent-2`, `world`, `bridge`, ...).
    pub process: String,
    /// Its operating-system id, while it runs.
    pub pid: Option<u32>,
    /// Whether it is running.
    pub alive: bool,
    /// Milliseconds since its last heartbeat.
    pub heartbeat_age_ms: u64,
    /// How many times it has been restarted.
    pub restarts: u32,
    /// How many messages it rejected as malformed.
    pub rejections: u64,
}

/// A process's latency percentiles, in microseconds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct LatencySummary {
    /// The process's name.
    pub process: String,
    /// What is measured (for example `decision` or `round_trip`).
    pub measure: String,
    /// How many samples.
    pub count: u64,
    /// Median.
    pub p50_us: u64,
    /// 90th percentile.
    pub p90_us: u64,
    /// 99th percentile.
    pub p99_us: u64,
    /// Largest sample.
    pub max_us: u64,
}

/// One record of the feed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum FeedEvent {
    /// A plan's structure.
    Plan(PlanShape),
    /// A marking.
    Marking(MarkingSample),
    /// A choice.
    Choice(ChoiceMade),
    /// A reward.
    Reward(RewardSample),
    /// An episode's end.
    Episode(EpisodeEnd),
    /// A point of the learning curve.
    Curve(CurvePoint),
    /// A process's health.
    Health(ProcessHealth),
    /// A process's latency percentiles.
    Latency(LatencySummary),
}

/// Every topic of the feed, one per kind of [`FeedEvent`], in the order of its variants.
pub const CHANNELS: [&str; 8] = [
    "/learnpnp/plan",
    "/learnpnp/marking",
    "/learnpnp/choice",
    "/learnpnp/reward",
    "/learnpnp/episode",
    "/learnpnp/curve",
    "/learnpnp/health",
    "/learnpnp/latency",
];

/// The tag of each kind of [`FeedEvent`] in the record's JSON
/// (`{"Choice":{...}}`), in the order of [`CHANNELS`].
pub const KINDS: [&str; 8] = [
    "Plan", "Marking", "Choice", "Reward", "Episode", "Curve", "Health", "Latency",
];

impl FeedEvent {
    /// Splits a record's compact JSON (`{"Kind":payload}`, as serde_json
    /// writes a [`FeedEvent`]) into its kind's index in [`CHANNELS`] and its
    /// payload (what the kind's channel carries), without reading the
    /// payload; `None` for anything else.
    pub fn split_json(bytes: &[u8]) -> Option<(usize, &[u8])> {
        let rest = bytes.strip_prefix(b"{\"")?.strip_suffix(b"}")?;
        KINDS.iter().enumerate().find_map(|(kind, tag)| {
            let payload = rest.strip_prefix(tag.as_bytes())?.strip_prefix(b"\":")?;
            Some((kind, payload))
        })
    }

    /// The index of the record's kind in [`CHANNELS`].
    pub fn kind(&self) -> usize {
        match self {
            FeedEvent::Plan(_) => 0,
            FeedEvent::Marking(_) => 1,
            FeedEvent::Choice(_) => 2,
            FeedEvent::Reward(_) => 3,
            FeedEvent::Episode(_) => 4,
            FeedEvent::Curve(_) => 5,
            FeedEvent::Health(_) => 6,
            FeedEvent::Latency(_) => 7,
        }
    }

    /// The record itself (without the kind's tag) as JSON: what a channel carries.
    pub fn payload_json(&self) -> serde_json::Result<Vec<u8>> {
        match self {
            FeedEvent::Plan(r) => serde_json::to_vec(r),
            FeedEvent::Marking(r) => serde_json::to_vec(r),
            FeedEvent::Choice(r) => serde_json::to_vec(r),
            FeedEvent::Reward(r) => serde_json::to_vec(r),
            FeedEvent::Episode(r) => serde_json::to_vec(r),
            FeedEvent::Curve(r) => serde_json::to_vec(r),
            FeedEvent::Health(r) => serde_json::to_vec(r),
            FeedEvent::Latency(r) => serde_json::to_vec(r),
        }
    }

    /// Reads back a record from its channel's JSON payload; `None` for an
    /// unknown topic or a payload that is not that channel's record.
    pub fn from_payload(channel: &str, payload: &[u8]) -> Option<FeedEvent> {
        FeedEvent::from_kind_payload(CHANNELS.iter().position(|c| *c == channel)?, payload)
    }

    /// Reads back a record of kind `kind` (its index in [`CHANNELS`]) from
    /// its channel's JSON payload; `None` for an unknown kind or a payload
    /// that is not that kind's record.
    pub fn from_kind_payload(kind: usize, payload: &[u8]) -> Option<FeedEvent> {
        let event = match kind {
            0 => FeedEvent::Plan(serde_json::from_slice(payload).ok()?),
            1 => FeedEvent::Marking(serde_json::from_slice(payload).ok()?),
            2 => FeedEvent::Choice(serde_json::from_slice(payload).ok()?),
            3 => FeedEvent::Reward(serde_json::from_slice(payload).ok()?),
            4 => FeedEvent::Episode(serde_json::from_slice(payload).ok()?),
            5 => FeedEvent::Curve(serde_json::from_slice(payload).ok()?),
            6 => FeedEvent::Health(serde_json::from_slice(payload).ok()?),
            7 => FeedEvent::Latency(serde_json::from_slice(payload).ok()?),
            _ => return None,
        };
        Some(event)
    }

    /// The topic (Foxglove channel, MCAP channel) the record is published on.
    pub fn channel(&self) -> &'static str {
        CHANNELS[self.kind()]
    }
}

/// The JSON schema of each channel's record, in the order of [`CHANNELS`]:
/// (topic, schema name, schema as JSON text).
#[cfg(feature = "schema")]
pub fn channel_schemas() -> Vec<(&'static str, &'static str, String)> {
    fn of<T: schemars::JsonSchema>() -> String {
        serde_json::to_string(&schemars::schema_for!(T)).unwrap_or_else(|_| "{}".into())
    }
    let schemas = [
        ("learnpnp.PlanShape", of::<PlanShape>()),
        ("learnpnp.MarkingSample", of::<MarkingSample>()),
        ("learnpnp.ChoiceMade", of::<ChoiceMade>()),
        ("learnpnp.RewardSample", of::<RewardSample>()),
        ("learnpnp.EpisodeEnd", of::<EpisodeEnd>()),
        ("learnpnp.CurvePoint", of::<CurvePoint>()),
        ("learnpnp.ProcessHealth", of::<ProcessHealth>()),
        ("learnpnp.LatencySummary", of::<LatencySummary>()),
    ];
    CHANNELS
        .iter()
        .zip(schemas)
        .map(|(topic, (name, schema))| (*topic, name, schema))
        .collect()
}

/// Where feed records go: a view's server, a recording, a shared-memory
/// publisher. Publishing must not block the caller for long: a sink that
/// cannot keep up drops what it cannot send (and counts it).
pub trait FeedSink: Send + Sync {
    /// Publishes one record.
    fn publish(&self, event: &FeedEvent);

    /// Publishes one record already encoded: `payload` is what channel
    /// `CHANNELS[kind]` carries, checked by the caller to be such a record.
    /// By default it is decoded and [published](FeedSink::publish); a sink
    /// that sends JSON on passes it through as it is.
    fn publish_payload(&self, kind: usize, payload: &[u8]) {
        if let Some(event) = FeedEvent::from_kind_payload(kind, payload) {
            self.publish(&event);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_record_round_trips_through_json() {
        let event = FeedEvent::Choice(ChoiceMade {
            source: Source { run: 0, agent: 1 },
            episode: 3,
            step: 17,
            choice_point: "choose_pass".into(),
            options: vec![
                OptionValue {
                    label: "pass_1".into(),
                    value: Some(1.5),
                    updates: 4,
                },
                OptionValue {
                    label: "hold".into(),
                    value: None,
                    updates: 0,
                },
            ],
            taken: 1,
            greedy: 0,
            explored: true,
        });
        let text = serde_json::to_string(&event).unwrap();
        assert_eq!(serde_json::from_str::<FeedEvent>(&text).unwrap(), event);
        assert_eq!(event.channel(), "/learnpnp/choice");
        let payload = event.payload_json().unwrap();
        assert_eq!(FeedEvent::split_json(text.as_bytes()), Some((2, &payload[..])));
        assert_eq!(FeedEvent::from_payload(event.channel(), &payload), Some(event));
        for not_a_record in [
            &b""[..],
            b"{}",
            b"{\"Choice\"}",
            b"{\"Choose\":{}}",
            b" {\"Choice\":{}}",
        ] {
            assert_eq!(FeedEvent::split_json(not_a_record), None);
        }
    }
}
