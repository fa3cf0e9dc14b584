//! Write a plan with the builder, check it, and save it for the PNP editor
//! (JARP PNML) and for other Petri net tools (standard PNML).
//!
//! `cargo run --example build_and_save [DIR]` (default: a temporary directory).

use std::path::PathBuf;

use learnpnp::analysis::{DEFAULT_LIMIT, check};
use learnpnp::plan::{AllowedAtoms, PlanBuilder};
use learnpnp::plan_file::load_plan;
use learnpnp::pnml::{self, Dialect};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    run(std::env::args().nth(1))
}

/// The example, given the directory to write into (a temporary one by default); the tests call it
/// without the test harness's own arguments.
fn run(arg: Option<String>) -> Result<(), Box<dyn std::error::Error>> {
    let dir = arg.map_or_else(|| std::env::temp_dir().join("learnpnp-build-and-save"), PathBuf::from);
    std::fs::create_dir_all(&dir)?;

    // The penalty kick of thesis Figure 3.6: walk straight or turn, then kick.
    let mut b = PlanBuilder::new("penalty_kick_plain");
    let start = b.initial_place("start");
    let ready = b.place("ready");
    b.action_into(start, "WalkStraight", ready);
    b.action_into(start, "Turn", ready);
    let goal = b.goal_place();
    b.action_into(ready, "Kick", goal);

    // The net as the file will hold it, then the plan it means.
    let net = b.build_net()?;
    let plan = learnpnp::plan::Plan::from_net(net.clone(), AllowedAtoms::Open)?;
    let report = check(&plan, DEFAULT_LIMIT);
    print!("{report}");
    assert!(report.passed(), "the plan passes every check");

    let jarp = dir.join("penalty_kick_plain.pnml");
    let standard = dir.join("penalty_kick_plain.std.pnml");
    pnml::write_file(&net, Dialect::Jarp, &jarp)?;
    pnml::write_file(&net, Dialect::Standard, &standard)?;

    // Both files load back as the same plan.
    for file in [&jarp, &standard] {
        let back = load_plan(file, AllowedAtoms::Open)?;
        assert_eq!(back.net().places().len(), plan.net().places().len());
        assert_eq!(back.actions().len(), 3);
        println!(
            "wrote {} ({} places, {} transitions)",
            file.display(),
            back.net().places().len(),
            back.net().transitions().len()
        );
    }
    println!("check it with: learnpnp check {}", jarp.display());
    Ok(())
}

#[test]
fn the_example_runs() {
    run(None).expect("the example runs");
}
