//! A journal of whole episodes: one JSON line per episode. The simulator's
//! (`super::host::simulator::JournalEntry`: its mode, what it earned, the simulator's random state
//! after it, and the counters) lets a simulator that was killed be restarted
//! from the last episode boundary: it replays the journaled outcomes through
//! the protocol (rebuilding the run's results without playing them again),
//! restores the random state, and plays on. A world's agent, which runs the
//! protocol itself, journals its episodes the same way
//! (`super::agent::world`).
//!
//! Lines are appended and handed to the operating system (no `fsync`: they
//! outlive the process, which is what a restart needs), each at once (the
//! simulator's) or gathered for a few milliseconds (a world agent's, whose
//! episodes may last a few cycles: a write each would cost as much as the
//! episode). A kill loses what was not handed over yet: the restarted process
//! plays those episodes again. A kill in the middle of a line leaves a torn
//! last line, which reading ignores.

use std::fs::File;
use std::io::{self, BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use serde::Serialize;

use learnpnp::domains::TaskError;
use learnpnp::learning::EpisodeMode;

/// Why the journal cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum JournalError {
    /// Reading or writing failed.
    #[error("{path}: {source}")]
    Io {
        /// The journal.
        path: PathBuf,
        /// The error.
        source: io::Error,
    },
    /// A line other than the last does not read.
    #[error("{path}, line {line}: not a journal entry: {detail}")]
    Corrupt {
        /// The journal.
        path: PathBuf,
        /// The line (1-based).
        line: usize,
        /// Why.
        detail: String,
    },
}

/// Checks that a replayed journal entry of mode `journaled` is the episode
/// the protocol has due (of mode `due`).
pub(crate) fn follows_protocol(journaled: EpisodeMode, due: EpisodeMode) -> Result<(), TaskError> {
    if journaled == due {
        Ok(())
    } else {
        Err(TaskError::Invalid(format!(
            "the journal does not follow the protocol: a {journaled:?} episode where a {due:?} one is due"
        )))
    }
}

/// Reads every whole entry of the journal at `path` (none if there is no journal).
pub(crate) fn read<E: serde::de::DeserializeOwned>(path: &Path) -> Result<Vec<E>, JournalError> {
    let io = |source| JournalError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = match File::open(path) {
        Ok(file) => file,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io(e)),
    };
    let lines: Vec<String> = BufReader::new(file).lines().collect::<Result<_, _>>().map_err(io)?;
    let mut entries = Vec::with_capacity(lines.len());
    for (i, line) in lines.iter().enumerate() {
        match serde_json::from_str(line) {
            Ok(entry) => entries.push(entry),
            // A kill in the middle of the last line tears it.
            Err(_) if i + 1 == lines.len() => break,
            Err(e) => {
                return Err(JournalError::Corrupt {
                    path: path.to_path_buf(),
                    line: i + 1,
                    detail: e.to_string(),
                });
            }
        }
    }
    Ok(entries)
}

/// Appends entries to a journal.
#[derive(Debug)]
pub(crate) struct Journal {
    path: PathBuf,
    file: File,
    /// Lines appended, not yet handed to the operating system.
    pending: Vec<u8>,
    /// How long lines may wait in `pending`.
    gather_for: Duration,
    last_write: Instant,
}

impl Journal {
    /// Opens the journal at `path`: a fresh one (truncated) or, to resume, the
    /// one there is with `keep` whole entries (a torn last line is cut off).
    /// Appended lines are written when `gather_for` has passed since the last
    /// write (`Duration::ZERO`: each at once), and on [`Journal::flush`].
    pub(crate) fn open<E: Serialize>(path: &Path, keep: &[E], gather_for: Duration) -> Result<Self, JournalError> {
        let io = |source| JournalError::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut file = File::create(path).map_err(io)?;
        let mut lines = Vec::new();
        for entry in keep {
            push_line(&mut lines, entry).map_err(io)?;
        }
        file.write_all(&lines).map_err(io)?;
        Ok(Journal {
            path: path.to_path_buf(),
            file,
            pending: Vec::new(),
            gather_for,
            last_write: Instant::now(),
        })
    }

    /// Appends `entry`, written now if the journal's gathering time has passed.
    pub(crate) fn append<E: Serialize>(&mut self, entry: &E) -> Result<(), JournalError> {
        push_line(&mut self.pending, entry).map_err(|source| JournalError::Io {
            path: self.path.clone(),
            source,
        })?;
        self.flush_if_due()
    }

    /// Writes the lines waiting if the gathering time has passed.
    pub(crate) fn flush_if_due(&mut self) -> Result<(), JournalError> {
        if self.last_write.elapsed() >= self.gather_for {
            self.flush()
        } else {
            Ok(())
        }
    }

    /// Writes the lines waiting now. Lines that cannot be written (a full
    /// disk) are dropped with the error: a restart plays their episodes again.
    pub fn flush(&mut self) -> Result<(), JournalError> {
        self.last_write = Instant::now();
        if self.pending.is_empty() {
            return Ok(());
        }
        let written = self.file.write_all(&self.pending);
        self.pending.clear();
        written.map_err(|source| JournalError::Io {
            path: self.path.clone(),
            source,
        })
    }
}

impl Drop for Journal {
    fn drop(&mut self) {
        // Best effort: an error here was already counted or cannot be.
        let _ = self.flush();
    }
}

/// Appends `entry` to `lines` as one JSON line.
fn push_line<E: Serialize>(lines: &mut Vec<u8>, entry: &E) -> io::Result<()> {
    serde_json::to_writer(&mut *lines, entry).map_err(io::Error::other)?;
    lines.push(b'\n');
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::multiprocess::host::simulator::{JOURNAL_FILE, JournalEntry, SimTotals};
    use learnpnp::domains::EpisodeOutcome;
    use learnpnp::rng::seeded;

    fn entry(i: u64) -> JournalEntry {
        JournalEntry {
            mode: EpisodeMode::Learn,
            outcome: EpisodeOutcome {
                ret: 12.300000000000002,
                actions: 123,
                steps: 123,
                exploratory: i.is_multiple_of(2),
            },
            rng: seeded(i),
            totals: SimTotals {
                episode_seq: i,
                cycles: 123 * i,
                ..SimTotals::default()
            },
        }
    }

    #[test]
    fn entries_round_trip_and_a_torn_last_line_is_ignored() {
        let dir = std::env::temp_dir().join(format!("learnpnp-journal-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(JOURNAL_FILE);
        let mut journal = Journal::open::<JournalEntry>(&path, &[], Duration::ZERO).unwrap();
        for i in 1..=3 {
            journal.append(&entry(i)).unwrap();
        }
        drop(journal);
        let mut text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(read::<JournalEntry>(&path).unwrap(), vec![entry(1), entry(2), entry(3)]);
        text.push_str("{\"mode\":\"Le");
        std::fs::write(&path, &text).unwrap();
        let read_back = read::<JournalEntry>(&path).unwrap();
        assert_eq!(read_back.len(), 3, "the torn line is ignored");
        let mut journal = Journal::open(&path, &read_back, Duration::ZERO).unwrap();
        journal.append(&entry(4)).unwrap();
        assert_eq!(
            read::<JournalEntry>(&path).unwrap().len(),
            4,
            "and cut off when the journal is reopened"
        );
        std::fs::write(&path, format!("garbage\n{text}")).unwrap();
        assert!(matches!(
            read::<JournalEntry>(&path),
            Err(JournalError::Corrupt { line: 1, .. })
        ));
        assert!(read::<JournalEntry>(&dir.join("none")).unwrap().is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
