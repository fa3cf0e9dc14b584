//! The independent parts of a plan: sets of places and transitions that share
//! no place, explored one by one instead of together.
//!
//! A plan's net may be "not connected" on purpose (thesis 5.3, Figure 5.9): a
//! part of the network tracks the environment (a place for `x` and one for
//! `not x`, with the transitions `[x]` and `[not x]` between them) beside the
//! procedural part. With guards free, every tracker flips at any time, so
//! exploring the plan as one net stores every combination of the trackers with
//! every procedural marking: 2^k times the procedure's markings for k trackers.
//!
//! Exploring each connected component (places joined through the arcs of a
//! transition) apart is exact, not an approximation. Two components share no
//! place, so whether a transition is enabled and what it changes depend on its
//! own component alone: with interleaving semantics the reachable markings of
//! the whole are the combinations of the components' reachable markings, and
//! the edges of the whole are the edges of one component with the others
//! unchanged. The one coupling is that goal and fail markings end the plan
//! (nothing fires there): the components holding goal or fail places are
//! therefore explored together as the *ending* part, and every other component
//! is a *free* part, explored without terminal markings. When the initial
//! marking is not terminal, every free part's markings are reached while the
//! ending part still sits in its initial marking, so the combinations are
//! exactly the reachable markings; when it is terminal, nothing fires and the
//! plan is one part. The checks read the parts through
//! [`super::Exploration`], which combines them: a place's bound is its bound in
//! its part, a transition fires if it fires in its part, a combined marking is
//! dead when each part's marking is, and a goal is reachable from a combined
//! marking when it is from its ending part's marking.

use super::count::Tri;
use super::markings::{self, Entry};
use crate::net::{PlaceId, TransitionId};
use crate::plan::Plan;

/// Places and transitions explored together.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct Part {
    /// Its places, in index order.
    pub(super) places: Vec<PlaceId>,
    /// Its transitions, in index order.
    pub(super) transitions: Vec<TransitionId>,
    /// Whether it holds the goal and fail places (its goal and fail markings are terminal).
    pub(super) ends: bool,
}

/// The plan's initial marking in sparse form.
pub(super) fn initial(plan: &Plan) -> Vec<Entry> {
    plan.initial_marking()
        .marked()
        .map(|(p, n)| (p, u16::from(n)))
        .collect()
}

/// Whether `marking` is a goal or fail marking of `plan` for certain.
pub(super) fn is_terminal(plan: &Plan, marking: &[Entry]) -> bool {
    markings::matches(plan.goal(), marking) == Tri::Yes || markings::matches(plan.fail(), marking) == Tri::Yes
}

/// The whole plan as one part.
pub(super) fn whole(plan: &Plan) -> Part {
    let incidence = plan.incidence();
    Part {
        places: (0..incidence.place_count()).map(PlaceId::new).collect(),
        transitions: incidence.transition_ids().collect(),
        ends: true,
    }
}

/// The root of `i` in the union-find forest `up`, halving paths on the way.
fn root(up: &mut [usize], mut i: usize) -> usize {
    while up[i] != i {
        up[i] = up[up[i]];
        i = up[i];
    }
    i
}

/// The independent parts of `plan`: the ending part first (if the plan has
/// goal or fail places), then the free parts in order of their first place,
/// then one part for each transition without arcs. One part holding
/// everything when the initial marking is already terminal.
pub(super) fn parts(plan: &Plan) -> Vec<Part> {
    if is_terminal(plan, &initial(plan)) {
        return vec![whole(plan)];
    }
    let incidence = plan.incidence();
    let places = incidence.place_count();
    let mut up: Vec<usize> = (0..places).collect();
    let arcs = |t| incidence.inputs(t).iter().chain(incidence.outputs(t));
    for t in incidence.transition_ids() {
        let mut places = arcs(t).map(|a| a.place.index());
        if let Some(first) = places.next() {
            let first = root(&mut up, first);
            for p in places {
                let r = root(&mut up, p);
                up[r] = first;
            }
        }
    }
    let ending: Vec<usize> = plan
        .goal()
        .iter()
        .chain(plan.fail())
        .map(|&(p, _)| root(&mut up, p.index()))
        .collect();
    // Every place's part: the ending part is number 0, the others follow by first place.
    let mut part_of_root = vec![usize::MAX; places];
    let mut found = Vec::new();
    if !ending.is_empty() {
        for &r in &ending {
            part_of_root[r] = 0;
        }
        found.push(Part {
            places: Vec::new(),
            transitions: Vec::new(),
            ends: true,
        });
    }
    let mut part_of_place = vec![0; places];
    for (p, part) in part_of_place.iter_mut().enumerate() {
        let r = root(&mut up, p);
        if part_of_root[r] == usize::MAX {
            part_of_root[r] = found.len();
            found.push(Part {
                places: Vec::new(),
                transitions: Vec::new(),
                ends: false,
            });
        }
        *part = part_of_root[r];
        found[*part].places.push(PlaceId::new(p));
    }
    for t in incidence.transition_ids() {
        match arcs(t).next() {
            Some(a) => found[part_of_place[a.place.index()]].transitions.push(t),
            None => found.push(Part {
                places: Vec::new(),
                transitions: vec![t],
                ends: false,
            }),
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{AllowedAtoms, PlanBuilder};

    fn ids(part: &Part) -> (Vec<usize>, Vec<usize>, bool) {
        (
            part.places.iter().map(|p| p.index()).collect(),
            part.transitions.iter().map(|t| t.index()).collect(),
            part.ends,
        )
    }

    #[test]
    fn trackers_are_free_parts_beside_the_ending_procedure() {
        let mut b = PlanBuilder::new("tracked");
        b.tracker("x");
        let start = b.initial_place("start");
        let goal = b.goal_place();
        b.action_into(start, "A", goal);
        b.tracker("y");
        let plan = b.build(AllowedAtoms::Open).expect("a plan");
        let found: Vec<_> = parts(&plan).iter().map(ids).collect();
        // Places: x 0, not_x 1, start 2, goal 3, A.exec 4, y 5, not_y 6.
        assert_eq!(
            found,
            [
                (vec![2, 3, 4], vec![2, 3], true),
                (vec![0, 1], vec![0, 1], false),
                (vec![5, 6], vec![4, 5], false),
            ]
        );
    }

    #[test]
    fn a_terminal_initial_marking_keeps_the_plan_whole() {
        let mut b = PlanBuilder::new("done");
        b.tracker("x");
        let goal = b.goal_place();
        b.set_tokens(goal, 1);
        let plan = b.build(AllowedAtoms::Open).expect("a plan");
        let found = parts(&plan);
        assert_eq!(found.len(), 1);
        assert_eq!(ids(&found[0]), (vec![0, 1, 2], vec![0, 1], true));
    }
}
