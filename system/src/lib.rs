//! learnpnp's multi-process system: the Keepaway simulator, or any world in
//! a process of its own, and each agent (its plan, executor and learner) in a
//! process of its own, exchanging knowledge-base snapshots, commands and
//! rewards through iceoryx2 shared memory (the layouts are the `shm_layouts`
//! crate), under a supervisor that launches, watches and restarts them;
//! latency histograms, soaks and fault injection; a bridge carrying a run's
//! services to agents on other hosts over Zenoh (the crate
//! `learnpnp-bridge`, a process of its own; [`hosts`]: what it shares with
//! the supervisor). The plans,
//! executor and learners are the `learnpnp` crate.

#![deny(missing_docs)]

/// The command line of the run's child processes.
pub mod child_args;
/// A run across hosts, as the supervisor and each host's bridge share it.
pub mod hosts;
/// The transport of the multi-process system: iceoryx2 shared memory.
pub mod ipc;
/// Latency histograms of the multi-process system.
pub mod latency;
/// The multi-process learner system.
pub mod multiprocess;
/// Resident memory that follows what a process holds.
pub mod resident_memory;
