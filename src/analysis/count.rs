//! Token counts that may be unbounded (the ω of the Karp–Miller construction).
//!
//! Exploration stores counts as `u16` with [`OMEGA`] for "unboundedly many", so
//! a count above 255 (more than a [`crate::net::Marking`] stores) is never an
//! error: it becomes ω. Finite counts never exceed 255, so plain numeric order
//! on the `u16` values is the order of counts with ω above every number.

use std::fmt;

/// The internal representation of ω.
pub(super) const OMEGA: u16 = u16::MAX;

/// The token count of a place in an explored marking, or a place's bound.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Count {
    /// Exactly (or, as a bound, at most) this many tokens.
    Finite(u8),
    /// Unboundedly many: the place grows without limit (or past 255 tokens).
    Unbounded,
}

impl Count {
    /// Reads an internal count.
    pub(super) fn from_raw(raw: u16) -> Self {
        u8::try_from(raw).map_or(Count::Unbounded, Count::Finite)
    }

    /// Whether the count is above one token.
    pub(crate) fn exceeds_one(self) -> bool {
        self > Count::Finite(1)
    }
}

/// `n` for a number, `unbounded` for ω.
impl fmt::Display for Count {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Count::Finite(n) => write!(f, "{n}"),
            Count::Unbounded => f.write_str("unbounded"),
        }
    }
}

/// Adds `w` tokens to an internal count; ω absorbs, and more than 255 becomes ω.
pub(super) fn add(raw: u16, w: u8) -> u16 {
    if raw == OMEGA {
        return OMEGA;
    }
    let sum = raw + u16::from(w);
    if sum > u16::from(u8::MAX) { OMEGA } else { sum }
}

/// Removes `w` tokens from an internal count known to hold them; ω absorbs.
pub(super) fn sub(raw: u16, w: u8) -> u16 {
    if raw == OMEGA {
        OMEGA
    } else {
        raw.saturating_sub(u16::from(w))
    }
}

/// A three-valued answer for markings with ω.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Tri {
    /// Holds for every marking the ω-marking stands for.
    Yes,
    /// Holds for some of them only.
    Maybe,
    /// Holds for none.
    No,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic_saturates_to_omega() {
        assert_eq!(add(254, 1), 255);
        assert_eq!(add(255, 1), OMEGA);
        assert_eq!(add(OMEGA, 3), OMEGA);
        assert_eq!(sub(OMEGA, 3), OMEGA);
        assert_eq!(sub(3, 2), 1);
        assert_eq!(Count::from_raw(OMEGA), Count::Unbounded);
        assert_eq!(Count::from_raw(7), Count::Finite(7));
        assert!(Count::Unbounded > Count::Finite(255));
        assert!(Count::Finite(2).exceeds_one() && !Count::Finite(1).exceeds_one());
    }
}
