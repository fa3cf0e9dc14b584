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

pub mod child_args;
pub mod hosts;
pub mod ipc;
pub mod latency;
pub mod multiprocess;
/// Resident memory that follows what a process holds.
pub mod resident_memory;
