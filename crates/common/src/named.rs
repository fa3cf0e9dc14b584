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
