//! # learnpnp: reinforcement learning in plan space
//!
//! A designer writes a behaviour as a Petri Net Plan and leaves some choices
//! open; the executor runs the plan with the operational semantics of
//! Leonetti's thesis (*Reinforcement Learning in Plan Space*, 5.3) and hands
//! every open choice to a learner, which learns from the rewards which option
//! pays best, even where the world is only partly observable.
//!
//! ## The path a user takes
//!
//! 1. **A plan**: load a file with [`load_plan`] (the PNP editor's JARP PNML,
//!    standard PNML, or a plan schema, thesis chapter 3), or build one with
//!    [`PlanBuilder`] and the thesis's operators (sequence, sensing, fork and
//!    join, interrupts, non-deterministic choice). Guards name atoms; a
//!    [`AllowedAtoms`] says which atoms the world has. [`analysis::check`] verifies
//!    safety, minimality and effectiveness.
//! 2. **A world and its actions**: the world answers the atoms
//!    ([`KnowledgeBase`]) and pays rewards ([`World`]); each action the plan
//!    names is an [`Action`] registered by name in a [`Registry`].
//! 3. **An agent with a learner**: a [`PlanAgent`] runs episodes of the plan in
//!    the world with a [`Learner`] at the choice points: [`SoSmc`] (the
//!    thesis's algorithm), or Sarsa(λ), Sarsa(0), Q-learning and MCESP in
//!    [`learning`].
//! 4. **Values saved and loaded**: [`persist::save`] writes what was learned
//!    ([`SavedValues`]) in the format `learnpnp values` reads; [`persist::load`]
//!    reads it back, checked, to start a learner from it.
//!
//! The thesis's domains ([`domains`]: the penalty kick, Parr and Russell's and
//! Sutton's grids, Keepaway on the simulator of [`learnpnp_keepaway`]) and its
//! experiments ([`experiment`]) are built the same way. The multi-process
//! system (the `learnpnp-system` crate) and the `learnpnp` command
//! (`learnpnp-cli`) sit on top of this crate; `docs/ARCHITECTURE.md` follows the
//! data from plan file to executor to learner to world and back.
//!
//! ## Example
//!
//! Two doors: the left one pays 1, the right one 0. The plan leaves the choice
//! open; SoSMC learns to open the left door, and its values survive a file.
//!
//! ```
//! use std::sync::Arc;
//!
//! use learnpnp::learning::{Assessment, ExploitPolicy, Schedule, Sigma, StepSize, Unestimated};
//! use learnpnp::rng::seeded;
//! use learnpnp::{
//!     Action, AtomId, AtomTable, EpisodeMode, EpisodeStart, KnowledgeBase, Learner, PlanAgent, PlanBuilder,
//!     Registry, SavedValues, SoSmc, SoSmcConfig, TaskError, AllowedAtoms, World, persist,
//! };
//!
//! /// The world: whether a door is open, what it paid, and the reward the
//! /// executor has not collected yet.
//! #[derive(Default)]
//! struct Doors {
//!     open: bool,
//!     earned: f64,
//!     pending: f64,
//! }
//!
//! impl KnowledgeBase for Doors {
//!     fn holds(&self, _atom: AtomId) -> bool {
//!         self.open // the one atom, "Open"
//!     }
//! }
//!
//! impl World for Doors {
//!     fn take_reward(&mut self) -> f64 {
//!         std::mem::take(&mut self.pending)
//!     }
//! }
//!
//! /// Opening a door: its reward, at once.
//! struct OpenDoor(f64);
//!
//! impl Action<Doors> for OpenDoor {
//!     fn start(&mut self, world: &mut Doors) {
//!         world.open = true;
//!         world.earned += self.0;
//!         world.pending += self.0;
//!     }
//!     fn finished(&self, world: &Doors) -> bool {
//!         world.open
//!     }
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // 1. The plan: from the start, open the left or the right door, then stop.
//! let mut builder = PlanBuilder::new("doors");
//! let start = builder.initial_place("start");
//! let goal = builder.goal_place();
//! builder.action_into(start, "Left", goal);
//! builder.action_into(start, "Right", goal);
//! let atoms: AtomTable = ["Open"].into_iter().collect();
//! let plan = Arc::new(builder.build(AllowedAtoms::Closed(&atoms))?);
//!
//! // 2. The actions, by the names the plan uses.
//! let mut registry = Registry::new();
//! registry.action("Left", &[], |_| OpenDoor(1.0));
//! registry.action("Right", &[], |_| OpenDoor(0.0));
//!
//! // 3. An agent learning with epsilon-SoSMC.
//! let config = SoSmcConfig {
//!     gamma: 1.0,
//!     initial_phase: 20,
//!     sigma: Sigma::EpsilonGreedy,
//!     initial_parameter: Schedule::constant(0.5),
//!     assessing_parameter: Schedule::constant(0.1),
//!     assessment: Assessment::EveryN(10),
//!     step_size: StepSize::Constant(0.1),
//!     initial_value: f64::NEG_INFINITY,
//!     threshold: None,
//!     unestimated: Unestimated::AsBest,
//!     exploit: ExploitPolicy::Greedy,
//! };
//! let mut agent = PlanAgent::new(plan, &registry, Box::new(SoSmc::new(config, seeded(7))))?;
//! let episode = |agent: &mut PlanAgent<Doors>, mode| -> Result<f64, TaskError> {
//!     let mut doors = Doors::default();
//!     agent.run(&mut doors, EpisodeStart::of(mode), 10, |_| false)?;
//!     Ok(doors.earned)
//! };
//! for _ in 0..200 {
//!     episode(&mut agent, EpisodeMode::Learn)?;
//! }
//! assert_eq!(episode(&mut agent, EpisodeMode::Greedy)?, 1.0, "the left door, greedily");
//!
//! // 4. The values, saved and loaded back.
//! let file = std::env::temp_dir().join(format!("learnpnp-doors-{}.bin", std::process::id()));
//! persist::save(&file, &SavedValues::new("eps-sosmc", agent.learner().values(), &[agent.plan()]))?;
//! let loaded = persist::load(&file)?;
//! assert_eq!(loaded, SavedValues::new("eps-sosmc", agent.learner().values(), &[agent.plan()]));
//! std::fs::remove_file(&file)?;
//! # Ok(())
//! # }
//! ```

#![deny(missing_docs)]

/// The guide's Rust code blocks (`docs/guide/src/plans.md`), compiled and
/// run as doc-tests.
#[doc = include_str!("../docs/guide/src/plans.md")]
#[cfg(doctest)]
pub(crate) struct GuideDoctests;

/// Agents running a plan with a learner at its choice points.
pub mod agent;
/// Structural analysis of a plan.
pub mod analysis;
/// Guard conditions.
pub mod condition;
/// Domains the thesis learns in, each driven by a plan.
pub mod domains;
/// Graphviz DOT export of a plan.
pub mod dot;
/// The plan executor.
pub mod executor;
/// Experiments over many seeded runs.
pub mod experiment;
/// Plans generated from planners' plans: linear and conditional plans, the k
/// best plans merged into choice points, execution rules.
pub mod generate;
/// The live feed's records and sink (the `learnpnp-feed` crate).
pub use learnpnp_feed as feed;
pub(crate) mod json_float;
/// Learners at the executor's choice points.
pub mod learning;
/// Enumerations picked by name (from the `learnpnp-common` crate).
pub use learnpnp_common::named;
/// Place/transition nets: the structure under every plan.
pub mod net;
/// Petri Net Plans.
pub mod plan;
/// Loading plan files of either kind.
pub mod plan_file;
/// Plan files in PNML.
pub mod pnml;
/// Seeded, reproducible random numbers (from the `learnpnp-common` crate).
pub use learnpnp_common::rng;
/// Plan schemas: partially specified plans as hierarchies of state machines.
pub mod schema;

pub use agent::PlanAgent;
pub use condition::{AtomId, AtomTable, KnowledgeBase};
pub use domains::TaskError;
pub use executor::{Action, Chooser, Executor, Registry, Status, World};
pub use learning::persist::{self, SavedValues};
pub use learning::{EpisodeMode, EpisodeStart, Learner, SoSmc, SoSmcConfig};
pub use named::Named;
pub use plan::{AllowedAtoms, Plan, PlanBuilder, PlanError};
pub use plan_file::{LoadError, load_plan};
