//! The command-line side of learnpnp: the flags that `learnpnp experiment` and
//! the multi-process supervisor share ([`args`]), and stopping long work on a
//! signal ([`interrupt`]), the live view's flags ([`view`]). The library itself is the `learnpnp` crate.

#![deny(missing_docs)]

/// The experiment's and the supervisor's flags: `ExperimentOptions`.
pub mod args;
/// Stopping long work on Ctrl-C or SIGTERM without losing what is done.
pub mod interrupt;
/// The live view's flags, shared by `learnpnp experiment` and the supervisor.
pub mod view;
