//! The multi-process system's tests, one binary: the supervisor, simulator and agent processes over iceoryx2 shared memory, and the wait strategies.

// Each crate's test binary includes the workspace's shared helpers; each uses
// a subset. The helper that runs the `learnpnp` command (the cli crate's
// binary, unknown here) is not among them.
#[allow(dead_code, clippy::option_env_unwrap)]
#[path = "../../tests/util.rs"]
mod util;

mod ipc_wait;
mod multiprocess;
