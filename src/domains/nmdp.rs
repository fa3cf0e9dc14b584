//! The small N-MDP of thesis Figure 4.3 (section 4.2.1): three states, four
//! actions, four policies whose returns are normally distributed.
//!
//! In S1 the agent chooses A1 or B1, in S2 (reached either way: the process
//! is not Markovian, S2 does not tell which was taken) A2 or B2, and the
//! episode ends in S3 with one reward drawn from the normal distribution of
//! the policy followed. The thesis gives the figure's means and deviations
//! only as a drawing we do not have; ours are chosen to show its point
//! (docs/results/RESULTS.md): the policy A1-A2 has a high variance and a
//! middling mean, so after an exploratory phase its actions hold the highest
//! upper bounds, while B1-A2 has the best mean, which the assessment finds.

use std::sync::Arc;

use rand_distr::{Distribution, Normal};

use super::Task;
use super::task::{EpisodeOutcome, TaskError, root_key, traced};
use crate::agent::PlanAgent;
use crate::condition::{AtomId, KnowledgeBase};
use crate::executor::{Action, Registry, World};
use crate::learning::{EpisodeMode, EpisodeStart, Learner, StateKey};
use crate::plan::{AllowedAtoms, Plan, PlanBuilder};
use crate::rng::SimRng;

/// The actions, in the order of [`NmdpConfig::returns`]'s indices: the first
/// state's two, then the second state's two.
pub(crate) const ACTIONS: [&str; 4] = ["A1", "B1", "A2", "B2"];

/// A normal distribution of returns: mean and standard deviation.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct ReturnDistribution {
    /// The mean.
    pub mean: f64,
    /// The standard deviation.
    pub(crate) sd: f64,
}

/// The four policies' return distributions.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct NmdpConfig {
    /// `returns[first][second]`: the policy taking A1 (0) or B1 (1) in S1
    /// and A2 (0) or B2 (1) in S2.
    pub(crate) returns: [[ReturnDistribution; 2]; 2],
}

impl Default for NmdpConfig {
    /// A1-A2: mean 6, sd 5 (the highest upper bound after exploration);
    /// B1-A2: 8, 1 (the best mean); A1-B2: 2, 1; B1-B2: 1, 1.
    fn default() -> Self {
        let d = |mean, sd| ReturnDistribution { mean, sd };
        NmdpConfig {
            returns: [[d(6.0, 5.0), d(2.0, 1.0)], [d(8.0, 1.0), d(1.0, 1.0)]],
        }
    }
}

/// The N-MDP as the plan's world: what was chosen in S1, and the reward due.
pub struct NmdpWorld {
    config: NmdpConfig,
    rng: SimRng,
    first: usize,
    pending: f64,
    ret: f64,
}

impl KnowledgeBase for NmdpWorld {
    fn holds(&self, _: AtomId) -> bool {
        false
    }
}

impl World for NmdpWorld {
    fn take_reward(&mut self) -> f64 {
        std::mem::take(&mut self.pending)
    }
}

/// One of the four actions: one step; the second state's draws the return.
struct Choose {
    index: usize,
    done: bool,
}

impl Action<NmdpWorld> for Choose {
    fn reset(&mut self) {
        self.done = false;
    }
    fn start(&mut self, _: &mut NmdpWorld) {
        self.done = false;
    }
    fn step(&mut self, w: &mut NmdpWorld) {
        if self.done {
            return;
        }
        self.done = true;
        if self.index < 2 {
            w.first = self.index;
            return;
        }
        let d = w.config.returns[w.first][self.index - 2];
        let reward = Normal::new(d.mean, d.sd).map_or(d.mean, |n| n.sample(&mut w.rng));
        w.pending += reward;
        w.ret += reward;
    }
    fn finished(&self, _: &NmdpWorld) -> bool {
        self.done
    }
}

/// The four actions.
pub fn registry() -> Registry<NmdpWorld> {
    let mut r = Registry::new();
    for (index, name) in ACTIONS.into_iter().enumerate() {
        r.action(name, &[], move |_| Choose { index, done: false });
    }
    r
}

/// The plan of Figure 4.3(a): a choice between A1 and B1 from S1 into S2,
/// then between A2 and B2 into S3, the goal.
pub fn plan() -> Result<Plan, TaskError> {
    let mut b = PlanBuilder::new("nmdp");
    let s1 = b.initial_place("S1");
    let s2 = b.place("S2");
    let s3 = b.goal_place();
    b.action_into(s1, "A1", s2);
    b.action_into(s1, "B1", s2);
    b.action_into(s2, "A2", s3);
    b.action_into(s2, "B2", s3);
    Ok(b.build(AllowedAtoms::Open)?)
}

/// Learning runs in the N-MDP; the traced values are the four actions',
/// named `S1/A1`, `S1/B1`, `S2/A2`, `S2/B2`.
pub struct Nmdp {
    agent: PlanAgent<NmdpWorld>,
    world: NmdpWorld,
    traced: Vec<(String, StateKey)>,
}

impl Nmdp {
    /// A run of `plan` with `learner`, rewards drawn from `rng`.
    pub fn new(config: NmdpConfig, plan: Arc<Plan>, learner: Box<dyn Learner>, rng: SimRng) -> Result<Self, TaskError> {
        let agent = PlanAgent::new(Arc::clone(&plan), &registry(), learner)?;
        // `S1/A1`: one plot per state, as the figure's panels (c) and (d).
        let traced = ACTIONS
            .iter()
            .enumerate()
            .filter_map(|(i, name)| {
                root_key(&plan, &[&format!("{name}.exec")]).map(|key| (format!("S{}/{name}", 1 + i / 2), key))
            })
            .collect();
        let world = NmdpWorld {
            config,
            rng,
            first: 0,
            pending: 0.0,
            ret: 0.0,
        };
        Ok(Nmdp { agent, world, traced })
    }
}

impl Task for Nmdp {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        self.world.pending = 0.0;
        self.world.ret = 0.0;
        let steps = self
            .agent
            .run(&mut self.world, EpisodeStart::of(mode), 100, |_| false)?;
        Ok(EpisodeOutcome {
            ret: self.world.ret,
            actions: 2,
            steps,
            exploratory: self.agent.learner().exploratory(),
        })
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        traced(self.agent.learner(), &self.traced)
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        vec![self.agent.learner()]
    }
}
