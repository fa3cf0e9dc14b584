//! Bad input through the binary: plans that fail their checks, hostile XML,
//! corrupt value tables, closed pipes. Each gets one clear error (exit 2) or
//! a correct result.

use crate::util::{temp_dir, text, write_in};
use crate::{learnpnp, short_experiment};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use learnpnp::learning::persist;

fn path(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// `start -> [guard] -> goal`, as JARP PNML, with the given initial token count.
fn one_step_plan(initial: u8, guard: &str) -> String {
    format!(
        "<pnml><net id='n'>\
         <place id='p1'><name><value>start</value></name>\
         <initialMarking><value>Default,{initial}</value></initialMarking></place>\
         <place id='p2'><name><value>goal</value></name></place>\
         <transition id='t1'><name><value>{guard}</value></name></transition>\
         <arc id='a1' source='p1' target='t1'/><arc id='a2' source='t1' target='p2'/>\
         </net></pnml>"
    )
}

/// A short penalty-kick experiment learning in `plan`.
fn experiment_on(plan: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = short_experiment("penalty-kick", "sarsa0", "1", "10");
    args.extend([
        "--eval-every",
        "10",
        "--threads",
        "1",
        "--plan",
        path(plan),
        "--out",
        path(out),
    ]);
    args.extend_from_slice(extra);
    learnpnp(&args)
}

#[test]
fn plans_that_fail_their_checks_are_refused_unless_unchecked() {
    let dir = temp_dir("checks");
    let no_token = write_in(&dir, "no_token.pnml", one_step_plan(0, "[]"));
    let out = experiment_on(&no_token, &dir.join("out"), &[]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no_token.pnml") && err.contains("fails the structural checks") && err.contains("--unchecked"),
        "{err}"
    );
    assert!(err.contains("effectiveness") && err.contains("can never fire"), "{err}");
    assert!(!dir.join("out").exists(), "nothing was run");
    // An expert may run it anyway.
    let out = experiment_on(&no_token, &dir.join("out"), &["--unchecked"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    // A plan that passes runs without the flag.
    let fine = write_in(&dir, "fine.pnml", one_step_plan(1, "[]"));
    let out = experiment_on(&fine, &dir.join("fine-out"), &[]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn empty_and_hostile_xml_is_refused_by_every_command() {
    let dir = temp_dir("xml");
    let empty = write_in(&dir, "empty.pnml", "<pnml><net id='n'></net></pnml>");
    // Deeply nested elements that hold no plan.
    let nested = dir.join("nested.pnml");
    let depth = 5000;
    std::fs::write(
        &nested,
        format!(
            "<pnml><net id='n'>{}{}</net></pnml>",
            "<a>".repeat(depth),
            "</a>".repeat(depth)
        ),
    )
    .expect("write");
    let converted = dir.join("x.pnml");
    for (file, expected) in [(&empty, "no places"), (&nested, "nest deeper than 100 levels")] {
        for command in [
            vec!["check", path(file)],
            vec!["dot", path(file)],
            vec!["convert", path(file), "--to", "standard", "-o", path(&converted)],
        ] {
            let out = learnpnp(&command);
            let err = text(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{command:?}: {err}");
            assert!(err.contains(expected) && err.contains(path(file)), "{command:?}: {err}");
        }
        let out = experiment_on(file, &dir.join("out"), &[]);
        assert_eq!(out.status.code(), Some(2));
        assert!(text(&out.stderr).contains(expected), "{}", text(&out.stderr));
    }
    assert!(!converted.exists());
    // A truncated file is reported where it ends, not at line 1, column 1.
    let full = std::fs::read_to_string(crate::util::root().join("plans").join("penalty_kick_plain.pnml"))
        .expect("shipped plan");
    let cut = &full[..full.len() / 2];
    let truncated = write_in(&dir, "truncated.pnml", cut);
    let out = learnpnp(&["check", path(&truncated)]);
    let err = text(&out.stderr);
    let lines = cut.lines().count();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        err.contains(&format!("line {lines},")) || err.contains(&format!("line {},", lines + 1)),
        "{err} (the text has {lines} lines)"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn errors_are_printed_once() {
    let dir = temp_dir("once");
    let bad_guard = write_in(&dir, "bad_guard.pnml", one_step_plan(1, "[and a]"));
    for out in [
        learnpnp(&["dot", path(&bad_guard)]),
        experiment_on(&bad_guard, &dir.join("out"), &[]),
    ] {
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert_eq!(err.matches("needs at least two operands").count(), 1, "{err}");
        assert!(err.contains("bad_guard.pnml") && err.contains("t1"), "{err}");
    }
    let file = write_in(&dir, "a-file", "x");
    let out = experiment_on(&bad_guard, &file.join("sub"), &[]);
    let err = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    for line in err.lines() {
        let parts: Vec<&str> = line.split(": ").collect();
        let mut unique = parts.clone();
        unique.dedup();
        assert_eq!(parts, unique, "repeated: {line}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn check_refuses_a_zero_limit_and_counts_are_checked() {
    let plan = crate::util::root().join("plans").join("football.pnml");
    let out = learnpnp(&["check", path(&plan), "--limit", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("at least 1"), "{}", text(&out.stderr));
    let out = learnpnp(&["reproduce", "--runs", "0"]);
    assert_eq!(out.status.code(), Some(2));
    let out = learnpnp(&["reproduce", "6.3", "--threads", "1000"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("from 1 to 256"), "{}", text(&out.stderr));
}

#[test]
fn a_closed_pipe_is_no_error() {
    let dir = temp_dir("pipe");
    // A plan whose DOT text, and whole check report, are far larger than a pipe's buffer.
    let mut b = learnpnp::plan::PlanBuilder::new("long");
    let mut at = b.initial_place("start");
    for i in 0..3000 {
        let next = b.place(format!("step{i}"));
        b.action_into(at, &format!("Act{i}"), next);
        at = next;
    }
    let goal = b.goal_place();
    b.action_into(at, "Last", goal);
    let plan = dir.join("long.pnml");
    learnpnp::pnml::write_file(&b.build_net().expect("a net"), learnpnp::pnml::Dialect::Jarp, &plan).expect("write");
    for args in [vec!["dot", path(&plan)], vec!["check", path(&plan), "--verbose"]] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_learnpnp"))
            .args(&args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("runs");
        // Read a little, as `head -1` does, then close the pipe.
        let mut first = [0u8; 16];
        let _ = child.stdout.take().expect("piped").read(&mut first);
        let out = child.wait_with_output().expect("ends");
        let err = text(&out.stderr);
        assert!(!err.contains("error") && !err.contains("panicked"), "{args:?}: {err}");
        assert!(
            // check: passed, failed or (a limit reached) inconclusive.
            out.status.code().is_some_and(|c| matches!(c, 0 | 1 | 3)),
            "{args:?}: {:?}",
            out.status
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_corrupt_value_table_is_an_error_unless_the_fallback_is_asked_for() {
    let dir = temp_dir("values");
    let learn = |out: &Path, extra: &[&str]| {
        let mut args = short_experiment("parr-russell", "eps-sosmc", "1", "40");
        args.extend(["--eval-every", "20", "--out", path(out)]);
        args.extend_from_slice(extra);
        learnpnp(&args)
    };
    let o = learn(&dir.join("first"), &[]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    // A table with a previous good version beside it, then damaged.
    let table = dir.join("v.bin");
    let saved = persist::load(&dir.join("first").join("values.bin")).expect("a table");
    persist::save(&table, &saved).expect("save");
    persist::save(&table, &saved).expect("save again: keeps .prev");
    std::fs::write(&table, b"LPNPVAL\0 damaged").expect("damage");

    let o = learn(&dir.join("strict"), &["--initial-values", path(&table)]);
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("v.bin") && err.contains("--initial-values-fallback"),
        "{err}"
    );
    assert!(!dir.join("strict").exists());

    let o = learn(
        &dir.join("fallback"),
        &["--initial-values", path(&table), "--initial-values-fallback"],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("v.bin.prev"), "{}", text(&o.stderr));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("fallback").join("summary.json")).expect("summary"))
            .expect("json");
    let used = summary["spec"]["initial_values"][0].as_str().expect("a path");
    assert!(used.ends_with("v.bin.prev"), "the summary names the table used: {used}");
    let _ = std::fs::remove_dir_all(&dir);
}
