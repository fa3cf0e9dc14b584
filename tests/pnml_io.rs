//! Reading and writing plan files in PNML: both dialects, errors, files, round trips.

use crate::util::{fixture, temp_dir};
use std::fs;

use learnpnp::net::{NetError, NodeRef, PetriNet, PlaceNode, Position, TransitionNode};
use learnpnp::pnml::{self, Dialect, PnmlError, PnmlFileError};

fn ids<T>(items: &[T], id: impl Fn(&T) -> &str) -> Vec<&str> {
    items.iter().map(id).collect()
}

/// A JARP net with the given body (no plan name comment).
fn jarp(body: &str) -> String {
    format!("<?xml version=\"1.0\"?>\n<pnml>\n<net id=\"n1\" type=\"PTNet\">\n{body}\n</net>\n</pnml>\n")
}

fn parse_err(text: &str) -> PnmlError {
    pnml::parse(text, "x").expect_err("the text should be rejected")
}

// ---------------------------------------------------------------- JARP

#[test]
fn reads_a_hand_written_jarp_plan() {
    let net = pnml::read_file(&fixture("pnml/fetch_choice.pnml")).unwrap();
    assert_eq!(net.name(), "fetch_choice", "from the PLAN NAME comment, trimmed");
    assert_eq!(ids(net.places(), |p| &p.id), ["p1", "p2", "p3", "p4", "p5"]);
    assert_eq!(ids(net.transitions(), |t| &t.id), ["t1", "t2", "t3"]);
    assert_eq!(
        ids(net.arcs(), |a| &a.id),
        ["a1", "a2", "a3", "a4", "a5", "a6", "a7"],
        "only the first net is read"
    );

    let labels = ids(net.places(), |p| &p.label);
    assert_eq!(
        labels,
        ["init", "goto_door.exec", "goto_door.exec", "goal", ""],
        "a place without a name has an empty label"
    );
    assert_eq!(net.places_labelled("goto_door.exec").count(), 2);
    let initial: Vec<u8> = net.places().iter().map(|p| p.initial).collect();
    assert_eq!(initial, [1, 0, 0, 0, 2], "Default,N counts N; absent counts 0");
    assert_eq!(net.places()[0].position, Some(Position { x: 40.0, y: 120.0 }));
    assert_eq!(net.places()[1].position, Some(Position { x: 160.5, y: 60.0 }));
    assert_eq!(net.places()[2].position, None);

    assert_eq!(net.transitions()[0].label, "goto_door.start [free && near]");
    assert_eq!(net.transitions()[0].position, Some(Position { x: 100.0, y: 60.0 }));
    let weights: Vec<u8> = net.arcs().iter().map(|a| a.weight).collect();
    assert_eq!(weights, [1, 1, 1, 1, 1, 2, 1], "absent inscription weighs 1");
    assert_eq!(net.node_id(net.arcs()[3].source), "t2");
    assert!(matches!(net.arcs()[3].target, NodeRef::Place(_)));
}

#[test]
fn plan_name_falls_back_to_the_file_name() {
    let net = pnml::read_file(&fixture("pnml/untitled.v2.pnml")).unwrap();
    assert_eq!(
        net.name(),
        "untitled",
        "the file name up to its first '.'; a lower-case 'plan name:' does not count"
    );
    let text = jarp(r#"<place id="p1"><name><value>a</value></name></place>"#);
    assert_eq!(pnml::parse(&text, "given").unwrap().name(), "given");
}

#[test]
fn keeps_labels_verbatim() {
    let text = jarp(
        "<place id=\"p1\"><name><value> </value></name></place>\
         <place id=\"p2\"><name><value><![CDATA[a<b]]> &amp; c</value></name></place>\
         <transition id=\"t1\"><name><value>[not x]  a.start </value></name></transition>",
    );
    let net = pnml::parse(&text, "x").unwrap();
    assert_eq!(net.places()[0].label, " ");
    assert_eq!(net.places()[1].label, "a<b & c");
    assert_eq!(net.transitions()[0].label, "[not x]  a.start ");
}

// ---------------------------------------------------------------- standard

#[test]
fn reads_standard_pnml_with_nested_pages() {
    let net = pnml::read_file(&fixture("pnml/nested_pages.pnml")).unwrap();
    assert_eq!(net.name(), "patrol", "net/name/text, trimmed");
    assert_eq!(
        ids(net.places(), |p| &p.id),
        ["start", "moving", "done"],
        "pages are collected recursively, in document order; toolspecific is skipped"
    );
    assert_eq!(ids(net.transitions(), |t| &t.id), ["go", "stop"]);
    assert_eq!(ids(net.arcs(), |a| &a.id), ["e3", "e1", "e2", "e4"]);
    assert_eq!(ids(net.places(), |p| &p.label), ["init", "patrol.exec", "goal"]);
    assert_eq!(net.transitions()[1].label, "patrol.end [at <home>]");
    assert_eq!(net.places()[0].initial, 3);
    assert_eq!(net.places()[1].initial, 0);
    assert_eq!(net.places()[0].position, Some(Position { x: -12.25, y: 300.0 }));
    assert_eq!(net.transitions()[0].position, Some(Position { x: 50.0, y: 300.0 }));
    let weights: Vec<u8> = net.arcs().iter().map(|a| a.weight).collect();
    assert_eq!(weights, [1, 2, 1, 1]);
}

#[test]
fn reads_pm4py_style_pnml_without_namespace_or_name() {
    let text = r#"<?xml version='1.0' encoding='UTF-8'?>
<pnml>
  <net id="net1" type="http://www.pnml.org/version-2009/grammar/pnmlcoremodel">
    <page id="n0">
      <place id="source"><name><text>source</text></name>
        <initialMarking><text>1</text></initialMarking></place>
      <place id="sink"><name><text>sink</text></name></place>
      <transition id="t"><name><text>a</text></name>
        <toolspecific tool="ProM" version="6.4" activity="$invisible$" localNodeID="x"/></transition>
      <arc id="1" source="source" target="t"/>
      <arc id="2" source="t" target="sink"><inscription><text>3</text></inscription></arc>
    </page>
    <finalmarkings><marking><place idref="sink"><text>1</text></place></marking></finalmarkings>
  </net>
</pnml>"#;
    let net = pnml::parse(text, "from_file").unwrap();
    assert_eq!(net.name(), "from_file");
    assert_eq!(ids(net.places(), |p| &p.id), ["source", "sink"]);
    assert_eq!(net.places()[0].initial, 1);
    assert_eq!(net.arcs()[1].weight, 3);
}

#[test]
fn matches_prefixed_namespaced_elements_by_local_name() {
    let text = r#"<p:pnml xmlns:p="http://www.pnml.org/version-2009/grammar/pnml">
  <p:net id="n"><p:name><p:text>ns</p:text></p:name><p:page id="g">
    <p:place id="a"><p:name><p:text>x</p:text></p:name></p:place>
    <p:transition id="b"/>
    <p:arc id="c" source="a" target="b"/>
  </p:page></p:net></p:pnml>"#;
    let net = pnml::parse(text, "x").unwrap();
    assert_eq!(net.name(), "ns");
    assert_eq!(net.places()[0].label, "x");
    assert_eq!(net.transitions()[0].label, "");
    assert_eq!(net.arcs().len(), 1);
}

// ---------------------------------------------------------------- errors

#[test]
fn malformed_xml_names_line_and_column() {
    let err = parse_err("<pnml>\n<net id=\"n1\">\n  <place id=\"p1\">\n</net>\n</pnml>");
    let PnmlError::Xml { line, column, message } = &err else {
        panic!("expected an XML error, got {err}");
    };
    assert_eq!((*line, *column), (4, 1), "{err}");
    assert!(message.contains("'place'"), "{err}");
    assert!(!message.contains("4:1"), "the position is given once: {err}");
    assert!(err.to_string().contains("line 4, column"), "{err}");
    assert!(matches!(parse_err(""), PnmlError::Xml { .. }));
    assert!(matches!(parse_err("<pnml>"), PnmlError::Xml { .. }));
}

#[test]
fn rejects_a_missing_root_or_net() {
    let err = parse_err("<petrinet><net id=\"n\"/></petrinet>");
    assert_eq!(
        err,
        PnmlError::NotPnml {
            found: "petrinet".into()
        }
    );
    assert!(err.to_string().contains("<petrinet>"), "{err}");
    assert_eq!(parse_err("<pnml><page/></pnml>"), PnmlError::NoNet);
}

#[test]
fn rejects_nodes_without_id() {
    let err = parse_err(&jarp("<place id=\"p1\"/>\n  <place>\n</place>"));
    assert_eq!(
        err,
        PnmlError::MissingId {
            element: "place",
            line: 5,
            column: 3
        }
    );
    assert_eq!(err.to_string(), "place at line 5, column 3 has no id");
    let err = parse_err(&jarp("<transition id=\"\"/>"));
    assert!(
        matches!(
            err,
            PnmlError::MissingId {
                element: "transition",
                ..
            }
        ),
        "{err}"
    );
    let err = parse_err(&jarp(
        "<place id=\"p\"/><transition id=\"t\"/><arc source=\"p\" target=\"t\"/>",
    ));
    assert!(matches!(err, PnmlError::MissingId { element: "arc", .. }), "{err}");
}

#[test]
fn rejects_arcs_without_ends() {
    let err = parse_err(&jarp(
        "<place id=\"p\"/><transition id=\"t\"/><arc id=\"a3\" source=\"p\"/>",
    ));
    assert_eq!(err.to_string(), "arc 'a3' has no target attribute");
    let err = parse_err(&jarp(
        "<place id=\"p\"/><transition id=\"t\"/><arc id=\"a4\" target=\"t\"/>",
    ));
    assert_eq!(err.to_string(), "arc 'a4' has no source attribute");
}

#[test]
fn bad_initial_markings_name_the_place_and_the_token() {
    for (value, token) in [
        ("Default,x", "Default,x"),
        ("-1", "-1"),
        ("Default,256", "Default,256"),
        (" 1.5 ", "1.5"),
        ("", ""),
        ("2,", "2,"),
    ] {
        let text = jarp(&format!(
            "<place id=\"p3\"><initialMarking><value>{value}</value></initialMarking></place>"
        ));
        let err = parse_err(&text);
        let message = err.to_string();
        assert!(
            message.starts_with(&format!("place 'p3': initial marking '{token}' is not a token count")),
            "{value:?}: {message}"
        );
    }
    let text = jarp("<place id=\"p\"><initialMarking><value>255</value></initialMarking></place>");
    assert_eq!(pnml::parse(&text, "x").unwrap().places()[0].initial, 255);
}

#[test]
fn bad_inscriptions_name_the_arc_and_the_token() {
    for value in ["Default,abc", "-2", "1000", "one"] {
        let text = jarp(&format!(
            "<place id=\"p\"/><transition id=\"t\"/>\
             <arc id=\"a9\" source=\"p\" target=\"t\"><inscription><value>{value}</value></inscription></arc>"
        ));
        let err = parse_err(&text);
        assert_eq!(
            err,
            PnmlError::BadCount {
                element: "arc",
                id: "a9".into(),
                field: "inscription",
                text: value.into()
            }
        );
        assert!(
            err.to_string()
                .starts_with(&format!("arc 'a9': inscription '{value}' is not a token count")),
            "{err}"
        );
    }
}

#[test]
fn net_level_errors_are_wrapped() {
    let cases = [
        (
            "<place id=\"p\"/><transition id=\"t\"/>\
             <arc id=\"a1\" source=\"p\" target=\"t\"><inscription><value>Default,0</value></inscription></arc>",
            NetError::ZeroWeight { arc: "a1".into() },
        ),
        (
            "<place id=\"p\"/><transition id=\"t\"/><arc id=\"a2\" source=\"p\" target=\"t9\"/>",
            NetError::DanglingArc {
                arc: "a2".into(),
                end: "target",
                node: "t9".into(),
            },
        ),
        (
            "<place id=\"p\"/><transition id=\"p\"/>",
            NetError::DuplicateId { id: "p".into() },
        ),
        (
            "<transition id=\"t1\"/><transition id=\"t2\"/><arc id=\"a3\" source=\"t1\" target=\"t2\"/>",
            NetError::SameKindArc {
                arc: "a3".into(),
                kind: "transition",
                source_id: "t1".into(),
                target_id: "t2".into(),
            },
        ),
        (
            "<place id=\"p\"/><transition id=\"t\"/>\
             <arc id=\"a4\" source=\"p\" target=\"t\"/><arc id=\"a5\" source=\"p\" target=\"t\"/>",
            NetError::RepeatedArc {
                arc: "a5".into(),
                source_id: "p".into(),
                target_id: "t".into(),
            },
        ),
    ];
    for (body, expected) in cases {
        let err = parse_err(&jarp(body));
        assert_eq!(err.to_string(), expected.to_string());
        assert_eq!(err, PnmlError::Net(expected));
    }
}

#[test]
fn file_errors_start_with_the_path() {
    let path = fixture("pnml/place_to_place.pnml");
    let err = pnml::read_file(&path).unwrap_err();
    assert!(matches!(err, PnmlFileError::Pnml { .. }));
    assert_eq!(err.path(), path);
    let message = err.to_string();
    assert!(
        message.starts_with(&format!("{}: arc 'a7' joins two places", path.display())),
        "{message}"
    );

    let missing = fixture("pnml/no_such_plan.pnml");
    let err = pnml::read_file(&missing).unwrap_err();
    assert!(matches!(err, PnmlFileError::Io { .. }), "{err}");
    assert!(
        err.to_string().starts_with(&format!("{}: ", missing.display())),
        "{err}"
    );
}

#[test]
fn reads_latin1_files() {
    let dir = temp_dir("latin1");
    let path = dir.join("caf.pnml");
    let mut bytes = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n<pnml><net id=\"n\" type=\"PTNet\">\
          <place id=\"p1\"><name><value>caf"
        .to_vec();
    bytes.extend_from_slice(b"\xe9.exec</value></name></place></net></pnml>");
    fs::write(&path, bytes).unwrap();
    let net = pnml::read_file(&path).unwrap();
    assert_eq!(net.places()[0].label, "café.exec");
    assert_eq!(net.name(), "caf");
    fs::remove_dir_all(&dir).unwrap();
}

// ---------------------------------------------------------------- writing

/// A net exercising every field, with XML-special and non-ASCII text.
fn sample_net() -> PetriNet {
    let place = |id: &str, label: &str, initial: u8, position: Option<Position>| PlaceNode {
        id: id.into(),
        label: label.into(),
        initial,
        position,
    };
    let transition = |id: &str, label: &str, position: Option<Position>| TransitionNode {
        id: id.into(),
        label: label.into(),
        position,
    };
    PetriNet::new(
        "fetch & <carry> \"it\"",
        vec![
            place("n1", "init", 1, Some(Position { x: 10.0, y: -2.5 })),
            place("p&2", "a<b>.exec", 0, None),
            place("p'3\"", "a<b>.exec", 7, Some(Position { x: 0.1, y: 1e-7 })),
            place("page1", " spaced\ttab\nline\r\n ", 255, None),
            place("c1", "", 0, None),
        ],
        vec![
            transition("t1", "[and a b] a<b>.start", Some(Position { x: 3.0, y: 4.0 })),
            transition("net1", "ünïcødé ✓ 🤖", None),
        ],
        &[
            ("a1", "n1", "t1", 1),
            ("a2", "t1", "p&2", 2),
            ("a3", "t1", "p'3\"", 1),
            ("a4", "p'3\"", "net1", 255),
            ("a5", "net1", "page1", 1),
        ],
    )
    .unwrap()
}

#[test]
fn round_trips_in_both_dialects() {
    let net = sample_net();
    for dialect in [Dialect::Jarp, Dialect::Standard] {
        let text = pnml::write(&net, dialect);
        let back = pnml::parse(&text, "fallback").unwrap_or_else(|e| panic!("{dialect}: {e}\n{text}"));
        assert_eq!(back, net, "{dialect}:\n{text}");
    }
}

#[test]
fn round_trips_real_layouts_across_dialects() {
    for name in ["fetch_choice.pnml", "nested_pages.pnml", "untitled.v2.pnml"] {
        let net = pnml::read_file(&fixture(&format!("pnml/{name}"))).unwrap();
        let standard = pnml::write(&net, Dialect::Standard);
        let via_standard = pnml::parse(&standard, "lost").unwrap();
        assert_eq!(via_standard, net, "{name}: jarp -> standard");
        let back = pnml::parse(&pnml::write(&via_standard, Dialect::Jarp), "lost").unwrap();
        assert_eq!(back, net, "{name}: standard -> jarp");
    }
}

#[test]
fn jarp_writer_emits_what_jarp_emits() {
    let text = pnml::write(&sample_net(), Dialect::Jarp);
    assert!(text.contains("type=\"PTNet\""), "{text}");
    assert!(text.contains("<value>Default,7</value>"), "{text}");
    assert!(text.contains("<value>Default,0</value>"), "{text}");
    assert!(text.contains("<value>Default,2</value>"), "{text}");
    assert!(
        text.contains("<value>PLAN NAME: fetch &amp; &lt;carry&gt; \"it\"</value>"),
        "{text}"
    );
    assert!(text.contains("<position x=\"10\" y=\"-2.5\"/>"), "{text}");
    assert!(!text.contains("<page"), "{text}");
    assert!(!text.contains("<text>PLAN"), "{text}");
    assert!(
        !text.contains("<net id=\"n1\""),
        "the net id must not clash with place n1:\n{text}"
    );
    assert!(!text.contains("<comment id=\"c1\""), "{text}");
}

#[test]
fn standard_writer_emits_the_2009_grammar() {
    let text = pnml::write(&sample_net(), Dialect::Standard);
    assert!(
        text.contains("<pnml xmlns=\"http://www.pnml.org/version-2009/grammar/pnml\">"),
        "{text}"
    );
    assert!(
        text.contains("type=\"http://www.pnml.org/version-2009/grammar/ptnet\""),
        "{text}"
    );
    assert_eq!(text.matches("<page ").count(), 1, "{text}");
    assert!(!text.contains("<value>"), "{text}");
    assert!(!text.contains("<comment"), "{text}");
    assert_eq!(
        text.matches("<initialMarking>").count(),
        3,
        "no initial marking when 0:\n{text}"
    );
    assert_eq!(
        text.matches("<inscription>").count(),
        2,
        "no inscription when 1:\n{text}"
    );
    assert!(!text.contains("<page id=\"page1\""), "{text}");
    assert!(!text.contains("<net id=\"net1\""), "{text}");
}

#[test]
fn write_file_replaces_the_file_atomically() {
    let dir = temp_dir("write");
    let path = dir.join("plan.v1.pnml");
    fs::write(&path, "old contents").unwrap();
    let net = sample_net();
    for dialect in [Dialect::Standard, Dialect::Jarp] {
        pnml::write_file(&net, dialect, &path).unwrap();
        assert_eq!(pnml::read_file(&path).unwrap(), net, "{dialect}");
    }
    let entries: Vec<_> = fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(entries, ["plan.v1.pnml"], "no temporary file is left behind");

    let err = pnml::write_file(&net, Dialect::Jarp, &dir.join("missing/plan.pnml")).unwrap_err();
    assert!(err.to_string().contains("missing/plan.pnml"), "{err}");
    fs::remove_dir_all(&dir).unwrap();
}
