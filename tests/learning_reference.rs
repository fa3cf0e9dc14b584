//! The reference library's learner test (shared/reference/pnp-format.md, last paragraph):
//! p1 branches to p2 -> p4 and p3 -> p5; ending the action at p4 pays 5, at p5
//! pays 1; alpha 0.1, gamma 0.8, 300 episodes. Expected V(p2)=4, V(p3)=0.8,
//! V(p4)=5, V(p5)=1 within 0.01 for TD(0), TD(0.9) and Monte Carlo with
//! epsilon-greedy(0.5), and V(p1)=3.2 for Q-learning.

use std::sync::Arc;

use learnpnp::condition::{AtomId, KnowledgeBase};
use learnpnp::executor::{Executor, OneStep, PlanKey, Registry, World};
use learnpnp::learning::{
    EpisodeStart, Exploration, Learner, MonteCarlo, MonteCarloConfig, Schedule, Scope, Target, TdConfig, TdLearner,
};
use learnpnp::net::{Marking, PetriNet, PlaceNode, TransitionNode};
use learnpnp::plan::{AllowedAtoms, Plan};
use learnpnp::rng::seeded;

#[derive(Default)]
struct Env {
    reward: f64,
}

impl KnowledgeBase for Env {
    fn holds(&self, _: AtomId) -> bool {
        false
    }
}

impl World for Env {
    fn take_reward(&mut self) -> f64 {
        std::mem::take(&mut self.reward)
    }
}

/// An action that finishes in its first step, paying `amount`.
fn pay(amount: f64) -> OneStep<impl FnMut(&mut Env) + Send> {
    OneStep::new(move |env: &mut Env| env.reward += amount)
}

fn env1() -> Plan {
    let place = |id: &str, label: &str, m: u8| PlaceNode {
        id: id.into(),
        label: label.into(),
        initial: m,
        position: None,
    };
    let transition = |id: &str, label: &str| TransitionNode {
        id: id.into(),
        label: label.into(),
        position: None,
    };
    let net = PetriNet::new(
        "env1",
        vec![
            place("p1", "p1", 1),
            place("p2", "p2", 0),
            place("p3", "p3", 0),
            place("p4", "a4.exec", 0),
            place("p5", "a5.exec", 0),
        ],
        vec![
            transition("t1", ""),
            transition("t2", ""),
            transition("t3", "a4.start"),
            transition("t4", "a5.start"),
            transition("t5", "a4.end"),
            transition("t6", "a5.end"),
        ],
        &[
            ("a1", "p1", "t1", 1),
            ("a2", "t1", "p2", 1),
            ("a3", "p1", "t2", 1),
            ("a4", "t2", "p3", 1),
            ("a5", "p2", "t3", 1),
            ("a6", "t3", "p4", 1),
            ("a7", "p3", "t4", 1),
            ("a8", "t4", "p5", 1),
            ("a9", "p4", "t5", 1),
            ("a10", "p5", "t6", 1),
        ],
    )
    .expect("valid net");
    Plan::from_net(net, AllowedAtoms::Open).expect("valid plan")
}

fn train(learner: &mut dyn Learner) {
    let mut registry = Registry::new();
    registry.action("a4", &[], |_| pay(5.0));
    registry.action("a5", &[], |_| pay(1.0));
    let mut exec = Executor::new(Arc::new(env1()), &registry).expect("executor");
    let mut env = Env::default();
    for _ in 0..300 {
        learner.begin_episode(EpisodeStart::LEARN);
        exec.reset(&mut env, learner);
        for _ in 0..10 {
            exec.step(&mut env, learner).expect("step");
            if exec.marking().total() == 0 {
                break;
            }
        }
        assert_eq!(exec.marking().total(), 0, "the episode ends with an empty marking");
        learner.end_episode(exec.take_pending());
    }
}

fn value(learner: &dyn Learner, place: usize) -> f64 {
    let mut tokens = vec![0; 5];
    tokens[place - 1] = 1;
    learner.values().value_of(PlanKey::ROOT, &Marking::from_tokens(tokens))
}

fn td(lambda: f64, target: Target) -> TdLearner {
    TdLearner::new(
        TdConfig {
            gamma: 0.8,
            alpha: 0.1,
            lambda,
            target,
            scope: Scope::Markings,
            exploration: Exploration::EpsilonGreedy(Schedule::constant(0.5)),
            initial_value: 0.0,
            consistent: false,
        },
        seeded(11),
    )
}

fn assert_reference_values(learner: &dyn Learner, name: &str) {
    for (place, expected) in [(2, 4.0), (3, 0.8), (4, 5.0), (5, 1.0)] {
        let v = value(learner, place);
        assert!(
            (v - expected).abs() < 0.01,
            "{name}: V(p{place}) = {v}, expected {expected}"
        );
    }
}

#[test]
fn td0_matches_the_reference() {
    let mut l = td(0.0, Target::OnPolicy);
    train(&mut l);
    assert_reference_values(&l, "TD(0)");
}

#[test]
fn td_lambda_matches_the_reference() {
    let mut l = td(0.9, Target::OnPolicy);
    train(&mut l);
    assert_reference_values(&l, "TD(0.9)");
}

#[test]
fn monte_carlo_matches_the_reference() {
    let mut l = MonteCarlo::new(
        MonteCarloConfig {
            gamma: 0.8,
            alpha: 0.1,
            exploration: Exploration::EpsilonGreedy(Schedule::constant(0.5)),
            initial_value: 0.0,
        },
        seeded(12),
    );
    train(&mut l);
    assert_reference_values(&l, "Monte Carlo");
}

#[test]
fn q_learning_matches_the_reference() {
    let mut l = td(0.0, Target::Max);
    train(&mut l);
    assert_reference_values(&l, "Q-learning");
    let v1 = value(&l, 1);
    assert!((v1 - 3.2).abs() < 0.01, "Q-learning: V(p1) = {v1}, expected 3.2");
}
