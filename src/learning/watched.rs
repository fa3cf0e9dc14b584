//! A learner watched by a view: it forwards everything to the learner it
//! wraps and publishes what happens to a [`FeedSink`] (the live feed of
//! [`learnpnp_feed`]). A run with no view wraps nothing and pays nothing.

use std::collections::HashMap;
use std::sync::Arc;
use std::time::{Duration, Instant};

use learnpnp_feed::{
    ACTION_MARKINGS_PER_SECOND, ChoiceMade, EpisodeEnd, FeedEvent, FeedSink, MARKINGS_PER_SECOND, MarkingSample,
    OptionValue, PlaceShape, PlaceTokens, PlanShape, RewardSample, Source, TransitionShape,
};

use super::{EpisodeMode, EpisodeStart, Learner, ValueTable};
use crate::analysis::option_label;
use crate::executor::{Chooser, PendingReward, PlanKey};
use crate::net::{Marking, NodeRef, PlaceId};
use crate::plan::Plan;

/// The labels a view reads of one plan (the root plan or a sub-plan).
#[derive(Debug, Clone)]
struct PlanLabels {
    /// The plan's name.
    name: String,
    /// Each place's name (its label, or its id when the label is blank).
    places: Vec<String>,
    /// Each action's name and its execution places.
    actions: Vec<(String, Vec<PlaceId>)>,
}

impl PlanLabels {
    fn new(plan: &Plan) -> Self {
        PlanLabels {
            name: plan.name().to_owned(),
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

    /// The first place `to` holds fewer tokens in than `from`: where a choice leaves from.
    fn lost(&self, from: &Marking, to: &Marking) -> Option<String> {
        let i = from.tokens().iter().zip(to.tokens()).position(|(a, b)| b < a)?;
        Some(self.place(i))
    }
}

/// The options of one plan's choices named as `learnpnp values` names them:
/// by the transitions that lead to them ([`option_label`]), each pair of
/// markings worked out once.
#[derive(Debug)]
struct OptionNames {
    plan: Plan,
    /// Names by the marking where the choice is made, then by the option's
    /// marking (looked up by reference: nothing is cloned to find a name).
    known: HashMap<Marking, HashMap<Marking, String>>,
    /// How many names `known` holds.
    kept: usize,
}

/// How many option names [`OptionNames`] keeps before it starts again (a
/// plan's choices are made at few markings; this bounds a plan with many).
const OPTION_NAMES_KEPT: usize = 4096;

impl OptionNames {
    fn new(plan: &Plan) -> Self {
        OptionNames {
            plan: plan.clone(),
            known: HashMap::new(),
            kept: 0,
        }
    }

    /// The name of the option that leads from `from` to `to`.
    fn name(&mut self, from: &Marking, to: &Marking) -> String {
        if let Some(name) = self.known.get(from).and_then(|options| options.get(to)) {
            return name.clone();
        }
        if self.kept >= OPTION_NAMES_KEPT {
            self.known.clear();
            self.kept = 0;
        }
        let name = option_label(&self.plan, from, to);
        self.known
            .entry(from.clone())
            .or_default()
            .insert(to.clone(), name.clone());
        self.kept += 1;
        name
    }
}

/// A [`Learner`] that publishes to a feed: its plan's shape once, the
/// markings of the plan and its sub-plans (at most [`MARKINGS_PER_SECOND`] a
/// second in all, each naming its sub-plan, with the rewards
/// received since the previous one; and besides, at most
/// [`ACTION_MARKINGS_PER_SECOND`] a second, each marking whose running
/// actions are others than the last published, so that each action a robot
/// runs is seen), every choice with the options' values and update counts,
/// and every episode's end and return.
pub struct WatchedLearner {
    inner: Box<dyn Learner>,
    sink: Arc<dyn FeedSink>,
    source: Source,
    /// Labels of the plan (index 0) and its sub-plans, in [`PlanKey`] order.
    plans: Vec<PlanLabels>,
    /// Names of their choices' options, in the same order.
    option_names: Vec<OptionNames>,
    episode: u64,
    episodes_begun: u64,
    evaluation: bool,
    step: u64,
    episode_return: f64,
    /// Rewards received since the last reward sample.
    unsent_reward: f64,
    next_sample: Instant,
    /// When a marking whose running actions changed may next be published.
    next_action_sample: Instant,
    /// The running actions (indices) of the marking examined last, and of
    /// the last published one, with their plans.
    running: (PlanKey, Vec<usize>),
    running_sent: (PlanKey, Vec<usize>),
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
    name: String::new(),
    places: Vec::new(),
    actions: Vec::new(),
};

/// The interval between two marking samples.
const SAMPLE_PERIOD: Duration = Duration::from_nanos(1_000_000_000 / MARKINGS_PER_SECOND as u64);

/// The interval between two markings published because their running actions changed.
const ACTION_SAMPLE_PERIOD: Duration = Duration::from_nanos(1_000_000_000 / ACTION_MARKINGS_PER_SECOND as u64);

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
            option_names: plan.activation_plans().into_iter().map(OptionNames::new).collect(),
            episode: 0,
            episodes_begun: 0,
            evaluation: false,
            step: 0,
            episode_return: 0.0,
            unsent_reward: 0.0,
            next_sample: Instant::now(),
            next_action_sample: Instant::now(),
            running: (PlanKey::ROOT, Vec::new()),
            running_sent: (PlanKey::ROOT, Vec::new()),
        }
    }

    /// Publishes `plan`'s marking if the agent's budget of markings allows
    /// (the root plan and its sub-plans share the budget), or if actions
    /// other than the last published run in it and the budget of such
    /// markings allows.
    fn sample(&mut self, plan: PlanKey, marking: &Marking) {
        let now = Instant::now();
        let labels = self.plans.get(usize::from(plan.0)).unwrap_or(&UNKNOWN_PLAN);
        self.running.0 = plan;
        self.running.1.clear();
        self.running.1.extend(
            labels
                .actions
                .iter()
                .enumerate()
                .filter(|(_, (_, places))| places.iter().any(|&p| marking.get(p) > 0))
                .map(|(i, _)| i),
        );
        if now >= self.next_sample {
            self.next_sample = now + SAMPLE_PERIOD;
        } else if !self.running.1.is_empty() && self.running != self.running_sent && now >= self.next_action_sample {
            self.next_action_sample = now + ACTION_SAMPLE_PERIOD;
        } else {
            return;
        }
        self.running_sent.clone_from(&self.running);
        let running = self.running.1.iter().map(|&i| labels.actions[i].0.clone()).collect();
        self.sink.publish(&FeedEvent::Marking(MarkingSample {
            source: self.source.clone(),
            sub_plan: (plan != PlanKey::ROOT).then(|| labels.name.clone()),
            episode: self.episode,
            step: self.step,
            tokens: marking.tokens().iter().map(|&n| u32::from(n)).collect(),
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

    fn publish_choice(&mut self, plan: PlanKey, state: &Marking, options: &[Marking], taken: usize) {
        let labels = self.plans.get(usize::from(plan.0)).unwrap_or(&UNKNOWN_PLAN);
        let mut names = self.option_names.get_mut(usize::from(plan.0));
        let table: &ValueTable = self.inner.values();
        let values: Vec<OptionValue> = options
            .iter()
            .enumerate()
            .map(|(i, option)| {
                let id = table.find(plan, option);
                OptionValue {
                    label: names
                        .as_mut()
                        .map_or_else(|| format!("option {i}"), |n| n.name(state, option)),
                    // A value never updated is the initial value, not a learned one.
                    value: id.filter(|&id| table.visits(id) > 0).map(|id| table.value(id)),
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
        }
        self.sample(plan, marking);
    }

    fn plan_started(&mut self, plan: PlanKey, marking: &Marking) {
        self.inner.plan_started(plan, marking);
        self.sample(plan, marking);
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

#[cfg(test)]
mod tests {
    use std::path::Path;
    use std::sync::Mutex;

    use super::*;
    use crate::learning::{Exploration, MonteCarlo, MonteCarloConfig, Schedule};
    use crate::plan::AllowedAtoms;
    use crate::plan_file::load_plan;
    use crate::rng::seeded;

    /// A sink that keeps what is published.
    #[derive(Default)]
    struct Kept(Mutex<Vec<FeedEvent>>);

    impl FeedSink for Kept {
        fn publish(&self, event: &FeedEvent) {
            self.0.lock().unwrap().push(event.clone());
        }
    }

    /// A marking of `places` places with one token in the first.
    fn first_marked(places: usize) -> Marking {
        let mut tokens = vec![0; places];
        tokens[0] = 1;
        Marking::from_tokens(tokens)
    }

    /// Agent 1's Monte Carlo learner on `plan`, watched, and what it publishes.
    fn watched(plan: &Plan) -> (WatchedLearner, Arc<Kept>) {
        let kept = Arc::new(Kept::default());
        let learner = MonteCarlo::new(
            MonteCarloConfig {
                gamma: 1.0,
                alpha: 0.1,
                exploration: Exploration::EpsilonGreedy(Schedule::constant(0.1)),
                initial_value: 0.0,
            },
            seeded(1),
        );
        let watched = WatchedLearner::new(Box::new(learner), plan, Source { run: 0, agent: 1 }, kept.clone());
        (watched, kept)
    }

    #[test]
    fn sub_plans_markings_are_sampled_within_the_agents_budget_and_name_their_sub_plan() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("plans/keepaway_position.schema");
        let plan = load_plan(&path, AllowedAtoms::Open).unwrap();
        let plans = plan.activation_plans();
        let sub = plans[1];
        let (mut watched, kept) = watched(&plan);
        let root = first_marked(plan.net().places().len());
        let inner = first_marked(sub.net().places().len());
        watched.plan_started(PlanKey::ROOT, &root);
        // Within the same period: the agent's budget is spent, nothing is sampled.
        watched.plan_started(PlanKey(1), &inner);
        std::thread::sleep(SAMPLE_PERIOD + Duration::from_millis(5));
        watched.transition(PlanKey(1), &inner, 0.0, 1);
        let markings = markings(&kept);
        assert_eq!(markings.len(), 2, "{markings:?}");
        assert_eq!(markings[0].sub_plan, None);
        assert_eq!(markings[0].marked[0].label, plan.place_name(PlaceId::new(0)));
        assert_eq!(markings[1].sub_plan.as_deref(), Some(sub.name()));
        assert_eq!(markings[1].marked[0].label, sub.place_name(PlaceId::new(0)));
        assert_eq!(markings[1].tokens.len(), sub.net().places().len());
        // The root plan's marking is written as before (no `sub_plan` key).
        let root_json = String::from_utf8(FeedEvent::Marking(markings[0].clone()).payload_json().unwrap()).unwrap();
        assert!(!root_json.contains("sub_plan"), "{root_json}");
    }

    /// The records of one kind published, in order (`pick` keeps that kind).
    fn published<T>(kept: &Kept, pick: impl Fn(&FeedEvent) -> Option<T>) -> Vec<T> {
        kept.0.lock().unwrap().iter().filter_map(pick).collect()
    }

    /// The markings published, in order.
    fn markings(kept: &Kept) -> Vec<MarkingSample> {
        published(kept, |e| match e {
            FeedEvent::Marking(m) => Some(m.clone()),
            _ => None,
        })
    }

    /// The choices published, in order.
    fn choices(kept: &Kept) -> Vec<ChoiceMade> {
        published(kept, |e| match e {
            FeedEvent::Choice(c) => Some(c.clone()),
            _ => None,
        })
    }

    #[test]
    fn each_action_started_is_published_beyond_the_markings_budget() {
        // A robot's steps: each action ends (no action runs) and the next
        // starts at once, a cycle of the robot later (here a little more
        // than the action markings' interval, far less than the markings').
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("plans/corridor.pnml");
        let plan = load_plan(&path, AllowedAtoms::Open).unwrap();
        let places = plan.net().places().len();
        let (mut watched, kept) = watched(&plan);
        watched.plan_started(PlanKey::ROOT, &first_marked(places));
        let actions: Vec<(String, PlaceId)> = plan
            .actions()
            .iter()
            .map(|a| (a.name.clone(), a.exec_places[0]))
            .collect();
        assert!(actions.len() >= 2, "{actions:?}");
        let idle = Marking::from_tokens(vec![0; places]);
        let mut started = Vec::new();
        for step in 0..6 {
            let (name, place) = &actions[step % actions.len()];
            let mut running = vec![0; places];
            running[place.index()] = 1;
            std::thread::sleep(ACTION_SAMPLE_PERIOD + Duration::from_millis(1));
            watched.transition(PlanKey::ROOT, &idle, 0.0, 1);
            watched.transition(PlanKey::ROOT, &Marking::from_tokens(running), 0.0, 0);
            started.push(name.clone());
        }
        let published = markings(&kept);
        // After the plan's start (published first):
        let shown: Vec<&str> = published[1..]
            .iter()
            .filter(|m| !m.running.is_empty())
            .map(|m| m.running[0].as_str())
            .collect();
        assert_eq!(shown, started, "every action started, in order: {published:?}");
    }

    #[test]
    fn a_choices_options_are_named_by_the_transitions_that_lead_to_them() {
        // keepaway_position's options all gain `decide` (and a position's
        // memory place): a place could not tell them apart, a transition does.
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("plans/keepaway_position.pnml");
        let plan = load_plan(&path, AllowedAtoms::Open).unwrap();
        let state = plan.initial_marking();
        let choice = crate::analysis::choices_at(&plan, &state)
            .into_iter()
            .next()
            .expect("the plan chooses at its start");
        let options: Vec<Marking> = choice.options.iter().map(|(_, next)| next.clone()).collect();
        let (mut watched, kept) = watched(&plan);
        for _ in 0..2 {
            watched.choose(PlanKey::ROOT, &state, &options);
        }
        let choices = choices(&kept);
        assert_eq!(choices.len(), 2);
        let expected: Vec<String> = choice
            .options
            .iter()
            .map(|&(t, _)| crate::analysis::transition_name(&plan, t).to_owned())
            .collect();
        for made in &choices {
            let labels: Vec<&str> = made.options.iter().map(|o| o.label.as_str()).collect();
            assert_eq!(labels, expected);
        }
        let distinct: std::collections::HashSet<&String> = expected.iter().collect();
        assert_eq!(distinct.len(), expected.len(), "{expected:?}");
    }
}
