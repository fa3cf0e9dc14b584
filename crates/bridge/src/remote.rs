//! What the hosts of a run tell each other besides the services: host A's
//! description of the run ([`RunInfo`](learnpnp_system::hosts::run_info::RunInfo), written by its supervisor and asked for by host B's bridge before
//! anything else), and, at the end, host B's files (the remote agents'
//! checkpoints and histograms) for host A's report ([`FileShipping`](crate::remote::FileShipping)).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crossbeam::channel::{Receiver, unbounded};
use zenoh::pubsub::Subscriber;
use zenoh::qos::CongestionControl;
use zenoh::query::Queryable;
use zenoh::{Session, Wait};

use super::{BridgeError, zenoh_error};
use learnpnp_system::hosts::report::LinkRefusals;
use learnpnp_system::hosts::run_info::{OUTBOX, RunInfo};
use learnpnp_system::hosts::shipped::Quarantine;

/// The Zenoh key of the run's description (one run per link).
pub(crate) const RUN_INFO_KEY: &str = "learnpnp/run-info";

/// Host A: answers host B's request for the run. Over a secure link, host
/// A's access control lets only host B's certificate ask
/// ([`super::access`]); over plain TCP anyone who reaches the port can.
pub(crate) fn serve_run_info(session: &Session, info: &RunInfo) -> Result<Queryable<()>, BridgeError> {
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
pub(crate) fn fetch_run_info(session: &Session, timeout: Duration) -> Result<RunInfo, BridgeError> {
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

/// The Zenoh key of file `name` of the run whose prefix is `prefix` (a
/// key expression when `name` holds wildcards).
pub(crate) fn file_key(prefix: &str, name: &str) -> String {
    super::carry::key(prefix, &format!("file/{name}"))
}

/// The Zenoh key of the acknowledgement of file `name`.
pub(crate) fn ack_key(prefix: &str, name: &str) -> String {
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
    Receiver(Box<Reception>),
}

/// Host A's reception of host B's files: each passes the [`Quarantine`]
/// (written there, checked, moved into the run only if good) and is
/// acknowledged once in the run; a refused one is never acknowledged.
pub struct Reception {
    /// The run's prefix.
    prefix: String,
    /// Where files wait to be checked.
    pub(crate) quarantine: Quarantine,
    /// Files that arrived (name, bytes).
    arrivals: Receiver<(String, Vec<u8>)>,
    /// Held for the files.
    _subscriber: Subscriber<()>,
}

/// The file name at the end of a key (`.../file/NAME`): a plain name only.
fn name_after(key: &str, marker: &str) -> Option<String> {
    let name = key.rsplit_once(marker)?.1;
    let plain = !name.is_empty() && !name.contains('/') && !name.starts_with('.');
    plain.then(|| name.to_string())
}

impl FileShipping {
    /// Host B: ships the files that appear in `work_dir/outbox`.
    pub(crate) fn sender(session: &Session, prefix: &str, work_dir: &Path) -> Result<Self, BridgeError> {
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

    /// Host A: writes the files host B ships for the run `info` into
    /// `work_dir`, those of the expected names and content only.
    pub(crate) fn receiver(session: &Session, info: &RunInfo, work_dir: &Path) -> Result<Self, BridgeError> {
        let prefix = info.prefix.as_str();
        let (tx, rx) = unbounded();
        let subscriber = session
            .declare_subscriber(file_key(prefix, "*"))
            .callback(move |sample| {
                // A name that is not plain arrives empty, to be refused and counted.
                let name = name_after(sample.key_expr().as_str(), "/file/").unwrap_or_default();
                let _ = tx.send((name, sample.payload().to_bytes().into_owned()));
            })
            .wait()
            .map_err(zenoh_error)?;
        Ok(FileShipping::Receiver(Box::new(Reception {
            prefix: prefix.to_string(),
            quarantine: Quarantine::new(info, work_dir),
            arrivals: rx,
            _subscriber: subscriber,
        })))
    }

    /// Sends, resends or writes what is due; returns how many files moved.
    /// A file under a name the run does not expect is counted in `refused`
    /// and neither written nor acknowledged.
    pub(crate) fn pump(&mut self, session: &Session, refused: &mut LinkRefusals) -> Result<usize, BridgeError> {
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
                        .congestion_control(CongestionControl::Block)
                        .wait()
                        .map_err(zenoh_error)?;
                    sent.insert(name, Instant::now());
                }
                Ok(moved)
            }
            FileShipping::Receiver(reception) => {
                let mut moved = 0;
                while let Ok((name, bytes)) = reception.arrivals.try_recv() {
                    match reception.quarantine.take(&name, &bytes) {
                        Ok(Ok(())) => {
                            // Droppable: a subscriber to the acknowledgements
                            // that stops reading must not block host A
                            // (a lost one is asked for again: the file comes again).
                            session
                                .put(ack_key(&reception.prefix, &name), Vec::<u8>::new())
                                .congestion_control(CongestionControl::Drop)
                                .wait()
                                .map_err(zenoh_error)?;
                            moved += 1;
                        }
                        Ok(Err(refusal)) => refusal.count(refused),
                        Err(source) => {
                            return Err(BridgeError::Io {
                                path: PathBuf::from(name),
                                source,
                            });
                        }
                    }
                }
                Ok(moved)
            }
        }
    }
}
