//! A Petri Net Plan: a net whose labels are interpreted as actions, goals and guards.

use std::any::Any;
use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::labels::{Function, TransitionToken, parse_place_label, transition_tokens};
use super::{PlanError, PlanWarning};
use crate::condition::{AtomRef, AtomTable, Condition, parse_condition};
use crate::net::{Incidence, Marking, PetriNet, PlaceId, TransitionId, TransitionNode};

/// Index of an action (or sub-plan call) in its plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct ActionId(pub u32);

impl ActionId {
    /// Its index.
    #[inline]
    pub const fn index(self) -> usize {
        self.0 as usize
    }
}

/// An action or sub-plan named by execution places.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActionInfo {
    /// The full name before `.exec`, agent prefix and parameters included (`r1#goto_3_4`).
    pub name: String,
    /// The agent in charge, from a `robot#action` prefix.
    pub agent: Option<String>,
    /// Places labelled as its execution place (they share one action object).
    pub exec_places: Vec<PlaceId>,
}

impl ActionInfo {
    /// The name without the agent prefix.
    pub fn base_name(&self) -> &str {
        self.name.split_once('#').map_or(&self.name, |(_, b)| b)
    }
}

/// A function call carried by a transition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Call {
    /// What to call.
    pub function: Function,
    /// On which action.
    pub action: ActionId,
}

/// The interpreted label of a transition.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TransitionInfo {
    /// The compiled guard: the explicit one, or the implicit wait for
    /// `A.finished` (`A.end`) / `A.failed` (`A.fail`), or true.
    pub guard: Condition,
    /// The explicit guard text, if the label had one.
    pub explicit_guard: Option<String>,
    /// The functions it calls, in label order.
    pub calls: Vec<Call>,
}

/// What an internal condition asks of its action.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum InternalKind {
    /// `A.finished`.
    Finished,
    /// `A.failed`.
    Failed,
    /// Any other condition the action declares.
    Declared(String),
}

/// An internal condition `A.cond`, tested by the action itself.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct InternalCondition {
    /// The action answering it.
    pub action: ActionId,
    /// Which condition.
    pub kind: InternalKind,
}

/// Which atoms a plan may use.
#[derive(Debug, Clone, Copy)]
pub enum AllowedAtoms<'a> {
    /// Any atom: the plan collects its own table (for inspection tools).
    Open,
    /// Only the atoms a domain declares; any other is refused at load.
    Closed(&'a AtomTable),
}

/// A loaded plan: the net plus its interpretation, ready to execute or analyse.
#[derive(Debug, Clone)]
pub struct Plan {
    net: PetriNet,
    incidence: Incidence,
    actions: Vec<ActionInfo>,
    place_action: Vec<Option<ActionId>>,
    goal: Vec<(PlaceId, u8)>,
    fail: Vec<(PlaceId, u8)>,
    transitions: Vec<TransitionInfo>,
    internal: Vec<InternalCondition>,
    atoms: AtomTable,
    warnings: Vec<PlanWarning>,
    origin: Option<Arc<dyn PlanOrigin>>,
}

/// What a plan was constructed from when it is the process of another model
/// (a plan schema's, thesis chapter 3), carried by the plan so that whoever
/// knows that model's kind (the executor) can run it with its own semantics.
pub(crate) trait PlanOrigin: Any + Send + Sync + fmt::Debug {
    /// The other plans whose markings a learner of the plan sees, in plan key
    /// order after the plan itself (a schema's other machines).
    fn called_plans(&self) -> Vec<&Plan>;
}

impl Plan {
    /// Interprets `net` as a plan, resolving atoms against `vocabulary`. A net
    /// without places is refused ([`PlanError::Empty`]).
    pub fn from_net(net: PetriNet, vocabulary: AllowedAtoms<'_>) -> Result<Self, PlanError> {
        if net.places().is_empty() {
            return Err(PlanError::Empty);
        }
        let incidence = Incidence::new(&net);
        let places = read_places(&net)?;
        let mut labels = Labels::new(&incidence, places, vocabulary);
        let mut transitions = Vec::with_capacity(net.transitions().len());
        for (i, node) in net.transitions().iter().enumerate() {
            transitions.push(labels.transition(TransitionId::new(i), node)?);
        }
        let Labels {
            places,
            atoms,
            internal,
            warnings,
            ..
        } = labels;
        Ok(Plan {
            incidence,
            actions: places.actions,
            place_action: places.place_action,
            goal: places.goal,
            fail: places.fail,
            transitions,
            internal,
            atoms,
            warnings,
            origin: None,
            net,
        })
    }

    /// This plan, constructed from `origin` (the process of a plan schema,
    /// thesis chapter 3) rather than read as a Petri Net Plan: its net is the
    /// origin's.
    pub(crate) fn with_origin(mut self, origin: Arc<dyn PlanOrigin>) -> Self {
        self.origin = Some(origin);
        self
    }

    /// What this plan was constructed from, if it is not a Petri Net Plan
    /// read as such (`schema` recovers its process from it).
    pub(crate) fn origin(&self) -> Option<&Arc<dyn PlanOrigin>> {
        self.origin.as_ref()
    }

    /// The plans whose markings a learner of this plan sees, indexed by the
    /// executor's `PlanKey`: this plan, then (for a plan constructed from a
    /// schema) the other machines of the schema.
    pub fn activation_plans(&self) -> Vec<&Plan> {
        let called = self.origin.iter().flat_map(|o| o.called_plans());
        std::iter::once(self).chain(called).collect()
    }

    /// What is unusual in the plan but accepted, as the PNP library accepts it.
    pub fn warnings(&self) -> &[PlanWarning] {
        &self.warnings
    }

    /// The name of place `p` for a reader: its label, or its id when the label is blank.
    pub(crate) fn place_name(&self, p: PlaceId) -> &str {
        let place = self.net.place(p);
        if place.label.trim().is_empty() {
            &place.id
        } else {
            &place.label
        }
    }

    /// The plan's name.
    pub fn name(&self) -> &str {
        self.net.name()
    }

    /// The underlying net with its ids and labels.
    pub fn net(&self) -> &PetriNet {
        &self.net
    }

    /// The compiled pre/post sets.
    pub(crate) fn incidence(&self) -> &Incidence {
        &self.incidence
    }

    /// Every action and sub-plan the plan names.
    pub fn actions(&self) -> &[ActionInfo] {
        &self.actions
    }

    /// One action.
    pub fn action(&self, id: ActionId) -> &ActionInfo {
        &self.actions[id.index()]
    }

    /// The action named `name`, if any.
    pub fn action_named(&self, name: &str) -> Option<ActionId> {
        self.actions
            .iter()
            .position(|a| a.name == name)
            .map(|i| ActionId(i as u32))
    }

    /// The action whose execution place `place` is.
    #[inline]
    pub(crate) fn exec_action(&self, place: PlaceId) -> Option<ActionId> {
        self.place_action[place.index()]
    }

    /// Places with a goal value and that value.
    pub fn goal(&self) -> &[(PlaceId, u8)] {
        &self.goal
    }

    /// Places with a fail value and that value.
    pub fn fail(&self) -> &[(PlaceId, u8)] {
        &self.fail
    }

    /// The interpreted label of `t`.
    #[inline]
    pub fn transition(&self, t: TransitionId) -> &TransitionInfo {
        &self.transitions[t.index()]
    }

    /// Internal conditions referenced by guards (indexed by `AtomRef::Internal`).
    pub fn internal_conditions(&self) -> &[InternalCondition] {
        &self.internal
    }

    /// The atom table guards resolve against.
    pub fn atoms(&self) -> &AtomTable {
        &self.atoms
    }

    /// The initial marking.
    pub fn initial_marking(&self) -> Marking {
        self.net.initial_marking()
    }

    /// Whether `m` is a goal marking (a plan without goal places never is).
    #[inline]
    pub(crate) fn is_goal(&self, m: &Marking) -> bool {
        !self.goal.is_empty() && self.goal.iter().all(|&(p, n)| m.get(p) == n)
    }

    /// Whether `m` is a fail marking (a plan without fail places never is).
    #[inline]
    pub(crate) fn is_fail(&self, m: &Marking) -> bool {
        !self.fail.is_empty() && self.fail.iter().all(|&(p, n)| m.get(p) == n)
    }

    /// A readable name for an atom reference.
    pub fn atom_name(&self, atom: AtomRef) -> String {
        match atom {
            AtomRef::Fact(id) => self.atoms.name(id).to_string(),
            AtomRef::Internal(i) => {
                let c = &self.internal[i as usize];
                let cond = match &c.kind {
                    InternalKind::Finished => "finished",
                    InternalKind::Failed => "failed",
                    InternalKind::Declared(s) => s,
                };
                format!("{}.{}", self.action(c.action).name, cond)
            }
        }
    }

    /// A readable description of a marking: the labels of its marked places.
    pub fn describe(&self, m: &Marking) -> String {
        let parts: Vec<String> = m
            .marked()
            .map(|(p, n)| {
                let name = self.place_name(p);
                if n == 1 {
                    name.to_string()
                } else {
                    format!("{name}*{n}")
                }
            })
            .collect();
        if parts.is_empty() {
            "-".to_string()
        } else {
            parts.join(" ")
        }
    }
}

/// What the place labels say: actions and their execution places, goal and fail values.
struct Places {
    actions: Vec<ActionInfo>,
    by_name: HashMap<String, ActionId>,
    place_action: Vec<Option<ActionId>>,
    goal: Vec<(PlaceId, u8)>,
    fail: Vec<(PlaceId, u8)>,
}

impl Places {
    /// Adds action `name`, with no execution place yet.
    fn add_action(&mut self, name: &str) -> ActionId {
        self.actions.push(ActionInfo {
            agent: name.split_once('#').map(|(a, _)| a.to_string()),
            name: name.to_string(),
            exec_places: Vec::new(),
        });
        let id = ActionId(self.actions.len() as u32 - 1);
        self.by_name.insert(name.to_string(), id);
        id
    }
}

/// Reads every place label of `net`: execution places (one action per name),
/// goal and fail values.
fn read_places(net: &PetriNet) -> Result<Places, PlanError> {
    let mut places = Places {
        actions: Vec::new(),
        by_name: HashMap::new(),
        place_action: vec![None; net.places().len()],
        goal: Vec::new(),
        fail: Vec::new(),
    };
    for (i, place) in net.places().iter().enumerate() {
        let pid = PlaceId::new(i);
        let label = parse_place_label(&place.label).map_err(|e| PlanError::PlaceLabel {
            place: place.id.clone(),
            label: place.label.clone(),
            token: e.token,
            reason: e.reason,
        })?;
        if let Some(name) = label.exec {
            let id = match places.by_name.get(&name) {
                Some(&id) => id,
                None => places.add_action(&name),
            };
            places.actions[id.index()].exec_places.push(pid);
            places.place_action[i] = Some(id);
        }
        if let Some(n) = label.goal {
            places.goal.push((pid, n));
        }
        if let Some(n) = label.fail {
            places.fail.push((pid, n));
        }
    }
    Ok(places)
}

/// The interpretation of transition labels under way: the places' reading,
/// extended by actions only calls and guards name, and what the labels add.
struct Labels<'a> {
    incidence: &'a Incidence,
    vocabulary: AllowedAtoms<'a>,
    places: Places,
    atoms: AtomTable,
    internal: Vec<InternalCondition>,
    warnings: Vec<PlanWarning>,
}

impl<'a> Labels<'a> {
    fn new(incidence: &'a Incidence, places: Places, vocabulary: AllowedAtoms<'a>) -> Self {
        let atoms = match vocabulary {
            AllowedAtoms::Open => AtomTable::new(),
            AllowedAtoms::Closed(table) => table.clone(),
        };
        Labels {
            incidence,
            vocabulary,
            places,
            atoms,
            internal: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// Interprets the label of transition `t`: its calls, then its guard (the
    /// explicit one, or the implicit wait of its calls).
    fn transition(&mut self, t: TransitionId, node: &TransitionNode) -> Result<TransitionInfo, PlanError> {
        let tokens =
            transition_tokens(&node.label).ok_or_else(|| label_error(node, &node.label, "unbalanced brackets"))?;
        let mut guard_text: Option<&str> = None;
        let mut calls = Vec::new();
        for token in tokens {
            match token {
                TransitionToken::Guard(g) => {
                    if guard_text.replace(g).is_some() {
                        return Err(label_error(
                            node,
                            &format!("[{g}]"),
                            "a transition has at most one guard",
                        ));
                    }
                }
                TransitionToken::Call(name, function) => calls.push(self.named_call(t, node, name, function)),
                TransitionToken::BareCall(function) => {
                    let adjacent =
                        adjacent_actions(self.incidence, &self.places.place_action, t, function.binds_output());
                    if adjacent.is_empty() {
                        return Err(label_error(
                            node,
                            function.as_str(),
                            "no adjacent execution place for this function",
                        ));
                    }
                    calls.extend(adjacent.into_iter().map(|action| Call { function, action }));
                }
                TransitionToken::Name(_) => {}
                TransitionToken::UnknownFunction(token) => {
                    return Err(label_error(
                        node,
                        token,
                        "unknown transition function (expected start, end, interrupt, resume or fail)",
                    ));
                }
            }
        }
        let guard = match guard_text {
            Some(text) => self.guard(node, text)?,
            None => implicit_wait(&calls, &mut self.internal),
        };
        Ok(TransitionInfo {
            guard,
            explicit_guard: guard_text.map(str::to_string),
            calls,
        })
    }

    /// The call `name.function` of transition `t`, warning if it is unusual;
    /// an action no execution place names is added.
    fn named_call(&mut self, t: TransitionId, node: &TransitionNode, name: &str, function: Function) -> Call {
        let known = self.places.by_name.get(name).copied();
        let places = &self.places;
        if let Some(message) = unusual_call(
            self.incidence,
            &places.place_action,
            t,
            name,
            function,
            known,
            &places.actions,
        ) {
            self.warnings.push(PlanWarning {
                transition: node.id.clone(),
                label: node.label.clone(),
                message,
            });
        }
        // The PNP library calls executables by name: an action no execution
        // place names is started or ended all the same, and never stepped.
        let action = known.unwrap_or_else(|| self.places.add_action(name));
        Call { function, action }
    }

    /// Parses and compiles the explicit guard `text` of `node`.
    fn guard(&mut self, node: &TransitionNode, text: &str) -> Result<Condition, PlanError> {
        let expr = parse_condition(text).map_err(|source| PlanError::Guard {
            transition: node.id.clone(),
            label: node.label.clone(),
            source: Box::new(source),
        })?;
        Condition::compile(&expr, &mut |atom| self.guard_atom(node, atom))
    }

    /// Resolves one atom of `node`'s guard; the action of an internal
    /// condition no execution place names is added, with a warning.
    fn guard_atom(&mut self, node: &TransitionNode, atom: &str) -> Result<AtomRef, PlanError> {
        if let Some((name, _)) = atom.split_once('.').filter(|_| atom.matches('.').count() == 1)
            && !name.is_empty()
            && !self.places.by_name.contains_key(name)
        {
            // As for calls: the PNP library asks the executable by name.
            self.warnings.push(PlanWarning {
                transition: node.id.clone(),
                label: node.label.clone(),
                message: format!(
                    "no execution place names action '{name}', whose condition '{atom}' the guard \
                     tests; as the PNP library does, '{name}' is asked by name and never stepped"
                ),
            });
            self.places.add_action(name);
        }
        resolve_atom(
            atom,
            &self.places.by_name,
            &mut self.atoms,
            self.vocabulary,
            &mut self.internal,
        )
        .map_err(|reason| label_error(node, atom, &reason))
    }
}

/// An error in the label of transition `node`, at `token`.
fn label_error(node: &TransitionNode, token: &str, reason: &str) -> PlanError {
    PlanError::TransitionLabel {
        transition: node.id.clone(),
        label: node.label.clone(),
        token: token.to_string(),
        reason: reason.to_string(),
    }
}

/// Why a call of `function` on `action` (named `name`, `None` when no
/// execution place names it) by transition `t` is unusual, if it is: a start
/// or resume that marks none of the action's execution places, or an end, fail
/// or interrupt that takes its token from none of them.
fn unusual_call(
    incidence: &Incidence,
    place_action: &[Option<ActionId>],
    t: TransitionId,
    name: &str,
    function: Function,
    action: Option<ActionId>,
    actions: &[ActionInfo],
) -> Option<String> {
    let outputs = function.binds_output();
    let adjacent = adjacent_actions(incidence, place_action, t, outputs);
    if action.is_some_and(|a| adjacent.contains(&a)) {
        return None;
    }
    let call = format!("{name}.{}", function.as_str());
    let others: Vec<&str> = adjacent.iter().map(|a| actions[a.index()].name.as_str()).collect();
    let place = match (outputs, others.is_empty()) {
        (true, true) => String::new(),
        (true, false) => format!(
            " (it marks the execution place of '{}', which thus runs without being started)",
            others.join("', '")
        ),
        (false, true) => String::new(),
        (false, false) => format!(" (it takes the token of '{}')", others.join("', '")),
    };
    Some(match action {
        None => format!(
            "no execution place names action '{name}'{place}; as the PNP library does, '{call}' is \
             called by name and '{name}' is never stepped"
        ),
        Some(_) if outputs => format!(
            "'{call}' marks no execution place of '{name}'{place}; as the PNP library does, it is called by name"
        ),
        Some(_) => format!(
            "'{call}' takes its token from no execution place of '{name}'{place}; as the PNP library does, \
             it is called by name"
        ),
    })
}

/// Actions of the execution places adjacent to `t` (outputs or inputs).
fn adjacent_actions(
    incidence: &Incidence,
    place_action: &[Option<ActionId>],
    t: TransitionId,
    outputs: bool,
) -> Vec<ActionId> {
    let arcs = if outputs {
        incidence.outputs(t)
    } else {
        incidence.inputs(t)
    };
    let mut found: Vec<ActionId> = arcs.iter().filter_map(|a| place_action[a.place.index()]).collect();
    found.sort_unstable();
    found.dedup();
    found
}

fn intern_internal(internal: &mut Vec<InternalCondition>, cond: InternalCondition) -> AtomRef {
    let index = internal.iter().position(|c| *c == cond).unwrap_or_else(|| {
        internal.push(cond);
        internal.len() - 1
    });
    AtomRef::Internal(index as u32)
}

/// Resolves one atom name: `A.cond` (exactly one '.') is internal, anything else a fact.
fn resolve_atom(
    atom: &str,
    actions: &HashMap<String, ActionId>,
    atoms: &mut AtomTable,
    vocabulary: AllowedAtoms<'_>,
    internal: &mut Vec<InternalCondition>,
) -> Result<AtomRef, String> {
    if atom.matches('.').count() == 1 {
        let (name, cond) = atom.split_once('.').unwrap_or((atom, ""));
        let action = *actions
            .get(name)
            .ok_or_else(|| format!("internal condition of '{name}', which no execution place names"))?;
        let kind = match cond {
            "finished" => InternalKind::Finished,
            "failed" => InternalKind::Failed,
            "" => return Err("empty internal condition".to_string()),
            other => InternalKind::Declared(other.to_string()),
        };
        return Ok(intern_internal(internal, InternalCondition { action, kind }));
    }
    match vocabulary {
        AllowedAtoms::Open => Ok(AtomRef::Fact(atoms.intern(atom))),
        AllowedAtoms::Closed(_) => atoms.get(atom).map(AtomRef::Fact).ok_or_else(|| {
            let known: Vec<&str> = atoms.names().collect();
            format!("unknown atom (the domain declares: {})", known.join(", "))
        }),
    }
}

/// The implicit guard: wait for `finished` of ended actions and `failed` of failed ones.
fn implicit_wait(calls: &[Call], internal: &mut Vec<InternalCondition>) -> Condition {
    let waits: Vec<Condition> = calls
        .iter()
        .filter_map(|c| {
            match c.function {
                Function::End => Some(InternalKind::Finished),
                Function::Fail => Some(InternalKind::Failed),
                _ => None,
            }
            .map(|kind| Condition::Atom(intern_internal(internal, InternalCondition { action: c.action, kind })))
        })
        .collect();
    match waits.len() {
        0 => Condition::True,
        1 => waits.into_iter().next().unwrap_or(Condition::True),
        _ => Condition::And(waits.into_boxed_slice()),
    }
}
