//! learnpnp: reinforcement learning in plan space.
//!
//! A designer writes a behaviour as a Petri Net Plan and leaves some choices open;
//! the executor runs the plan with the thesis's operational semantics and hands
//! every open choice to a learner. See `docs/ARCHITECTURE.md` for the data path.

#![deny(missing_docs)]

/// The README's code blocks, compiled and run as doc-tests.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

pub mod analysis;
pub mod atomic_file;
pub mod condition;
pub mod domains;
pub mod dot;
pub mod executor;
pub mod experiment;
pub mod json_float;
pub mod keepaway_sim;
pub mod learning;
pub mod named;
pub mod net;
pub mod plan;
pub mod plan_file;
pub mod pnml;
pub mod result_dir;
pub mod rng;
pub mod schema;
