//! The chassis both agent processes run on (a Keepaway keeper,
//! [`super::agent_process`](crate::multiprocess::agent::keeper), and a world's agent, [`super::world_agent`](crate::multiprocess::agent::world)):
//! the heartbeat and its counts, the supervisor's orders, the checkpoints
//! (written by a background thread, every N learning episodes and on
//! request) with the compute histogram, the resumed values a restart
//! reports, the agent's "ready", and in a run with a view its live feed
//! ([`crate::ipc::feed`]). What an agent decides with, and the messages of
//! its world, are its own.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::ipc::convert::{Rejection, agent_report, read_control};
use crate::ipc::feed::FeedPublisher;
use crate::ipc::protocol::{AgentNews, Order, ProcessState, Role};
use crate::ipc::services::{IpcError, Outlet, Pub, Sub, receive};
use crate::latency::Latency;
use crate::multiprocess::agent::background_save::{BackgroundSave, CHECKPOINT_SPACING, Checkpoint};
use crate::multiprocess::host::simulator::histogram_file;
use crate::multiprocess::{Pacemaker, ProcessError, RunContext};
use learnpnp::feed::{FeedSink, Source};
use learnpnp::learning::persist::{self, PlanLabels, SavedValues};
use learnpnp::learning::{Learner, WatchedLearner};
use learnpnp::plan::Plan;
use shm_layouts::{AgentReport, Control, Heartbeat};

/// Writes a line to the agent's log (its stderr). Unlike `eprintln!` it does
/// not panic when the write fails: a full disk must not kill the agent.
pub(crate) fn report(line: &str) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// The name of agent `k`'s checkpoint file: as the in-process experiment names
/// the values of its learning agents (`values.bin`, `values-agent2.bin`, ...).
pub fn checkpoint_name(k: usize) -> String {
    if k == 0 {
        "values.bin".to_string()
    } else {
        format!("values-agent{}.bin", k + 1)
    }
}

/// Where a restarted agent writes the values it resumed with:
/// `resumed-keeper<k>.<pid>.bin` in the run's work directory.
pub(crate) fn resumed_file(dir: &Path, k: usize, pid: u32) -> PathBuf {
    dir.join(format!("resumed-keeper{}.{pid}.bin", k + 1))
}

/// Loads a checkpoint for a restart: the file, or, if it is unusable, its
/// previous good version, reporting the problem; an error naming the file if
/// neither can be used or the values belong to another plan.
pub(crate) fn load_checkpoint(path: &Path, plan: &Plan) -> Result<SavedValues, ProcessError> {
    let saved = match persist::load(path) {
        Ok(saved) => saved,
        Err(problem) => {
            let prev = persist::prev_path(path);
            let saved = persist::load(&prev)
                .map_err(|_| ProcessError::CannotResume(format!("{problem} (and no usable {})", prev.display())))?;
            report(&format!(
                "error: {problem}; resuming from the previous checkpoint {}",
                prev.display()
            ));
            saved
        }
    };
    let expected: Vec<PlanLabels> = plan.activation_plans().into_iter().map(PlanLabels::of).collect();
    if saved.plans != expected {
        return Err(ProcessError::CannotResume(format!(
            "{}: the checkpoint was learned on another plan",
            path.display()
        )));
    }
    Ok(saved)
}

/// What every agent process carries: its run, its heartbeat, its compute
/// time, its checkpoints and its count of learning episodes.
pub(crate) struct Chassis {
    /// The run.
    pub(crate) context: RunContext,
    /// The agent (0-based): keeper `index` or world agent `index`.
    pub(crate) index: usize,
    /// Who it is to the supervisor.
    role: Role,
    /// The heartbeat and what it says.
    pub(crate) pacemaker: Pacemaker,
    /// The time from a snapshot to the agent's answer.
    pub(crate) compute: Latency,
    /// The checkpoint file.
    pub(crate) checkpoint: PathBuf,
    /// Checkpoint every this many learning episodes (0: only on request and at the end).
    checkpoint_every: u64,
    saver: BackgroundSave,
    /// Learning episodes played (and replayed) since the agent started.
    pub(crate) learning_episodes: u64,
    /// A run with a view: the agent's live feed (none otherwise: nothing of it exists).
    pub(crate) feed: Option<Arc<FeedPublisher>>,
}

impl Chassis {
    /// The chassis of agent `index` as `role` in `context`'s run, its compute
    /// histogram named `compute`.
    pub(crate) fn new(
        context: &RunContext,
        role: Role,
        index: usize,
        checkpoint_every: u64,
        compute: String,
    ) -> Result<Self, ProcessError> {
        Ok(Chassis {
            context: context.clone(),
            index,
            role,
            pacemaker: Pacemaker::new(role, context.run_id),
            compute: Latency::new(compute),
            checkpoint: context.work_dir.join(checkpoint_name(index)),
            checkpoint_every,
            saver: BackgroundSave::start(CHECKPOINT_SPACING).map_err(ProcessError::Writer)?,
            learning_episodes: 0,
            feed: match context.feed {
                true => Some(Arc::new(FeedPublisher::open(
                    &context.namespace()?,
                    index,
                    context.run_id,
                )?)),
                false => None,
            },
        })
    }

    /// `learner`, the agent's learner running `plan`, watched by the run's
    /// view if it has one (its plan, markings, choices, rewards and episodes
    /// published on the agent's feed); as it is otherwise.
    pub(crate) fn watched(&self, learner: Box<dyn Learner>, plan: &Plan) -> Box<dyn Learner> {
        let Some(feed) = &self.feed else {
            return learner;
        };
        let source = Source {
            run: self.context.run as u32,
            agent: self.index as u32,
        };
        let sink: Arc<dyn FeedSink> = feed.clone();
        Box::new(WatchedLearner::new(learner, plan, source, sink))
    }

    /// Counts a refused message in the heartbeat.
    pub(crate) fn count(&mut self, why: Rejection) {
        self.pacemaker.pulse.rejected.count(why);
    }

    /// Hands `values` (none for a fixed policy) and the histograms (the
    /// compute histogram, then `more`) to the writer thread; a failure is
    /// reported and counted there, the previous checkpoint stays.
    pub(crate) fn save(&mut self, values: Option<SavedValues>, more: &[&Latency]) {
        let mut files = Vec::new();
        for histogram in std::iter::once(&self.compute).chain(more.iter().copied()) {
            match histogram.to_bytes() {
                Ok(bytes) => files.push((histogram_file(&self.context.work_dir, histogram.name()), bytes)),
                Err(e) => report(&format!("error: {e}")),
            }
        }
        self.saver.submit(Checkpoint {
            values: values.map(|values| (self.checkpoint.clone(), values)),
            files,
        });
    }

    /// Waits until what was handed to the writer thread is written.
    pub(crate) fn flush(&mut self) {
        self.saver.flush();
    }

    /// Whether a checkpoint is due after the learning episode just counted.
    pub(crate) fn checkpoint_due(&self) -> bool {
        let every = self.checkpoint_every;
        every > 0 && self.learning_episodes.is_multiple_of(every) && self.saver.due()
    }

    /// A restart: writes the values the learner resumed with, for the
    /// supervisor to compare with the checkpoint it resumed from.
    pub(crate) fn record_resumed(&self, values: &SavedValues) -> Result<(), ProcessError> {
        let path = resumed_file(&self.context.work_dir, self.index, std::process::id());
        persist::save(&path, values)?;
        Ok(())
    }

    /// Sends a heartbeat if one is due, with the checkpoints written and
    /// failed (`more_failures`: the agent's own, e.g. its journal's).
    pub(crate) fn tick(&mut self, heartbeat: &Pub<Heartbeat>, more_failures: u64) -> Result<(), IpcError> {
        self.pacemaker.pulse.checkpoints = self.saver.written();
        self.pacemaker.pulse.checkpoint_failures = self.saver.failed() + more_failures;
        self.pacemaker.tick(heartbeat)
    }

    /// Says `state` in a heartbeat now.
    pub(crate) fn beat(&mut self, heartbeat: &Pub<Heartbeat>, state: ProcessState) -> Result<(), IpcError> {
        self.pacemaker.pulse.state = state;
        self.pacemaker.beat(heartbeat)
    }

    /// The supervisor's next order to this agent (stop, checkpoint, the host
    /// restarted), if one has come; refused messages are counted, and also
    /// handed to `refused`.
    pub(crate) fn next_order(
        &mut self,
        control: &Sub<Control>,
        mut refused: impl FnMut(Rejection),
    ) -> Result<Option<Order>, IpcError> {
        let (me, run_id) = (self.role, self.context.run_id);
        while let Some(order) = receive(control, |m| read_control(m, me, run_id))? {
            match order {
                Ok(Some(Order::KeeperLost { .. }) | None) => {}
                Ok(Some(order)) => return Ok(Some(order)),
                Err(why) => {
                    self.count(why);
                    refused(why);
                }
            }
        }
        Ok(None)
    }

    /// Says this process is ready for an episode.
    pub(crate) fn announce(&self, report: &Outlet<AgentReport>) -> Result<(), IpcError> {
        let ready = AgentNews::Ready {
            pid: std::process::id(),
        };
        report.send(agent_report(ready, self.index, self.context.run_id))?;
        Ok(())
    }
}
