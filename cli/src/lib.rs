//! The command-line side of learnpnp: the flags that `learnpnp experiment` and
//! the multi-process supervisor share ([`args`]), and stopping long work on a
//! signal ([`interrupt`]), the live view's flags ([`view`]). The library itself is the `learnpnp` crate.

#![deny(missing_docs)]

pub mod args;
pub mod interrupt;
pub mod view;
