//! A learner watched by a view: it forwards everything to the learner it
//! wraps and publishes what happens to a [`FeedSink`] (the live feed of
//! [`learnpnp_feed`]). A run with no view wraps nothing and pays nothing.

use std::sync::Arc;
use std::time::{Duration, Instant};

use learnpnp_feed::{
    ChoiceMade, EpisodeEnd, FeedEvent, FeedSink, MARKINGS_PER_SECOND, MarkingSample, OptionValue, PlaceShape,
    PlaceTokens, PlanShape, RewardSample, Source, TransitionShape,
};

use super::{EpisodeMode, EpisodeStart, Learner, ValueTable};
use crate::executor::{Chooser, PendingReward, PlanKey};
use crate::net::{Marking, NodeRef, PlaceId};
use crate::plan::Plan;

/// The labels a view reads of one plan (the root plan or a sub-plan).
#[derive(Debug, Clone)]
struct PlanLabels {
    /// Each place's name (its label, or its id when the label is blank).
    places: Vec<String>,
    /// Each action's name and its execution places.
    actions: Vec<(String, Vec<PlaceId>)>,
}

impl PlanLabels {
    fn new(plan: &Plan) -> Self {
        PlanLabels {
            places: (0..plan.net().places().len())
                .map(|i| plan.place_name(PlaceId::new(i)).to_owned())
                .collect(),
            actions: plan
                .actions()
                .iter()
                .map(|a| (a.name.clone(), a.exec_places.clone()))
                .collect(),
        }
    }

    fn place(&self, index: usize) -> String {
        self.places.get(index).cloned().unwrap_or_else(|| format!("p{index}"))
    }

    /// The first place `to` holds more tokens in than `from`: what tells an
    /// option's successor marking apart, named for a designer (an action's
    /// execution place by the action's name).
    fn gained(&self, from: &Marking, to: &Marking) -> Option<String> {
        let i = from.tokens().iter().zip(to.tokens()).position(|(a, b)| b > a)?;
        let name = self.place(i);
        Some(name.strip_suffix(".exec").map(str::to_owned).unwrap_or(name))
    }

    /// The first place `to` holds fewer tokens in than `from`: where a choice leaves from.
    fn lost(&self, from: &Marking, to: &Marking) -> Option<String> {
        let i = from.tokens().iter().zip(to.tokens()).position(|(a, b)| b < a)?;
        Some(self.place(i))
    }
}

/// A [`Learner`] that publishes to a feed: its plan's shape once, the root
/// plan's markings (at most [`MARKINGS_PER_SECOND`] a second, with the rewards
/// received since the previous one), every choice with the options' values
/// and update counts, and every episode's end and return.
pub struct WatchedLearner {
    inner: Box<dyn Learner>,
    sink: Arc<dyn FeedSink>,
    source: Source,
    /// Labels of the plan (index 0) and its sub-plans, in [`PlanKey`] order.
    plans: Vec<PlanLabels>,
    episode: u64,
    episodes_begun: u64,
    evaluation: bool,
    step: u64,
    episode_return: f64,
    /// Rewards received since the last reward sample.
    unsent_reward: f64,
    next_sample: Instant,
}

impl std::fmt::Debug for WatchedLearner {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WatchedLearner")
            .field("source", &self.source)
            .field("episode", &self.episode)
            .finish_non_exhaustive()
    }
}

/// The labels of a plan the learner was not told of (places named by index).
static UNKNOWN_PLAN: PlanLabels = PlanLabels {
    places: Vec::new(),
    actions: Vec::new(),
};

/// The interval between two marking samples.
const SAMPLE_PERIOD: Duration = Duration::from_nanos(1_000_000_000 / MARKINGS_PER_SECOND as u64);

impl WatchedLearner {
    /// Wraps `inner`, the learner of `source` running `plan`, and publishes
    /// the plan's shape to `sink` at once.
    pub fn new(inner: Box<dyn Learner>, plan: &Plan, source: Source, sink: Arc<dyn FeedSink>) -> Self {
        sink.publish(&FeedEvent::Plan(plan_shape(plan, &source)));
        WatchedLearner {
            inner,
            sink,
            source,
            plans: plan.activation_plans().into_iter().map(PlanLabels::new).collect(),
            episode: 0,
            episodes_begun: 0,
            evaluation: false,
            step: 0,
            episode_return: 0.0,
            unsent_reward: 0.0,
            next_sample: Instant::now(),
        }
    }

    fn sample(&mut self, marking: &Marking) {
        let now = Instant::now();
        if now < self.next_sample {
            return;
        }
        self.next_sample = now + SAMPLE_PERIOD;
        let labels = &self.plans[0];
        let tokens = marking.tokens();
        let running = labels
            .actions
            .iter()
            .filter(|(_, places)| places.iter().any(|&p| marking.get(p) > 0))
            .map(|(name, _)| name.clone())
            .collect();
        self.sink.publish(&FeedEvent::Marking(MarkingSample {
            source: self.source.clone(),
            episode: self.episode,
            step: self.step,
            tokens: tokens.iter().map(|&n| u32::from(n)).collect(),
            marked: marking
                .marked()
                .map(|(p, n)| PlaceTokens {
                    label: labels.place(p.index()),
                    tokens: u32::from(n),
                })
                .collect(),
            running,
        }));
        self.send_reward();
    }

    fn send_reward(&mut self) {
        if self.unsent_reward != 0.0 {
            self.sink.publish(&FeedEvent::Reward(RewardSample {
                source: self.source.clone(),
                episode: self.episode,
                step: self.step,
                reward: self.unsent_reward,
            }));
            self.unsent_reward = 0.0;
        }
    }

    fn publish_choice(&self, plan: PlanKey, state: &Marking, options: &[Marking], taken: usize) {
        let labels = self.plans.get(usize::from(plan.0)).unwrap_or(&UNKNOWN_PLAN);
        let table: &ValueTable = self.inner.values();
        let values: Vec<OptionValue> = options
            .iter()
            .enumerate()
            .map(|(i, option)| {
                let id = table.find(plan, option);
                OptionValue {
                    label: labels.gained(state, option).unwrap_or_else(|| format!("option {i}")),
                    value: id.map(|id| table.value(id)),
                    updates: id.map_or(0, |id| table.visits(id)),
                }
            })
            .collect();
        let score = |o: &OptionValue| o.value.unwrap_or(table.initial_value());
        let best = values.iter().map(score).fold(f64::NEG_INFINITY, f64::max);
        // Among equally valued options the one taken is greedy.
        let greedy = if values.get(taken).is_some_and(|o| score(o) >= best) {
            taken
        } else {
            values.iter().position(|o| score(o) >= best).unwrap_or(taken)
        };
        let choice_point = options
            .first()
            .and_then(|o| labels.lost(state, o))
            .unwrap_or_else(|| "choice".into());
        self.sink.publish(&FeedEvent::Choice(ChoiceMade {
            source: self.source.clone(),
            episode: self.episode,
            step: self.step,
            choice_point,
            options: values,
            taken: taken as u32,
            greedy: greedy as u32,
            explored: taken != greedy,
        }));
    }
}

/// The shape of `plan` as the feed sends it.
pub fn plan_shape(plan: &Plan, source: &Source) -> PlanShape {
    let net = plan.net();
    let mut transitions: Vec<TransitionShape> = net
        .transitions()
        .iter()
        .enumerate()
        .map(|(i, t)| TransitionShape {
            id: i as u32,
            label: if t.label.trim().is_empty() {
                t.id.clone()
            } else {
                t.label.clone()
            },
            inputs: Vec::new(),
            outputs: Vec::new(),
        })
        .collect();
    for arc in net.arcs() {
        match (arc.source, arc.target) {
            (NodeRef::Place(p), NodeRef::Transition(t)) => transitions[t.index()].inputs.push(p.index() as u32),
            (NodeRef::Transition(t), NodeRef::Place(p)) => transitions[t.index()].outputs.push(p.index() as u32),
            _ => {}
        }
    }
    PlanShape {
        source: source.clone(),
        plan: plan.name().to_owned(),
        places: net
            .places()
            .iter()
            .enumerate()
            .map(|(i, p)| PlaceShape {
                id: i as u32,
                label: plan.place_name(PlaceId::new(i)).to_owned(),
                file_id: p.id.clone(),
            })
            .collect(),
        transitions,
    }
}

impl Chooser for WatchedLearner {
    fn choose(&mut self, plan: PlanKey, state: &Marking, options: &[Marking]) -> usize {
        let taken = self.inner.choose(plan, state, options);
        self.publish_choice(plan, state, options, taken);
        taken
    }

    fn transition(&mut self, plan: PlanKey, marking: &Marking, reward: f64, elapsed: u32) {
        self.inner.transition(plan, marking, reward, elapsed);
        if plan == PlanKey::ROOT {
            self.step += u64::from(elapsed);
            self.episode_return += reward;
            self.unsent_reward += reward;
            self.sample(marking);
        }
    }

    fn plan_started(&mut self, plan: PlanKey, marking: &Marking) {
        self.inner.plan_started(plan, marking);
        if plan == PlanKey::ROOT {
            self.sample(marking);
        }
    }
}

impl Learner for WatchedLearner {
    fn begin_episode(&mut self, start: EpisodeStart) {
        self.inner.begin_episode(start);
        self.episode = self.episodes_begun;
        self.episodes_begun += 1;
        self.evaluation = start.mode != EpisodeMode::Learn;
        self.step = 0;
        self.episode_return = 0.0;
        self.unsent_reward = 0.0;
    }

    fn end_episode(&mut self, tail: PendingReward) {
        self.inner.end_episode(tail);
        self.step += u64::from(tail.elapsed);
        self.episode_return += tail.reward;
        self.unsent_reward += tail.reward;
        self.send_reward();
        self.sink.publish(&FeedEvent::Episode(EpisodeEnd {
            source: self.source.clone(),
            episode: self.episode,
            episode_return: self.episode_return,
            evaluation: self.evaluation,
        }));
    }

    fn exploratory(&self) -> bool {
        self.inner.exploratory()
    }

    fn values(&self) -> &ValueTable {
        self.inner.values()
    }

    fn values_mut(&mut self) -> &mut ValueTable {
        self.inner.values_mut()
    }
}
