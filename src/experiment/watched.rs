//! An experiment's task watched by a view: the learning curve published to a
//! feed as the runner records it.

use std::sync::Arc;

use learnpnp_feed::{CurvePoint, FeedEvent, FeedSink};

use crate::domains::{EpisodeOutcome, Task, TaskError};
use crate::learning::{EpisodeMode, Learner};

/// A [`Task`] that forwards everything to the task it wraps and publishes
/// each evaluation's score as a point of the learning curve.
pub(crate) struct WatchedTask {
    inner: Box<dyn Task>,
    run: u32,
    learned: u64,
    sink: Arc<dyn FeedSink>,
}

impl WatchedTask {
    /// Wraps `inner`, the task of run `run`, publishing to `sink`.
    pub(crate) fn new(inner: Box<dyn Task>, run: usize, sink: Arc<dyn FeedSink>) -> Self {
        WatchedTask {
            inner,
            run: run as u32,
            learned: 0,
            sink,
        }
    }
}

impl Task for WatchedTask {
    fn episode(&mut self, mode: EpisodeMode) -> Result<EpisodeOutcome, TaskError> {
        let outcome = self.inner.episode(mode)?;
        if mode == EpisodeMode::Learn {
            self.learned += 1;
        }
        Ok(outcome)
    }

    fn evaluate(&mut self, episodes: usize) -> Result<f64, TaskError> {
        let value = self.inner.evaluate(episodes)?;
        self.sink.publish(&FeedEvent::Curve(CurvePoint {
            run: self.run,
            episode: self.learned,
            value,
        }));
        Ok(value)
    }

    fn greedy_score(&mut self, episodes: usize) -> Result<f64, TaskError> {
        self.inner.greedy_score(episodes)
    }

    fn traced_values(&self) -> Vec<(String, f64)> {
        self.inner.traced_values()
    }

    fn actions_played(&self) -> Option<u64> {
        self.inner.actions_played()
    }

    fn learners(&self) -> Vec<&dyn Learner> {
        self.inner.learners()
    }

    fn replays(&mut self) -> Result<Vec<String>, TaskError> {
        self.inner.replays()
    }
}
