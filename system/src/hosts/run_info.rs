//! Host A's description of a run for the other hosts ([`RunInfo`](crate::hosts::run_info::RunInfo)): the
//! supervisor writes it, host A's bridge serves it, host B's bridge writes
//! what it fetched for host B's supervisor.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::ipc::protocol::Roster;
use crate::ipc::wait::WaitStrategy;
use crate::multiprocess::Clock;

/// Why a run's description cannot be read or written.
#[derive(Debug, thiserror::Error)]
pub enum RunInfoError {
    /// The file cannot be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// Its JSON is unreadable.
    #[error("the run: {0}")]
    Json(String),
}

/// The directory of host B's work directory whose files its bridge ships.
pub const OUTBOX: &str = "outbox";

/// What host B needs to join host A's run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunInfo {
    /// Host A's iceoryx2 prefix: the run's name in every Zenoh key.
    pub prefix: String,
    /// The run's id (every message carries it).
    pub run_id: u64,
    /// The run's index in the experiment (it derives the seeds).
    pub run: usize,
    /// The run's processes.
    pub roster: Roster,
    /// The agents on other hosts (0-based).
    pub remote: Vec<usize>,
    /// Lock-step or real time.
    pub clock: Clock,
    /// How processes wait.
    pub wait: WaitStrategy,
    /// Agents checkpoint every this many learning episodes.
    pub checkpoint_every: u64,
    /// Round trips of each host's floor measurement.
    pub floor_round_trips: usize,
    /// The experiment, as `summary.json` holds it.
    pub spec: serde_json::Value,
}

impl RunInfo {
    /// Reads it from `path`.
    pub fn read(path: &Path) -> Result<Self, RunInfoError> {
        let text = std::fs::read(path).map_err(|source| RunInfoError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        serde_json::from_slice(&text).map_err(|e| RunInfoError::Json(format!("{}: {e}", path.display())))
    }

    /// Writes it to `path` (atomically).
    pub fn write(&self, path: &Path) -> Result<(), RunInfoError> {
        let json = serde_json::to_vec_pretty(self).map_err(|e| RunInfoError::Json(e.to_string()))?;
        atomic_file::write_atomic(path, &json).map_err(|source| RunInfoError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}
