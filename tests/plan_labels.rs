//! Interpreting place and transition labels; every error names the element and token.

use learnpnp::condition::{AtomRef, AtomTable, Condition};
use learnpnp::net::PetriNet;
use learnpnp::plan::{AllowedAtoms, Function, InternalKind, Plan, PlanError, catalog};

/// A net whose arcs all weigh 1.
fn net(places: &[(&str, &str, u8)], transitions: &[(&str, &str)], arcs: &[(&str, &str)]) -> PetriNet {
    let arcs: Vec<_> = arcs.iter().map(|&(s, t)| (s, t, 1)).collect();
    crate::util::net(places, transitions, &arcs)
}

/// init -> t1 -> goto.exec -> t2 -> done
fn action_net(start_label: &str, end_label: &str) -> PetriNet {
    net(
        &[("p1", "init", 1), ("p2", "goto.exec", 0), ("p3", "done goal", 0)],
        &[("t1", start_label), ("t2", end_label)],
        &[("p1", "t1"), ("t1", "p2"), ("p2", "t2"), ("t2", "p3")],
    )
}

fn load(n: PetriNet) -> Result<Plan, PlanError> {
    Plan::from_net(n, AllowedAtoms::Open)
}

#[test]
fn explicit_and_bare_functions_bind_to_the_action() {
    for (start, end) in [
        ("goto.start", "goto.end"),
        ("start", "end"),
        ("T1 start", "T2 goto.end"),
    ] {
        let plan = load(action_net(start, end)).unwrap();
        assert_eq!(plan.actions().len(), 1);
        let t = |i| plan.transition(learnpnp::net::TransitionId::new(i));
        assert_eq!(t(0).calls[0].function, Function::Start);
        assert_eq!(t(1).calls[0].function, Function::End);
        // The end waits implicitly for goto.finished.
        let Condition::Atom(AtomRef::Internal(i)) = t(1).guard else {
            panic!("implicit wait expected")
        };
        assert_eq!(plan.internal_conditions()[i as usize].kind, InternalKind::Finished);
        assert_eq!(plan.goal().len(), 1);
    }
}

#[test]
fn an_explicit_guard_replaces_the_implicit_wait() {
    let plan = load(action_net("goto.start", "goto.end [and arrived (not goto.failed)]")).unwrap();
    let t = plan.transition(learnpnp::net::TransitionId::new(1));
    assert_eq!(t.explicit_guard.as_deref(), Some("and arrived (not goto.failed)"));
    let names: Vec<String> = t.guard.atoms().into_iter().map(|a| plan.atom_name(a)).collect();
    assert_eq!(names, ["arrived", "goto.failed"]);
}

fn transition_error(start: &str, end: &str) -> PlanError {
    load(action_net(start, end)).unwrap_err()
}

#[test]
fn transition_label_errors_name_the_transition_and_token() {
    let cases = [
        (
            "goto.strat",
            "goto.end",
            "t1",
            "goto.strat",
            "unknown transition function",
        ),
        ("goto.start", "goto.end [a] [b]", "t2", "[b]", "at most one guard"),
        ("goto.start", "goto.end [a", "t2", "goto.end [a", "unbalanced"),
        ("end", "goto.end", "t1", "end", "no adjacent execution place"),
    ];
    for (start, end, id, token, reason) in cases {
        let err = transition_error(start, end);
        let msg = err.to_string();
        assert!(msg.contains(&format!("transition '{id}'")), "{msg}");
        assert!(msg.contains(&format!("'{token}'")), "{msg}");
        assert!(msg.contains(reason), "{msg}");
    }
}

#[test]
fn calls_of_actions_no_place_executes_are_accepted_with_a_warning() {
    // As the PNP library does: executables are called and asked by name.
    for (start, end, token) in [
        ("goto.start", "fly.end", "fly.end"),
        ("goto.start", "goto.end [fly.finished]", "fly.finished"),
    ] {
        let plan = load(action_net(start, end)).expect("accepted");
        assert!(plan.action_named("fly").is_some(), "{end}");
        assert!(plan.action(plan.action_named("fly").unwrap()).exec_places.is_empty());
        let warnings: Vec<String> = plan.warnings().iter().map(|w| w.to_string()).collect();
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(
            warnings[0].contains("transition 't2'") && warnings[0].contains("no execution place names action 'fly'"),
            "{warnings:?}"
        );
        assert!(warnings[0].contains(token), "{warnings:?}");
    }
    // A start into another action's place, an end taking another's token.
    let plan = load(action_net("fly.start", "goto.end")).expect("accepted");
    assert!(
        plan.warnings()[0]
            .message
            .contains("marks the execution place of 'goto'"),
        "{:?}",
        plan.warnings()
    );
    assert!(
        load(action_net("goto.start", "goto.end"))
            .unwrap()
            .warnings()
            .is_empty()
    );
}

#[test]
fn broken_guard_syntax_names_the_token() {
    let err = transition_error("goto.start", "goto.end [and a]");
    assert!(matches!(err, PlanError::Guard { ref transition, .. } if transition == "t2"));
    assert!(err.to_string().contains("two operands"), "{err}");
    let err = transition_error("goto.start", "goto.end [a b]");
    assert!(err.to_string().contains("'b'"), "{err}");
    let err = transition_error("goto.start", "goto.end [not 9lives]");
    assert!(err.to_string().contains("'9lives'"), "{err}");
}

#[test]
fn malformed_goal_tokens_are_refused() {
    for label in ["goalX", "goal(two)", "fail(0)", "goal goal"] {
        let n = net(&[("p1", label, 1)], &[], &[]);
        let err = load(n).unwrap_err();
        assert!(
            matches!(err, PlanError::PlaceLabel { ref place, .. } if place == "p1"),
            "{label}: {err}"
        );
    }
    let plan = load(net(&[("p1", "goal(2)", 1), ("p2", "fail", 0)], &[], &[])).unwrap();
    assert_eq!(plan.goal()[0].1, 2);
    assert_eq!(plan.fail()[0].1, 1);
}

#[test]
fn unknown_atoms_are_refused_against_a_domain() {
    let atoms: AtomTable = ["arrived", "blocked"].into_iter().collect();
    let err = Plan::from_net(
        action_net("goto.start", "goto.end [or arrived lost]"),
        AllowedAtoms::Closed(&atoms),
    )
    .unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("'lost'") && msg.contains("unknown atom") && msg.contains("arrived, blocked"),
        "{msg}"
    );
    // Known atoms resolve to the domain's ids.
    let plan = Plan::from_net(
        action_net("goto.start", "goto.end [blocked]"),
        AllowedAtoms::Closed(&atoms),
    )
    .unwrap();
    let t = plan.transition(learnpnp::net::TransitionId::new(1));
    assert_eq!(t.guard.atoms(), [AtomRef::Fact(atoms.get("blocked").unwrap())]);
}

#[test]
fn agent_prefix_and_parameters_stay_in_the_action_name() {
    let n = net(
        &[("p1", "init", 1), ("p2", "r1#gotopose_6_2_0.exec", 0), ("p3", "", 0)],
        &[("t1", "r1#gotopose_6_2_0.start"), ("t2", "r1#gotopose_6_2_0.end")],
        &[("p1", "t1"), ("t1", "p2"), ("p2", "t2"), ("t2", "p3")],
    );
    let plan = load(n).unwrap();
    let a = &plan.actions()[0];
    assert_eq!(a.name, "r1#gotopose_6_2_0");
    assert_eq!(a.agent.as_deref(), Some("r1"));
    assert_eq!(a.base_name(), "gotopose_6_2_0");
}

#[test]
fn places_sharing_an_exec_label_share_one_action() {
    let plan = Plan::from_net(catalog::penalty_kick_tree().unwrap(), AllowedAtoms::Open).unwrap();
    let kick = plan.action_named("Kick").unwrap();
    assert_eq!(plan.action(kick).exec_places.len(), 2);
}

#[test]
fn every_catalog_plan_loads() {
    for (name, n) in catalog::all().unwrap() {
        let plan = Plan::from_net(n, AllowedAtoms::Open).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(plan.name(), name);
    }
}
