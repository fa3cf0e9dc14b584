//! Graphviz DOT export of a plan: what `learnpnp dot PLAN` prints.
//!
//! Places are circles, transitions boxes. Execution places are filled and
//! labelled with their action, choice points are double circles (the same
//! ones `learnpnp check` reports: [`choice_points`] of the reachable
//! markings), goal and fail places are coloured with a bold outline; the
//! output starts with a legend comment.

use std::fmt;

use crate::analysis::{DEFAULT_LIMIT, choice_points, explore};
use crate::net::{NodeRef, PlaceId};
use crate::plan::Plan;

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

/// The plan as a Graphviz `digraph`, deterministic (nodes and arcs in file
/// order); choice points are found over at most [`DEFAULT_LIMIT`] reachable
/// markings, as `check` finds them.
pub fn to_dot(plan: &Plan) -> String {
    to_dot_with_limit(plan, DEFAULT_LIMIT)
}

/// [`to_dot`] exploring at most `limit` markings for the choice points.
pub fn to_dot_with_limit(plan: &Plan, limit: usize) -> String {
    let graph = explore(plan, limit);
    let mut choice = vec![false; plan.net().places().len()];
    for c in choice_points(plan, &graph) {
        choice[c.place.index()] = true;
    }
    Dot { plan, choice }.to_string()
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
        writeln!(f, "digraph \"{}\" {{", escape(net.name()))?;
        f.write_str("  rankdir=LR;\n")?;
        f.write_str("  node [fontname=\"Helvetica\", fontsize=10];\n")?;
        f.write_str("  edge [fontname=\"Helvetica\", fontsize=9];\n")?;
        for (i, &is_choice) in self.choice.iter().enumerate() {
            self.place(f, PlaceId::new(i), is_choice)?;
        }
        for t in net.transitions() {
            let label = if t.label.is_empty() { &t.id } else { &t.label };
            writeln!(
                f,
                "  \"{}\" [shape=box, label=\"{}\", tooltip=\"{}\"];",
                escape(&t.id),
                escape(label),
                escape(&t.id),
            )?;
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
