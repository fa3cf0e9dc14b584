//! The transport of the multi-process system: iceoryx2 shared memory.
//!
//! - [`namespace`]: a run's own prefix and directory, its owner lock, and the
//!   cleanup of what dead runs left;
//! - [`services`]: every service of a run with its limits, and each process's ports
//!   (made of [`port`]'s iceoryx2 types);
//! - [`feed`]: an agent's live feed to the view process (a run with a view);
//! - [`wait`]: how a process waits between polls (spin, yield, block, hybrid);
//! - [`protocol`]: the protocol's own types (roles, what messages say, orders);
//! - [`convert`]: the in-process types to and from their `shm_layouts`
//!   layouts, validating everything read.

pub mod convert;
pub mod feed;
pub mod namespace;
pub mod port;
pub mod protocol;
pub mod services;
pub mod wait;
pub mod world;
