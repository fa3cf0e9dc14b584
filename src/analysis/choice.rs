//! Choice points: places whose output transitions can be executable together
//! and compete for its tokens, so the executor (and the learner) must choose.
//!
//! Two output transitions of a place form an option pair when their guards are
//! jointly satisfiable ([`jointly_satisfiable`]). A sensing action's `[a]` /
//! `[not a]` outcomes are therefore no choice; the choice operator's unguarded
//! transitions are, and so is an action's end next to an interrupt whose
//! condition may hold at the same time (the executor then asks the chooser).

use super::exploration::Exploration;
use super::guards::jointly_satisfiable;
use super::reachability::enabled;
use crate::net::{PlaceId, TransitionId};
use crate::plan::Plan;

/// A place where a choice is made, with the transitions it chooses among.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChoicePoint {
    /// The contested place.
    pub place: PlaceId,
    /// Its output transitions that can be chosen, in index order.
    pub options: Vec<TransitionId>,
}

/// Two output transitions of one place with jointly satisfiable guards, with
/// the weights of their arcs from that place.
struct OptionPair {
    first: (TransitionId, u8),
    second: (TransitionId, u8),
}

fn option_pairs(plan: &Plan, place: PlaceId) -> Vec<OptionPair> {
    let consumers = plan.incidence().consumers(place);
    let mut pairs = Vec::new();
    for (i, &first) in consumers.iter().enumerate() {
        for &second in &consumers[i + 1..] {
            let guards = [&plan.transition(first.0).guard, &plan.transition(second.0).guard];
            if jointly_satisfiable(&guards) {
                pairs.push(OptionPair { first, second });
            }
        }
    }
    pairs
}

fn choice_point<'a>(place: PlaceId, pairs: impl Iterator<Item = &'a OptionPair>) -> Option<ChoicePoint> {
    let mut options: Vec<TransitionId> = pairs.flat_map(|p| [p.first.0, p.second.0]).collect();
    options.sort_unstable();
    options.dedup();
    (!options.is_empty()).then_some(ChoicePoint { place, options })
}

/// Choice points from the structure alone: places with two or more output
/// transitions whose guards can hold together, whether or not the place is
/// ever marked. Cheap (no exploration); in place order.
pub fn structural_choice_points(plan: &Plan) -> Vec<ChoicePoint> {
    (0..plan.incidence().place_count())
        .map(PlaceId::new)
        .filter_map(|p| choice_point(p, option_pairs(plan, p).iter()))
        .collect()
}

/// Choice points of the explored markings: places with two output transitions
/// whose guards can hold together, both token-enabled in some explored
/// non-terminal marking where the place holds fewer tokens than they consume
/// together (so firing one excludes the other). In place order. Both
/// transitions consume from the place, so they belong to its part, and the
/// markings of that part decide.
pub fn choice_points(plan: &Plan, exploration: &Exploration) -> Vec<ChoicePoint> {
    let incidence = plan.incidence();
    let pairs: Vec<Vec<OptionPair>> = (0..incidence.place_count())
        .map(|p| option_pairs(plan, PlaceId::new(p)))
        .collect();
    let mut confirmed: Vec<Vec<bool>> = pairs.iter().map(|p| vec![false; p.len()]).collect();
    for graph in exploration.parts() {
        for s in graph.states().filter(|&s| !graph.is_terminal(s)) {
            let marking = graph.entries(s);
            for &(place, tokens) in marking {
                let at = place.index();
                for (pair, seen) in pairs[at].iter().zip(confirmed[at].iter_mut()) {
                    if !*seen {
                        let demand = u16::from(pair.first.1) + u16::from(pair.second.1);
                        *seen = tokens < demand
                            && enabled(incidence, marking, pair.first.0)
                            && enabled(incidence, marking, pair.second.0);
                    }
                }
            }
        }
    }
    pairs
        .iter()
        .zip(&confirmed)
        .enumerate()
        .filter_map(|(p, (pairs, confirmed))| {
            let chosen = pairs.iter().zip(confirmed).filter(|&(_, &c)| c).map(|(p, _)| p);
            choice_point(PlaceId::new(p), chosen)
        })
        .collect()
}
