//! The schema file format: one declaration per line, written by hand.
//!
//! ```text
//! # The penalty kick of thesis Figure 3.6.
//! machine penalty_kick                 # a machine; the first one is the root
//!   initial start                      # the initial state (no actions)
//!   state walk {WalkStraight}          # a state and the actions running in it
//!   state turn {Turn}
//!   state kick {Kick}
//!   final scored                       # a final state (`final NAME failed`: ends as failed)
//!   start -> walk                      # an edge with the empty event and no condition
//!   start -> turn
//!   walk, turn -> kick on WalkStraight.finished   # several sources or targets: one edge each
//!   kick -> scored on Kick.finished [not ballLost]
//! ```
//!
//! - `machine NAME` opens a machine; every following line belongs to it until
//!   the next `machine`. The first machine is the root; a state's action that
//!   names another machine of the file calls it.
//! - `initial NAME {A, B}`, `state NAME {A, B}`: a plan state and its actions
//!   (commas or spaces between them; `{}` or nothing for none). Exactly one
//!   state per machine is `initial`.
//! - `final NAME` / `final NAME failed`: a final (absorbing) state; the
//!   machine has finished (`M.finished`) or failed (`M.failed`).
//! - `FROM[, FROM...] -> TO[, TO...] [on EVENT] [[CONDITION]]`: edges. EVENT is
//!   one atom: an event the knowledge base senses, or `A.finished`, `A.failed`
//!   or another condition `A.x` of an action `A` running in the source state.
//!   Without `on` the edge has the empty event, which always triggers.
//!   CONDITION is a guard in the prefix syntax of plan guards
//!   (`and FacingGoal (not FarFromGoal)`); without it the guard is true.
//! - `#` starts a comment when it begins a word outside a condition
//!   (`r1#kick` is an action name); blank lines are ignored.
//! - Names of machines and states: a letter or `_`, then letters, digits, `_`;
//!   the words `machine`, `initial`, `state`, `final`, `failed`, `on` are reserved.
//!
//! Every malformed line is refused with its line number and the offending token.

use std::fmt::Write as _;

use super::SchemaError;
use super::model::{Draft, DraftEdge, DraftMachine, DraftState, Schema, StateKind, validate};
use crate::condition::Expr;

/// Removes a comment: `#` at the start of a word, outside `[...]`.
fn strip_comment(line: &str) -> &str {
    let mut depth = 0usize;
    let mut previous_blank = true;
    for (i, c) in line.char_indices() {
        match c {
            '[' => depth += 1,
            ']' => depth = depth.saturating_sub(1),
            '#' if depth == 0 && previous_blank => return &line[..i],
            _ => {}
        }
        previous_blank = c.is_whitespace();
    }
    line
}

/// The whitespace-separated words of `text` with their byte offsets.
fn words_at(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, c) in text.char_indices() {
        match (c.is_whitespace(), start) {
            (true, Some(s)) => {
                out.push((s, &text[s..i]));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, &text[s..]));
    }
    out
}

/// Splits `text` on commas into trimmed, non-empty single words.
fn name_list(text: &str, what: &str, line: usize) -> Result<Vec<String>, SchemaError> {
    text.split(',')
        .map(|part| {
            let part = part.trim();
            let mut words = part.split_whitespace();
            match (words.next(), words.next()) {
                (None, _) => Err(SchemaError::new(
                    Some(line),
                    format!("expected a {what} name"),
                    if text.trim().is_empty() { "<end>" } else { text.trim() },
                )),
                (Some(w), None) => Ok(w.to_string()),
                (Some(_), Some(extra)) => Err(SchemaError::new(
                    Some(line),
                    format!("expected ',' between {what} names"),
                    extra,
                )),
            }
        })
        .collect()
}

/// `NAME` or `NAME {A, B}` after `initial` / `state`.
fn state_declaration(rest: &str, initial: bool, line: usize) -> Result<DraftState, SchemaError> {
    let (name_part, actions) = match rest.find('{') {
        None => {
            if let Some(close) = rest.find('}') {
                return Err(SchemaError::new(Some(line), "'}' without '{'", &rest[close..=close]));
            }
            (rest, Vec::new())
        }
        Some(open) => {
            let close = rest[open..]
                .find('}')
                .map(|i| open + i)
                .ok_or_else(|| SchemaError::new(Some(line), "the action set is not closed with '}'", "<end>"))?;
            let inner = &rest[open + 1..close];
            if inner.contains('{') {
                return Err(SchemaError::new(Some(line), "a brace inside the action set", "{"));
            }
            let after = rest[close + 1..].trim();
            if !after.is_empty() {
                return Err(SchemaError::new(Some(line), "text after the action set", after));
            }
            let actions = inner
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|a| !a.is_empty())
                .map(str::to_string)
                .collect();
            (&rest[..open], actions)
        }
    };
    let mut words = name_part.split_whitespace();
    let name = match (words.next(), words.next()) {
        (None, _) => return Err(SchemaError::new(Some(line), "expected a state name", "<end>")),
        (Some(n), None) => n.to_string(),
        (Some(_), Some(extra)) => {
            return Err(SchemaError::new(
                Some(line),
                "expected the action set in braces after the state name",
                extra,
            ));
        }
    };
    Ok(DraftState {
        name,
        actions,
        initial,
        kind: StateKind::Ordinary,
        line: Some(line),
    })
}

/// `NAME` or `NAME failed` after `final`.
fn final_declaration(rest: &str, line: usize) -> Result<DraftState, SchemaError> {
    let words: Vec<&str> = rest.split_whitespace().collect();
    let kind = match words.as_slice() {
        [] => return Err(SchemaError::new(Some(line), "expected a state name", "<end>")),
        [_] => StateKind::Final,
        [_, "failed"] => StateKind::Failure,
        [_, other, ..] => {
            return Err(SchemaError::new(
                Some(line),
                "a final state takes only its name and optionally 'failed'",
                *other,
            ));
        }
    };
    if words[0].contains(['{', '}']) {
        return Err(SchemaError::new(Some(line), "a final state runs no actions", words[0]));
    }
    Ok(DraftState {
        name: words[0].to_string(),
        actions: Vec::new(),
        initial: false,
        kind,
        line: Some(line),
    })
}

/// `FROMS -> TOS [on EVENT] [[CONDITION]]`: one draft edge per source and target.
fn edge_declaration(text: &str, line: usize) -> Result<Vec<DraftEdge>, SchemaError> {
    let (left, right) = text.split_once("->").unwrap_or((text, ""));
    if right.contains("->") {
        return Err(SchemaError::new(Some(line), "one '->' per edge line", "->"));
    }
    let sources = name_list(left, "source state", line)?;
    let (before, condition) = match right.find('[') {
        None => {
            if let Some(close) = right.find(']') {
                return Err(SchemaError::new(Some(line), "']' without '['", &right[close..=close]));
            }
            (right, None)
        }
        Some(open) => {
            let rest = right[open..].trim_end();
            let close = rest
                .rfind(']')
                .ok_or_else(|| SchemaError::new(Some(line), "the condition is not closed with ']'", "<end>"))?;
            if close + 1 != rest.len() {
                return Err(SchemaError::new(
                    Some(line),
                    "text after the condition",
                    rest[close + 1..].trim(),
                ));
            }
            (&right[..open], Some(rest[1..close].to_string()))
        }
    };
    let words = words_at(before);
    let (targets, event) = match words.iter().position(|(_, w)| *w == "on") {
        None => (before, None),
        Some(i) => {
            let event = match &words[i + 1..] {
                [] => return Err(SchemaError::new(Some(line), "expected an event after 'on'", "<end>")),
                [(_, e)] => e.to_string(),
                [_, (_, extra), ..] => {
                    return Err(SchemaError::new(
                        Some(line),
                        "an edge has one event (a condition goes in [brackets])",
                        *extra,
                    ));
                }
            };
            (&before[..words[i].0], Some(event))
        }
    };
    let targets = name_list(targets, "target state", line)?;
    let mut edges = Vec::with_capacity(sources.len() * targets.len());
    for from in &sources {
        for to in &targets {
            edges.push(DraftEdge {
                from: from.clone(),
                to: to.clone(),
                event: event.clone(),
                condition: condition.clone(),
                line: Some(line),
            });
        }
    }
    Ok(edges)
}

/// Reads a schema from its text; errors name the line and the offending token.
pub fn parse_schema(text: &str) -> Result<Schema, SchemaError> {
    let mut draft = Draft::default();
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let content = strip_comment(raw).trim();
        let Some(first) = content.split_whitespace().next() else {
            continue;
        };
        let rest = content[first.len()..].trim();
        if first == "machine" {
            let mut words = rest.split_whitespace();
            let name = match (words.next(), words.next()) {
                (None, _) => return Err(SchemaError::new(Some(line), "expected a machine name", "<end>")),
                (Some(n), None) => n,
                (Some(_), Some(extra)) => {
                    return Err(SchemaError::new(
                        Some(line),
                        "a machine line takes only its name",
                        extra,
                    ));
                }
            };
            draft.machines.push(DraftMachine {
                name: name.to_string(),
                line: Some(line),
                states: Vec::new(),
                edges: Vec::new(),
            });
            continue;
        }
        let Some(machine) = draft.machines.last_mut() else {
            return Err(SchemaError::new(
                Some(line),
                "a declaration before the first 'machine NAME' line",
                first,
            ));
        };
        match first {
            "initial" | "state" => machine.states.push(state_declaration(rest, first == "initial", line)?),
            "final" => machine.states.push(final_declaration(rest, line)?),
            _ if content.contains("->") => machine.edges.extend(edge_declaration(content, line)?),
            _ => {
                return Err(SchemaError::new(
                    Some(line),
                    "expected 'machine', 'initial', 'state', 'final' or an edge 'FROM -> TO'",
                    first,
                ));
            }
        }
    }
    validate(draft)
}

/// Writes `schema` in the file format (one canonical form: parsing it gives the same schema).
pub fn write_schema(schema: &Schema) -> String {
    let mut out = String::new();
    for (i, m) in schema.machines().iter().enumerate() {
        if i > 0 {
            out.push('\n');
        }
        let _ = writeln!(out, "machine {}", m.name());
        for (s, state) in m.states().iter().enumerate() {
            let keyword = match state.kind {
                StateKind::Final | StateKind::Failure => "final",
                StateKind::Ordinary if s == m.initial() => "initial",
                StateKind::Ordinary => "state",
            };
            let _ = write!(out, "  {keyword} {}", state.name);
            if !state.actions.is_empty() {
                let _ = write!(out, " {{{}}}", state.actions.join(", "));
            }
            if state.kind == StateKind::Failure {
                out.push_str(" failed");
            }
            out.push('\n');
        }
        for e in m.edges() {
            let _ = write!(out, "  {} -> {}", m.states()[e.from].name, m.states()[e.to].name);
            if let Some(event) = &e.event {
                let _ = write!(out, " on {event}");
            }
            if e.condition != Expr::True {
                let _ = write!(out, " [{}]", e.condition.to_guard_text());
            }
            out.push('\n');
        }
    }
    out
}
