//! Keepaway 3 vs 2 with plan-driven keepers (thesis chapter 7).
//!
//! The simulator (the `learnpnp-keepaway` crate) knows nothing of plans: each cycle a keeper
//! gets its own `PlayerView`, its plan steps until an action issues the cycle's
//! primitive command, and the simulator steps. The reward is the time elapsed,
//! so an episode's return is its duration in seconds.

mod actions;
mod agent;
mod config;
mod decisions;
mod task;
mod team;
mod world;

pub use actions::{decision_name, goto_name, registry};
pub use agent::{MAX_STEPS_PER_CYCLE, PlanKeeper};
pub use config::{FixedPolicy, KeepawayDomainConfig, KeepawayMode};
pub use decisions::{Decision, PassDecisions, Start, Stop};
pub use task::{KeepawayTask, RunSeeds};
pub use team::{KeeperTeam, LocalTeam, TeamStep};
pub use world::{ATOMS, KeeperWorld, atoms};
