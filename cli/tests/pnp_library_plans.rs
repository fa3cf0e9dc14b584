//! Plans written for the public PNP library load as that library loads them:
//! executables are called by name, so an `X.end` whose input place is not
//! `X.exec`, or an `X.start` into another action's place, is accepted with a
//! warning (the library's own test plans do both). The nets here are our own,
//! shaped like those test plans; blank labels (" ") as its editor leaves them.
//!
//! With `LEARNPNP_PNP_LIBRARY` naming a checkout of the library, every `.pnml`
//! file in it is also checked: none may be refused (exit 2), and every failed
//! check must say why.

use crate::util::temp_dir;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use learnpnp::plan::PlanBuilder;
use learnpnp::pnml::{self, Dialect};

fn check(path: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_learnpnp"))
        .arg("check")
        .arg(path)
        .output()
        .expect("the binary runs")
}

#[test]
fn calls_by_name_load_with_a_warning() {
    let dir = temp_dir("by-name");
    // An end of an action no place executes, after unlabelled steps (env1's shape).
    let mut b = PlanBuilder::new("by_name_end");
    let p1 = b.initial_place("P1");
    let p2 = b.place("P2");
    let goal = b.goal_place();
    b.transition(" ", &[(p1, 1)], &[(p2, 1)]);
    b.transition("RA_5.end", &[(p2, 1)], &[(goal, 1)]);
    let end = dir.join("by_name_end.pnml");
    pnml::write_file(&b.build_net().expect("a net"), Dialect::Jarp, &end).expect("written");

    // A start of A3 into A2's execution place (enabledTransitions2's shape).
    let mut b = PlanBuilder::new("start_elsewhere");
    let p1 = b.initial_place(" ");
    let p7 = b.initial_place(" ");
    let a2 = b.place("A2.exec");
    let goal = b.goal_place();
    b.transition("A2.start", &[(p1, 1)], &[(a2, 1)]);
    b.transition("A3.start", &[(p7, 1)], &[(a2, 1)]);
    b.transition("A2.end", &[(a2, 1)], &[(goal, 1)]);
    let start = dir.join("start_elsewhere.pnml");
    pnml::write_file(&b.build_net().expect("a net"), Dialect::Jarp, &start).expect("written");

    for (file, warning) in [
        (
            &end,
            "warning: transition 't2' (label 'RA_5.end'): no execution place names action 'RA_5'",
        ),
        (
            &start,
            "warning: transition 't2' (label 'A3.start'): no execution place names action 'A3' (it marks the execution place of 'A2', which thus runs without being started)",
        ),
    ] {
        let out = check(file);
        let text = String::from_utf8_lossy(&out.stdout);
        assert_ne!(
            out.status.code(),
            Some(2),
            "{}: {}",
            file.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(text.contains(warning), "{text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_plan_of_the_public_library_loads_and_failures_say_why() {
    let Some(root) = std::env::var_os("LEARNPNP_PNP_LIBRARY") else {
        eprintln!("skipped: set LEARNPNP_PNP_LIBRARY to a checkout of the PNP library to check its plans");
        return;
    };
    let mut stack = vec![PathBuf::from(root)];
    let mut files = Vec::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("a directory") {
            let path = entry.expect("an entry").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "pnml") {
                files.push(path);
            }
        }
    }
    assert!(!files.is_empty(), "no .pnml file found");
    for file in &files {
        let out = check(file);
        let text = String::from_utf8_lossy(&out.stdout);
        match out.status.code() {
            // Passed, or inconclusive (no failure to explain).
            Some(0 | 3) => {}
            Some(1) => assert!(
                text.contains("      because "),
                "{}: no reason given\n{text}",
                file.display()
            ),
            code => panic!(
                "{}: exit {code:?}: {}",
                file.display(),
                String::from_utf8_lossy(&out.stderr)
            ),
        }
    }
    eprintln!("{} plans of the PNP library checked", files.len());
}
