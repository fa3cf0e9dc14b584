//! Experiments: the thesis's protocol over many seeded runs, with CSV, JSON
//! and SVG results.

pub mod checkpoint;
pub mod defaults;
pub mod options;
pub mod output;
pub mod plot;
pub mod presets;
pub mod progress;
pub mod ranges;
pub mod report;
pub mod result_dir;
pub mod runner;
pub mod shard;
pub mod spec;
pub(crate) mod stats;
mod watched;
