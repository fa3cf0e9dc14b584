//! A run across hosts, as the supervisor and each host's bridge share it:
//! the bridge itself (Zenoh) is the crate `learnpnp-bridge`, a process of its
//! own that the supervisor starts and reads back through files: the run's
//! description ([`run_info`]), the link report ([`report`]) and the link's
//! certificates ([`certs`], made by `learnpnp-supervisor link-certs`).

pub mod certs;
pub mod report;
pub mod run_info;

use std::time::Duration;

/// How long a remote host's bridge asks for the run before giving up.
pub const JOIN_TIMEOUT: Duration = Duration::from_secs(60);

/// What a plain TCP link (`--insecure-plain-tcp`) gives up, for logs and reports.
pub const PLAIN_TCP_WARNING: &str = "the link between hosts is plain TCP (--insecure-plain-tcp): not encrypted, \
     no host authenticated, no access control; anyone who reaches the bridge's port can read the run and take it over";
