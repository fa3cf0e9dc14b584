//! A plan schema (thesis Definition 4): machines whose plan states are labelled
//! with the actions that run in parallel there, and whose edges carry an event
//! (the trigger) and a guard condition.
//!
//! A [`Schema`] is always valid: it is only made by [`validate`] from a
//! [`Draft`] (what the file reader and the builder collect), which checks names,
//! references, events, conditions and that no machine calls itself.

use std::collections::HashMap;

use super::SchemaError;
use crate::condition::{Expr, parse_condition};

/// Words of the file format that cannot name a machine or a state.
pub const KEYWORDS: [&str; 6] = ["machine", "initial", "state", "final", "failed", "on"];

/// What a plan state is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum StateKind {
    /// An ordinary state: its actions run until an outgoing edge is followed.
    Ordinary,
    /// A final state: entering it ends the machine successfully (`M.finished`).
    Final,
    /// A final state that ends the machine as failed (`M.failed`).
    Failure,
}

impl StateKind {
    /// Whether the state is final (absorbing).
    pub(crate) fn is_final(self) -> bool {
        self != StateKind::Ordinary
    }
}

/// A plan state: a configuration of its machine and the actions running in it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlanState {
    /// Its name, unique in the machine.
    pub name: String,
    /// The actions executed in parallel in this state (primitive actions, or
    /// machines of the same schema), in the order written.
    pub actions: Vec<String>,
    /// Ordinary or final.
    pub kind: StateKind,
    /// The line that declared it, if it came from a file.
    pub line: Option<usize>,
}

/// A transition of a machine: `from` to `to` when `event` happens and `condition` holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Edge {
    /// Index of the source state.
    pub from: usize,
    /// The triggering event: an atom sensed in the knowledge base (`closeToBall`)
    /// or a condition of a running action (`Kick.finished`); `None` is the empty
    /// event, which always triggers.
    pub event: Option<String>,
    /// The guard ([`Expr::True`] when absent).
    pub condition: Expr,
    /// Index of the target state.
    pub(crate) to: usize,
    /// The line that declared it, if it came from a file.
    pub line: Option<usize>,
}

/// One state machine of a schema.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Machine {
    name: String,
    line: Option<usize>,
    states: Vec<PlanState>,
    initial: usize,
    edges: Vec<Edge>,
}

impl Machine {
    /// Its name (how other machines call it).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The line that opened it, if it came from a file.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// Its plan states, in the order declared.
    pub fn states(&self) -> &[PlanState] {
        &self.states
    }

    /// Index of the initial state.
    pub fn initial(&self) -> usize {
        self.initial
    }

    /// Its edges, in the order declared.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// The index of the state called `name`.
    pub fn state_named(&self, name: &str) -> Option<usize> {
        self.states.iter().position(|s| s.name == name)
    }

    /// Every action name of its states, each once, in order of first appearance.
    pub fn actions(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for a in self.states.iter().flat_map(|s| &s.actions) {
            if !out.contains(&a.as_str()) {
                out.push(a);
            }
        }
        out
    }
}

/// A plan schema: its machines, the first being the root.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Schema {
    machines: Vec<Machine>,
}

impl Schema {
    /// Every machine; index 0 is the root.
    pub fn machines(&self) -> &[Machine] {
        &self.machines
    }

    /// The root machine (the first one).
    pub fn root(&self) -> &Machine {
        &self.machines[0]
    }

    /// The index of the machine called `name`.
    pub(crate) fn machine_named(&self, name: &str) -> Option<usize> {
        self.machines.iter().position(|m| m.name == name)
    }
}

/// A state as written, before validation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DraftState {
    pub name: String,
    pub actions: Vec<String>,
    pub initial: bool,
    pub kind: StateKind,
    pub line: Option<usize>,
}

/// An edge as written, before validation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DraftEdge {
    pub from: String,
    pub(crate) to: String,
    pub event: Option<String>,
    pub condition: Option<String>,
    pub line: Option<usize>,
}

/// A machine as written, before validation.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct DraftMachine {
    pub name: String,
    pub line: Option<usize>,
    pub states: Vec<DraftState>,
    pub(crate) edges: Vec<DraftEdge>,
}

/// A schema as written, before validation.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Draft {
    pub(crate) machines: Vec<DraftMachine>,
}

/// Whether `word` is a name of a machine or state: a letter or `_`, then letters, digits or `_`.
pub(crate) fn is_name(word: &str) -> bool {
    let mut chars = word.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Whether `word` is an action name: like a state name, also allowing the
/// `robot#` agent prefix and `-` (no `.`: `A.finished` names a condition of `A`).
pub(crate) fn is_action_name(word: &str) -> bool {
    let mut chars = word.chars();
    matches!(chars.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || "_#-".contains(c))
}

fn check_name(word: &str, what: &str, line: Option<usize>) -> Result<(), SchemaError> {
    if KEYWORDS.contains(&word) {
        return Err(SchemaError::new(line, format!("a keyword cannot name a {what}"), word));
    }
    if !is_name(word) {
        return Err(SchemaError::new(
            line,
            format!("malformed {what} name (a letter or '_', then letters, digits or '_')"),
            word,
        ));
    }
    Ok(())
}

/// The action `A` of an internal condition `A.cond` (exactly one '.', as in plan guards).
pub(crate) fn internal_action(atom: &str) -> Option<(&str, &str)> {
    if atom.matches('.').count() == 1 {
        atom.split_once('.')
    } else {
        None
    }
}

/// Checks that every internal condition `A.x` among `atoms` names an action of `state`.
fn check_internal_atoms<'a>(
    atoms: impl IntoIterator<Item = &'a str>,
    state: &PlanState,
    machine: &str,
    line: Option<usize>,
) -> Result<(), SchemaError> {
    for atom in atoms {
        if let Some((action, cond)) = internal_action(atom) {
            if cond.is_empty() {
                return Err(SchemaError::new(line, "empty internal condition", atom));
            }
            if !state.actions.iter().any(|a| a == action) {
                return Err(SchemaError::new(
                    line,
                    format!(
                        "machine '{machine}': '{action}' does not run in state '{}', so its conditions cannot be sensed there",
                        state.name
                    ),
                    atom,
                ));
            }
        }
    }
    Ok(())
}

fn validate_machine(draft: DraftMachine) -> Result<Machine, SchemaError> {
    let machine = draft.name.clone();
    check_name(&draft.name, "machine", draft.line)?;
    let mut states: Vec<PlanState> = Vec::with_capacity(draft.states.len());
    let mut initial: Option<(usize, Option<usize>)> = None;
    for s in draft.states {
        check_name(&s.name, "state", s.line)?;
        if states.iter().any(|t| t.name == s.name) {
            return Err(SchemaError::new(
                s.line,
                format!("machine '{machine}': a second state with this name"),
                &s.name,
            ));
        }
        for (i, a) in s.actions.iter().enumerate() {
            if !is_action_name(a) {
                return Err(SchemaError::new(
                    s.line,
                    "malformed action name (a letter or '_', then letters, digits, '_', '#' or '-')",
                    a,
                ));
            }
            if s.actions[..i].contains(a) {
                return Err(SchemaError::new(s.line, "an action listed twice in one state", a));
            }
        }
        if s.kind.is_final() && !s.actions.is_empty() {
            return Err(SchemaError::new(
                s.line,
                format!(
                    "final state '{}' lists actions; a final state ends its machine and runs nothing",
                    s.name
                ),
                &s.actions[0],
            ));
        }
        if s.initial {
            if s.kind.is_final() {
                return Err(SchemaError::new(s.line, "the initial state cannot be final", &s.name));
            }
            if let Some((_, line)) = initial {
                let at = line.map_or(String::new(), |l| format!(" (the first is on line {l})"));
                return Err(SchemaError::new(
                    s.line,
                    format!("machine '{machine}': a second initial state{at}"),
                    &s.name,
                ));
            }
            initial = Some((states.len(), s.line));
        }
        states.push(PlanState {
            name: s.name,
            actions: s.actions,
            kind: s.kind,
            line: s.line,
        });
    }
    let Some((initial, _)) = initial else {
        return Err(SchemaError::new(
            draft.line,
            "a machine needs one initial state ('initial NAME {ACTIONS}')",
            &machine,
        ));
    };

    let mut edges: Vec<Edge> = Vec::with_capacity(draft.edges.len());
    let mut seen: HashMap<(usize, Option<String>, String, usize), Option<usize>> = HashMap::new();
    for e in draft.edges {
        let find = |name: &str| {
            states
                .iter()
                .position(|s| s.name == name)
                .ok_or_else(|| SchemaError::new(e.line, format!("machine '{machine}': no state has this name"), name))
        };
        let from = find(&e.from)?;
        let to = find(&e.to)?;
        if states[from].kind.is_final() {
            return Err(SchemaError::new(
                e.line,
                "an edge leaves a final state; final states are absorbing",
                &e.from,
            ));
        }
        let event = match e.event {
            None => None,
            Some(text) => {
                let parsed = parse_condition(&text).map_err(|err| {
                    SchemaError::new(e.line, format!("malformed event ({})", err.message), &err.token)
                })?;
                match parsed {
                    Expr::Atom(a) if a == text.trim() => Some(a),
                    _ => {
                        return Err(SchemaError::new(
                            e.line,
                            "an event is one atom (a sensed event such as closeToBall, or Action.finished)",
                            text,
                        ));
                    }
                }
            }
        };
        let condition = match &e.condition {
            None => Expr::True,
            Some(text) => parse_condition(text).map_err(|err| {
                SchemaError::new(
                    e.line,
                    format!("malformed condition: {} ({})", err.message, err.hint()),
                    &err.token,
                )
            })?,
        };
        let atoms: Vec<&str> = event.iter().map(String::as_str).chain(condition.atoms()).collect();
        check_internal_atoms(atoms, &states[from], &machine, e.line)?;
        let key = (from, event.clone(), condition.to_guard_text(), to);
        if let Some(first) = seen.insert(key, e.line) {
            let at = first.map_or(String::new(), |l| format!(" (first on line {l})"));
            return Err(SchemaError::new(
                e.line,
                format!("an edge repeated{at}"),
                format!("{} -> {}", e.from, e.to),
            ));
        }
        edges.push(Edge {
            from,
            event,
            condition,
            to,
            line: e.line,
        });
    }
    Ok(Machine {
        name: draft.name,
        line: draft.line,
        states,
        initial,
        edges,
    })
}

/// Checks a draft and makes it a schema; errors name the line and token.
pub(crate) fn validate(draft: Draft) -> Result<Schema, SchemaError> {
    if draft.machines.is_empty() {
        return Err(SchemaError::new(
            None,
            "a schema needs at least one machine ('machine NAME')",
            "<end>",
        ));
    }
    let mut machines: Vec<Machine> = Vec::with_capacity(draft.machines.len());
    for m in draft.machines {
        if let Some(first) = machines.iter().find(|x| x.name == m.name) {
            let at = first
                .line
                .map_or(String::new(), |l| format!(" (the first is on line {l})"));
            return Err(SchemaError::new(
                m.line,
                format!("a second machine with this name{at}"),
                &m.name,
            ));
        }
        machines.push(validate_machine(m)?);
    }
    let schema = Schema { machines };
    check_calls(&schema)?;
    Ok(schema)
}

/// Refuses a machine that calls itself, directly or through other machines.
fn check_calls(schema: &Schema) -> Result<(), SchemaError> {
    fn visit(schema: &Schema, m: usize, path: &mut Vec<usize>, done: &mut [bool]) -> Result<(), SchemaError> {
        if done[m] {
            return Ok(());
        }
        let machine = &schema.machines[m];
        for state in machine.states() {
            for action in &state.actions {
                let Some(callee) = schema.machine_named(action) else {
                    continue;
                };
                if callee == m || path.contains(&callee) {
                    let names: Vec<&str> = path
                        .iter()
                        .chain(std::iter::once(&m))
                        .map(|&i| schema.machines[i].name())
                        .chain(std::iter::once(action.as_str()))
                        .collect();
                    return Err(SchemaError::new(
                        state.line,
                        format!("a machine calls itself ({})", names.join(" -> ")),
                        action,
                    ));
                }
                path.push(m);
                visit(schema, callee, path, done)?;
                path.pop();
            }
        }
        done[m] = true;
        Ok(())
    }
    let mut done = vec![false; schema.machines.len()];
    for m in 0..schema.machines.len() {
        visit(schema, m, &mut Vec::new(), &mut done)?;
    }
    Ok(())
}
