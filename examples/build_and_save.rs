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

    // A delivery robot: it reaches the office by one of three routes (the
    // choice point a learner will settle), then hands the parcel over.
    let mut b = PlanBuilder::new("deliver");
    let start = b.initial_place("start");
    let goal = b.goal_place();
    let at_office = b.place("at_office");
    for route in ["ViaCorridor", "ViaLab", "ViaStairs"] {
        b.action_into(start, route, at_office);
    }
    b.action_into(at_office, "HandOver", goal);

    // The net as the file will hold it, then the plan it means.
    let net = b.build_net()?;
    let plan = learnpnp::plan::Plan::from_net(net.clone(), AllowedAtoms::Open)?;
    let report = check(&plan, DEFAULT_LIMIT);
    print!("{report}");
    assert!(report.passed(), "the plan passes every check");

    let jarp = dir.join("deliver.pnml");
    let standard = dir.join("deliver.std.pnml");
    pnml::write_file(&net, Dialect::Jarp, &jarp)?;
    pnml::write_file(&net, Dialect::Standard, &standard)?;

    // Both files load back as the same plan.
    for file in [&jarp, &standard] {
        let back = load_plan(file, AllowedAtoms::Open)?;
        assert_eq!(back.net().places().len(), plan.net().places().len());
        assert_eq!(back.actions().len(), 4);
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
