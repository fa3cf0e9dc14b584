//! The supervisor: for each run of an experiment it picks a run-unique
//! iceoryx2 namespace, creates the services, starts the host (the Keepaway
//! simulator, or a world in its own process) and one agent process per
//! keeper or agent, watches their exit status and heartbeats, restarts an
//! agent that dies or hangs (from its last checkpoint; the host aborts the
//! episode in flight) and a world that dies, stops everything on request with
//! a final checkpoint, and removes every shared-memory file of the run.
//!
//! Its jobs, one module each: `config` (configuration and errors),
//! `life_cycle` (the processes' launch, heartbeats, restarts and stop),
//! `hand_off` (a run across hosts: the bridge and the remote agents' files),
//! `results` (what a run produced); `watch` holds one run's state and
//! `observe` what watches it from the supervisor's loop.

pub(crate) mod config;
pub(crate) mod hand_off;
/// Starting the run's processes.
pub mod launch;
pub(crate) mod life_cycle;
pub(crate) mod observe;
/// A host of remote agents.
pub mod remote_host;
/// What a multi-process run writes.
pub mod report;
pub(crate) mod results;
pub(crate) mod watch;

pub use crate::multiprocess::supervisor::launch::world_env;
pub(crate) use config::json_error;
pub use config::{
    Cluster, EXIT_CANNOT_RESUME, IDENTITY_FILE, RunFailure, SampleLogError, SupervisorConfig, SupervisorError,
    ViewConfig,
};
pub use hand_off::{BRIDGE_STOP_GRACE, REMOTE_FILES_TIMEOUT, RUN_INFO_FILE};
pub use life_cycle::STALL_TIMEOUTS;
pub use observe::{Progress, Request, RunObserver, RunView};
pub use results::{ResumeCheck, RunRecord};
pub use watch::Fault;

use learnpnp::experiment::result_dir::{self, ResultDir};
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::ipc::feed::FeedServices;
use crate::ipc::namespace::{Namespace, NamespaceOwner};
use crate::ipc::services::{RunServices, node};
use config::{RUNS_DIR, io_error};
use watch::Watch;

/// Runs run `run` of `config`'s experiment with its files in `work_dir`
/// (created): returns what it produced once the simulator has ended and every
/// process has stopped, also when the run failed ([`RunRecord::failure`]).
/// The run's namespace is removed in every case.
pub fn supervise_run(
    config: &SupervisorConfig,
    run: usize,
    work_dir: &Path,
    stop: &AtomicBool,
    observer: &mut dyn RunObserver,
) -> Result<RunRecord, SupervisorError> {
    fs::create_dir_all(work_dir).map_err(io_error(work_dir))?;
    let spec_path = work_dir.join("spec.json");
    let spec_json = serde_json::to_vec_pretty(&config.spec).map_err(json_error("the experiment spec"))?;
    atomic_file::write_atomic(&spec_path, &spec_json).map_err(io_error(&spec_path))?;
    let owner = Namespace::claim_unique()?;
    let outcome = run_in(config, run, work_dir, &spec_path, &owner, stop, observer);
    let prefix = owner.namespace().prefix().to_string();
    let namespace = owner.namespace().clone();
    let released = owner.release();
    let mut record = outcome?;
    released?;
    record.leftover_files = namespace.files().len();
    record.prefix = prefix;
    Ok(record)
}

fn run_in(
    config: &SupervisorConfig,
    run: usize,
    work_dir: &Path,
    spec_path: &Path,
    owner: &NamespaceOwner,
    stop: &AtomicBool,
    observer: &mut dyn RunObserver,
) -> Result<RunRecord, SupervisorError> {
    let namespace = owner.namespace();
    let node = node(namespace, "supervisor")?;
    let _services = RunServices::create(&node, config.roster())?;
    let _feeds = match config.feeds() {
        true => Some(FeedServices::create(&node, config.roster().agents())?),
        false => None,
    };
    let mut watch = Watch::launch(config, namespace, &node, run, work_dir, spec_path)?;
    let watched = watch.watch(stop, observer);
    watch.stop_agents(Duration::from_secs(10))?;
    watch.stop_view();
    watch.await_remote_files()?;
    watch.collect(watched)
}

/// Where run `run`'s working files (checkpoints, logs, histograms) of the
/// output directory `out` are: in the `runs` directory of the result set being
/// written (inside its hidden staging directory, see [`learnpnp::experiment::result_dir`])
/// while the supervisor works, under `out/runs/` once the set is published.
pub fn run_work_dir(out: &Path, run: usize) -> PathBuf {
    let name = format!("run-{run}");
    result_dir::staging_dirs(out)
        .into_iter()
        .map(|staging| staging.join(RUNS_DIR).join(&name))
        .find(|dir| dir.is_dir())
        .unwrap_or_else(|| out.join(RUNS_DIR).join(name))
}

/// Runs every run of `config`'s experiment one after the other (stopping at
/// the first that fails, or when `stop` is set or `observer` asks) and
/// publishes the report in `out` as one set (the runs' working files under
/// `runs/`, then the observer's files).
pub fn supervise(
    config: &SupervisorConfig,
    out: &mut ResultDir,
    stop: &AtomicBool,
    observer: &mut dyn RunObserver,
) -> Result<crate::multiprocess::supervisor::report::Report, SupervisorError> {
    let started = Instant::now();
    let mut files = out.writer()?;
    let runs_dir = files.scratch_dir(RUNS_DIR)?;
    observer.start(&mut files)?;
    let mut records: Vec<RunRecord> = Vec::new();
    for run in 0..config.spec.protocol.runs {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        let work_dir = runs_dir.join(format!("run-{run}"));
        let record = supervise_run(config, run, &work_dir, stop, observer)?;
        let ended = record.failure.is_some() || !record.sim.complete;
        records.push(record);
        if ended {
            break;
        }
    }
    observer.finish(&mut files, &records)?;
    crate::multiprocess::supervisor::report::write_report(files, config, &records, started.elapsed().as_secs_f64())
}
