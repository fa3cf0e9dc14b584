//! Markings: the token count of every place.

use std::fmt;

use serde::{Deserialize, Serialize};

use super::ids::PlaceId;

/// A place would exceed the largest token count a marking stores (255).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("place #{place} would hold more than 255 tokens")]
pub struct TokenOverflow {
    /// Index of the place that overflowed.
    pub(crate) place: usize,
}

/// The token count of every place, one byte per place.
///
/// Markings are the keys of every value table, so they are kept small and flat:
/// hashing, comparing and cloning touch one contiguous byte slice. Counts above
/// 255 are refused with [`TokenOverflow`] (plans are 1-safe on execution places;
/// memory places count choices or loop passes, far below that in one episode).
#[derive(Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Marking(Box<[u8]>);

impl Marking {
    /// The empty marking over `places` places.
    pub fn empty(places: usize) -> Self {
        Marking(vec![0; places].into_boxed_slice())
    }

    /// A marking from explicit token counts.
    pub fn from_tokens(tokens: Vec<u8>) -> Self {
        Marking(tokens.into_boxed_slice())
    }

    /// Number of places.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether the net has no places.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Tokens in `place`.
    #[inline]
    pub fn get(&self, place: PlaceId) -> u8 {
        self.0[place.index()]
    }

    /// Sets the tokens in `place`.
    #[inline]
    pub fn set(&mut self, place: PlaceId, tokens: u8) {
        self.0[place.index()] = tokens;
    }

    /// Adds `tokens` to `place`, refusing overflow.
    #[inline]
    pub(crate) fn add(&mut self, place: PlaceId, tokens: u8) -> Result<(), TokenOverflow> {
        let slot = &mut self.0[place.index()];
        *slot = slot.checked_add(tokens).ok_or(TokenOverflow { place: place.index() })?;
        Ok(())
    }

    /// Removes `tokens` from `place` (saturating at zero).
    #[inline]
    pub(crate) fn remove(&mut self, place: PlaceId, tokens: u8) {
        let slot = &mut self.0[place.index()];
        *slot = slot.saturating_sub(tokens);
    }

    /// The token counts, indexed by place.
    pub fn tokens(&self) -> &[u8] {
        &self.0
    }

    /// The marked places with their counts.
    pub(crate) fn marked(&self) -> impl Iterator<Item = (PlaceId, u8)> + '_ {
        self.0
            .iter()
            .enumerate()
            .filter(|(_, t)| **t > 0)
            .map(|(i, t)| (PlaceId::new(i), *t))
    }

    /// Total number of tokens.
    pub fn total(&self) -> u32 {
        self.0.iter().map(|&t| u32::from(t)).sum()
    }

    /// Whether every place holds at least as many tokens as in `other`.
    pub fn covers(&self, other: &Marking) -> bool {
        self.0.len() == other.0.len() && self.0.iter().zip(other.0.iter()).all(|(a, b)| a >= b)
    }
}

impl fmt::Debug for Marking {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Marking({self})")
    }
}

/// Lists the marked places as `p<index>:<tokens>`, or `-` when empty.
impl fmt::Display for Marking {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for (p, t) in self.marked() {
            if !first {
                f.write_str(" ")?;
            }
            first = false;
            write!(f, "p{}:{}", p.index(), t)?;
        }
        if first {
            f.write_str("-")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn add_refuses_overflow() {
        let mut m = Marking::empty(2);
        m.set(PlaceId::new(1), 250);
        assert!(m.add(PlaceId::new(1), 5).is_ok());
        assert_eq!(m.add(PlaceId::new(1), 1), Err(TokenOverflow { place: 1 }));
        assert_eq!(m.get(PlaceId::new(1)), 255);
    }

    #[test]
    fn display_lists_marked_places() {
        let m = Marking::from_tokens(vec![0, 1, 0, 2]);
        assert_eq!(m.to_string(), "p1:1 p3:2");
        assert_eq!(Marking::empty(3).to_string(), "-");
        assert_eq!(m.total(), 3);
    }

    #[test]
    fn covers_is_pointwise() {
        let a = Marking::from_tokens(vec![1, 2]);
        let b = Marking::from_tokens(vec![1, 1]);
        assert!(a.covers(&b));
        assert!(!b.covers(&a));
    }
}
