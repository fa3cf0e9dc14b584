//! The multi-process system's tests, one binary: the supervisor, simulator and agent processes over iceoryx2 shared memory, and the wait strategies.

// Each crate's test binary includes the workspace's shared helpers; each uses a subset.
#[allow(dead_code)]
#[path = "../../tests/util.rs"]
mod util;

/// The short run's protocol, where `multiprocess.rs` looks for it (the
/// multi-host tests that held it are the bridge package's now).
mod hosts {
    pub(crate) use crate::support::SHORT;
}
mod ipc_wait;
mod multiprocess;
mod support;
mod world;
