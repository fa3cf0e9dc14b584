//! The core crate's integration tests, one binary: plans, checks, executor, schemas, learners, domains, Keepaway's plans and decisions, experiments (the Keepaway simulator's own tests are the keepaway crate's).

// Each crate's test binary includes the workspace's shared helpers; each uses a subset.
#[allow(dead_code)]
mod util;

mod analysis_check;
mod analysis_choice;
mod condition_grammar;
mod dot_export;
mod executor_semantics;
mod experiment_cycles;
mod generate_plans;
mod keepaway_decisions;
mod keepaway_plans;
mod learning_behaviour;
mod learning_reference;
mod parr_russell_optimum;
mod persist_corruption;
mod persist_roundtrip;
mod plan_fuzz;
mod plan_labels;
mod plot_svg;
mod pnml_fuzz;
mod pnml_io;
mod schema_format;
mod schema_semantics;
mod schema_thesis;
mod shipped_plans;
mod sutton_optimum;
mod values_migration;
