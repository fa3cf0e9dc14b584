//! Experiments: statistics over independent runs and the plots of their results.

pub mod plot;
pub mod stats;
