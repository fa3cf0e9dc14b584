//! Helpers shared by the test binaries of every crate in the workspace (each
//! crate's `tests/main.rs` includes this file as its `util` module).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use learnpnp::experiment::runner::{Completed, ExperimentOutput, RunOptions, run_experiment};
use learnpnp::experiment::spec::ExperimentSpec;

/// The workspace's root directory (where `plans/` and `tests/fixtures/` are).
pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .find(|dir| dir.join("Cargo.lock").exists())
        .expect("the workspace root holds Cargo.lock")
}

/// The path of the shipped plan file `plans/FILE`.
pub fn shipped(file: &str) -> PathBuf {
    root().join("plans").join(file)
}

/// The path of the shipped plan file `plans/FILE`, as a command-line argument.
pub fn shipped_arg(file: &str) -> String {
    shipped(file).display().to_string()
}

/// The path of `tests/fixtures/RELATIVE`.
pub fn fixture(relative: &str) -> PathBuf {
    root().join("tests/fixtures").join(relative)
}

/// A fresh, empty directory for one test: unique within the test binary
/// (every call gets its own) and across concurrent runs (the process id).
pub fn temp_dir(tag: &str) -> PathBuf {
    static NEXT: AtomicUsize = AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("learnpnp-test-{}-{n}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    dir
}

/// Output bytes as text (lossy).
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs `spec` with `threads` workers, no progress bar and no stop flag.
pub fn run_quietly(spec: &ExperimentSpec, threads: usize) -> ExperimentOutput {
    let options = RunOptions {
        threads,
        progress: false,
        stop: None,
    };
    run_experiment(spec, options, Completed::default()).expect("the experiment runs")
}
