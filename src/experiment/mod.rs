//! Experiments: the thesis's protocol over many seeded runs, with CSV, JSON
//! and SVG results.

pub mod checkpoint;
/// The thesis's parameters as defaults, and a user's overrides.
pub mod defaults;
pub mod options;
pub mod output;
/// SVG plots of experiment results.
pub mod plot;
/// The thesis's figures as experiment presets.
pub mod presets;
/// How far a reproduction has come, and how long the rest will take.
pub mod progress;
pub mod ranges;
/// The table of reproduced figures.
pub mod report;
pub mod result_dir;
/// Running the runs of an experiment in parallel, reproducibly.
pub mod runner;
pub mod shard;
/// What an experiment runs.
pub mod spec;
pub(crate) mod stats;
mod watched;
