//! What was learned, shown on the plan: `learnpnp values` groups a saved
//! table by choice point with options named by their transitions, and
//! `learnpnp dot --values` writes each option's value and updates on the plan,
//! marking the greedy one; both read the same grouping.

use crate::util::{shipped_arg, temp_dir};
use crate::{learnpnp, short_experiment};

fn ok(args: &[&str]) -> String {
    let out = learnpnp(args);
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn values_are_grouped_by_choice_point_and_drawn_on_the_plan() {
    let dir = temp_dir("kick");
    let out = dir.join("kick");
    let out = out.to_str().expect("a path");
    let printed = ok(&[
        "experiment",
        "penalty-kick",
        "--algo",
        "sarsa0",
        "--variant",
        "memory",
        "--runs",
        "1",
        "--episodes",
        "300",
        "--threads",
        "1",
        "--out",
        out,
    ]);
    // The run prints its full configuration first: the spec summary.json keeps.
    let json_end = printed.find("\n}\n").expect("the configuration's end") + 2;
    let json_start = printed.find("\n{").expect("the configuration's start") + 1;
    assert!(printed.starts_with("configuration (1 worker threads"), "{printed}");
    let printed_spec: serde_json::Value = serde_json::from_str(&printed[json_start..json_end]).expect("JSON");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(format!("{out}/summary.json")).expect("summary.json"))
            .expect("JSON");
    assert_eq!(printed_spec, summary["spec"]);
    assert_eq!(printed_spec["protocol"]["episodes"], 300);

    let table = format!("{out}/values.bin");
    // The plan comes from the experiment's summary.json.
    let csv = ok(&["values", &table]);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("plan,choice_point,at,option,marking,value,visits,greedy")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let start: Vec<&Vec<&str>> = rows.iter().filter(|r| r[1] == "start").collect();
    let options: Vec<&str> = start.iter().map(|r| r[3]).collect();
    assert_eq!(options, ["WalkStraight.start", "Turn.start"], "{csv}");
    let greedy: Vec<&&Vec<&str>> = start.iter().filter(|r| r[7] == "greedy").collect();
    assert_eq!(greedy.len(), 1, "one greedy option: {csv}");
    let best: f64 = greedy[0][5].parse().expect("a value");
    for r in &start {
        if let Ok(v) = r[5].parse::<f64>() {
            assert!(v <= best, "{csv}");
        }
    }
    // The same with the plan given, and a plan it was not learned on refused.
    assert_eq!(
        ok(&["values", &table, "--plan", &shipped_arg("penalty_kick_memory.pnml")]),
        csv
    );
    // The supervisor's summary (the main job's) holds the experiment's under `experiment`.
    let supervisor_like = dir.join("supervisor");
    std::fs::create_dir_all(&supervisor_like).expect("a directory");
    std::fs::copy(&table, supervisor_like.join("values.bin")).expect("copied");
    let nested = serde_json::json!({ "mode": "lockstep", "experiment": summary });
    std::fs::write(supervisor_like.join("summary.json"), nested.to_string()).expect("written");
    assert_eq!(
        ok(&["values", supervisor_like.join("values.bin").to_str().expect("a path")]),
        csv
    );
    let wrong = learnpnp(&["values", &table, "--plan", &shipped_arg("penalty_kick_plain.pnml")]);
    assert_eq!(wrong.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&wrong.stderr).contains("learned on plan 'penalty_kick_memory'"));

    // dot --values: the options' values on the plan, the greedy one starred and blue.
    let dot = ok(&["dot", &shipped_arg("penalty_kick_memory.pnml"), "--values", &table]);
    assert!(dot.contains("// Learned values (--values)"), "{dot}");
    for r in &start {
        let line = dot
            .lines()
            .find(|l| l.contains(&format!("label=\"{}\\n", r[3])))
            .unwrap_or_else(|| panic!("no labelled transition {}: {dot}", r[3]));
        let value: f64 = r[5].parse().expect("a value");
        assert!(line.contains(&format!("{value:.2} (n={})", r[6])), "{line}");
        assert_eq!(line.contains('★'), r[7] == "greedy", "{line}");
        assert_eq!(line.contains("color=blue"), r[7] == "greedy", "{line}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_table_without_its_plan_is_listed_per_marking_with_a_warning() {
    let dir = temp_dir("bare");
    let out = dir.join("pr");
    let out = out.to_str().expect("a path");
    let mut args = short_experiment("parr-russell", "eps-sosmc", "1", "50");
    args.extend(["--threads", "1", "--out", out]);
    ok(&args);
    let moved = dir.join("moved.bin");
    std::fs::copy(format!("{out}/values.bin"), &moved).expect("copied");
    let listed = learnpnp(&["values", moved.to_str().expect("a path")]);
    assert!(listed.status.success());
    assert!(String::from_utf8_lossy(&listed.stdout).starts_with("plan,marking,value,visits\n"));
    assert!(String::from_utf8_lossy(&listed.stderr).contains("give --plan PLAN"));
    let grouped = ok(&[
        "values",
        moved.to_str().expect("a path"),
        "--plan",
        &shipped_arg("parr_russell.pnml"),
    ]);
    assert!(grouped.lines().skip(1).any(|l| l.ends_with(",greedy")), "{grouped}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `plans/keepaway_pass.pnml` without the option `Pass2` (its place, its two
/// transitions and their arcs), as a designer would prune it.
fn without_pass2(pnml: &str) -> String {
    let mut out = String::new();
    let mut skipping = false;
    for line in pnml.lines() {
        let t = line.trim_start();
        let starts = [
            r#"<place id="p15">"#,
            r#"<transition id="t17">"#,
            r#"<transition id="t18">"#,
        ];
        let arc = t.starts_with("<arc ") && ["\"p15\"", "\"t17\"", "\"t18\""].iter().any(|id| t.contains(id));
        if starts.iter().any(|s| t.starts_with(s)) || (arc && !t.ends_with("/>")) {
            skipping = true;
            continue;
        }
        if arc {
            continue;
        }
        if skipping {
            if t.starts_with("</place>") || t.starts_with("</transition>") || t.starts_with("</arc>") {
                skipping = false;
            }
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

#[test]
fn values_carry_into_a_revised_plan_with_a_report() {
    let dir = temp_dir("revised");
    let full = shipped_arg("keepaway_pass.pnml");
    let revised = dir.join("no_pass2.pnml");
    let text = std::fs::read_to_string(&full).expect("the shipped plan");
    std::fs::write(&revised, without_pass2(&text)).expect("write");
    let revised = revised.to_str().expect("a path");
    let learned = dir.join("learned");
    let learned = learned.to_str().expect("a path");
    let common = [
        "--algo",
        "soft-sosmc",
        "--runs",
        "1",
        "--episodes",
        "40",
        "--threads",
        "1",
    ];
    let mut args = vec!["experiment", "keepaway-pass", "--plan", &full, "--out", learned];
    args.extend(common);
    ok(&args);
    let values = format!("{learned}/values.bin");
    let out = learnpnp(&["values", &values, "--plan", revised]);
    assert!(out.status.success());
    let (csv, err) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(
        err.contains("values carried into a revised plan") && err.contains("ball (-Pass2.start)"),
        "{err}"
    );
    assert!(!csv.contains("Pass2") && csv.contains("Pass1.start"), "{csv}");
    // The experiment starts from the carried values and writes the report.
    let next = dir.join("next");
    let next = next.to_str().expect("a path");
    let mut args = vec![
        "experiment",
        "keepaway-pass",
        "--plan",
        revised,
        "--initial-values",
        &values,
        "--out",
        next,
    ];
    args.extend(common);
    let out = learnpnp(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(format!("{next}/migration.json")).expect("migration.json"))
            .expect("JSON");
    let report = &report[0]["report"];
    assert!(report["kept"].as_u64().expect("a count") > 0, "{report}");
    assert!(
        report["dropped"]
            .as_array()
            .expect("a list")
            .iter()
            .all(|e| e["marking"].as_str().unwrap_or("").contains("Pass2.exec"))
    );
    assert_eq!(report["changed_choices"][0]["removed"][0], "Pass2.start");
    // The same plan: no report, the table as saved.
    let same = dir.join("same");
    let same = same.to_str().expect("a path");
    let mut args = vec![
        "experiment",
        "keepaway-pass",
        "--plan",
        &full,
        "--initial-values",
        &values,
        "--out",
        same,
    ];
    args.extend(common);
    ok(&args);
    assert!(!std::path::Path::new(&format!("{same}/migration.json")).exists());
}
