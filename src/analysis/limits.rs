//! What an exploration may use, and which limit stopped it.
//!
//! Two limits bound an exploration: the number of markings it stores, and the
//! bytes its markings, edges and index take together with the bookkeeping the
//! checks add over them. Both are counted as the exploration goes, so the
//! exploration stops at whichever is reached first and says which.

use std::fmt;

/// The marking limit `check` uses unless told otherwise: large enough for the
/// shipped plans and for generated ones of ten thousand places.
pub const DEFAULT_LIMIT: usize = 1_000_000;

/// The memory an exploration (and the checks over it) may use unless told
/// otherwise: 256 MiB.
pub const MEMORY_LIMIT: usize = 256 << 20;

/// Bytes the checks add for every stored marking (the predecessor index and
/// the flags they keep per marking).
pub(super) const CHECK_STATE_BYTES: usize = 16;

/// Bytes the checks add for every stored edge (its entry in the predecessor index).
pub(super) const CHECK_EDGE_BYTES: usize = 4;

/// The bounds of one exploration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// The most markings stored (each independent part stores at least its
    /// initial marking, even beyond this).
    pub markings: usize,
    /// The most bytes the stored markings, edges and index may take, with the
    /// checks' bookkeeping over them.
    pub memory: usize,
}

impl Limits {
    /// At most `markings` markings (at least one), within [`MEMORY_LIMIT`].
    pub fn markings(markings: usize) -> Self {
        Limits {
            markings: markings.max(1),
            memory: MEMORY_LIMIT,
        }
    }
}

/// The limit that ended an exploration before every reachable marking was stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The stored markings reached the marking limit.
    Markings {
        /// The marking limit.
        limit: usize,
    },
    /// The stored markings and edges, with the checks' bookkeeping, reached
    /// the memory limit.
    Memory {
        /// The memory limit, in bytes.
        limit: usize,
        /// The markings stored when it was reached.
        markings: usize,
        /// The edges stored when it was reached.
        edges: usize,
    },
}

impl Stop {
    /// `markings` or `memory`: which limit, for tools.
    pub fn name(self) -> &'static str {
        match self {
            Stop::Markings { .. } => "markings",
            Stop::Memory { .. } => "memory",
        }
    }
}

/// `marking limit of N`, or `memory limit of M MiB (N markings and E edges stored)`.
impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stop::Markings { limit } => write!(f, "marking limit of {limit}"),
            Stop::Memory { limit, markings, edges } => write!(
                f,
                "memory limit of {} MiB ({markings} markings and {edges} edges stored)",
                limit >> 20
            ),
        }
    }
}

/// What the parts explored so far have used, against the [`Limits`].
#[derive(Debug, Clone, Copy)]
pub(super) struct Budget {
    pub(super) limits: Limits,
    /// Markings stored by the finished parts.
    pub(super) markings: usize,
    /// Edges stored by the finished parts.
    pub(super) edges: usize,
    /// Bytes taken by the finished parts, bookkeeping included.
    pub(super) bytes: usize,
}

impl Budget {
    /// Nothing used yet.
    pub(super) fn new(limits: Limits) -> Self {
        Budget {
            limits,
            markings: 0,
            edges: 0,
            bytes: 0,
        }
    }

    /// The limit a part storing `markings` markings and `edges` edges in
    /// `bytes` bytes (bookkeeping included) has reached, on top of the
    /// finished parts, if any. `adding` says a new marking is about to be
    /// stored (the marking limit is then reached one marking earlier).
    pub(super) fn reached(&self, markings: usize, edges: usize, bytes: usize, adding: bool) -> Option<Stop> {
        let markings = self.markings + markings;
        if adding && markings >= self.limits.markings {
            return Some(Stop::Markings {
                limit: self.limits.markings,
            });
        }
        (self.bytes + bytes > self.limits.memory).then_some(Stop::Memory {
            limit: self.limits.memory,
            markings,
            edges: self.edges + edges,
        })
    }
}
