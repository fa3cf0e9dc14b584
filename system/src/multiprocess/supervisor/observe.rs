//! What watches a supervised run from the supervisor's loop: a
//! [`RunObserver`] sees a [`RunView`] about every 10 ms and may make
//! [`Request`]s (progress bars, soak sampling, fault injection). Publishers
//! of a run's state to other processes belong here, beside the observers.

use std::path::Path;

use super::config::SupervisorError;
use super::results::RunRecord;
use crate::ipc::namespace::Namespace;
use crate::ipc::protocol::{Order, Pulse, Role, Roster};

/// A supervised run at a moment, as an observer sees it.
#[derive(Debug)]
pub struct RunView<'a> {
    /// The run's index.
    pub run: usize,
    /// Seconds since its processes were started.
    pub seconds: f64,
    /// Its iceoryx2 namespace.
    pub namespace: &'a Namespace,
    /// Its working directory (checkpoints, logs, histograms).
    pub work_dir: &'a Path,
    /// Its id (every message carries it).
    pub run_id: u64,
    /// The processes alive now, with their ids.
    pub processes: Vec<(Role, u32)>,
    /// The last heartbeat of each process alive now.
    pub pulses: Vec<Pulse>,
    /// The current host's (simulator's or world's) last heartbeat.
    pub simulator: Option<&'a Pulse>,
    /// The run's processes.
    pub roster: Roster,
}

/// What an observer asks of the supervisor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Request {
    /// Stop the run (as Ctrl-C does).
    Stop,
    /// Send `order` to `target` on the supervisor's control port.
    Order(Order, Role),
}

/// Watches supervised runs from the supervisor's loop (about every 10 ms):
/// progress bars, soak sampling, fault injection.
pub trait RunObserver {
    /// Looks at the run; returns what it asks of the supervisor (usually nothing).
    fn observe(&mut self, view: &RunView<'_>) -> Vec<Request>;

    /// Called once before the first run, with the result set the observer may
    /// claim files in (to write them as it goes).
    fn start(
        &mut self,
        _files: &mut learnpnp::experiment::result_dir::ResultWriter<'_>,
    ) -> Result<(), SupervisorError> {
        Ok(())
    }

    /// Adds the observer's files to the result set before it is published.
    fn finish(
        &mut self,
        _files: &mut learnpnp::experiment::result_dir::ResultWriter<'_>,
        _records: &[RunRecord],
    ) -> Result<(), SupervisorError> {
        Ok(())
    }
}

/// An observer that only reports the learning episodes done in each run.
pub struct Progress<F: Fn(usize, u64)>(pub F);

impl<F: Fn(usize, u64)> RunObserver for Progress<F> {
    fn observe(&mut self, view: &RunView<'_>) -> Vec<Request> {
        if let Some(pulse) = view.simulator {
            (self.0)(view.run, pulse.episodes);
        }
        Vec::new()
    }
}
