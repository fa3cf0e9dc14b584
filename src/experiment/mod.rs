//! Experiments: the thesis's protocol over many seeded runs, with CSV, JSON
//! and SVG results.

/// The completed runs of an interrupted experiment, for `--resume`.
pub mod checkpoint;
/// The thesis's parameters as defaults, and a user's overrides.
pub mod defaults;
/// The options of an experiment as a user states them.
pub mod options;
/// Writing an experiment's results.
pub mod output;
/// SVG plots of experiment results.
pub mod plot;
/// The thesis's figures as experiment presets.
pub mod presets;
/// How far a reproduction has come, and how long the rest will take.
pub mod progress;
/// The valid range of every numeric experiment parameter.
pub mod ranges;
/// The table of reproduced figures.
pub mod report;
/// Result directories: a set of files published whole.
pub mod result_dir;
/// Running the runs of an experiment in parallel, reproducibly.
pub mod runner;
/// Experiments sharded across machines.
pub mod shard;
/// What an experiment runs.
pub mod spec;
pub(crate) mod stats;
/// The verdict table: each claim of the thesis checked on the reproduced curves.
pub mod verdict;
mod watched;
