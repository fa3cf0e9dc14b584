//! The multi-process system's tests, one binary: the supervisor, simulator and agent processes over iceoryx2 shared memory, worlds, and the wait strategies.
//!
//! End-to-end tests live with the package whose binary they test: the bridge's
//! (runs across hosts, intruders) in `crates/bridge/tests/hosts/`, the view
//! process's in `crates/view_process/tests/`. They include `support.rs`
//! (a sandbox per test, processes, results) with `#[path]` and find this
//! package's binaries beside their own (`support::workspace_binary`), which
//! `cargo test --workspace` builds before any test runs; no test runs cargo.

// Each crate's test binary includes the workspace's shared helpers; each uses a subset.
#[allow(dead_code)]
#[path = "../../tests/util.rs"]
mod util;

mod ipc_wait;
mod multiprocess;
mod support;
mod world;
