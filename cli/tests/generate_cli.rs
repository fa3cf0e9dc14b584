//! `learnpnp generate`: plans from planners' plans, end to end: the files
//! written in both dialects pass `learnpnp check`, the k plans merge into
//! choice points, rules and conditional plans, errors naming what is wrong.

use crate::learnpnp;
use crate::util::{temp_dir, text, write_in};

#[test]
fn k_ipc_plans_generate_a_plan_that_check_passes_in_both_dialects() {
    let dir = temp_dir("generate-k");
    let first = write_in(
        &dir,
        "sas_plan.1",
        "(pick parcel depot)\n(move depot hall)\n(move hall office)\n(drop parcel office)\n; cost = 4 (unit cost)\n",
    );
    let second = write_in(
        &dir,
        "sas_plan.2",
        "(pick parcel depot)\n(move depot corridor)\n(move corridor annex)\n(move annex office)\n(drop parcel office)\n",
    );
    let rules = write_in(
        &dir,
        "retry.er",
        "*if* door_locked *during* move_hall_office *do* wait_door; restart_action\n",
    );
    for dialect in ["jarp", "standard"] {
        let out_file = dir.join(format!("delivery-{dialect}.pnml"));
        let out = learnpnp(&[
            "generate",
            first.to_str().expect("utf-8"),
            second.to_str().expect("utf-8"),
            "--rules",
            rules.to_str().expect("utf-8"),
            "--atoms",
            "door_locked",
            "--name",
            "delivery",
            "--to",
            dialect,
            "-o",
            out_file.to_str().expect("utf-8"),
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        // After the pick (the two routes), and in the door's move (its end or
        // the rule's interrupt, both free to the check).
        assert!(text(&out.stderr).contains("2 choice points"), "{}", text(&out.stderr));
        let check = learnpnp(&["check", "--verbose", out_file.to_str().expect("utf-8")]);
        assert_eq!(check.status.code(), Some(0), "{}", text(&check.stdout));
        let report = text(&check.stdout);
        assert!(
            report.contains("move_depot_hall.start") && report.contains("move_depot_corridor.start"),
            "{report}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_pnpgen_line_and_a_conditional_plan_print_as_pnml() {
    let dir = temp_dir("generate-forms");
    let line = write_in(&dir, "printer.plan", "goto_printer|30; say_hello; goto_home|15\n");
    let out = learnpnp(&["generate", line.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("<value>wait_30.exec</value>"),
        "{}",
        text(&out.stdout)
    );
    let shipped = crate::util::root().join("plans/pddl/door.condplan");
    let out = learnpnp(&["generate", "--conditional", shipped.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("sense_open.end [not sense_open]"),
        "{}",
        text(&out.stdout)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn generate_errors_name_the_file_line_and_token() {
    let dir = temp_dir("generate-errors");
    let plan = write_in(&dir, "plan.txt", "(pick parcel depot)\nmove depot hall\n");
    let out = learnpnp(&["generate", plan.to_str().expect("utf-8")]);
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(
        err.contains("plan.txt") && err.contains("line 2") && err.contains("'move depot hall'"),
        "{err}"
    );
    let good = write_in(&dir, "good.plan", "goto; say\n");
    let rules = write_in(&dir, "bad.er", "*if* door_locked *during* open_door *do* skip_action\n");
    let out = learnpnp(&[
        "generate",
        good.to_str().expect("utf-8"),
        "--rules",
        rules.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(err.contains("bad.er") && err.contains("no action 'open_door'"), "{err}");
    let rules = write_in(&dir, "atom.er", "*if* door_lockd *during* goto *do* skip_action\n");
    let out = learnpnp(&[
        "generate",
        good.to_str().expect("utf-8"),
        "--rules",
        rules.to_str().expect("utf-8"),
        "--atoms",
        "door_locked",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("'door_lockd'"), "{}", text(&out.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_fail_plan_rule_generates_a_plan_that_check_passes_with_its_failure_end() {
    let dir = temp_dir("generate-fail-plan");
    let line = write_in(&dir, "printer.plan", "goto_printer|30; say_hello; goto_home|15\n");
    let rules = write_in(
        &dir,
        "gives_up.er",
        "*if* lowbattery *during* goto *do* goto_recharge; fail_plan\n",
    );
    for dialect in ["jarp", "standard"] {
        let out_file = dir.join(format!("gives_up-{dialect}.pnml"));
        let out = learnpnp(&[
            "generate",
            line.to_str().expect("utf-8"),
            "--rules",
            rules.to_str().expect("utf-8"),
            "--to",
            dialect,
            "-o",
            out_file.to_str().expect("utf-8"),
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
        let check = learnpnp(&["check", "--json", out_file.to_str().expect("utf-8")]);
        assert_eq!(check.status.code(), Some(0), "{}", text(&check.stdout));
        let report: serde_json::Value = serde_json::from_slice(&check.stdout).expect("json");
        assert_eq!(report["failure_ends"][0]["label"], "fail", "{report}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
