//! The page's channel, [`BUNDLE_CHANNEL`]: every [`crate::BUNDLE_EVERY`], for each agent, what
//! the page draws of the records that come at the run's pace (markings,
//! choices, episode ends) instead of every record, and the processes' latest
//! health and latency. A page draws the latest marking and each choice
//! point's latest choice, counts the rest, and plots every episode's return;
//! so a bundle carries just that, and a page open on a fast run is sent (and
//! parses) one message a second, not every record nor a message per process.
//!
//! A bundle is `{"agents":[AGENT,...],"processes":[HEALTH,...],"latency":[LATENCY,...]}`:
//! `HEALTH` and `LATENCY` are what `/learnpnp/health` and `/learnpnp/latency`
//! carry, the latest of each process (and each measure of its latency) that
//! came since the last bundle. An `AGENT` is
//! `{"source":SOURCE,"markings":N,"marking":MARKING|null,"sub_plan_markings":N,
//! "sub_plan_marking":MARKING|null,"choices":N,"latest_choices":[CHOICE,...],
//! "episodes":N,"returns":[[EPISODE,RETURN],...],"last_episode":EPISODE|null}`:
//! since the last bundle, the agent's root-plan markings (and the last), its
//! sub-plans' markings (and the last), its choices (and the last at each
//! choice point, in the order the points were first met), its episode ends
//! (the returns of those that were not evaluations, in order, and the last
//! episode's number). `MARKING` and `CHOICE` are what `/learnpnp/marking` and
//! `/learnpnp/choice` carry, passed on as the agent wrote them.

use std::borrow::Cow;
use std::sync::Arc;

use foxglove::RawChannel;
use learnpnp_feed::{ChoiceMade, EpisodeEnd, FeedEvent, MarkingSample, Source};
use serde::{Deserialize, Serialize};

/// The page's channel (see the module's documentation).
pub const BUNDLE_CHANNEL: &str = "/learnpnp/bundle";

/// The JSON schema of a [`BUNDLE_CHANNEL`] message.
pub(crate) const BUNDLE_SCHEMA: &str = r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"Bundle","type":"object","required":["agents","processes","latency"],"properties":{"processes":{"type":"array","items":{"type":"object"}},"latency":{"type":"array","items":{"type":"object"}},"agents":{"type":"array","items":{"type":"object","required":["source","markings","marking","sub_plan_markings","sub_plan_marking","choices","latest_choices","episodes","returns","last_episode"],"properties":{"source":{"type":"object"},"markings":{"type":"integer"},"marking":{"type":["object","null"]},"sub_plan_markings":{"type":"integer"},"sub_plan_marking":{"type":["object","null"]},"choices":{"type":"integer"},"latest_choices":{"type":"array","items":{"type":"object"}},"episodes":{"type":"integer"},"returns":{"type":"array","items":{"type":"array","prefixItems":[{"type":"integer"},{"type":["number","null"]}]}},"last_episode":{"type":["integer","null"]}}}}}}"#;

/// What a bundle files a marking by.
#[derive(Deserialize)]
struct MarkingKey {
    source: Source,
    #[serde(default)]
    sub_plan: Option<serde::de::IgnoredAny>,
}

/// What a bundle files a process's health by.
#[derive(Deserialize)]
struct HealthKey<'a> {
    #[serde(borrow)]
    process: Cow<'a, str>,
}

/// What a bundle files a latency summary by.
#[derive(Deserialize)]
struct LatencyKey<'a> {
    #[serde(borrow)]
    process: Cow<'a, str>,
    #[serde(borrow)]
    measure: Cow<'a, str>,
}

/// What a bundle files a choice by.
#[derive(Deserialize)]
struct ChoiceKey<'a> {
    source: Source,
    #[serde(borrow)]
    choice_point: Cow<'a, str>,
}

/// A latest marking or choice: as an agent process encoded it, or as a
/// learner in the view's process published it (encoded only if it is still
/// the latest when the bundle is sent).
enum Kept {
    Json(Vec<u8>),
    Marking(MarkingSample),
    Choice(ChoiceMade),
}

impl Kept {
    /// Makes `slot` hold `json`, reusing its buffer.
    fn keep_json(slot: &mut Option<Kept>, json: &[u8]) {
        match slot {
            Some(Kept::Json(kept)) => {
                kept.clear();
                kept.extend_from_slice(json);
            }
            _ => *slot = Some(Kept::Json(json.to_vec())),
        }
    }

    /// Writes it as JSON.
    fn write(&self, out: &mut Vec<u8>) {
        match self {
            Kept::Json(json) => out.extend_from_slice(json),
            Kept::Marking(marking) => push_json(out, marking),
            Kept::Choice(choice) => push_json(out, choice),
        }
    }
}

/// One agent's part of the bundle being gathered.
#[derive(Default)]
struct AgentPart {
    markings: u64,
    marking: Option<Kept>,
    sub_plan_markings: u64,
    sub_plan_marking: Option<Kept>,
    choices: u64,
    /// Each choice point's latest choice, in the order the points were first met.
    latest_choices: Vec<(String, Option<Kept>)>,
    episodes: u64,
    returns: Vec<(u64, f64)>,
    last_episode: Option<u64>,
}

impl AgentPart {
    /// The slot (and the count) of a root-plan marking, or of a sub-plan's.
    fn marking_slot(&mut self, sub_plan: bool) -> (&mut u64, &mut Option<Kept>) {
        if sub_plan {
            (&mut self.sub_plan_markings, &mut self.sub_plan_marking)
        } else {
            (&mut self.markings, &mut self.marking)
        }
    }

    /// The slot of `point`'s latest choice (counting the choice).
    fn choice_slot(&mut self, point: &str) -> &mut Option<Kept> {
        self.choices += 1;
        let i = match self.latest_choices.iter().position(|(p, _)| p == point) {
            Some(i) => i,
            None => {
                self.latest_choices.push((point.to_owned(), None));
                self.latest_choices.len() - 1
            }
        };
        &mut self.latest_choices[i].1
    }

    fn end_episode(&mut self, end: &EpisodeEnd) {
        self.episodes += 1;
        if !end.evaluation {
            self.returns.push((end.episode, end.episode_return));
        }
        self.last_episode = Some(end.episode);
    }
}

/// The latest record of each key (a process, or a process's measure), in
/// the order the keys were first met, as JSON.
struct Latest<K> {
    records: Vec<(K, Vec<u8>)>,
}

impl<K: PartialEq> Latest<K> {
    fn new() -> Self {
        Latest { records: Vec::new() }
    }

    /// Makes `json` the latest record of `key`.
    fn keep(&mut self, key: K, json: &[u8]) {
        match self.records.iter_mut().find(|(k, _)| *k == key) {
            Some((_, kept)) => {
                kept.clear();
                kept.extend_from_slice(json);
            }
            None => self.records.push((key, json.to_vec())),
        }
    }

    fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    fn clear(&mut self) {
        self.records.clear();
    }

    /// Writes the records as a JSON array.
    fn write(&self, out: &mut Vec<u8>) {
        out.push(b'[');
        for (i, (_, json)) in self.records.iter().enumerate() {
            if i > 0 {
                out.push(b',');
            }
            out.extend_from_slice(json);
        }
        out.push(b']');
    }
}

/// The [`BUNDLE_CHANNEL`] message being gathered.
pub(crate) struct Bundle {
    pub(crate) channel: Arc<RawChannel>,
    agents: Vec<(Source, AgentPart)>,
    processes: Latest<String>,
    latency: Latest<(String, String)>,
    json: Vec<u8>,
}

impl Bundle {
    pub(crate) fn new(channel: Arc<RawChannel>) -> Bundle {
        Bundle {
            channel,
            agents: Vec::new(),
            processes: Latest::new(),
            latency: Latest::new(),
            json: Vec::new(),
        }
    }

    fn agent(&mut self, source: &Source) -> &mut AgentPart {
        let i = match self.agents.iter().position(|(s, _)| s == source) {
            Some(i) => i,
            None => {
                self.agents.push((source.clone(), AgentPart::default()));
                self.agents.len() - 1
            }
        };
        &mut self.agents[i].1
    }

    /// Files a marking (`json`, what `/learnpnp/marking` carries), while a client subscribes.
    pub(crate) fn add_marking(&mut self, json: &[u8]) {
        if !self.channel.has_sinks() {
            return;
        }
        let Ok(key) = serde_json::from_slice::<MarkingKey>(json) else {
            return;
        };
        let (count, slot) = self.agent(&key.source).marking_slot(key.sub_plan.is_some());
        *count += 1;
        Kept::keep_json(slot, json);
    }

    /// Files a choice (`json`, what `/learnpnp/choice` carries), while a client subscribes.
    pub(crate) fn add_choice(&mut self, json: &[u8]) {
        if !self.channel.has_sinks() {
            return;
        }
        let Ok(key) = serde_json::from_slice::<ChoiceKey>(json) else {
            return;
        };
        Kept::keep_json(self.agent(&key.source).choice_slot(&key.choice_point), json);
    }

    /// Files an episode's end (`json`, what `/learnpnp/episode` carries), while a client subscribes.
    pub(crate) fn add_episode(&mut self, json: &[u8]) {
        if !self.channel.has_sinks() {
            return;
        }
        if let Ok(end) = serde_json::from_slice::<EpisodeEnd>(json) {
            self.agent(&end.source).end_episode(&end);
        }
    }

    /// Files a process's health (`json`, what `/learnpnp/health` carries), while a client subscribes.
    pub(crate) fn add_health(&mut self, json: &[u8]) {
        if !self.channel.has_sinks() {
            return;
        }
        if let Ok(key) = serde_json::from_slice::<HealthKey>(json) {
            self.processes.keep(key.process.into_owned(), json);
        }
    }

    /// Files a process's latency summary (`json`, what `/learnpnp/latency` carries), while a client subscribes.
    pub(crate) fn add_latency(&mut self, json: &[u8]) {
        if !self.channel.has_sinks() {
            return;
        }
        if let Ok(key) = serde_json::from_slice::<LatencyKey>(json) {
            self.latency
                .keep((key.process.into_owned(), key.measure.into_owned()), json);
        }
    }

    /// Files a record published in the view's process, while a client
    /// subscribes: a marking or choice is encoded only if it is still the
    /// latest of its kind when the bundle is sent; a process's health or
    /// latency (once a second each) at once.
    pub(crate) fn add_event(&mut self, event: &FeedEvent) {
        if !self.channel.has_sinks() {
            return;
        }
        match event {
            FeedEvent::Marking(marking) => {
                let (count, slot) = self.agent(&marking.source).marking_slot(marking.sub_plan.is_some());
                *count += 1;
                match slot {
                    Some(Kept::Marking(kept)) => kept.clone_from(marking),
                    _ => *slot = Some(Kept::Marking(marking.clone())),
                }
            }
            FeedEvent::Choice(choice) => {
                let slot = self.agent(&choice.source).choice_slot(&choice.choice_point);
                match slot {
                    Some(Kept::Choice(kept)) => kept.clone_from(choice),
                    _ => *slot = Some(Kept::Choice(choice.clone())),
                }
            }
            FeedEvent::Episode(end) => self.agent(&end.source).end_episode(end),
            FeedEvent::Health(health) => self.processes.keep(health.process.clone(), &json_of(health)),
            FeedEvent::Latency(summary) => self
                .latency
                .keep((summary.process.clone(), summary.measure.clone()), &json_of(summary)),
            _ => {}
        }
    }

    /// Logs what was gathered, if anything, and starts the next message.
    pub(crate) fn send(&mut self) {
        if self.agents.is_empty() && self.processes.is_empty() && self.latency.is_empty() {
            return;
        }
        self.json.clear();
        self.json.extend_from_slice(br#"{"agents":["#);
        for (i, (source, part)) in self.agents.iter().enumerate() {
            if i > 0 {
                self.json.push(b',');
            }
            write_agent(&mut self.json, source, part);
        }
        self.json.extend_from_slice(br#"],"processes":"#);
        self.processes.write(&mut self.json);
        self.json.extend_from_slice(br#","latency":"#);
        self.latency.write(&mut self.json);
        self.json.push(b'}');
        self.channel.log(&self.json);
        self.agents.clear();
        self.processes.clear();
        self.latency.clear();
    }
}

/// A record as JSON.
fn json_of<T: Serialize>(record: &T) -> Vec<u8> {
    let mut json = Vec::new();
    push_json(&mut json, record);
    json
}

/// Writes `value` as JSON (a number that is not finite as `null`). Writing
/// into a `Vec` cannot fail, nor can serialising numbers and a [`Source`].
fn push_json<T: Serialize + ?Sized>(out: &mut Vec<u8>, value: &T) {
    let _ = serde_json::to_writer(&mut *out, value);
}

/// Writes a JSON value into a buffer.
type WriteJson<'a> = dyn Fn(&mut Vec<u8>) + 'a;

/// Writes one agent's part of a bundle (see the module's documentation).
fn write_agent(out: &mut Vec<u8>, source: &Source, part: &AgentPart) {
    let kept_or_null = |out: &mut Vec<u8>, kept: &Option<Kept>| match kept {
        Some(kept) => kept.write(out),
        None => out.extend_from_slice(b"null"),
    };
    let latest_choices = |out: &mut Vec<u8>| {
        out.push(b'[');
        let kept = part.latest_choices.iter().filter_map(|(_, kept)| kept.as_ref());
        for (i, choice) in kept.enumerate() {
            if i > 0 {
                out.push(b',');
            }
            choice.write(out);
        }
        out.push(b']');
    };
    let fields: [(&str, &WriteJson); 10] = [
        ("source", &|out| push_json(out, source)),
        ("markings", &|out| push_json(out, &part.markings)),
        ("marking", &|out| kept_or_null(out, &part.marking)),
        ("sub_plan_markings", &|out| push_json(out, &part.sub_plan_markings)),
        ("sub_plan_marking", &|out| kept_or_null(out, &part.sub_plan_marking)),
        ("choices", &|out| push_json(out, &part.choices)),
        ("latest_choices", &latest_choices),
        ("episodes", &|out| push_json(out, &part.episodes)),
        ("returns", &|out| push_json(out, &part.returns)),
        ("last_episode", &|out| push_json(out, &part.last_episode)),
    ];
    out.push(b'{');
    for (i, (name, write)) in fields.iter().enumerate() {
        if i > 0 {
            out.push(b',');
        }
        out.push(b'"');
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(b"\":");
        write(out);
    }
    out.push(b'}');
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_latest_record_of_each_key_is_kept_in_the_order_keys_came() {
        let mut latest = Latest::new();
        latest.keep("keeper 2", br#"{"n":1}"#);
        latest.keep("keeper 1", br#"{"n":2}"#);
        latest.keep("keeper 2", br#"{"n":3}"#);
        let mut out = Vec::new();
        latest.write(&mut out);
        assert_eq!(out, br#"[{"n":3},{"n":2}]"#);
    }
}
