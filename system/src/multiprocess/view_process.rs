//! The view process of a run with a view (`learnpnp-view`, started by the
//! supervisor): read-only, off the learners' path. It reads every agent's
//! live feed ([`crate::ipc::feed`]: each record checked, what is refused or
//! lost counted) and the heartbeats, and hands to its sink (the view's
//! server) the agents' records and, once a second, every process's health
//! and the latency percentiles of the histograms the processes write into
//! the run's directory. It takes nothing from the agents or the simulator
//! but what they publish, and sends them nothing; killed, it loses only what
//! the view shows, and a restarted one carries its predecessor's counts on.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant, SystemTime};

use learnpnp_feed::{FeedEvent, FeedSink, LatencySummary, ProcessHealth};
use serde::{Deserialize, Serialize};

use super::agent::keeper::roster_compute_histogram;
use super::supervisor::ViewConfig;
use super::{ProcessError, RunContext};
use crate::ipc::convert::read_heartbeat;
use crate::ipc::feed::{FeedCounts, FeedReader};
use crate::ipc::protocol::{Pulse, Role, Roster};
use crate::ipc::services::{ViewPorts, node, receive};
use crate::latency::Latency;

/// The view's counts in the run's directory, rewritten every second and at
/// the end; the supervisor's summary reports them.
pub const VIEW_COUNTS_FILE: &str = "view.json";

/// How often the feeds are read: the feed services' buffers hold far more
/// than the records of this long.
const POLL: Duration = Duration::from_millis(20);

/// How often health, latency and the counts are published.
const SUMMARY_EVERY: Duration = Duration::from_secs(1);

/// A process silent for this long is shown as not alive (ten heartbeats).
const SILENT: Duration = Duration::from_secs(1);

/// What a view counted over the run (its restarts included).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ViewCounts {
    /// The agents' feeds: records passed on, refused, lost.
    pub feed: FeedCounts,
    /// Records the view's server dropped (a client or recording too slow).
    pub served_dropped: u64,
    /// Heartbeats that did not read (a foreign process's).
    pub heartbeats_rejected: u64,
}

impl ViewCounts {
    /// Feed records lost anywhere: in shared memory or in the server.
    pub fn dropped(&self) -> u64 {
        self.feed.dropped + self.served_dropped
    }

    /// Reads the counts a view wrote in `work_dir` (none: zero).
    pub fn load(work_dir: &Path) -> Self {
        std::fs::read(work_dir.join(VIEW_COUNTS_FILE))
            .ok()
            .and_then(|bytes| serde_json::from_slice(&bytes).ok())
            .unwrap_or_default()
    }

    /// The sum of two counts.
    pub fn add(&self, other: &ViewCounts) -> ViewCounts {
        ViewCounts {
            feed: FeedCounts {
                received: self.feed.received + other.feed.received,
                rejected: self.feed.rejected.plus(&other.feed.rejected),
                dropped: self.feed.dropped + other.feed.dropped,
            },
            served_dropped: self.served_dropped + other.served_dropped,
            heartbeats_rejected: self.heartbeats_rejected + other.heartbeats_rejected,
        }
    }
}

/// What the view knows of one process from its heartbeats.
#[derive(Debug)]
struct Seen {
    pulse: Pulse,
    heard: Instant,
    /// Process ids seen in this role (a new one is a restart).
    pids: Vec<u32>,
}

/// Runs the view of `context`'s run into `sink` until `stop` is set;
/// `sink_dropped` says how many records the sink has dropped. Returns the
/// counts (its predecessors' included), also written to [`VIEW_COUNTS_FILE`].
pub fn run(
    context: &RunContext,
    sink: &dyn FeedSink,
    sink_dropped: &dyn Fn() -> u64,
    stop: &AtomicBool,
) -> Result<ViewCounts, ProcessError> {
    let spec = context.load_spec()?;
    let roster = Roster::of(&spec.domain);
    let namespace = context.namespace()?;
    let node = node(&namespace, "view")?;
    let mut reader = FeedReader::open(&node, roster.agents(), context.run_id, context.run)?;
    let ports = ViewPorts::open(&node)?;
    let before = ViewCounts::load(&context.work_dir);
    let mut seen: BTreeMap<Role, Seen> = BTreeMap::new();
    let mut heartbeats_rejected = 0;
    let mut last_summary: Option<Instant> = None;
    let mut latency = LatencyFiles::default();
    loop {
        let stopping = stop.load(Ordering::Relaxed);
        // The agents' records go on as they encoded them (checked, not encoded again).
        reader.read_records(|record| sink.publish_payload(record.kind, record.payload))?;
        while let Some(reading) = receive(&ports.heartbeats, |m| read_heartbeat(m, context.run_id, roster))? {
            match reading {
                Ok(pulse) => {
                    let entry = seen.entry(pulse.role).or_insert_with(|| Seen {
                        pulse,
                        heard: Instant::now(),
                        pids: Vec::new(),
                    });
                    if !entry.pids.contains(&pulse.pid) {
                        entry.pids.push(pulse.pid);
                    }
                    entry.pulse = pulse;
                    entry.heard = Instant::now();
                }
                Err(_) => heartbeats_rejected += 1,
            }
        }
        let counts = before.add(&ViewCounts {
            feed: reader.counts().clone(),
            served_dropped: sink_dropped(),
            heartbeats_rejected,
        });
        if stopping || last_summary.is_none_or(|t| t.elapsed() >= SUMMARY_EVERY) {
            last_summary = Some(Instant::now());
            for (role, process) in &seen {
                sink.publish(&FeedEvent::Health(health(*role, process)));
            }
            sink.publish(&FeedEvent::Health(ProcessHealth {
                process: "view".into(),
                pid: Some(std::process::id()),
                alive: true,
                heartbeat_age_ms: 0,
                restarts: 0,
                rejections: counts.feed.rejected.total() + counts.heartbeats_rejected,
            }));
            for summary in latency.summaries(&context.work_dir, roster) {
                sink.publish(&FeedEvent::Latency(summary.clone()));
            }
            write_counts(&context.work_dir, &counts)?;
        }
        if stopping {
            return Ok(counts);
        }
        std::thread::sleep(POLL);
    }
}

/// One process's health from its last heartbeat.
fn health(role: Role, seen: &Seen) -> ProcessHealth {
    let age = seen.heard.elapsed();
    ProcessHealth {
        process: role.to_string(),
        pid: Some(seen.pulse.pid),
        alive: age < SILENT,
        heartbeat_age_ms: u64::try_from(age.as_millis()).unwrap_or(u64::MAX),
        restarts: u32::try_from(seen.pids.len().saturating_sub(1)).unwrap_or(u32::MAX),
        rejections: seen.pulse.rejected.total(),
    }
}

/// Writes `counts` into `work_dir` (atomically).
fn write_counts(work_dir: &Path, counts: &ViewCounts) -> Result<(), ProcessError> {
    let path = work_dir.join(VIEW_COUNTS_FILE);
    let json = serde_json::to_vec(counts).unwrap_or_default();
    atomic_file::write_atomic(&path, &json).map_err(|source| ProcessError::Io { path, source })
}

/// A histogram file as last seen: its path, length and modification time.
type FileStamp = (PathBuf, u64, Option<SystemTime>);

/// The latency summaries of a work directory, each histogram read again only
/// when one of its files changes (the processes rewrite theirs every few
/// seconds, each on its own; decoding every file whenever one changed was
/// most of an idle view's work).
#[derive(Debug, Default)]
struct LatencyFiles {
    /// Each histogram's files when last read, and its summary (`None`: none of its files read).
    read: BTreeMap<String, (Vec<FileStamp>, Option<LatencySummary>)>,
    summaries: Vec<LatencySummary>,
}

impl LatencyFiles {
    /// The summaries of `work_dir`'s histograms as they are now, in the
    /// histograms' name order.
    fn summaries(&mut self, work_dir: &Path, roster: Roster) -> &[LatencySummary] {
        let mut now: BTreeMap<String, Vec<FileStamp>> = BTreeMap::new();
        for entry in std::fs::read_dir(work_dir).into_iter().flatten().flatten() {
            let path = entry.path();
            let (Some(name), Ok(meta)) = (histogram_name(&path), entry.metadata()) else {
                continue;
            };
            now.entry(name)
                .or_default()
                .push((path, meta.len(), meta.modified().ok()));
        }
        let before = self.read.len();
        self.read.retain(|name, _| now.contains_key(name));
        let mut changed = self.read.len() != before;
        for (name, mut stamps) in now {
            stamps.sort();
            if self.read.get(&name).is_some_and(|(read, _)| *read == stamps) {
                continue;
            }
            let summary = latency_summary(&name, stamps.iter().map(|(path, ..)| path.as_path()), roster);
            self.read.insert(name, (stamps, summary));
            changed = true;
        }
        if changed {
            self.summaries = self.read.values().filter_map(|(_, summary)| summary.clone()).collect();
        }
        &self.summaries
    }
}

/// The latency percentiles of histogram `name` from its files `paths`
/// (`<name>.<pid>.hdr`, each incarnation of a process writing its own:
/// merged), filed under the process that writes it, named as its health is
/// (an agent's compute time under the agent, the rest under the run's host);
/// a file that does not read is passed over, and a histogram none of whose
/// files reads has none.
fn latency_summary<'a>(name: &str, paths: impl Iterator<Item = &'a Path>, roster: Roster) -> Option<LatencySummary> {
    let mut merged: Option<Latency> = None;
    for path in paths {
        let Ok(bytes) = std::fs::read(path) else {
            continue;
        };
        let Ok(histogram) = Latency::from_bytes(name, &bytes) else {
            continue;
        };
        match &mut merged {
            None => merged = Some(histogram),
            // Histograms of one name have the same bounds; one that does not merge is passed over.
            Some(total) => {
                let _ = total.merge(&histogram);
            }
        }
    }
    let histogram = merged?;
    let p = histogram.percentiles();
    let agent = (0..roster.agents()).find(|&k| roster_compute_histogram(roster, k) == name);
    let (process, measure) = match agent {
        Some(k) => (roster.agent(k).to_string(), "compute".to_string()),
        None => (roster.host().to_string(), name.to_string()),
    };
    Some(LatencySummary {
        process,
        measure,
        count: histogram.count(),
        p50_us: p.p50 as u64,
        p90_us: p.p90 as u64,
        p99_us: p.p99 as u64,
        max_us: p.max as u64,
    })
}

/// The histogram's name of a file `<name>.<pid>.hdr`.
fn histogram_name(path: &Path) -> Option<String> {
    let file = path.file_name()?.to_str()?;
    let stem = file.strip_suffix(".hdr")?;
    let (name, pid) = stem.rsplit_once('.')?;
    pid.parse::<u32>().ok().map(|_| name.to_string())
}

/// The view process's command line beyond the run's for run `run` of `view`.
pub(crate) fn view_args(view: &ViewConfig, run: usize) -> Vec<std::ffi::OsString> {
    let mut args = Vec::new();
    if let Some(address) = view.address {
        args.push("--listen".into());
        args.push(address.to_string().into());
    }
    if let Some(file) = view.recording(run) {
        args.push("--record-mcap".into());
        args.push(file.into());
    }
    if let Some(address) = view.pnp_monitor {
        args.push("--pnp-monitor".into());
        args.push(address.to_string().into());
    }
    if let Some(file) = &view.jsonl {
        args.push("--jsonl".into());
        args.push(file.clone().into());
    }
    args
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histogram_files_are_named_by_their_histogram() {
        assert_eq!(
            histogram_name(Path::new("/r/compute-keeper1.4242.hdr")).as_deref(),
            Some("compute-keeper1")
        );
        assert_eq!(
            histogram_name(Path::new("/r/roundtrip.17.hdr")).as_deref(),
            Some("roundtrip")
        );
        assert_eq!(histogram_name(Path::new("/r/view.json")), None);
        assert_eq!(histogram_name(Path::new("/r/a.b.hdr")), None);
    }

    #[test]
    fn latency_is_filed_under_the_process_named_as_its_health_is() {
        let dir = std::env::temp_dir().join(format!("learnpnp-view-latency-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (file, name) in [
            ("compute-keeper2.7.hdr", "compute-keeper2"),
            ("roundtrip.8.hdr", "roundtrip"),
        ] {
            let mut histogram = Latency::new(name);
            histogram.record(Duration::from_micros(20));
            std::fs::write(dir.join(file), histogram.to_bytes().unwrap()).unwrap();
        }
        let mut filed: Vec<(String, String)> = LatencyFiles::default()
            .summaries(&dir, Roster::Keepaway)
            .iter()
            .map(|s| (s.process.clone(), s.measure.clone()))
            .collect();
        filed.sort();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(
            filed,
            [
                (Role::Keeper(1).to_string(), "compute".to_string()),
                (Role::Simulator.to_string(), "roundtrip".to_string()),
            ]
        );
    }

    #[test]
    fn a_histogram_is_read_again_only_when_one_of_its_files_changes() {
        let dir = std::env::temp_dir().join(format!("learnpnp-view-latency-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let write = |file: &str, micros: &[u64]| {
            let mut histogram = Latency::new(file.split('.').next().unwrap());
            for &us in micros {
                histogram.record(Duration::from_micros(us));
            }
            std::fs::write(dir.join(file), histogram.to_bytes().unwrap()).unwrap();
        };
        let counts = |files: &mut LatencyFiles| -> Vec<(String, u64)> {
            let summaries = files.summaries(&dir, Roster::Keepaway);
            summaries.iter().map(|s| (s.measure.clone(), s.count)).collect()
        };
        let mut files = LatencyFiles::default();
        assert!(counts(&mut files).is_empty());
        write("roundtrip.8.hdr", &[20]);
        write("floor.8.hdr", &[1, 2]);
        assert_eq!(counts(&mut files), [("floor".into(), 2), ("roundtrip".into(), 1)]);
        // The floor's file spoilt but left as it was seen (length and time):
        // it is not read again, so its summary stays; the round trip's
        // rewritten file is read.
        let floor = dir.join("floor.8.hdr");
        let seen = std::fs::metadata(&floor).unwrap();
        std::fs::write(&floor, vec![0xff; seen.len() as usize]).unwrap();
        std::fs::File::options()
            .write(true)
            .open(&floor)
            .unwrap()
            .set_modified(seen.modified().unwrap())
            .unwrap();
        write("roundtrip.8.hdr", &[20, 30, 40]);
        assert_eq!(counts(&mut files), [("floor".into(), 2), ("roundtrip".into(), 3)]);
        // A second incarnation's file is merged in; a removed file's histogram goes.
        write("roundtrip.9.hdr", &[50]);
        std::fs::remove_file(&floor).unwrap();
        assert_eq!(counts(&mut files), [("roundtrip".into(), 4)]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_restarted_view_carries_the_counts_on() {
        let mut a = ViewCounts::default();
        a.feed.received = 5;
        a.feed.rejected.content = 2;
        a.served_dropped = 1;
        let mut b = ViewCounts::default();
        b.feed.received = 3;
        b.feed.dropped = 4;
        b.feed.rejected.content = 1;
        let sum = a.add(&b);
        assert_eq!(sum.feed.received, 8);
        assert_eq!(sum.feed.rejected.content, 3);
        assert_eq!(sum.dropped(), 5);
    }
}
