//! The view process's end-to-end tests, one binary: runs with a view, the
//! supervisor (the system package's binary, which `cargo test --workspace`
//! builds beside this package's: `support::workspace_binary`) starting this
//! package's `learnpnp-view`.

// Each package's test binary includes the workspace's shared helpers and the
// end-to-end support of the system package's tests; each uses a subset.
#[allow(dead_code)]
#[path = "../../../tests/util.rs"]
mod util;

#[allow(dead_code)]
#[path = "../../../system/tests/support.rs"]
mod support;

mod view;
