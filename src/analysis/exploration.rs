//! One exploration of a plan, read by every check: the explored graphs of its
//! independent parts ([`super::parts`]) and how they combine into the plan's
//! reachable markings.
//!
//! A marking of the plan is one marking of each part; it is reachable when
//! each of them is (the parts share no place, and the ending part's initial
//! marking is not terminal, or the plan is one part). So the plan's reachable
//! markings are counted as a product, and a combined marking is reached by
//! firing the free parts' traces first, then the ending part's.

use super::count::Count;
use super::limits::{Budget, Limits, Stop};
use super::markings::Entry;
use super::parts;
use super::reachability::{Reachability, StateId, describe};
use crate::net::{PlaceId, TransitionId};
use crate::plan::Plan;

/// The reachable markings of a plan, explored part by part.
#[derive(Debug, Clone)]
pub struct Exploration {
    parts: Vec<Reachability>,
    /// The part of every place.
    place_part: Vec<u32>,
    /// The part of every transition.
    transition_part: Vec<u32>,
    limit: usize,
    stop: Option<Stop>,
}

/// A marking of the plan made of one explored marking of each part, with a
/// firing sequence reaching it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Combined {
    /// Its marked places and their counts, in place order.
    pub(super) marking: Vec<Entry>,
    /// Transitions fired from the plan's initial marking.
    pub(super) trace: Vec<TransitionId>,
}

impl Combined {
    /// The marking as the labels of its marked places.
    pub(super) fn describe(&self, plan: &Plan) -> String {
        describe(plan, &self.marking)
    }
}

/// Explores the markings reachable from `plan`'s initial marking, part by
/// part, storing at most `limit` markings (at least each part's initial one)
/// within [`super::MEMORY_LIMIT`].
pub fn explore(plan: &Plan, limit: usize) -> Exploration {
    explore_within(plan, Limits::markings(limit))
}

/// [`explore`] within `limits`. Parts are explored in order (the ending part
/// first); once a limit is reached, the parts left keep their initial marking
/// only, unexpanded.
pub fn explore_within(plan: &Plan, limits: Limits) -> Exploration {
    explore_parts(plan, limits, parts::parts(plan))
}

/// The whole plan explored as one part, as it was before parts (the tests
/// compare the two).
#[cfg(test)]
pub(super) fn explore_whole(plan: &Plan, limits: Limits) -> Exploration {
    explore_parts(plan, limits, vec![parts::whole(plan)])
}

/// Explores `parts` of `plan` in order within `limits`.
fn explore_parts(plan: &Plan, limits: Limits, parts: Vec<parts::Part>) -> Exploration {
    // State numbers are u32: never store more markings than they count.
    let limits = Limits {
        markings: limits.markings.clamp(1, u32::MAX as usize - 1),
        memory: limits.memory,
    };
    let incidence = plan.incidence();
    let mut exploration = Exploration {
        parts: Vec::new(),
        place_part: vec![0; incidence.place_count()],
        transition_part: vec![0; incidence.transition_count()],
        limit: limits.markings,
        stop: None,
    };
    let mut budget = Budget::new(limits);
    for (i, part) in parts.into_iter().enumerate() {
        let mut graph = Reachability::start(plan, &part);
        if exploration.stop.is_none() {
            exploration.stop = graph.expand(plan, &budget);
        }
        budget.markings += graph.len();
        budget.edges += graph.edge_count();
        budget.bytes += graph.bytes();
        for p in &part.places {
            exploration.place_part[p.index()] = i as u32;
        }
        for t in &part.transitions {
            exploration.transition_part[t.index()] = i as u32;
        }
        exploration.parts.push(graph);
    }
    exploration
}

/// The product of `counts`, saturating at `usize::MAX`.
pub(super) fn product(counts: impl IntoIterator<Item = usize>) -> usize {
    counts.into_iter().fold(1, usize::saturating_mul)
}

impl Exploration {
    /// The explored parts: the ending part first (see [`Reachability::is_ending`]), then the free ones.
    pub fn parts(&self) -> &[Reachability] {
        &self.parts
    }

    /// The index of the part holding `place`.
    pub(super) fn part_index(&self, place: PlaceId) -> usize {
        self.place_part[place.index()] as usize
    }

    /// The part holding `place`.
    pub fn part_of(&self, place: PlaceId) -> &Reachability {
        &self.parts[self.part_index(place)]
    }

    /// The part holding transition `t`.
    pub(crate) fn part_of_transition(&self, t: TransitionId) -> &Reachability {
        &self.parts[self.transition_part[t.index()] as usize]
    }

    /// The part holding the goal and fail places, if the plan has any.
    pub(crate) fn ending(&self) -> Option<&Reachability> {
        self.parts.first().filter(|p| p.is_ending())
    }

    /// The number of reachable markings of the plan: the product of the
    /// parts' explored markings (saturating at `usize::MAX`; only those
    /// explored when the exploration is incomplete).
    pub fn markings(&self) -> usize {
        product(self.parts.iter().map(Reachability::len))
    }

    /// The number of markings stored, over all parts.
    pub(crate) fn stored(&self) -> usize {
        self.parts.iter().map(Reachability::len).sum()
    }

    /// The number of edges stored, over all parts.
    pub fn edges(&self) -> usize {
        self.parts.iter().map(Reachability::edge_count).sum()
    }

    /// The marking limit it ran with.
    pub fn limit(&self) -> usize {
        self.limit
    }

    /// The limit that stopped it, if one did.
    pub fn stop(&self) -> Option<Stop> {
        self.stop
    }

    /// Whether every reachable marking was explored (no limit was hit).
    pub(crate) fn is_complete(&self) -> bool {
        self.stop.is_none()
    }

    /// The largest count of every place over the explored markings (a lower
    /// bound when the exploration is incomplete).
    pub(crate) fn bounds(&self) -> Vec<Count> {
        let mut max = vec![0u16; self.place_part.len()];
        for part in &self.parts {
            for &(p, n) in part.all_entries() {
                max[p.index()] = max[p.index()].max(n);
            }
        }
        max.into_iter().map(Count::from_raw).collect()
    }

    /// The plan's marking made of the states `picks` (part index and state)
    /// and the initial marking of every other part, with a firing sequence:
    /// the free parts' traces, then the ending part's.
    pub(super) fn combine(&self, picks: &[(usize, StateId)]) -> Combined {
        let state = |i: usize| {
            picks
                .iter()
                .find(|&&(part, _)| part == i)
                .map_or(StateId::initial(), |&(_, s)| s)
        };
        let mut marking: Vec<Entry> = Vec::new();
        let mut trace = Vec::new();
        let order = (1..self.parts.len()).chain(0..1.min(self.parts.len()));
        for i in order {
            let part = &self.parts[i];
            marking.extend_from_slice(part.entries(state(i)));
            trace.extend(part.trace(state(i)));
        }
        marking.sort_unstable();
        Combined { marking, trace }
    }
}
