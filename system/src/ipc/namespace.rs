//! A run's own iceoryx2 namespace: a run-unique file prefix and a private root
//! directory, so that runs (and tests) never see each other's services, and
//! everything a run created can be found and removed, even after a kill.
//!
//! iceoryx2 keeps its shared-memory segments in `/dev/shm/<prefix>*` and its
//! service and node records under the configured root directory. A namespace
//! puts that root at `<base>/<prefix>/` (base: [`base_dir`](crate::ipc::namespace::base_dir)) and is owned by
//! the supervisor through an advisory lock on `<base>/<prefix>.lock`: when the
//! owner dies, the lock is released, and [`clean_stale`](crate::ipc::namespace::clean_stale) (run by every launch)
//! removes the dead run's nodes with iceoryx2's dead-node cleanup and then
//! every remaining file of its prefix. A prefix is never reused.

use std::fs::{self, File};
use std::io;
use std::path::{Path, PathBuf};

use iceoryx2::config::Config;
use iceoryx2::prelude::{CallbackProgression, FileName, Node, NodeState, SemanticString};
use rand::RngExt;

/// Where a run's shared-memory segments live.
pub const SHM_DIR: &str = "/dev/shm";

/// The start of every learnpnp prefix.
const PREFIX_START: &str = "lp";

/// The longest path of a unix socket (`sun_path` holds 108 bytes with its NUL).
const MAX_SOCKET_PATH: usize = 107;

/// What iceoryx2 appends to a namespace's root for an event's socket: the
/// prefix, a 31-digit id and `.event`.
const SOCKET_NAME: usize = 31 + ".event".len();

/// Why a namespace cannot be set up or cleaned.
#[derive(Debug, thiserror::Error)]
pub enum NamespaceError {
    /// A prefix with characters iceoryx2 does not allow in file names, or not ours.
    #[error("invalid iceoryx2 prefix {0:?}: expected 'lp' followed by letters, digits or '_'")]
    BadPrefix(String),
    /// The namespace's directory is too long for iceoryx2's unix sockets.
    #[error(
        "{path}: too long for iceoryx2's unix sockets (a socket path holds {MAX_SOCKET_PATH} bytes): set LEARNPNP_IPC_DIR to a shorter directory"
    )]
    PathTooLong {
        /// The namespace's root directory.
        path: PathBuf,
    },
    /// A file operation failed.
    #[error("{path}: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The error.
        source: io::Error,
    },
    /// iceoryx2 refused the configuration or the cleanup.
    #[error("iceoryx2: {0}")]
    Iceoryx(String),
}

fn io_error(path: &Path) -> impl FnOnce(io::Error) -> NamespaceError + '_ {
    move |source| NamespaceError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// The directory holding the namespaces' root directories and owner locks:
/// `$LEARNPNP_IPC_DIR`, or `/tmp/learnpnp-ipc`.
pub fn base_dir() -> PathBuf {
    std::env::var_os("LEARNPNP_IPC_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("/tmp/learnpnp-ipc"))
}

/// One run's iceoryx2 namespace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Namespace {
    prefix: String,
    base: PathBuf,
}

impl Namespace {
    /// A fresh namespace under [`base_dir`] with a random prefix (32 bits;
    /// [`Namespace::claim`] refuses one that exists).
    pub(crate) fn unique() -> Self {
        let random: u32 = rand::rng().random();
        Namespace {
            prefix: format!("{PREFIX_START}{random:08x}_"),
            base: base_dir(),
        }
    }

    /// Claims a fresh namespace under [`base_dir`], drawing another prefix if
    /// the first is taken.
    pub fn claim_unique() -> Result<NamespaceOwner, NamespaceError> {
        let mut attempt = 0;
        loop {
            match Namespace::unique().claim() {
                Err(NamespaceError::Io { source, .. })
                    if source.kind() == io::ErrorKind::AlreadyExists && attempt < 8 =>
                {
                    attempt += 1;
                }
                other => return other,
            }
        }
    }

    /// The namespace of `prefix` (as a supervisor passes it to its processes),
    /// under [`base_dir`].
    pub fn from_prefix(prefix: &str) -> Result<Self, NamespaceError> {
        Self::at(&base_dir(), prefix)
    }

    /// The namespace of `prefix` under `base`.
    pub fn at(base: &Path, prefix: &str) -> Result<Self, NamespaceError> {
        let valid = prefix.starts_with(PREFIX_START)
            && prefix.len() <= 64
            && prefix.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
        if !valid {
            return Err(NamespaceError::BadPrefix(prefix.to_string()));
        }
        Ok(Namespace {
            prefix: prefix.to_string(),
            base: base.to_path_buf(),
        })
    }

    /// The file prefix.
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    /// The private root directory of iceoryx2's records.
    pub fn root(&self) -> PathBuf {
        self.base.join(self.prefix.trim_end_matches('_'))
    }

    /// The owner's lock file.
    fn lock_path(&self) -> PathBuf {
        self.base.join(format!("{}.lock", self.prefix.trim_end_matches('_')))
    }

    /// The iceoryx2 configuration of this namespace, for every node of the run.
    pub fn config(&self) -> Result<Config, NamespaceError> {
        let mut config = Config::default();
        config.global.prefix =
            FileName::new(self.prefix.as_bytes()).map_err(|e| NamespaceError::Iceoryx(format!("{e:?}")))?;
        let root = format!("{}/", self.root().display());
        let root =
            iceoryx2::prelude::Path::new(root.as_bytes()).map_err(|e| NamespaceError::Iceoryx(format!("{e:?}")))?;
        config.global.set_root_path(&root);
        Ok(config)
    }

    /// Takes ownership: creates the lock file and holds its lock until the
    /// returned guard is dropped (or the process dies). The lock is taken on a
    /// temporary name and then renamed into place, so that [`clean_stale`]
    /// never sees an unlocked lock file of a live run.
    /// Fails if the prefix is taken or the directory is too long for the
    /// run's unix sockets.
    pub(crate) fn claim(&self) -> Result<NamespaceOwner, NamespaceError> {
        let root = self.root();
        if root.as_os_str().len() + 1 + self.prefix.len() + SOCKET_NAME > MAX_SOCKET_PATH {
            return Err(NamespaceError::PathTooLong { path: root });
        }
        fs::create_dir_all(&self.base).map_err(io_error(&self.base))?;
        let path = self.lock_path();
        let tmp = path.with_extension("lock.new");
        let taken = |p: &Path| p.exists();
        if taken(&path) || taken(&root) {
            return Err(NamespaceError::Io {
                path,
                source: io::Error::from(io::ErrorKind::AlreadyExists),
            });
        }
        let file = File::options()
            .write(true)
            .create_new(true)
            .open(&tmp)
            .map_err(io_error(&tmp))?;
        file.lock().map_err(io_error(&tmp))?;
        fs::rename(&tmp, &path).map_err(io_error(&path))?;
        fs::create_dir_all(self.root()).map_err(io_error(&self.root()))?;
        Ok(NamespaceOwner {
            namespace: self.clone(),
            _lock: file,
        })
    }

    /// Every file and directory of this namespace that exists now: its
    /// shared-memory segments and its root directory's tree.
    pub fn files(&self) -> Vec<PathBuf> {
        let mut found = Vec::new();
        if let Ok(entries) = fs::read_dir(SHM_DIR) {
            for entry in entries.flatten() {
                if entry.file_name().to_string_lossy().starts_with(&self.prefix) {
                    found.push(entry.path());
                }
            }
        }
        collect_tree(&self.root(), &mut found);
        found
    }

    /// Removes what the namespace's dead nodes left (iceoryx2's dead-node
    /// cleanup), then every remaining file of the namespace. Returns how many
    /// files and directories were removed. Only call this when no process of
    /// the run is alive.
    pub fn remove_all(&self) -> Result<usize, NamespaceError> {
        if self.root().exists() {
            self.remove_dead_nodes()?;
        }
        let files = self.files();
        let mut removed = 0;
        // Deepest first, so directories are empty when their turn comes.
        for path in files.iter().rev() {
            let result = if path.is_dir() {
                fs::remove_dir(path)
            } else {
                fs::remove_file(path)
            };
            match result {
                Ok(()) => removed += 1,
                Err(e) if e.kind() == io::ErrorKind::NotFound => {}
                Err(e) => {
                    return Err(NamespaceError::Io {
                        path: path.clone(),
                        source: e,
                    });
                }
            }
        }
        Ok(removed)
    }

    /// iceoryx2's cleanup of the nodes of this namespace whose process is
    /// dead (their ports, so that a replacement finds its port's slot free).
    pub(crate) fn remove_dead_nodes(&self) -> Result<(), NamespaceError> {
        let config = self.config()?;
        Node::<iceoryx2::prelude::ipc::Service>::list(&config, |state| {
            if let NodeState::Dead(node) = state {
                // Failures leave files behind; the file sweep that follows removes them.
                let _ = node.try_remove_stale_resources();
            }
            CallbackProgression::Continue
        })
        .map_err(|e| NamespaceError::Iceoryx(format!("listing nodes: {e:?}")))
    }
}

/// Appends `dir` and everything below it, parents before children.
fn collect_tree(dir: &Path, found: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else { return };
    found.push(dir.to_path_buf());
    for entry in entries.flatten() {
        let path = entry.path();
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            collect_tree(&path, found);
        } else {
            found.push(path);
        }
    }
}

/// The supervisor's ownership of a namespace: while it lives, no other launch
/// cleans the namespace. Dropping it does not remove the files; call
/// [`NamespaceOwner::release`] once every process of the run has exited.
#[derive(Debug)]
pub struct NamespaceOwner {
    namespace: Namespace,
    _lock: File,
}

impl NamespaceOwner {
    /// The namespace.
    pub fn namespace(&self) -> &Namespace {
        &self.namespace
    }

    /// Removes every file of the namespace, then the lock file. Returns how
    /// many files and directories were removed.
    pub fn release(self) -> Result<usize, NamespaceError> {
        let removed = self.namespace.remove_all()?;
        let lock = self.namespace.lock_path();
        fs::remove_file(&lock).map_err(io_error(&lock))?;
        Ok(removed + 1)
    }
}

/// A dead run's namespace that [`clean_stale`] removed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StaleNamespace {
    /// Its prefix.
    pub prefix: String,
    /// Files and directories removed.
    pub removed: usize,
}

/// Removes the namespaces of runs whose supervisor is dead (their lock is free).
pub fn clean_stale() -> Result<Vec<StaleNamespace>, NamespaceError> {
    let base = base_dir();
    let Ok(entries) = fs::read_dir(&base) else {
        return Ok(Vec::new());
    };
    let mut cleaned = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(stem) = name.strip_suffix(".lock") else {
            continue;
        };
        let Ok(namespace) = Namespace::at(&base, &format!("{stem}_")) else {
            continue;
        };
        let path = entry.path();
        let Ok(file) = File::options().write(true).open(&path) else {
            continue;
        };
        if file.try_lock().is_err() {
            continue; // its owner is alive
        }
        let removed = namespace.remove_all()?;
        fs::remove_file(&path).map_err(io_error(&path))?;
        cleaned.push(StaleNamespace {
            prefix: namespace.prefix,
            removed: removed + 1,
        });
    }
    Ok(cleaned)
}
