//! The options of a choice, named as a designer drew them: by the transitions
//! that lead from the marking where the plan chose to the marking it chose.
//!
//! The executor offers a learner next markings (afterstates); a value table is
//! keyed on them. These functions go back from markings to transitions: which
//! transitions turn one marking into another ([`option_transitions`]), which
//! choices a marking offers with guards free ([`choices_at`]), and from which
//! marking one transition leads to a given one ([`before`]).

use super::choice::{ChoicePoint, structural_choice_points};
use super::guards::jointly_satisfiable;
use crate::net::{Marking, PlaceId, TransitionId};
use crate::plan::Plan;

/// The transitions whose firing from `from` is part of reaching `to`: those
/// enabled at `from` that change some place, each place they change in the
/// direction (and by no more than) `to` differs from `from`. For the options of
/// one choice this is the option's own transition plus any conflict-free ones
/// fired in the same step.
pub fn option_transitions(plan: &Plan, from: &Marking, to: &Marking) -> Vec<TransitionId> {
    let incidence = plan.incidence();
    let delta: Vec<i32> = from
        .tokens()
        .iter()
        .zip(to.tokens())
        .map(|(&a, &b)| i32::from(b) - i32::from(a))
        .collect();
    let mut effect = vec![0i32; delta.len()];
    incidence
        .transition_ids()
        .filter(|&t| {
            if !incidence.is_enabled(from, t) {
                return false;
            }
            effect.iter_mut().for_each(|e| *e = 0);
            for a in incidence.inputs(t) {
                effect[a.place.index()] -= i32::from(a.weight);
            }
            for a in incidence.outputs(t) {
                effect[a.place.index()] += i32::from(a.weight);
            }
            let changes = effect.iter().any(|&e| e != 0);
            changes
                && effect
                    .iter()
                    .zip(&delta)
                    .all(|(&e, &d)| e == 0 || (e.signum() == d.signum() && e.abs() <= d.abs()))
        })
        .collect()
}

/// The name of a transition: its label, or its id when the label is blank.
pub fn transition_name(plan: &Plan, t: TransitionId) -> &str {
    let node = plan.net().transition(t);
    if node.label.trim().is_empty() {
        &node.id
    } else {
        &node.label
    }
}

/// The option from `from` to `to` named by its transitions (`Pass1.start`,
/// several joined by ` + `); the marking `to` when no transition explains it.
pub fn option_label(plan: &Plan, from: &Marking, to: &Marking) -> String {
    let names: Vec<&str> = option_transitions(plan, from, to)
        .into_iter()
        .map(|t| transition_name(plan, t))
        .collect();
    if names.is_empty() {
        plan.describe(to)
    } else {
        names.join(" + ")
    }
}

/// A choice a marking offers: a place whose output transitions compete for
/// its tokens, and the marking each of them leads to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChoiceAt {
    /// The contested place.
    pub(crate) place: PlaceId,
    /// The competing transitions with the marking each one's firing gives.
    pub options: Vec<(TransitionId, Marking)>,
}

/// The choices `marking` offers with guards free: for every place with output
/// transitions whose guards can hold together, those transitions enabled at
/// `marking` that compete with another such one for the place's tokens.
pub fn choices_at(plan: &Plan, marking: &Marking) -> Vec<ChoiceAt> {
    choices_among(plan, &structural_choice_points(plan), marking)
}

/// [`choices_at`] among `points`, the plan's structural choice points
/// (computed once by the caller for many markings).
pub fn choices_among(plan: &Plan, points: &[ChoicePoint], marking: &Marking) -> Vec<ChoiceAt> {
    let incidence = plan.incidence();
    let mut found = Vec::new();
    for point in points {
        let tokens = u16::from(marking.get(point.place));
        if tokens == 0 {
            continue;
        }
        let weight = |t: TransitionId| {
            incidence
                .inputs(t)
                .iter()
                .find(|a| a.place == point.place)
                .map_or(0, |a| u16::from(a.weight))
        };
        let enabled: Vec<TransitionId> = point
            .options
            .iter()
            .copied()
            .filter(|&t| incidence.is_enabled(marking, t))
            .collect();
        let competing: Vec<TransitionId> = enabled
            .iter()
            .copied()
            .filter(|&t| {
                enabled.iter().any(|&u| {
                    u != t
                        && weight(t) + weight(u) > tokens
                        && jointly_satisfiable(&[&plan.transition(t).guard, &plan.transition(u).guard])
                })
            })
            .collect();
        if competing.len() < 2 {
            continue;
        }
        let options = competing
            .into_iter()
            .filter_map(|t| {
                let mut next = marking.clone();
                incidence.fire(&mut next, t).ok().map(|()| (t, next))
            })
            .collect();
        found.push(ChoiceAt {
            place: point.place,
            options,
        });
    }
    found
}

/// The marking from which firing `t` gives `after`, if there is one.
pub fn before(plan: &Plan, after: &Marking, t: TransitionId) -> Option<Marking> {
    let incidence = plan.incidence();
    let mut tokens: Vec<i32> = after.tokens().iter().map(|&n| i32::from(n)).collect();
    for a in incidence.outputs(t) {
        tokens[a.place.index()] -= i32::from(a.weight);
    }
    for a in incidence.inputs(t) {
        tokens[a.place.index()] += i32::from(a.weight);
    }
    let tokens: Option<Vec<u8>> = tokens.into_iter().map(|n| u8::try_from(n).ok()).collect();
    tokens.map(Marking::from_tokens)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{AllowedAtoms, catalog};

    /// The penalty kick of Figure 3.6: walk straight or turn, then kick.
    fn kick() -> Plan {
        Plan::from_net(catalog::penalty_kick_plain().expect("a net"), AllowedAtoms::Open).expect("a plan")
    }

    #[test]
    fn options_are_named_by_their_transitions_and_found_back() {
        let plan = kick();
        let start = plan.initial_marking();
        let choices = choices_at(&plan, &start);
        assert_eq!(choices.len(), 1);
        let names: Vec<String> = choices[0]
            .options
            .iter()
            .map(|(_, next)| option_label(&plan, &start, next))
            .collect();
        assert_eq!(names, ["WalkStraight.start", "Turn.start"]);
        for (t, next) in &choices[0].options {
            assert_eq!(before(&plan, next, *t).as_ref(), Some(&start));
        }
        // Once an action runs there is nothing to choose.
        let (_, walking) = &choices[0].options[0];
        assert!(choices_at(&plan, walking).is_empty());
        // No transition leads from the initial marking back to itself.
        assert_eq!(option_label(&plan, &start, &start), plan.describe(&start));
    }
}
