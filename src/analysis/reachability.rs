//! The markings a plan can reach, guards ignored, with unbounded places accelerated.
//!
//! Every guard may be true or false, so every token-enabled transition may fire
//! (interleaving semantics: one transition per edge). Goal and fail markings are
//! terminal, as in the executor, which stops there. A new marking that strictly
//! covers one of its ancestors makes the grown places unbounded (Karp–Miller):
//! they become ω and the exploration terminates. The result is then a
//! coverability graph: an ω-marking stands for reachable markings that agree on
//! its finite places and hold arbitrarily many tokens in its ω places.

use rustc_hash::FxHashMap;

use super::count::{self, Count, OMEGA, Tri};
use crate::net::{Incidence, Marking, PlaceId, TransitionId};
use crate::plan::Plan;

/// A marking limit large enough for hand-written plans.
pub const DEFAULT_LIMIT: usize = 100_000;

/// The memory an exploration (and the checks over it) may use for its
/// markings and edges: 256 MiB. The marking limit is lowered so that the
/// stored markings fit ([`marking_limit`]); a plan with many places thus
/// explores fewer markings, and its check becomes inconclusive instead of
/// exhausting memory.
pub const MEMORY_LIMIT: usize = 256 << 20;

/// Bytes a stored marking of `places` places costs, with the checks'
/// bookkeeping: two `u16` copies of every count (the marking and its hash
/// key) and about a hundred bytes per state.
const fn state_bytes(places: usize) -> usize {
    4 * places + 128
}

/// Bytes an edge costs (its entry, and the predecessor list the checks build).
const EDGE_BYTES: usize = 16;

/// The number of markings an exploration of a plan with `places` places
/// stores at most when asked for `limit`: `limit`, lowered to what
/// [`MEMORY_LIMIT`] holds (at least one).
pub fn marking_limit(places: usize, limit: usize) -> usize {
    limit.min(MEMORY_LIMIT / state_bytes(places)).max(1)
}

/// Index of an explored marking (the initial marking is state 0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct StateId(u32);

impl StateId {
    /// Its index, in order of discovery (breadth first).
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

/// The explored markings and the transitions between them.
#[derive(Debug, Clone)]
pub struct Reachability {
    places: usize,
    /// Token counts, state after state, `places` values each.
    tokens: Vec<u16>,
    /// Token totals with ω counted as 256 (a quick test for strict covering).
    totals: Vec<u32>,
    /// How each state was first reached.
    parent: Vec<Option<(StateId, TransitionId)>>,
    terminal: Vec<bool>,
    /// `edges[edge_start[i]..edge_start[i + 1]]` leave expanded state `i`.
    edge_start: Vec<usize>,
    edges: Vec<(TransitionId, StateId)>,
    complete: bool,
    limit: usize,
}

/// Explores the markings reachable from `plan`'s initial marking, storing at
/// most `limit` of them (at least the initial one), lowered by
/// [`marking_limit`] to fit [`MEMORY_LIMIT`]; edges beyond what the memory
/// left holds also stop the exploration. Breadth first, transitions in index
/// order: the result and its state numbering are deterministic.
pub fn explore(plan: &Plan, limit: usize) -> Reachability {
    let incidence = plan.incidence();
    let places = incidence.place_count();
    let limit = marking_limit(places, limit);
    let max_edges = MEMORY_LIMIT.saturating_sub(limit * state_bytes(places)) / EDGE_BYTES;
    let mut graph = Reachability {
        places,
        tokens: Vec::new(),
        totals: Vec::new(),
        parent: Vec::new(),
        terminal: Vec::new(),
        edge_start: vec![0],
        edges: Vec::new(),
        complete: false,
        limit,
    };
    let mut index: FxHashMap<Box<[u16]>, StateId> = FxHashMap::default();
    let initial: Vec<u16> = plan.initial_marking().tokens().iter().map(|&t| u16::from(t)).collect();
    graph.push(plan, &initial, None, &mut index);

    let mut current = vec![0u16; places];
    let mut next = vec![0u16; places];
    let mut state = 0;
    while state < graph.len() {
        let from = StateId(state as u32);
        if !graph.terminal[state] {
            current.copy_from_slice(graph.state_tokens(from));
            for t in incidence.transition_ids() {
                if !enabled(incidence, &current, t) {
                    continue;
                }
                fire(incidence, &current, t, &mut next);
                let target = match index.get(&next[..]) {
                    Some(&known) => known,
                    None => {
                        graph.accelerate(from, &mut next);
                        match index.get(&next[..]) {
                            Some(&known) => known,
                            None if graph.len() >= graph.limit => {
                                // The state stays unexpanded: drop its partial edges.
                                graph.edges.truncate(graph.edge_start[state]);
                                return graph;
                            }
                            None => graph.push(plan, &next, Some((from, t)), &mut index),
                        }
                    }
                };
                if graph.edges.len() >= max_edges {
                    graph.edges.truncate(graph.edge_start[state]);
                    return graph;
                }
                graph.edges.push((t, target));
            }
        }
        graph.edge_start.push(graph.edges.len());
        state += 1;
    }
    graph.complete = true;
    graph
}

/// Whether `t` has enough tokens in every input place (ω is enough).
pub(super) fn enabled(incidence: &Incidence, tokens: &[u16], t: TransitionId) -> bool {
    incidence
        .inputs(t)
        .iter()
        .all(|a| tokens[a.place.index()] >= u16::from(a.weight))
}

/// Fires enabled `t` from `from` into `to`.
fn fire(incidence: &Incidence, from: &[u16], t: TransitionId, to: &mut [u16]) {
    to.copy_from_slice(from);
    for a in incidence.inputs(t) {
        let slot = &mut to[a.place.index()];
        *slot = count::sub(*slot, a.weight);
    }
    for a in incidence.outputs(t) {
        let slot = &mut to[a.place.index()];
        *slot = count::add(*slot, a.weight);
    }
}

/// The token total with ω as 256: strictly monotone in every place.
fn weighted_total(tokens: &[u16]) -> u32 {
    tokens
        .iter()
        .map(|&t| if t == OMEGA { 256 } else { u32::from(t) })
        .sum()
}

impl Reachability {
    fn push(
        &mut self,
        plan: &Plan,
        tokens: &[u16],
        parent: Option<(StateId, TransitionId)>,
        index: &mut FxHashMap<Box<[u16]>, StateId>,
    ) -> StateId {
        let id = StateId(self.parent.len() as u32);
        self.tokens.extend_from_slice(tokens);
        self.totals.push(weighted_total(tokens));
        self.parent.push(parent);
        self.terminal
            .push(count::matches(plan.goal(), tokens) == Tri::Yes || count::matches(plan.fail(), tokens) == Tri::Yes);
        index.insert(tokens.into(), id);
        id
    }

    /// Karp–Miller acceleration: for every ancestor of the new marking (its
    /// parent `from` included) that it strictly covers, the grown places become ω.
    fn accelerate(&self, from: StateId, new: &mut [u16]) {
        let mut total = weighted_total(new);
        let mut cursor = Some(from);
        while let Some(ancestor) = cursor {
            let old = self.state_tokens(ancestor);
            if self.totals[ancestor.index()] < total && new.iter().zip(old).all(|(n, o)| n >= o) {
                for (n, &o) in new.iter_mut().zip(old) {
                    if *n > o {
                        *n = OMEGA;
                    }
                }
                total = weighted_total(new);
            }
            cursor = self.parent[ancestor.index()].map(|(p, _)| p);
        }
    }

    pub(super) fn state_tokens(&self, s: StateId) -> &[u16] {
        let start = s.index() * self.places;
        &self.tokens[start..start + self.places]
    }

    /// Number of explored markings.
    pub fn len(&self) -> usize {
        self.parent.len()
    }

    /// Never true: the initial marking is always explored.
    pub fn is_empty(&self) -> bool {
        self.parent.is_empty()
    }

    /// Whether every reachable marking was explored (the limit was not hit).
    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// The marking limit the exploration ran with (lowered by
    /// [`marking_limit`] for plans with many places).
    pub fn limit(&self) -> usize {
        self.limit
    }

    /// Every explored state, in order of discovery.
    pub fn states(&self) -> impl Iterator<Item = StateId> + use<> {
        (0..self.len() as u32).map(StateId)
    }

    /// Tokens of `place` in state `s`.
    pub fn tokens(&self, s: StateId, place: PlaceId) -> Count {
        Count::from_raw(self.state_tokens(s)[place.index()])
    }

    /// Whether some place of `s` is unbounded (ω).
    pub fn has_omega(&self, s: StateId) -> bool {
        self.state_tokens(s).contains(&OMEGA)
    }

    /// The marking of `s`, or `None` when it has an unbounded place.
    pub fn marking(&self, s: StateId) -> Option<Marking> {
        self.state_tokens(s)
            .iter()
            .map(|&t| u8::try_from(t).ok())
            .collect::<Option<Vec<u8>>>()
            .map(Marking::from_tokens)
    }

    /// Whether `s` is a goal or fail marking (the executor stops there; not expanded).
    pub fn is_terminal(&self, s: StateId) -> bool {
        self.terminal[s.index()]
    }

    /// Whether the successors of `s` were computed (false for the states left
    /// when the limit was hit).
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

    /// A shortest firing sequence from the initial marking to `s`.
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

    /// The largest count of every place over the explored markings (a lower
    /// bound when the exploration is incomplete).
    pub fn bounds(&self) -> Vec<Count> {
        let mut max = vec![0u16; self.places];
        for chunk in self.tokens.chunks_exact(self.places.max(1)) {
            for (m, &t) in max.iter_mut().zip(chunk) {
                *m = (*m).max(t);
            }
        }
        max.into_iter().map(Count::from_raw).collect()
    }

    /// `s` as the labels of its marked places (see [`Plan::describe`]), `*ω`
    /// marking an unbounded place.
    pub fn describe(&self, plan: &Plan, s: StateId) -> String {
        if let Some(m) = self.marking(s) {
            return plan.describe(&m);
        }
        let parts: Vec<String> = self
            .state_tokens(s)
            .iter()
            .enumerate()
            .filter(|&(_, &t)| t > 0)
            .map(|(i, &t)| {
                let name = plan.place_name(PlaceId::new(i));
                match t {
                    1 => name.to_string(),
                    OMEGA => format!("{name}*ω"),
                    n => format!("{name}*{n}"),
                }
            })
            .collect();
        parts.join(" ")
    }
}
