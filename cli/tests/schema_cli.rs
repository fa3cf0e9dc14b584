//! Plan schemas through the `learnpnp` binary: the process listing and drawing,
//! checks, and experiments in every domain with a schema as the plan.

use crate::learnpnp;
use crate::util::{SHIPPED_SCHEMAS, shipped_arg, temp_dir, text, write_in};
use std::path::Path;

#[test]
fn schema_lists_the_constructed_process() {
    let out = learnpnp(&["schema", &shipped_arg("football_choice.schema")]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let listing = text(&out.stdout);
    for expected in [
        "machine football_choice (root, plan key 0)",
        "|S| = 5 action states, |S_c| = 11 constituent states, |S_sp| = 16",
        "12 event transitions (1 loop), 12 plan-actions, 1 choice state (2 options)",
        "approach --closeToBall--> [approach, closeToBall, {FacingGoal, FarFromGoal}]",
        "approach --closeToBall--> approach   (no condition holds)",
        "[approach, closeToBall, {FacingGoal, FarFromGoal}] => side {SideKick, TrackBall}",
        "[approach, closeToBall, {FacingGoal, FarFromGoal}]: punt | side",
    ] {
        assert!(listing.contains(expected), "'{expected}' missing from:\n{listing}");
    }
}

#[test]
fn schema_dot_and_dot_draw_the_process() {
    let drawn = learnpnp(&["schema", "--dot", &shipped_arg("football.schema")]);
    assert_eq!(drawn.status.code(), Some(0), "{}", text(&drawn.stderr));
    let dot = text(&drawn.stdout);
    assert!(dot.starts_with("// learnpnp schema process"), "{dot}");
    assert!(
        dot.contains("digraph \"football\"") && dot.contains("cluster_1"),
        "{dot}"
    );
    assert!(dot.contains("style=dashed"), "plan-actions are drawn: {dot}");
    let same = learnpnp(&["dot", &shipped_arg("football.schema")]);
    assert_eq!(text(&same.stdout), dot);
}

#[test]
fn check_exit_codes_on_schemas() {
    for name in SHIPPED_SCHEMAS {
        let out = learnpnp(&["check", &shipped_arg(&format!("{name}.schema"))]);
        assert_eq!(out.status.code(), Some(0), "{name}: {}", text(&out.stdout));
        assert!(text(&out.stdout).contains("result: passed"));
    }
    let dir = temp_dir("check");
    let failing = write_in(
        &dir,
        "failing.schema",
        "machine m\n  initial s\n  state lonely {A}\n  state stuck\n  final f\n  s -> stuck\n  s -> f [x]\n",
    );
    let out = learnpnp(&["check", failing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out.stdout));
    let report = text(&out.stdout);
    assert!(
        report.contains("FAIL reachable: never entered from the initial state: lonely"),
        "{report}"
    );
    assert!(report.contains("FAIL no dead states"), "{report}");
    assert!(report.contains("FAIL effective"), "{report}");

    let malformed = write_in(&dir, "malformed.schema", "machine m\n  initial s\n  s -> t\n");
    for command in ["check", "schema", "dot"] {
        let out = learnpnp(&[command, malformed.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let err = text(&out.stderr);
        assert!(
            err.contains("malformed.schema: line 3: ") && err.contains("'t'"),
            "{command}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs a short experiment in `domain` with `schema` as the plan; returns the values listing.
fn short_experiment(domain: &str, schema: &str, algo: &[&str], dir: &Path) -> String {
    let out_dir = dir.join(domain);
    let plan = shipped_arg(&format!("{schema}.schema"));
    let mut args = vec![
        "experiment",
        domain,
        "--plan",
        &plan,
        "--runs",
        "2",
        "--episodes",
        "40",
        "--eval-every",
        "20",
        "--eval-episodes",
        "2",
        "--greedy-episodes",
        "2",
        "--threads",
        "1",
        "--out",
        out_dir.to_str().unwrap(),
        "--algo",
    ];
    args.extend_from_slice(algo);
    let out = learnpnp(&args);
    assert_eq!(out.status.code(), Some(0), "{domain}: {}", text(&out.stderr));
    let values = learnpnp(&["values", out_dir.join("values.bin").to_str().unwrap()]);
    assert_eq!(values.status.code(), Some(0), "{domain}: {}", text(&values.stderr));
    text(&values.stdout)
}

#[test]
fn schemas_learn_in_every_domain() {
    let dir = temp_dir("domains");
    for (domain, schema, option) in [
        ("penalty-kick", "penalty_kick", "[start, -, {true}: walk]"),
        (
            "parr-russell",
            "parr_russell",
            "[choose, -, {WallLeft, not WallRight}: north]",
        ),
        ("sutton", "sutton", ": north]"),
        ("keepaway-pass", "keepaway_pass", "[ball, -, {"),
        ("keepaway-position", "keepaway_position", "[start, -, {true}: at_"),
    ] {
        let values = short_experiment(domain, schema, &["eps-sosmc"], &dir);
        assert!(values.contains(option), "{domain}: no value for '{option}':\n{values}");
    }
    // Valuing every marking, sub-machines' values are saved under their names.
    let every = ["q-learning", "--every-marking"];
    let values = short_experiment("keepaway-position", "keepaway_position", &every, &dir);
    assert!(values.lines().any(|l| l.starts_with("Keeper")), "{values}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_schema_with_atoms_the_domain_lacks_is_refused() {
    let dir = temp_dir("atoms");
    let schema = write_in(
        &dir,
        "grid.schema",
        "machine grid\n  initial s {MoveNorth}\n  final f\n  s -> f on MoveNorth.finished [AtTheGoal]\n",
    );
    let out = learnpnp(&[
        "experiment",
        "parr-russell",
        "--plan",
        schema.to_str().unwrap(),
        "--algo",
        "eps-sosmc",
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = text(&out.stderr);
    assert!(
        err.contains("grid.schema: line 4: unknown atom") && err.contains("'AtTheGoal'"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
