//! Domains the thesis learns in, each driven by a plan: the penalty kick
//! (chapter 3 and 5), Parr and Russell's 4 x 3 grid and Sutton's grid (chapter 6).
//!
//! A domain is a [`Task`](crate::domains::Task): it runs episodes of a plan with a learner choosing at
//! its choice points, and reports what each episode earned.

/// Implements the knowledge base and world of a world with no atoms (every
/// condition is false) whose only feedback is a reward accumulated in its
/// `pending` field (the N-MDP and the penalty kick).
macro_rules! reward_only_world {
    ($world:ty) => {
        impl crate::condition::KnowledgeBase for $world {
            fn holds(&self, _: crate::condition::AtomId) -> bool {
                false
            }
        }

        impl crate::executor::World for $world {
            fn take_reward(&mut self) -> f64 {
                std::mem::take(&mut self.pending)
            }
        }
    };
}

/// What a plan for each domain may use.
pub mod describe;
/// What the grid worlds share.
pub mod grid;
/// Keepaway 3 vs 2 with plan-driven keepers.
pub mod keepaway;
/// The small N-MDP of thesis Figure 4.3.
pub mod nmdp;
/// Parr and Russell's 4 x 3 grid.
pub mod parr_russell;
/// The penalty kick.
pub mod penalty_kick;
/// Sutton's 9 x 6 grid.
pub mod sutton;
mod task;

pub use task::{EpisodeOutcome, EpisodeWorld, PlanTask, TaskError};

use crate::learning::{EpisodeMode, Learner};

/// Episodes of one learning run in one domain.
pub trait Task {
    /// Runs one episode in `mode`.
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError>;

    /// The score the evaluation protocol plots: by default the mean return of
    /// `episodes` evaluation episodes (values frozen, behaviour as while learning).
    fn evaluate(&mut self, episodes: usize) -> Result<f64, TaskError> {
        mean_return(self, EpisodeMode::Evaluate, episodes)
    }

    /// The mean return of the greedy policy over `episodes` episodes.
    fn greedy_score(&mut self, episodes: usize) -> Result<f64, TaskError> {
        mean_return(self, EpisodeMode::Greedy, episodes)
    }

    /// Named values followed through a run (e.g. the options at the initial observation).
    fn traced_values(&self) -> Vec<(String, f64)>;

    /// The learners of the task (one per learning agent).
    fn learners(&self) -> Vec<&dyn Learner>;

    /// Primitive actions (moves; Keepaway: simulated cycles) of every episode
    /// the task has played so far, of every kind (learning, evaluation,
    /// greedy, recorded, and Keepaway's episodes played again after the team
    /// aborted them); `None` if the task does not count them.
    fn actions_played(&self) -> Option<u64> {
        None
    }

    /// The episodes the domain's configuration asks to replay, played after
    /// the run's last evaluation and each recorded as its domain's log text
    /// (Keepaway: a RoboCup game log); none by default.
    fn replays(&mut self) -> Result<Vec<String>, TaskError> {
        Ok(Vec::new())
    }
}

fn mean_return<T: Task + ?Sized>(task: &mut T, mode: EpisodeMode, episodes: usize) -> Result<f64, TaskError> {
    let mut total = 0.0;
    for _ in 0..episodes {
        total += task.episode(mode)?.ret;
    }
    Ok(total / episodes.max(1) as f64)
}
