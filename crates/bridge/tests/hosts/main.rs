//! The bridge's end-to-end tests, one binary: runs across two hosts (network
//! namespaces where the test runs as root, loopback otherwise), each host's
//! supervisor starting this package's bridge, and intruders on their link.
//! The supervisor and the corridor world are the system package's binaries,
//! which `cargo test --workspace` builds beside this package's
//! (`support::workspace_binary`); no test builds one.

// Each package's test binary includes the workspace's shared helpers and the
// end-to-end support of the system package's tests; each uses a subset.
#[allow(dead_code)]
#[path = "../../../../tests/util.rs"]
mod util;

#[allow(dead_code)]
#[path = "../../../../system/tests/support.rs"]
mod support;

mod hosts;
mod intruders;
