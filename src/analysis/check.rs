//! The structural checks of a plan (thesis section 2.3) over its explored markings.
//!
//! - Safety: an execution place never holds more than one token. Other places
//!   may (memory places, loop counters: thesis 5.5); they get a note.
//! - Minimality: every transition fires somewhere in the explored graph.
//! - Effectiveness: a goal marking is reachable from every reachable marking
//!   (thesis Definition 3), or a declared failure end is: a fail marking
//!   (places labelled `fail`), where PNP's executor ends the plan as failed,
//!   as a `fail_plan` execution rule's recovery does. The goal must stay
//!   reachable from the initial marking: a plan that can only fail fails.
//!   The failure ends and the markings that can end only there are noted.
//! - Deadlock: a marking with no enabled transition is a goal or fail marking.
//!
//! Every property reads the one [`Exploration`] of the plan, part by part
//! (see [`super::parts`] for why the parts decide exactly).
//!
//! A failure found in an incomplete exploration is real (the marking is
//! reachable, and effectiveness only counts markings whose every continuation
//! was explored); a pass needs the whole graph, so hitting the limit makes it
//! inconclusive. Unbounded places are ω: effectiveness is exact when they are
//! never read (counters only written), otherwise a pass is inconclusive.

use super::choice::choice_points;
use super::count::{Count, Tri};
use super::diagnosis;
use super::exploration::{Exploration, explore_within, product};
use super::limits::Limits;
use super::markings;
use super::reachability::{Reachability, StateId};
use super::report::{CheckReport, Element, Example, Failure, Note, PlaceBound, Property, ReportedChoice, Verdict};
use crate::net::{PlaceId, TransitionId};
use crate::plan::Plan;

/// How many example markings a failure lists.
const MAX_EXAMPLES: usize = 3;

/// Explores `plan` (at most `limit` markings, within [`super::MEMORY_LIMIT`])
/// and checks every property.
pub fn check(plan: &Plan, limit: usize) -> CheckReport {
    check_within(plan, Limits::markings(limit))
}

/// [`check`] within `limits`: one exploration ([`super::explore_within`]),
/// which every property reads.
pub fn check_within(plan: &Plan, limits: Limits) -> CheckReport {
    report(plan, &explore_within(plan, limits))
}

/// Every property of `plan` from its `exploration`.
fn report(plan: &Plan, exploration: &Exploration) -> CheckReport {
    let bounds: Vec<PlaceBound> = exploration
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
    let incomplete = exploration.stop().map_or_else(String::new, |stop| {
        format!("the {stop} was reached before every marking was explored")
    });
    let counts: Vec<Count> = bounds.iter().map(|b| b.bound).collect();
    let checker = Checker {
        plan,
        exploration,
        bounds: &counts,
        incomplete: &incomplete,
    };
    let (deadlock, dead) = checker.deadlock();
    let verdicts = vec![
        (Property::Safety, checker.safety(&bounds, &mut failures, &mut notes)),
        (Property::Minimality, checker.minimality(&mut failures)),
        (
            Property::Effectiveness,
            checker.effectiveness(&mut failures, &mut notes),
        ),
        (Property::Deadlock, deadlock),
    ];
    failures.extend(dead);
    let choice_points = choice_points(plan, exploration)
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
        markings: exploration.markings(),
        stored: exploration.stored(),
        parts: exploration.parts().len(),
        limit: exploration.limit(),
        complete: exploration.is_complete(),
        stop: exploration.stop(),
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
    exploration: &'a Exploration,
    bounds: &'a [Count],
    incomplete: &'a str,
}

impl Checker<'_> {
    /// The plan's marking made of `picks` (part, state), the other parts in
    /// their initial marking, as an example.
    fn example(&self, picks: &[(usize, StateId)]) -> Example {
        let combined = self.exploration.combine(picks);
        Example {
            marking: combined.describe(self.plan),
            trace: combined
                .trace
                .into_iter()
                .map(|t| Element::transition(self.plan, t).name().to_string())
                .collect(),
        }
    }

    /// Examples of the states `states` of the ending part (part 0).
    fn examples(&self, states: &[StateId]) -> Vec<Example> {
        states
            .iter()
            .take(MAX_EXAMPLES)
            .map(|&s| self.example(&[(0, s)]))
            .collect()
    }

    fn goal(&self, graph: &Reachability, s: StateId) -> Tri {
        markings::matches(self.plan.goal(), graph.entries(s))
    }

    fn fail(&self, graph: &Reachability, s: StateId) -> Tri {
        markings::matches(self.plan.fail(), graph.entries(s))
    }

    /// Passed when nothing was found and the exploration is complete.
    fn verdict(&self, found: bool) -> Verdict {
        if found {
            Verdict::Failed
        } else if self.exploration.is_complete() {
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
            let part = self.exploration.part_index(b.place);
            let graph = &self.exploration.parts()[part];
            if let Some(s) = graph.states().find(|&s| graph.tokens(s, b.place).exceeds_one()) {
                found = true;
                failures.push(Failure::UnsafeExecution {
                    place: b.place,
                    element: b.element.clone(),
                    action: action.clone(),
                    bound: b.bound,
                    example: self.example(&[(part, s)]),
                });
            }
        }
        self.verdict(found)
    }

    fn minimality(&self, failures: &mut Vec<Failure>) -> Verdict {
        let mut fired = vec![false; self.plan.incidence().transition_count()];
        for graph in self.exploration.parts() {
            for s in graph.states() {
                for &(t, _) in graph.successors(s) {
                    fired[t.index()] = true;
                }
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
        if !self.exploration.is_complete() {
            return Verdict::Inconclusive(format!(
                "{} transition(s) have not fired yet, and {}",
                never.len(),
                self.incomplete
            ));
        }
        failures.extend(never.into_iter().map(|t| Failure::DeadTransition {
            transition: t,
            element: Element::transition(self.plan, t),
            why: diagnosis::dead_transition(self.plan, self.exploration.part_of_transition(t), self.bounds, t),
        }));
        Verdict::Failed
    }

    /// The states of `graph` from which some state in `seeds` is reachable,
    /// over one index of predecessors.
    fn reaching(graph: &Reachability, predecessors: &Predecessors, seeds: impl Fn(StateId) -> bool) -> Vec<bool> {
        let mut reached = vec![false; graph.len()];
        let mut stack: Vec<StateId> = graph.states().filter(|&s| seeds(s)).collect();
        for s in &stack {
            reached[s.index()] = true;
        }
        while let Some(s) = stack.pop() {
            for &p in predecessors.of_state(s) {
                if !reached[p.index()] {
                    reached[p.index()] = true;
                    stack.push(p);
                }
            }
        }
        reached
    }

    /// Effectiveness, decided on the ending part: a goal or fail marking is
    /// reachable from a marking of the plan exactly when it is from its
    /// ending part's marking (the other parts hold no goal or fail place and
    /// never block it).
    fn effectiveness(&self, failures: &mut Vec<Failure>, notes: &mut Vec<Note>) -> Verdict {
        let Some(graph) = self.exploration.ending().filter(|_| !self.plan.goal().is_empty()) else {
            notes.push(Note::NoGoal);
            return Verdict::NotApplicable("the plan has no goal places".to_string());
        };
        let predecessors = Predecessors::of(graph);
        // Unexplored continuations might reach a goal: count them as able to.
        let may_reach_goal = Self::reaching(graph, &predecessors, |s| {
            self.goal(graph, s) != Tri::No || !graph.is_expanded(s)
        });
        let may_fail = Self::reaching(graph, &predecessors, |s| self.fail(graph, s) != Tri::No);
        let others = product(self.exploration.parts()[1..].iter().map(Reachability::len));
        let failure_ends = !self.plan.fail().is_empty();
        if failure_ends {
            let committed = graph
                .states()
                .filter(|&s| !may_reach_goal[s.index()] && self.fail(graph, s) == Tri::No)
                .count();
            notes.push(Note::FailureEnds {
                places: self
                    .plan
                    .fail()
                    .iter()
                    .map(|&(p, _)| Element::place(self.plan, p))
                    .collect(),
                committed: committed.saturating_mul(others),
            });
        }
        let stuck: Vec<StateId> = graph
            .states()
            .filter(|&s| !may_reach_goal[s.index()] && !may_fail[s.index()])
            .collect();
        if !stuck.is_empty() {
            failures.push(Failure::NoGoalReachable {
                markings: stuck.len().saturating_mul(others),
                failure_ends,
                why: diagnosis::no_goal(self.plan, self.exploration, graph, self.bounds, &stuck),
                examples: self.examples(&stuck),
            });
            return Verdict::Failed;
        }
        if !may_reach_goal[StateId::initial().index()] {
            let initial = [StateId::initial()];
            failures.push(Failure::GoalUnreachable {
                why: diagnosis::no_goal(self.plan, self.exploration, graph, self.bounds, &initial),
            });
            return Verdict::Failed;
        }
        if !self.exploration.is_complete() {
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
        (0..self.bounds.len()).map(PlaceId::new).find(|&p| {
            self.bounds[p.index()] == Count::Unbounded
                && (!self.plan.incidence().consumers(p).is_empty() || marking_place(p))
        })
    }

    /// Dead markings: a marking of the plan is dead when every part's marking
    /// enables nothing, and it is no goal or fail marking when its ending
    /// part's is not. The verdict, and the failure if there are dead markings.
    fn deadlock(&self) -> (Verdict, Option<Failure>) {
        let incidence = self.plan.incidence();
        let dead: Vec<Vec<StateId>> = self
            .exploration
            .parts()
            .iter()
            .map(|graph| {
                graph
                    .states()
                    .filter(|&s| {
                        (!graph.is_ending() || (self.goal(graph, s) == Tri::No && self.fail(graph, s) == Tri::No))
                            && graph.enables_nothing(incidence, s)
                    })
                    .collect()
            })
            .collect();
        let markings = product(dead.iter().map(Vec::len));
        if markings == 0 {
            return (self.verdict(false), None);
        }
        // The first dead marking of every part, the first few of the first part.
        let first: Vec<(usize, StateId)> = dead.iter().map(|d| d[0]).enumerate().collect();
        let examples = dead[0]
            .iter()
            .take(MAX_EXAMPLES)
            .map(|&s| {
                let mut picks = first.clone();
                picks[0].1 = s;
                self.example(&picks)
            })
            .collect();
        let combined = self.exploration.combine(&first);
        let initial = first.iter().all(|&(_, s)| s.index() == 0);
        let failure = Failure::DeadMarkings {
            markings,
            why: diagnosis::dead_marking(self.plan, &combined.marking, initial),
            examples,
        };
        (self.verdict(true), Some(failure))
    }
}

/// The predecessors of every state of a part, in one flat index.
struct Predecessors {
    /// `from[start[i]..start[i + 1]]` lead into state `i`.
    start: Vec<usize>,
    from: Vec<StateId>,
}

impl Predecessors {
    fn of(graph: &Reachability) -> Self {
        let mut start = vec![0usize; graph.len() + 1];
        for s in graph.states() {
            for &(_, target) in graph.successors(s) {
                start[target.index() + 1] += 1;
            }
        }
        for i in 0..graph.len() {
            start[i + 1] += start[i];
        }
        let mut next = start.clone();
        let mut from = vec![StateId::initial(); start[graph.len()]];
        for s in graph.states() {
            for &(_, target) in graph.successors(s) {
                from[next[target.index()]] = s;
                next[target.index()] += 1;
            }
        }
        Predecessors { start, from }
    }

    fn of_state(&self, s: StateId) -> &[StateId] {
        &self.from[self.start[s.index()]..self.start[s.index() + 1]]
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::super::exploration::explore_whole;
    use super::*;
    use crate::net::{PetriNet, PlaceNode, TransitionNode};
    use crate::plan::{AllowedAtoms, PlanBuilder, catalog};

    /// What a report decides, examples and traces aside (they may differ in
    /// the order the parts' transitions fire).
    fn decided(report: &CheckReport) -> impl PartialEq + std::fmt::Debug {
        let failures: Vec<(Property, Vec<usize>)> = report
            .failures
            .iter()
            .map(|f| {
                let counts = match f {
                    Failure::UnsafeExecution { place, .. } => vec![place.index()],
                    Failure::DeadTransition { transition, .. } => vec![transition.index()],
                    Failure::NoGoalReachable { markings, .. } => vec![*markings],
                    Failure::GoalUnreachable { .. } => Vec::new(),
                    Failure::DeadMarkings { markings, .. } => vec![*markings],
                };
                (f.property(), counts)
            })
            .collect();
        (
            report.markings,
            report.complete,
            report.bounds.clone(),
            report.verdicts.clone(),
            report.choice_points.clone(),
            failures,
            report.notes.clone(),
        )
    }

    /// `plan` checked part by part and as one net decides the same.
    fn same_as_whole(plan: &Plan) -> Result<(), TestCaseError> {
        let limits = Limits::markings(100_000);
        let split = check_within(plan, limits);
        let whole = report(plan, &explore_whole(plan, limits));
        prop_assert_eq!(decided(&split), decided(&whole), "{}\n{}", split, whole);
        Ok(())
    }

    #[test]
    fn the_thesis_plans_decide_the_same_part_by_part() {
        for (name, net) in catalog::all().expect("the catalogue builds") {
            let plan = Plan::from_net(net, AllowedAtoms::Open).expect("a plan");
            same_as_whole(&plan).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }

    #[test]
    fn a_stuck_procedure_beside_a_tracker_is_explained_by_the_tracker_loop() {
        // The procedure stops before its goal; the tracker keeps flipping.
        let mut b = PlanBuilder::new("stuck");
        b.tracker("x");
        let start = b.initial_place("start");
        let there = b.place("there");
        let never = b.place("never");
        b.action_into(start, "A", there);
        let goal = b.goal_place();
        b.transition("finish", &[(there, 1), (never, 1)], &[(goal, 1)]);
        let plan = b.build(AllowedAtoms::Open).expect("a plan");
        same_as_whole(&plan).expect("the same decisions");
        let text = check(&plan, 100).to_string();
        assert!(text.contains("effectiveness  FAILED"), "{text}");
        assert!(text.contains("deadlock       passed"), "{text}");
        assert!(
            text.contains(
                "from [not_x start] the plan loops for ever without reaching its goal: [x] → [not x] leads back to it"
            ),
            "{text}"
        );
    }

    /// A net of `codes.len() / 2 / places` transitions: codes 7 and 8 make
    /// an arc of weight 1, 9 of weight 2, others none (inputs, then outputs).
    fn random_plan(initial: &[u8], labels: &[u8], codes: &[u8]) -> Option<Plan> {
        let n = initial.len();
        let places = (0..n)
            .map(|i| PlaceNode {
                id: format!("p{i}"),
                label: match labels[i] {
                    0 => "goal".to_string(),
                    1 => "fail".to_string(),
                    _ => format!("q{i}"),
                },
                initial: initial[i],
                position: None,
            })
            .collect();
        let m = codes.len() / (2 * n);
        let transitions = (0..m)
            .map(|t| TransitionNode {
                id: format!("t{t}"),
                label: String::new(),
                position: None,
            })
            .collect();
        let mut arcs = Vec::new();
        for t in 0..m {
            for p in 0..n {
                for (k, input) in [(0, true), (1, false)] {
                    let weight = match codes[2 * (t * n + p) + k] {
                        7 | 8 => 1,
                        9 => 2,
                        _ => continue,
                    };
                    let (source, target) = if input {
                        (format!("p{p}"), format!("t{t}"))
                    } else {
                        (format!("t{t}"), format!("p{p}"))
                    };
                    arcs.push((format!("a{}", arcs.len()), source, target, weight));
                }
            }
        }
        let arcs: Vec<(&str, &str, &str, u8)> = arcs
            .iter()
            .map(|(id, s, t, w)| (id.as_str(), s.as_str(), t.as_str(), *w))
            .collect();
        let net = PetriNet::new("random", places, transitions, &arcs).ok()?;
        Plan::from_net(net, AllowedAtoms::Open).ok()
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

        /// Exploring the independent parts apart decides what exploring the
        /// whole net decides (bounded nets: the coverability graphs of
        /// unbounded ones depend on the order of exploration).
        #[test]
        fn parts_decide_as_the_whole_net(
            (initial, labels, codes) in (1usize..7, 0usize..7).prop_flat_map(|(n, m)| (
                prop::collection::vec(0u8..3, n),
                prop::collection::vec(0u8..6, n),
                prop::collection::vec(0u8..10, 2 * n * m),
            ))
        ) {
            let Some(plan) = random_plan(&initial, &labels, &codes) else {
                return Ok(());
            };
            let whole = check(&plan, 100_000);
            prop_assume!(whole.bounds.iter().all(|b| b.bound != Count::Unbounded));
            same_as_whole(&plan)?;
        }
    }

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
        let plan = b.build(AllowedAtoms::Open).expect("plan builds");
        let report = check(&plan, 100);
        let bounds: Vec<Count> = report.bounds.iter().map(|b| b.bound).collect();
        assert_eq!(bounds, [Count::Finite(2); 3]);
        assert_eq!(report.markings, 6);
    }
}
