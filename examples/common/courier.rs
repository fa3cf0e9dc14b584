//! A small environment of our own, in the style of gymnasium (`reset`, then
//! `step(action)` until `terminated` or `truncated`), and the glue that lets a
//! Petri Net Plan drive it and a learner learn in it.
//!
//! A courier delivers two parcels. Before each delivery it sees whether it
//! rains, and picks a route: the short one takes 1 hour but may cross a
//! flooded underpass that costs 10 more (10% of the time when dry, 60% in the
//! rain); the long one always takes 3. The reward is minus the hours spent.
//! The best plan: short when dry (-2 on average), long in the rain (-3).

use std::sync::Arc;

use learnpnp::PlanAgent;
use learnpnp::condition::{AtomId, AtomTable, KnowledgeBase};
use learnpnp::domains::TaskError;
use learnpnp::executor::{OneStep, Registry, World};
use learnpnp::learning::{
    Assessment, EpisodeMode, EpisodeStart, ExploitPolicy, Learner, Schedule, Sigma, SoSmc, SoSmcConfig, StepSize,
    Unestimated,
};
use learnpnp::plan::{AllowedAtoms, Plan, PlanBuilder, PlanError};
use learnpnp::rng::{SimRng, seeded};
use rand::RngExt;

/// The environment's actions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Route {
    /// One hour, unless the underpass is flooded (ten more).
    Short,
    /// Three hours.
    Long,
}

/// What the courier sees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Observation {
    /// It rains now.
    pub raining: bool,
    /// Parcels still to deliver.
    pub parcels: u8,
}

/// The result of one step, as gymnasium returns it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// What the courier sees next.
    pub observation: Observation,
    /// Minus the hours the delivery took.
    pub reward: f64,
    /// Every parcel is delivered.
    pub terminated: bool,
    /// The episode was cut (never here: two deliveries always end it).
    pub truncated: bool,
}

/// The courier's world.
pub struct CourierEnv {
    rng: SimRng,
    state: Observation,
}

impl CourierEnv {
    /// An environment drawing from `seed`.
    pub fn new(seed: u64) -> Self {
        CourierEnv {
            rng: seeded(seed),
            state: Observation::default(),
        }
    }

    /// A new episode: two parcels, the weather drawn.
    pub fn reset(&mut self) -> Observation {
        self.state = Observation {
            raining: self.rng.random_bool(0.5),
            parcels: 2,
        };
        self.state
    }

    /// Delivers one parcel by `route`.
    pub fn step(&mut self, route: Route) -> Step {
        let flood = if self.state.raining { 0.6 } else { 0.1 };
        let hours = match route {
            Route::Short if self.rng.random_bool(flood) => 11.0,
            Route::Short => 1.0,
            Route::Long => 3.0,
        };
        self.state.parcels = self.state.parcels.saturating_sub(1);
        self.state.raining = self.rng.random_bool(0.5);
        Step {
            observation: self.state,
            reward: -hours,
            terminated: self.state.parcels == 0,
            truncated: false,
        }
    }
}

/// The atoms a plan's guards may test, in the order of their ids.
pub const ATOMS: [&str; 2] = ["Raining", "Delivered"];

/// The environment as a plan's executor sees it: a knowledge base (the atoms
/// of the latest observation) and the reward collected since it last asked.
pub struct Courier {
    /// The environment.
    pub env: CourierEnv,
    observation: Observation,
    pending: f64,
    /// What the current episode earned.
    pub episode_return: f64,
}

impl Courier {
    /// A courier in a new environment drawing from `seed`.
    pub fn new(seed: u64) -> Self {
        Courier {
            env: CourierEnv::new(seed),
            observation: Observation::default(),
            pending: 0.0,
            episode_return: 0.0,
        }
    }

    /// Starts an episode.
    pub fn reset(&mut self) {
        self.observation = self.env.reset();
        self.pending = 0.0;
        self.episode_return = 0.0;
    }
}

impl KnowledgeBase for Courier {
    fn holds(&self, atom: AtomId) -> bool {
        match atom.index() {
            0 => self.observation.raining,
            1 => self.observation.parcels == 0,
            _ => false,
        }
    }
}

impl World for Courier {
    fn take_reward(&mut self) -> f64 {
        std::mem::take(&mut self.pending)
    }
}

impl Courier {
    /// One delivery by `route`.
    fn drive(&mut self, route: Route) {
        let step = self.env.step(route);
        self.observation = step.observation;
        self.pending += step.reward;
        self.episode_return += step.reward;
    }
}

/// The actions a plan may name: `Short` and `Long`.
pub fn registry() -> Registry<Courier> {
    let mut r = Registry::new();
    // A plan action: one delivery by one route (one executor step).
    r.action("Short", &[], |_| OneStep::new(|w: &mut Courier| w.drive(Route::Short)));
    r.action("Long", &[], |_| OneStep::new(|w: &mut Courier| w.drive(Route::Long)));
    r
}

/// The plan: read the weather, then choose a route (a choice point in each
/// weather, so that the two choices get their own values), until delivered.
pub fn plan() -> Result<Plan, PlanError> {
    let mut b = PlanBuilder::new("courier");
    let look = b.initial_place("look");
    let wet = b.place("wet");
    let dry = b.place("dry");
    b.transition("[Raining]", &[(look, 1)], &[(wet, 1)]);
    b.transition("[not Raining]", &[(look, 1)], &[(dry, 1)]);
    let delivered = b.place("delivered");
    for weather in [wet, dry] {
        b.action_into(weather, "Short", delivered);
        b.action_into(weather, "Long", delivered);
    }
    let goal = b.goal_place();
    b.transition("[Delivered]", &[(delivered, 1)], &[(goal, 1)]);
    b.transition("[not Delivered]", &[(delivered, 1)], &[(look, 1)]);
    let atoms: AtomTable = ATOMS.into_iter().collect();
    b.build(AllowedAtoms::Closed(&atoms))
}

/// epsilon-SoSMC (thesis chapter 4): 100 exploratory episodes, then every 20th.
pub fn learner(seed: u64) -> Box<dyn Learner> {
    Box::new(SoSmc::new(
        SoSmcConfig {
            gamma: 1.0,
            initial_phase: 100,
            sigma: Sigma::EpsilonGreedy,
            initial_parameter: Schedule::constant(0.5),
            assessing_parameter: Schedule::constant(0.2),
            assessment: Assessment::EveryN(20),
            step_size: StepSize::Constant(0.05),
            initial_value: f64::NEG_INFINITY,
            threshold: None,
            unestimated: Unestimated::AsBest,
            exploit: ExploitPolicy::Greedy,
        },
        seeded(seed),
    ))
}

/// Plays one episode in `mode` and returns what it earned.
pub fn episode(agent: &mut PlanAgent<Courier>, courier: &mut Courier, mode: EpisodeMode) -> Result<f64, TaskError> {
    courier.reset();
    agent.run(courier, EpisodeStart::of(mode), 100, |_| false)?;
    Ok(courier.episode_return)
}

/// A learner (from `seed`) trained for `episodes` episodes in a courier's world.
pub fn train(seed: u64, episodes: u64) -> Result<PlanAgent<Courier>, TaskError> {
    let plan = Arc::new(plan()?);
    let mut agent = PlanAgent::new(plan, &registry(), learner(seed))?;
    let mut courier = Courier::new(seed + 1);
    for _ in 0..episodes {
        episode(&mut agent, &mut courier, EpisodeMode::Learn)?;
    }
    Ok(agent)
}
