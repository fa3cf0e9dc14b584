//! Maximal non-conflicting sets of executable transitions.

use crate::net::{Incidence, Marking, TransitionId};

/// Reusable buffers for conflict resolution (no allocation in steady state).
#[derive(Debug, Default)]
pub(crate) struct ConflictScratch {
    demand: Vec<u16>,
    capacity: Vec<u16>,
    conflicting: Vec<TransitionId>,
    current: Vec<TransitionId>,
    /// The alternatives found, flattened: set i is `members[bounds[i].0..bounds[i].1]`.
    members: Vec<TransitionId>,
    bounds: Vec<(usize, usize)>,
    /// Executable transitions that conflict with nothing: they fire in every alternative.
    pub(crate) free: Vec<TransitionId>,
}

impl ConflictScratch {
    /// Number of alternatives found by the last [`enumerate`].
    pub(super) fn len(&self) -> usize {
        self.bounds.len()
    }

    /// Alternative `i`: the conflicting transitions it fires.
    pub(super) fn set(&self, i: usize) -> &[TransitionId] {
        let (a, b) = self.bounds[i];
        &self.members[a..b]
    }
}

/// Whether some place is asked for more tokens than it holds by `executable` together.
pub(crate) fn has_conflict(
    incidence: &Incidence,
    marking: &Marking,
    executable: &[TransitionId],
    scratch: &mut ConflictScratch,
) -> bool {
    if executable.len() < 2 {
        return false;
    }
    scratch.demand.resize(incidence.place_count(), 0);
    let mut conflict = false;
    for &t in executable {
        for a in incidence.inputs(t) {
            let d = &mut scratch.demand[a.place.index()];
            *d += u16::from(a.weight);
            conflict |= *d > u16::from(marking.get(a.place));
        }
    }
    for &t in executable {
        for a in incidence.inputs(t) {
            scratch.demand[a.place.index()] = 0;
        }
    }
    conflict
}

/// Splits `executable` into free and conflicting transitions and enumerates every
/// maximal feasible subset of the conflicting ones into `scratch.sets`.
/// Returns `false` if more than `limit` sets exist.
pub(crate) fn enumerate(
    incidence: &Incidence,
    marking: &Marking,
    executable: &[TransitionId],
    scratch: &mut ConflictScratch,
    limit: usize,
) -> bool {
    scratch.demand.resize(incidence.place_count(), 0);
    for &t in executable {
        for a in incidence.inputs(t) {
            scratch.demand[a.place.index()] += u16::from(a.weight);
        }
    }
    scratch.free.clear();
    scratch.conflicting.clear();
    for &t in executable {
        let contested = incidence
            .inputs(t)
            .iter()
            .any(|a| scratch.demand[a.place.index()] > u16::from(marking.get(a.place)));
        if contested {
            &mut scratch.conflicting
        } else {
            &mut scratch.free
        }
        .push(t);
    }
    for &t in executable {
        for a in incidence.inputs(t) {
            scratch.demand[a.place.index()] = 0;
        }
    }
    scratch.capacity.clear();
    scratch.capacity.extend(marking.tokens().iter().map(|&t| u16::from(t)));
    scratch.members.clear();
    scratch.bounds.clear();
    scratch.current.clear();
    let ConflictScratch {
        capacity,
        conflicting,
        current,
        members,
        bounds,
        ..
    } = scratch;
    let mut found = Found { members, bounds, limit };
    search(incidence, conflicting, 0, capacity, current, &mut found)
}

fn fits(incidence: &Incidence, capacity: &[u16], t: TransitionId) -> bool {
    incidence
        .inputs(t)
        .iter()
        .all(|a| capacity[a.place.index()] >= u16::from(a.weight))
}

fn take(incidence: &Incidence, capacity: &mut [u16], t: TransitionId, sign: bool) {
    for a in incidence.inputs(t) {
        let c = &mut capacity[a.place.index()];
        if sign {
            *c -= u16::from(a.weight);
        } else {
            *c += u16::from(a.weight);
        }
    }
}

/// Where the search puts the maximal sets it finds.
struct Found<'a> {
    members: &'a mut Vec<TransitionId>,
    bounds: &'a mut Vec<(usize, usize)>,
    limit: usize,
}

/// Depth-first over include/exclude of each conflicting transition; a leaf is
/// kept when no excluded transition still fits (maximality).
fn search(
    incidence: &Incidence,
    items: &[TransitionId],
    i: usize,
    capacity: &mut [u16],
    current: &mut Vec<TransitionId>,
    found: &mut Found<'_>,
) -> bool {
    if i == items.len() {
        let maximal = items
            .iter()
            .all(|t| current.contains(t) || !fits(incidence, capacity, *t));
        if maximal {
            if found.bounds.len() >= found.limit {
                return false;
            }
            let start = found.members.len();
            found.members.extend_from_slice(current);
            found.bounds.push((start, found.members.len()));
        }
        return true;
    }
    let t = items[i];
    if fits(incidence, capacity, t) {
        take(incidence, capacity, t, true);
        current.push(t);
        let ok = search(incidence, items, i + 1, capacity, current, found);
        current.pop();
        take(incidence, capacity, t, false);
        if !ok {
            return false;
        }
    }
    search(incidence, items, i + 1, capacity, current, found)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::net::{PetriNet, PlaceNode, TransitionNode};

    fn net(places: &[(&str, u8)], transitions: &[&str], arcs: &[(&str, &str, u8)]) -> (Incidence, Marking) {
        let ps = places
            .iter()
            .map(|(id, m)| PlaceNode {
                id: id.to_string(),
                label: String::new(),
                initial: *m,
                position: None,
            })
            .collect();
        let ts = transitions
            .iter()
            .map(|id| TransitionNode {
                id: id.to_string(),
                label: String::new(),
                position: None,
            })
            .collect();
        let ids: Vec<String> = (0..arcs.len()).map(|i| format!("a{i}")).collect();
        let specs: Vec<_> = arcs
            .iter()
            .zip(&ids)
            .map(|((s, t, w), id)| (id.as_str(), *s, *t, *w))
            .collect();
        let n = PetriNet::new("n", ps, ts, &specs).unwrap();
        (Incidence::new(&n), n.initial_marking())
    }

    fn sets(s: &ConflictScratch) -> Vec<Vec<TransitionId>> {
        (0..s.len()).map(|i| s.set(i).to_vec()).collect()
    }

    fn t(i: usize) -> TransitionId {
        TransitionId::new(i)
    }

    #[test]
    fn three_way_choice_and_a_free_transition() {
        // p0 (1 token) feeds t0, t1, t2; p1 (1 token) feeds t3 alone.
        let (inc, m) = net(
            &[("p0", 1), ("p1", 1)],
            &["t0", "t1", "t2", "t3"],
            &[("p0", "t0", 1), ("p0", "t1", 1), ("p0", "t2", 1), ("p1", "t3", 1)],
        );
        let exec = [t(0), t(1), t(2), t(3)];
        let mut s = ConflictScratch::default();
        assert!(has_conflict(&inc, &m, &exec, &mut s));
        assert!(enumerate(&inc, &m, &exec, &mut s, 100));
        assert_eq!(s.free, vec![t(3)]);
        assert_eq!(sets(&s), vec![vec![t(0)], vec![t(1)], vec![t(2)]]);
    }

    #[test]
    fn two_tokens_allow_pairs() {
        let (inc, m) = net(
            &[("p0", 2)],
            &["t0", "t1", "t2"],
            &[("p0", "t0", 1), ("p0", "t1", 1), ("p0", "t2", 1)],
        );
        let mut s = ConflictScratch::default();
        assert!(enumerate(&inc, &m, &[t(0), t(1), t(2)], &mut s, 100));
        assert_eq!(sets(&s), vec![vec![t(0), t(1)], vec![t(0), t(2)], vec![t(1), t(2)]]);
    }

    #[test]
    fn weighted_arcs_and_limit() {
        // t0 needs both tokens, t1 and t2 one each: maximal sets {t0} and {t1, t2}.
        let (inc, m) = net(
            &[("p0", 2)],
            &["t0", "t1", "t2"],
            &[("p0", "t0", 2), ("p0", "t1", 1), ("p0", "t2", 1)],
        );
        let mut s = ConflictScratch::default();
        assert!(enumerate(&inc, &m, &[t(0), t(1), t(2)], &mut s, 100));
        assert_eq!(sets(&s), vec![vec![t(0)], vec![t(1), t(2)]]);
        assert!(!enumerate(&inc, &m, &[t(0), t(1), t(2)], &mut s, 1));
    }

    #[test]
    fn no_conflict_when_tokens_suffice() {
        let (inc, m) = net(&[("p0", 2)], &["t0", "t1"], &[("p0", "t0", 1), ("p0", "t1", 1)]);
        let mut s = ConflictScratch::default();
        assert!(!has_conflict(&inc, &m, &[t(0), t(1)], &mut s));
    }
}
