//! What the hosts of a run tell each other besides the services: host A's
//! description of the run ([`RunInfo`], asked for by host B's bridge before
//! anything else), and, at the end, host B's files (the remote agents'
//! checkpoints and histograms) for host A's report ([`FileShipping`]).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crossbeam::channel::{Receiver, unbounded};
use serde::{Deserialize, Serialize};
use zenoh::pubsub::Subscriber;
use zenoh::query::Queryable;
use zenoh::{Session, Wait};

use super::{BridgeError, zenoh_error};
use crate::ipc::protocol::Roster;
use crate::ipc::wait::WaitStrategy;
use crate::multiprocess::Clock;

/// The Zenoh key of the run's description (one run per link).
pub const RUN_INFO_KEY: &str = "learnpnp/run-info";

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
    pub fn read(path: &Path) -> Result<Self, BridgeError> {
        let text = std::fs::read(path).map_err(|source| BridgeError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        serde_json::from_slice(&text).map_err(|e| BridgeError::RunInfo(format!("{}: {e}", path.display())))
    }

    /// Writes it to `path` (atomically).
    pub fn write(&self, path: &Path) -> Result<(), BridgeError> {
        let json = serde_json::to_vec_pretty(self).map_err(|e| BridgeError::RunInfo(e.to_string()))?;
        learnpnp::atomic_file::write_atomic(path, &json).map_err(|source| BridgeError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// Host A: answers host B's request for the run.
pub fn serve_run_info(session: &Session, info: &RunInfo) -> Result<Queryable<()>, BridgeError> {
    let json = serde_json::to_vec(info).map_err(|e| BridgeError::RunInfo(e.to_string()))?;
    session
        .declare_queryable(RUN_INFO_KEY)
        .callback(move |query| {
            // A reply that cannot be sent (the asker is gone) is asked for again.
            let _ = query.reply(RUN_INFO_KEY, json.clone()).wait();
        })
        .wait()
        .map_err(zenoh_error)
}

/// Host B: asks host A for the run until it answers, or `timeout` passes.
pub fn fetch_run_info(session: &Session, timeout: Duration) -> Result<RunInfo, BridgeError> {
    let started = Instant::now();
    while started.elapsed() < timeout {
        let replies = session
            .get(RUN_INFO_KEY)
            .timeout(Duration::from_secs(2))
            .wait()
            .map_err(zenoh_error)?;
        while let Ok(reply) = replies.recv() {
            if let Ok(sample) = reply.result() {
                return serde_json::from_slice(&sample.payload().to_bytes())
                    .map_err(|e| BridgeError::RunInfo(format!("host A's description: {e}")));
            }
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    Err(BridgeError::RunInfo(format!(
        "no host answered on the link within {} s",
        timeout.as_secs()
    )))
}

/// The Zenoh key of file `name` of the run whose prefix is `prefix`.
fn file_key(prefix: &str, name: &str) -> String {
    super::carry::key(prefix, &format!("file/{name}"))
}

/// The Zenoh key of the acknowledgement of file `name`.
fn ack_key(prefix: &str, name: &str) -> String {
    super::carry::key(prefix, &format!("file-ack/{name}"))
}

/// How often an unacknowledged file is sent again.
const RESEND_EVERY: Duration = Duration::from_millis(500);

/// The files of host B's outbox on their way to host A, or host A's
/// reception of them: every file is sent until host A acknowledges it, then
/// removed from the outbox; host A writes each into its work directory
/// (atomically) and acknowledges it.
pub enum FileShipping {
    /// Host B's side.
    Sender {
        /// The outbox.
        outbox: PathBuf,
        /// The run's prefix.
        prefix: String,
        /// When each file was last sent.
        sent: BTreeMap<String, Instant>,
        /// Acknowledged names.
        acks: Receiver<String>,
        /// Held for the acknowledgements.
        _subscriber: Subscriber<()>,
    },
    /// Host A's side.
    Receiver {
        /// Where the files go.
        work_dir: PathBuf,
        /// The run's prefix.
        prefix: String,
        /// Files that arrived (name, bytes).
        arrivals: Receiver<(String, Vec<u8>)>,
        /// Held for the files.
        _subscriber: Subscriber<()>,
    },
}

/// The file name at the end of a key (`.../file/NAME`): a plain name only.
fn name_after(key: &str, marker: &str) -> Option<String> {
    let name = key.rsplit_once(marker)?.1;
    let plain = !name.is_empty() && !name.contains('/') && !name.starts_with('.');
    plain.then(|| name.to_string())
}

impl FileShipping {
    /// Host B: ships the files that appear in `work_dir/outbox`.
    pub fn sender(session: &Session, prefix: &str, work_dir: &Path) -> Result<Self, BridgeError> {
        let outbox = work_dir.join(OUTBOX);
        std::fs::create_dir_all(&outbox).map_err(|source| BridgeError::Io {
            path: outbox.clone(),
            source,
        })?;
        let (tx, rx) = unbounded();
        let subscriber = session
            .declare_subscriber(ack_key(prefix, "*"))
            .callback(move |sample| {
                if let Some(name) = name_after(sample.key_expr().as_str(), "/file-ack/") {
                    let _ = tx.send(name);
                }
            })
            .wait()
            .map_err(zenoh_error)?;
        Ok(FileShipping::Sender {
            outbox,
            prefix: prefix.to_string(),
            sent: BTreeMap::new(),
            acks: rx,
            _subscriber: subscriber,
        })
    }

    /// Host A: writes the files host B ships into `work_dir`.
    pub fn receiver(session: &Session, prefix: &str, work_dir: &Path) -> Result<Self, BridgeError> {
        let (tx, rx) = unbounded();
        let subscriber = session
            .declare_subscriber(file_key(prefix, "*"))
            .callback(move |sample| {
                if let Some(name) = name_after(sample.key_expr().as_str(), "/file/") {
                    let _ = tx.send((name, sample.payload().to_bytes().into_owned()));
                }
            })
            .wait()
            .map_err(zenoh_error)?;
        Ok(FileShipping::Receiver {
            work_dir: work_dir.to_path_buf(),
            prefix: prefix.to_string(),
            arrivals: rx,
            _subscriber: subscriber,
        })
    }

    /// Sends, resends or writes what is due; returns how many files moved.
    pub fn pump(&mut self, session: &Session) -> Result<usize, BridgeError> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| BridgeError::Io { path, source }
        };
        match self {
            FileShipping::Sender {
                outbox,
                prefix,
                sent,
                acks,
                ..
            } => {
                let mut moved = 0;
                while let Ok(name) = acks.try_recv() {
                    let path = outbox.join(&name);
                    if path.exists() {
                        std::fs::remove_file(&path).map_err(io(&path))?;
                        moved += 1;
                    }
                    sent.remove(&name);
                }
                for entry in std::fs::read_dir(&*outbox).map_err(io(outbox))?.flatten() {
                    let name = entry.file_name().to_string_lossy().into_owned();
                    if name.starts_with('.') || !entry.path().is_file() {
                        continue;
                    }
                    if sent.get(&name).is_some_and(|t| t.elapsed() < RESEND_EVERY) {
                        continue;
                    }
                    let bytes = std::fs::read(entry.path()).map_err(io(&entry.path()))?;
                    session
                        .put(file_key(prefix, &name), bytes)
                        .wait()
                        .map_err(zenoh_error)?;
                    sent.insert(name, Instant::now());
                }
                Ok(moved)
            }
            FileShipping::Receiver {
                work_dir,
                prefix,
                arrivals,
                ..
            } => {
                let mut moved = 0;
                while let Ok((name, bytes)) = arrivals.try_recv() {
                    let path = work_dir.join(&name);
                    learnpnp::atomic_file::write_atomic(&path, &bytes).map_err(io(&path))?;
                    session
                        .put(ack_key(prefix, &name), Vec::<u8>::new())
                        .wait()
                        .map_err(zenoh_error)?;
                    moved += 1;
                }
                Ok(moved)
            }
        }
    }
}
