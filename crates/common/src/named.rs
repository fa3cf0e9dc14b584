//! Enumerations a user picks by name (on the command line, from Python): every
//! value, its kebab-case name, and the value of a name.

use thiserror::Error;

/// A name that is none of an enumeration's values.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown {kind} '{given}' (expected one of: {expected})")]
pub struct UnknownName {
    /// What was named (`"algorithm"`, `"domain"`, ...).
    pub(crate) kind: &'static str,
    /// The name given.
    pub(crate) given: String,
    /// The names that exist, comma-separated.
    pub(crate) expected: String,
}

/// An enumeration whose values have names.
pub trait Named: Sized + Copy + 'static {
    /// What a value is called in messages (`"algorithm"`).
    const KIND: &'static str;
    /// Every value, in the order shown to users.
    const ALL: &'static [Self];

    /// The value's name.
    fn name(self) -> &'static str;

    /// The value called `name`.
    fn from_name(name: &str) -> Result<Self, UnknownName> {
        Self::ALL
            .iter()
            .copied()
            .find(|v| v.name() == name)
            .ok_or_else(|| UnknownName {
                kind: Self::KIND,
                given: name.to_string(),
                expected: Self::ALL.iter().map(|v| v.name()).collect::<Vec<_>>().join(", "),
            })
    }
}

/// Implements [`Named`] for enumeration `$ty` from one list: what a value is
/// called, then every value with its name, in the order shown to users.
///
/// ```
/// # use learnpnp_common::named::{Named, impl_named};
/// #[derive(Debug, Clone, Copy, PartialEq)]
/// enum Weather {
///     Sunny,
///     Rainy,
/// }
/// impl_named!(Weather, "weather", [Sunny => "sunny", Rainy => "rainy"]);
/// assert_eq!(Weather::from_name("rainy"), Ok(Weather::Rainy));
/// assert_eq!(Weather::ALL, [Weather::Sunny, Weather::Rainy]);
/// ```
#[doc(hidden)]
#[macro_export]
macro_rules! __impl_named {
    ($ty:ident, $kind:literal, [$($value:ident => $name:literal),+ $(,)?]) => {
        impl $crate::named::Named for $ty {
            const KIND: &'static str = $kind;
            const ALL: &'static [Self] = &[$($ty::$value),+];

            fn name(self) -> &'static str {
                match self {
                    $($ty::$value => $name,)+
                }
            }
        }
    };
}

/// Implements [`Named`] for an enumeration from one list of its values and their names.
pub use crate::__impl_named as impl_named;
