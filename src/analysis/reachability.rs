//! The markings one part of a plan can reach, guards ignored, with unbounded
//! places accelerated.
//!
//! Every guard may be true or false, so every token-enabled transition may fire
//! (interleaving semantics: one transition per edge). Goal and fail markings are
//! terminal, as in the executor, which stops there. A new marking that strictly
//! covers one of its ancestors makes the grown places unbounded (Karp–Miller):
//! they become ω and the exploration terminates. The result is then a
//! coverability graph: an ω-marking stands for reachable markings that agree on
//! its finite places and hold arbitrarily many tokens in its ω places.
//!
//! Markings are stored sparsely ([`super::markings`]), and a marking's
//! successors are found from the transitions that consume its marked places
//! (plus those with no input place), so exploring a marking costs what its
//! tokens touch, not what the plan holds.

use super::count::{self, OMEGA};
use super::limits::{Budget, CHECK_EDGE_BYTES, CHECK_STATE_BYTES, Stop};
use super::markings::{self, Entry, Markings, weighted_total};
use super::parts::{self, Part};
use crate::net::{Incidence, Marking, PlaceId, TransitionId};
use crate::plan::Plan;

/// Index of an explored marking in its part (the initial marking is state 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct StateId(u32);

impl StateId {
    /// Its index, in order of discovery (breadth first).
    pub const fn index(self) -> usize {
        self.0 as usize
    }

    /// The initial marking of a part.
    pub(super) const fn initial() -> Self {
        StateId(0)
    }
}

/// The explored markings of one part of a plan (see [`super::Exploration`])
/// and the transitions between them. Its markings hold tokens in the part's
/// places only.
#[derive(Debug, Clone)]
pub struct Reachability {
    /// Places of the whole plan (the length of a [`Marking`]).
    places: usize,
    markings: Markings,
    /// Token totals with ω counted as 256 (a quick test for strict covering).
    totals: Vec<u32>,
    /// The least total of each state and its ancestors: no ancestor can be
    /// strictly covered by a marking whose total is not above it.
    floors: Vec<u32>,
    /// How each state was first reached.
    parent: Vec<Option<(StateId, TransitionId)>>,
    terminal: Vec<bool>,
    /// `edges[edge_start[i]..edge_start[i + 1]]` leave expanded state `i`.
    edge_start: Vec<usize>,
    edges: Vec<(TransitionId, StateId)>,
    /// The part's transitions without input places: enabled in every marking.
    sources: Vec<TransitionId>,
    /// Whether goal and fail markings are terminal here (the ending part).
    ends: bool,
    complete: bool,
}

/// Fires `t` (enabled) from the sparse marking `from` into `to`.
fn fire(incidence: &Incidence, from: &[Entry], t: TransitionId, to: &mut Vec<Entry>) {
    to.clear();
    to.extend_from_slice(from);
    for a in incidence.inputs(t) {
        if let Ok(i) = to.binary_search_by_key(&a.place, |&(p, _)| p) {
            to[i].1 = count::sub(to[i].1, a.weight);
        }
    }
    for a in incidence.outputs(t) {
        match to.binary_search_by_key(&a.place, |&(p, _)| p) {
            Ok(i) => to[i].1 = count::add(to[i].1, a.weight),
            Err(i) => to.insert(i, (a.place, count::add(0, a.weight))),
        }
    }
    to.retain(|&(_, n)| n > 0);
}

/// Whether `t` has enough tokens in every input place of the sparse `marking` (ω is enough).
pub(super) fn enabled(incidence: &Incidence, marking: &[Entry], t: TransitionId) -> bool {
    incidence
        .inputs(t)
        .iter()
        .all(|a| markings::count(marking, a.place) >= u16::from(a.weight))
}

impl Reachability {
    /// The part `part` of `plan` with its initial marking only, not expanded yet.
    pub(super) fn start(plan: &Plan, part: &Part) -> Self {
        let incidence = plan.incidence();
        let mut graph = Reachability {
            places: incidence.place_count(),
            markings: Markings::new(),
            totals: Vec::new(),
            floors: Vec::new(),
            parent: Vec::new(),
            terminal: Vec::new(),
            edge_start: vec![0],
            edges: Vec::new(),
            sources: part
                .transitions
                .iter()
                .copied()
                .filter(|&t| incidence.inputs(t).is_empty())
                .collect(),
            ends: part.ends,
            complete: false,
        };
        let initial: Vec<Entry> = parts::initial(plan)
            .into_iter()
            .filter(|(p, _)| part.places.binary_search(p).is_ok())
            .collect();
        graph.push(plan, &initial, None);
        graph
    }

    /// Explores breadth first, transitions in index order (the result and its
    /// state numbering are deterministic), until every reachable marking is
    /// stored or `budget` says a limit is reached: then the limit, with the
    /// state being expanded left unexpanded.
    pub(super) fn expand(&mut self, plan: &Plan, budget: &Budget) -> Option<Stop> {
        let incidence = plan.incidence();
        let mut current = Vec::new();
        let mut candidates = Vec::new();
        let mut next = Vec::new();
        let mut state = self.edge_start.len() - 1;
        while state < self.len() {
            if let Some(stop) = budget.reached(self.len(), self.edges.len(), self.bytes(), false) {
                return Some(stop);
            }
            let from = StateId(state as u32);
            if !self.terminal[state] {
                current.clear();
                current.extend_from_slice(self.markings.get(state));
                self.enabled_into(incidence, &current, &mut candidates);
                for &t in &candidates {
                    fire(incidence, &current, t, &mut next);
                    let known = match self.markings.find(&next) {
                        Some(known) => Some(known),
                        None => {
                            self.accelerate(from, &mut next);
                            self.markings.find(&next)
                        }
                    };
                    let target = match known {
                        Some(known) => known,
                        None => {
                            if let Some(stop) = budget.reached(self.len(), self.edges.len(), self.bytes(), true) {
                                self.edges.truncate(self.edge_start[state]);
                                return Some(stop);
                            }
                            self.push(plan, &next, Some((from, t)))
                        }
                    };
                    self.edges.push((t, StateId(target as u32)));
                }
            }
            self.edge_start.push(self.edges.len());
            state += 1;
        }
        self.complete = true;
        None
    }

    /// The transitions enabled in the sparse `marking` (of this part), in index order, into `out`.
    fn enabled_into(&self, incidence: &Incidence, marking: &[Entry], out: &mut Vec<TransitionId>) {
        out.clear();
        for &(p, _) in marking {
            out.extend(incidence.consumers(p).iter().map(|&(t, _)| t));
        }
        out.extend_from_slice(&self.sources);
        out.sort_unstable();
        out.dedup();
        out.retain(|&t| enabled(incidence, marking, t));
    }

    /// Whether no transition is enabled in `s`.
    pub(super) fn enables_nothing(&self, incidence: &Incidence, s: StateId) -> bool {
        let mut out = Vec::new();
        self.enabled_into(incidence, self.entries(s), &mut out);
        out.is_empty()
    }

    fn push(&mut self, plan: &Plan, marking: &[Entry], parent: Option<(StateId, TransitionId)>) -> usize {
        let id = self.markings.insert(marking);
        let total = weighted_total(marking);
        let floor = parent.map_or(total, |(p, _)| total.min(self.floors[p.index()]));
        self.totals.push(total);
        self.floors.push(floor);
        self.parent.push(parent);
        self.terminal.push(self.ends && parts::is_terminal(plan, marking));
        id
    }

    /// Karp–Miller acceleration: for every ancestor of the new marking (its
    /// parent `from` included) that it strictly covers, the grown places
    /// become ω. The walk stops at the first ancestor whose floor shows that
    /// none further up has a smaller total.
    fn accelerate(&self, from: StateId, new: &mut [Entry]) {
        let mut total = weighted_total(new);
        let mut cursor = Some(from);
        while let Some(ancestor) = cursor {
            if self.floors[ancestor.index()] >= total {
                break;
            }
            let old = self.markings.get(ancestor.index());
            if self.totals[ancestor.index()] < total && old.iter().all(|&(p, n)| markings::count(new, p) >= n) {
                for (p, n) in new.iter_mut() {
                    if *n > markings::count(old, *p) {
                        *n = OMEGA;
                    }
                }
                total = weighted_total(new);
            }
            cursor = self.parent[ancestor.index()].map(|(p, _)| p);
        }
    }

    /// Bytes allocated for this graph, with what the checks will add over it.
    pub(super) fn bytes(&self) -> usize {
        self.markings.bytes()
            + (self.totals.capacity() + self.floors.capacity()) * size_of::<u32>()
            + self.parent.capacity() * size_of::<Option<(StateId, TransitionId)>>()
            + self.terminal.capacity()
            + self.edge_start.capacity() * size_of::<usize>()
            + self.edges.capacity() * size_of::<(TransitionId, StateId)>()
            + self.len() * CHECK_STATE_BYTES
            + self.edges.len() * CHECK_EDGE_BYTES
    }

    /// The marked places of `s` and their counts, in place order.
    pub(super) fn entries(&self, s: StateId) -> &[Entry] {
        self.markings.get(s.index())
    }

    /// The entries of every state, state after state.
    pub(super) fn all_entries(&self) -> &[Entry] {
        self.markings.entries()
    }

    /// Number of edges stored.
    pub(crate) fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// Number of explored markings.
    pub fn len(&self) -> usize {
        self.parent.len()
    }

    /// Never true: the initial marking is always explored.
    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// Whether every reachable marking of the part was explored.
    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// Whether this is the ending part: the one holding the goal and fail places.
    pub fn is_ending(&self) -> bool {
        self.ends
    }

    /// Every explored state, in order of discovery.
    pub fn states(&self) -> impl Iterator<Item = StateId> + use<> {
        (0..self.len() as u32).map(StateId)
    }

    /// Tokens of `place` in state `s` (0 for a place of another part).
    pub(crate) fn tokens(&self, s: StateId, place: PlaceId) -> count::Count {
        count::Count::from_raw(markings::count(self.entries(s), place))
    }

    /// Whether some place of `s` is unbounded (ω).
    pub fn has_omega(&self, s: StateId) -> bool {
        self.entries(s).iter().any(|&(_, n)| n == OMEGA)
    }

    /// The marking of `s` over the whole plan's places (the other parts' places
    /// empty), or `None` when it has an unbounded place.
    pub fn marking(&self, s: StateId) -> Option<Marking> {
        let mut tokens = vec![0u8; self.places];
        for &(p, n) in self.entries(s) {
            tokens[p.index()] = u8::try_from(n).ok()?;
        }
        Some(Marking::from_tokens(tokens))
    }

    /// Whether `s` is a goal or fail marking (the executor stops there; not expanded).
    pub fn is_terminal(&self, s: StateId) -> bool {
        self.terminal[s.index()]
    }

    /// Whether the successors of `s` were computed (false for the states left
    /// when a limit was hit).
    pub(crate) fn is_expanded(&self, s: StateId) -> bool {
        s.index() + 1 < self.edge_start.len()
    }

    /// The transitions enabled in `s` and the states they lead to (empty for a
    /// terminal or unexpanded state).
    pub fn successors(&self, s: StateId) -> &[(TransitionId, StateId)] {
        match (self.edge_start.get(s.index()), self.edge_start.get(s.index() + 1)) {
            (Some(&start), Some(&end)) => &self.edges[start..end],
            _ => &[],
        }
    }

    /// A shortest firing sequence of the part from its initial marking to `s`.
    pub fn trace(&self, s: StateId) -> Vec<TransitionId> {
        let mut out = Vec::new();
        let mut cursor = s;
        while let Some((parent, t)) = self.parent[cursor.index()] {
            out.push(t);
            cursor = parent;
        }
        out.reverse();
        out
    }

    /// `s` as the labels of its marked places, as [`Plan::describe`] writes a
    /// marking, `*ω` marking an unbounded place.
    pub fn describe(&self, plan: &Plan, s: StateId) -> String {
        describe(plan, self.entries(s))
    }
}

/// A sparse marking as the labels of its marked places, as [`Plan::describe`]
/// writes a marking (`*n` for n tokens, `-` for none), `*ω` marking an unbounded place.
pub(super) fn describe(plan: &Plan, marking: &[Entry]) -> String {
    if marking.is_empty() {
        return "-".to_string();
    }
    let parts: Vec<String> = marking
        .iter()
        .map(|&(p, n)| {
            let name = plan.place_name(p);
            match n {
                1 => name.to_string(),
                OMEGA => format!("{name}*ω"),
                n => format!("{name}*{n}"),
            }
        })
        .collect();
    parts.join(" ")
}
