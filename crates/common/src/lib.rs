//! What every learnpnp crate shares: seeded, reproducible random numbers
//! ([`rng`]) and enumerations a user picks by name ([`named`]). The `learnpnp`
//! crate re-exports both (`learnpnp::rng`, `learnpnp::named`).

#![deny(missing_docs)]

/// Enumerations a user picks by name.
pub mod named;
/// Seeded, reproducible random numbers.
pub mod rng;
