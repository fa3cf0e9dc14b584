//! The knowledge base a plan asks, and the atoms a domain declares.

use std::collections::HashMap;

use serde::{Deserialize, Serialize};

/// Index of an atom in its domain's [`AtomTable`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct AtomId(pub u32);

impl AtomId {
    /// Its index.
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

/// Answers atoms: the agent's beliefs about the world, kept up to date by its perception.
pub trait KnowledgeBase {
    /// Whether the knowledge base entails `atom`.
    fn holds(&self, atom: AtomId) -> bool;
}

/// The atoms a domain knows, by name. Plans using any other atom are refused.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct AtomTable {
    names: Vec<String>,
    #[serde(skip)]
    index: HashMap<String, AtomId>,
}

impl AtomTable {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }

    /// The id of `name`, adding it if new.
    pub fn intern(&mut self, name: &str) -> AtomId {
        if let Some(&id) = self.index.get(name) {
            return id;
        }
        let id = AtomId(self.names.len() as u32);
        self.names.push(name.to_string());
        self.index.insert(name.to_string(), id);
        id
    }

    /// The id of `name`, if declared.
    pub fn get(&self, name: &str) -> Option<AtomId> {
        self.index.get(name).copied()
    }

    /// The name of `id`.
    pub fn name(&self, id: AtomId) -> &str {
        &self.names[id.index()]
    }

    /// Number of atoms.
    pub fn len(&self) -> usize {
        self.names.len()
    }

    /// Whether no atom is declared.
    pub fn is_empty(&self) -> bool {
        self.names.is_empty()
    }

    /// Every atom name in id order.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.names.iter().map(String::as_str)
    }
}

impl<'a> FromIterator<&'a str> for AtomTable {
    fn from_iter<I: IntoIterator<Item = &'a str>>(iter: I) -> Self {
        let mut table = AtomTable::new();
        for name in iter {
            table.intern(name);
        }
        table
    }
}

/// A knowledge base of independent boolean facts, one bit per atom.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BitKnowledgeBase {
    words: Vec<u64>,
}

impl BitKnowledgeBase {
    /// All atoms false, for a table of `atoms` atoms.
    pub fn new(atoms: usize) -> Self {
        BitKnowledgeBase {
            words: vec![0; atoms.div_ceil(64).max(1)],
        }
    }

    /// Sets the truth of `atom` (atoms beyond the table are ignored).
    #[inline]
    pub fn set(&mut self, atom: AtomId, value: bool) {
        let (w, b) = (atom.index() / 64, atom.index() % 64);
        if let Some(word) = self.words.get_mut(w) {
            if value {
                *word |= 1 << b;
            } else {
                *word &= !(1 << b);
            }
        }
    }

    /// Makes every atom false.
    pub(crate) fn clear(&mut self) {
        self.words.iter_mut().for_each(|w| *w = 0);
    }
}

impl KnowledgeBase for BitKnowledgeBase {
    #[inline]
    fn holds(&self, atom: AtomId) -> bool {
        let (w, b) = (atom.index() / 64, atom.index() % 64);
        self.words.get(w).is_some_and(|word| word & (1 << b) != 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interns_once() {
        let mut t: AtomTable = ["a", "b"].into_iter().collect();
        assert_eq!(t.intern("a"), AtomId(0));
        assert_eq!(t.intern("c"), AtomId(2));
        assert_eq!(t.get("b"), Some(AtomId(1)));
        assert_eq!(t.get("z"), None);
        assert_eq!(t.name(AtomId(2)), "c");
    }

    #[test]
    fn bits_hold() {
        let mut kb = BitKnowledgeBase::new(70);
        kb.set(AtomId(69), true);
        kb.set(AtomId(3), true);
        kb.set(AtomId(3), false);
        assert!(kb.holds(AtomId(69)));
        assert!(!kb.holds(AtomId(3)));
        assert!(!kb.holds(AtomId(500)));
    }
}
