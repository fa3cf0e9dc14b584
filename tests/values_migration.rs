//! Values carried into a revised plan: kept entries exact, new options at the
//! initial value, changed choices' visits reset, a foreign plan refused, the
//! same plan (and a version 1 file) loaded as before.

use std::fs;
use std::path::PathBuf;

use learnpnp::analysis::{choices_at, transition_name};
use learnpnp::executor::PlanKey;
use learnpnp::learning::by_choice::group_by_choice;
use learnpnp::learning::migrate::migrate;
use learnpnp::learning::persist::place_keys;
use learnpnp::learning::persist::{self, FORMAT_VERSION, HEADER_LEN, MAGIC, SavedValues};
use learnpnp::learning::{StateKey, ValueTable};
use learnpnp::net::Marking;
use learnpnp::plan::{AllowedAtoms, Plan, PlanBuilder};

const CELLS: usize = 3;

/// A small grid's navigation plan as the Python builder writes it: sense the
/// cell, then choose among `moves` (back to sensing) or `stop` (the goal).
/// Every move's execution place is `<move>.exec` in every cell.
fn grid(name: &str, moves: &[&str]) -> Plan {
    let mut b = PlanBuilder::new(name);
    let nav = b.initial_place("nav");
    let goal = b.goal_place();
    for c in 0..CELLS {
        let cell = b.place(format!("cell_{c}"));
        b.transition(format!("[at_{c}]"), &[(nav, 1)], &[(cell, 1)]);
        for m in moves {
            b.action_into(cell, m, nav);
        }
        b.action_into(cell, "stop", goal);
    }
    b.build(AllowedAtoms::Open).expect("a plan")
}

/// The marking where cell `c` chooses.
fn at_cell(plan: &Plan, c: usize) -> Marking {
    let places = plan.net().places();
    let mut tokens = vec![0u8; places.len()];
    let i = places
        .iter()
        .position(|p| p.label == format!("cell_{c}"))
        .expect("the cell");
    tokens[i] = 1;
    Marking::from_tokens(tokens)
}

/// A table valuing every option of every cell: value `10 c + k` (k: the
/// option's rank by name), visits `100 + c`.
fn learned(plan: &Plan) -> SavedValues {
    let mut table = ValueTable::new(-7.0);
    for c in 0..CELLS {
        for choice in choices_at(plan, &at_cell(plan, c)) {
            for (t, after) in choice.options {
                let k = f64::from(transition_name(plan, t).as_bytes()[0]);
                table.insert(
                    StateKey {
                        plan: PlanKey::ROOT,
                        marking: after,
                    },
                    10.0 * c as f64 + k,
                    100 + c as u64,
                );
            }
        }
    }
    SavedValues::new("eps-sosmc", &table, &[plan])
}

/// (cell marking text, option, value, visits) for every option of `plan` under `values`.
fn options(plan: &Plan, values: &SavedValues) -> Vec<(String, String, Option<f64>, u64)> {
    let learned = group_by_choice(&[plan], values).expect("grouped");
    let mut rows: Vec<_> = learned
        .choices
        .iter()
        .flat_map(|c| {
            c.options
                .iter()
                .map(|o| (c.at_text.clone(), o.name.clone(), o.value, o.visits))
        })
        .collect();
    rows.sort_by(|a, b| (&a.0, &a.1).partial_cmp(&(&b.0, &b.1)).expect("ordered"));
    rows
}

fn scratch(test: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("values_migration_{test}"));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

#[test]
fn repeated_labels_are_qualified_by_the_place_leading_to_them() {
    let plan = grid("lake", &["left", "right"]);
    let keys = place_keys(&plan);
    assert!(keys.contains(&"left.exec<cell_0>".to_string()), "{keys:?}");
    assert!(keys.contains(&"cell_2".to_string()), "{keys:?}");
    let mut unique = keys.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), keys.len(), "every key is unique: {keys:?}");
}

#[test]
fn a_revised_plan_keeps_the_values_of_what_did_not_change() {
    let old = grid("lake", &["left", "right", "up"]);
    let saved = learned(&old);
    let path = scratch("revised").join("values.bin");
    persist::save(&path, &saved).expect("save");
    let saved = persist::load(&path).expect("load");
    // Prune `left` everywhere and add `down`: the plan's places move.
    let new = grid("lake", &["down", "right", "up"]);
    let (migrated, report) = migrate(&saved, &[&new]).expect("migrated");
    assert!(!report.unchanged);
    let before = options(&old, &saved);
    let after = options(&new, &migrated);
    for (at, option, value, visits) in &after {
        match option.as_str() {
            "down.start" => assert_eq!((*value, *visits), (None, 0), "{at}: new option"),
            _ => {
                let old = before
                    .iter()
                    .find(|(a, o, _, _)| a == at && o == option)
                    .expect("the option was valued");
                // Exactly the old value; visits restart: every cell's options changed.
                assert_eq!(*value, old.2, "{at} {option}");
                assert_eq!(*visits, 0, "{at} {option}");
            }
        }
    }
    assert_eq!(after.len(), CELLS * 4);
    assert_eq!(report.kept, CELLS * 3);
    assert_eq!(report.dropped.len(), CELLS, "{report}");
    assert!(
        report.dropped.iter().all(|e| e.marking.starts_with("left.exec<cell_")),
        "{report}"
    );
    assert!(report.ambiguous.is_empty(), "{report}");
    assert_eq!(report.new_options.len(), CELLS, "{report}");
    assert!(report.new_options.iter().all(|o| o.option == "down.start"), "{report}");
    assert_eq!(report.changed_choices.len(), CELLS, "{report}");
    assert_eq!(report.changed_choices[0].added, ["down.start"]);
    assert_eq!(report.changed_choices[0].removed, ["left.start"]);
    assert_eq!(report.visits_reset, CELLS * 3);
    // The new option starts at the learner's initial value.
    let table = migrated.to_table(-7.0);
    let down = options(&new, &migrated);
    assert!(down.iter().any(|r| r.1 == "down.start" && r.2.is_none()));
    let choice = choices_at(&new, &at_cell(&new, 1)).pop().expect("a choice");
    let (_, down_after) = choice
        .options
        .iter()
        .find(|(t, _)| transition_name(&new, *t) == "down.start")
        .expect("down")
        .clone();
    assert_eq!(table.value_of(PlanKey::ROOT, &down_after), -7.0);
    let text = report.to_string();
    assert!(
        text.contains("9 kept, 3 dropped, 0 ambiguous, 3 new option(s)"),
        "{text}"
    );
}

#[test]
fn an_edit_elsewhere_keeps_every_value_and_every_count() {
    let old = grid("lake", &["left", "right"]);
    let saved = learned(&old);
    // A branch added before the grid (a new first place shifts every position).
    let mut b = PlanBuilder::new("lake");
    let start = b.initial_place("wake_up");
    let nav = b.place("nav");
    b.action_into(start, "stretch", nav);
    let goal = b.goal_place();
    for c in 0..CELLS {
        let cell = b.place(format!("cell_{c}"));
        b.transition(format!("[at_{c}]"), &[(nav, 1)], &[(cell, 1)]);
        for m in ["left", "right"] {
            b.action_into(cell, m, nav);
        }
        b.action_into(cell, "stop", goal);
    }
    let new = b.build(AllowedAtoms::Open).expect("a plan");
    let (migrated, report) = migrate(&saved, &[&new]).expect("migrated");
    assert_eq!(report.kept, saved.entries.len(), "{report}");
    assert!(
        report.changed_choices.is_empty() && report.dropped.is_empty(),
        "{report}"
    );
    assert_eq!(report.visits_reset, 0);
    let strip = |rows: Vec<(String, String, Option<f64>, u64)>| {
        rows.into_iter()
            .map(|(at, o, v, n)| (at.replace("wake_up ", ""), o, v, n))
            .collect::<Vec<_>>()
    };
    assert_eq!(strip(options(&new, &migrated)), strip(options(&old, &saved)));
}

#[test]
fn the_same_plan_loads_the_values_as_saved() {
    let plan = grid("lake", &["left", "right"]);
    let saved = learned(&plan);
    let (migrated, report) = migrate(&saved, &[&plan]).expect("the same plan");
    assert!(report.unchanged);
    assert_eq!(migrated, saved);
    assert_eq!(
        report.to_string(),
        format!(
            "values learned on this plan: {} entries loaded as saved",
            saved.entries.len()
        )
    );
}

/// The bytes a version 1 build wrote for `values` (no identities).
fn version_1_file(values: &SavedValues) -> Vec<u8> {
    #[derive(serde::Serialize)]
    struct V1<'a> {
        algorithm: &'a str,
        plans: &'a [persist::PlanLabels],
        entries: &'a [persist::SavedEntry],
    }
    let payload = bincode::serde::encode_to_vec(
        V1 {
            algorithm: &values.algorithm,
            plans: &values.plans,
            entries: &values.entries,
        },
        bincode::config::standard(),
    )
    .expect("encoded");
    let mut bytes = MAGIC.to_vec();
    bytes.extend_from_slice(&1u32.to_le_bytes());
    bytes.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    bytes.extend_from_slice(&payload);
    assert_eq!(bytes.len(), HEADER_LEN + payload.len());
    bytes
}

#[test]
fn a_version_1_file_loads_as_before_and_migrates_by_unique_names() {
    assert_eq!(FORMAT_VERSION, 2);
    let plan = grid("lake", &["left", "right"]);
    let saved = learned(&plan);
    let path = scratch("v1").join("values.bin");
    fs::write(&path, version_1_file(&saved)).expect("write");
    let old = persist::load(&path).expect("a version 1 file reads");
    assert!(old.identities.is_empty());
    assert_eq!((&old.plans, &old.entries), (&saved.plans, &saved.entries));
    // Into the same plan: exactly the table it always gave.
    let (migrated, report) = migrate(&old, &[&plan]).expect("the same plan");
    assert!(report.unchanged);
    let same = |a: &ValueTable, b: &ValueTable| a.entries().eq(b.entries());
    assert!(same(&migrated.to_table(0.0), &saved.to_table(0.0)));
    // Into a revision: labels repeat, so the options are ambiguous; nothing
    // that can be told apart is lost, and the report says so.
    let new = grid("lake", &["right", "up"]);
    let err = migrate(&old, &[&new]).expect_err("every entry marks a repeated label");
    assert!(err.to_string().contains("share nothing"), "{err}");
}

#[test]
fn a_plan_that_shares_nothing_is_refused_with_what_differs() {
    let plan = grid("lake", &["left", "right"]);
    let saved = learned(&plan);
    let mut b = PlanBuilder::new("kick");
    let start = b.initial_place("start");
    let goal = b.goal_place();
    b.action_into(start, "walk", goal);
    b.action_into(start, "turn", goal);
    let other = b.build(AllowedAtoms::Open).expect("a plan");
    let err = migrate(&saved, &[&other]).expect_err("nothing shared");
    let text = err.to_string();
    assert!(
        text.contains("share nothing with plan 'kick'")
            && text.contains("learned on plan 'lake'")
            && text.contains("cell_0, cell_1, cell_2]")
            && text.contains("[start]"),
        "{text}"
    );
}
