//! The `learnpnp` binary end to end: exit codes and the files it writes.

use crate::util::{shipped_arg, temp_dir, text, write_in};
use crate::{learnpnp, short_experiment};
use std::path::Path;

use learnpnp::plan::PlanBuilder;
use learnpnp::pnml::{self, Dialect};

#[test]
fn check_exit_codes() {
    let ok = learnpnp(&["check", &shipped_arg("penalty_kick_memory.pnml")]);
    assert_eq!(ok.status.code(), Some(0), "{}", text(&ok.stdout));
    assert!(text(&ok.stdout).contains("result: passed"));

    // Two starts into one execution place after a fork: unsafe.
    let dir = temp_dir("check");
    let mut b = PlanBuilder::new("unsafe");
    let start = b.initial_place("start");
    let branches = b.fork(start, 2);
    let exec = b.place("twice.exec");
    b.transition("twice.start", &[(branches[0], 1)], &[(exec, 1)]);
    b.transition("twice.start", &[(branches[1], 1)], &[(exec, 1)]);
    let goal = b.goal_place();
    b.transition("twice.end", &[(exec, 2)], &[(goal, 1)]);
    let bad = dir.join("unsafe.pnml");
    pnml::write_file(&b.build_net().unwrap(), Dialect::Jarp, &bad).unwrap();
    let fails = learnpnp(&["check", bad.to_str().unwrap()]);
    assert_eq!(fails.status.code(), Some(1), "{}", text(&fails.stdout));
    assert!(text(&fails.stdout).contains("safety"), "{}", text(&fails.stdout));

    let garbage = write_in(
        &dir,
        "garbage.pnml",
        "<pnml><net><place id='p1'><name><value>[oops</value></name></place></net></pnml>",
    );
    let unreadable = learnpnp(&["check", garbage.to_str().unwrap()]);
    assert_eq!(unreadable.status.code(), Some(2));
    let err = text(&unreadable.stderr);
    assert!(
        err.contains("garbage.pnml") && err.contains("p1") && err.contains("[oops"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The verdict lines of a report: `(property, verdict)`.
fn verdicts(report: &str) -> Vec<(String, String)> {
    report
        .lines()
        .filter_map(|line| {
            let (property, rest) = line.split_once(' ')?;
            let verdict = ["passed", "FAILED", "inconclusive", "not applicable"]
                .into_iter()
                .find(|v| rest.trim_start().starts_with(v))?;
            ["safety", "minimality", "effectiveness", "deadlock"]
                .contains(&property)
                .then(|| (property.to_string(), verdict.to_string()))
        })
        .collect()
}

#[test]
fn check_of_a_big_plan_fits_a_screen_and_concludes() {
    // 1,217 places, 212 choice points: every marking stored, the check concludes.
    let taxi = shipped_arg("taxi.pnml");
    let out = learnpnp(&["check", &taxi]);
    let summary = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{summary}");
    assert!(summary.ends_with("result: passed\n"), "{summary}");
    assert!(
        summary.starts_with(
            "plan 'taxi': 1217 places, 2218 transitions, 212 choice point(s), 1217 reachable marking(s)\n"
        ),
        "{summary}"
    );
    assert!(summary.lines().count() < 40, "{summary}");
    assert!(summary.lines().all(|l| l.chars().count() < 320), "{summary}");
    assert!(
        summary.contains("  - p8 'get_R': t7 '[taxi_0_0]', ")
            && summary.contains(", ... and 17 more (--verbose shows all)\n"),
        "{summary}"
    );
    assert!(summary.contains("choice points (212):\n"), "{summary}");
    assert!(
        summary.contains("  ... and 204 more choice points (--verbose shows all)\n"),
        "{summary}"
    );

    let out = learnpnp(&["check", &taxi, "--verbose"]);
    let full = text(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{full}");
    assert!(!full.contains("... and"), "{full}");
    let get_r = full
        .lines()
        .find_map(|l| l.strip_prefix("  - p8 'get_R': "))
        .expect("the choice at get_R");
    assert_eq!(get_r.split(", ").count(), 25);
    assert_eq!(full.lines().filter(|l| l.starts_with("  - p")).count(), 212);
    // The summary is the full report with lists cut, nothing reworded.
    for line in summary.lines().filter(|l| !l.contains("... and")) {
        assert!(full.lines().any(|f| f == line), "'{line}' not in the full report");
    }

    let out = learnpnp(&["check", &taxi, "--json"]);
    assert_eq!(out.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(json["result"], "passed");
    assert_eq!(json["passed"], true);
    assert_eq!(json["places"], 1217);
    assert_eq!(
        (json["markings"].as_u64(), json["stored"].as_u64()),
        (Some(1217), Some(1217))
    );
    assert_eq!(json["complete"], true);
    assert_eq!(json["stopped_by"], serde_json::Value::Null);
    assert_eq!(json["bounds"]["at_most_one"], 1217);
    assert_eq!(json["choice_points"].as_array().map(Vec::len), Some(212));
    assert_eq!(json["text"], full.as_str());
    let from_json: Vec<(String, String)> = json["verdicts"]
        .as_object()
        .expect("verdicts")
        .iter()
        .map(|(p, v)| (p.clone(), v.as_str().expect("a verdict").to_string()))
        .collect();
    let mut from_text = verdicts(&summary);
    from_text.sort();
    assert_eq!(from_json.len(), 4);
    assert_eq!(from_json, from_text);

    let out = learnpnp(&["check", &taxi, "--json", "--verbose"]);
    assert_eq!(out.status.code(), Some(2), "the two forms are exclusive");
}

#[test]
fn check_names_the_limit_it_reached() {
    let taxi = shipped_arg("taxi.pnml");
    let out = learnpnp(&["check", &taxi, "--limit", "100", "--json"]);
    assert_eq!(out.status.code(), Some(3));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        (json["result"].as_str(), json["stopped_by"].as_str()),
        (Some("inconclusive"), Some("markings"))
    );
    assert!(
        json["reasons"]["safety"]
            .as_str()
            .is_some_and(|r| r.contains("the marking limit of 100 was reached")),
        "{json}"
    );
    // Three chains of 60 actions in parallel: 121^3 markings, far more than 1 MiB holds.
    let dir = temp_dir("limits");
    let mut b = learnpnp::plan::PlanBuilder::new("parallel");
    let start = b.initial_place("start");
    for (i, mut at) in b.fork(start, 3).into_iter().enumerate() {
        for j in 0..60 {
            at = b.action(at, &format!("A{i}_{j}")).done;
        }
    }
    let plan = dir.join("parallel.pnml");
    learnpnp::pnml::write_file(&b.build_net().expect("a net"), learnpnp::pnml::Dialect::Jarp, &plan).expect("write");
    let out = learnpnp(&["check", plan.to_str().expect("a path"), "--memory", "1"]);
    let report = text(&out.stdout);
    assert_eq!(out.status.code(), Some(3), "{report}");
    assert!(report.contains("\n  memory limit of 1 MiB ("), "{report}");
    assert!(
        report.contains(" edges stored) reached: exploration incomplete"),
        "{report}"
    );
    let _ = std::fs::remove_dir_all(&dir);
    let out = learnpnp(&["check", &taxi, "--memory", "0"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("from 1 to"), "{}", text(&out.stderr));
}

#[test]
fn check_exit_codes_tell_failed_from_inconclusive() {
    // A plan that fails (a dead marking), as text and as JSON.
    let untitled = crate::util::fixture("pnml/untitled.v2.pnml");
    let untitled = untitled.to_str().unwrap();
    let out = learnpnp(&["check", untitled]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stdout));
    assert!(text(&out.stdout).ends_with("result: FAILED\n"));
    let out = learnpnp(&["check", untitled, "--json"]);
    assert_eq!(out.status.code(), Some(1));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        (json["result"].as_str(), json["verdicts"]["deadlock"].as_str()),
        (Some("FAILED"), Some("FAILED"))
    );
    assert_eq!(json["failures"].as_array().map(Vec::len), Some(1));

    // A plan that passes, stopped by the marking limit: inconclusive.
    let kick = shipped_arg("penalty_kick_memory.pnml");
    let out = learnpnp(&["check", &kick, "--json"]);
    assert_eq!(out.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        (json["result"].as_str(), json["passed"].as_bool()),
        (Some("passed"), Some(true))
    );
    let out = learnpnp(&["check", &kick, "--limit", "2"]);
    assert_eq!(out.status.code(), Some(3), "{}", text(&out.stdout));
    assert!(text(&out.stdout).ends_with("result: inconclusive\n"));

    // A schema: its checks pass or fail, never inconclusive; as JSON too.
    let out = learnpnp(&["check", &shipped_arg("football_choice.schema"), "--json"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stdout));
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(
        (json["result"].as_str(), json["passed"].as_bool()),
        (Some("passed"), Some(true))
    );
    assert!(json["text"].as_str().is_some_and(|t| t.contains("result: passed")));
}

#[test]
fn convert_round_trips_between_dialects() {
    let dir = temp_dir("convert");
    let standard = dir.join("sutton.std.pnml");
    let back = dir.join("sutton.jarp.pnml");
    let out = learnpnp(&[
        "convert",
        &shipped_arg("sutton.pnml"),
        "--to",
        "standard",
        "-o",
        standard.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(std::fs::read_to_string(&standard).unwrap().contains("<page"));
    let out = learnpnp(&[
        "convert",
        standard.to_str().unwrap(),
        "--to",
        "jarp",
        "-o",
        back.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(
        pnml::read_file(&back).unwrap(),
        pnml::read_file(Path::new(&shipped_arg("sutton.pnml"))).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn dot_marks_choice_points() {
    let out = learnpnp(&["dot", &shipped_arg("choice_point.pnml")]);
    assert!(out.status.success());
    let dot = text(&out.stdout);
    assert!(dot.contains("digraph") && dot.contains("doublecircle"), "{dot}");
}

#[test]
fn an_experiment_writes_its_results_and_replays_with_its_seed() {
    let dir = temp_dir("experiment");
    let run = |out: &Path, threads: &str| {
        let mut args = short_experiment("parr-russell", "eps-sosmc", "4", "200");
        args.extend([
            "--eval-every",
            "50",
            "--seed",
            "7",
            "--threads",
            threads,
            "--out",
            out.to_str().unwrap(),
        ]);
        let o = learnpnp(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
    };
    let (a, b) = (dir.join("a"), dir.join("b"));
    run(&a, "1");
    run(&b, "2");
    for file in [
        "curve.csv",
        "runs.csv",
        "episodes.csv",
        "summary.json",
        "curve.svg",
        "traces.csv",
        "values.bin",
    ] {
        assert!(a.join(file).exists(), "{file} missing");
    }
    // Same seed, any thread count: same numbers.
    for file in ["curve.csv", "runs.csv", "episodes.csv"] {
        assert_eq!(
            std::fs::read(a.join(file)).unwrap(),
            std::fs::read(b.join(file)).unwrap(),
            "{file} differs"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(a.join("summary.json")).unwrap()).unwrap();
    for key in [
        "final_mean",
        "final_ci95",
        "final_greedy_mean",
        "wall_seconds",
        "episodes_per_second",
    ] {
        assert!(!summary[key].is_null(), "{key} missing");
    }
    assert_eq!(summary["spec"]["seed"], 7);
    let curve = std::fs::read_to_string(a.join("curve.csv")).unwrap();
    assert_eq!(
        curve.lines().count(),
        1 + 5,
        "header and evaluations at 0, 50, 100, 150, 200"
    );

    let values = learnpnp(&["values", a.join("values.bin").to_str().unwrap()]);
    assert!(values.status.success());
    let csv = text(&values.stdout);
    assert!(
        csv.starts_with("plan,choice_point,at,option,marking,value,visits,greedy") && csv.contains("MoveNorth.start"),
        "{csv}"
    );

    // A later experiment can start from the learned table; one learned on
    // a plan that shares nothing with the experiment's is refused.
    let resumed = dir.join("resumed");
    let values_file = a.join("values.bin");
    let mut args = short_experiment("parr-russell", "eps-sosmc", "2", "50");
    let (values_arg, resumed_arg) = (values_file.to_str().unwrap(), resumed.to_str().unwrap());
    args.extend([
        "--eval-every",
        "50",
        "--initial-values",
        values_arg,
        "--out",
        resumed_arg,
    ]);
    let o = learnpnp(&args);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let wrong = dir.join("wrong");
    let mut args = short_experiment("sutton", "eps-sosmc", "1", "10");
    args.extend(["--initial-values", values_arg, "--out", wrong.to_str().unwrap()]);
    let o = learnpnp(&args);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o.stderr).contains("share nothing with plan 'sutton'"),
        "{}",
        text(&o.stderr)
    );

    let svg = dir.join("both.svg");
    let plot = learnpnp(&[
        "plot",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert!(plot.status.success(), "{}", text(&plot.stderr));
    assert!(std::fs::read_to_string(&svg).unwrap().contains("eps-sosmc"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arguments_and_corrupt_tables_are_reported() {
    let dir = temp_dir("bad");
    let corrupt = write_in(&dir, "values.bin", b"not a value table");
    let out = learnpnp(&["values", corrupt.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("values.bin"));
    let out = learnpnp(&[
        "experiment",
        "parr-russell",
        "--algo",
        "eps-sosmc",
        "--assess",
        "sometimes",
    ]);
    assert!(!out.status.success());
    assert!(text(&out.stderr).contains("sometimes"));
    let _ = std::fs::remove_dir_all(&dir);
}
