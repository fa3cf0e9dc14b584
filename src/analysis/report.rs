//! What `check` found, as data and as a readable report.

use std::fmt;

use super::count::Count;
use super::limits::Stop;
use crate::net::{PlaceId, TransitionId};
use crate::plan::Plan;

/// Longest firing sequence an example shows (its last transitions).
const SHOWN_TRACE: usize = 8;

/// A net element named for a reader: its file id and label.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Element {
    /// The element id in the file (`p3`, `t7`).
    pub id: String,
    /// Its label (may be empty).
    pub label: String,
}

impl Element {
    /// Place `p` of `plan`.
    pub(crate) fn place(plan: &Plan, p: PlaceId) -> Self {
        let node = plan.net().place(p);
        Element {
            id: node.id.clone(),
            label: node.label.clone(),
        }
    }

    /// Transition `t` of `plan`.
    pub fn transition(plan: &Plan, t: TransitionId) -> Self {
        let node = plan.net().transition(t);
        Element {
            id: node.id.clone(),
            label: node.label.clone(),
        }
    }

    /// The label, or the id when the label is blank.
    pub fn name(&self) -> &str {
        if self.label.trim().is_empty() {
            &self.id
        } else {
            &self.label
        }
    }
}

/// `id 'label'`, or `id` alone when the label is blank.
impl fmt::Display for Element {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.label.trim().is_empty() {
            f.write_str(&self.id)
        } else {
            write!(f, "{} '{}'", self.id, self.label)
        }
    }
}

/// An explored marking given as an example, with a shortest way to reach it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Example {
    /// The marking, as the labels of its marked places (`*n` for n tokens, `*ω` unbounded).
    pub marking: String,
    /// The transitions fired from the initial marking (labels, or ids when empty).
    pub trace: Vec<String>,
}

/// `marking (after a → b)`, the trace cut to its last transitions.
impl fmt::Display for Example {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[{}]", self.marking)?;
        if self.trace.is_empty() {
            return f.write_str(" (the initial marking)");
        }
        f.write_str(" after ")?;
        let skipped = self.trace.len().saturating_sub(SHOWN_TRACE);
        if skipped > 0 {
            write!(f, "({skipped} earlier) … → ")?;
        }
        f.write_str(&self.trace[skipped..].join(" → "))
    }
}

/// The properties a plan is checked for (thesis section 2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Property {
    /// No execution place holds more than one token (an action never runs twice at once).
    Safety,
    /// Every transition fires in some firing sequence (L1-liveness).
    Minimality,
    /// A goal marking is reachable from every reachable marking (thesis
    /// Definition 3), but from those that can end only in a declared failure
    /// end (PNP's fail marking, where the plan ends as failed); and from the
    /// initial marking always.
    Effectiveness,
    /// Every marking with no enabled transition is a goal or fail marking.
    Deadlock,
}

impl Property {
    /// Every property, in report order.
    pub const ALL: [Property; 4] = [
        Property::Safety,
        Property::Minimality,
        Property::Effectiveness,
        Property::Deadlock,
    ];

    /// A short name.
    pub fn name(self) -> &'static str {
        match self {
            Property::Safety => "safety",
            Property::Minimality => "minimality",
            Property::Effectiveness => "effectiveness",
            Property::Deadlock => "deadlock",
        }
    }

    /// What holds when the property passes.
    pub(crate) fn meaning(self) -> &'static str {
        match self {
            Property::Safety => "no execution place holds more than one token",
            Property::Minimality => "every transition can fire",
            Property::Effectiveness => {
                "a goal marking is reachable from every reachable marking (or a declared failure end is)"
            }
            Property::Deadlock => "every dead marking is a goal or fail marking",
        }
    }
}

/// The outcome of one property.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    /// It holds.
    Passed,
    /// It does not: the failures say where.
    Failed,
    /// The exploration cannot decide it; the text says why.
    Inconclusive(String),
    /// It does not apply to this plan; the text says why.
    NotApplicable(String),
}

impl Verdict {
    /// `passed`, `FAILED`, `inconclusive` or `not applicable`.
    pub fn summary(&self) -> &'static str {
        match self {
            Verdict::Passed => "passed",
            Verdict::Failed => "FAILED",
            Verdict::Inconclusive(_) => "inconclusive",
            Verdict::NotApplicable(_) => "not applicable",
        }
    }

    /// Why it is inconclusive or does not apply.
    pub(crate) fn reason(&self) -> Option<&str> {
        match self {
            Verdict::Passed | Verdict::Failed => None,
            Verdict::Inconclusive(why) | Verdict::NotApplicable(why) => Some(why),
        }
    }
}

/// `passed`, `FAILED`, `inconclusive: why`, `not applicable: why`.
impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Verdict::Passed => f.write_str("passed"),
            Verdict::Failed => f.write_str("FAILED"),
            Verdict::Inconclusive(why) => write!(f, "inconclusive: {why}"),
            Verdict::NotApplicable(why) => write!(f, "not applicable: {why}"),
        }
    }
}

/// The overall result of a check, from its verdicts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Outcome {
    /// Every property passed or does not apply.
    Passed,
    /// Some property failed.
    Failed,
    /// None failed, but some could not be decided (e.g. the marking limit was
    /// reached): neither a pass nor a failure.
    Inconclusive,
}

impl Outcome {
    /// `passed`, `FAILED` or `inconclusive`, as the report's last line says.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Passed => "passed",
            Outcome::Failed => "FAILED",
            Outcome::Inconclusive => "inconclusive",
        }
    }
}

/// The most tokens a place holds in any reachable marking.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlaceBound {
    /// The place.
    pub(crate) place: PlaceId,
    /// Its id and label.
    pub element: Element,
    /// The action whose execution place it is, if any.
    pub action: Option<String>,
    /// Its bound (0: never marked).
    pub bound: Count,
}

/// A choice point with the names of its place and options.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ReportedChoice {
    /// The place.
    pub(crate) place: PlaceId,
    /// Its id and label.
    pub element: Element,
    /// The transitions chosen among, with their ids and labels.
    pub options: Vec<(TransitionId, Element)>,
}

/// A violated property, named by element ids and labels.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Failure {
    /// An execution place can hold more than one token: its action would run
    /// twice at once (safety).
    UnsafeExecution {
        /// The place.
        place: PlaceId,
        /// Its id and label.
        element: Element,
        /// The action it executes.
        action: String,
        /// The most tokens it can hold.
        bound: Count,
        /// The first explored marking with more than one token there.
        example: Example,
    },
    /// A transition that fires in no firing sequence (minimality).
    DeadTransition {
        /// The transition.
        transition: TransitionId,
        /// Its id and label.
        element: Element,
        /// Why, in the drawing's terms (an input place never marked...).
        why: Vec<String>,
    },
    /// Reachable markings from which neither a goal marking nor a declared
    /// failure end (a fail marking) is reachable (effectiveness).
    NoGoalReachable {
        /// How many explored markings.
        markings: usize,
        /// Whether the plan declares failure ends (which they cannot reach either).
        failure_ends: bool,
        /// Why, in the drawing's terms (a goal place with no incoming arc, a loop...).
        why: Vec<String>,
        /// A few of them, nearest to the initial marking first.
        examples: Vec<Example>,
    },
    /// No goal marking is reachable from the initial marking: every run ends
    /// in a failure end (effectiveness).
    GoalUnreachable {
        /// Why, in the drawing's terms (a goal place never marked...).
        why: Vec<String>,
    },
    /// Reachable markings with no enabled transition that are neither goal nor
    /// fail markings: the plan stops there for good.
    DeadMarkings {
        /// How many explored markings.
        markings: usize,
        /// Why the first of them stops, in the drawing's terms.
        why: Vec<String>,
        /// A few of them, nearest to the initial marking first.
        examples: Vec<Example>,
    },
}

impl Failure {
    /// The property it violates.
    pub fn property(&self) -> Property {
        match self {
            Failure::UnsafeExecution { .. } => Property::Safety,
            Failure::DeadTransition { .. } => Property::Minimality,
            Failure::NoGoalReachable { .. } | Failure::GoalUnreachable { .. } => Property::Effectiveness,
            Failure::DeadMarkings { .. } => Property::Deadlock,
        }
    }
}

fn write_examples(f: &mut fmt::Formatter<'_>, examples: &[Example]) -> fmt::Result {
    for example in examples {
        write!(f, "\n      e.g. {example}")?;
    }
    Ok(())
}

fn write_why(f: &mut fmt::Formatter<'_>, why: &[String]) -> fmt::Result {
    for (i, reason) in why.iter().enumerate() {
        let lead = if i == 0 { "because" } else { "and" };
        write!(f, "\n      {lead} {reason}")?;
    }
    Ok(())
}

/// One line (examples on the lines below), prefixed with the property.
impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: ", self.property().name())?;
        match self {
            Failure::UnsafeExecution {
                element,
                action,
                bound,
                example,
                ..
            } => {
                let amount = match bound {
                    Count::Finite(n) => format!("{n} tokens"),
                    Count::Unbounded => "unboundedly many tokens".to_string(),
                };
                write!(
                    f,
                    "execution place {element} of action '{action}' can hold {amount}: \
                     the action would run twice at once"
                )?;
                write_examples(f, std::slice::from_ref(example))
            }
            Failure::DeadTransition { element, why, .. } => {
                write!(f, "transition {element} can never fire")?;
                write_why(f, why)
            }
            Failure::NoGoalReachable {
                markings,
                failure_ends,
                why,
                examples,
            } => {
                write!(f, "{markings} reachable marking(s) cannot reach a goal marking")?;
                if *failure_ends {
                    f.write_str(" nor a failure end")?;
                }
                write_why(f, why)?;
                write_examples(f, examples)
            }
            Failure::GoalUnreachable { why } => {
                f.write_str("no goal marking is reachable from the initial marking: every run ends in a failure end")?;
                write_why(f, why)
            }
            Failure::DeadMarkings {
                markings,
                why,
                examples,
            } => {
                write!(
                    f,
                    "{markings} reachable marking(s) enable no transition and are neither goal nor fail markings"
                )?;
                write_why(f, why)?;
                write_examples(f, examples)
            }
        }
    }
}

/// Something worth knowing that is no failure.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Note {
    /// A place that is not an execution place holds more than one token: a
    /// memory place recording choices, or a loop counter (thesis 5.5), which may
    /// be unbounded by design.
    AboveOne {
        /// The place.
        place: PlaceId,
        /// Its id and label.
        element: Element,
        /// The most tokens it holds.
        bound: Count,
    },
    /// The plan has no goal places: it runs until stopped, and effectiveness
    /// does not apply.
    NoGoal,
    /// The plan declares failure ends (its fail places, PNP's `fail`): the
    /// plan ends there as failed, as in a goal it ends as done.
    FailureEnds {
        /// The fail places, with their ids and labels.
        places: Vec<Element>,
        /// How many reachable markings, not fail markings, can end only there
        /// (a recovery that gives up).
        committed: usize,
    },
}

impl fmt::Display for Note {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Note::AboveOne {
                element,
                bound: Count::Unbounded,
                ..
            } => write!(
                f,
                "place {element} is unbounded: it gains tokens without limit \
                 (by design for a loop counter, thesis 5.5)"
            ),
            Note::AboveOne { element, bound, .. } => write!(
                f,
                "place {element} holds up to {bound} tokens \
                 (not an execution place: allowed, e.g. a memory place, thesis 5.5)"
            ),
            Note::NoGoal => {
                f.write_str("the plan has no goal places: it runs until stopped, effectiveness does not apply")
            }
            Note::FailureEnds { places, committed } => {
                let places: Vec<String> = places.iter().map(ToString::to_string).collect();
                write!(
                    f,
                    "failure end {}: the plan ends there as failed; {committed} reachable marking(s) can end only there",
                    places.join(" + ")
                )
            }
        }
    }
}

/// What `check` reports on a plan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CheckReport {
    /// The plan's name.
    pub plan: String,
    /// Number of places.
    pub places: usize,
    /// Number of transitions.
    pub transitions: usize,
    /// Number of reachable markings explored (ω-markings of unbounded places
    /// count once): the product of the parts' markings, saturating at `usize::MAX`.
    pub markings: usize,
    /// Number of markings stored: the sum of the parts' markings.
    pub stored: usize,
    /// Number of independent parts explored apart (see [`super::Exploration`]).
    pub parts: usize,
    /// The marking limit of the exploration.
    pub limit: usize,
    /// Whether every reachable marking was explored (no limit was hit).
    pub complete: bool,
    /// The limit that stopped the exploration, if one did.
    pub stop: Option<Stop>,
    /// The token bound of every place, in place order (lower bounds when incomplete).
    pub bounds: Vec<PlaceBound>,
    /// The choice points met in the explored markings, in place order.
    pub choice_points: Vec<ReportedChoice>,
    /// The verdict of every property, in [`Property::ALL`] order.
    pub verdicts: Vec<(Property, Verdict)>,
    /// What is wrong, by property.
    pub failures: Vec<Failure>,
    /// What is worth knowing and not wrong.
    pub notes: Vec<Note>,
    /// What is unusual in the plan but accepted (as the PNP library accepts it).
    pub warnings: Vec<String>,
    /// Whether the plan has goal places (a plan without runs until stopped).
    pub(crate) has_goal: bool,
}

impl CheckReport {
    /// Whether every property passed or does not apply (an inconclusive
    /// property, e.g. from hitting the marking limit, is no pass).
    pub fn passed(&self) -> bool {
        self.outcome() == Outcome::Passed
    }

    /// Failed if some property failed; otherwise inconclusive if some could
    /// not be decided; otherwise passed.
    pub fn outcome(&self) -> Outcome {
        let verdicts = || self.verdicts.iter().map(|(_, v)| v);
        if verdicts().any(|v| *v == Verdict::Failed) {
            Outcome::Failed
        } else if verdicts().any(|v| matches!(v, Verdict::Inconclusive(_))) {
            Outcome::Inconclusive
        } else {
            Outcome::Passed
        }
    }

    /// The verdict on `property`.
    pub fn verdict(&self, property: Property) -> Option<&Verdict> {
        self.verdicts.iter().find(|(p, _)| *p == property).map(|(_, v)| v)
    }

    /// Whether some place is unbounded.
    pub fn has_unbounded(&self) -> bool {
        self.bounds.iter().any(|b| b.bound == Count::Unbounded)
    }

    /// The report as [`Display`](fmt::Display) writes it, but with every list
    /// (warnings, places, choice points and their options, failures, notes)
    /// cut to its first `most` items, followed by how many more there are:
    /// `learnpnp check` without `--verbose`.
    pub fn summary(&self, most: usize) -> impl fmt::Display + '_ {
        Shown {
            report: self,
            most: Some(most),
        }
    }

    /// The whole report as JSON, as `learnpnp check --json` prints it: `plan`,
    /// `result` (as the last line of the text), `passed`, `places`,
    /// `transitions`, `markings` (reachable), `stored` (markings stored, over
    /// `parts` independent parts), `limit`, `complete`, `stopped_by` (`null`,
    /// `markings` or `memory`: the limit that stopped the exploration),
    /// `verdicts` (property ->
    /// [`Verdict::summary`]), `reasons` (property -> why it is inconclusive or
    /// does not apply), `bounds` (`at_most_one`: how many places; `above_one`:
    /// place and bound, a number or `unbounded`; `never_marked`: places),
    /// `choice_points` (place and options), `failure_ends` (the fail places,
    /// where the plan ends as failed), `failures`, `notes` and `warnings`
    /// (as the text words them), and `text` (the report as text, in full).
    /// Places and transitions are `{"id", "label"}`.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::{Map, Value, json};
        let element = |e: &Element| json!({ "id": e.id, "label": e.label });
        let verdicts: Map<String, Value> = self
            .verdicts
            .iter()
            .map(|(p, v)| (p.name().to_string(), Value::from(v.summary())))
            .collect();
        let reasons: Map<String, Value> = self
            .verdicts
            .iter()
            .filter_map(|(p, v)| Some((p.name().to_string(), Value::from(v.reason()?))))
            .collect();
        let above_one: Vec<Value> = self
            .above_one()
            .map(|b| {
                let bound = match b.bound {
                    Count::Finite(n) => Value::from(n),
                    Count::Unbounded => Value::from("unbounded"),
                };
                json!({ "place": element(&b.element), "bound": bound })
            })
            .collect();
        let never_marked: Vec<Value> = self.never_marked().map(|b| element(&b.element)).collect();
        let choice_points: Vec<Value> = self
            .choice_points
            .iter()
            .map(|c| {
                let options: Vec<Value> = c.options.iter().map(|(_, e)| element(e)).collect();
                json!({ "place": element(&c.element), "options": options })
            })
            .collect();
        let failures: Vec<String> = self.failures.iter().map(ToString::to_string).collect();
        let notes: Vec<String> = self.notes.iter().map(ToString::to_string).collect();
        let failure_ends: Vec<Value> = self
            .notes
            .iter()
            .filter_map(|n| match n {
                Note::FailureEnds { places, .. } => Some(places),
                _ => None,
            })
            .flatten()
            .map(element)
            .collect();
        json!({
            "plan": self.plan,
            "result": self.outcome().name(),
            "passed": self.passed(),
            "places": self.places,
            "transitions": self.transitions,
            "markings": self.markings,
            "stored": self.stored,
            "parts": self.parts,
            "limit": self.limit,
            "complete": self.complete,
            "stopped_by": self.stop.map(Stop::name),
            "verdicts": verdicts,
            "reasons": reasons,
            "bounds": {
                "at_most_one": self.at_most_one(),
                "above_one": above_one,
                "never_marked": never_marked,
            },
            "choice_points": choice_points,
            "failures": failures,
            "failure_ends": failure_ends,
            "notes": notes,
            "warnings": self.warnings,
            "text": self.to_string(),
        })
    }

    /// How many places hold at most one token.
    fn at_most_one(&self) -> usize {
        self.bounds.iter().filter(|b| b.bound == Count::Finite(1)).count()
    }

    /// The places that hold more than one token.
    fn above_one(&self) -> impl Iterator<Item = &PlaceBound> {
        self.bounds.iter().filter(|b| b.bound.exceeds_one())
    }

    /// The places never marked.
    fn never_marked(&self) -> impl Iterator<Item = &PlaceBound> {
        self.bounds.iter().filter(|b| b.bound == Count::Finite(0))
    }
}

/// A report as text, every list in full (`most` is `None`) or cut to its
/// first `most` items.
struct Shown<'a> {
    report: &'a CheckReport,
    most: Option<usize>,
}

impl Shown<'_> {
    /// The first items of `items` to show, and how many are left out.
    fn cut<'b, T>(&self, items: &'b [T]) -> (&'b [T], usize) {
        let shown = self.most.map_or(items.len(), |most| most.min(items.len()));
        (&items[..shown], items.len() - shown)
    }

    /// `items` on one line, separated by commas, cut to the first few.
    fn write_inline(&self, f: &mut fmt::Formatter<'_>, items: &[String]) -> fmt::Result {
        let (shown, rest) = self.cut(items);
        f.write_str(&shown.join(", "))?;
        if rest > 0 {
            write!(f, ", {}", more(rest, ""))?;
        }
        Ok(())
    }

    /// `title (count):` and one line per item (`- item`), cut to the first few.
    fn write_lines<T: fmt::Display>(&self, f: &mut fmt::Formatter<'_>, title: &str, items: &[T]) -> fmt::Result {
        if items.is_empty() {
            return Ok(());
        }
        writeln!(f, "{title} ({}):", items.len())?;
        let (shown, rest) = self.cut(items);
        for item in shown {
            writeln!(f, "  - {item}")?;
        }
        if rest > 0 {
            writeln!(f, "  {}", more(rest, &format!(" {title}")))?;
        }
        Ok(())
    }

    fn write_bounds(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let report = self.report;
        let seen = if report.complete { "" } else { " (seen so far)" };
        writeln!(
            f,
            "token bounds{seen}: {} place(s) hold at most 1 token",
            report.at_most_one()
        )?;
        let above: Vec<String> = report
            .above_one()
            .map(|b| format!("{} {}", b.element, b.bound))
            .collect();
        let never: Vec<String> = report.never_marked().map(|b| b.element.to_string()).collect();
        for (title, places) in [("above 1 token", above), ("never marked", never)] {
            if !places.is_empty() {
                write!(f, "  {title} ({}): ", places.len())?;
                self.write_inline(f, &places)?;
                writeln!(f)?;
            }
        }
        Ok(())
    }
}

/// `... and N more things (--verbose shows all)`: what stands for `rest`
/// items left out of a list (`what`, with its leading space, names them).
fn more(rest: usize, what: &str) -> String {
    format!("... and {rest} more{what} (--verbose shows all)")
}

/// A multi-line report: summary, verdicts, bounds, choice points, failures,
/// notes and the overall result, every list in full
/// ([`CheckReport::summary`] cuts them).
impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        Shown {
            report: self,
            most: None,
        }
        .fmt(f)
    }
}

impl fmt::Display for Shown<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let report = self.report;
        let markings = if report.markings == usize::MAX {
            format!("at least {}", report.markings)
        } else {
            report.markings.to_string()
        };
        writeln!(
            f,
            "plan '{}': {} places, {} transitions, {} choice point(s), {markings} reachable marking(s)",
            report.plan,
            report.places,
            report.transitions,
            report.choice_points.len(),
        )?;
        if report.parts > 1 {
            writeln!(
                f,
                "  {} independent parts (no place in common) explored apart: {} marking(s) stored, \
                 the reachable markings are their combinations",
                report.parts, report.stored
            )?;
        }
        if let Some(stop) = report.stop {
            writeln!(f, "  {stop} reached: exploration incomplete, results partial")?;
        }
        if report.has_unbounded() {
            writeln!(
                f,
                "  unbounded places are counted as ω: markings form a coverability graph"
            )?;
        }
        let (warnings, rest) = self.cut(&report.warnings);
        for w in warnings {
            writeln!(f, "warning: {w}")?;
        }
        if rest > 0 {
            writeln!(f, "{}", more(rest, " warnings"))?;
        }
        for (property, verdict) in &report.verdicts {
            let meaning = match (property, verdict, report.has_goal) {
                // Without a goal place a plan never ends by itself: say what passing means.
                (Property::Deadlock, Verdict::Passed, false) => {
                    "no reachable marking stops the plan: with no goal place it runs until stopped from outside"
                }
                _ => property.meaning(),
            };
            writeln!(f, "{:<14} {:<15}{}", property.name(), verdict.summary(), meaning)?;
            if let Some(why) = verdict.reason() {
                writeln!(f, "{:<15}({why})", "")?;
            }
        }
        self.write_bounds(f)?;
        let choice_points: Vec<ShownChoice<'_>> = report
            .choice_points
            .iter()
            .map(|choice| ShownChoice { shown: self, choice })
            .collect();
        self.write_lines(f, "choice points", &choice_points)?;
        self.write_lines(f, "failures", &report.failures)?;
        self.write_lines(f, "notes", &report.notes)?;
        writeln!(f, "result: {}", report.outcome().name())
    }
}

/// A choice point as a report shows it: `place: option, option...`.
struct ShownChoice<'a> {
    shown: &'a Shown<'a>,
    choice: &'a ReportedChoice,
}

impl fmt::Display for ShownChoice<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let options: Vec<String> = self.choice.options.iter().map(|(_, e)| e.to_string()).collect();
        write!(f, "{}: ", self.choice.element)?;
        self.shown.write_inline(f, &options)
    }
}
