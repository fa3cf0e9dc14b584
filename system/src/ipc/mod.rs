//! The transport of the multi-process system: iceoryx2 shared memory.
//!
//! - [`namespace`](crate::ipc::namespace): a run's own prefix and directory, its owner lock, and the
//!   cleanup of what dead runs left;
//! - [`services`](crate::ipc::services): every service of a run with its limits, and each process's ports
//!   (made of [`port`](crate::ipc::port)'s iceoryx2 types);
//! - [`feed`](crate::ipc::feed): an agent's live feed to the view process (a run with a view);
//! - [`wait`](crate::ipc::wait): how a process waits between polls (spin, yield, block, hybrid);
//! - [`protocol`](crate::ipc::protocol): the protocol's own types (roles, what messages say, orders);
//! - [`convert`](crate::ipc::convert): the in-process types to and from their `shm_layouts`
//!   layouts, validating everything read.

/// The in-process types to and from their shared-memory layouts.
pub mod convert;
/// An agent's live feed on iceoryx2.
pub mod feed;
/// A run's own iceoryx2 namespace.
pub mod namespace;
/// What every port of a run is made of.
pub mod port;
/// The protocol's own types.
pub mod protocol;
/// The run's iceoryx2 services and the ports each process holds.
pub mod services;
/// How a process waits for a message that has not arrived yet.
pub mod wait;
/// The protocol of a world in its own process.
pub mod world;
