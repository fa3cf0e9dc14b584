//! Property tests for PNML: random nets round-trip through both dialects, and
//! mutated PNML text never makes `parse` panic.

use std::collections::HashSet;
use std::sync::LazyLock;

use learnpnp::net::{PetriNet, PlaceNode, Position, TransitionNode};
use learnpnp::pnml::{self, Dialect};
use proptest::prelude::*;
use proptest::sample::Index;

/// `cases` cases; failures are saved next to this file (integration tests have
/// no lib.rs for proptest's default to find).
/// Text with XML-special characters, white space (carriage return included) and
/// non-ASCII characters.
fn text() -> impl Strategy<Value = String> {
    "[a-zA-Z0-9_.,:#()\\[\\] <>&\"'\t\n\r=;!?é✓🤖中\u{a0}]{0,12}"
}

fn position() -> impl Strategy<Value = Option<Position>> {
    let coord = prop_oneof![
        (-2000i32..2000).prop_map(f64::from),
        -1e6f64..1e6,
        prop::num::f64::NORMAL | prop::num::f64::SUBNORMAL | prop::num::f64::ZERO,
    ];
    prop::option::of((coord.clone(), coord).prop_map(|(x, y)| Position { x, y }))
}

/// A valid net: unique ids (`p<i>:`, `t<i>:`, `a<i>:` then random text), any
/// labels, markings and finite positions, arcs joining a place and a transition.
fn net() -> impl Strategy<Value = PetriNet> {
    let places = prop::collection::vec((text(), text(), any::<u8>(), position()), 0..6);
    let transitions = prop::collection::vec((text(), text(), position()), 0..6);
    let arcs = prop::collection::vec(
        (any::<Index>(), any::<Index>(), any::<bool>(), 1u8..=255, text()),
        0..12,
    );
    (text(), places, transitions, arcs).prop_map(|(name, places, transitions, arcs)| {
        let places: Vec<PlaceNode> = places
            .into_iter()
            .enumerate()
            .map(|(i, (id, label, initial, position))| PlaceNode {
                id: format!("p{i}:{id}"),
                label,
                initial,
                position,
            })
            .collect();
        let transitions: Vec<TransitionNode> = transitions
            .into_iter()
            .enumerate()
            .map(|(i, (id, label, position))| TransitionNode {
                id: format!("t{i}:{id}"),
                label,
                position,
            })
            .collect();
        let mut seen = HashSet::new();
        let mut specs = Vec::new();
        if !places.is_empty() && !transitions.is_empty() {
            for (i, (p, t, into_place, weight, id)) in arcs.into_iter().enumerate() {
                let p = &places[p.index(places.len())].id;
                let t = &transitions[t.index(transitions.len())].id;
                let (source, target) = if into_place { (t, p) } else { (p, t) };
                if seen.insert((source.clone(), target.clone())) {
                    specs.push((format!("a{i}:{id}"), source.clone(), target.clone(), weight));
                }
            }
        }
        let specs: Vec<_> = specs
            .iter()
            .map(|(id, s, t, w)| (id.as_str(), s.as_str(), t.as_str(), *w))
            .collect();
        PetriNet::new(name.trim(), places, transitions, &specs).expect("a valid random net")
    })
}

/// Valid PNML texts to mutate: every fixture and a written net in each dialect.
static SEEDS: LazyLock<Vec<String>> = LazyLock::new(|| {
    let dir = crate::util::root().join("tests/fixtures/pnml");
    let mut seeds: Vec<String> = std::fs::read_dir(dir)
        .expect("fixture directory")
        .map(|e| std::fs::read_to_string(e.expect("fixture").path()).expect("fixture text"))
        .collect();
    seeds.sort();
    let net =
        pnml::read_file(&crate::util::root().join("tests/fixtures/pnml/fetch_choice.pnml")).expect("valid fixture");
    seeds.push(pnml::write(&net, Dialect::Jarp));
    seeds.push(pnml::write(&net, Dialect::Standard));
    seeds
});

/// Fragments worth splicing in: markup, numbers and references that reach past
/// the XML parser into the PNML reader.
const SNIPPETS: &[&str] = &[
    "<",
    ">",
    "/",
    "\"",
    "'",
    ",",
    "&amp;",
    "&#0;",
    "&#x1F916;",
    "&bogus;",
    "<![CDATA[",
    "]]>",
    "<page>",
    "</page>",
    "<place id=\"p1\"/>",
    "<transition id=\"x\">",
    "</place>",
    "<value>",
    "</value>",
    "<text>",
    "Default,",
    "-1",
    "256",
    "0",
    " id=\"\"",
    " source=\"p1\"",
    "PLAN NAME:",
    "\u{0}",
    "é",
];

#[derive(Debug, Clone)]
enum Mutation {
    Delete(Index, usize),
    Insert(Index, u8),
    Replace(Index, u8),
    Splice(Index, Index),
    Truncate(Index),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        3 => (any::<Index>(), 1usize..40).prop_map(|(at, len)| Mutation::Delete(at, len)),
        3 => (any::<Index>(), any::<u8>()).prop_map(|(at, b)| Mutation::Insert(at, b)),
        3 => (any::<Index>(), any::<u8>()).prop_map(|(at, b)| Mutation::Replace(at, b)),
        3 => (any::<Index>(), any::<Index>()).prop_map(|(at, s)| Mutation::Splice(at, s)),
        1 => any::<Index>().prop_map(Mutation::Truncate),
    ]
}

fn apply(bytes: &mut Vec<u8>, mutation: &Mutation) {
    let len = bytes.len();
    let at = |i: &Index| i.index(len + 1);
    match mutation {
        Mutation::Delete(i, n) => {
            let start = at(i).min(len);
            bytes.drain(start..(start + n).min(len));
        }
        Mutation::Insert(i, b) => bytes.insert(at(i), *b),
        Mutation::Replace(i, b) => {
            if len > 0 {
                bytes[i.index(len)] = *b;
            }
        }
        Mutation::Splice(i, s) => {
            let snippet = SNIPPETS[s.index(SNIPPETS.len())].as_bytes();
            let at = at(i);
            bytes.splice(at..at, snippet.iter().copied());
        }
        Mutation::Truncate(i) => bytes.truncate(at(i)),
    }
}

proptest! {
    #![proptest_config(crate::util::proptest_config(256))]

    #[test]
    fn random_nets_round_trip_in_both_dialects(net in net()) {
        for dialect in [Dialect::Jarp, Dialect::Standard] {
            let text = pnml::write(&net, dialect);
            let back = pnml::parse(&text, "fallback");
            prop_assert_eq!(back.as_ref(), Ok(&net), "{}:\n{}", dialect, text);
        }
        let via_standard = pnml::parse(&pnml::write(&net, Dialect::Standard), "fallback").unwrap();
        let back = pnml::parse(&pnml::write(&via_standard, Dialect::Jarp), "fallback").unwrap();
        prop_assert_eq!(back, net);
    }
}

proptest! {
    #![proptest_config(crate::util::proptest_config(1000))]

    /// `parse` returns Ok or Err on mangled input, never panics; whatever it
    /// accepts it also writes back and reads again unchanged.
    #[test]
    fn mutated_pnml_never_panics(
        seed in any::<Index>(),
        mutations in prop::collection::vec(mutation(), 1..6),
    ) {
        let mut bytes = SEEDS[seed.index(SEEDS.len())].clone().into_bytes();
        for m in &mutations {
            apply(&mut bytes, m);
        }
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(net) = pnml::parse(&text, "fallback") {
            for dialect in [Dialect::Jarp, Dialect::Standard] {
                let written = pnml::write(&net, dialect);
                let back = pnml::parse(&written, "other");
                prop_assert_eq!(back.as_ref(), Ok(&net), "{}:\n{}", dialect, written);
            }
        }
    }
}

const IDS: &[&str] = &["p1", "p2", "p3", "t1", "t2", "a1", "a2", "", " "];
const COORDINATES: &[&str] = &["1", "-3", "2.5", "", "1e400", "NaN", "inf", "x"];
const TEXTS: &[&str] = &[
    "Default,1",
    "Default,0",
    "3",
    "256",
    "-1",
    "x",
    "",
    " ",
    "PLAN NAME: q",
    "goal",
    "a.exec",
    "[not b] a.start",
];

/// What may sit inside a node's field: a value, a text or a position.
fn leaf() -> impl Strategy<Value = String> {
    prop_oneof![
        (
            prop::sample::select(&["value", "text"][..]),
            prop::sample::select(TEXTS)
        )
            .prop_map(|(tag, text)| format!("<{tag}>{text}</{tag}>")),
        (prop::sample::select(COORDINATES), prop::sample::select(COORDINATES))
            .prop_map(|(x, y)| format!("<position x=\"{x}\" y=\"{y}\"/>")),
    ]
}

/// A child of a node: name, marking, inscription, graphics, ...
fn field() -> impl Strategy<Value = String> {
    let tags = &[
        "name",
        "initialMarking",
        "inscription",
        "graphics",
        "toolspecific",
        "text",
        "other",
    ][..];
    (prop::sample::select(tags), prop::collection::vec(leaf(), 0..3))
        .prop_map(|(tag, children)| format!("<{tag}>{}</{tag}>", children.concat()))
}

/// An attribute, or nothing.
fn attribute(name: &'static str, probability: f64) -> impl Strategy<Value = String> {
    prop::option::weighted(probability, prop::sample::select(IDS))
        .prop_map(move |v| v.map_or(String::new(), |v| format!(" {name}=\"{v}\"")))
}

/// A place, transition, arc or comment (usually with an id), or a page of them.
fn item() -> impl Strategy<Value = String> {
    let tags = &["place", "transition", "arc", "comment", "other"][..];
    let node = (
        prop::sample::select(tags),
        attribute("id", 0.95),
        attribute("source", 0.9),
        attribute("target", 0.9),
        prop::collection::vec(field(), 0..4),
    )
        .prop_map(|(tag, id, source, target, fields)| {
            format!("<{tag}{id}{source}{target}>{}</{tag}>", fields.concat())
        });
    node.prop_recursive(3, 24, 4, |inner| {
        prop::collection::vec(inner, 0..4).prop_map(|items| format!("<page id=\"g\">{}</page>", items.concat()))
    })
}

proptest! {
    #![proptest_config(crate::util::proptest_config(500))]

    /// Well-formed documents of PNML elements in random arrangements reach the
    /// PNML reader itself: it returns Ok or Err, never panics, and what it
    /// accepts round-trips.
    #[test]
    fn random_pnml_structures_never_panic(body in prop::collection::vec(item(), 0..8)) {
        let text = format!("<pnml><net id=\"n\">{}</net></pnml>", body.concat());
        if let Ok(net) = pnml::parse(&text, "fallback") {
            for dialect in [Dialect::Jarp, Dialect::Standard] {
                let written = pnml::write(&net, dialect);
                let back = pnml::parse(&written, "other");
                prop_assert_eq!(back.as_ref(), Ok(&net), "{}:\n{}", dialect, written);
            }
        }
    }
}
