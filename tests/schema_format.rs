//! The schema file format: shipped files load and round-trip through the
//! writer; every malformed input is refused with its line and token; the
//! builder makes the same schemas as the reader.

use crate::util::SHIPPED_SCHEMAS;
use crate::util::shipped;

use learnpnp::plan::AllowedAtoms;
use learnpnp::plan_file::load_plan;
use learnpnp::schema::{
    DecisionProcess, SchemaBuilder, SchemaFileError, StateKind, load_schema_plan, parse_schema, read_schema,
    write_schema,
};
use proptest::prelude::*;

#[test]
fn shipped_schemas_round_trip_through_the_writer() {
    for name in SHIPPED_SCHEMAS {
        let schema = read_schema(&shipped(&format!("{name}.schema"))).unwrap_or_else(|e| panic!("{e}"));
        let text = write_schema(&schema);
        let again = parse_schema(&text).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
        assert_eq!(write_schema(&again), text, "{name}");
        assert_eq!(again.machines().len(), schema.machines().len());
        for (a, b) in again.machines().iter().zip(schema.machines()) {
            assert_eq!(a.edges().len(), b.edges().len(), "{name}");
            assert_eq!(a.states().len(), b.states().len(), "{name}");
        }
    }
}

#[test]
fn shipped_schemas_load_as_plans() {
    for name in SHIPPED_SCHEMAS {
        let plan = load_plan(&shipped(&format!("{name}.schema")), AllowedAtoms::Open).unwrap_or_else(|e| panic!("{e}"));
        assert!(plan.schema_process().is_some(), "{name}");
        assert_eq!(
            plan.activation_plans().len(),
            read_schema(&shipped(&format!("{name}.schema")))
                .unwrap()
                .machines()
                .len()
        );
    }
}

#[test]
fn the_builder_makes_what_the_reader_reads() {
    let mut b = SchemaBuilder::new();
    b.machine("penalty_kick")
        .initial("start", &[])
        .state("walk", &["WalkStraight"])
        .state("turn", &["Turn"])
        .state("kick", &["Kick"])
        .final_state("done")
        .edge("start", "walk", None, None)
        .edge("start", "turn", None, None)
        .edge("walk", "kick", Some("WalkStraight.finished"), None)
        .edge("turn", "kick", Some("Turn.finished"), None)
        .edge("kick", "done", Some("Kick.finished"), None);
    let built = b.build().unwrap();
    let read = read_schema(&shipped("penalty_kick.schema")).unwrap();
    assert_eq!(write_schema(&built), write_schema(&read));
}

#[test]
fn writer_keeps_kinds_actions_events_and_conditions() {
    let text = "machine m\n  initial a {X, r1#Y}\n  state b\n  final ok\n  final bad failed\n  a -> b on X.finished [and c (not d)]\n  b -> ok\n  b -> bad on e\n\nmachine X\n  initial s\n  final f\n  s -> f\n";
    let schema = parse_schema(text).unwrap();
    assert_eq!(write_schema(&schema), text);
    let m = schema.root();
    assert_eq!(m.states()[3].kind, StateKind::Failure);
    assert_eq!(m.states()[0].actions, ["X", "r1#Y"]);
    assert_eq!(m.edges()[0].condition.to_guard_text(), "and c (not d)");
}

#[test]
fn comments_blank_lines_and_lists() {
    let text = "# a comment\n\nmachine m # trailing\n  initial a {r1#Kick}   # r1#Kick keeps its '#'\n  state b\n  state c\n  a -> b, c on e\n  b, c -> a\n";
    let schema = parse_schema(text).unwrap();
    assert_eq!(schema.root().edges().len(), 4);
    assert_eq!(schema.root().states()[0].actions, ["r1#Kick"]);
}

/// (schema text, line of the error, offending token, a word of the message)
const MALFORMED: &[(&str, usize, &str, &str)] = &[
    ("", 0, "<end>", "at least one machine"),
    ("state a\n", 1, "state", "before the first"),
    ("machine\n", 1, "<end>", "machine name"),
    ("machine a b\n", 1, "b", "only its name"),
    ("machine 1a\n  initial s\n", 1, "1a", "malformed machine name"),
    ("machine state\n  initial s\n", 1, "state", "keyword"),
    (
        "machine m\n  initial s\nmachine m\n  initial s\n",
        3,
        "m",
        "second machine",
    ),
    ("machine m\n  state s\n", 1, "m", "initial state"),
    ("machine m\n  initial s\n  initial t\n", 3, "t", "second initial"),
    ("machine m\n  initial s\n  state s\n", 3, "s", "second state"),
    ("machine m\n  initial\n", 2, "<end>", "state name"),
    ("machine m\n  initial s t\n", 2, "t", "action set"),
    ("machine m\n  initial s {A\n", 2, "<end>", "not closed"),
    ("machine m\n  initial s {A} x\n", 2, "x", "after the action set"),
    ("machine m\n  initial s A}\n", 2, "}", "without"),
    ("machine m\n  initial s {A {B}}\n", 2, "{", "brace inside"),
    ("machine m\n  initial s {A, A}\n", 2, "A", "twice"),
    ("machine m\n  initial s {A.b}\n", 2, "A.b", "malformed action"),
    ("machine m\n  initial s {on}\n  state on\n", 3, "on", "keyword"),
    ("machine m\n  initial s\n  final\n", 3, "<end>", "state name"),
    ("machine m\n  initial s\n  final f x\n", 3, "x", "only its name"),
    ("machine m\n  initial s\n  final f {A}\n", 3, "{A}", "only its name"),
    ("machine m\n  initial s\n  final s2\n  s2 -> s\n", 4, "s2", "absorbing"),
    ("machine m\n  initial s\n  s -> t\n", 3, "t", "no state"),
    ("machine m\n  initial s\n  x -> s\n", 3, "x", "no state"),
    ("machine m\n  initial s\n  -> s\n", 3, "<end>", "source state"),
    ("machine m\n  initial s\n  s ->\n", 3, "<end>", "target state"),
    ("machine m\n  initial s\n  s -> s,\n", 3, "s,", "target state"),
    ("machine m\n  initial s\n  s t -> s\n", 3, "t", "','"),
    ("machine m\n  initial s\n  s -> s -> s\n", 3, "->", "one '->'"),
    ("machine m\n  initial s\n  s -> s on\n", 3, "<end>", "event after"),
    ("machine m\n  initial s\n  s -> s on a b\n", 3, "b", "one event"),
    ("machine m\n  initial s\n  s -> s on (a)\n", 3, "(a)", "one atom"),
    ("machine m\n  initial s\n  s -> s on 9x\n", 3, "9x", "malformed event"),
    ("machine m\n  initial s\n  s -> s [a\n", 3, "<end>", "not closed"),
    (
        "machine m\n  initial s\n  s -> s [a] b\n",
        3,
        "b",
        "after the condition",
    ),
    ("machine m\n  initial s\n  s -> s a]\n", 3, "]", "without"),
    ("machine m\n  initial s\n  s -> s [and a]\n", 3, "<end>", "at least two"),
    (
        "machine m\n  initial s\n  s -> s [a and b]\n",
        3,
        "and",
        "'and' is an operator, written first: [and a b], not [a and b]",
    ),
    (
        "machine m\n  initial s\n  s -> s [not]\n",
        3,
        "not",
        "malformed condition",
    ),
    (
        "machine m\n  initial s\n  s -> s on A.finished\n",
        3,
        "A.finished",
        "does not run",
    ),
    ("machine m\n  initial s {A}\n  s -> s [B.x]\n", 3, "B.x", "does not run"),
    (
        "machine m\n  initial s {A}\n  s -> s on A.\n",
        3,
        "A.",
        "empty internal",
    ),
    (
        "machine m\n  initial s\n  s -> s\n  s -> s [true]\n  s -> s\n",
        5,
        "s -> s",
        "repeated",
    ),
    ("machine m\n  initial s\n  s => s\n", 3, "s", "expected 'machine'"),
    ("machine m\n  initial s {m}\n", 2, "m", "calls itself"),
    (
        "machine m\n  initial s {n}\nmachine n\n  initial t {m}\n",
        4,
        "m",
        "calls itself",
    ),
    ("machine m\n  initial s\n  final f {\n", 3, "{", "only its name"),
    (
        "machine m\n  final f\n  initial f2 {}\n  final f2\n",
        4,
        "f2",
        "second state",
    ),
];

#[test]
fn every_malformed_input_names_its_line_and_token() {
    for &(text, line, token, word) in MALFORMED {
        let e = match parse_schema(text) {
            Ok(_) => panic!("accepted:\n{text}"),
            Err(e) => e,
        };
        let expected_line = if line == 0 { None } else { Some(line) };
        assert_eq!(e.line, expected_line, "{text:?}: {e}");
        assert_eq!(e.token, token, "{text:?}: {e}");
        assert!(e.message.contains(word), "{text:?}: '{word}' not in '{e}'");
        if let Some(l) = expected_line {
            assert!(e.to_string().starts_with(&format!("line {l}: ")), "{e}");
        }
    }
}

#[test]
fn file_errors_name_the_path_and_line() {
    let dir = std::env::temp_dir().join(format!("learnpnp-schema-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.schema");
    std::fs::write(&path, "machine m\n  initial s\n  s -> nowhere\n").unwrap();
    let e = load_schema_plan(&path, AllowedAtoms::Open).unwrap_err();
    assert!(matches!(e, SchemaFileError::Schema { .. }));
    let text = e.to_string();
    assert!(
        text.contains("bad.schema: line 3: ") && text.contains("'nowhere'"),
        "{text}"
    );
    let missing = load_schema_plan(&dir.join("missing.schema"), AllowedAtoms::Open).unwrap_err();
    assert!(matches!(missing, SchemaFileError::Io { .. }), "{missing}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn atoms_unknown_to_the_domain_are_refused_with_the_line() {
    let schema =
        parse_schema("machine m\n  initial s {MoveNorth}\n  final f\n  s -> f on MoveNorth.finished [Walll]\n")
            .unwrap();
    let atoms = learnpnp::domains::parr_russell::atoms();
    let e = DecisionProcess::new(&schema, AllowedAtoms::Closed(&atoms)).unwrap_err();
    assert_eq!(e.line, Some(4));
    assert_eq!(e.token, "Walll");
    assert!(e.message.contains("WallLeft"), "{e}");
}

#[test]
fn too_many_overlapping_conditions_are_refused() {
    let mut text = String::from("machine m\n  initial s\n  state t\n");
    for i in 0..13 {
        text.push_str(&format!("  s -> t [c{i}]\n"));
    }
    let schema = parse_schema(&text).unwrap();
    let e = DecisionProcess::new(&schema, AllowedAtoms::Open).unwrap_err();
    assert_eq!(e.line, Some(4));
    assert!(e.message.contains("at most 12"), "{e}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Mutilated shipped schemas never panic: they load or give a line-numbered error.
    #[test]
    fn mutilated_schemas_never_panic(cut in 0usize..2000, insert in "[ -~\n]{0,12}", which in 0usize..8) {
        let text = std::fs::read_to_string(shipped(&format!("{}.schema", SHIPPED_SCHEMAS[which]))).unwrap();
        let at = text.char_indices().map(|(i, _)| i).nth(cut % text.chars().count()).unwrap_or(0);
        let mut broken = text.clone();
        broken.insert_str(at, &insert);
        match parse_schema(&broken) {
            Ok(schema) => {
                let _ = DecisionProcess::new(&schema, AllowedAtoms::Open);
            }
            Err(e) => {
                if let Some(line) = e.line {
                    prop_assert!(line >= 1 && line <= broken.lines().count());
                }
            }
        }
    }
}
