//! Petri Net Plans generated from planners' plans, as PNPgen (the PNP
//! library's generator) does, with the learner in mind.
//!
//! - [`linear`](crate::generate::linear): a linear plan, from an IPC plan file or PNPgen's `a|30; b`
//!   line, to a sequence ([`GeneratedPlan::sequence`](crate::generate::GeneratedPlan::sequence));
//! - [`merge`](crate::generate::merge): the k best plans of a planner merged by their common prefixes
//!   into one plan whose choice points are where they differ;
//! - [`conditional`](crate::generate::conditional): PNPgen's conditional plan (states, actions, edges
//!   labelled by sensing outcomes) to a plan with sensing;
//! - [`rules`](crate::generate::rules): PNPgen's execution rules, `*if* COND *during* ACTION *do*
//!   RECOVERY`, added as interrupts with their recovery branches.
//!
//! Every plan is made with [`PlanBuilder`](crate::plan::PlanBuilder)'s operators, so it reads, checks,
//! saves (JARP or standard PNML) and runs as a drawn one; the builder's
//! layered layout places its nodes.

pub mod conditional;
mod error;
pub mod linear;
pub mod merge;
pub mod rules;

pub use error::GenerateError;
pub use linear::PlanStep;

use crate::net::{NetError, PetriNet};
use crate::plan::{AllowedAtoms, PlaceRef, Plan, PlanBuilder, PlanError};

/// Where one occurrence of an action sits in a generated plan: what an
/// execution rule attaches to.
#[derive(Debug, Clone, PartialEq, Eq)]
struct ActionSite {
    /// The action's name.
    name: String,
    /// The place its start transition leaves (for a timed action, the place
    /// before the fork into the action and its wait).
    before: PlaceRef,
    /// Its execution place.
    exec: PlaceRef,
    /// The place after it (for a timed action, after the action or its wait).
    after: PlaceRef,
    /// A timed action's `wait_<seconds>` execution place.
    wait_exec: Option<PlaceRef>,
}

/// A plan being generated: the builder, its initial place, its goal and fail
/// places, and every action of the plan proper (not of recovery branches).
#[derive(Debug, Clone)]
pub struct GeneratedPlan {
    builder: PlanBuilder,
    init: PlaceRef,
    goal: PlaceRef,
    fail: Option<PlaceRef>,
    sites: Vec<ActionSite>,
}

impl GeneratedPlan {
    /// An empty plan: its initial place `init` and its goal place.
    fn new(name: &str) -> Self {
        let mut builder = PlanBuilder::new(name);
        let init = builder.initial_place("init");
        let goal = builder.goal_place();
        GeneratedPlan {
            builder,
            init,
            goal,
            fail: None,
            sites: Vec::new(),
        }
    }

    /// A linear plan as a sequence from `init` to `goal` (an empty plan: one
    /// transition `finish`).
    pub fn sequence(name: &str, steps: &[PlanStep]) -> Self {
        let mut plan = GeneratedPlan::new(name);
        let goal = plan.goal;
        let init = plan.init;
        plan.chain(init, steps, goal, true);
        plan
    }

    /// The names of the plan's actions (of the plan proper, not of recovery
    /// branches), each once, in order of appearance.
    pub fn actions(&self) -> Vec<&str> {
        let mut names: Vec<&str> = Vec::new();
        for s in &self.sites {
            if !names.contains(&s.name.as_str()) {
                names.push(&s.name);
            }
        }
        names
    }

    /// The net, laid out for drawing.
    pub fn into_net(self) -> Result<PetriNet, NetError> {
        self.builder.build_net()
    }

    /// The plan, atoms resolved against `vocabulary`.
    pub fn into_plan(self, vocabulary: AllowedAtoms<'_>) -> Result<Plan, PlanError> {
        self.builder.build(vocabulary)
    }

    /// The shared fail place, made on first use.
    fn fail_place(&mut self) -> PlaceRef {
        match self.fail {
            Some(p) => p,
            None => {
                let p = self.builder.place("fail");
                self.fail = Some(p);
                p
            }
        }
    }

    /// `steps` one after another from `from` into `into` (a transition
    /// `finish` when there are none); `record`: whether they are the plan's
    /// own actions, which rules attach to.
    fn chain(&mut self, from: PlaceRef, steps: &[PlanStep], into: PlaceRef, record: bool) {
        let Some((last, first)) = steps.split_last() else {
            self.builder.transition("finish", &[(from, 1)], &[(into, 1)]);
            return;
        };
        let mut at = from;
        for step in first {
            at = self.step(at, step, None, record);
        }
        self.step(at, last, Some(into), record);
    }

    /// One action from `from`, into `into` or a new place; returns the place after it.
    fn step(&mut self, from: PlaceRef, step: &PlanStep, into: Option<PlaceRef>, record: bool) -> PlaceRef {
        let after = into.unwrap_or_else(|| self.builder.place(""));
        let site = match step.timeout {
            None => {
                let net = self.builder.action_into(from, &step.action, after);
                ActionSite {
                    name: step.action.clone(),
                    before: from,
                    exec: net.exec,
                    after,
                    wait_exec: None,
                }
            }
            Some(seconds) => self.timed(from, &step.action, seconds, after),
        };
        if record {
            self.sites.push(site);
        }
        after
    }

    /// PNPgen's timed action: a fork into the action and `wait_<seconds>`;
    /// whichever ends first interrupts the other, both into `after`. Where
    /// both end in the same step, a join takes the two (PNPgen leaves that
    /// marking dead).
    fn timed(&mut self, from: PlaceRef, name: &str, seconds: u32, after: PlaceRef) -> ActionSite {
        let b = &mut self.builder;
        let wait = format!("wait_{seconds}");
        let branches = b.fork(from, 2);
        let action = b.action(branches[0], name);
        let waiting = b.action(branches[1], &wait);
        b.transition(
            format!("{wait}.interrupt []"),
            &[(waiting.exec, 1), (action.done, 1)],
            &[(after, 1)],
        );
        b.transition(
            format!("{name}.interrupt []"),
            &[(action.exec, 1), (waiting.done, 1)],
            &[(after, 1)],
        );
        b.transition("join", &[(action.done, 1), (waiting.done, 1)], &[(after, 1)]);
        ActionSite {
            name: name.to_string(),
            before: from,
            exec: action.exec,
            after,
            wait_exec: Some(waiting.exec),
        }
    }
}
