//! Graphviz DOT export of a plan: what `learnpnp dot PLAN` prints.
//!
//! Places are circles, transitions boxes. Execution places are filled and
//! labelled with their action, choice points are double circles (the same
//! ones `learnpnp check` reports: [`choice_points`](crate::analysis::choice_points) of the reachable
//! markings), goal and fail places are coloured with a bold outline; the
//! output starts with a legend comment.

use std::fmt;

use crate::analysis::{DEFAULT_LIMIT, choice_points, explore};
use crate::learning::by_choice::{ChoiceValues, LearnedValues, OptionValue};
use crate::net::{NodeRef, PlaceId};
use crate::plan::Plan;

/// Most markings of one choice whose values a transition lists; beyond, a summary.
const LISTED_MARKINGS: usize = 8;

/// The legend printed as a comment at the top of every graph.
const LEGEND: &str = "\
// Legend:
//   circle                  place (its label, or its id when unlabelled);
//                           ● = a token of the initial marking (●×n for n > 3)
//   filled light blue       execution place, labelled with its action
//   double circle           choice point: output transitions that can be
//                           executable together in a reachable marking, as
//                           `learnpnp check` reports them (gold when not an
//                           execution place)
//   green, bold outline     goal place
//   pink, bold outline      fail place
//   box                     transition, with its label
//   arc label               arc weight (shown when above 1)
";

/// The legend's lines for learned values.
const VALUES_LEGEND: &str = "\
// Learned values (--values): an option transition of a choice point lists,
//   for each marking where the choice was made (named by the places that
//   differ between those markings), the option's value and its updates (n);
//   ★ marks the greedy option (the best estimate), and a blue bold box an
//   option greedy in at least one of those markings.
";

/// The plan as a Graphviz `digraph`, deterministic (nodes and arcs in file
/// order); choice points are found over at most [`DEFAULT_LIMIT`] reachable
/// markings, as `check` finds them.
pub fn to_dot(plan: &Plan) -> String {
    to_dot_with_limit(plan, DEFAULT_LIMIT)
}

/// [`to_dot`] exploring at most `limit` markings for the choice points, with
/// the values learned in the plan (`values`, grouped by choice point) written
/// on the option transitions of its choices.
pub fn to_dot_with_values(plan: &Plan, limit: usize, values: Option<&LearnedValues>) -> String {
    let graph = explore(plan, limit);
    let mut choice = vec![false; plan.net().places().len()];
    for c in choice_points(plan, &graph) {
        choice[c.place.index()] = true;
    }
    let mut learned: Vec<Vec<(String, &OptionValue)>> = vec![Vec::new(); plan.net().transitions().len()];
    let choices: Vec<&ChoiceValues> = values.iter().flat_map(|v| &v.choices).filter(|c| c.plan == 0).collect();
    for c in &choices {
        // Name the marking by what differs between the markings of this choice point.
        let same: Vec<bool> = (0..c.at.len())
            .map(|i| {
                choices
                    .iter()
                    .filter(|d| d.place == c.place)
                    .all(|d| d.at.tokens()[i] == c.at.tokens()[i])
            })
            .collect();
        let mut differing = c.at.clone();
        for (i, &same) in same.iter().enumerate() {
            if same {
                differing.set(PlaceId::new(i), 0);
            }
        }
        let at = if differing.total() == 0 {
            String::new()
        } else {
            plan.describe(&differing)
        };
        for o in &c.options {
            learned[o.transition.index()].push((at.clone(), o));
        }
    }
    Dot {
        plan,
        choice,
        learned: values.map(|_| learned),
    }
    .to_string()
}

/// [`to_dot`] exploring at most `limit` markings for the choice points.
pub(crate) fn to_dot_with_limit(plan: &Plan, limit: usize) -> String {
    to_dot_with_values(plan, limit, None)
}

/// A value for a label: two decimals, `none` when never estimated.
fn value_text(value: Option<f64>) -> String {
    match value {
        Some(v) if v.is_finite() => format!("{v:.2}"),
        Some(_) => "no estimate".to_string(),
        None => "never valued".to_string(),
    }
}

/// The lines a transition's label gets from its learned values, and whether
/// it is greedy somewhere.
fn value_lines(rows: &[(String, &OptionValue)]) -> (String, bool) {
    let greedy = rows.iter().any(|(_, o)| o.greedy);
    let star = |o: &OptionValue| if o.greedy { " ★" } else { "" };
    let text = match rows {
        [] => String::new(),
        [(_, o)] => format!("\n{} (n={}){}", value_text(o.value), o.visits, star(o)),
        rows if rows.len() <= LISTED_MARKINGS => rows
            .iter()
            .map(|(at, o)| format!("\n[{at}]: {} (n={}){}", value_text(o.value), o.visits, star(o)))
            .collect(),
        rows => {
            let values: Vec<f64> = rows
                .iter()
                .filter_map(|(_, o)| o.value)
                .filter(|v| v.is_finite())
                .collect();
            let visits: u64 = rows.iter().map(|(_, o)| o.visits).sum();
            let greedy_in = rows.iter().filter(|(_, o)| o.greedy).count();
            let range = match (
                values.iter().copied().reduce(f64::min),
                values.iter().copied().reduce(f64::max),
            ) {
                (Some(lo), Some(hi)) => format!("values {lo:.2} .. {hi:.2}"),
                _ => "no estimate".to_string(),
            };
            format!(
                "\n{range} over {} markings (n={visits})\n★ in {greedy_in} of them",
                rows.len()
            )
        }
    };
    (text, greedy)
}

/// Escapes `text` for a double-quoted DOT string: quotes and backslashes are
/// escaped (so Graphviz reads no `\n`-style sequences of its own), line breaks
/// become `\n`. Brackets, braces and angle brackets need no escaping inside
/// quotes (every label is quoted and no shape is a record).
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            c if c.is_control() => out.push(' '),
            c => out.push(c),
        }
    }
    out
}

/// Text safe on one comment line.
fn comment(text: &str) -> String {
    text.chars().map(|c| if c.is_control() { ' ' } else { c }).collect()
}

/// The initial tokens as dots.
fn tokens(n: u8) -> String {
    match n {
        0 => String::new(),
        1..=3 => "●".repeat(usize::from(n)),
        n => format!("●×{n}"),
    }
}

struct Dot<'a> {
    plan: &'a Plan,
    /// Per place: whether it is a choice point.
    choice: Vec<bool>,
    /// Per transition: the learned values of the option it leads to, by
    /// marking where the choice was made (`None`: no values given).
    learned: Option<Vec<Vec<(String, &'a OptionValue)>>>,
}

impl Dot<'_> {
    fn place(&self, f: &mut fmt::Formatter<'_>, p: PlaceId, choice: bool) -> fmt::Result {
        let plan = self.plan;
        let node = plan.net().place(p);
        let action = plan.exec_action(p).map(|a| plan.action(a).name.as_str());
        let goal = plan.goal().iter().any(|&(q, _)| q == p);
        let fail = plan.fail().iter().any(|&(q, _)| q == p);
        let mut label = match action {
            Some(name) => name.to_string(),
            None if node.label.is_empty() => node.id.clone(),
            None => node.label.clone(),
        };
        if node.initial > 0 {
            label.push('\n');
            label.push_str(&tokens(node.initial));
        }
        let shape = if choice { "doublecircle" } else { "circle" };
        write!(
            f,
            "  \"{}\" [shape={shape}, label=\"{}\", tooltip=\"{}\"",
            escape(&node.id),
            escape(&label),
            escape(&if node.label.is_empty() {
                node.id.clone()
            } else {
                format!("{}: {}", node.id, node.label)
            }),
        )?;
        let fill = if goal {
            Some("palegreen")
        } else if fail {
            Some("lightpink")
        } else if action.is_some() {
            Some("lightblue")
        } else if choice {
            Some("gold")
        } else {
            None
        };
        if let Some(colour) = fill {
            write!(f, ", style=filled, fillcolor={colour}")?;
        }
        if goal || fail {
            f.write_str(", penwidth=2")?;
        }
        f.write_str("];\n")
    }
}

impl fmt::Display for Dot<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let plan = self.plan;
        let net = plan.net();
        writeln!(f, "// Petri Net Plan '{}' (learnpnp dot)", comment(net.name()))?;
        f.write_str(LEGEND)?;
        if self.learned.is_some() {
            f.write_str(VALUES_LEGEND)?;
        }
        writeln!(f, "digraph \"{}\" {{", escape(net.name()))?;
        f.write_str("  rankdir=LR;\n")?;
        f.write_str("  node [fontname=\"Helvetica\", fontsize=10];\n")?;
        f.write_str("  edge [fontname=\"Helvetica\", fontsize=9];\n")?;
        for (i, &is_choice) in self.choice.iter().enumerate() {
            self.place(f, PlaceId::new(i), is_choice)?;
        }
        for (i, t) in net.transitions().iter().enumerate() {
            let mut label = if t.label.trim().is_empty() {
                t.id.clone()
            } else {
                t.label.clone()
            };
            let rows = self.learned.as_ref().map_or(&[][..], |l| &l[i]);
            let (values, greedy) = value_lines(rows);
            label.push_str(&values);
            write!(
                f,
                "  \"{}\" [shape=box, label=\"{}\", tooltip=\"{}\"",
                escape(&t.id),
                escape(&label),
                escape(&t.id),
            )?;
            if greedy {
                f.write_str(", color=blue, penwidth=2.5")?;
            }
            f.write_str("];\n")?;
        }
        for arc in net.arcs() {
            let id = |node: NodeRef| escape(net.node_id(node));
            write!(f, "  \"{}\" -> \"{}\"", id(arc.source), id(arc.target))?;
            if arc.weight > 1 {
                write!(f, " [label=\"{}\"]", arc.weight)?;
            }
            f.write_str(";\n")?;
        }
        f.write_str("}\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_quotes_backslashes_and_lines() {
        assert_eq!(escape(r#"a "b" \n [c]"#), r#"a \"b\" \\n [c]"#);
        assert_eq!(escape("x\ny\tz"), "x\\ny z");
        assert_eq!(comment("a\nb"), "a b");
        assert_eq!(tokens(2), "●●");
        assert_eq!(tokens(9), "●×9");
    }
}
