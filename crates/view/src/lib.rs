//! The live view of a learnpnp run.
