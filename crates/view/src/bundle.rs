//! The page's channel, [`BUNDLE_CHANNEL`]: every [`crate::BUNDLE_EVERY`], for each agent, what
//! the page draws of the records that come at the run's pace (markings,
//! choices, episode ends) instead of every record. A page draws the latest
//! marking and each choice point's latest choice, counts the rest, and plots
//! every episode's return; so a bundle carries just that, and a page open on a
//! fast run is sent (and parses) a few kilobytes a bundle, not every record.
//!
//! A bundle is `{"agents":[AGENT,...]}`, an `AGENT` being
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
use learnpnp_feed::{EpisodeEnd, Source};
use serde::{Deserialize, Serialize};

/// The page's channel (see the module's documentation).
pub const BUNDLE_CHANNEL: &str = "/learnpnp/bundle";

/// The JSON schema of a [`BUNDLE_CHANNEL`] message.
pub(crate) const BUNDLE_SCHEMA: &str = r#"{"$schema":"https://json-schema.org/draft/2020-12/schema","title":"Bundle","type":"object","required":["agents"],"properties":{"agents":{"type":"array","items":{"type":"object","required":["source","markings","marking","sub_plan_markings","sub_plan_marking","choices","latest_choices","episodes","returns","last_episode"],"properties":{"source":{"type":"object"},"markings":{"type":"integer"},"marking":{"type":["object","null"]},"sub_plan_markings":{"type":"integer"},"sub_plan_marking":{"type":["object","null"]},"choices":{"type":"integer"},"latest_choices":{"type":"array","items":{"type":"object"}},"episodes":{"type":"integer"},"returns":{"type":"array","items":{"type":"array","prefixItems":[{"type":"integer"},{"type":["number","null"]}]}},"last_episode":{"type":["integer","null"]}}}}}}"#;

/// What a bundle files a marking by.
#[derive(Deserialize)]
struct MarkingKey {
    source: Source,
    #[serde(default)]
    sub_plan: Option<serde::de::IgnoredAny>,
}

/// What a bundle files a choice by.
#[derive(Deserialize)]
struct ChoiceKey<'a> {
    source: Source,
    #[serde(borrow)]
    choice_point: Cow<'a, str>,
}

/// One agent's part of the bundle being gathered.
#[derive(Default)]
struct AgentPart {
    markings: u64,
    marking: Option<Vec<u8>>,
    sub_plan_markings: u64,
    sub_plan_marking: Option<Vec<u8>>,
    choices: u64,
    /// Each choice point's latest choice, in the order the points were first met.
    latest_choices: Vec<(String, Vec<u8>)>,
    episodes: u64,
    returns: Vec<(u64, f64)>,
    last_episode: Option<u64>,
}

/// The [`BUNDLE_CHANNEL`] message being gathered.
pub(crate) struct Bundle {
    pub(crate) channel: Arc<RawChannel>,
    agents: Vec<(Source, AgentPart)>,
    json: Vec<u8>,
}

impl Bundle {
    pub(crate) fn new(channel: Arc<RawChannel>) -> Bundle {
        Bundle {
            channel,
            agents: Vec::new(),
            json: Vec::new(),
        }
    }

    fn agent(&mut self, source: Source) -> &mut AgentPart {
        let i = match self.agents.iter().position(|(s, _)| *s == source) {
            Some(i) => i,
            None => {
                self.agents.push((source, AgentPart::default()));
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
        let agent = self.agent(key.source);
        let (count, latest) = match key.sub_plan {
            None => (&mut agent.markings, &mut agent.marking),
            Some(_) => (&mut agent.sub_plan_markings, &mut agent.sub_plan_marking),
        };
        *count += 1;
        let latest = latest.get_or_insert_with(Vec::new);
        latest.clear();
        latest.extend_from_slice(json);
    }

    /// Files a choice (`json`, what `/learnpnp/choice` carries), while a client subscribes.
    pub(crate) fn add_choice(&mut self, json: &[u8]) {
        if !self.channel.has_sinks() {
            return;
        }
        let Ok(key) = serde_json::from_slice::<ChoiceKey>(json) else {
            return;
        };
        let agent = self.agent(key.source);
        agent.choices += 1;
        match agent
            .latest_choices
            .iter_mut()
            .find(|(point, _)| *point == key.choice_point)
        {
            Some((_, latest)) => {
                latest.clear();
                latest.extend_from_slice(json);
            }
            None => agent
                .latest_choices
                .push((key.choice_point.into_owned(), json.to_vec())),
        }
    }

    /// Files an episode's end (`json`, what `/learnpnp/episode` carries), while a client subscribes.
    pub(crate) fn add_episode(&mut self, json: &[u8]) {
        if !self.channel.has_sinks() {
            return;
        }
        let Ok(end) = serde_json::from_slice::<EpisodeEnd>(json) else {
            return;
        };
        let agent = self.agent(end.source);
        agent.episodes += 1;
        if !end.evaluation {
            agent.returns.push((end.episode, end.episode_return));
        }
        agent.last_episode = Some(end.episode);
    }

    /// Logs what was gathered, if anything, and starts the next message.
    pub(crate) fn send(&mut self) {
        if self.agents.is_empty() {
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
        self.json.extend_from_slice(b"]}");
        self.channel.log(&self.json);
        self.agents.clear();
    }
}

/// Writes `value` as JSON (a number that is not finite as `null`). Writing
/// into a `Vec` cannot fail, nor can serialising numbers and a [`Source`].
fn push_json<T: Serialize + ?Sized>(out: &mut Vec<u8>, value: &T) {
    let _ = serde_json::to_writer(&mut *out, value);
}

/// Writes one agent's part of a bundle (see the module's documentation).
fn write_agent(out: &mut Vec<u8>, source: &Source, part: &AgentPart) {
    let raw_or_null = |out: &mut Vec<u8>, json: &Option<Vec<u8>>| match json {
        Some(json) => out.extend_from_slice(json),
        None => out.extend_from_slice(b"null"),
    };
    out.extend_from_slice(br#"{"source":"#);
    push_json(out, source);
    out.extend_from_slice(br#","markings":"#);
    push_json(out, &part.markings);
    out.extend_from_slice(br#","marking":"#);
    raw_or_null(out, &part.marking);
    out.extend_from_slice(br#","sub_plan_markings":"#);
    push_json(out, &part.sub_plan_markings);
    out.extend_from_slice(br#","sub_plan_marking":"#);
    raw_or_null(out, &part.sub_plan_marking);
    out.extend_from_slice(br#","choices":"#);
    push_json(out, &part.choices);
    out.extend_from_slice(br#","latest_choices":["#);
    for (i, (_, choice)) in part.latest_choices.iter().enumerate() {
        if i > 0 {
            out.push(b',');
        }
        out.extend_from_slice(choice);
    }
    out.extend_from_slice(br#"],"episodes":"#);
    push_json(out, &part.episodes);
    out.extend_from_slice(br#","returns":"#);
    push_json(out, &part.returns);
    out.extend_from_slice(br#","last_episode":"#);
    push_json(out, &part.last_episode);
    out.push(b'}');
}
