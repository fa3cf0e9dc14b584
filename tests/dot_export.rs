//! Graphviz DOT export: node shapes, colours, weights and escaping.

use crate::util::looking;
use learnpnp::dot::to_dot;
use learnpnp::plan::{AllowedAtoms, Plan, PlanBuilder};

/// A choice among A, B and giving up (into a fail place), with awkward labels.
fn demo() -> Plan {
    let mut b = PlanBuilder::new(r#"dot "demo""#);
    let init = b.initial_place(r#"the "start" \ place"#);
    let goal = b.goal_place();
    b.action_into(init, "A", goal);
    b.action_into(init, "B", goal);
    let fail = b.place("fail");
    b.transition(r#"give up [quote"d]"#, &[(init, 1)], &[(fail, 1)]);
    let pile = b.place("");
    b.transition("spill", &[(fail, 1)], &[(pile, 2)]);
    b.build(AllowedAtoms::Open).expect("demo plan builds")
}

/// Every line has an even number of unescaped double quotes.
fn quotes_balance(line: &str) -> bool {
    let mut count = 0;
    let mut escaped = false;
    for c in line.chars() {
        match c {
            _ if escaped => escaped = false,
            '\\' => escaped = true,
            '"' => count += 1,
            _ => {}
        }
    }
    count % 2 == 0
}

fn line_of<'a>(dot: &'a str, node: &str) -> &'a str {
    let prefix = format!("  \"{node}\" [");
    dot.lines()
        .find(|l| l.starts_with(&prefix))
        .unwrap_or_else(|| panic!("no node {node} in\n{dot}"))
}

#[test]
fn nodes_have_their_shapes_and_colours() {
    let dot = to_dot(&demo());
    assert!(dot.starts_with("// Petri Net Plan 'dot \"demo\"'"), "{dot}");
    assert!(dot.contains("// Legend:"), "{dot}");
    assert!(dot.contains("digraph \"dot \\\"demo\\\"\" {"), "{dot}");
    assert!(dot.trim_end().ends_with('}'));

    // The initial place is a choice point (A.start, B.start, give up).
    let init = line_of(&dot, "p1");
    assert!(init.contains("shape=doublecircle"), "{init}");
    assert!(init.contains("fillcolor=gold"), "{init}");
    assert!(init.contains(r#"label="the \"start\" \\ place\n●""#), "{init}");
    // The goal place: green, bold.
    let goal = line_of(&dot, "p2");
    assert!(
        goal.contains("shape=circle") && goal.contains("fillcolor=palegreen") && goal.contains("penwidth=2"),
        "{goal}"
    );
    // Execution places: filled, labelled with the action.
    let exec_a = line_of(&dot, "p3");
    assert!(
        exec_a.contains(r#"label="A""#) && exec_a.contains("fillcolor=lightblue"),
        "{exec_a}"
    );
    // The fail place: pink, bold.
    let fail = line_of(&dot, "p5");
    assert!(
        fail.contains("fillcolor=lightpink") && fail.contains("penwidth=2"),
        "{fail}"
    );
    // An unlabelled place shows its id.
    assert!(line_of(&dot, "p6").contains(r#"label="p6""#));

    // Transitions are boxes; a guard keeps its brackets, its quote is escaped.
    let give_up = line_of(&dot, "t5");
    assert!(
        give_up.contains(r#"shape=box, label="give up [quote\"d]""#),
        "{give_up}"
    );
    assert!(line_of(&dot, "t1").contains(r#"label="A.start""#));

    // Arcs, with the weight shown above 1 only.
    assert!(dot.contains("  \"p1\" -> \"t1\";\n"), "{dot}");
    assert!(dot.contains("  \"t6\" -> \"p6\" [label=\"2\"];\n"), "{dot}");

    for line in dot.lines() {
        assert!(quotes_balance(line), "unbalanced quotes: {line}");
    }
}

#[test]
fn complementary_sensing_outcomes_are_no_choice_point() {
    let (mut b, exec, goal) = looking("sensing");
    b.transition("look.end [seen]", &[(exec, 1)], &[(goal, 1)]);
    b.transition("look.end [not seen]", &[(exec, 1)], &[(goal, 1)]);
    let dot = to_dot(&b.build(AllowedAtoms::Open).expect("plan builds"));
    let nodes: Vec<&str> = dot.lines().filter(|l| l.contains("shape=")).collect();
    assert!(nodes.iter().all(|l| !l.contains("doublecircle")), "{dot}");
    assert_eq!(nodes.iter().filter(|l| l.contains("shape=circle")).count(), 3);
    assert_eq!(nodes.iter().filter(|l| l.contains("shape=box")).count(), 3);
    // Initial tokens are drawn.
    assert!(line_of(&dot, "p1").contains(r#"label="init\n●""#), "{dot}");
}

#[test]
fn output_is_deterministic() {
    assert_eq!(to_dot(&demo()), to_dot(&demo()));
}

/// `check` and `dot` agree on the choice points of every shipped plan: the
/// double circles are the places `check` lists.
#[test]
fn dot_draws_the_choice_points_check_reports() {
    let dir = crate::util::root().join("plans");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("plans/")
        .map(|e| e.expect("an entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "pnml"))
        .collect();
    files.sort();
    assert!(files.len() >= 10);
    for file in files {
        let plan = learnpnp::plan_file::load_plan(&file, AllowedAtoms::Open).expect("a shipped plan loads");
        let report = learnpnp::analysis::check(&plan, learnpnp::analysis::DEFAULT_LIMIT);
        let mut reported: Vec<String> = report.choice_points.iter().map(|c| c.element.id.clone()).collect();
        reported.sort();
        let dot = to_dot(&plan);
        let mut drawn: Vec<String> = dot
            .lines()
            .filter(|l| l.contains("shape=doublecircle"))
            .map(|l| {
                l.trim_start()
                    .trim_start_matches('"')
                    .split('"')
                    .next()
                    .unwrap_or("")
                    .to_string()
            })
            .collect();
        drawn.sort();
        assert_eq!(drawn, reported, "{}", file.display());
    }
}
