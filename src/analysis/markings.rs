//! The markings of an exploration, stored sparsely.
//!
//! A marking is stored as the list of its marked places with their counts,
//! in place order, so that what it costs follows its tokens and not the
//! plan's places: a plan of ten thousand places whose markings hold a few
//! tokens stores a few entries per marking. An open-addressing index (one
//! `u32` per slot, at most half full) finds the number of a stored marking
//! without keeping a second copy of it.

use std::hash::Hasher as _;

use rustc_hash::FxHasher;

use super::count::{OMEGA, Tri};
use crate::net::PlaceId;

/// A marked place and its count (never 0; [`OMEGA`] for unboundedly many).
pub(super) type Entry = (PlaceId, u16);

/// The count of `place` in the sparse marking `marking` (0 when absent).
pub(super) fn count(marking: &[Entry], place: PlaceId) -> u16 {
    marking
        .binary_search_by_key(&place, |&(p, _)| p)
        .map_or(0, |i| marking[i].1)
}

/// The token total with ω counted as 256: strictly monotone in every place.
pub(super) fn weighted_total(marking: &[Entry]) -> u32 {
    marking
        .iter()
        .map(|&(_, t)| if t == OMEGA { 256 } else { u32::from(t) })
        .sum()
}

/// Stored markings, numbered in order of storage, with an index from marking to number.
#[derive(Debug, Clone)]
pub(super) struct Markings {
    /// `entries[start[i]..start[i + 1]]` is marking `i`.
    start: Vec<usize>,
    entries: Vec<Entry>,
    /// Marking number + 1, or 0 for a free slot; the length is a power of two.
    slots: Vec<u32>,
}

fn hash(marking: &[Entry]) -> u64 {
    let mut hasher = FxHasher::default();
    for &(p, t) in marking {
        hasher.write_u32(p.index() as u32);
        hasher.write_u16(t);
    }
    hasher.finish()
}

impl Markings {
    /// No marking stored.
    pub(super) fn new() -> Self {
        Markings {
            start: vec![0],
            entries: Vec::new(),
            slots: vec![0; 16],
        }
    }

    /// Number of stored markings.
    pub(super) fn len(&self) -> usize {
        self.start.len() - 1
    }

    /// Marking `i`.
    pub(super) fn get(&self, i: usize) -> &[Entry] {
        &self.entries[self.start[i]..self.start[i + 1]]
    }

    /// Every stored entry, marking after marking.
    pub(super) fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// The first slot of `marking`'s probe sequence holding it or free.
    fn slot(&self, marking: &[Entry]) -> usize {
        let mask = self.slots.len() - 1;
        let mut at = hash(marking) as usize & mask;
        loop {
            match self.slots[at] {
                0 => return at,
                n if self.get(n as usize - 1) == marking => return at,
                _ => at = (at + 1) & mask,
            }
        }
    }

    /// The number of `marking`, if stored.
    pub(super) fn find(&self, marking: &[Entry]) -> Option<usize> {
        match self.slots[self.slot(marking)] {
            0 => None,
            n => Some(n as usize - 1),
        }
    }

    /// Stores `marking` (not stored yet) and returns its number.
    pub(super) fn insert(&mut self, marking: &[Entry]) -> usize {
        let id = self.len();
        if 2 * (id + 1) > self.slots.len() {
            self.grow();
        }
        let at = self.slot(marking);
        self.entries.extend_from_slice(marking);
        self.start.push(self.entries.len());
        self.slots[at] = u32::try_from(id + 1).expect("fewer markings than u32::MAX (the memory limit stops first)");
        id
    }

    /// Doubles the index and places every marking again.
    fn grow(&mut self) {
        self.slots = vec![0; 2 * self.slots.len()];
        for i in 0..self.len() {
            let at = self.slot(self.get(i));
            self.slots[at] = i as u32 + 1;
        }
    }

    /// Bytes allocated for the markings and their index.
    pub(super) fn bytes(&self) -> usize {
        self.start.capacity() * size_of::<usize>()
            + self.entries.capacity() * size_of::<Entry>()
            + self.slots.capacity() * size_of::<u32>()
    }
}

/// Whether the sparse `marking` has exactly the required count on every
/// listed place (the goal or fail test); a plan with no such places never matches.
pub(super) fn matches(required: &[(PlaceId, u8)], marking: &[Entry]) -> Tri {
    if required.is_empty() {
        return Tri::No;
    }
    let mut answer = Tri::Yes;
    for &(p, n) in required {
        match count(marking, p) {
            OMEGA => answer = Tri::Maybe,
            raw if raw == u16::from(n) => {}
            _ => return Tri::No,
        }
    }
    answer
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(entries: &[(usize, u16)]) -> Vec<Entry> {
        entries.iter().map(|&(p, t)| (PlaceId::new(p), t)).collect()
    }

    #[test]
    fn stored_markings_are_found_by_content_across_growth() {
        let mut store = Markings::new();
        let all: Vec<Vec<Entry>> = (0..100).map(|i| m(&[(i, 1), (i + 1000, 2)])).collect();
        for (i, marking) in all.iter().enumerate() {
            assert_eq!(store.find(marking), None);
            assert_eq!(store.insert(marking), i);
        }
        assert_eq!(store.insert(&[]), 100);
        for (i, marking) in all.iter().enumerate() {
            assert_eq!(store.find(marking), Some(i));
            assert_eq!(store.get(i), &marking[..]);
        }
        assert_eq!(store.find(&[]), Some(100));
        assert_eq!(store.find(&m(&[(0, 2), (1000, 2)])), None);
        assert_eq!(store.len(), 101);
        assert!(store.bytes() >= 201 * size_of::<Entry>());
    }

    #[test]
    fn counts_and_totals_read_the_sparse_form() {
        let marking = m(&[(2, 1), (5, OMEGA), (9, 3)]);
        assert_eq!(count(&marking, PlaceId::new(5)), OMEGA);
        assert_eq!(count(&marking, PlaceId::new(4)), 0);
        assert_eq!(weighted_total(&marking), 260);
    }

    #[test]
    fn goal_test_is_three_valued() {
        let req = [(PlaceId::new(0), 1), (PlaceId::new(1), 2)];
        let marking = |a, b| [(PlaceId::new(0), a), (PlaceId::new(1), b)];
        assert_eq!(matches(&req, &marking(1, 2)), Tri::Yes);
        assert_eq!(matches(&req, &marking(1, OMEGA)), Tri::Maybe);
        assert_eq!(matches(&req, &[(PlaceId::new(1), OMEGA)]), Tri::No);
        assert_eq!(matches(&[], &marking(1, 2)), Tri::No);
    }
}
