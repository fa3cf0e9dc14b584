//! Mutated plan files and condition strings never panic: they load or are refused.

use learnpnp::condition::parse_condition;
use learnpnp::net::{PetriNet, PlaceNode, TransitionNode};
use learnpnp::plan::{AllowedAtoms, Plan, catalog};
use learnpnp::pnml::{self, Dialect};
use proptest::prelude::*;

/// Fragments that stress the label and guard languages.
fn fragment() -> impl Strategy<Value = String> {
    prop_oneof![
        Just("[".to_string()),
        Just("]".to_string()),
        Just("(".to_string()),
        Just(")".to_string()),
        Just(" ".to_string()),
        Just(".".to_string()),
        Just("#".to_string()),
        Just("and".to_string()),
        Just("or".to_string()),
        Just("not".to_string()),
        Just("goal".to_string()),
        Just("fail(".to_string()),
        Just(".exec".to_string()),
        Just(".start".to_string()),
        Just(".end".to_string()),
        Just(".finished".to_string()),
        Just("start".to_string()),
        Just("interrupt".to_string()),
        "[a-zA-Z0-9_]{1,4}",
        "\\PC{1,2}",
    ]
}

fn label() -> impl Strategy<Value = String> {
    prop::collection::vec(fragment(), 0..8).prop_map(|parts| parts.concat())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn condition_strings_never_panic(text in label()) {
        let _ = parse_condition(&text);
    }

    #[test]
    fn mutated_labels_load_or_are_refused(labels in prop::collection::vec(label(), 1..12), seed in any::<u64>()) {
        // Relabel the football plan's nodes with random labels.
        let net = catalog::football().expect("catalog plan");
        let places: Vec<PlaceNode> = net.places().iter().enumerate().map(|(i, p)| PlaceNode {
            label: if (seed >> (i % 64)) & 1 == 1 { labels[i % labels.len()].clone() } else { p.label.clone() },
            ..p.clone()
        }).collect();
        let transitions: Vec<TransitionNode> = net.transitions().iter().enumerate().map(|(i, t)| TransitionNode {
            label: if (seed >> ((i + 7) % 64)) & 1 == 1 { labels[(i + 3) % labels.len()].clone() } else { t.label.clone() },
            ..t.clone()
        }).collect();
        let arcs: Vec<(String, String, String, u8)> = net.arcs().iter()
            .map(|a| (a.id.clone(), net.node_id(a.source).to_string(), net.node_id(a.target).to_string(), a.weight))
            .collect();
        let specs: Vec<(&str, &str, &str, u8)> = arcs.iter().map(|(a, s, t, w)| (a.as_str(), s.as_str(), t.as_str(), *w)).collect();
        let mutated = PetriNet::new("m", places, transitions, &specs).expect("same structure");
        if let Err(e) = Plan::from_net(mutated, AllowedAtoms::Open) {
            prop_assert!(!e.to_string().is_empty());
        }
    }

    #[test]
    fn mutated_files_load_or_are_refused(cuts in prop::collection::vec((any::<prop::sample::Index>(), label()), 1..6)) {
        let text = pnml::write(&catalog::football().expect("catalog plan"), Dialect::Jarp);
        let mut bytes = text.into_bytes();
        for (at, insert) in cuts {
            let i = at.index(bytes.len() + 1);
            bytes.splice(i..(i + 3).min(bytes.len()), insert.into_bytes());
        }
        let mutated = String::from_utf8_lossy(&bytes);
        if let Ok(net) = pnml::parse(&mutated, "fuzz") {
            let _ = Plan::from_net(net, AllowedAtoms::Open);
        }
    }
}
