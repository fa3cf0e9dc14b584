//! `check`: safety, minimality, effectiveness and dead markings on small plans
//! built in code (and raw nets malformed by design).

use crate::util::{looking, net};
use learnpnp::analysis::{
    CheckReport, Count, Failure, Limits, Note, Outcome, Property, Stop, Verdict, check, check_within, explore,
};
use learnpnp::net::{NetError, PetriNet, PlaceId, TransitionId};
use learnpnp::plan::{AllowedAtoms, Plan, PlanBuilder, catalog};

const LIMIT: usize = 10_000;

fn build(b: PlanBuilder) -> Plan {
    b.build(AllowedAtoms::Open).expect("test plan builds")
}

/// The plan of a net from the catalogue.
fn catalogued(net: Result<PetriNet, NetError>) -> Plan {
    Plan::from_net(net.expect("a catalogued net"), AllowedAtoms::Open).expect("a catalogued plan")
}

fn verdict(report: &CheckReport, property: Property) -> &Verdict {
    report.verdict(property).expect("every property has a verdict")
}

fn failures_of(report: &CheckReport, property: Property) -> Vec<&Failure> {
    report.failures.iter().filter(|f| f.property() == property).collect()
}

/// A raw net: places `(id, label, initial)`, transitions `(id, label)`, arcs `(source, target, weight)`.
fn raw_plan(places: &[(&str, &str, u8)], transitions: &[(&str, &str)], arcs: &[(&str, &str, u8)]) -> Plan {
    Plan::from_net(net(places, transitions, arcs), AllowedAtoms::Open).expect("raw net is a plan")
}

/// init -> A -> B -> goal.
fn sequence() -> Plan {
    let mut b = PlanBuilder::new("sequence");
    let init = b.initial_place("init");
    let a = b.action(init, "A");
    let goal = b.goal_place();
    b.action_into(a.done, "B", goal);
    build(b)
}

#[test]
fn a_sequence_passes() {
    let report = check(&sequence(), LIMIT);
    assert!(report.passed(), "{report}");
    assert!(report.failures.is_empty() && report.notes.is_empty(), "{report}");
    for property in Property::ALL {
        assert_eq!(verdict(&report, property), &Verdict::Passed, "{property:?}");
    }
    // init, A.exec, A's output, B.exec, goal.
    assert_eq!(report.markings, 5);
    assert!(report.complete);
    assert_eq!((report.places, report.transitions), (5, 4));
    assert!(report.choice_points.is_empty());
    assert!(report.bounds.iter().all(|b| b.bound == Count::Finite(1)));
    let text = report.to_string();
    assert!(text.contains("result: passed"), "{text}");
    assert!(text.contains("plan 'sequence': 5 places, 4 transitions"), "{text}");
}

#[test]
fn the_goal_marking_is_terminal() {
    let exploration = explore(&sequence(), LIMIT);
    assert_eq!(exploration.parts().len(), 1);
    let graph = &exploration.parts()[0];
    let goal = graph
        .states()
        .find(|&s| graph.is_terminal(s))
        .expect("the goal is reached");
    assert!(graph.successors(goal).is_empty());
    let trace: Vec<usize> = graph.trace(goal).iter().map(|t| t.index()).collect();
    assert_eq!(trace, [0, 1, 2, 3]);
    assert_eq!(graph.describe(&sequence(), goal), "goal");
}

#[test]
fn a_fork_without_join_leaving_a_token_off_the_goal_fails_effectiveness() {
    // The goal needs both goal places; the second branch ends in a plain place.
    let mut b = PlanBuilder::new("forgotten_join");
    let init = b.initial_place("init");
    let branches = b.fork(init, 2);
    let goal_a = b.goal_place();
    b.action_into(branches[0], "A", goal_a);
    b.goal_place();
    b.action(branches[1], "B");
    let report = check(&build(b), LIMIT);
    assert!(!report.passed());
    assert_eq!(verdict(&report, Property::Effectiveness), &Verdict::Failed);
    let [Failure::NoGoalReachable { markings, examples, .. }] = failures_of(&report, Property::Effectiveness)[..]
    else {
        panic!("one effectiveness failure expected: {report}");
    };
    assert_eq!(*markings, report.markings, "no marking can reach the goal");
    assert_eq!(examples.len(), 3);
    assert!(examples[0].trace.is_empty(), "the initial marking comes first");
    // The branches end with tokens in a goal place and in B's output: dead.
    assert_eq!(verdict(&report, Property::Deadlock), &Verdict::Failed);
    let text = report.to_string();
    assert!(text.contains("cannot reach a goal marking"), "{text}");
    assert!(text.contains("result: FAILED"), "{text}");
}

#[test]
fn a_dead_end_branch_fails_only_the_markings_after_it() {
    let (mut b, exec, goal) = looking("dead_end");
    let lost = b.place("lost");
    b.transition("look.end [ok]", &[(exec, 1)], &[(goal, 1)]);
    b.transition("look.end [not ok]", &[(exec, 1)], &[(lost, 1)]);
    let report = check(&build(b), LIMIT);
    let [
        Failure::NoGoalReachable {
            markings: 1,
            examples,
            failure_ends: false,
            why,
        },
    ] = failures_of(&report, Property::Effectiveness)[..]
    else {
        panic!("only 'lost' cannot reach the goal: {report}");
    };
    assert_eq!(examples[0].marking, "lost");
    assert_eq!(why, &["the plan can stop before its goal (see deadlock)"]);
    let text = report.to_string();
    assert!(
        text.contains("because no transition leaves p4 'lost': add one, or label it 'goal' (or 'fail')"),
        "{text}"
    );
    assert_eq!(examples[0].trace, ["look.start", "look.end [not ok]"]);
    let [Failure::DeadMarkings { markings: 1, .. }] = failures_of(&report, Property::Deadlock)[..] else {
        panic!("'lost' is dead: {report}");
    };
    assert_eq!(verdict(&report, Property::Minimality), &Verdict::Passed);
}

#[test]
fn fail_markings_are_terminal_and_excluded() {
    let (mut b, exec, goal) = looking("with_fail");
    let fail = b.place("fail");
    b.transition("look.end [ok]", &[(exec, 1)], &[(goal, 1)]);
    b.transition("look.end [not ok]", &[(exec, 1)], &[(fail, 1)]);
    let report = check(&build(b), LIMIT);
    assert!(report.passed(), "{report}");
}

#[test]
fn a_recovery_that_gives_up_ends_in_the_declared_failure_end_and_passes() {
    // PNPgen's fail_plan: the recovery's markings can end only in `fail`.
    let (mut b, exec, goal) = looking("gives_up");
    b.transition("look.end [ok]", &[(exec, 1)], &[(goal, 1)]);
    let lost = b.place("lost");
    b.transition("look.end [not ok]", &[(exec, 1)], &[(lost, 1)]);
    let fail = b.place("fail");
    b.action_into(lost, "report", fail);
    let report = check(&build(b), LIMIT);
    assert!(report.passed(), "{report}");
    let [Note::FailureEnds { places, committed }] = &report.notes[..] else {
        panic!("the failure end is noted: {report}");
    };
    let names: Vec<&str> = places.iter().map(|p| p.name()).collect();
    assert_eq!(names, ["fail"]);
    assert_eq!(*committed, 2, "lost and report.exec can end only in fail");
    let text = report.to_string();
    assert!(text.contains("2 reachable marking(s) can end only there"), "{text}");
    assert_eq!(report.to_json()["failure_ends"][0]["label"], "fail");
}

#[test]
fn a_loop_that_reaches_neither_goal_nor_failure_end_fails_effectiveness() {
    let (mut b, exec, goal) = looking("spins");
    b.transition("look.end [ok]", &[(exec, 1)], &[(goal, 1)]);
    let fail = b.place("fail");
    b.transition("look.fail", &[(exec, 1)], &[(fail, 1)]);
    let lost = b.place("lost");
    b.transition("look.end [not ok]", &[(exec, 1)], &[(lost, 1)]);
    b.transition("spin", &[(lost, 1)], &[(lost, 1)]);
    let report = check(&build(b), LIMIT);
    assert_eq!(verdict(&report, Property::Effectiveness), &Verdict::Failed, "{report}");
    let [
        Failure::NoGoalReachable {
            markings: 1,
            failure_ends: true,
            ..
        },
    ] = failures_of(&report, Property::Effectiveness)[..]
    else {
        panic!("only 'lost' reaches neither: {report}");
    };
    assert!(
        report
            .to_string()
            .contains("cannot reach a goal marking nor a failure end"),
        "{report}"
    );
}

#[test]
fn a_dead_end_beside_a_failure_end_still_fails_deadlock() {
    let (mut b, exec, goal) = looking("dead_beside_fail");
    b.transition("look.end [ok]", &[(exec, 1)], &[(goal, 1)]);
    let fail = b.place("fail");
    b.transition("look.fail", &[(exec, 1)], &[(fail, 1)]);
    let lost = b.place("lost");
    b.transition("look.end [not ok]", &[(exec, 1)], &[(lost, 1)]);
    let report = check(&build(b), LIMIT);
    assert_eq!(verdict(&report, Property::Deadlock), &Verdict::Failed, "{report}");
    assert_eq!(verdict(&report, Property::Effectiveness), &Verdict::Failed, "{report}");
    assert!(!report.passed());
}

#[test]
fn a_plan_that_can_only_fail_fails_effectiveness() {
    let mut b = PlanBuilder::new("only_fails");
    let init = b.initial_place("init");
    let fail = b.place("fail");
    b.action_into(init, "A", fail);
    b.goal_place();
    let report = check(&build(b), LIMIT);
    assert_eq!(verdict(&report, Property::Effectiveness), &Verdict::Failed, "{report}");
    let [Failure::GoalUnreachable { why }] = failures_of(&report, Property::Effectiveness)[..] else {
        panic!("the goal is unreachable: {report}");
    };
    assert!(why[0].contains("has no incoming arc"), "{why:?}");
    assert!(
        report.to_string().contains("every run ends in a failure end"),
        "{report}"
    );
}

#[test]
fn a_transition_whose_input_is_never_marked_fails_minimality() {
    let mut b = PlanBuilder::new("orphan");
    let init = b.initial_place("init");
    let goal = b.goal_place();
    b.action_into(init, "A", goal);
    let orphan = b.place("orphan");
    b.transition("never", &[(orphan, 1)], &[(goal, 1)]);
    let report = check(&build(b), LIMIT);
    assert_eq!(verdict(&report, Property::Minimality), &Verdict::Failed);
    let [
        Failure::DeadTransition {
            transition,
            element,
            why,
        },
    ] = failures_of(&report, Property::Minimality)[..]
    else {
        panic!("one dead transition expected: {report}");
    };
    assert_eq!(
        why,
        &["its input place p4 'orphan' is never marked: no arc leads into it and it starts empty"]
    );
    assert_eq!(*transition, TransitionId::new(2));
    assert_eq!((element.id.as_str(), element.label.as_str()), ("t3", "never"));
    for property in [Property::Safety, Property::Effectiveness, Property::Deadlock] {
        assert_eq!(verdict(&report, property), &Verdict::Passed, "{property:?}");
    }
    let text = report.to_string();
    assert!(text.contains("transition t3 'never' can never fire"), "{text}");
    assert!(text.contains("never marked (1): p4 'orphan'"), "{text}");
}

#[test]
fn two_starts_into_one_execution_place_fail_safety() {
    let mut b = PlanBuilder::new("double_start");
    let init = b.initial_place("init");
    let branches = b.fork(init, 2);
    let exec = b.place("A.exec");
    let done = b.place("done");
    b.transition("A.start", &[(branches[0], 1)], &[(exec, 1)]);
    b.transition("A.start", &[(branches[1], 1)], &[(exec, 1)]);
    b.transition("A.end", &[(exec, 1)], &[(done, 1)]);
    let goal = b.goal_place();
    b.transition("both", &[(done, 2)], &[(goal, 1)]);
    let report = check(&build(b), LIMIT);
    assert!(!report.passed());
    assert_eq!(verdict(&report, Property::Safety), &Verdict::Failed);
    let [
        Failure::UnsafeExecution {
            place,
            action,
            bound,
            example,
            ..
        },
    ] = failures_of(&report, Property::Safety)[..]
    else {
        panic!("one safety failure expected: {report}");
    };
    assert_eq!(*place, PlaceId::new(3));
    assert_eq!(action, "A");
    assert_eq!(*bound, Count::Finite(2));
    assert_eq!(example.marking, "A.exec*2");
    assert_eq!(example.trace, ["fork", "A.start", "A.start"]);
    // `done` also holds two tokens, by design: a note, not a failure.
    assert!(
        report
            .notes
            .iter()
            .any(|n| matches!(n, Note::AboveOne { element, bound: Count::Finite(2), .. } if element.label == "done")),
        "{report}"
    );
    for property in [Property::Minimality, Property::Effectiveness, Property::Deadlock] {
        assert_eq!(verdict(&report, property), &Verdict::Passed, "{property:?}");
    }
    assert!(report.to_string().contains("would run twice at once"));
}

/// Thesis Figure 5.7: each pass of the loop adds a token to `passes`.
#[test]
fn the_loop_counter_is_unbounded_by_design_and_passes() {
    let report = check(&catalogued(catalog::loop_counter()), LIMIT);
    assert!(report.passed(), "{report}");
    assert!(report.complete);
    assert_eq!(report.bounds[1].bound, Count::Unbounded);
    assert!(report.has_unbounded());
    assert_eq!(
        report.notes,
        [Note::AboveOne {
            place: PlaceId::new(1),
            element: report.bounds[1].element.clone(),
            bound: Count::Unbounded
        }]
    );
    let text = report.to_string();
    assert!(text.contains("place p2 'passes' is unbounded"), "{text}");
    assert!(text.contains("coverability graph"), "{text}");
    // The junction is the one choice point.
    assert_eq!(report.choice_points.len(), 1);
    assert_eq!(report.choice_points[0].element.label, "junction");
}

#[test]
fn an_unbounded_place_that_is_read_leaves_effectiveness_inconclusive() {
    // `t1` pumps tokens into `pool` forever; `t2` drains one into the goal.
    let plan = raw_plan(
        &[("p1", "start", 1), ("p2", "pool", 0), ("p3", "goal", 0)],
        &[("t1", "pump"), ("t2", "drain")],
        &[
            ("p1", "t1", 1),
            ("t1", "p1", 1),
            ("t1", "p2", 1),
            ("p2", "t2", 1),
            ("t2", "p3", 1),
        ],
    );
    let report = check(&plan, LIMIT);
    assert!(report.complete);
    assert_eq!(report.bounds[1].bound, Count::Unbounded);
    let Verdict::Inconclusive(why) = verdict(&report, Property::Effectiveness) else {
        panic!("effectiveness should be inconclusive: {report}");
    };
    assert!(why.contains("p2 'pool'"), "{why}");
    assert!(!report.passed());
    assert!(report.to_string().contains("result: inconclusive"));
}

/// Thesis Figure 5.4: forks record the choice in a memory place; joins remove
/// the memory token before the goal.
#[test]
fn the_penalty_kick_memory_place_stays_one_bounded_and_passes() {
    let report = check(&catalogued(catalog::penalty_kick_memory()), LIMIT);
    assert!(report.passed(), "{report}");
    assert!(report.notes.is_empty(), "{report}");
    assert_eq!(report.bounds[2].bound, Count::Finite(1));
    assert_eq!(report.choice_points.len(), 1);
    assert_eq!(report.choice_points[0].element.label, "start");
}

#[test]
fn hitting_the_marking_limit_makes_passes_inconclusive() {
    let mut b = PlanBuilder::new("long");
    let mut at = b.initial_place("init");
    for i in 0..10 {
        at = b.action(at, &format!("A{i}")).done;
    }
    let goal = b.goal_place();
    b.transition("finish", &[(at, 1)], &[(goal, 1)]);
    let report = check(&build(b), 4);
    assert!(!report.complete);
    assert_eq!(report.markings, 4);
    assert!(report.failures.is_empty(), "{report}");
    for property in Property::ALL {
        assert!(
            matches!(verdict(&report, property), Verdict::Inconclusive(_)),
            "{property:?}: {report}"
        );
    }
    assert!(!report.passed());
    assert_eq!(report.outcome(), Outcome::Inconclusive);
    let text = report.to_string();
    assert!(text.contains("marking limit of 4 reached"), "{text}");
    assert!(text.contains("effectiveness  inconclusive"), "{text}");
    assert!(text.contains("result: inconclusive"), "{text}");
}

#[test]
fn a_failure_found_before_the_limit_is_still_a_failure() {
    let mut b = PlanBuilder::new("early_double_start");
    let init = b.initial_place("init");
    b.set_tokens(init, 2);
    let mut at = b.action(init, "A").done;
    for i in 0..10 {
        at = b.action(at, &format!("B{i}")).done;
    }
    let report = check(&build(b), 8);
    assert!(!report.complete);
    assert_eq!(verdict(&report, Property::Safety), &Verdict::Failed);
    assert!(matches!(
        verdict(&report, Property::Effectiveness),
        Verdict::NotApplicable(_)
    ));
}

#[test]
fn a_plan_without_goal_places_gets_a_note() {
    // Runs forever: a cycle of two actions.
    let mut b = PlanBuilder::new("forever");
    let init = b.initial_place("init");
    let a = b.action(init, "A");
    b.action_into(a.done, "B", init);
    let report = check(&build(b), LIMIT);
    assert!(report.passed(), "{report}");
    assert_eq!(report.notes, [Note::NoGoal]);
    assert!(matches!(
        verdict(&report, Property::Effectiveness),
        Verdict::NotApplicable(_)
    ));
    assert!(report.to_string().contains("no goal places"));
}

#[test]
fn overflow_beyond_255_tokens_counts_as_unbounded_without_panicking() {
    let plan = raw_plan(
        &[("p1", "heap", 255), ("p2", "", 0)],
        &[("t1", "grow")],
        &[("p1", "t1", 1), ("t1", "p1", 2)],
    );
    let report = check(&plan, LIMIT);
    assert_eq!(report.bounds[0].bound, Count::Unbounded);
    assert_eq!(report.bounds[1].bound, Count::Finite(0));
    assert!(report.complete);
    assert_eq!(report.markings, 2);
    // The heap and the empty place are independent parts.
    let exploration = explore(&plan, LIMIT);
    assert_eq!(exploration.parts().len(), 2);
    let graph = exploration.part_of(PlaceId::new(0));
    let last = graph.states().last().expect("two markings");
    assert!(graph.marking(last).is_none() && graph.has_omega(last));
    assert_eq!(graph.describe(&plan, last), "heap*ω");
}

#[test]
fn an_empty_net_is_no_plan() {
    let net = PetriNet::new("empty", Vec::new(), Vec::new(), &[]).expect("a net");
    let err = Plan::from_net(net, AllowedAtoms::Open).expect_err("nothing to run");
    assert!(err.to_string().contains("no places"), "{err}");
}

#[test]
fn an_unmarked_place_is_one_dead_marking() {
    let report = check(&raw_plan(&[("p", "idle", 0)], &[], &[]), 0);
    assert_eq!(report.markings, 1);
    assert_eq!(report.limit, 1);
    assert_eq!(verdict(&report, Property::Minimality), &Verdict::Passed);
    assert_eq!(verdict(&report, Property::Deadlock), &Verdict::Failed);
    assert!(report.to_string().contains("e.g. [-] (the initial marking)"));
}

#[test]
fn reports_are_deterministic() {
    let a = check(&sequence(), LIMIT).to_string();
    let b = check(&sequence(), LIMIT).to_string();
    assert_eq!(a, b);
}

/// Plans like the public PNP library's ROS demos: a loop that never marks the
/// goal place, which no arc reaches.
#[test]
fn a_plan_that_loops_for_ever_is_explained_by_its_goal_place_and_its_loop() {
    let mut b = PlanBuilder::new("patrol");
    let init = b.initial_place("init");
    let there = b.place("there");
    b.action_into(init, "goto", there);
    b.action_into(there, "home", init);
    b.goal_place();
    let report = check(&build(b), LIMIT);
    assert_eq!(verdict(&report, Property::Effectiveness), &Verdict::Failed);
    let text = report.to_string();
    assert!(
        text.contains("because the goal place p5 'goal' has no incoming arc: no transition ever marks it"),
        "{text}"
    );
    assert!(
        text.contains("and from [init] the plan loops for ever without reaching its goal: goto.start → goto.end → home.start → home.end leads back to it"),
        "{text}"
    );
}

#[test]
fn a_join_waiting_for_a_token_that_never_comes_is_named() {
    // Two exclusive branches joined as if both ran (the library's enabledTransitions plan).
    let mut b = PlanBuilder::new("bad_join");
    let init = b.initial_place("init");
    let a = b.place("after_a");
    let c = b.place("after_b");
    b.action_into(init, "A", a);
    b.action_into(init, "B", c);
    let goal = b.goal_place();
    b.transition("join", &[(a, 1), (c, 1)], &[(goal, 1)]);
    let report = check(&build(b), LIMIT);
    let text = report.to_string();
    assert!(text.contains("transition t5 'join' can never fire"), "{text}");
    assert!(
        text.contains("because its input places p2 'after_a', p3 'after_b' are never marked at the same time"),
        "{text}"
    );
    assert!(
        text.contains("the goal place p6 'goal' is never marked: the transitions into it (t5 'join') never fire"),
        "{text}"
    );
    assert!(
        text.contains("t5 'join', which takes the token of p2 'after_a', also needs a token in p3 'after_b': the plan waits there for ever"),
        "{text}"
    );
}

#[test]
fn passing_deadlock_without_a_goal_place_says_what_it_means() {
    let mut b = PlanBuilder::new("forever");
    let init = b.initial_place("init");
    let there = b.place("there");
    b.action_into(init, "goto", there);
    b.action_into(there, "home", init);
    let report = check(&build(b), LIMIT);
    assert!(report.passed(), "{report}");
    let text = report.to_string();
    assert!(
        text.contains("deadlock       passed         no reachable marking stops the plan: with no goal place it runs until stopped from outside"),
        "{text}"
    );
}

#[test]
fn an_empty_initial_marking_is_named() {
    let mut b = PlanBuilder::new("empty");
    let start = b.place("start");
    let goal = b.goal_place();
    b.action_into(start, "A", goal);
    let text = check(&build(b), LIMIT).to_string();
    assert!(
        text.contains("because no place holds a token at the start: give the initial place a token"),
        "{text}"
    );
}

/// A chain of `n` steps from `p0` to the goal place `p{n}`, as a raw net.
fn chain(n: usize) -> Plan {
    let places: Vec<(String, String, u8)> = (0..=n)
        .map(|i| {
            (
                format!("p{i}"),
                if i == n { "goal".into() } else { format!("s{i}") },
                u8::from(i == 0),
            )
        })
        .collect();
    let transitions: Vec<(String, String)> = (0..n).map(|i| (format!("t{i}"), String::new())).collect();
    let arcs: Vec<(String, String, u8)> = (0..n)
        .flat_map(|i| {
            [
                (format!("p{i}"), format!("t{i}"), 1),
                (format!("t{i}"), format!("p{}", i + 1), 1),
            ]
        })
        .collect();
    raw_plan(
        &places
            .iter()
            .map(|(a, b, c)| (a.as_str(), b.as_str(), *c))
            .collect::<Vec<_>>(),
        &transitions
            .iter()
            .map(|(a, b)| (a.as_str(), b.as_str()))
            .collect::<Vec<_>>(),
        &arcs
            .iter()
            .map(|(a, b, c)| (a.as_str(), b.as_str(), *c))
            .collect::<Vec<_>>(),
    )
}

#[test]
fn a_huge_plan_with_few_tokens_is_checked_whole() {
    // 100 001 places: a marking stores its one marked place, not every place,
    // so every marking fits and the check concludes.
    let n = 100_000;
    let report = check(&chain(n), 1_000_000);
    assert!(report.complete, "{}", report.summary(3));
    assert_eq!((report.markings, report.stored, report.stop), (n + 1, n + 1, None));
    assert!(report.passed(), "{}", report.summary(3));
}

#[test]
fn the_limit_that_stops_an_exploration_is_named() {
    let plan = chain(20_000);
    // Markings and edges together outgrow one MiB before 20 000 markings.
    let report = check_within(
        &plan,
        Limits {
            markings: 1_000_000,
            memory: 1 << 20,
        },
    );
    assert!(!report.complete);
    let Some(Stop::Memory { limit, markings, edges }) = report.stop else {
        panic!("stopped by memory: {:?}", report.stop);
    };
    assert_eq!(limit, 1 << 20);
    assert!(
        markings < 20_000 && markings == report.stored && edges + 1 == markings,
        "{markings} {edges}"
    );
    let text = report.to_string();
    assert!(
        text.contains(&format!(
            "memory limit of 1 MiB ({markings} markings and {edges} edges stored) reached: exploration incomplete"
        )),
        "{text}"
    );
    assert!(
        matches!(report.verdict(Property::Safety), Some(Verdict::Inconclusive(why)) if why.contains("memory limit")),
        "{text}"
    );
    assert_eq!(report.to_json()["stopped_by"], "memory");
    // The marking limit, when it comes first, is the one named.
    let report = check(&plan, 100);
    assert_eq!(report.stop, Some(Stop::Markings { limit: 100 }));
    assert_eq!(report.to_json()["stopped_by"], "markings");
    assert!(report.to_string().contains("marking limit of 100 reached"));
}

#[test]
fn the_summary_cuts_every_list_and_the_json_holds_it_whole() {
    // Twelve transitions that never fire, from twelve places never marked.
    let mut b = PlanBuilder::new("orphans");
    let init = b.initial_place("init");
    let goal = b.goal_place();
    b.action_into(init, "A", goal);
    for i in 0..12 {
        let orphan = b.place(format!("orphan{i}"));
        b.transition(format!("never{i}"), &[(orphan, 1)], &[(goal, 1)]);
    }
    let report = check(&build(b), LIMIT);
    assert_eq!(report.outcome(), Outcome::Failed);
    assert_eq!(report.failures.len(), 12);
    let full = report.to_string();
    let summary = report.summary(5).to_string();
    assert!(full.contains("orphan11") && !full.contains("... and"), "{full}");
    assert!(summary.contains("never marked (12): "), "{summary}");
    assert!(
        summary.contains("'orphan4', ... and 7 more (--verbose shows all)"),
        "{summary}"
    );
    assert!(summary.contains("failures (12):"), "{summary}");
    assert!(
        summary.contains("  ... and 7 more failures (--verbose shows all)"),
        "{summary}"
    );
    assert!(!summary.contains("orphan5"), "{summary}");
    // The summary is the full report with lines cut, nothing reworded.
    for line in summary.lines().filter(|l| !l.contains("... and")) {
        assert!(full.contains(line), "'{line}' not in the full report");
    }
    assert!(summary.ends_with("result: FAILED\n"), "{summary}");

    let json = report.to_json();
    assert_eq!(json["result"], "FAILED");
    assert_eq!(json["passed"], false);
    assert_eq!(json["verdicts"]["minimality"], "FAILED");
    assert_eq!(json["verdicts"]["safety"], "passed");
    assert_eq!(json["failures"].as_array().map(Vec::len), Some(12));
    assert_eq!(json["bounds"]["never_marked"].as_array().map(Vec::len), Some(12));
    assert_eq!(json["bounds"]["never_marked"][11]["label"], "orphan11");
    assert_eq!(json["text"], full.as_str());
}
