//! The structural checks of a plan (thesis section 2.3) over its explored markings.
//!
//! - Safety: an execution place never holds more than one token. Other places
//!   may (memory places, loop counters: thesis 5.5); they get a note.
//! - Minimality: every transition fires somewhere in the explored graph.
//! - Effectiveness: a goal marking is reachable from every reachable marking
//!   that is not a fail marking.
//! - Deadlock: a marking with no enabled transition is a goal or fail marking.
//!
//! A failure found in an incomplete exploration is real (the marking is
//! reachable, and effectiveness only counts markings whose every continuation
//! was explored); a pass needs the whole graph, so hitting the limit makes it
//! inconclusive. Unbounded places are ω: effectiveness is exact when they are
//! never read (counters only written), otherwise a pass is inconclusive.

use super::choice::choice_points;
use super::count::{self, Count, OMEGA, Tri};
use super::diagnosis;
use super::reachability::{MEMORY_LIMIT, Reachability, StateId, enabled, explore};
use super::report::{CheckReport, Element, Example, Failure, Note, PlaceBound, Property, ReportedChoice, Verdict};
use crate::net::{PlaceId, TransitionId};
use crate::plan::Plan;

/// How many example markings a failure lists.
const MAX_EXAMPLES: usize = 3;

/// Explores `plan` (at most `limit` markings, fewer for plans too large for
/// [`MEMORY_LIMIT`]) and checks every property.
pub fn check(plan: &Plan, limit: usize) -> CheckReport {
    let graph = explore(plan, limit);
    let bounds: Vec<PlaceBound> = graph
        .bounds()
        .into_iter()
        .enumerate()
        .map(|(i, bound)| {
            let place = PlaceId::new(i);
            PlaceBound {
                place,
                element: Element::place(plan, place),
                action: plan.exec_action(place).map(|a| plan.action(a).name.clone()),
                bound,
            }
        })
        .collect();
    let mut failures = Vec::new();
    let mut notes = Vec::new();
    let incomplete = if graph.limit() < limit {
        format!(
            "the marking limit, lowered to {} so that markings of {} places fit in {} MiB, \
             was reached before every marking was explored",
            graph.limit(),
            plan.net().places().len(),
            MEMORY_LIMIT >> 20
        )
    } else {
        format!(
            "the marking limit of {} was reached before every marking was explored",
            graph.limit()
        )
    };
    let counts: Vec<Count> = bounds.iter().map(|b| b.bound).collect();
    let checker = Checker {
        plan,
        graph: &graph,
        bounds: &counts,
        incomplete: &incomplete,
    };
    let verdicts = vec![
        (Property::Safety, checker.safety(&bounds, &mut failures, &mut notes)),
        (Property::Minimality, checker.minimality(&mut failures)),
        (
            Property::Effectiveness,
            checker.effectiveness(&mut failures, &mut notes),
        ),
        (Property::Deadlock, checker.deadlock(&mut failures)),
    ];
    let choice_points = choice_points(plan, &graph)
        .into_iter()
        .map(|c| ReportedChoice {
            place: c.place,
            element: Element::place(plan, c.place),
            options: c.options.iter().map(|&t| (t, Element::transition(plan, t))).collect(),
        })
        .collect();
    CheckReport {
        plan: plan.name().to_string(),
        places: plan.net().places().len(),
        transitions: plan.net().transitions().len(),
        markings: graph.len(),
        limit: graph.limit(),
        complete: graph.is_complete(),
        bounds,
        choice_points,
        verdicts,
        failures,
        notes,
        warnings: plan.warnings().iter().map(ToString::to_string).collect(),
        has_goal: !plan.goal().is_empty(),
    }
}

struct Checker<'a> {
    plan: &'a Plan,
    graph: &'a Reachability,
    bounds: &'a [Count],
    incomplete: &'a str,
}

impl Checker<'_> {
    fn example(&self, s: StateId) -> Example {
        Example {
            marking: self.graph.describe(self.plan, s),
            trace: self
                .graph
                .trace(s)
                .into_iter()
                .map(|t| Element::transition(self.plan, t).name().to_string())
                .collect(),
        }
    }

    fn examples(&self, states: &[StateId]) -> Vec<Example> {
        states.iter().take(MAX_EXAMPLES).map(|&s| self.example(s)).collect()
    }

    fn goal(&self, s: StateId) -> Tri {
        count::matches(self.plan.goal(), self.graph.state_tokens(s))
    }

    fn fail(&self, s: StateId) -> Tri {
        count::matches(self.plan.fail(), self.graph.state_tokens(s))
    }

    /// Passed when nothing was found and the graph is complete.
    fn verdict(&self, found: bool) -> Verdict {
        if found {
            Verdict::Failed
        } else if self.graph.is_complete() {
            Verdict::Passed
        } else {
            Verdict::Inconclusive(self.incomplete.to_string())
        }
    }

    fn safety(&self, bounds: &[PlaceBound], failures: &mut Vec<Failure>, notes: &mut Vec<Note>) -> Verdict {
        let mut found = false;
        for b in bounds.iter().filter(|b| b.bound.exceeds_one()) {
            let Some(action) = &b.action else {
                notes.push(Note::AboveOne {
                    place: b.place,
                    element: b.element.clone(),
                    bound: b.bound,
                });
                continue;
            };
            let first = self
                .graph
                .states()
                .find(|&s| self.graph.tokens(s, b.place).exceeds_one());
            if let Some(s) = first {
                found = true;
                failures.push(Failure::UnsafeExecution {
                    place: b.place,
                    element: b.element.clone(),
                    action: action.clone(),
                    bound: b.bound,
                    example: self.example(s),
                });
            }
        }
        self.verdict(found)
    }

    fn minimality(&self, failures: &mut Vec<Failure>) -> Verdict {
        let mut fired = vec![false; self.plan.incidence().transition_count()];
        for s in self.graph.states() {
            for &(t, _) in self.graph.successors(s) {
                fired[t.index()] = true;
            }
        }
        let never: Vec<TransitionId> = fired
            .iter()
            .enumerate()
            .filter(|&(_, &f)| !f)
            .map(|(i, _)| TransitionId::new(i))
            .collect();
        if never.is_empty() {
            return Verdict::Passed;
        }
        if !self.graph.is_complete() {
            return Verdict::Inconclusive(format!(
                "{} transition(s) have not fired yet, and {}",
                never.len(),
                self.incomplete
            ));
        }
        failures.extend(never.into_iter().map(|t| Failure::DeadTransition {
            transition: t,
            element: Element::transition(self.plan, t),
            why: diagnosis::dead_transition(self.plan, self.graph, self.bounds, t),
        }));
        Verdict::Failed
    }

    /// The states from which some state in `seeds` is reachable.
    fn reaching(&self, seeds: impl Fn(StateId) -> bool) -> Vec<bool> {
        let n = self.graph.len();
        let mut predecessors: Vec<Vec<StateId>> = vec![Vec::new(); n];
        for s in self.graph.states() {
            for &(_, target) in self.graph.successors(s) {
                predecessors[target.index()].push(s);
            }
        }
        let mut reached = vec![false; n];
        let mut stack: Vec<StateId> = self.graph.states().filter(|&s| seeds(s)).collect();
        for s in &stack {
            reached[s.index()] = true;
        }
        while let Some(s) = stack.pop() {
            for &p in &predecessors[s.index()] {
                if !reached[p.index()] {
                    reached[p.index()] = true;
                    stack.push(p);
                }
            }
        }
        reached
    }

    fn effectiveness(&self, failures: &mut Vec<Failure>, notes: &mut Vec<Note>) -> Verdict {
        if self.plan.goal().is_empty() {
            notes.push(Note::NoGoal);
            return Verdict::NotApplicable("the plan has no goal places".to_string());
        }
        // Unexplored continuations might reach a goal: count them as able to.
        let may_reach_goal = self.reaching(|s| self.goal(s) != Tri::No || !self.graph.is_expanded(s));
        let stuck: Vec<StateId> = self
            .graph
            .states()
            .filter(|&s| !may_reach_goal[s.index()] && self.fail(s) == Tri::No)
            .collect();
        if !stuck.is_empty() {
            let may_fail = self.reaching(|s| self.fail(s) != Tri::No);
            failures.push(Failure::NoGoalReachable {
                markings: stuck.len(),
                ending_in_fail: stuck.iter().filter(|s| may_fail[s.index()]).count(),
                why: diagnosis::no_goal(self.plan, self.graph, self.bounds, &stuck),
                examples: self.examples(&stuck),
            });
            return Verdict::Failed;
        }
        if !self.graph.is_complete() {
            return Verdict::Inconclusive(self.incomplete.to_string());
        }
        match self.read_unbounded_place() {
            Some(p) => Verdict::Inconclusive(format!(
                "place {} is unbounded and {}: the coverability graph over-approximates what can follow",
                Element::place(self.plan, p),
                if self.plan.incidence().consumers(p).is_empty() {
                    "decides a goal or fail marking"
                } else {
                    "is read by transitions"
                },
            )),
            None => Verdict::Passed,
        }
    }

    /// An unbounded place whose count matters: an input of some transition, or a
    /// goal or fail place. Counters that are only written leave effectiveness exact.
    fn read_unbounded_place(&self) -> Option<PlaceId> {
        let marking_place = |p: PlaceId| self.plan.goal().iter().chain(self.plan.fail()).any(|&(q, _)| q == p);
        let places = self.plan.incidence().place_count();
        (0..places).map(PlaceId::new).find(|&p| {
            (!self.plan.incidence().consumers(p).is_empty() || marking_place(p))
                && self
                    .graph
                    .states()
                    .any(|s| self.graph.state_tokens(s)[p.index()] == OMEGA)
        })
    }

    fn deadlock(&self, failures: &mut Vec<Failure>) -> Verdict {
        let incidence = self.plan.incidence();
        let dead: Vec<StateId> = self
            .graph
            .states()
            .filter(|&s| {
                let tokens = self.graph.state_tokens(s);
                self.goal(s) == Tri::No
                    && self.fail(s) == Tri::No
                    && !incidence.transition_ids().any(|t| enabled(incidence, tokens, t))
            })
            .collect();
        if !dead.is_empty() {
            failures.push(Failure::DeadMarkings {
                markings: dead.len(),
                why: diagnosis::dead_marking(self.plan, self.graph, dead[0]),
                examples: self.examples(&dead),
            });
        }
        self.verdict(!dead.is_empty())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{PlanBuilder, Vocabulary};

    #[test]
    fn bounds_are_exact_for_bounded_places() {
        // Two tokens flow through a place one at a time or together.
        let mut b = PlanBuilder::new("two");
        let start = b.initial_place("start");
        b.set_tokens(start, 2);
        let mid = b.place("mid");
        let end = b.place("end");
        b.transition("a", &[(start, 1)], &[(mid, 1)]);
        b.transition("b", &[(mid, 1)], &[(end, 1)]);
        let plan = b.build(Vocabulary::Open).expect("plan builds");
        let report = check(&plan, 100);
        let bounds: Vec<Count> = report.bounds.iter().map(|b| b.bound).collect();
        assert_eq!(bounds, [Count::Finite(2); 3]);
        assert_eq!(report.markings, 6);
    }
}
