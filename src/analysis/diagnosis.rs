//! Why a check fails, in a designer's words: which place or transition of the
//! drawing is at fault ("the goal place has no incoming arc", "no transition
//! leaves P5", "the plan loops for ever: a → b → a") rather than only how many
//! markings are affected.

use super::count::Count;
use super::exploration::Exploration;
use super::markings::{self, Entry};
use super::reachability::{Reachability, StateId, enabled};
use crate::net::{PlaceId, TransitionId};
use crate::plan::Plan;

/// Longest loop a diagnosis spells out.
const SHOWN_LOOP: usize = 8;

/// A place named for a reader: `id 'label'`, or the id alone when the label is blank.
fn place(plan: &Plan, p: PlaceId) -> String {
    let node = plan.net().place(p);
    for_reader(&node.id, &node.label)
}

/// A transition named for a reader, like [`place`].
fn transition(plan: &Plan, t: TransitionId) -> String {
    let node = plan.net().transition(t);
    for_reader(&node.id, &node.label)
}

/// `id 'label'`, or `id` alone when `label` is blank.
fn for_reader(id: &str, label: &str) -> String {
    if label.trim().is_empty() {
        id.to_string()
    } else {
        format!("{id} '{label}'")
    }
}

/// The transitions with an arc into `p`.
fn producers(plan: &Plan, p: PlaceId) -> Vec<TransitionId> {
    let incidence = plan.incidence();
    incidence
        .transition_ids()
        .filter(|&t| incidence.outputs(t).iter().any(|a| a.place == p))
        .collect()
}

fn names(plan: &Plan, transitions: &[TransitionId]) -> String {
    transitions
        .iter()
        .map(|&t| transition(plan, t))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Why transition `t` never fires (`graph`: the part holding `t`).
pub(super) fn dead_transition(plan: &Plan, graph: &Reachability, bounds: &[Count], t: TransitionId) -> Vec<String> {
    let incidence = plan.incidence();
    let mut why = Vec::new();
    for arc in incidence.inputs(t) {
        let bound = bounds[arc.place.index()];
        if bound == Count::Finite(0) {
            let source = if producers(plan, arc.place).is_empty() {
                ": no arc leads into it and it starts empty"
            } else {
                ""
            };
            why.push(format!(
                "its input place {} is never marked{source}",
                place(plan, arc.place)
            ));
        } else if bound < Count::Finite(arc.weight) {
            why.push(format!(
                "it needs {} tokens in {}, which holds at most {bound}",
                arc.weight,
                place(plan, arc.place)
            ));
        }
    }
    if why.is_empty() {
        let covering: Vec<StateId> = graph
            .states()
            .filter(|&s| enabled(incidence, graph.entries(s), t))
            .collect();
        if covering.is_empty() {
            let inputs: Vec<String> = incidence.inputs(t).iter().map(|a| place(plan, a.place)).collect();
            why.push(format!(
                "its input places {} are never marked at the same time",
                inputs.join(", ")
            ));
        } else if covering.iter().all(|&s| graph.is_terminal(s)) {
            why.push("it is enabled only in goal or fail markings, where the plan has already ended".to_string());
        }
    }
    why
}

/// Why no goal marking can be reached from the `stuck` markings of the
/// ending part `graph` (part 0 of `exploration`).
pub(super) fn no_goal(
    plan: &Plan,
    exploration: &Exploration,
    graph: &Reachability,
    bounds: &[Count],
    stuck: &[StateId],
) -> Vec<String> {
    let mut why = Vec::new();
    let goal = plan.goal();
    for &(g, needed) in goal {
        let into = producers(plan, g);
        let bound = bounds[g.index()];
        if into.is_empty() && bound < Count::Finite(needed) {
            why.push(format!(
                "the goal place {} has no incoming arc: no transition ever marks it, so the plan never reaches its goal",
                place(plan, g)
            ));
        } else if bound < Count::Finite(needed) {
            let amount = if needed == 1 {
                String::new()
            } else {
                format!(" with {needed} tokens")
            };
            why.push(format!(
                "the goal place {} is never marked{amount}: the transitions into it ({}) never fire",
                place(plan, g),
                names(plan, &into)
            ));
        }
    }
    if why.is_empty() && goal.len() > 1 {
        let reached = graph.states().any(|s| {
            let marking = graph.entries(s);
            goal.iter().all(|&(g, n)| markings::count(marking, g) >= u16::from(n))
        });
        if !reached {
            let places: Vec<String> = goal.iter().map(|&(g, _)| place(plan, g)).collect();
            why.push(format!(
                "the goal places {} are never marked together",
                places.join(", ")
            ));
        }
    }
    // A loop of the ending part through stuck markings, or else a loop of a
    // free part, which leaves the ending part stuck where it is.
    let cycle = stuck_loop(graph, stuck).map(|(s, loop_)| (exploration.combine(&[(0, s)]), loop_));
    let cycle = cycle.or_else(|| {
        let &first = stuck.first()?;
        exploration.parts().iter().enumerate().skip(1).find_map(|(i, part)| {
            let all: Vec<StateId> = part.states().collect();
            stuck_loop(part, &all).map(|(s, loop_)| (exploration.combine(&[(0, first), (i, s)]), loop_))
        })
    });
    if let Some((start, transitions)) = &cycle {
        let shown: Vec<String> = transitions
            .iter()
            .take(SHOWN_LOOP)
            .map(|&t| super::choice_options::transition_name(plan, t).to_string())
            .collect();
        let more = if transitions.len() > SHOWN_LOOP { " → …" } else { "" };
        why.push(format!(
            "from [{}] the plan loops for ever without reaching its goal: {}{more} leads back to it",
            start.describe(plan),
            shown.join(" → ")
        ));
    } else if stuck
        .iter()
        .any(|&s| graph.successors(s).is_empty() && !graph.is_terminal(s))
    {
        why.push("the plan can stop before its goal (see deadlock)".to_string());
    }
    why
}

/// A loop through the stuck markings: a state on it and the transitions
/// around it, found by following successors that stay stuck. Each walk takes
/// the first stuck successor until a state repeats; a walk that ends, or meets
/// a state an earlier walk left, finds no loop, so every state is walked once.
fn stuck_loop(graph: &Reachability, stuck: &[StateId]) -> Option<(StateId, Vec<TransitionId>)> {
    const UNSEEN: usize = usize::MAX;
    const LEFT: usize = usize::MAX - 1;
    let mut is_stuck = vec![false; graph.len()];
    for s in stuck {
        is_stuck[s.index()] = true;
    }
    // The position of a state on the current walk, or UNSEEN, or LEFT.
    let mut seen = vec![UNSEEN; graph.len()];
    for &start in stuck {
        let mut path: Vec<(StateId, TransitionId)> = Vec::new();
        let mut at = start;
        loop {
            match seen[at.index()] {
                LEFT => break,
                UNSEEN => {}
                from => {
                    let transitions = path[from..].iter().map(|&(_, t)| t).collect();
                    return Some((at, transitions));
                }
            }
            seen[at.index()] = path.len();
            let Some(&(t, next)) = graph.successors(at).iter().find(|(_, n)| is_stuck[n.index()]) else {
                seen[at.index()] = LEFT;
                break;
            };
            path.push((at, t));
            at = next;
        }
        for (s, _) in path {
            seen[s.index()] = LEFT;
        }
    }
    None
}

/// Why the plan stops in the dead marking `marking` (sparse; `initial` when
/// it is the initial marking).
pub(super) fn dead_marking(plan: &Plan, marking: &[Entry], initial: bool) -> Vec<String> {
    let incidence = plan.incidence();
    let mut why = Vec::new();
    let marked: Vec<PlaceId> = marking.iter().map(|&(p, _)| p).collect();
    if marked.is_empty() {
        why.push(if initial {
            "no place holds a token at the start: give the initial place a token".to_string()
        } else {
            "every token has been consumed and no place is marked".to_string()
        });
    }
    for &p in &marked {
        let consumers = incidence.consumers(p);
        if consumers.is_empty() {
            let ending = if plan.goal().is_empty() {
                "; the plan has no goal place, so stopping here is never a success: label it 'goal' if it \
                 should end here"
            } else {
                ", or label it 'goal' (or 'fail') if the plan should end there"
            };
            why.push(format!("no transition leaves {}: add one{ending}", place(plan, p)));
            continue;
        }
        for &(t, _) in consumers {
            let missing: Vec<String> = incidence
                .inputs(t)
                .iter()
                .filter(|a| markings::count(marking, a.place) < u16::from(a.weight))
                .map(|a| {
                    if a.weight == 1 {
                        format!("a token in {}", place(plan, a.place))
                    } else {
                        format!("{} tokens in {}", a.weight, place(plan, a.place))
                    }
                })
                .collect();
            if !missing.is_empty() {
                why.push(format!(
                    "{}, which takes the token of {}, also needs {}: the plan waits there for ever",
                    transition(plan, t),
                    place(plan, p),
                    missing.join(" and ")
                ));
            }
        }
    }
    why
}
