//! A run across hosts, as the supervisor and each host's bridge share it:
//! the bridge itself (Zenoh) is the crate `learnpnp-bridge`, a process of its
//! own that the supervisor starts and reads back through files: the run's
//! description ([`run_info`](crate::hosts::run_info)), the link report ([`report`](crate::hosts::report)) and the link's
//! certificates ([`certs`](crate::hosts::certs), made by `learnpnp-supervisor link-certs`).

/// The private CA of a run's hosts and their certificates.
pub mod certs;
/// What a message carried from another host must hold.
pub mod inbound;
/// What a host's bridges did over a run.
pub mod report;
/// Host A's description of a run for the other hosts.
pub mod run_info;
/// The files host B ships to host A, and what each must hold.
pub mod shipped;

use std::time::Duration;

/// How long a remote host's bridge asks for the run before giving up.
pub const JOIN_TIMEOUT: Duration = Duration::from_secs(60);

/// What a plain TCP link (`--insecure-plain-tcp`) gives up, for logs and reports.
pub const PLAIN_TCP_WARNING: &str = "the link between hosts is plain TCP (--insecure-plain-tcp): not encrypted, \
     no host authenticated, no access control; anyone who reaches the bridge's port can read the run and take it over";
