//! Keepaway 3 vs 2: a faithful re-implementation of the RoboCup 2D Soccer Server's
//! physics (2005-era parameters), the keepaway referee, and the keepaway player
//! framework's skills, takers and baseline keeper policies (Stone, Sutton, Kuhlmann
//! 2005), as used in chapter 7 of the thesis.
//!
//! Layers, bottom up:
//! - [`geometry`], [`params`], [`command`]: vectors and angles (degrees), parameters,
//!   the primitive commands;
//! - [`world`], [`referee`], [`simulator`]: state, physics step, episode end and
//!   reset, all randomness from one seeded generator;
//! - [`perception`]: what each agent perceives ([`view::PlayerView`]):
//!   the framework players' perception (by default: [`see`], what the server
//!   tells them, [`timing`], when, and [`world_model`], what their world model
//!   makes of it), full state, or quantised;
//! - [`skills`], [`taker`], [`keeper`]: the framework's behaviours; the keeper with the
//!   ball asks a pluggable [`keeper::KeeperPolicy`];
//! - [`policies`]: random, always-hold, hand-coded and the thesis's threshold policy;
//! - [`state_vars`], [`features`], [`positions`]: abstractions for plans and learners;
//! - [`episode`]: running episodes;
//! - [`rcg`], [`replay`]: RoboCup game logs (`.rcg`) of episodes, for rcssmonitor,
//!   and a self-contained HTML page replaying one.

#![deny(missing_docs)]

use learnpnp_common::{named, rng};

/// The server's primitive body commands.
pub mod command;
/// Running episodes in this process.
pub mod episode;
/// The thesis's abstraction for the keeper with the ball.
pub mod features;
/// One Keepaway cycle in named stages over plain data.
pub mod game;
/// Plane geometry for the simulator.
pub mod geometry;
/// The keepers' fixed procedure around a pluggable decision.
pub mod keeper;
/// Parameters: physics, skills and the task.
pub mod params;
/// What one agent perceives, and the pipeline that makes it.
pub mod perception;
#[cfg(test)]
mod played_views;
/// Baseline decisions for the keeper with the ball.
pub mod policies;
/// The nine positioning points of the thesis's multi-agent experiment.
pub mod positions;
/// RoboCup soccer simulator game logs (`.rcg`).
pub mod rcg;
/// The keepaway referee.
pub mod referee;
/// A game log as one self-contained HTML page.
pub mod replay;
/// What the soccer server tells each player.
pub mod see;
/// The simulator behind one step function.
pub mod simulator;
/// The keepaway framework's skills.
pub mod skills;
/// The 13 state variables of the original keepaway benchmark.
pub mod state_vars;
/// The takers' fixed policy.
pub mod taker;
/// When the players' see messages arrive, and when the players act.
pub mod timing;
/// What one agent perceives, as plain data.
pub mod view;
/// The field's state and the server's physics step.
pub mod world;
/// What a framework player believes: the keepaway framework's world model.
pub mod world_model;

pub use command::Command;
pub use episode::{Keepaway, run_episode};
pub use game::{Cycle, EpisodeSummary, Game};
pub use geometry::Vec2;
pub use keeper::{KeeperAction, KeeperPolicy, SupportAction};
pub use params::{ConfigError, KeepawayConfig, RefereeRule, ServerParams, ServerTimer, SkillParams, VisionMode};
pub use perception::{Perception, perceive};
pub use policies::BaselinePolicy;
pub use referee::EndReason;
pub use simulator::Simulator;
pub use view::{PlayerId, PlayerView};
pub use world::FieldState;
