//! The host processes of a run: the one process that owns the world's state
//! and steps it, either the Keepaway simulator or a world written in Rust.

/// Real time on absolute deadlines, with the heartbeat kept while asleep.
pub(crate) mod cadence;
/// What both hosts share: heartbeat, the supervisor's orders, readiness, lost agents and shutdown.
pub(crate) mod chassis;
/// The Keepaway simulator's process.
pub mod simulator;
/// A world written in Rust, served as the world process of a run.
pub mod world;
