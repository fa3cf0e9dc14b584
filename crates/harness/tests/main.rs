//! The harness's tests, one binary: `learnpnp-soak` run as a user runs it,
//! soaks with and without faults injected into the multi-process system.

// Each crate's test binary includes the workspace's shared helpers; each uses a subset.
#[allow(dead_code)]
#[path = "../../../tests/util.rs"]
mod util;

// The system's end-to-end support: sandboxes, the workspace's binaries, processes.
#[allow(dead_code)]
#[path = "../../../system/tests/support.rs"]
mod support;

mod soak;
