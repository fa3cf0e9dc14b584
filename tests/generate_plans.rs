//! Plans generated from planners' plans (`learnpnp::generate`): each input
//! form against its golden file, the checks, both PNML dialects, every
//! learner, the execution rules and their errors, and the k-plan merge's
//! paths (a proptest).
//!
//! Regenerate the golden files after changing the generator:
//! `LEARNPNP_WRITE_GOLDEN=1 cargo test --test main generate_plans`

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::sync::Arc;

use learnpnp::agent::stepwise::{ActionOutcome, StepwiseAgent};
use learnpnp::analysis::{self, Outcome};
use learnpnp::condition::AtomTable;
use learnpnp::executor::Status;
use learnpnp::experiment::defaults::plan_learner;
use learnpnp::experiment::spec::Algorithm;
use learnpnp::generate::linear::{parse_ipc_plan, parse_linear_plan, parse_pnpgen_line};
use learnpnp::generate::rules::parse_rules;
use learnpnp::generate::{GenerateError, GeneratedPlan, PlanStep};
use learnpnp::learning::EpisodeMode;
use learnpnp::net::{NodeRef, PetriNet, PlaceId};
use learnpnp::plan::{AllowedAtoms, Plan};
use learnpnp::pnml::{self, Dialect};
use learnpnp::{Named, rng};
use proptest::prelude::*;

fn fixture(name: &str) -> PathBuf {
    crate::util::root().join("tests/fixtures/generate").join(name)
}

/// The plan passes every check.
fn assert_checks(plan: &Plan) {
    let report = analysis::check(plan, analysis::DEFAULT_LIMIT);
    assert_eq!(report.outcome(), Outcome::Passed, "{}: {report}", plan.name());
}

/// `net` equals its golden file (JARP), reads back from both dialects
/// unchanged, and passes the checks.
fn assert_golden(net: PetriNet, golden: &str) -> Plan {
    let path = fixture(golden);
    if std::env::var_os("LEARNPNP_WRITE_GOLDEN").is_some() {
        pnml::write_file(&net, Dialect::Jarp, &path).expect("write golden");
    }
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(
        pnml::write(&net, Dialect::Jarp),
        text,
        "{golden} differs; regenerate it"
    );
    for dialect in [Dialect::Jarp, Dialect::Standard] {
        let back = pnml::parse(&pnml::write(&net, dialect), "x").expect("reads back");
        assert_eq!(back, net, "{dialect:?}");
    }
    let plan = Plan::from_net(net, AllowedAtoms::Open).expect("plan");
    assert_checks(&plan);
    plan
}

#[test]
fn a_pnpgen_line_with_timeouts_is_a_sequence_of_timed_actions() {
    let steps = parse_pnpgen_line("goto_printer|30; say_hello; goto_home|15").expect("reads");
    assert_eq!(steps[0].timeout, Some(30));
    assert_eq!(steps[1], PlanStep::new("say_hello"));
    let plan = assert_golden(
        GeneratedPlan::sequence("printer", &steps).into_net().expect("net"),
        "printer.pnml",
    );
    let actions: Vec<&str> = plan.actions().iter().map(|a| a.name.as_str()).collect();
    assert!(
        actions.contains(&"wait_30") && actions.contains(&"goto_home"),
        "{actions:?}"
    );
}

#[test]
fn an_ipc_plan_file_is_read_with_its_comments_and_grounded_names() {
    let text = "(pick pkg depot)\n(move depot hall)\n; a comment\n(MOVE hall office)\n(drop pkg office)\n; cost = 4 (unit cost)\n";
    let steps = parse_linear_plan(text).expect("reads");
    let names: Vec<&str> = steps.iter().map(|s| s.action.as_str()).collect();
    assert_eq!(
        names,
        [
            "pick_pkg_depot",
            "move_depot_hall",
            "move_hall_office",
            "drop_pkg_office"
        ]
    );
    assert_golden(
        GeneratedPlan::sequence("delivery", &steps).into_net().expect("net"),
        "delivery_first.pnml",
    );
    let temporal = parse_ipc_plan("0.000: (move a b) [10.000]\n10.001: (load p t)  [2.000]\n").expect("reads");
    assert_eq!(temporal, [PlanStep::new("move_a_b"), PlanStep::new("load_p_t")]);
}

#[test]
fn bad_plans_are_errors_naming_line_and_token() {
    let e = parse_ipc_plan("(a b)\nmove a b\n").unwrap_err();
    assert!(
        matches!(&e, GenerateError::BadStep { line: 2, token, .. } if token == "move a b"),
        "{e}"
    );
    let e = parse_pnpgen_line("a; b|soon").unwrap_err();
    assert!(
        matches!(&e, GenerateError::BadTimeout { line: 1, token, .. } if token == "b|soon"),
        "{e}"
    );
    let e = parse_ipc_plan("(go.to a)").unwrap_err();
    assert!(e.to_string().contains("go.to_a"), "{e}");
    assert_eq!(GeneratedPlan::merged("none", &[]).unwrap_err(), GenerateError::NoPlans);
}

fn plans(lines: &[&str]) -> Vec<Vec<PlanStep>> {
    lines.iter().map(|l| parse_pnpgen_line(l).expect("reads")).collect()
}

#[test]
fn k_plans_merge_into_choice_points_where_they_differ() {
    let k = plans(&[
        "pick move_depot_hall move_hall_office drop",
        "pick move_depot_corridor move_corridor_office drop",
        "pick move_depot_hall move_hall_corridor move_corridor_office drop",
        "pick move_depot_hall move_hall_office drop",
    ]);
    let plan = assert_golden(
        GeneratedPlan::merged("delivery_top3", &k)
            .expect("merge")
            .into_net()
            .expect("net"),
        "delivery_top3.pnml",
    );
    let report = analysis::check(&plan, analysis::DEFAULT_LIMIT);
    let options: Vec<BTreeSet<String>> = report
        .choice_points
        .iter()
        .map(|c| c.options.iter().map(|(_, e)| e.to_string()).collect())
        .collect();
    assert_eq!(options.len(), 2, "after pick, and after move_depot_hall: {options:?}");
    let every: String = format!("{options:?}");
    for start in [
        "move_depot_corridor.start",
        "move_hall_office.start",
        "move_hall_corridor.start",
    ] {
        assert!(every.contains(start), "{start} is an option: {every}");
    }
}

#[test]
fn a_plan_that_is_a_prefix_of_another_offers_to_finish() {
    let merged = GeneratedPlan::merged("prefix", &plans(&["a b", "a b c", ""])).expect("merge");
    let plan = Plan::from_net(merged.into_net().expect("net"), AllowedAtoms::Open).expect("plan");
    assert_checks(&plan);
    assert_eq!(
        paths(plan.net()),
        BTreeSet::from([
            vec![],
            vec!["a".into(), "b".into()],
            vec!["a".into(), "b".into(), "c".into()]
        ])
    );
}

#[test]
fn a_conditional_plan_becomes_a_plan_with_sensing() {
    let text = std::fs::read_to_string(crate::util::root().join("plans/pddl/door.condplan")).expect("shipped");
    let plan = assert_golden(
        GeneratedPlan::conditional("door", &text)
            .expect("generates")
            .into_net()
            .expect("net"),
        "door_condplan.pnml",
    );
    let guards: Vec<&str> = plan.net().transitions().iter().map(|t| t.label.as_str()).collect();
    assert!(
        guards.contains(&"sense_open.end [sense_open]") && guards.contains(&"sense_open.end [not sense_open]"),
        "{guards:?}"
    );
    let e = GeneratedPlan::conditional("x", "plan{ 0[label=0,actions=a]\n \"0\" -> \"9\" }").unwrap_err();
    assert!(e.to_string().contains("'9'"), "{e}");
}

#[test]
fn execution_rules_add_interrupts_with_their_recovery() {
    let rules = parse_rules(
        "# PNPgen's printer rules\n\
         *if* (and personhere closetotarget) *during* goto *do* skip_action\n\
         *if* (and personhere (not closetotarget)) *during* goto *do* say_MoveAway; waitfor_freespace; restart_action\n\
         *if* lowbattery *during* say_hello *do* goto_recharge; goal\n\
         *if* action_failed *during* goto_home *do* restart_plan\n",
    )
    .expect("reads");
    assert_eq!(rules.len(), 4);
    let mut generated = GeneratedPlan::sequence(
        "printer_rules",
        &parse_pnpgen_line("goto_printer|30; say_hello; goto_home|15").expect("reads"),
    );
    generated.apply_rules(&rules, None).expect("applies");
    let plan = assert_golden(generated.into_net().expect("net"), "printer_rules.pnml");
    let labels: Vec<&str> = plan.net().transitions().iter().map(|t| t.label.as_str()).collect();
    for l in [
        "goto_printer.interrupt [(and personhere closetotarget)]",
        "goto_home.interrupt [(and personhere (not closetotarget))]",
        "say_hello.interrupt [lowbattery]",
        "goto_home.fail",
        "restart_plan",
        "goal",
    ] {
        assert!(labels.contains(&l), "{l} in {labels:?}");
    }
}

/// PNPgen's printer plan with a rule that gives up on a low battery.
fn giving_up() -> GeneratedPlan {
    let rules = parse_rules("*if* lowbattery *during* say *do* goto_recharge; fail_plan").expect("reads");
    let mut generated = GeneratedPlan::sequence(
        "gives_up",
        &parse_pnpgen_line("goto; say_hello; goto_home").expect("reads"),
    );
    generated.apply_rules(&rules, None).expect("applies");
    generated
}

#[test]
fn a_fail_plan_rule_ends_in_a_declared_failure_end_that_check_accepts_and_pnml_keeps() {
    let net = giving_up().into_net().expect("net");
    for dialect in [Dialect::Jarp, Dialect::Standard] {
        let back = pnml::parse(&pnml::write(&net, dialect), "x").expect("reads back");
        let plan = Plan::from_net(back, AllowedAtoms::Open).expect("plan");
        let ends: Vec<&str> = plan
            .fail()
            .iter()
            .map(|&(p, _)| plan.net().places()[p.index()].label.as_str())
            .collect();
        assert_eq!(ends, ["fail"], "{dialect:?}: the failure end is kept");
        let report = analysis::check(&plan, analysis::DEFAULT_LIMIT);
        assert_eq!(report.outcome(), Outcome::Passed, "{dialect:?}: {report}");
        // The recovery's markings: before goto_recharge, during and after it.
        assert!(
            report.to_string().contains("3 reachable marking(s) can end only there"),
            "{report}"
        );
    }
}

#[test]
fn an_episode_ending_in_the_failure_end_is_failed_for_every_learner() {
    let plan = Arc::new(giving_up().into_plan(AllowedAtoms::Open).expect("plan"));
    for &algorithm in Algorithm::ALL {
        let learner = plan_learner(algorithm).build(rng::seeded(5));
        let mut agent = StepwiseAgent::new(plan.clone(), learner).expect("binds");
        let low = agent.atom("lowbattery").expect("an atom");
        let mut ran: Vec<String> = Vec::new();
        let mut next = agent.act(ActionOutcome::Finished).expect("steps");
        while let Some(i) = next {
            let name = agent.action_names()[i].clone();
            agent.reward(-1.0).expect("reward");
            next = if name == "say_hello" {
                // The battery runs low while it speaks: the rule interrupts it.
                agent.set_atoms(&[low]);
                agent.act(ActionOutcome::Running)
            } else {
                agent.act(ActionOutcome::Finished)
            }
            .expect("steps");
            ran.push(name);
            assert!(ran.len() < 10, "{}: the plan ends", algorithm.name());
        }
        assert_eq!(ran, ["goto", "say_hello", "goto_recharge"], "{}", algorithm.name());
        assert_eq!(agent.status(), Status::Failed, "{}", algorithm.name());
        agent.end_episode();
        assert!(!agent.in_episode());
    }
}

/// The greedy route after `episodes` of learning with `algorithm` (seed
/// `seed`) on two routes, `risky` (which always fails, by a `fail_plan`
/// rule) and `safe slow` (which reaches the goal, paid 10); every action
/// costs 1: failing ends the episode with what was earned so far.
fn learned_route(algorithm: Algorithm, seed: u64, episodes: usize) -> Vec<String> {
    let mut generated = GeneratedPlan::merged("routes", &plans(&["risky", "safe slow"])).expect("merge");
    generated
        .apply_rules(
            &parse_rules("*if* danger *during* risky *do* fail_plan").expect("reads"),
            None,
        )
        .expect("applies");
    let plan = Arc::new(generated.into_plan(AllowedAtoms::Open).expect("plan"));
    let mut agent = StepwiseAgent::new(plan, plan_learner(algorithm).build(rng::seeded(seed))).expect("binds");
    let danger = agent.atom("danger").expect("an atom");
    agent.set_atoms(&[danger]);
    let mut route = Vec::new();
    for episode in 0..=episodes {
        if episode == episodes {
            agent.set_mode(EpisodeMode::Greedy);
        }
        route.clear();
        let mut next = agent.act(ActionOutcome::Finished).expect("steps");
        while let Some(i) = next {
            let name = agent.action_names()[i].clone();
            agent.reward(-1.0).expect("reward");
            // The world decides the rule: danger holds while `risky` runs.
            let outcome = if name == "risky" {
                ActionOutcome::Running
            } else {
                ActionOutcome::Finished
            };
            route.push(name);
            next = agent.act(outcome).expect("steps");
        }
        match agent.status() {
            Status::Goal => agent.reward(10.0).expect("reward"),
            status => assert_eq!(status, Status::Failed, "the plan has ended"),
        }
        agent.end_episode();
    }
    route
}

#[test]
fn learners_avoid_the_route_that_ends_in_failure() {
    for &algorithm in Algorithm::ALL.iter().filter(|&&a| a != Algorithm::Random) {
        let safe = (0..10)
            .filter(|&seed| learned_route(algorithm, seed, 200) == ["safe", "slow"])
            .count();
        assert!(safe >= 9, "{}: the safe route in {safe} of 10 seeds", algorithm.name());
    }
}

#[test]
fn a_rule_naming_what_the_plan_lacks_is_an_error_naming_it() {
    let steps = parse_pnpgen_line("goto_printer; say_hello").expect("reads");
    let rules = parse_rules("\n*if* door_locked *during* open_door *do* skip_action").expect("reads");
    let e = GeneratedPlan::sequence("p", &steps)
        .apply_rules(&rules, None)
        .unwrap_err();
    assert!(
        matches!(&e, GenerateError::UnknownRuleAction { line: 2, action, .. } if action == "open_door"),
        "{e}"
    );
    let rules = parse_rules("*if* door_lockd *during* goto *do* skip_action").expect("reads");
    let atoms: AtomTable = ["door_locked"].into_iter().collect();
    let e = GeneratedPlan::sequence("p", &steps)
        .apply_rules(&rules, Some(&atoms))
        .unwrap_err();
    assert!(
        matches!(&e, GenerateError::UnknownRuleAtom { atom, .. } if atom == "door_lockd"),
        "{e}"
    );
    for (text, says) in [
        ("*if* a *during* goto *do* wait; retry", "'retry'"),
        ("*if* a *during* goto skip_action", "*if* CONDITION"),
        ("*if* (and a *during* goto *do* skip_action", "does not read"),
        ("*if* a *during* goto *do* ", "recovery is empty"),
    ] {
        let e = parse_rules(text).unwrap_err();
        assert!(
            matches!(e, GenerateError::BadRule { line: 1, .. }) && e.to_string().contains(says),
            "{text}: {e}"
        );
    }
}

#[test]
fn a_generated_plan_runs_in_every_learner() {
    let k = plans(&["a b c", "a c", "b c", "b a c"]);
    let mut generated = GeneratedPlan::merged("every_learner", &k).expect("merge");
    generated
        .apply_rules(
            &parse_rules("*if* stuck *during* c *do* restart_action").expect("reads"),
            None,
        )
        .expect("applies");
    let plan = Arc::new(generated.into_plan(AllowedAtoms::Open).expect("plan"));
    assert_checks(&plan);
    for &algorithm in Algorithm::ALL {
        let learner = plan_learner(algorithm).build(rng::seeded(3));
        let mut agent = StepwiseAgent::new(plan.clone(), learner).expect("binds");
        for _ in 0..20 {
            let mut steps = 0;
            while agent.act(ActionOutcome::Finished).expect("steps").is_some() {
                agent.reward(-1.0).expect("reward");
                steps += 1;
                assert!(steps < 10, "{}: the plan ends", algorithm.name());
            }
            agent.end_episode();
        }
    }
}

/// The action sequences of the paths from `init` to `goal` of a merged
/// plan (a tree of places and one-in, one-out transitions).
fn paths(net: &PetriNet) -> BTreeSet<Vec<String>> {
    let mut out = BTreeSet::new();
    let init = net.places().iter().position(|p| p.label == "init").expect("init");
    let mut stack = vec![(init, Vec::new())];
    while let Some((place, seq)) = stack.pop() {
        if net.places()[place].label == "goal" {
            out.insert(seq);
            continue;
        }
        for arc in net
            .arcs()
            .iter()
            .filter(|a| a.source == NodeRef::Place(PlaceId::new(place)))
        {
            let NodeRef::Transition(t) = arc.target else { continue };
            let mut next: Vec<String> = seq.clone();
            if let Some(action) = net.transition(t).label.strip_suffix(".start") {
                next.push(action.to_string());
            }
            for out_arc in net.arcs().iter().filter(|a| a.source == NodeRef::Transition(t)) {
                if let NodeRef::Place(p) = out_arc.target {
                    stack.push((p.index(), next.clone()));
                }
            }
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Every input plan is a path of the merged net, and no other action
    /// sequence is; the merged plan passes the checks.
    #[test]
    fn the_merged_plans_paths_are_exactly_the_input_plans(
        input in prop::collection::vec(prop::collection::vec(0usize..4, 0..5), 1..6)
    ) {
        let names = ["a", "b", "c", "d"];
        let k: Vec<Vec<PlanStep>> = input.iter().map(|p| p.iter().map(|&i| PlanStep::new(names[i])).collect()).collect();
        let net = GeneratedPlan::merged("prop", &k).expect("merge").into_net().expect("net");
        let expected: BTreeSet<Vec<String>> = k.iter().map(|p| p.iter().map(|s| s.action.clone()).collect()).collect();
        prop_assert_eq!(paths(&net), expected);
        let plan = Plan::from_net(net, AllowedAtoms::Open).expect("plan");
        prop_assert_eq!(analysis::check(&plan, analysis::DEFAULT_LIMIT).outcome(), Outcome::Passed);
    }
}

/// A path below an element (`""`: the element itself) and the attributes it carries.
type Required = (&'static str, &'static [&'static str]);

/// What every element of a kind carries in the JARP files of PetriNetPlans
/// (v1.4.7: the editor's own plans, e.g. `PNP/plantests/*.pnml`, and what
/// PNPgen writes for JARP): a path below the element, and its attributes.
const JARP_ELEMENTS: &[(&str, &[Required])] = &[
    (
        "place",
        &[
            ("", &["id"]),
            ("graphics/position", &["x", "y"]),
            ("graphics/size", &["width", "height"]),
            ("name/value", &[]),
            ("name/graphics/offset", &["x", "y"]),
            ("initialMarking/value", &[]),
            ("toolspecific", &["tool", "version"]),
        ],
    ),
    (
        "transition",
        &[
            ("", &["id"]),
            ("graphics/position", &["x", "y"]),
            ("graphics/size", &["width", "height"]),
            ("name/value", &[]),
            ("name/graphics/offset", &["x", "y"]),
            ("toolspecific", &["tool", "version"]),
        ],
    ),
    (
        "arc",
        &[
            ("", &["id", "source", "target"]),
            ("inscription/value", &[]),
            ("inscription/graphics/offset", &["x", "y"]),
            ("toolspecific", &["tool", "version"]),
        ],
    ),
];

/// The child of `node` at `path` (`a/b`), if any.
fn at<'a>(node: roxmltree::Node<'a, 'a>, path: &str) -> Option<roxmltree::Node<'a, 'a>> {
    path.split('/')
        .filter(|s| !s.is_empty())
        .try_fold(node, |n, step| n.children().find(|c| c.has_tag_name(step)))
}

/// `text` (JARP PNML) has JARP's element structure, unique ids, arcs between
/// them, and a layered layout: every node placed, no two at one position.
fn assert_jarp_structure(name: &str, text: &str) {
    let doc = roxmltree::Document::parse(text).unwrap_or_else(|e| panic!("{name}: {e}"));
    let net = at(doc.root(), "pnml/net").unwrap_or_else(|| panic!("{name}: pnml/net"));
    assert_eq!(net.attribute("type"), Some("PTNet"), "{name}");
    assert!(at(net, "name/value").is_some(), "{name}: net/name/value");
    let mut ids = BTreeSet::new();
    let mut positions = BTreeSet::new();
    for &(kind, required) in JARP_ELEMENTS {
        for element in net.children().filter(|c| c.has_tag_name(kind)) {
            let id = element.attribute("id").unwrap_or("?");
            for &(path, attributes) in required {
                let found = at(element, path).unwrap_or_else(|| panic!("{name}: {kind} {id} lacks {path}"));
                for attribute in attributes {
                    assert!(
                        found.attribute(*attribute).is_some(),
                        "{name}: {kind} {id}: {path} lacks '{attribute}'"
                    );
                }
            }
            if kind == "arc" {
                continue;
            }
            assert!(ids.insert(id.to_string()), "{name}: id {id} twice");
            let position = at(element, "graphics/position").expect("checked above");
            let xy = (position.attribute("x").expect("x"), position.attribute("y").expect("y"));
            assert!(
                positions.insert((xy.0.to_string(), xy.1.to_string())),
                "{name}: {kind} {id} at {xy:?}, where another node is"
            );
        }
    }
    for arc in net.children().filter(|c| c.has_tag_name("arc")) {
        for end in ["source", "target"] {
            let node = arc.attribute(end).expect("checked above");
            assert!(ids.contains(node), "{name}: arc's {end} {node} is no node");
        }
    }
}

#[test]
fn generated_plans_in_jarp_have_jarps_element_structure_and_a_layered_layout() {
    let mut checked = 0;
    for entry in std::fs::read_dir(fixture("")).expect("fixtures") {
        let path = entry.expect("an entry").path();
        if path.extension().is_some_and(|e| e == "pnml") {
            let text = std::fs::read_to_string(&path).expect("reads");
            assert_jarp_structure(&path.display().to_string(), &text);
            checked += 1;
        }
    }
    assert!(checked >= 4, "the golden plans: {checked}");
    let k = plans(&["a b c", "a c", "b c", "b a c"]);
    let mut merged = GeneratedPlan::merged("merged", &k).expect("merge");
    merged
        .apply_rules(
            &parse_rules("*if* stuck *during* c *do* fail_plan").expect("reads"),
            None,
        )
        .expect("applies");
    let net = merged.into_net().expect("net");
    assert_jarp_structure("merged", &pnml::write(&net, Dialect::Jarp));
}
