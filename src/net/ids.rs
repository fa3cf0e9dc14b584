//! The indices of a net's places and transitions.

use serde::{Deserialize, Serialize};

/// Index of a place in its net.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PlaceId(u32);

impl PlaceId {
    /// The place at `index`.
    pub const fn new(index: usize) -> Self {
        PlaceId(index as u32)
    }

    /// Its index.
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

/// Index of a transition in its net.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct TransitionId(u32);

impl TransitionId {
    /// The transition at `index`.
    pub const fn new(index: usize) -> Self {
        TransitionId(index as u32)
    }

    /// Its index.
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}
