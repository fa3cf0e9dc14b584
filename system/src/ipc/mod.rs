//! The transport of the multi-process system: iceoryx2 shared memory.
//!
//! - [`namespace`]: a run's own prefix and directory, its owner lock, and the
//!   cleanup of what dead runs left;
//! - [`services`]: every service of a run with its limits, and each process's ports
//!   (made of [`port`]'s iceoryx2 types);
//! - [`wait`]: how a process waits between polls (spin, yield, block, hybrid);
//! - [`protocol`]: the protocol's own types (roles, what messages say, orders);
//! - [`convert`]: the in-process types to and from their `shm_layouts`
//!   layouts, validating everything read.

/// Validation of every message read, and the messages built.
pub mod convert;
/// A run's iceoryx2 namespace: prefix, directory, owner lock, cleanup.
pub mod namespace;
/// What every port is made of: the iceoryx2 service variant and its errors.
pub mod port;
/// The protocol's own types (roles, orders, pulses, news).
pub mod protocol;
/// A run's services and each process's ports.
pub mod services;
/// Wait strategies: spin, yield, block, hybrid.
pub mod wait;
/// The world protocol: snapshots, commands and vocabulary of a world in its own process.
pub mod world;
