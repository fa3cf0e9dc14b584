//! A saved value table read against its plan: what was learned at each
//! choice point, options named by the transitions that lead to them.
//!
//! A table holds one value per marking (afterstate). An entry is an option of
//! a choice when one transition `t` leads to its marking from a marking where
//! `t` competes with other transitions for a choice point's tokens
//! ([`crate::analysis::choices_at`], guards free). Entries are grouped by
//! (choice point, marking where the choice is made); every competing option of
//! the group is listed, with its value and visits when the table has them, and
//! the greedy option (the best estimate) is marked. Entries that are no such
//! option (TD learners value every marking) are listed apart.

use std::collections::HashMap;

use super::persist::{PlanLabels, SavedValues};
use crate::analysis::{ChoiceAt, ChoicePoint, before, choices_among, structural_choice_points, transition_name};
use crate::net::{Marking, PlaceId, TransitionId};
use crate::plan::Plan;

/// One option of a choice and what was learned of it.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionValue {
    /// The transition that leads to it.
    pub transition: TransitionId,
    /// Its label (or id when blank): the option's name.
    pub name: String,
    /// The marking it leads to, as the labels of its marked places.
    pub marking: String,
    /// Its learned value; `None` when the table has no entry (never valued),
    /// negative infinity when the entry has no estimate yet.
    pub value: Option<f64>,
    /// Updates of the value.
    pub visits: u64,
    /// Whether it has the best estimate of the choice (ties all marked).
    pub greedy: bool,
}

/// What was learned at one choice point, in one marking.
#[derive(Debug, Clone, PartialEq)]
pub struct ChoiceValues {
    /// The plan's index in the table (0: the root plan).
    pub plan: u16,
    /// The choice point.
    pub(crate) place: PlaceId,
    /// Its name (label, or id when blank).
    pub(crate) place_name: String,
    /// The marking where the choice is made.
    pub at: Marking,
    /// That marking as the labels of its marked places.
    pub at_text: String,
    /// The competing options, in transition order.
    pub options: Vec<OptionValue>,
}

/// An entry of the table that is no option of a choice.
#[derive(Debug, Clone, PartialEq)]
pub struct OtherValue {
    /// The plan's index in the table.
    pub plan: u16,
    /// The marking, as the labels of its marked places.
    pub marking: String,
    /// The value.
    pub value: f64,
    /// Its updates.
    pub visits: u64,
}

/// A table grouped by choice point.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LearnedValues {
    /// One group per (choice point, marking), by plan, place, then marking text.
    pub choices: Vec<ChoiceValues>,
    /// The other entries, by plan then marking text.
    pub others: Vec<OtherValue>,
}

/// A table that was not learned on the plans given.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "the values were learned on plan '{saved}' (places {saved_places:?}), not on plan '{given}' (places {given_places:?})"
)]
pub struct PlanMismatch {
    /// The saved plan's name.
    pub saved: String,
    /// Its place names.
    pub(crate) saved_places: Vec<String>,
    /// The given plan's name.
    pub(crate) given: String,
    /// Its place names.
    pub(crate) given_places: Vec<String>,
}

/// Finds the choices whose options lead to a marking, remembering the
/// choices offered at each marking it looked at.
pub(crate) struct ChoiceFinder<'a> {
    plan: &'a Plan,
    points: Vec<ChoicePoint>,
    /// The transitions that may lead to a marking with a token in each place
    /// (its producers), and those with no output (they may lead anywhere).
    producers: Vec<Vec<TransitionId>>,
    sinks: Vec<TransitionId>,
    offered: HashMap<Marking, Vec<ChoiceAt>>,
}

impl<'a> ChoiceFinder<'a> {
    /// A finder over `plan`'s structural choice points.
    pub(crate) fn new(plan: &'a Plan) -> Self {
        let incidence = plan.incidence();
        let mut producers = vec![Vec::new(); incidence.place_count()];
        let mut sinks = Vec::new();
        for t in incidence.transition_ids() {
            let outputs = incidence.outputs(t);
            if outputs.is_empty() {
                sinks.push(t);
            }
            for out in outputs {
                producers[out.place.index()].push(t);
            }
        }
        ChoiceFinder {
            plan,
            points: structural_choice_points(plan),
            producers,
            sinks,
            offered: HashMap::new(),
        }
    }

    /// Every (marking where the choice is made, choice) with an option that
    /// leads to `after`.
    pub(crate) fn leading_to(&mut self, after: &Marking) -> Vec<(Marking, ChoiceAt)> {
        let mut candidates: Vec<TransitionId> = after
            .marked()
            .flat_map(|(p, _)| self.producers[p.index()].iter().copied())
            .chain(self.sinks.iter().copied())
            .collect();
        candidates.sort_unstable();
        candidates.dedup();
        let mut found = Vec::new();
        for t in candidates {
            let Some(at) = before(self.plan, after, t) else {
                continue;
            };
            let (plan, points) = (self.plan, &self.points);
            let choices = self
                .offered
                .entry(at.clone())
                .or_insert_with(|| choices_among(plan, points, &at));
            for c in choices.iter() {
                if c.options.iter().any(|(u, next)| *u == t && next == after) {
                    found.push((at.clone(), c.clone()));
                }
            }
        }
        found
    }

    /// The choices offered at `at`, if the finder has looked at it.
    pub(crate) fn offered(&self, at: &Marking) -> Option<&[ChoiceAt]> {
        self.offered.get(at).map(Vec::as_slice)
    }
}

/// Groups `saved` by the choice points of `plans` (indexed as the table's
/// plans: the root plan first). Entries of plans not given count as others.
pub fn group_by_choice(plans: &[&Plan], saved: &SavedValues) -> Result<LearnedValues, PlanMismatch> {
    for (plan, labels) in plans.iter().zip(&saved.plans) {
        let given = PlanLabels::of(plan);
        if given != *labels {
            return Err(PlanMismatch {
                saved: labels.name.clone(),
                saved_places: labels.places.clone(),
                given: given.name,
                given_places: given.places,
            });
        }
    }
    let mut out = LearnedValues::default();
    let mut claimed = vec![false; saved.entries.len()];
    for (k, plan) in plans.iter().enumerate() {
        let k = k as u16;
        let entries: HashMap<&[u8], usize> = saved
            .entries
            .iter()
            .enumerate()
            .filter(|(_, e)| e.plan == k)
            .map(|(i, e)| (e.tokens.as_slice(), i))
            .collect();
        let mut finder = ChoiceFinder::new(plan);
        // (place, marking where chosen) -> its options, each with its entry if any.
        let mut groups: HashMap<(PlaceId, Marking), Vec<(TransitionId, Marking)>> = HashMap::new();
        for (&tokens, &i) in &entries {
            for (at, c) in finder.leading_to(&Marking::from_tokens(tokens.to_vec())) {
                claimed[i] = true;
                groups.entry((c.place, at)).or_insert(c.options);
            }
        }
        let mut choices: Vec<ChoiceValues> = groups
            .into_iter()
            .map(|((place, at), options)| {
                let mut options: Vec<OptionValue> = options
                    .into_iter()
                    .map(|(t, next)| {
                        let entry = entries.get(next.tokens()).map(|&i| &saved.entries[i]);
                        OptionValue {
                            transition: t,
                            name: transition_name(plan, t).to_string(),
                            marking: plan.describe(&next),
                            value: entry.map(|e| e.value),
                            visits: entry.map_or(0, |e| e.visits),
                            greedy: false,
                        }
                    })
                    .collect();
                let best = options
                    .iter()
                    .filter_map(|o| o.value)
                    .filter(|v| v.is_finite())
                    .fold(f64::NEG_INFINITY, f64::max);
                for o in &mut options {
                    o.greedy = best.is_finite() && o.value == Some(best);
                }
                ChoiceValues {
                    plan: k,
                    place,
                    place_name: plan.place_name(place).to_string(),
                    at_text: plan.describe(&at),
                    at,
                    options,
                }
            })
            .collect();
        choices.sort_by(|a, b| (a.place, &a.at_text).cmp(&(b.place, &b.at_text)));
        out.choices.extend(choices);
    }
    let mut others: Vec<OtherValue> = saved
        .entries
        .iter()
        .zip(&claimed)
        .filter(|(_, claimed)| !**claimed)
        .map(|(e, _)| OtherValue {
            plan: e.plan,
            marking: saved
                .plans
                .get(usize::from(e.plan))
                .map_or_else(String::new, |p| p.describe(&e.tokens)),
            value: e.value,
            visits: e.visits,
        })
        .collect();
    others.sort_by(|a, b| (a.plan, &a.marking).cmp(&(b.plan, &b.marking)));
    out.others = others;
    Ok(out)
}

/// Quotes a CSV field when it holds a comma, a quote or a line break.
fn csv_field(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\"")).into()
    } else {
        text.into()
    }
}

/// Lists `learned` as CSV, `plan,choice_point,at,option,marking,value,visits,greedy`:
/// one row per option of each choice (choice point, the marking where the
/// choice is made, the option's transition and the marking it leads to), then
/// one row per other entry with the choice columns empty. `value` is exact
/// (`-inf`: no estimate yet) and empty for an option the table never valued;
/// `greedy` says `greedy` on the best estimate of each choice.
pub fn write_csv(learned: &LearnedValues, saved: &SavedValues, out: &mut impl std::io::Write) -> std::io::Result<()> {
    let plan_name = |k: u16| saved.plans.get(usize::from(k)).map_or("", |p| p.name.as_str());
    writeln!(out, "plan,choice_point,at,option,marking,value,visits,greedy")?;
    for c in &learned.choices {
        for o in &c.options {
            writeln!(
                out,
                "{},{},{},{},{},{},{},{}",
                csv_field(plan_name(c.plan)),
                csv_field(&c.place_name),
                csv_field(&c.at_text),
                csv_field(&o.name),
                csv_field(&o.marking),
                o.value.map_or_else(String::new, |v| format!("{v:?}")),
                o.visits,
                if o.greedy { "greedy" } else { "" }
            )?;
        }
    }
    for e in &learned.others {
        writeln!(
            out,
            "{},,,,{},{:?},{},",
            csv_field(plan_name(e.plan)),
            csv_field(&e.marking),
            e.value,
            e.visits
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::executor::PlanKey;
    use crate::learning::{StateKey, ValueTable};
    use crate::plan::{AllowedAtoms, PlanBuilder, catalog};

    #[test]
    fn options_are_grouped_under_their_choice_with_the_greedy_one_marked() {
        let net = catalog::penalty_kick_plain().expect("the kick of Figure 3.6");
        let plan = Plan::from_net(net, AllowedAtoms::Open).expect("a plan");
        let options = crate::analysis::choices_at(&plan, &plan.initial_marking())
            .pop()
            .expect("a choice")
            .options;
        let mut table = ValueTable::new(0.0);
        table.insert(
            StateKey {
                plan: PlanKey::ROOT,
                marking: options[0].1.clone(),
            },
            0.25,
            7,
        );
        table.insert(
            StateKey {
                plan: PlanKey::ROOT,
                marking: options[1].1.clone(),
            },
            0.5,
            3,
        );
        // A marking no choice leads to (a TD learner values those too).
        table.insert(
            StateKey {
                plan: PlanKey::ROOT,
                marking: plan.initial_marking(),
            },
            0.1,
            1,
        );
        let saved = SavedValues::new("test", &table, &[&plan]);
        let learned = group_by_choice(&[&plan], &saved).expect("the same plan");
        assert_eq!(learned.choices.len(), 1);
        let c = &learned.choices[0];
        assert_eq!((c.place_name.as_str(), c.at_text.as_str()), ("start", "start"));
        let rows: Vec<(&str, Option<f64>, u64, bool)> = c
            .options
            .iter()
            .map(|o| (o.name.as_str(), o.value, o.visits, o.greedy))
            .collect();
        assert_eq!(
            rows,
            [
                ("WalkStraight.start", Some(0.25), 7, false),
                ("Turn.start", Some(0.5), 3, true)
            ]
        );
        assert_eq!(learned.others.len(), 1);
        assert_eq!(learned.others[0].marking, "start");

        let mut other = PlanBuilder::new("other");
        other.initial_place("x");
        let other = other.build(AllowedAtoms::Open).expect("a plan");
        assert!(group_by_choice(&[&other], &saved).is_err());
    }
}
