//! Saving and loading value tables: exact round trips, `.prev` copies, CSV listings.

use std::fs;
use std::path::PathBuf;

use learnpnp::executor::PlanKey;
use learnpnp::learning::persist::{
    PersistError, PlanLabels, SavedEntry, SavedValues, load, load_latest, prev_path, save, write_csv,
};
use learnpnp::learning::{StateKey, ValueTable};
use learnpnp::net::{Marking, PetriNet, PlaceNode};
use learnpnp::plan::{AllowedAtoms, Plan};

/// A fresh, empty directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("persist_roundtrip_{test}"));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

/// A plan with the given (id, label) places and no transitions.
fn plan(name: &str, places: &[(&str, &str)]) -> Plan {
    let places = places
        .iter()
        .map(|(id, label)| PlaceNode {
            id: id.to_string(),
            label: label.to_string(),
            initial: 0,
            position: None,
        })
        .collect();
    let net = PetriNet::new(name, places, Vec::new(), &[]).expect("valid net");
    Plan::from_net(net, AllowedAtoms::Open).expect("valid plan")
}

fn root_plan() -> Plan {
    plan(
        "root",
        &[("p1", "start"), ("p2", "goto.exec"), ("p3", ""), ("p4", "done goal")],
    )
}

/// `table` saved by Monte Carlo, its plan the root plan.
fn of_root(table: &ValueTable) -> SavedValues {
    SavedValues::new("mc", table, &[&root_plan()])
}

fn sub_plan() -> Plan {
    plan("kick, \"left\"", &[("q1", "a.exec"), ("q2", "b")])
}

fn key(plan: u16, tokens: &[u8]) -> StateKey {
    StateKey {
        plan: PlanKey(plan),
        marking: Marking::from_tokens(tokens.to_vec()),
    }
}

/// A table over both plans with finite values, a missing estimate and odd numbers.
fn table() -> ValueTable {
    let mut t = ValueTable::new(f64::NEG_INFINITY);
    t.insert(key(0, &[1, 0, 0, 0]), 0.1 + 0.2, 7);
    t.insert(key(0, &[0, 1, 2, 0]), f64::NEG_INFINITY, 0);
    t.insert(key(1, &[0, 1]), -1.0e-300, u64::MAX);
    t.insert(key(0, &[0, 0, 0, 1]), 123_456_789.125, 3);
    t.insert(key(1, &[0, 0]), f64::MIN_POSITIVE, 1);
    t
}

/// Every entry of a table with its value's bits, in id order.
fn contents(t: &ValueTable) -> Vec<(StateKey, u64, u64)> {
    t.entries().map(|(k, v, n)| (k.clone(), v.to_bits(), n)).collect()
}

#[test]
fn labels_use_the_place_id_when_the_label_is_empty() {
    let labels = PlanLabels::of(&root_plan());
    assert_eq!(labels.name, "root");
    assert_eq!(labels.places, ["start", "goto.exec", "p3", "done goal"]);
    assert_eq!(labels.describe(&[1, 0, 3, 0]), "start p3*3");
    assert_eq!(labels.describe(&[0, 0, 0, 0]), "-");
}

#[test]
fn a_table_round_trips_exactly() {
    let dir = scratch("exact");
    let path = dir.join("values.bin");
    let (root, sub) = (root_plan(), sub_plan());
    let original = table();
    let saved = SavedValues::new("sosmc", &original, &[&root, &sub]);
    save(&path, &saved).expect("save");
    let loaded = load(&path).expect("load");
    assert_eq!(loaded, saved);
    assert_eq!(loaded.algorithm, "sosmc");
    assert_eq!(loaded.plans.len(), 2);
    let restored = loaded.to_table(-4.0);
    assert_eq!(contents(&restored), contents(&original));
    assert_eq!(restored.initial_value(), -4.0);
    assert_eq!(
        restored.value_of(PlanKey(0), &Marking::from_tokens(vec![0, 1, 2, 0])),
        f64::NEG_INFINITY
    );
    // No temporary files are left behind, and there was nothing to keep as `.prev`.
    let names: Vec<_> = fs::read_dir(&dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name())
        .collect();
    assert_eq!(names, ["values.bin"]);
}

#[test]
fn an_empty_table_round_trips() {
    let dir = scratch("empty");
    let path = dir.join("empty.bin");
    let saved = SavedValues::new("td", &ValueTable::new(0.0), &[]);
    save(&path, &saved).expect("save");
    let loaded = load(&path).expect("load");
    assert_eq!(loaded, saved);
    assert!(loaded.to_table(0.0).is_empty());
}

#[test]
fn large_payloads_are_within_the_decoder_limits() {
    let dir = scratch("large");
    let path = dir.join("large.bin");
    // Empty names are the densest claims on the decoder (8 per encoded byte).
    let places = 300_000;
    let wide = SavedValues {
        algorithm: "x".repeat(100_000),
        plans: vec![PlanLabels {
            name: String::new(),
            places: vec![String::new(); places],
        }],
        entries: (0..20u8)
            .map(|i| SavedEntry {
                plan: 0,
                tokens: {
                    let mut t = vec![0; places];
                    t[usize::from(i)] = 1;
                    t
                },
                value: f64::from(i),
                visits: 0,
            })
            .collect(),
        identities: Vec::new(),
    };
    save(&path, &wide).expect("save");
    assert_eq!(load(&path).expect("load"), wide);

    let root = root_plan();
    let mut t = ValueTable::new(0.0);
    for i in 0..200_000u32 {
        let tokens = i.to_le_bytes();
        t.insert(key(0, &tokens), f64::from(i), 0);
    }
    let many = SavedValues::new("mc", &t, &[&root]);
    save(&path, &many).expect("save");
    assert_eq!(load(&path).expect("load"), many);
}

#[test]
fn a_second_save_keeps_the_previous_table() {
    let dir = scratch("prev");
    let path = dir.join("values.bin");
    let mut t = ValueTable::new(0.0);
    t.insert(key(0, &[1, 0, 0, 0]), 1.0, 1);
    let first = of_root(&t);
    save(&path, &first).expect("first save");
    assert!(!prev_path(&path).exists());
    t.insert(key(0, &[1, 0, 0, 0]), 2.0, 2);
    let second = of_root(&t);
    save(&path, &second).expect("second save");
    assert_eq!(load(&path).expect("main"), second);
    assert_eq!(load(&prev_path(&path)).expect("prev"), first);
    assert_eq!(
        prev_path(&path).file_name().and_then(|n| n.to_str()),
        Some("values.bin.prev")
    );
    let (latest, problem) = load_latest(&path).expect("latest");
    assert_eq!(latest, second);
    assert!(problem.is_none());
}

#[test]
fn a_corrupt_main_file_falls_back_to_prev_and_is_never_kept_as_prev() {
    let dir = scratch("fallback");
    let path = dir.join("values.bin");
    let mut t = ValueTable::new(0.0);
    t.insert(key(0, &[1, 0, 0, 0]), 1.0, 1);
    let first = of_root(&t);
    t.insert(key(0, &[0, 1, 0, 0]), 5.0, 1);
    let second = of_root(&t);
    save(&path, &first).expect("first save");
    save(&path, &second).expect("second save");

    // The main file is damaged: load_latest reports it and returns `.prev`.
    let mut bytes = fs::read(&path).expect("read");
    let last = bytes.len() - 1;
    bytes[last] ^= 0x40;
    fs::write(&path, &bytes).expect("corrupt");
    let (values, problem) = load_latest(&path).expect("fallback");
    assert_eq!(values, first);
    assert!(matches!(problem, Some(PersistError::Checksum { .. })), "{problem:?}");
    assert_eq!(fs::read(&path).expect("untouched"), bytes);

    // Saving over a corrupt file does not replace the good `.prev` with it.
    let third = of_root(&ValueTable::new(0.0));
    save(&path, &third).expect("third save");
    assert_eq!(load(&path).expect("main"), third);
    assert_eq!(load(&prev_path(&path)).expect("prev"), first);
}

#[test]
fn a_missing_main_file_falls_back_to_prev() {
    let dir = scratch("missing");
    let path = dir.join("values.bin");
    let saved = SavedValues::new("mc", &table(), &[&root_plan(), &sub_plan()]);
    save(&path, &saved).expect("save");
    // As if a crash had happened after the copy to `.prev`, before the new file.
    fs::copy(&path, prev_path(&path)).expect("copy");
    fs::remove_file(&path).expect("remove");
    let (values, problem) = load_latest(&path).expect("fallback");
    assert_eq!(values, saved);
    assert!(matches!(problem, Some(PersistError::Io { .. })), "{problem:?}");
}

#[test]
fn without_a_usable_file_load_latest_reports_the_main_error() {
    let dir = scratch("nothing");
    let path = dir.join("values.bin");
    let err = load_latest(&path).expect_err("nothing to load");
    assert!(
        matches!(&err, PersistError::Io { path: p, .. } if *p == path),
        "{err:?}"
    );
    assert!(err.to_string().contains("values.bin"), "{err}");
}

#[test]
fn inconsistent_values_are_not_saved() {
    let dir = scratch("refuse");
    let path = dir.join("values.bin");
    let root = root_plan();
    // A key of plan 1, but only the root plan is described.
    let saved = SavedValues::new("mc", &table(), &[&root]);
    let err = save(&path, &saved).expect_err("inconsistent");
    assert!(matches!(err, PersistError::Inconsistent { .. }), "{err:?}");
    assert!(!path.exists());
}

#[test]
fn csv_lists_every_entry_sorted_and_quoted() {
    let saved = SavedValues::new("sosmc", &table(), &[&root_plan(), &sub_plan()]);
    let mut out = Vec::new();
    write_csv(&saved, &mut out).expect("csv");
    let text = String::from_utf8(out).expect("utf-8");
    assert_eq!(
        text,
        "plan,marking,value,visits\n\
         root,done goal,123456789.125,3\n\
         root,goto.exec p3*2,-inf,0\n\
         root,start,0.30000000000000004,7\n\
         \"kick, \"\"left\"\"\",-,2.2250738585072014e-308,1\n\
         \"kick, \"\"left\"\"\",b,-1e-300,18446744073709551615\n"
    );
}

#[test]
fn csv_refuses_inconsistent_values() {
    let saved = SavedValues {
        algorithm: "mc".into(),
        plans: vec![],
        entries: vec![SavedEntry {
            plan: 0,
            tokens: vec![],
            value: 0.0,
            visits: 0,
        }],
        identities: Vec::new(),
    };
    let err = write_csv(&saved, &mut Vec::new()).expect_err("no plan 0");
    assert_eq!(err.kind(), std::io::ErrorKind::InvalidData);
}
