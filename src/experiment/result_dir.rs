//! Result directories: a set of files that is published whole, by one process
//! at a time.
//!
//! Every command that writes results (CSV, JSON, SVG, value tables, latency
//! histograms) writes them through this module. The guarantees:
//!
//! - **Checked before any work.** [`ResultDir::open`](crate::experiment::result_dir::ResultDir::open) refuses a target that is
//!   an existing file, a directory that holds something other than results, or
//!   a place where nothing can be written (the parent is created if missing,
//!   then a lock file is created in it), so a long computation never ends in
//!   "cannot write".
//! - **One writer.** `open` takes an advisory lock (`flock`, through
//!   [`File::try_lock`](std::fs::File::try_lock)) on the hidden file `.NAME.lock` beside the target
//!   `NAME`, held until the [`ResultDir`](crate::experiment::result_dir::ResultDir) is dropped. A second process that
//!   opens the same target is refused at once with [`ResultDirError::Busy`](crate::experiment::result_dir::ResultDirError::Busy),
//!   naming the holder's process id. The lock file is removed on drop.
//! - **Whole or nothing.** A [`ResultWriter`](crate::experiment::result_dir::ResultWriter) writes every file into a hidden
//!   staging directory `.NAME.staging-PID-N` beside the target. [`ResultWriter::commit`](crate::experiment::result_dir::ResultWriter::commit)
//!   syncs the files, writes `MANIFEST` last, and publishes the staging
//!   directory in one step: on Linux the two directories are exchanged
//!   atomically (`renameat2(RENAME_EXCHANGE)`) and the old results removed; a
//!   new target is simply renamed into place. Where the exchange is not
//!   available, the old directory is first renamed aside (`.NAME.old-PID-N`),
//!   so a reader may briefly find no directory, never a mixed one. A kill at any
//!   point leaves the target holding either the previous set or the new one,
//!   complete, and at worst a hidden staging directory beside it.
//! - **Clean-up.** Under the lock, `open` removes the staging directories
//!   that dead writers left for this target, and restores the previous results
//!   if a writer died between the two renames of the fallback.
//! - **Partial results.** A set may be committed as partial
//!   ([`Progress`](crate::experiment::result_dir::Progress): completed and planned runs); the manifest then says
//!   `"complete": false`, and [`ResultDir::contents`](crate::experiment::result_dir::ResultDir::contents) reads it back (for
//!   `--resume`). Readers that need finished results check
//!   [`Manifest::complete`](crate::experiment::result_dir::Manifest::complete).
//!
//! - **Work files.** [`ResultWriter::scratch_dir`](crate::experiment::result_dir::ResultWriter::scratch_dir) gives a directory inside
//!   the set for files written while the work runs (logs, state of child
//!   processes): published with the set, cleaned with the staging directory
//!   if the work never completes.
//!
//! ```no_run
//! use learnpnp::experiment::result_dir::{Progress, ResultDir};
//!
//! let mut dir = ResultDir::open("out/run")?;          // checked and locked
//! let mut files = dir.writer()?;                      // a fresh staging directory
//! files.add_text("curve.csv", "episode,mean\n0,1.5\n")?;
//! let svg = files.path_for("curve.svg")?;             // for libraries that write files
//! std::fs::write(&svg, "<svg/>").map_err(|e| e.to_string())?;
//! files.commit(Progress::complete(20))?;              // published whole
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fs::{self, File, OpenOptions, TryLockError};
use std::io::{self, Read, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use serde::{Deserialize, Serialize};

/// The file written last into every result directory: what it holds and
/// whether it is complete.
pub(crate) const MANIFEST: &str = "manifest.json";

/// The format version of [`MANIFEST`] this build writes and reads.
pub(crate) const MANIFEST_FORMAT: u32 = 1;

/// A file of results written by versions without a manifest; a directory
/// holding it (and no manifest) is taken as their results and may be replaced.
pub(crate) const LEGACY_MARKER: &str = "summary.json";

/// What a result directory's `MANIFEST` says.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Manifest {
    /// `MANIFEST_FORMAT` when written.
    pub format: u32,
    /// Whether every planned run completed (false for an interrupted run).
    pub complete: bool,
    /// Runs whose results the directory holds.
    pub runs_completed: u64,
    /// Runs the experiment was to make.
    pub runs_planned: u64,
    /// Every file of the set (the manifest aside), in the order written.
    pub files: Vec<String>,
    /// Directories written during the work ([`ResultWriter::scratch_dir`]),
    /// published with the set; their files are not listed one by one.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(crate) dirs: Vec<String>,
}

/// How far the work whose results are committed went.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Progress {
    /// Runs completed.
    pub completed: u64,
    /// Runs planned.
    pub planned: u64,
}

impl Progress {
    /// Every one of `runs` runs completed.
    pub fn complete(runs: u64) -> Self {
        Progress {
            completed: runs,
            planned: runs,
        }
    }

    /// Whether every planned run completed.
    pub(crate) fn is_complete(self) -> bool {
        self.completed >= self.planned
    }
}

/// What a target directory holds now.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Contents {
    /// Nothing yet (missing or empty).
    Empty,
    /// A result set, complete or partial.
    Results(Manifest),
    /// Results of a version that wrote no manifest (a `LEGACY_MARKER` file).
    Legacy,
}

/// Why a result directory cannot be opened, written or read. Each message
/// starts with the path at fault.
#[derive(Debug, thiserror::Error)]
pub enum ResultDirError {
    /// The target exists and is not a directory.
    #[error("{}: exists and is not a directory; choose another output directory", path.display())]
    NotADirectory {
        /// The target.
        path: PathBuf,
    },
    /// The target is a directory holding something other than results.
    #[error(
        "{}: exists and does not hold learnpnp results (no {MANIFEST} or {LEGACY_MARKER}); \
         choose another output directory, or empty it",
        path.display()
    )]
    Foreign {
        /// The target.
        path: PathBuf,
    },
    /// Another process holds the target's lock.
    #[error(
        "{}: another process{} is writing results there (it holds the lock {}); \
         wait for it to finish or choose another output directory",
        path.display(),
        holder.map(|pid| format!(" (pid {pid})")).unwrap_or_default(),
        lock.display()
    )]
    Busy {
        /// The target.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// The process id the lock file names, if readable.
        holder: Option<u32>,
    },
    /// A file system operation failed.
    #[error("{}: cannot {action}: {error}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What was being done.
        action: &'static str,
        /// What the operating system said.
        error: io::Error,
    },
    /// A file name that cannot be part of a result set.
    #[error("{}: '{name}' cannot be a result file: {reason}", dir.display())]
    BadName {
        /// The target.
        dir: PathBuf,
        /// The name given.
        name: String,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A file announced with [`ResultWriter::path_for`] was never written.
    #[error("{}: the result file '{name}' was never written", dir.display())]
    NotWritten {
        /// The target.
        dir: PathBuf,
        /// The file's name.
        name: String,
    },
    /// The manifest cannot be read or does not describe the directory.
    #[error("{}: {reason}", path.display())]
    BadManifest {
        /// The manifest (or the file it lists).
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

/// Shorthand for an [`ResultDirError::Io`] at `path`.
fn io_error<'a>(path: &'a Path, action: &'static str) -> impl FnOnce(io::Error) -> ResultDirError + 'a {
    move |error| ResultDirError::Io {
        path: path.to_path_buf(),
        action,
        error,
    }
}

/// A target directory, checked and locked for this process (see the module
/// documentation). Dropping it releases the lock.
#[derive(Debug)]
pub struct ResultDir {
    target: PathBuf,
    parent: PathBuf,
    name: String,
    lock_path: PathBuf,
    /// Held (flock) while this value lives.
    lock: File,
}

/// Distinguishes staging directories of one process.
static STAGING_COUNTER: AtomicU64 = AtomicU64::new(0);

/// The kinds of hidden directories a writer of `NAME` leaves beside it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Leftover {
    /// `.NAME.staging-PID-N`: files being written, or old results after an exchange.
    Staging,
    /// `.NAME.old-PID-N`: the previous results, renamed aside by the fallback.
    Old,
}

impl Leftover {
    fn tag(self) -> &'static str {
        match self {
            Leftover::Staging => "staging",
            Leftover::Old => "old",
        }
    }

    /// A fresh name of this kind for target `name`.
    fn fresh(self, name: &str) -> String {
        format!(
            ".{name}.{}-{}-{}",
            self.tag(),
            std::process::id(),
            STAGING_COUNTER.fetch_add(1, Ordering::Relaxed)
        )
    }

    /// The kind of `entry` if it is exactly `.NAME.<tag>-<digits>-<digits>`.
    fn of(entry: &str, name: &str) -> Option<Leftover> {
        let rest = entry.strip_prefix('.')?.strip_prefix(name)?.strip_prefix('.')?;
        [Leftover::Staging, Leftover::Old].into_iter().find(|kind| {
            rest.strip_prefix(kind.tag())
                .and_then(|r| r.strip_prefix('-'))
                .and_then(|r| r.split_once('-'))
                .is_some_and(|(pid, n)| is_digits(pid) && is_digits(n))
        })
    }
}

fn is_digits(s: &str) -> bool {
    !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit())
}

impl ResultDir {
    /// Checks `target` and locks it for this process: creates its parent if
    /// needed, refuses an existing file, a directory holding anything but
    /// results, an unwritable place, or a target another process holds; then
    /// cleans what dead writers left beside it.
    pub fn open(target: impl AsRef<Path>) -> Result<ResultDir, ResultDirError> {
        let target = target.as_ref().to_path_buf();
        let name = match target.components().next_back() {
            Some(Component::Normal(name)) => name.to_string_lossy().into_owned(),
            _ => {
                return Err(ResultDirError::BadName {
                    dir: target.clone(),
                    name: target.display().to_string(),
                    reason: "an output directory must end in a plain name (not '.', '..' or '/')",
                });
            }
        };
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if let Ok(meta) = fs::metadata(&target)
            && !meta.is_dir()
        {
            return Err(ResultDirError::NotADirectory { path: target });
        }
        if let Some(file) = parent.ancestors().find(|a| a.is_file()) {
            return Err(ResultDirError::NotADirectory {
                path: file.to_path_buf(),
            });
        }
        fs::create_dir_all(&parent).map_err(io_error(&parent, "create the directory"))?;
        let lock_path = parent.join(format!(".{name}.lock"));
        let lock = acquire(&target, &lock_path)?;
        let dir = ResultDir {
            target,
            parent,
            name,
            lock_path,
            lock,
        };
        dir.clean_leftovers()?;
        if dir.target.is_dir() {
            check_writable(&dir.target)?;
            let ours = dir.target.join(MANIFEST).exists() || dir.target.join(LEGACY_MARKER).exists();
            if !ours && !is_empty_dir(&dir.target)? {
                return Err(ResultDirError::Foreign {
                    path: dir.target.clone(),
                });
            }
        }
        Ok(dir)
    }

    /// The target directory.
    pub fn path(&self) -> &Path {
        &self.target
    }

    /// What the target holds now (see [`contents`]).
    pub fn contents(&self) -> Result<Contents, ResultDirError> {
        contents(&self.target)
    }

    /// The bytes of result file `name`, which the manifest must list.
    pub fn read(&self, name: &str) -> Result<Vec<u8>, ResultDirError> {
        let listed = match self.contents()? {
            Contents::Results(m) => m.files.iter().any(|f| f == name),
            Contents::Empty | Contents::Legacy => false,
        };
        let path = self.target.join(name);
        if !listed {
            return Err(ResultDirError::BadManifest {
                path,
                reason: format!("not part of the result set (not listed in {MANIFEST})"),
            });
        }
        let mut bytes = Vec::new();
        File::open(&path)
            .and_then(|mut f| f.read_to_end(&mut bytes))
            .map_err(io_error(&path, "read the file"))?;
        Ok(bytes)
    }

    /// A writer of a new result set, in a fresh staging directory. Nothing is
    /// visible at the target until [`ResultWriter::commit`]; a writer dropped
    /// without committing removes its staging directory.
    pub fn writer(&mut self) -> Result<ResultWriter<'_>, ResultDirError> {
        let staging = self.parent.join(Leftover::Staging.fresh(&self.name));
        fs::create_dir(&staging).map_err(io_error(&staging, "create the staging directory"))?;
        Ok(ResultWriter {
            dir: self,
            staging,
            files: Vec::new(),
            dirs: Vec::new(),
            committed: false,
        })
    }

    /// Removes staging directories of dead writers and, if the target is
    /// missing because a writer died between the fallback's renames, puts the
    /// previous results back. Only called under the lock.
    fn clean_leftovers(&self) -> Result<(), ResultDirError> {
        let entries = fs::read_dir(&self.parent).map_err(io_error(&self.parent, "list the directory"))?;
        let mut leftovers: Vec<(Leftover, PathBuf)> = entries
            .filter_map(Result::ok)
            .filter_map(|e| {
                let name = e.file_name().into_string().ok()?;
                Leftover::of(&name, &self.name).map(|kind| (kind, e.path()))
            })
            .collect();
        leftovers.sort();
        for (kind, path) in leftovers {
            if kind == Leftover::Old && !self.target.exists() {
                fs::rename(&path, &self.target).map_err(io_error(&path, "restore the previous results from"))?;
                continue;
            }
            fs::remove_dir_all(&path).map_err(io_error(&path, "remove a stale staging directory"))?;
        }
        Ok(())
    }
}

/// What directory `dir` holds, for readers (no lock is taken: a published
/// set never changes in place): nothing (missing or without a manifest), a
/// result set (its manifest, checked against the files present; readers that
/// need finished results check [`Manifest::complete`]), or results of a
/// version without manifests.
pub fn contents(dir: &Path) -> Result<Contents, ResultDirError> {
    let manifest_path = dir.join(MANIFEST);
    let text = match fs::read_to_string(&manifest_path) {
        Ok(text) => text,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            return Ok(if dir.join(LEGACY_MARKER).is_file() {
                Contents::Legacy
            } else {
                Contents::Empty
            });
        }
        Err(e) => return Err(io_error(&manifest_path, "read the manifest")(e)),
    };
    let manifest: Manifest = serde_json::from_str(&text).map_err(|e| ResultDirError::BadManifest {
        path: manifest_path.clone(),
        reason: format!("not a result manifest: {e}"),
    })?;
    if manifest.format != MANIFEST_FORMAT {
        return Err(ResultDirError::BadManifest {
            path: manifest_path,
            reason: format!(
                "manifest format {} (this build reads format {MANIFEST_FORMAT})",
                manifest.format
            ),
        });
    }
    if let Some(missing) = manifest.dirs.iter().find(|d| !dir.join(d).is_dir()) {
        return Err(ResultDirError::BadManifest {
            path: dir.join(missing),
            reason: format!("listed in {MANIFEST} but missing"),
        });
    }
    if let Some(missing) = manifest.files.iter().find(|f| !dir.join(f).is_file()) {
        return Err(ResultDirError::BadManifest {
            path: dir.join(missing),
            reason: format!("listed in {MANIFEST} but missing"),
        });
    }
    Ok(Contents::Results(manifest))
}

/// The staging directories beside `target`: of the writer at work (its
/// scratch directories hold the files of work in progress), or left by a dead
/// one until the next [`ResultDir::open`]. Most recently modified first.
pub fn staging_dirs(target: &Path) -> Vec<PathBuf> {
    let (Some(Component::Normal(name)), Some(parent)) = (target.components().next_back(), target.parent()) else {
        return Vec::new();
    };
    let name = name.to_string_lossy();
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    let Ok(entries) = fs::read_dir(parent) else {
        return Vec::new();
    };
    let mut found: Vec<(std::time::SystemTime, PathBuf)> = entries
        .filter_map(Result::ok)
        .filter(|e| {
            e.file_name()
                .to_str()
                .is_some_and(|n| Leftover::of(n, &name) == Some(Leftover::Staging))
        })
        .map(|e| {
            let modified = e.metadata().and_then(|m| m.modified()).unwrap_or(std::time::UNIX_EPOCH);
            (modified, e.path())
        })
        .collect();
    found.sort_by_key(|entry| std::cmp::Reverse(entry.0));
    found.into_iter().map(|(_, path)| path).collect()
}

impl Drop for ResultDir {
    fn drop(&mut self) {
        // Remove the lock file while still holding the lock: a process that
        // opened it meanwhile finds the path gone once it gets the lock, and
        // retries on a fresh file (see `acquire`).
        let _ = fs::remove_file(&self.lock_path);
        let _ = self.lock.unlock();
    }
}

/// Creates (or opens) the lock file and locks it without waiting; records
/// this process's id in it.
fn acquire(target: &Path, lock_path: &Path) -> Result<File, ResultDirError> {
    loop {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(lock_path)
            .map_err(io_error(lock_path, "create a lock file"))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => {
                let mut text = String::new();
                let _ = file.read_to_string(&mut text);
                return Err(ResultDirError::Busy {
                    path: target.to_path_buf(),
                    lock: lock_path.to_path_buf(),
                    holder: text.trim().parse().ok(),
                });
            }
            Err(TryLockError::Error(error)) => {
                return Err(io_error(lock_path, "lock")(error));
            }
        }
        // The previous holder may have removed the file after we opened it:
        // our lock is then on a file nobody else will ever see. Try again.
        if !still_at(&file, lock_path) {
            continue;
        }
        file.set_len(0)
            .and_then(|()| writeln!(file, "{}", std::process::id()))
            .map_err(io_error(lock_path, "write the lock file"))?;
        return Ok(file);
    }
}

/// Whether `path` still names the file `file` has open.
fn still_at(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = file;
        path.exists()
    }
}

/// Refuses a directory this process may not modify (publishing renames it).
fn check_writable(dir: &Path) -> Result<(), ResultDirError> {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        let Ok(c_path) = std::ffi::CString::new(dir.as_os_str().as_bytes()) else {
            return Ok(());
        };
        // SAFETY: `c_path` is a valid NUL-terminated string that outlives the call.
        if unsafe { libc::access(c_path.as_ptr(), libc::W_OK) } != 0 {
            return Err(io_error(dir, "write into the directory")(io::Error::last_os_error()));
        }
    }
    #[cfg(not(unix))]
    let _ = dir;
    Ok(())
}

fn is_empty_dir(dir: &Path) -> Result<bool, ResultDirError> {
    Ok(fs::read_dir(dir)
        .map_err(io_error(dir, "list the directory"))?
        .next()
        .is_none())
}

/// Files of one result set being written (see [`ResultDir::writer`]).
#[derive(Debug)]
pub struct ResultWriter<'a> {
    dir: &'a mut ResultDir,
    staging: PathBuf,
    files: Vec<String>,
    dirs: Vec<String>,
    committed: bool,
}

impl ResultWriter<'_> {
    /// Checks a name for the set: a relative path of plain names, none
    /// hidden, not the manifest, not overlapping one given before. Returns
    /// its path in the staging directory, parent directories created.
    fn claim(&mut self, name: &str) -> Result<PathBuf, ResultDirError> {
        let bad = |reason| ResultDirError::BadName {
            dir: self.dir.target.clone(),
            name: name.to_string(),
            reason,
        };
        let path = Path::new(name);
        let plain = path.components().all(|c| match c {
            Component::Normal(part) => !part.to_string_lossy().starts_with('.'),
            _ => false,
        });
        if name.is_empty() || !plain {
            return Err(bad("it must be a relative path of plain, visible names"));
        }
        if name == MANIFEST {
            return Err(bad("the manifest is written by the commit"));
        }
        let taken =
            |other: &String| other == name || Path::new(other).starts_with(path) || path.starts_with(Path::new(other));
        if self.files.iter().chain(&self.dirs).any(taken) {
            return Err(bad("it was already added, or overlaps a file or directory added"));
        }
        let full = self.staging.join(path);
        if let Some(sub) = full.parent() {
            fs::create_dir_all(sub).map_err(io_error(sub, "create the directory"))?;
        }
        Ok(full)
    }

    /// Adds file `name` (e.g. `curve.csv`, or `latency/ping.hgrm`) with these bytes.
    pub fn add_bytes(&mut self, name: &str, bytes: &[u8]) -> Result<(), ResultDirError> {
        let path = self.claim(name)?;
        fs::write(&path, bytes).map_err(io_error(&path, "write"))?;
        self.files.push(name.to_string());
        Ok(())
    }

    /// Adds file `name` with this text.
    pub fn add_text(&mut self, name: &str, text: &str) -> Result<(), ResultDirError> {
        self.add_bytes(name, text.as_bytes())
    }

    /// Reserves file `name` and returns the path to write it to, for libraries
    /// that write files themselves; the file must exist when the set is committed.
    pub fn path_for(&mut self, name: &str) -> Result<PathBuf, ResultDirError> {
        let path = self.claim(name)?;
        self.files.push(name.to_string());
        Ok(path)
    }

    /// Creates directory `name` in the set and returns its path, for files
    /// the work writes as it goes (logs, per-run state of child processes). It
    /// is published with the set and listed in the manifest as a directory;
    /// until then it lives in the hidden staging directory, so the files of
    /// work that never completes are cleaned with it.
    pub fn scratch_dir(&mut self, name: &str) -> Result<PathBuf, ResultDirError> {
        let path = self.claim(name)?;
        fs::create_dir_all(&path).map_err(io_error(&path, "create the directory"))?;
        self.dirs.push(name.to_string());
        Ok(path)
    }

    /// The files added so far, in order.
    pub fn files(&self) -> &[String] {
        &self.files
    }

    /// Syncs every file, writes the manifest last and publishes the set at
    /// the target in one step (see the module documentation).
    pub fn commit(mut self, progress: Progress) -> Result<Manifest, ResultDirError> {
        let manifest = self.seal(progress)?;
        self.publish()?;
        Ok(manifest)
    }

    /// Syncs the files and writes the manifest into the staging directory.
    fn seal(&self, progress: Progress) -> Result<Manifest, ResultDirError> {
        for name in &self.files {
            let path = self.staging.join(name);
            match File::open(&path) {
                Ok(file) => file.sync_all().map_err(io_error(&path, "sync"))?,
                Err(e) if e.kind() == io::ErrorKind::NotFound => {
                    return Err(ResultDirError::NotWritten {
                        dir: self.dir.target.clone(),
                        name: name.clone(),
                    });
                }
                Err(e) => return Err(io_error(&path, "open")(e)),
            }
        }
        let manifest = Manifest {
            format: MANIFEST_FORMAT,
            complete: progress.is_complete(),
            runs_completed: progress.completed,
            runs_planned: progress.planned,
            files: self.files.clone(),
            dirs: self.dirs.clone(),
        };
        let path = self.staging.join(MANIFEST);
        let text = serde_json::to_string_pretty(&manifest).map_err(|e| ResultDirError::BadManifest {
            path: path.clone(),
            reason: e.to_string(),
        })?;
        File::create(&path)
            .and_then(|mut f| {
                f.write_all(text.as_bytes())?;
                f.sync_all()
            })
            .map_err(io_error(&path, "write"))?;
        sync_dir(&self.staging);
        Ok(manifest)
    }

    /// Moves the sealed staging directory to the target.
    fn publish(&mut self) -> Result<(), ResultDirError> {
        let target = self.dir.target.clone();
        if !target.exists() {
            fs::rename(&self.staging, &target).map_err(io_error(&target, "publish the results to"))?;
        } else if exchange(&self.staging, &target).map_err(io_error(&target, "publish the results to"))? {
            // The staging path now holds the previous results.
            self.committed = true;
            let _ = fs::remove_dir_all(&self.staging);
        } else {
            self.replace_by_renames()?;
        }
        self.committed = true;
        sync_dir(&self.dir.parent);
        Ok(())
    }

    /// Replaces the target where directories cannot be exchanged: the old
    /// set is renamed aside, the new one renamed into place, the old removed.
    fn replace_by_renames(&self) -> Result<(), ResultDirError> {
        let target = &self.dir.target;
        let old = self.dir.parent.join(Leftover::Old.fresh(&self.dir.name));
        fs::rename(target, &old).map_err(io_error(target, "move the previous results aside from"))?;
        fs::rename(&self.staging, target).map_err(io_error(target, "publish the results to"))?;
        let _ = fs::remove_dir_all(&old);
        Ok(())
    }
}

impl Drop for ResultWriter<'_> {
    fn drop(&mut self) {
        if !self.committed {
            let _ = fs::remove_dir_all(&self.staging);
        }
    }
}

/// Exchanges two directories atomically; `Ok(false)` where the system cannot.
fn exchange(a: &Path, b: &Path) -> io::Result<bool> {
    #[cfg(any(target_os = "linux", target_os = "android"))]
    {
        use std::os::unix::ffi::OsStrExt;
        let c = |p: &Path| {
            std::ffi::CString::new(p.as_os_str().as_bytes())
                .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "a path holds a NUL byte"))
        };
        let (ca, cb) = (c(a)?, c(b)?);
        // SAFETY: both are valid NUL-terminated strings that outlive the call.
        let r = unsafe {
            libc::renameat2(
                libc::AT_FDCWD,
                ca.as_ptr(),
                libc::AT_FDCWD,
                cb.as_ptr(),
                libc::RENAME_EXCHANGE,
            )
        };
        if r == 0 {
            return Ok(true);
        }
        let error = io::Error::last_os_error();
        match error.raw_os_error() {
            Some(libc::EINVAL | libc::ENOSYS | libc::EOPNOTSUPP) => Ok(false),
            _ => Err(error),
        }
    }
    #[cfg(not(any(target_os = "linux", target_os = "android")))]
    {
        let _ = (a, b);
        Ok(false)
    }
}

/// Makes renames in `dir` durable (best effort: some file systems refuse).
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("learnpnp-resultdir-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// The hidden entries beside the target (lock file aside).
    fn hidden(parent: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(parent)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter(|n| n.starts_with('.') && !n.ends_with(".lock"))
            .collect();
        names.sort();
        names
    }

    fn write_set(dir: &mut ResultDir, tag: &str, files: usize) {
        let mut w = dir.writer().unwrap();
        for i in 0..files {
            w.add_text(&format!("f{i}.txt"), tag).unwrap();
        }
        w.commit(Progress::complete(1)).unwrap();
    }

    /// Every file of the target carries `tag`, and the manifest lists them all.
    fn assert_whole(target: &Path, tag: &str, files: usize) {
        for i in 0..files {
            assert_eq!(fs::read_to_string(target.join(format!("f{i}.txt"))).unwrap(), tag);
        }
        let m: Manifest = serde_json::from_str(&fs::read_to_string(target.join(MANIFEST)).unwrap()).unwrap();
        assert_eq!(m.files.len(), files);
    }

    #[test]
    fn leftover_names_are_parsed_exactly() {
        assert_eq!(Leftover::of(".a.staging-12-0", "a"), Some(Leftover::Staging));
        assert_eq!(Leftover::of(".a.old-1-3", "a"), Some(Leftover::Old));
        // Another target's staging directory is not ours.
        assert_eq!(Leftover::of(".a.staging-1-2.staging-5-0", "a"), None);
        assert_eq!(Leftover::of(".a.staging-x-0", "a"), None);
        assert_eq!(Leftover::of(".ab.staging-1-0", "a"), None);
        let fresh = Leftover::Staging.fresh("run");
        assert_eq!(Leftover::of(&fresh, "run"), Some(Leftover::Staging));
    }

    #[test]
    fn a_kill_at_any_step_leaves_one_whole_set() {
        let parent = temp("kill");
        let target = parent.join("run");
        let files = 4;
        {
            let mut dir = ResultDir::open(&target).unwrap();
            write_set(&mut dir, "old", files);
        }
        // A kill after each file: the writer's clean-up never runs.
        for written in 0..=files {
            let mut dir = ResultDir::open(&target).unwrap();
            assert!(hidden(&parent).is_empty(), "open cleans: {:?}", hidden(&parent));
            let mut w = dir.writer().unwrap();
            for i in 0..written {
                w.add_text(&format!("f{i}.txt"), "new").unwrap();
            }
            std::mem::forget(w);
            assert_whole(&target, "old", files);
            drop(dir);
        }
        // A kill after the manifest is written, before publishing.
        {
            let mut dir = ResultDir::open(&target).unwrap();
            let mut w = dir.writer().unwrap();
            for i in 0..files {
                w.add_text(&format!("f{i}.txt"), "new").unwrap();
            }
            w.seal(Progress::complete(1)).unwrap();
            std::mem::forget(w);
            assert_whole(&target, "old", files);
        }
        // A kill between the fallback's two renames: the target is missing;
        // the next open puts the previous results back.
        {
            let mut dir = ResultDir::open(&target).unwrap();
            let mut w = dir.writer().unwrap();
            w.add_text("f0.txt", "new").unwrap();
            w.seal(Progress::complete(1)).unwrap();
            let old = parent.join(Leftover::Old.fresh("run"));
            fs::rename(&target, &old).unwrap();
            std::mem::forget(w);
        }
        let mut dir = ResultDir::open(&target).unwrap();
        assert_whole(&target, "old", files);
        assert!(hidden(&parent).is_empty(), "{:?}", hidden(&parent));
        // A kill after the exchange, before the old set is removed: the new
        // set is in place, the old one hidden, removed at the next open.
        {
            let mut w = dir.writer().unwrap();
            for i in 0..files {
                w.add_text(&format!("f{i}.txt"), "new").unwrap();
            }
            w.seal(Progress::complete(1)).unwrap();
            if exchange(&w.staging, &target).unwrap() {
                std::mem::forget(w);
                assert_whole(&target, "new", files);
            } else {
                w.publish().unwrap();
            }
        }
        drop(dir);
        let _dir = ResultDir::open(&target).unwrap();
        assert_whole(&target, "new", files);
        assert!(hidden(&parent).is_empty(), "{:?}", hidden(&parent));
        fs::remove_dir_all(&parent).unwrap();
    }

    #[test]
    fn the_fallback_without_exchange_replaces_whole() {
        let parent = temp("fallback");
        let target = parent.join("run");
        let mut dir = ResultDir::open(&target).unwrap();
        write_set(&mut dir, "old", 2);
        let mut w = dir.writer().unwrap();
        w.add_text("f0.txt", "new").unwrap();
        w.seal(Progress::complete(1)).unwrap();
        w.replace_by_renames().unwrap();
        w.committed = true;
        drop(w);
        assert_whole(&target, "new", 1);
        assert!(!target.join("f1.txt").exists());
        assert!(hidden(&parent).is_empty(), "{:?}", hidden(&parent));
        drop(dir);
        fs::remove_dir_all(&parent).unwrap();
    }

    #[test]
    fn a_committed_set_replaces_the_previous_one_whole() {
        let parent = temp("replace");
        let target = parent.join("run");
        let mut dir = ResultDir::open(&target).unwrap();
        assert_eq!(dir.contents().unwrap(), Contents::Empty);
        write_set(&mut dir, "one", 3);
        assert_whole(&target, "one", 3);
        // Fewer files this time: none of the previous set survives.
        write_set(&mut dir, "two", 2);
        assert_whole(&target, "two", 2);
        assert!(!target.join("f2.txt").exists());
        // A writer dropped without committing leaves nothing behind.
        let mut w = dir.writer().unwrap();
        w.add_text("f0.txt", "three").unwrap();
        drop(w);
        assert_whole(&target, "two", 2);
        assert!(hidden(&parent).is_empty());
        drop(dir);
        assert!(!parent.join(".run.lock").exists(), "the lock file is removed");
        fs::remove_dir_all(&parent).unwrap();
    }

    #[test]
    fn a_second_opener_is_refused_at_once() {
        let parent = temp("busy");
        let target = parent.join("run");
        let first = ResultDir::open(&target).unwrap();
        let err = ResultDir::open(&target).unwrap_err();
        let text = err.to_string();
        assert!(matches!(err, ResultDirError::Busy { holder: Some(pid), .. } if pid == std::process::id()));
        assert!(text.contains("another process") && text.contains("run"), "{text}");
        drop(first);
        let again = ResultDir::open(&target).unwrap();
        drop(again);
        fs::remove_dir_all(&parent).unwrap();
    }

    #[test]
    fn unusable_targets_are_refused_before_any_work() {
        let parent = temp("refuse");
        let file = parent.join("file");
        fs::write(&file, "x").unwrap();
        assert!(matches!(
            ResultDir::open(&file),
            Err(ResultDirError::NotADirectory { .. })
        ));
        // A directory holding something else is not replaced.
        let docs = parent.join("docs");
        fs::create_dir(&docs).unwrap();
        fs::write(docs.join("thesis.tex"), "precious").unwrap();
        let err = ResultDir::open(&docs).unwrap_err();
        assert!(matches!(err, ResultDirError::Foreign { .. }), "{err}");
        // A parent below a file cannot be created.
        let err = ResultDir::open(file.join("sub")).unwrap_err();
        assert!(err.to_string().contains("file"), "{err}");
        assert!(ResultDir::open("..").is_err());
        // Results of a version without manifests are replaceable.
        let legacy = parent.join("legacy");
        fs::create_dir(&legacy).unwrap();
        fs::write(legacy.join(LEGACY_MARKER), "{}").unwrap();
        let mut dir = ResultDir::open(&legacy).unwrap();
        assert_eq!(dir.contents().unwrap(), Contents::Legacy);
        write_set(&mut dir, "new", 1);
        assert!(!legacy.join(LEGACY_MARKER).exists());
        drop(dir);
        fs::remove_dir_all(&parent).unwrap();
    }

    #[test]
    fn bad_names_and_unwritten_files_are_refused() {
        let parent = temp("names");
        let mut dir = ResultDir::open(parent.join("run")).unwrap();
        let mut w = dir.writer().unwrap();
        for name in ["", "../x", "/etc/x", ".hidden", "a/.b", MANIFEST] {
            assert!(w.add_text(name, "x").is_err(), "{name}");
        }
        w.add_text("sub/ok.csv", "x").unwrap();
        assert!(w.add_text("sub/ok.csv", "y").is_err(), "twice");
        let logs = w.scratch_dir("logs").unwrap();
        assert!(logs.is_dir());
        assert_eq!(staging_dirs(&parent.join("run")), [w.staging.clone()]);
        assert!(w.add_text("logs/a.txt", "y").is_err(), "inside a scratch directory");
        assert!(w.scratch_dir("sub").is_err(), "over a file's directory");
        w.path_for("plot.svg").unwrap();
        let err = w.commit(Progress::complete(1)).unwrap_err();
        assert!(
            matches!(err, ResultDirError::NotWritten { ref name, .. } if name == "plot.svg"),
            "{err}"
        );
        assert!(!dir.path().exists());
        drop(dir);
        fs::remove_dir_all(&parent).unwrap();
    }

    #[test]
    fn partial_results_read_back() {
        let parent = temp("partial");
        let mut dir = ResultDir::open(parent.join("run")).unwrap();
        let mut w = dir.writer().unwrap();
        w.add_bytes("state.bin", &[1, 2, 3]).unwrap();
        let path = w.path_for("plot.svg").unwrap();
        fs::write(path, "<svg/>").unwrap();
        let work = w.scratch_dir("runs").unwrap();
        fs::write(work.join("run-0.log"), "started").unwrap();
        let written = w
            .commit(Progress {
                completed: 3,
                planned: 10,
            })
            .unwrap();
        let Contents::Results(m) = dir.contents().unwrap() else {
            panic!("results expected")
        };
        assert_eq!(m, written);
        assert!(!m.complete);
        assert_eq!((m.runs_completed, m.runs_planned), (3, 10));
        assert_eq!(m.files, ["state.bin", "plot.svg"]);
        assert_eq!(m.dirs, ["runs"]);
        assert_eq!(
            fs::read_to_string(dir.path().join("runs/run-0.log")).unwrap(),
            "started"
        );
        assert_eq!(dir.read("state.bin").unwrap(), [1, 2, 3]);
        assert!(dir.read("other.bin").is_err());
        // A listed file that went missing makes the manifest untrustworthy.
        fs::remove_file(dir.path().join("plot.svg")).unwrap();
        assert!(matches!(dir.contents(), Err(ResultDirError::BadManifest { .. })));
        drop(dir);
        fs::remove_dir_all(&parent).unwrap();
    }
}
