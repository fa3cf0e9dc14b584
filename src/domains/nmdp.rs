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

use super::task::{EpisodeWorld, PlanTask, TaskError, root_key};
use crate::executor::{OneStep, Registry};
use crate::learning::Learner;
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

reward_only_world!(NmdpWorld);

impl NmdpWorld {
    /// One of the four actions, by its index in [`ACTIONS`]: the first state's
    /// records the choice, the second state's draws the return.
    fn choose(&mut self, index: usize) {
        if index < 2 {
            self.first = index;
            return;
        }
        let d = self.config.returns[self.first][index - 2];
        let reward = Normal::new(d.mean, d.sd).map_or(d.mean, |n| n.sample(&mut self.rng));
        self.pending += reward;
        self.ret += reward;
    }
}

impl EpisodeWorld for NmdpWorld {
    fn begin(&mut self) {
        self.pending = 0.0;
        self.ret = 0.0;
    }
    fn step_limit(&self) -> u32 {
        100
    }
    fn ret(&self) -> f64 {
        self.ret
    }
    /// Two: one choice in each state.
    fn actions(&self) -> u32 {
        2
    }
}

/// The four actions, one step each.
pub fn registry() -> Registry<NmdpWorld> {
    let mut r = Registry::new();
    for (index, name) in ACTIONS.into_iter().enumerate() {
        r.action(name, &[], move |_| {
            OneStep::new(move |w: &mut NmdpWorld| w.choose(index))
        });
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
pub type Nmdp = PlanTask<NmdpWorld>;

impl Nmdp {
    /// A run of `plan` with `learner`, rewards drawn from `rng`.
    pub fn new(config: NmdpConfig, plan: Arc<Plan>, learner: Box<dyn Learner>, rng: SimRng) -> Result<Self, TaskError> {
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
        PlanTask::with(plan, &registry(), learner, world, traced)
    }
}
