//! An agent's checkpoints written off its decision loop. Each checkpoint is
//! several durable writes (the previous values kept as `.prev`, the new
//! values, the histograms: each file and its directory synced), milliseconds
//! in all, which in lock-step the whole run would wait for. The agent hands
//! them to a writer thread and plays on.
//!
//! A checkpoint handed over while another waits replaces it (the newer one
//! holds all the older one would have); the one being written is finished
//! first. Periodic checkpoints are written at most once per
//! [`CHECKPOINT_SPACING`](crate::multiprocess::agent::background_save::CHECKPOINT_SPACING): in a world whose episodes take milliseconds,
//! "every 100 learning episodes" would otherwise mean hundreds of durable
//! writes a second, each taking the machine's cores from the run.
//! [`BackgroundSave::flush`](crate::multiprocess::agent::background_save::BackgroundSave::flush) writes what waits at once and returns when it is
//! written: an agent flushes after its first checkpoint (a restart must always
//! find one), on the supervisor's order to checkpoint, and at its end;
//! dropping the writer flushes too. A kill loses the learning since the last
//! checkpoint written, at most the spacing and the episodes between two
//! checkpoints; the last good checkpoint stays.

use std::io::Write as _;
use std::path::PathBuf;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use learnpnp::learning::persist::{self, SavedValues};

/// The least time between two periodic checkpoints' writes.
pub const CHECKPOINT_SPACING: Duration = Duration::from_secs(1);

/// What one checkpoint writes.
#[derive(Debug, Default)]
pub(crate) struct Checkpoint {
    /// The learner's values and their file (none: an agent that does not learn).
    pub values: Option<(PathBuf, SavedValues)>,
    /// Other files written whole (histograms) and their bytes.
    pub(crate) files: Vec<(PathBuf, Vec<u8>)>,
}

/// The writer thread and the agent's handle on it.
#[derive(Debug)]
pub struct BackgroundSave {
    shared: Arc<Shared>,
    spacing: Duration,
    thread: Option<JoinHandle<()>>,
}

#[derive(Debug, Default)]
struct Shared {
    state: Mutex<State>,
    /// Signalled when a checkpoint is handed over, one is written, or the
    /// writer is closed.
    changed: Condvar,
    written: AtomicU64,
    failed: AtomicU64,
}

#[derive(Debug, Default)]
struct State {
    waiting: Option<Checkpoint>,
    writing: bool,
    /// A flush waits: what waits is written now, whatever the spacing.
    urgent: bool,
    /// When the last checkpoint was written.
    last_written: Option<Instant>,
    closed: bool,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, State> {
        // The writer never panics while holding the lock; a poisoned lock
        // still holds a consistent state.
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// Writes a line to the process's log (its stderr), ignoring a failed write.
fn report(line: &str) {
    let _ = writeln!(std::io::stderr(), "{line}");
}

impl BackgroundSave {
    /// Starts the writer thread, which writes periodic checkpoints at
    /// least `spacing` apart.
    pub fn start(spacing: Duration) -> std::io::Result<Self> {
        let shared = Arc::new(Shared::default());
        let writer = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name("checkpoint-writer".into())
            .spawn(move || write_loop(&writer, spacing))?;
        Ok(BackgroundSave {
            shared,
            spacing,
            thread: Some(thread),
        })
    }

    /// Hands a checkpoint over, replacing one still waiting.
    pub(crate) fn submit(&self, checkpoint: Checkpoint) {
        self.shared.lock().waiting = Some(checkpoint);
        self.shared.changed.notify_all();
    }

    /// Whether a periodic checkpoint handed over now would be written at
    /// once: none waits or is being written, and the spacing has passed
    /// since the last one was written. An agent takes a periodic checkpoint
    /// only then: one taken earlier would only be replaced by a newer one
    /// before it is written, and taking one (the values copied, the
    /// histograms serialised) costs its decision loop.
    pub fn due(&self) -> bool {
        let state = self.shared.lock();
        state.waiting.is_none() && !state.writing && state.last_written.is_none_or(|t| t.elapsed() >= self.spacing)
    }

    /// Writes what waits now and returns when every checkpoint handed over
    /// is written (or has failed).
    pub fn flush(&self) {
        let mut state = self.shared.lock();
        state.urgent = true;
        self.shared.changed.notify_all();
        while state.waiting.is_some() || state.writing {
            state = self.shared.changed.wait(state).unwrap_or_else(PoisonError::into_inner);
        }
        state.urgent = false;
    }

    /// Value files written so far.
    pub(crate) fn written(&self) -> u64 {
        self.shared.written.load(Ordering::Relaxed)
    }

    /// Value files that could not be written (the previous one was kept).
    pub fn failed(&self) -> u64 {
        self.shared.failed.load(Ordering::Relaxed)
    }
}

impl Drop for BackgroundSave {
    fn drop(&mut self) {
        self.shared.lock().closed = true;
        self.shared.changed.notify_all();
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The writer thread: writes what is handed over (periodic checkpoints at
/// least `spacing` apart) until closed with nothing waiting.
fn write_loop(shared: &Shared, spacing: Duration) {
    loop {
        let checkpoint = {
            let mut state = shared.lock();
            loop {
                let due = state.last_written.map(|t| t + spacing);
                let early = due.and_then(|due| due.checked_duration_since(Instant::now()));
                match (&state.waiting, early) {
                    (Some(_), Some(wait)) if !state.urgent && !state.closed && !wait.is_zero() => {
                        state = shared
                            .changed
                            .wait_timeout(state, wait)
                            .unwrap_or_else(PoisonError::into_inner)
                            .0;
                    }
                    (Some(_), _) => {
                        state.writing = true;
                        break state.waiting.take();
                    }
                    (None, _) if state.closed => return,
                    (None, _) => state = shared.changed.wait(state).unwrap_or_else(PoisonError::into_inner),
                }
            }
        };
        if let Some(checkpoint) = checkpoint {
            write(shared, &checkpoint);
        }
        let mut state = shared.lock();
        state.last_written = Some(Instant::now());
        state.writing = false;
        drop(state);
        shared.changed.notify_all();
    }
}

/// Writes one checkpoint; a failure is reported and counted, the previous
/// files stay.
fn write(shared: &Shared, checkpoint: &Checkpoint) {
    if let Some((path, values)) = &checkpoint.values {
        match persist::save(path, values) {
            Ok(()) => {
                shared.written.fetch_add(1, Ordering::Relaxed);
            }
            Err(e) => {
                shared.failed.fetch_add(1, Ordering::Relaxed);
                report(&format!("error: checkpoint not written, the previous one is kept: {e}"));
            }
        }
    }
    for (path, bytes) in &checkpoint.files {
        if let Err(e) = atomic_file::write_atomic(path, bytes) {
            report(&format!("error: {}: {e}", path.display()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("learnpnp-background-save-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn histogram(path: &std::path::Path, byte: u8) -> Checkpoint {
        Checkpoint {
            values: None,
            files: vec![(path.to_path_buf(), vec![byte; 64])],
        }
    }

    #[test]
    fn a_flush_writes_the_last_checkpoint_handed_over_at_once() {
        let dir = scratch("flush");
        let saver = BackgroundSave::start(Duration::from_secs(3600)).unwrap();
        let file = dir.join("histogram");
        for round in 0..50u8 {
            saver.submit(histogram(&file, round));
        }
        saver.flush();
        assert_eq!(std::fs::read(&file).unwrap(), vec![49u8; 64]);
        // Spaced an hour apart: the next one waits, until the flush.
        saver.submit(histogram(&file, 50));
        std::thread::sleep(Duration::from_millis(50));
        assert_eq!(std::fs::read(&file).unwrap(), vec![49u8; 64]);
        saver.flush();
        assert_eq!(std::fs::read(&file).unwrap(), vec![50u8; 64]);
        assert_eq!((saver.written(), saver.failed()), (0, 0));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn dropping_the_writer_writes_the_newest_checkpoint_waiting() {
        let dir = scratch("drop");
        let saver = BackgroundSave::start(Duration::from_secs(3600)).unwrap();
        let file = dir.join("histogram");
        saver.submit(histogram(&file, 1));
        saver.flush();
        // Replaced before it is written (the spacing holds it back).
        saver.submit(histogram(&dir.join("replaced"), 2));
        saver.submit(histogram(&file, 3));
        drop(saver);
        assert_eq!(std::fs::read(&file).unwrap(), vec![3u8; 64]);
        assert!(!dir.join("replaced").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_periodic_checkpoint_is_due_only_when_it_would_be_written_at_once() {
        let dir = scratch("due");
        let file = dir.join("histogram");
        let spaced = BackgroundSave::start(Duration::from_secs(3600)).unwrap();
        assert!(spaced.due(), "nothing written yet");
        spaced.submit(histogram(&file, 1));
        spaced.flush();
        assert!(!spaced.due(), "written less than the spacing ago");
        spaced.submit(histogram(&file, 2));
        assert!(!spaced.due(), "one waits");
        drop(spaced);
        let unspaced = BackgroundSave::start(Duration::ZERO).unwrap();
        unspaced.submit(histogram(&file, 3));
        unspaced.flush();
        assert!(unspaced.due());
        drop(unspaced);
        assert_eq!(std::fs::read(&file).unwrap(), vec![3u8; 64]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
