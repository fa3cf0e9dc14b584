//! The construction of thesis section 3.2.1: a plan schema becomes a Timed
//! Non-Markovian Decision Process whose choice states a learner controls.
//!
//! For every plan state `s` and event `e` of its outgoing edges, the conditions
//! Phi(s, e) of those edges overlap: the condition constituents C_cnd(s, e) are
//! the sets of conditions that hold together (and exactly those) when `e`
//! happens. Each constituent becomes a state <s, e, C> of S_c; the event leads
//! from the action state `s` to it (a time-extended transition carrying the
//! reward), or back to `s` when no condition holds. From <s, e, C> a
//! deterministic, zero-time plan-action leads to the target of every edge whose
//! condition is in C: a constituent with more than one plan-action is a choice
//! state.
//!
//! Constituents no knowledge base can produce (`{BallSeen, not BallSeen}`,
//! "none holds" beside an unconditioned edge) are left out: the thesis's
//! power set would give them states that can never be entered. Atoms are taken
//! as independent, except that the event's own atom holds when it happens.
//!
//! Learners value markings (afterstates), so each machine's process is also a
//! Petri net with one place per process state, and one more place per option
//! of each choice state: the action state as entered by that plan-action from
//! that choice state. Its value is the thesis's Q(o, a) of the option; it
//! behaves exactly as the action state it enters.

use std::any::Any;
use std::sync::Arc;

use super::SchemaError;
use super::model::{Machine, Schema, StateKind, internal_action};
use crate::condition::{AtomRef, AtomTable, Condition, Expr};
use crate::net::{NetError, PetriNet, PlaceNode, TransitionNode};
use crate::plan::{AllowedAtoms, InternalKind, Plan, PlanError, PlanOrigin};

/// Most distinct conditions on the edges sharing one plan state and event.
pub const MAX_CONDITIONS: usize = 12;
/// Most distinct atoms in those conditions.
pub const MAX_ATOMS: usize = 16;

/// Index of a state of a machine's process; it is also the place of that state in [`MachineProcess::plan`].
pub type DecisionStateId = usize;

/// A state of the constructed process (S_sp = S u S_c, plus the afterstates of choices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DecisionState {
    /// An action state: plan state `state` (index in the machine), its actions running.
    Action {
        /// The plan state.
        state: usize,
    },
    /// A constituent state <s, e, C> of S_c.
    Constituent {
        /// The plan state s.
        state: usize,
        /// The event group of s (index into [`MachineProcess::groups`]).
        group: usize,
        /// C: bit i set when condition i of the group holds.
        conditions: u32,
    },
    /// Action state `target` as entered by its plan-action from choice state
    /// `choice`: the option a learner values.
    Afterstate {
        /// The constituent state where the choice was made.
        choice: DecisionStateId,
        /// The plan state entered.
        target: usize,
    },
}

/// A deterministic, zero-time plan-action of a constituent state.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlanAction {
    /// The plan state it enters.
    pub target: usize,
    /// The process state it enters: the target's action state, or the
    /// afterstate of this option when the constituent is a choice state.
    pub(crate) enters: DecisionStateId,
}

/// One constituent <s, e, C> of an event group.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Constituent {
    /// C: bit i set when condition i of the group holds, the others not.
    pub conditions: u32,
    /// Its process state.
    pub state: DecisionStateId,
    /// Its plan-actions, in edge order; more than one makes it a choice state.
    pub plan_actions: Vec<PlanAction>,
}

/// The edges of one plan state that share one event.
#[derive(Debug, Clone)]
pub struct EventGroup {
    /// The event (`None`: the empty event).
    pub event: Option<String>,
    /// Phi(s, e): the distinct conditions of those edges, in order of appearance.
    pub conditions: Vec<Expr>,
    /// C_cnd(s, e), by ascending bit mask.
    pub constituents: Vec<Constituent>,
    /// Whether the event may happen with no condition holding: a loop on s.
    pub loops: bool,
    /// The line of the first edge of the group, if from a file.
    pub line: Option<usize>,
    pub(crate) compiled_event: Option<Condition>,
    pub(crate) compiled_conditions: Vec<Condition>,
}

impl EventGroup {
    /// The constituent whose conditions are exactly `mask`.
    pub fn constituent(&self, mask: u32) -> Option<&Constituent> {
        self.constituents
            .binary_search_by_key(&mask, |c| c.conditions)
            .ok()
            .map(|i| &self.constituents[i])
    }
}

/// An action of a machine: primitive (from the domain) or another machine of the schema.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ProcessAction {
    /// The name as written.
    pub name: String,
    /// The machine it calls, if it is one.
    pub machine: Option<usize>,
}

/// A transition of the process, for display and tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProcessTransition {
    /// Event of group `group` of plan state `state` leading to constituent state `to`.
    Event {
        /// The plan state.
        state: usize,
        /// Its event group.
        group: usize,
        /// The constituent state.
        to: DecisionStateId,
    },
    /// The event happened and no condition holds: back to the plan state.
    Loop {
        /// The plan state.
        state: usize,
        /// Its event group.
        group: usize,
    },
    /// A plan-action of constituent state `from`.
    PlanAction {
        /// The constituent state.
        from: DecisionStateId,
        /// The action.
        action: PlanAction,
    },
}

/// Counts of a machine's process.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Counts {
    /// |S|: action states (the plan states).
    pub action_states: usize,
    /// |S_c|: constituent states.
    pub constituent_states: usize,
    /// Event transitions into constituent states.
    pub events: usize,
    /// Loops ("none holds").
    pub loops: usize,
    /// Plan-actions.
    pub plan_actions: usize,
    /// Constituent states with more than one plan-action.
    pub choice_states: usize,
    /// Options of the choice states (afterstates valued by learners).
    pub options: usize,
}

/// One machine's process.
#[derive(Debug, Clone)]
pub struct MachineProcess {
    machine: Machine,
    pub(crate) actions: Vec<ProcessAction>,
    pub(crate) state_actions: Vec<Vec<usize>>,
    pub(crate) groups: Vec<Vec<EventGroup>>,
    states: Vec<DecisionState>,
    pub(crate) internal: Vec<(usize, InternalKind)>,
    plan: Plan,
}

impl MachineProcess {
    /// The schema machine it was built from.
    pub fn machine(&self) -> &Machine {
        &self.machine
    }

    /// Its name.
    pub fn name(&self) -> &str {
        self.machine.name()
    }

    /// Its actions, each once.
    pub fn actions(&self) -> &[ProcessAction] {
        &self.actions
    }

    /// The actions (indices into [`Self::actions`]) of plan state `state`.
    pub fn state_actions(&self, state: usize) -> &[usize] {
        &self.state_actions[state]
    }

    /// The event groups of plan state `state`, in the order events are sensed:
    /// named events in order of first appearance, the empty event last.
    pub fn groups(&self, state: usize) -> &[EventGroup] {
        &self.groups[state]
    }

    /// Every process state; the index is its id. Action states come first, in
    /// plan state order (so the action state of plan state `s` is `s`).
    pub fn states(&self) -> &[DecisionState] {
        &self.states
    }

    /// The readable name of process state `id` (its place label).
    pub fn label(&self, id: DecisionStateId) -> &str {
        &self.plan.net().places()[id].label
    }

    /// The Petri net of the process: one place per process state.
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// Every transition of the process.
    pub fn transitions(&self) -> Vec<ProcessTransition> {
        let mut out = Vec::new();
        for (s, groups) in self.groups.iter().enumerate() {
            for (g, group) in groups.iter().enumerate() {
                for c in &group.constituents {
                    out.push(ProcessTransition::Event {
                        state: s,
                        group: g,
                        to: c.state,
                    });
                }
                if group.loops {
                    out.push(ProcessTransition::Loop { state: s, group: g });
                }
            }
        }
        for group in self.groups.iter().flatten() {
            for c in &group.constituents {
                for &action in &c.plan_actions {
                    out.push(ProcessTransition::PlanAction { from: c.state, action });
                }
            }
        }
        out
    }

    /// The constituent states with more than one plan-action.
    pub fn choice_states(&self) -> impl Iterator<Item = &Constituent> {
        self.groups
            .iter()
            .flatten()
            .flat_map(|g| &g.constituents)
            .filter(|c| c.plan_actions.len() > 1)
    }

    /// Its counts.
    pub fn counts(&self) -> Counts {
        let mut c = Counts {
            action_states: self.machine.states().len(),
            ..Counts::default()
        };
        for group in self.groups.iter().flatten() {
            c.constituent_states += group.constituents.len();
            c.events += group.constituents.len();
            c.loops += usize::from(group.loops);
            for k in &group.constituents {
                c.plan_actions += k.plan_actions.len();
                if k.plan_actions.len() > 1 {
                    c.choice_states += 1;
                    c.options += k.plan_actions.len();
                }
            }
        }
        c
    }

    /// Whether plan state `state` is final, and how.
    pub(crate) fn kind(&self, state: usize) -> StateKind {
        self.machine.states()[state].kind
    }
}

/// The controllable process a whole schema becomes (thesis 3.2.1, a Timed
/// Non-Markovian Decision Process): one per machine, the root first.
#[derive(Debug, Clone)]
pub struct DecisionProcess {
    machines: Vec<MachineProcess>,
    atoms: AtomTable,
}

impl DecisionProcess {
    /// Constructs the process of every machine of `schema`, resolving the
    /// atoms of events and conditions against `vocabulary`.
    pub fn new(schema: &Schema, vocabulary: AllowedAtoms<'_>) -> Result<Self, SchemaError> {
        let mut atoms = match vocabulary {
            AllowedAtoms::Open => AtomTable::new(),
            AllowedAtoms::Closed(t) => t.clone(),
        };
        let machines = schema
            .machines()
            .iter()
            .map(|m| build_machine(schema, m, vocabulary, &mut atoms))
            .collect::<Result<_, _>>()?;
        Ok(DecisionProcess { machines, atoms })
    }

    /// Every machine's process; index i is the machine's plan key.
    pub fn machines(&self) -> &[MachineProcess] {
        &self.machines
    }

    /// The atoms of the knowledge base that events and conditions ask.
    pub fn atoms(&self) -> &AtomTable {
        &self.atoms
    }

    /// The root machine's plan, carrying this process so the executor runs it
    /// with the schema's semantics.
    pub fn into_plan(self) -> Plan {
        let root = self.machines[0].plan.clone();
        root.with_origin(Arc::new(self))
    }
}

impl PlanOrigin for DecisionProcess {
    fn called_plans(&self) -> Vec<&Plan> {
        self.machines.iter().skip(1).map(MachineProcess::plan).collect()
    }
}

impl Plan {
    /// The process of the plan schema this plan was constructed from
    /// ([`DecisionProcess::into_plan`]), if any; the executor then follows the
    /// schema's semantics (thesis 3.1.1).
    pub fn schema_process(&self) -> Option<Arc<DecisionProcess>> {
        let origin: Arc<dyn PlanOrigin> = Arc::clone(self.origin()?);
        let origin: Arc<dyn Any + Send + Sync> = origin;
        origin.downcast().ok()
    }
}

/// C_cnd(s, e) of thesis section 3.2.1, restricted to what can happen: the
/// sets of `conditions` that hold together (and no other) for some truth of
/// their atoms, with `event`'s atom true. Returns the sets as bit masks (bit i:
/// condition i), ascending, without the empty set, and whether the empty set
/// ("none holds": the loop) can happen.
pub fn condition_constituents(conditions: &[Expr], event: Option<&str>) -> Result<(Vec<u32>, bool), String> {
    if conditions.len() > MAX_CONDITIONS {
        return Err(format!(
            "{} distinct conditions on edges with one event from one state (at most {MAX_CONDITIONS}: their constituents are 2^k)",
            conditions.len()
        ));
    }
    let mut names: Vec<&str> = Vec::new();
    for a in conditions.iter().flat_map(Expr::atoms) {
        if Some(a) != event && !names.contains(&a) {
            names.push(a);
        }
    }
    if names.len() > MAX_ATOMS {
        return Err(format!(
            "{} distinct atoms in the conditions of edges with one event from one state (at most {MAX_ATOMS})",
            names.len()
        ));
    }
    let mut realized = vec![false; 1 << conditions.len()];
    for assignment in 0u32..(1 << names.len()) {
        let truth = |atom: &str| {
            Some(atom) == event
                || names
                    .iter()
                    .position(|n| *n == atom)
                    .is_some_and(|i| assignment >> i & 1 == 1)
        };
        let mask = conditions
            .iter()
            .enumerate()
            .fold(0u32, |m, (i, c)| if eval(c, &truth) { m | 1 << i } else { m });
        realized[mask as usize] = true;
    }
    let masks = (1..realized.len() as u32).filter(|&m| realized[m as usize]).collect();
    Ok((masks, realized[0]))
}

fn eval(expr: &Expr, truth: &impl Fn(&str) -> bool) -> bool {
    match expr {
        Expr::True => true,
        Expr::Atom(a) => truth(a),
        Expr::Not(e) => !eval(e, truth),
        Expr::And(es) => es.iter().all(|e| eval(e, truth)),
        Expr::Or(es) => es.iter().any(|e| eval(e, truth)),
    }
}

/// How a condition is written in a state's name: `true` for the empty guard.
pub(crate) fn condition_text(c: &Expr) -> String {
    match c {
        Expr::True => "true".to_string(),
        other => other.to_guard_text(),
    }
}

fn build_machine(
    schema: &Schema,
    machine: &Machine,
    vocabulary: AllowedAtoms<'_>,
    atoms: &mut AtomTable,
) -> Result<MachineProcess, SchemaError> {
    let actions: Vec<ProcessAction> = machine
        .actions()
        .into_iter()
        .map(|name| ProcessAction {
            name: name.to_string(),
            machine: schema.machine_named(name),
        })
        .collect();
    let state_actions: Vec<Vec<usize>> = machine
        .states()
        .iter()
        .map(|s| {
            s.actions
                .iter()
                .filter_map(|a| actions.iter().position(|x| &x.name == a))
                .collect()
        })
        .collect();
    let mut internal: Vec<(usize, InternalKind)> = Vec::new();
    let mut resolve = |atom: &str, line: Option<usize>| -> Result<AtomRef, SchemaError> {
        if let Some((action, cond)) = internal_action(atom) {
            let a = actions.iter().position(|x| x.name == action).ok_or_else(|| {
                SchemaError::new(line, "internal condition of an action the machine does not run", atom)
            })?;
            let kind = match cond {
                "finished" => InternalKind::Finished,
                "failed" => InternalKind::Failed,
                other => InternalKind::Declared(other.to_string()),
            };
            let index = internal
                .iter()
                .position(|(b, k)| *b == a && *k == kind)
                .unwrap_or_else(|| {
                    internal.push((a, kind));
                    internal.len() - 1
                });
            return Ok(AtomRef::Internal(index as u32));
        }
        match vocabulary {
            AllowedAtoms::Open => Ok(AtomRef::Fact(atoms.intern(atom))),
            AllowedAtoms::Closed(_) => atoms.get(atom).map(AtomRef::Fact).ok_or_else(|| {
                let known: Vec<&str> = atoms.names().collect();
                SchemaError::new(
                    line,
                    format!("unknown atom (the domain declares: {})", known.join(", ")),
                    atom,
                )
            }),
        }
    };

    let n = machine.states().len();
    let mut states: Vec<DecisionState> = (0..n).map(|state| DecisionState::Action { state }).collect();
    let mut groups: Vec<Vec<EventGroup>> = Vec::with_capacity(n);
    for s in 0..n {
        let outgoing: Vec<_> = machine.edges().iter().filter(|e| e.from == s).collect();
        let mut events: Vec<Option<&str>> = Vec::new();
        for e in &outgoing {
            let ev = e.event.as_deref();
            if ev.is_some() && !events.contains(&ev) {
                events.push(ev);
            }
        }
        if outgoing.iter().any(|e| e.event.is_none()) {
            events.push(None);
        }
        let mut state_groups = Vec::with_capacity(events.len());
        for event in events {
            let edges: Vec<_> = outgoing.iter().filter(|e| e.event.as_deref() == event).collect();
            let line = edges.first().and_then(|e| e.line);
            let mut conditions: Vec<Expr> = Vec::new();
            for e in &edges {
                if !conditions.contains(&e.condition) {
                    conditions.push(e.condition.clone());
                }
            }
            let (masks, loops) = condition_constituents(&conditions, event)
                .map_err(|m| SchemaError::new(line, m, event.unwrap_or("-")))?;
            let group_index = state_groups.len();
            let mut constituents = Vec::with_capacity(masks.len());
            for mask in masks {
                let id = states.len();
                states.push(DecisionState::Constituent {
                    state: s,
                    group: group_index,
                    conditions: mask,
                });
                let mut targets: Vec<usize> = Vec::new();
                for e in &edges {
                    let c = conditions.iter().position(|c| *c == e.condition).unwrap_or(0);
                    if mask >> c & 1 == 1 && !targets.contains(&e.to) {
                        targets.push(e.to);
                    }
                }
                constituents.push(Constituent {
                    conditions: mask,
                    state: id,
                    plan_actions: targets
                        .into_iter()
                        .map(|target| PlanAction { target, enters: target })
                        .collect(),
                });
            }
            let compiled_event = event.map(|e| resolve(e, line).map(Condition::Atom)).transpose()?;
            let compiled_conditions = conditions
                .iter()
                .map(|c| Condition::compile(c, &mut |a: &str| resolve(a, line)))
                .collect::<Result<_, _>>()?;
            state_groups.push(EventGroup {
                event: event.map(str::to_string),
                conditions,
                constituents,
                loops,
                line,
                compiled_event,
                compiled_conditions,
            });
        }
        groups.push(state_groups);
    }
    // The options of every choice state get their own afterstate.
    for group in groups.iter_mut().flatten() {
        for c in &mut group.constituents {
            if c.plan_actions.len() > 1 {
                for action in &mut c.plan_actions {
                    action.enters = states.len();
                    states.push(DecisionState::Afterstate {
                        choice: c.state,
                        target: action.target,
                    });
                }
            }
        }
    }
    let net = process_net(machine, &groups, &states).map_err(|e| {
        SchemaError::new(
            machine.line(),
            format!("cannot build the process net: {e}"),
            machine.name(),
        )
    })?;
    let plan = Plan::from_net(net, vocabulary).map_err(|e: PlanError| {
        SchemaError::new(
            machine.line(),
            format!("cannot build the process net: {e}"),
            machine.name(),
        )
    })?;
    Ok(MachineProcess {
        machine: machine.clone(),
        actions,
        state_actions,
        groups,
        states,
        internal,
        plan,
    })
}

/// The readable name of a process state, bracketed so that plan label parsing reads nothing into it.
fn state_label(machine: &Machine, groups: &[Vec<EventGroup>], states: &[DecisionState], id: DecisionStateId) -> String {
    let constituent = |state: usize, group: usize, mask: u32| {
        let g = &groups[state][group];
        let conds: Vec<String> = g
            .conditions
            .iter()
            .enumerate()
            .filter(|(i, _)| mask >> i & 1 == 1)
            .map(|(_, c)| condition_text(c))
            .collect();
        format!(
            "{}, {}, {{{}}}",
            machine.states()[state].name,
            g.event.as_deref().unwrap_or("-"),
            conds.join(", ")
        )
    };
    match states[id] {
        DecisionState::Action { state } => format!("[{}]", machine.states()[state].name),
        DecisionState::Constituent {
            state,
            group,
            conditions,
        } => format!("[{}]", constituent(state, group, conditions)),
        DecisionState::Afterstate { choice, target } => match states[choice] {
            DecisionState::Constituent {
                state,
                group,
                conditions,
            } => format!(
                "[{}: {}]",
                constituent(state, group, conditions),
                machine.states()[target].name
            ),
            _ => format!("[{}]", machine.states()[target].name),
        },
    }
}

/// The process as a state-machine net: a place per process state, a transition
/// per event, loop and plan-action (events and loops also leave every afterstate
/// of a plan state, which behaves as that plan state).
fn process_net(machine: &Machine, groups: &[Vec<EventGroup>], states: &[DecisionState]) -> Result<PetriNet, NetError> {
    let places: Vec<PlaceNode> = (0..states.len())
        .map(|id| PlaceNode {
            id: format!("p{}", id + 1),
            label: state_label(machine, groups, states, id),
            initial: u8::from(id == machine.initial()),
            position: None,
        })
        .collect();
    let mut transitions: Vec<TransitionNode> = Vec::new();
    let mut arcs: Vec<(String, String, String)> = Vec::new();
    let mut connect = |from: DecisionStateId, to: DecisionStateId| {
        let t = format!("t{}", transitions.len() + 1);
        transitions.push(TransitionNode {
            id: t.clone(),
            label: String::new(),
            position: None,
        });
        arcs.push((format!("p{}", from + 1), t.clone(), String::new()));
        arcs.push((t, format!("p{}", to + 1), String::new()));
    };
    for (id, st) in states.iter().enumerate() {
        let s = match *st {
            DecisionState::Action { state } => state,
            DecisionState::Afterstate { target, .. } => target,
            DecisionState::Constituent { .. } => continue,
        };
        for group in &groups[s] {
            for c in &group.constituents {
                connect(id, c.state);
            }
            if group.loops {
                connect(id, id);
            }
        }
    }
    for c in groups.iter().flatten().flat_map(|g| &g.constituents) {
        for a in &c.plan_actions {
            connect(c.state, a.enters);
        }
    }
    let arcs: Vec<(String, String, String)> = arcs
        .into_iter()
        .enumerate()
        .map(|(i, (s, t, _))| (format!("a{}", i + 1), s, t))
        .collect();
    let specs: Vec<(&str, &str, &str, u8)> = arcs
        .iter()
        .map(|(a, s, t)| (a.as_str(), s.as_str(), t.as_str(), 1))
        .collect();
    PetriNet::new(machine.name(), places, transitions, &specs)
}
