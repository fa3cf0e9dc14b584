//! `learnpnp domains` and `learnpnp domain NAME` tell a plan author what each
//! domain offers, and what they say matches the domains' own plans; a plan
//! naming an action no domain registers is refused with the registered names.

use crate::{learnpnp, short_experiment};

use learnpnp::domains::describe::{domain, domains};
use learnpnp::plan::{AllowedAtoms, PlanBuilder};
use learnpnp::plan_file::load_plan;
use learnpnp::pnml::{self, Dialect};

#[test]
fn every_domain_is_described_and_its_plan_uses_only_what_is_listed() {
    let out = learnpnp(&["domains"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for d in domains() {
        assert!(text.contains(&format!("{}: ", d.name)), "{text}");
        let one = learnpnp(&["domain", d.name]);
        let one = String::from_utf8_lossy(&one.stdout);
        for part in ["plan: ", "actions (", "guards may test: ", "reward: ", "episode end: "] {
            assert!(one.contains(part), "{}: no {part}\n{one}", d.name);
        }
        assert!(!d.actions.is_empty(), "{}", d.name);
    }
    let plans = crate::util::root().join("plans");
    for (name, file) in [
        ("parr-russell", "parr_russell.pnml"),
        ("sutton", "sutton.pnml"),
        ("penalty-kick", "penalty_kick_memory.pnml"),
        ("keepaway-pass", "keepaway_pass.pnml"),
        ("keepaway-position", "keepaway_position.pnml"),
    ] {
        let d = domain(name).expect("a domain");
        let plan = load_plan(&plans.join(file), AllowedAtoms::Open).expect("the plan loads");
        let listed: Vec<String> = d.actions.iter().map(|a| a.pattern()).collect();
        for action in plan.actions() {
            assert!(
                listed.contains(&action.name),
                "{name}: {} is not listed: {listed:?}",
                action.name
            );
        }
        for atom in plan.atoms().names() {
            assert!(d.atoms.iter().any(|a| a == atom), "{name}: atom {atom} is not listed");
        }
    }
    let unknown = learnpnp(&["domain", "chess"]);
    assert_eq!(unknown.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("known: parr-russell, sutton"));
}

#[test]
fn an_unknown_action_lists_the_registered_ones() {
    let dir = std::env::temp_dir().join(format!("learnpnp-domains-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let mut b = PlanBuilder::new("fly");
    let start = b.initial_place("start");
    let goal = b.goal_place();
    b.action_into(start, "Fly", goal);
    let file = dir.join("fly.pnml");
    pnml::write_file(&b.build_net().expect("a net"), Dialect::Jarp, &file).expect("written");
    let out_dir = dir.join("out");
    let mut args = short_experiment("parr-russell", "sarsa0", "1", "10");
    args.extend([
        "--plan",
        file.to_str().expect("a path"),
        "--out",
        out_dir.to_str().expect("a path"),
    ]);
    let out = learnpnp(&args);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains(
            "no action or sub-plan is registered for 'Fly' (registered: MoveEast, MoveNorth, MoveSouth, MoveWest)"
        ),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
