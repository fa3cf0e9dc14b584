//! Building plans in code with the thesis's operators.
//!
//! Every operator adds places and transitions with ordinary PNP labels, so a
//! plan built here is interpreted exactly like one read from a file, and can be
//! written to PNML.

use crate::net::{NetError, PetriNet, PlaceNode, Position, TransitionNode};

use super::{AllowedAtoms, Plan, PlanError};

/// A place added by a [`PlanBuilder`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PlaceRef(usize);

/// A transition added by a [`PlanBuilder`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TransitionRef(usize);

/// The places of an ordinary action (or sub-plan call): its execution place and
/// the place reached when it ends.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ActionNet {
    /// The action's name.
    pub name: String,
    /// `name.exec`.
    pub exec: PlaceRef,
    /// The output place (after `name.end`).
    pub done: PlaceRef,
    /// The start transition.
    pub start: TransitionRef,
}

/// The places of a sensing action: one output place per outcome.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SensingNet {
    /// `name.exec`.
    pub exec: PlaceRef,
    /// One place per outcome, in the order the outcomes were given.
    pub outcomes: Vec<PlaceRef>,
}

/// A two-place sub-net that tracks whether an atom holds (thesis Figure 5.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tracker {
    /// Marked while the atom holds.
    pub holds: PlaceRef,
    /// Marked while it does not (initially marked).
    pub not_holds: PlaceRef,
}

/// Builds a plan operator by operator.
#[derive(Debug, Clone)]
pub struct PlanBuilder {
    name: String,
    places: Vec<PlaceNode>,
    transitions: Vec<TransitionNode>,
    arcs: Vec<(String, String, String, u8)>,
}

impl PlanBuilder {
    /// An empty plan called `name`.
    pub fn new(name: impl Into<String>) -> Self {
        PlanBuilder {
            name: name.into(),
            places: Vec::new(),
            transitions: Vec::new(),
            arcs: Vec::new(),
        }
    }

    /// A plain place (connector, memory or initial place) with `label`.
    pub fn place(&mut self, label: impl Into<String>) -> PlaceRef {
        let id = format!("p{}", self.places.len() + 1);
        self.places.push(PlaceNode {
            id,
            label: label.into(),
            initial: 0,
            position: None,
        });
        PlaceRef(self.places.len() - 1)
    }

    /// A place holding one token initially.
    pub fn initial_place(&mut self, label: impl Into<String>) -> PlaceRef {
        let p = self.place(label);
        self.set_tokens(p, 1);
        p
    }

    /// A place marking the goal (`goal`: the plan ends when it holds one token).
    pub fn goal_place(&mut self) -> PlaceRef {
        self.place("goal")
    }

    /// A memory place: no action, its tokens record choices or count passes (thesis 5.5).
    pub fn memory_place(&mut self, label: impl Into<String>) -> PlaceRef {
        self.place(label)
    }

    /// Sets the initial tokens of `p`.
    pub fn set_tokens(&mut self, p: PlaceRef, tokens: u8) {
        self.places[p.0].initial = tokens;
    }

    /// A transition with `label` and weighted input and output places.
    pub fn transition(
        &mut self,
        label: impl Into<String>,
        inputs: &[(PlaceRef, u8)],
        outputs: &[(PlaceRef, u8)],
    ) -> TransitionRef {
        let id = format!("t{}", self.transitions.len() + 1);
        self.transitions.push(TransitionNode {
            id,
            label: label.into(),
            position: None,
        });
        let t = TransitionRef(self.transitions.len() - 1);
        for &(p, w) in inputs {
            self.consume(t, p, w);
        }
        for &(p, w) in outputs {
            self.produce(t, p, w);
        }
        t
    }

    /// Adds an arc from `p` into `t` with weight `w`.
    pub(crate) fn consume(&mut self, t: TransitionRef, p: PlaceRef, w: u8) {
        let id = format!("a{}", self.arcs.len() + 1);
        self.arcs
            .push((id, self.places[p.0].id.clone(), self.transitions[t.0].id.clone(), w));
    }

    /// Adds an arc from `t` into `p` with weight `w` (e.g. a memory token).
    pub fn produce(&mut self, t: TransitionRef, p: PlaceRef, w: u8) {
        let id = format!("a{}", self.arcs.len() + 1);
        self.arcs
            .push((id, self.transitions[t.0].id.clone(), self.places[p.0].id.clone(), w));
    }

    /// Ordinary action `name` started from `from`; ends (waiting for `name.finished`) into a new place.
    pub fn action(&mut self, from: PlaceRef, name: &str) -> ActionNet {
        let done = self.place("");
        self.action_into(from, name, done)
    }

    /// Ordinary action `name` from `from` ending into `done` (sequence by place merging).
    pub fn action_into(&mut self, from: PlaceRef, name: &str, done: PlaceRef) -> ActionNet {
        self.action_with_start(from, name, format!("{name}.start"), done)
    }

    /// Action `name` from `from` into `done` whose start also needs `guard` (guard syntax).
    pub(crate) fn guarded_action_into(&mut self, from: PlaceRef, name: &str, guard: &str, done: PlaceRef) -> ActionNet {
        self.action_with_start(from, name, format!("{name}.start [{guard}]"), done)
    }

    /// Start transition `start_label` from `from`, execution place, end into `done`.
    fn action_with_start(&mut self, from: PlaceRef, name: &str, start_label: String, done: PlaceRef) -> ActionNet {
        let exec = self.place(format!("{name}.exec"));
        let start = self.transition(start_label, &[(from, 1)], &[(exec, 1)]);
        self.transition(format!("{name}.end"), &[(exec, 1)], &[(done, 1)]);
        ActionNet {
            name: name.to_string(),
            exec,
            done,
            start,
        }
    }

    /// A call of sub-plan `name`: structurally an action whose executable is a plan.
    pub fn call(&mut self, from: PlaceRef, name: &str) -> ActionNet {
        self.action(from, name)
    }

    /// Sensing action `name`: it ends into the outcome whose condition holds
    /// (conditions in the guard syntax, e.g. `not ballSeen`).
    pub fn sensing(&mut self, from: PlaceRef, name: &str, outcomes: &[&str]) -> SensingNet {
        let exec = self.place(format!("{name}.exec"));
        self.transition(format!("{name}.start"), &[(from, 1)], &[(exec, 1)]);
        let outcomes = outcomes
            .iter()
            .map(|cond| {
                let out = self.place("");
                self.transition(format!("{name}.end [{cond}]"), &[(exec, 1)], &[(out, 1)]);
                out
            })
            .collect();
        SensingNet { exec, outcomes }
    }

    /// Fork: one transition giving a token to each of `n` new places.
    pub fn fork(&mut self, from: PlaceRef, n: usize) -> Vec<PlaceRef> {
        let outs: Vec<PlaceRef> = (0..n).map(|_| self.place("")).collect();
        let arcs: Vec<(PlaceRef, u8)> = outs.iter().map(|&p| (p, 1)).collect();
        self.transition("fork", &[(from, 1)], &arcs);
        outs
    }

    /// Join: one transition waiting for a token in each of `inputs`.
    pub fn join(&mut self, inputs: &[PlaceRef]) -> PlaceRef {
        let out = self.place("");
        let arcs: Vec<(PlaceRef, u8)> = inputs.iter().map(|&p| (p, 1)).collect();
        self.transition("join", &arcs, &[(out, 1)]);
        out
    }

    /// Interrupt: leaves the execution of `action` for `to` when `condition`
    /// (guard syntax) holds.
    pub fn interrupt(&mut self, action: &ActionNet, condition: &str, to: PlaceRef) -> TransitionRef {
        let label = format!("{}.interrupt [{condition}]", action.name);
        self.transition(label, &[(action.exec, 1)], &[(to, 1)])
    }

    /// Non-deterministic choice: `n` unguarded conflicting transitions from `from`.
    pub fn choice(&mut self, from: PlaceRef, n: usize) -> Vec<PlaceRef> {
        (0..n)
            .map(|i| {
                let out = self.place("");
                self.transition(format!("choice{}", i + 1), &[(from, 1)], &[(out, 1)]);
                out
            })
            .collect()
    }

    /// A choice among actions (thesis Figure 5.1): each start transition is an option.
    pub fn choice_of_actions(&mut self, from: PlaceRef, names: &[&str]) -> Vec<ActionNet> {
        names.iter().map(|n| self.action(from, n)).collect()
    }

    /// An environment-tracking sub-net for `atom` (thesis Figure 5.9).
    pub fn tracker(&mut self, atom: &str) -> Tracker {
        let holds = self.place(atom);
        let not_holds = self.initial_place(format!("not_{atom}"));
        self.transition(format!("[{atom}]"), &[(not_holds, 1)], &[(holds, 1)]);
        self.transition(format!("[not {atom}]"), &[(holds, 1)], &[(not_holds, 1)]);
        Tracker { holds, not_holds }
    }

    /// Gives every node a drawing position: layers by distance from the
    /// initially marked places, left to right, so an editor shows the flow.
    fn layout(&mut self) {
        let node_count = self.places.len() + self.transitions.len();
        let index_of = |id: &str, places: &[PlaceNode], transitions: &[TransitionNode]| {
            places
                .iter()
                .position(|p| p.id == id)
                .or_else(|| transitions.iter().position(|t| t.id == id).map(|i| places.len() + i))
        };
        let mut successors = vec![Vec::new(); node_count];
        for (_, s, t, _) in &self.arcs {
            if let (Some(a), Some(b)) = (
                index_of(s, &self.places, &self.transitions),
                index_of(t, &self.places, &self.transitions),
            ) {
                successors[a].push(b);
            }
        }
        let mut layer = vec![usize::MAX; node_count];
        let mut queue = std::collections::VecDeque::new();
        for (i, p) in self.places.iter().enumerate() {
            if p.initial > 0 {
                layer[i] = 0;
                queue.push_back(i);
            }
        }
        let mut next_root = 0;
        loop {
            while let Some(n) = queue.pop_front() {
                for &m in &successors[n] {
                    if layer[m] == usize::MAX {
                        layer[m] = layer[n] + 1;
                        queue.push_back(m);
                    }
                }
            }
            match (next_root..node_count).find(|&i| layer[i] == usize::MAX) {
                Some(i) => {
                    next_root = i;
                    layer[i] = layer.iter().filter(|&&l| l != usize::MAX).max().map_or(0, |m| m + 1);
                    queue.push_back(i);
                }
                None => break,
            }
        }
        let mut rows: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
        for (i, &l) in layer.iter().enumerate() {
            let row = rows.entry(l).or_insert(0);
            let position = Some(Position {
                x: 60.0 + 90.0 * l as f64,
                y: 60.0 + 80.0 * *row as f64,
            });
            *row += 1;
            if i < self.places.len() {
                self.places[i].position = position;
            } else {
                self.transitions[i - self.places.len()].position = position;
            }
        }
    }

    /// The net as built, laid out for drawing.
    pub fn build_net(mut self) -> Result<PetriNet, NetError> {
        self.layout();
        let arcs: Vec<(&str, &str, &str, u8)> = self
            .arcs
            .iter()
            .map(|(a, s, t, w)| (a.as_str(), s.as_str(), t.as_str(), *w))
            .collect();
        PetriNet::new(self.name, self.places, self.transitions, &arcs)
    }

    /// The plan as built, atoms resolved against `vocabulary`.
    pub fn build(self, vocabulary: AllowedAtoms<'_>) -> Result<Plan, PlanError> {
        Plan::from_net(self.build_net()?, vocabulary)
    }
}
