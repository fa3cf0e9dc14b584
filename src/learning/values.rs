//! Value tables keyed by (plan, marking).

use rustc_hash::FxHashMap;
use serde::{Deserialize, Serialize};

use crate::executor::PlanKey;
use crate::net::Marking;

/// Dense index of a key in a [`ValueTable`].
pub type KeyId = u32;

/// A state key: a marking of one plan of the activation tree.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct StateKey {
    /// Which plan.
    pub plan: PlanKey,
    /// Its marking.
    pub marking: Marking,
}

/// Values (and visit counts) per marking, with dense ids for fast updates.
///
/// A value of negative infinity means "no estimate yet" (pessimistic
/// initialisation): greedy choices avoid it while anything else is known, and
/// the first sample replaces it.
#[derive(Debug, Clone)]
pub struct ValueTable {
    initial: f64,
    index: Vec<FxHashMap<Marking, KeyId>>,
    keys: Vec<StateKey>,
    values: Vec<f64>,
    visits: Vec<u64>,
}

impl ValueTable {
    /// An empty table whose new entries start at `initial`.
    pub fn new(initial: f64) -> Self {
        ValueTable {
            initial,
            index: Vec::new(),
            keys: Vec::new(),
            values: Vec::new(),
            visits: Vec::new(),
        }
    }

    /// The value new entries start at.
    pub fn initial_value(&self) -> f64 {
        self.initial
    }

    /// The id of a key, if present.
    #[inline]
    pub(crate) fn find(&self, plan: PlanKey, marking: &Marking) -> Option<KeyId> {
        self.index
            .get(usize::from(plan.0))
            .and_then(|m| m.get(marking))
            .copied()
    }

    /// The id of a key, adding it (at the initial value) if new.
    #[inline]
    pub(crate) fn intern(&mut self, plan: PlanKey, marking: &Marking) -> KeyId {
        if let Some(id) = self.find(plan, marking) {
            return id;
        }
        self.insert(
            StateKey {
                plan,
                marking: marking.clone(),
            },
            self.initial,
            0,
        )
    }

    /// The ids and values of a choice's options (next markings of `plan`),
    /// interning the new ones, into reusable buffers.
    pub(crate) fn intern_options(
        &mut self,
        plan: PlanKey,
        options: &[Marking],
        ids: &mut Vec<KeyId>,
        values: &mut Vec<f64>,
    ) {
        ids.clear();
        values.clear();
        for m in options {
            let id = self.intern(plan, m);
            ids.push(id);
            values.push(self.value(id));
        }
    }

    /// Adds a key with a value and visit count (replacing an existing value).
    pub fn insert(&mut self, key: StateKey, value: f64, visits: u64) -> KeyId {
        let plan = usize::from(key.plan.0);
        if self.index.len() <= plan {
            self.index.resize_with(plan + 1, FxHashMap::default);
        }
        if let Some(&id) = self.index[plan].get(&key.marking) {
            self.values[id as usize] = value;
            self.visits[id as usize] = visits;
            return id;
        }
        let id = self.keys.len() as KeyId;
        self.index[plan].insert(key.marking.clone(), id);
        self.keys.push(key);
        self.values.push(value);
        self.visits.push(visits);
        id
    }

    /// The value of an id.
    #[inline]
    pub fn value(&self, id: KeyId) -> f64 {
        self.values[id as usize]
    }

    /// The value of a key, or the initial value if unknown.
    pub fn value_of(&self, plan: PlanKey, marking: &Marking) -> f64 {
        self.find(plan, marking).map_or(self.initial, |id| self.value(id))
    }

    /// Sets the value of an id.
    #[inline]
    pub fn set(&mut self, id: KeyId, value: f64) {
        self.values[id as usize] = value;
    }

    /// Counts one update of an id.
    #[inline]
    pub(crate) fn visit(&mut self, id: KeyId) {
        self.visits[id as usize] += 1;
    }

    /// Updates of an id so far.
    pub(crate) fn visits(&self, id: KeyId) -> u64 {
        self.visits[id as usize]
    }

    /// The key of an id.
    pub fn key(&self, id: KeyId) -> &StateKey {
        &self.keys[id as usize]
    }

    /// Number of keys.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Whether the table is empty.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Every (key, value, visits) in id order.
    pub fn entries(&self) -> impl Iterator<Item = (&StateKey, f64, u64)> {
        self.keys
            .iter()
            .zip(&self.values)
            .zip(&self.visits)
            .map(|((k, v), n)| (k, *v, *n))
    }
}

/// Moves `value` toward `sample` by `alpha`; a missing estimate takes the sample.
#[inline]
pub fn blend(value: f64, sample: f64, alpha: f64) -> f64 {
    if value.is_finite() {
        value + alpha * (sample - value)
    } else {
        sample
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn intern_and_update() {
        let mut t = ValueTable::new(-4.0);
        let m = Marking::from_tokens(vec![1, 0]);
        let a = t.intern(PlanKey::ROOT, &m);
        assert_eq!(t.intern(PlanKey::ROOT, &m), a);
        let b = t.intern(PlanKey(1), &m);
        assert_ne!(a, b);
        assert_eq!(t.value(a), -4.0);
        t.set(a, 2.0);
        assert_eq!(t.value_of(PlanKey::ROOT, &m), 2.0);
        assert_eq!(t.value_of(PlanKey(3), &m), -4.0);
        assert_eq!(t.len(), 2);
    }

    #[test]
    fn blend_replaces_missing_estimates() {
        assert_eq!(blend(f64::NEG_INFINITY, 3.0, 0.1), 3.0);
        assert!((blend(1.0, 3.0, 0.5) - 2.0).abs() < 1e-12);
    }
}
