//! Values carried into a revised plan: saved entries named by what they mean,
//! mapped onto the places of the new plan, with a report of what was kept.
//!
//! **Identity.** Every place has a *key* ([`place_keys`](crate::learning::persist::place_keys)): its name (label, or
//! id when blank) when no other place of the plan has that name; otherwise its
//! name qualified by the keys of the places leading to it (the input places of
//! the transitions that put tokens into it), `name<pred1,pred2>`, refined for
//! up to [`REFINE_ROUNDS`](crate::learning::persist::REFINE_ROUNDS) rounds while keys still repeat. The builder's
//! `south.exec` of cell `nav_2_3` is `south.exec<nav_2_3>`. A saved entry (an
//! afterstate) is the multiset of the keys of its marked places; a choice
//! point is its place's key, an option the name of its transition. Keys that
//! still repeat after refinement are *ambiguous*: entries marking such a place
//! are not carried over.
//!
//! **Mapping.** The root plan maps to the root plan, a sub-plan to the sub-plan
//! of the same name. A saved place maps to the new place of the same key; when
//! no key matches, to the new place of the same name if that name is unique in
//! both plans. An entry is *kept* when all its marked places map, *dropped*
//! when one of them has no counterpart, *ambiguous* when one maps to several
//! places. A version 1 file has no keys: its places are mapped by name where
//! the name is unique in both plans.
//!
//! **Learner state.** Kept entries keep their value and visit count exactly;
//! options with no saved entry start at the learner's initial value (a new
//! entry of the table). A choice point whose options changed (one added or
//! removed; known from version 2 files) keeps its options' values but
//! restarts their visit counts at 0. What a learner keeps outside its table
//! (SoSMC's counts since the greedy policy changed, its episode number and
//! phase, TD's traces) is never saved, so it restarts with any loaded table.
//!
//! A table loaded into the plan it was learned on (the same names in the same
//! order) is used as it is: no mapping.

use std::collections::{BTreeSet, HashMap};
use std::fmt;

use serde::Serialize;

use super::by_choice::ChoiceFinder;
use super::persist::{PlanIdentity, PlanLabels, SavedChoice, SavedEntry, SavedValues, counts, identity_of};
use crate::analysis::transition_name;
use crate::net::{Marking, PlaceId};
use crate::plan::Plan;

/// How many items of each list the report's text shows.
const SHOWN: usize = 5;

/// A saved entry named by its plan and the keys of its marked places.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct EntryName {
    /// The plan's name.
    pub plan: String,
    /// The keys of the marked places (`key*n` for n tokens), space-separated.
    pub marking: String,
}

/// An option of the new plan that no saved entry valued, in a choice a kept
/// entry belongs to.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct NewOption {
    /// The plan's name.
    pub plan: String,
    /// The choice point's key.
    pub choice: String,
    /// The marking where the choice is made (place keys).
    pub at: String,
    /// The option's transition name.
    pub option: String,
}

/// A choice point present in both plans whose options differ.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ChangedChoice {
    /// The plan's name.
    pub plan: String,
    /// The choice point's key.
    pub choice: String,
    /// Options of the new plan only.
    pub added: Vec<String>,
    /// Options of the saved plan only.
    pub removed: Vec<String>,
}

/// What happened to a saved table loaded into a plan.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct MigrationReport {
    /// The values were learned on this very plan and are used as they are.
    pub unchanged: bool,
    /// The file had no place identities (version 1): places were matched by unique names.
    pub by_names_only: bool,
    /// Entries carried over (values and visits; visits reset where the choice changed).
    pub kept: usize,
    /// Saved entries with no counterpart in the new plan.
    pub dropped: Vec<EntryName>,
    /// Saved entries that could map to several places of the new plan.
    pub ambiguous: Vec<EntryName>,
    /// Options of the new plan without a saved value (they start at the initial value).
    pub new_options: Vec<NewOption>,
    /// Choice points whose options changed: their kept entries' visit counts restart at 0.
    pub changed_choices: Vec<ChangedChoice>,
    /// Choice points of the new plan only (keys).
    pub new_choices: Vec<String>,
    /// Choice points of the saved plan only (keys).
    pub removed_choices: Vec<String>,
    /// Kept entries whose visit count was reset.
    pub visits_reset: usize,
}

/// A table that shares nothing with the plan it is loaded into.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "the values share nothing with plan '{given}': none of their {entries} entries (learned on plan '{saved}') has a counterpart; their marked places missing here (first few): [{}]; the saved plan's first choice points are [{}], this plan's are [{}]",
    missing.join(", "),
    saved_choices.join(", "),
    given_choices.join(", ")
)]
pub struct SharesNothing {
    /// The saved plan's name.
    pub saved: String,
    /// The given plan's name.
    pub(crate) given: String,
    /// Saved entries.
    pub(crate) entries: usize,
    /// The first places marked by saved entries that have no unambiguous
    /// counterpart in the given plan (keys, or names for a version 1 file).
    pub(crate) missing: Vec<String>,
    /// The saved plan's first choice points (or places, for a version 1 file).
    pub(crate) saved_choices: Vec<String>,
    /// The given plan's first choice points.
    pub(crate) given_choices: Vec<String>,
}

/// Where a saved place goes in the new plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Target {
    Place(usize),
    Ambiguous,
    Gone,
}

/// `saved` carried into `plans` (the activation plans of the new plan, root
/// first): the table rewritten onto the new plans' places, and what happened.
/// A table learned on these very plans is returned as it is.
pub fn migrate(saved: &SavedValues, plans: &[&Plan]) -> Result<(SavedValues, MigrationReport), Box<SharesNothing>> {
    let labels: Vec<PlanLabels> = plans.iter().map(|p| PlanLabels::of(p)).collect();
    if saved.plans == labels {
        let report = MigrationReport {
            unchanged: true,
            kept: saved.entries.len(),
            ..MigrationReport::default()
        };
        return Ok((saved.clone(), report));
    }
    let identities: Vec<PlanIdentity> = plans.iter().map(|p| identity_of(p)).collect();
    let mut report = MigrationReport {
        by_names_only: saved.identities.is_empty(),
        ..MigrationReport::default()
    };
    // Saved plan index -> new plan index.
    let plan_map: Vec<Option<usize>> = saved
        .plans
        .iter()
        .enumerate()
        .map(|(k, p)| {
            if k == 0 {
                (!plans.is_empty()).then_some(0)
            } else {
                labels.iter().skip(1).position(|l| l.name == p.name).map(|i| i + 1)
            }
        })
        .collect();
    let targets: Vec<Vec<Target>> = saved
        .plans
        .iter()
        .enumerate()
        .map(|(k, old)| match plan_map[k] {
            Some(n) => place_targets(old, saved.identities.get(k), &labels[n], &identities[n]),
            None => vec![Target::Gone; old.places.len()],
        })
        .collect();
    let mut entries: Vec<SavedEntry> = Vec::new();
    let mut seen: HashMap<(u16, Vec<u8>), usize> = HashMap::new();
    let mut collided: BTreeSet<usize> = BTreeSet::new();
    for e in &saved.entries {
        let k = usize::from(e.plan);
        let name = || EntryName {
            plan: saved.plans[k].name.clone(),
            marking: describe_keys(saved_keys(saved, k).as_deref(), &saved.plans[k].places, &e.tokens),
        };
        let (Some(n), Some(targets)) = (plan_map.get(k).copied().flatten(), targets.get(k)) else {
            report.dropped.push(name());
            continue;
        };
        let mut tokens = vec![0u8; labels[n].places.len()];
        let mut outcome = Target::Place(0);
        for (i, &count) in e.tokens.iter().enumerate() {
            if count == 0 {
                continue;
            }
            match targets.get(i).copied().unwrap_or(Target::Gone) {
                Target::Place(j) => tokens[j] = count,
                Target::Ambiguous if outcome != Target::Gone => outcome = Target::Ambiguous,
                Target::Ambiguous => {}
                Target::Gone => outcome = Target::Gone,
            }
        }
        match outcome {
            Target::Gone => report.dropped.push(name()),
            Target::Ambiguous => report.ambiguous.push(name()),
            Target::Place(_) => {
                let key = (n as u16, tokens.clone());
                if let Some(&first) = seen.get(&key) {
                    // Two saved entries on one new marking: neither is trusted.
                    report.ambiguous.push(name());
                    collided.insert(first);
                    continue;
                }
                seen.insert(key, entries.len());
                entries.push(SavedEntry {
                    plan: n as u16,
                    tokens,
                    value: e.value,
                    visits: e.visits,
                });
            }
        }
    }
    // The first of colliding entries is ambiguous too.
    let entries: Vec<SavedEntry> = entries
        .into_iter()
        .enumerate()
        .filter(|(i, _)| !collided.contains(i))
        .map(|(_, e)| e)
        .collect();
    let collided = collided.len();
    report.kept = entries.len();
    if report.kept == 0 && !saved.entries.is_empty() {
        return Err(Box::new(shares_nothing(saved, plans, &identities, &targets)));
    }
    if collided > 0 {
        report.ambiguous.push(EntryName {
            plan: String::new(),
            marking: format!("({collided} more entr(ies) sharing a marking with those above)"),
        });
    }
    let mut migrated = SavedValues {
        algorithm: saved.algorithm.clone(),
        plans: labels,
        entries,
        identities,
    };
    compare_choices(saved, &plan_map, &migrated, &mut report);
    options_of_kept(plans, &mut migrated, &mut report);
    Ok((migrated, report))
}

/// The keys of saved plan `k`, when the file has them.
fn saved_keys(saved: &SavedValues, k: usize) -> Option<Vec<String>> {
    saved.identities.get(k).map(|i| i.keys.clone())
}

/// Tokens as the keys (or names) of the marked places.
fn describe_keys(keys: Option<&[String]>, names: &[String], tokens: &[u8]) -> String {
    super::persist::describe_tokens(tokens, |i| keys.and_then(|k| k.get(i)).or_else(|| names.get(i)))
}

/// Where every place of a saved plan goes in a new one.
fn place_targets(
    old: &PlanLabels,
    old_identity: Option<&PlanIdentity>,
    new: &PlanLabels,
    new_identity: &PlanIdentity,
) -> Vec<Target> {
    let by_key = index(&new_identity.keys);
    let by_name = index(&new.places);
    let old_names = counts(&old.places);
    old.places
        .iter()
        .enumerate()
        .map(|(i, name)| {
            if let Some(key) = old_identity.and_then(|id| id.keys.get(i)) {
                match by_key.get(key.as_str()).map(Vec::as_slice) {
                    Some([j]) => return Target::Place(*j),
                    Some([_, _, ..]) => return Target::Ambiguous,
                    _ => {}
                }
            }
            match by_name.get(name.as_str()).map(Vec::as_slice) {
                Some([j]) if old_names[name.as_str()] == 1 => Target::Place(*j),
                Some(_) => Target::Ambiguous,
                None => Target::Gone,
            }
        })
        .collect()
}

/// The positions of every string.
fn index(items: &[String]) -> HashMap<&str, Vec<usize>> {
    let mut map: HashMap<&str, Vec<usize>> = HashMap::with_capacity(items.len());
    for (i, s) in items.iter().enumerate() {
        map.entry(s.as_str()).or_default().push(i);
    }
    map
}

/// The refusal for a table that maps onto nothing.
fn shares_nothing(
    saved: &SavedValues,
    plans: &[&Plan],
    identities: &[PlanIdentity],
    targets: &[Vec<Target>],
) -> SharesNothing {
    let mut missing: BTreeSet<(usize, usize)> = BTreeSet::new();
    for e in &saved.entries {
        let k = usize::from(e.plan);
        for (i, &n) in e.tokens.iter().enumerate() {
            if n > 0 && !matches!(targets.get(k).and_then(|t| t.get(i)), Some(Target::Place(_))) {
                missing.insert((k, i));
            }
        }
    }
    let missing: Vec<String> = missing
        .into_iter()
        .take(SHOWN)
        .map(|(k, i)| {
            saved
                .identities
                .get(k)
                .and_then(|id| id.keys.get(i))
                .or_else(|| saved.plans[k].places.get(i))
                .cloned()
                .unwrap_or_default()
        })
        .collect();
    let saved_choices: Vec<String> = match saved.identities.first() {
        Some(id) => id.choices.iter().take(SHOWN).map(|c| c.place.clone()).collect(),
        None => saved
            .plans
            .first()
            .map(|p| p.places.iter().take(SHOWN).cloned().collect())
            .unwrap_or_default(),
    };
    let given_choices = identities
        .first()
        .map(|id| id.choices.iter().take(SHOWN).map(|c| c.place.clone()).collect())
        .unwrap_or_default();
    SharesNothing {
        saved: saved.plans.first().map_or_else(String::new, |p| p.name.clone()),
        given: plans.first().map_or_else(String::new, |p| p.name().to_string()),
        entries: saved.entries.len(),
        missing,
        saved_choices,
        given_choices,
    }
}

/// Choice points of both sides compared by key (version 2 files only).
fn compare_choices(
    saved: &SavedValues,
    plan_map: &[Option<usize>],
    migrated: &SavedValues,
    report: &mut MigrationReport,
) {
    for (k, old) in saved.identities.iter().enumerate() {
        let Some(n) = plan_map.get(k).copied().flatten() else {
            continue;
        };
        let plan = &migrated.plans[n].name;
        let new = &migrated.identities[n];
        let old_choices: HashMap<&str, &SavedChoice> = old.choices.iter().map(|c| (c.place.as_str(), c)).collect();
        let new_choices: HashMap<&str, &SavedChoice> = new.choices.iter().map(|c| (c.place.as_str(), c)).collect();
        for c in &new.choices {
            match old_choices.get(c.place.as_str()) {
                None => report.new_choices.push(c.place.clone()),
                Some(o) if o.options != c.options => {
                    let added = c.options.iter().filter(|x| !o.options.contains(x)).cloned().collect();
                    let removed = o.options.iter().filter(|x| !c.options.contains(x)).cloned().collect();
                    report.changed_choices.push(ChangedChoice {
                        plan: plan.clone(),
                        choice: c.place.clone(),
                        added,
                        removed,
                    });
                }
                Some(_) => {}
            }
        }
        for c in &old.choices {
            if !new_choices.contains_key(c.place.as_str()) {
                report.removed_choices.push(c.place.clone());
            }
        }
    }
}

/// Groups the kept entries by the new plan's choices: resets the visits of
/// options of changed choices, and lists the options no entry values.
fn options_of_kept(plans: &[&Plan], migrated: &mut SavedValues, report: &mut MigrationReport) {
    let changed: BTreeSet<(&str, &str)> = report
        .changed_choices
        .iter()
        .map(|c| (c.plan.as_str(), c.choice.as_str()))
        .collect();
    let mut reset: Vec<usize> = Vec::new();
    let mut new_options: Vec<NewOption> = Vec::new();
    for (n, plan) in plans.iter().enumerate() {
        let keys = &migrated.identities[n].keys;
        let name = &migrated.plans[n].name;
        let entries: HashMap<&[u8], usize> = migrated
            .entries
            .iter()
            .enumerate()
            .filter(|(_, e)| usize::from(e.plan) == n)
            .map(|(i, e)| (e.tokens.as_slice(), i))
            .collect();
        let mut finder = ChoiceFinder::new(plan);
        let mut groups: BTreeSet<(PlaceId, Vec<u8>)> = BTreeSet::new();
        for &tokens in entries.keys() {
            for (at, c) in finder.leading_to(&Marking::from_tokens(tokens.to_vec())) {
                groups.insert((c.place, at.tokens().to_vec()));
            }
        }
        for (place, at) in groups {
            let at = Marking::from_tokens(at);
            let choice = keys[place.index()].as_str();
            let is_changed = changed.contains(&(name.as_str(), choice));
            let Some(c) = finder.offered(&at).and_then(|cs| cs.iter().find(|c| c.place == place)) else {
                continue;
            };
            for (t, next) in &c.options {
                match entries.get(next.tokens()) {
                    Some(&i) if is_changed => reset.push(i),
                    Some(_) => {}
                    None => new_options.push(NewOption {
                        plan: name.clone(),
                        choice: choice.to_string(),
                        at: describe_keys(Some(keys), &migrated.plans[n].places, at.tokens()),
                        option: transition_name(plan, *t).to_string(),
                    }),
                }
            }
        }
    }
    reset.sort_unstable();
    reset.dedup();
    for &i in &reset {
        migrated.entries[i].visits = 0;
    }
    report.visits_reset = reset.len();
    new_options.sort_by(|a, b| (&a.plan, &a.choice, &a.at, &a.option).cmp(&(&b.plan, &b.choice, &b.at, &b.option)));
    new_options.dedup();
    report.new_options = new_options;
}

impl MigrationReport {
    /// The report as JSON (every list in full).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }
}

/// Up to [`SHOWN`] items, then how many more.
fn first<T>(items: &[T], show: impl Fn(&T) -> String) -> String {
    let mut parts: Vec<String> = items.iter().take(SHOWN).map(show).collect();
    if items.len() > SHOWN {
        parts.push(format!("... ({} more)", items.len() - SHOWN));
    }
    parts.join("; ")
}

impl fmt::Display for MigrationReport {
    /// A few lines a person reads: the counts, then the first few of each list.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.unchanged {
            return write!(f, "values learned on this plan: {} entries loaded as saved", self.kept);
        }
        write!(
            f,
            "values carried into a revised plan{}: {} kept, {} dropped, {} ambiguous, {} new option(s); {} choice point(s) changed (visits of {} kept entries reset), {} new, {} removed",
            if self.by_names_only {
                " (version 1 file: places matched by unique names)"
            } else {
                ""
            },
            self.kept,
            self.dropped.len(),
            self.ambiguous.len(),
            self.new_options.len(),
            self.changed_choices.len(),
            self.visits_reset,
            self.new_choices.len(),
            self.removed_choices.len()
        )?;
        let entry = |e: &EntryName| format!("{}: {}", e.plan, e.marking);
        if !self.changed_choices.is_empty() {
            let show = |c: &ChangedChoice| {
                let mut parts = Vec::new();
                if !c.added.is_empty() {
                    parts.push(format!("+{}", c.added.join(" +")));
                }
                if !c.removed.is_empty() {
                    parts.push(format!("-{}", c.removed.join(" -")));
                }
                format!("{} ({})", c.choice, parts.join(" "))
            };
            write!(f, "\n  changed: {}", first(&self.changed_choices, show))?;
        }
        if !self.new_options.is_empty() {
            write!(
                f,
                "\n  new: {}",
                first(&self.new_options, |o| format!("{} at {}", o.option, o.choice))
            )?;
        }
        if !self.dropped.is_empty() {
            write!(f, "\n  dropped: {}", first(&self.dropped, entry))?;
        }
        if !self.ambiguous.is_empty() {
            write!(f, "\n  ambiguous: {}", first(&self.ambiguous, entry))?;
        }
        if !self.new_choices.is_empty() {
            write!(f, "\n  new choice points: {}", first(&self.new_choices, String::clone))?;
        }
        if !self.removed_choices.is_empty() {
            write!(
                f,
                "\n  removed choice points: {}",
                first(&self.removed_choices, String::clone)
            )?;
        }
        Ok(())
    }
}
