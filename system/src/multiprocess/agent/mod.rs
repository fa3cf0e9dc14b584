//! The agent processes of a run: one per keeper or agent, each running its
//! plan, learner and executor against the host's snapshots.

/// An agent's checkpoints written off its decision loop.
pub mod background_save;
/// The chassis both agent processes run on.
pub mod chassis;
/// A keeper's process in Keepaway.
pub mod keeper;
/// An agent of a world in its own process.
pub mod world;
