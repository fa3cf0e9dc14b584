//! PNPgen's conditional plan: states with one action each, edges between
//! them, and edges labelled by a sensing action's outcome.
//!
//! ```text
//! plan{ n_states=4
//!  0[label=0,actions=goto_door]
//!  1[label=1,actions=sense_open]
//!  2[label=2,actions=goto_room]
//!  3[label=GOAL,actions=]
//!  "0" -> "1"
//!  "1" [t] -> "2" ; "1" [f] -> "0"
//!  "2" -> "GOAL"
//! }
//! ```
//!
//! States are named by their `label`, which edges quote; the first state
//! declared is the initial one, the state labelled `GOAL` (no action) is the
//! goal. A state with one plain edge runs its action into the next state; a
//! state whose edges carry labels runs a sensing action, ending into the
//! state of the outcome that holds: `[t]` and `[f]` test the atom named as
//! the action (`[sense_open]`, `[not sense_open]`), any other label is the
//! condition as written. A state with an action and no edge ends in the goal
//! (as PNPgen does). Edges back to a state already seen make loops.

use std::collections::HashMap;

use super::{ActionSite, GenerateError, GeneratedPlan, linear};
use crate::condition::parse_condition;
use crate::plan::PlaceRef;

/// One state: its label and action (none for the goal).
#[derive(Debug, Clone, PartialEq, Eq)]
struct State {
    label: String,
    action: Option<String>,
}

/// One edge: from, to, and the outcome's condition (none for a plain edge).
#[derive(Debug, Clone, PartialEq, Eq)]
struct Edge {
    from: String,
    to: String,
    outcome: Option<String>,
}

fn bad(message: impl Into<String>, token: impl Into<String>) -> GenerateError {
    GenerateError::BadConditional {
        message: message.into(),
        token: token.into(),
    }
}

/// Whether `label` names the goal state.
fn is_goal(label: &str) -> bool {
    label.eq_ignore_ascii_case("goal")
}

/// The states and edges of the text.
fn parse(text: &str) -> Result<(Vec<State>, Vec<Edge>), GenerateError> {
    let open = text
        .find('{')
        .ok_or_else(|| bad("a conditional plan is 'plan{ ... }'", text.trim()))?;
    let close = text
        .rfind('}')
        .filter(|&c| c > open)
        .ok_or_else(|| bad("no closing '}'", "<end>"))?;
    let body = &text[open + 1..close];
    let mut states = Vec::new();
    let mut edges = Vec::new();
    for part in body
        .lines()
        .flat_map(|l| l.split(';'))
        .map(str::trim)
        .filter(|p| !p.is_empty())
    {
        if part.starts_with("n_states") {
            continue;
        }
        if part.starts_with('"') {
            let (from, rest) = quoted(part)?;
            let rest = rest.trim_start();
            let (outcome, rest) = match rest.strip_prefix('[') {
                Some(r) => {
                    let (cond, r) = r
                        .split_once(']')
                        .ok_or_else(|| bad("an outcome is '[condition]'", part))?;
                    (Some(cond.trim().to_string()), r.trim_start())
                }
                None => (None, rest),
            };
            let rest = rest
                .strip_prefix("->")
                .ok_or_else(|| bad("an edge is \"from\" -> \"to\"", part))?;
            let (to, tail) = quoted(rest.trim_start())?;
            if !tail.trim().is_empty() {
                return Err(bad("text after an edge", tail.trim()));
            }
            edges.push(Edge { from, to, outcome });
            continue;
        }
        let attrs = part
            .split_once('[')
            .and_then(|(_, a)| a.strip_suffix(']'))
            .ok_or_else(|| bad("a state is 'id[label=L,actions=a]'", part))?;
        let mut label = None;
        let mut action = None;
        for kv in attrs.split(',') {
            match kv.split_once('=') {
                Some(("label", v)) => label = Some(v.trim().to_string()),
                Some(("actions", v)) => action = Some(v.trim().to_string()).filter(|a| !a.is_empty()),
                _ => return Err(bad("a state's attributes are label= and actions=", kv)),
            }
        }
        let label = label.ok_or_else(|| bad("a state has a label", part))?;
        if let Some(a) = &action
            && !linear::is_action_name(a)
        {
            return Err(bad("not an action's name", a.clone()));
        }
        if states.iter().any(|s: &State| s.label == label) {
            return Err(bad("two states with one label", label));
        }
        states.push(State { label, action });
    }
    Ok((states, edges))
}

/// The quoted name at the start of `text` and what follows it.
fn quoted(text: &str) -> Result<(String, &str), GenerateError> {
    let inner = text
        .strip_prefix('"')
        .ok_or_else(|| bad("a state is quoted in an edge", text))?;
    let (name, rest) = inner.split_once('"').ok_or_else(|| bad("no closing '\"'", text))?;
    Ok((name.to_string(), rest))
}

impl GeneratedPlan {
    /// A conditional plan in PNPgen's form, as a plan with sensing.
    pub fn conditional(name: &str, text: &str) -> Result<Self, GenerateError> {
        let (states, edges) = parse(text)?;
        let first = states.first().ok_or_else(|| bad("no state", text.trim()))?;
        for e in &edges {
            for end in [&e.from, &e.to] {
                if !is_goal(end) && !states.iter().any(|s| &s.label == end) {
                    return Err(bad("an edge names a state not declared", end.clone()));
                }
            }
        }
        let mut plan = GeneratedPlan::new(name);
        let mut places: HashMap<&str, PlaceRef> = HashMap::new();
        let start = plan.builder.place(first.label.clone());
        let init = plan.init;
        plan.builder.transition("[]", &[(init, 1)], &[(start, 1)]);
        places.insert(&first.label, start);
        let mut place_of = |plan: &mut GeneratedPlan, label: &str| -> PlaceRef {
            if is_goal(label) {
                return plan.goal;
            }
            *places
                .entry(
                    states
                        .iter()
                        .find(|s| s.label == label)
                        .map_or("", |s| s.label.as_str()),
                )
                .or_insert_with(|| plan.builder.place(label))
        };
        for state in &states {
            let Some(action) = &state.action else {
                if !is_goal(&state.label) && edges.iter().any(|e| e.from == state.label) {
                    return Err(bad("a state with edges but no action", state.label.clone()));
                }
                continue;
            };
            let here = place_of(&mut plan, &state.label);
            let out: Vec<&Edge> = edges.iter().filter(|e| e.from == state.label).collect();
            match out.as_slice() {
                [] => {
                    let goal = plan.goal;
                    plan.step(here, &linear::PlanStep::new(action.clone()), Some(goal), true);
                }
                [edge] if edge.outcome.is_none() => {
                    let to = place_of(&mut plan, &edge.to);
                    plan.step(here, &linear::PlanStep::new(action.clone()), Some(to), true);
                }
                _ => {
                    let exec = plan.builder.place(format!("{action}.exec"));
                    plan.builder
                        .transition(format!("{action}.start"), &[(here, 1)], &[(exec, 1)]);
                    let mut after = None;
                    for edge in out {
                        let cond = match edge.outcome.as_deref() {
                            Some("t") => action.clone(),
                            Some("f") => format!("not {action}"),
                            Some(c) => {
                                parse_condition(c).map_err(|e| bad(format!("the outcome does not read: {e}"), c))?;
                                c.to_string()
                            }
                            None => return Err(bad("a sensing state's edges all carry an outcome", edge.to.clone())),
                        };
                        let to = place_of(&mut plan, &edge.to);
                        after.get_or_insert(to);
                        plan.builder
                            .transition(format!("{action}.end [{cond}]"), &[(exec, 1)], &[(to, 1)]);
                    }
                    plan.sites.push(ActionSite {
                        name: action.clone(),
                        before: here,
                        exec,
                        after: after.unwrap_or(plan.goal),
                        wait_exec: None,
                    });
                }
            }
        }
        Ok(plan)
    }
}
