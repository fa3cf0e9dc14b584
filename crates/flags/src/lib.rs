//! The command-line pieces learnpnp's binaries share: the flags that `learnpnp
//! experiment` and the multi-process supervisor share ([`args`]), stopping
//! long work on a signal ([`interrupt`]), the live view's flags ([`view`]).
//! It does not depend on the view's server (`learnpnp-view`): the supervisor,
//! which only passes the view's flags on to the view's process, builds
//! without it. The library itself is the `learnpnp` crate.

#![deny(missing_docs)]

/// The experiment's and the supervisor's flags: `ExperimentOptions`.
pub mod args;
/// Stopping long work on Ctrl-C or SIGTERM without losing what is done.
pub mod interrupt;
/// The live view's flags, shared by `learnpnp experiment` and the supervisor.
pub mod view;
