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

/// The command line of the run's child processes (their run context as clap arguments).
pub mod child_args;
/// A run across hosts: what the supervisor and each host's bridge share (run description, link report, certificates).
pub mod hosts;
/// The transport on iceoryx2: namespaces, services and ports, wait strategies, the protocol and its validation.
pub mod ipc;
/// HdrHistogram latencies: percentiles, `.hgrm` text, serialisation, plots.
pub mod latency;
/// The processes of a run (simulator, world, agents) and the supervisor over them; soaks, chaos, benchmarks.
pub mod multiprocess;
/// glibc's mmap threshold fixed at its default, so that a soak's memory growth is a leak signal.
pub mod resident_memory;
