//! One running plan: its marking, its actions, and its running sub-plans
//! (a node of the activation tree).

use std::sync::Arc;

use super::activation::{Activation, PendingReward, Status};
use super::bits::BitSet;
use super::bound::{Binder, BoundActions, Executable};
use super::conflict::{self, ConflictScratch};
use super::registry::{Entry, Registry};
use super::{Chooser, ExecError, PlanKey, World};
use crate::condition::AtomRef;
use crate::net::{Marking, PlaceId, TransitionId};
use crate::plan::{ActionId, Call, Function, Plan};

/// Most alternative firing sets one conflict may offer.
pub(crate) const MAX_OPTIONS: usize = 4096;

/// A plan being executed.
pub(crate) struct PlanInstance<W> {
    plan: Arc<Plan>,
    key: PlanKey,
    marking: Marking,
    /// Per transition: input arcs whose place lacks tokens.
    missing: Vec<u16>,
    /// Transitions with enough tokens (guards aside).
    enabled: BitSet,
    actions: BoundActions<W, PlanInstance<W>>,
    /// Per action: how many of its execution places are marked.
    marked_exec: Vec<u16>,
    /// Actions with a marked execution place.
    active: BitSet,
    status: Status,
    /// Started (or resumed) during the current step: its transitions wait.
    fresh: bool,
    pending: PendingReward,
    executable: Vec<TransitionId>,
    chosen: Vec<TransitionId>,
    options: Vec<Marking>,
    conflicts: ConflictScratch,
}

impl<W: World> PlanInstance<W> {
    /// Instantiates `plan` and, recursively, its actions and sub-plans.
    pub(crate) fn new(
        plan: Arc<Plan>,
        key: PlanKey,
        registry: &Registry<W>,
        callers: &mut Vec<String>,
    ) -> Result<Self, ExecError> {
        if callers.iter().any(|c| c == plan.name()) {
            return Err(ExecError::RecursiveSubPlan {
                plan: plan.name().to_string(),
            });
        }
        callers.push(plan.name().to_string());
        let mut binder = Binder::with_capacity(plan.actions().len());
        for info in plan.actions() {
            match registry.resolve(&info.name) {
                Some(Entry::Primitive { declared, factory }) => binder.primitive(factory(&info.name), declared),
                Some(Entry::SubPlan(sub_key, sub)) => {
                    binder.sub(PlanInstance::new(Arc::clone(sub), sub_key, registry, callers)?);
                }
                None => return Err(registry.unknown_action(plan.name(), &info.name)),
            }
        }
        callers.pop();
        let actions = binder.bind(
            plan.name(),
            |a| &plan.actions()[a].name,
            plan.internal_conditions().iter().map(|c| (c.action.index(), &c.kind)),
        )?;
        let transitions = plan.incidence().transition_count();
        let action_count = plan.actions().len();
        let mut instance = PlanInstance {
            marking: plan.initial_marking(),
            missing: vec![0; transitions],
            enabled: BitSet::new(transitions),
            actions,
            marked_exec: vec![0; action_count],
            active: BitSet::new(action_count),
            status: Status::Running,
            fresh: true,
            pending: PendingReward::default(),
            executable: Vec::new(),
            chosen: Vec::new(),
            options: Vec::new(),
            conflicts: ConflictScratch::default(),
            key,
            plan,
        };
        instance.rebuild();
        Ok(instance)
    }

    /// Recomputes the enabled and active sets from the marking.
    fn rebuild(&mut self) {
        let incidence = self.plan.incidence();
        self.enabled.clear();
        for t in incidence.transition_ids() {
            let missing = incidence
                .inputs(t)
                .iter()
                .filter(|a| self.marking.get(a.place) < a.weight)
                .count();
            self.missing[t.index()] = missing as u16;
            self.enabled.set(t.index(), missing == 0);
        }
        self.active.clear();
        self.marked_exec.iter_mut().for_each(|c| *c = 0);
        for (p, _) in self.marking.marked() {
            if let Some(a) = self.plan.exec_action(p) {
                self.marked_exec[a.index()] += 1;
                self.active.set(a.index(), true);
            }
        }
        self.status = self.status_of_marking();
    }

    fn status_of_marking(&self) -> Status {
        if self.plan.is_goal(&self.marking) {
            Status::Goal
        } else if self.plan.is_fail(&self.marking) {
            Status::Failed
        } else {
            Status::Running
        }
    }

    /// Applies `function` to every active executable of this plan, recursively
    /// (ending, interrupting or failing a plan does the same to its sub-tree).
    fn propagate(&mut self, world: &mut W, function: Function) {
        for a in self.active.iter() {
            match self.actions.get_mut(a) {
                Executable::Primitive(x) => match function {
                    Function::Interrupt => x.interrupt(world),
                    Function::Resume => x.resume(world),
                    _ => x.end(world),
                },
                Executable::Sub(p) => p.propagate(world, function),
            }
        }
        if function == Function::Resume {
            self.fresh = true;
        }
    }

    fn fire_executable<C: Chooser + ?Sized>(
        &mut self,
        world: &mut W,
        chooser: &mut C,
        executable: &[TransitionId],
    ) -> Result<(), ExecError> {
        let incidence = self.plan.incidence();
        let mut chosen = std::mem::take(&mut self.chosen);
        chosen.clear();
        if conflict::has_conflict(incidence, &self.marking, executable, &mut self.conflicts) {
            if !conflict::enumerate(incidence, &self.marking, executable, &mut self.conflicts, MAX_OPTIONS) {
                self.chosen = chosen;
                return Err(ExecError::TooManyOptions {
                    plan: self.plan.name().to_string(),
                    limit: MAX_OPTIONS,
                });
            }
            let count = self.conflicts.len();
            self.options.truncate(count);
            for i in 0..count {
                let set = self.conflicts.set(i);
                if i < self.options.len() {
                    self.options[i].clone_from(&self.marking);
                } else {
                    self.options.push(self.marking.clone());
                }
                let next = &mut self.options[i];
                for &t in self.conflicts.free.iter().chain(set) {
                    incidence.fire(next, t).map_err(|e| ExecError::TokenOverflow {
                        plan: self.plan.name().to_string(),
                        place: self.plan.net().place(PlaceId::new(e.place)).id.clone(),
                    })?;
                }
            }
            let index = chooser.choose(self.key, &self.marking, &self.options);
            if index >= count {
                self.chosen = chosen;
                return Err(ExecError::InvalidChoice {
                    plan: self.plan.name().to_string(),
                    index,
                    count,
                });
            }
            chosen.extend_from_slice(&self.conflicts.free);
            chosen.extend_from_slice(self.conflicts.set(index));
        } else {
            chosen.extend_from_slice(executable);
        }
        let result = self.fire_set(world, chooser, &chosen);
        self.chosen = chosen;
        result?;
        self.status = self.status_of_marking();
        let pending = self.pending.take();
        chooser.transition(self.key, &self.marking, pending.reward, pending.elapsed);
        Ok(())
    }

    /// Moves the tokens of `set`, then calls the functions its transitions carry.
    fn fire_set<C: Chooser + ?Sized>(
        &mut self,
        world: &mut W,
        chooser: &mut C,
        set: &[TransitionId],
    ) -> Result<(), ExecError> {
        let plan = Arc::clone(&self.plan);
        let incidence = plan.incidence();
        for &t in set {
            for a in incidence.inputs(t) {
                let old = self.marking.get(a.place);
                self.marking.remove(a.place, a.weight);
                self.place_changed(a.place, old);
            }
        }
        for &t in set {
            for a in incidence.outputs(t) {
                let old = self.marking.get(a.place);
                self.marking
                    .add(a.place, a.weight)
                    .map_err(|_| ExecError::TokenOverflow {
                        plan: plan.name().to_string(),
                        place: plan.net().place(a.place).id.clone(),
                    })?;
                self.place_changed(a.place, old);
            }
        }
        for &t in set {
            for &call in &plan.transition(t).calls {
                self.call(world, chooser, call);
            }
        }
        Ok(())
    }

    /// Updates the enabled and active sets after `place` changed from `old` tokens.
    #[inline]
    fn place_changed(&mut self, place: PlaceId, old: u8) {
        let new = self.marking.get(place);
        for &(t, w) in self.plan.incidence().consumers(place) {
            let (was, is) = (old >= w, new >= w);
            if was != is {
                let m = &mut self.missing[t.index()];
                if is {
                    *m -= 1;
                } else {
                    *m += 1;
                }
                self.enabled.set(t.index(), *m == 0);
            }
        }
        if let Some(a) = self.plan.exec_action(place) {
            let count = &mut self.marked_exec[a.index()];
            match (old > 0, new > 0) {
                (false, true) => *count += 1,
                (true, false) => *count -= 1,
                _ => {}
            }
            self.active.set(a.index(), *count > 0);
        }
    }

    /// Calls one function on one action or sub-plan.
    fn call<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C, call: Call) {
        match self.actions.get_mut(call.action.index()) {
            Executable::Primitive(x) => match call.function {
                Function::Start => x.start(world),
                Function::End => x.end(world),
                Function::Interrupt => x.interrupt(world),
                Function::Resume => x.resume(world),
                Function::Fail => x.fail(world),
            },
            Executable::Sub(p) => match call.function {
                Function::Start => p.start(world, chooser),
                other => p.propagate(world, other),
            },
        }
    }
}

impl<W: World> Activation<W> for PlanInstance<W> {
    fn reset_actions(&mut self) {
        self.actions.reset();
    }

    /// Starts the plan from its initial marking; actions on initially marked
    /// execution places are started.
    fn start<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) {
        self.marking = self.plan.initial_marking();
        self.rebuild();
        self.fresh = true;
        self.pending = PendingReward::default();
        chooser.plan_started(self.key, &self.marking);
        for a in 0..self.actions.len() {
            if self.active.contains(a) {
                self.call(
                    world,
                    chooser,
                    Call {
                        function: Function::Start,
                        action: ActionId(a as u32),
                    },
                );
            }
        }
    }

    /// Steps every active action; sub-plans step their own actions in turn.
    #[inline]
    fn act(&mut self, world: &mut W) {
        self.fresh = false;
        self.actions.act(self.active.iter(), world);
    }

    /// Adds one step and its reward to this plan and its running sub-plans.
    #[inline]
    fn accrue(&mut self, reward: f64) {
        self.pending.add(reward);
        self.actions.accrue(self.active.iter(), reward);
    }

    /// Fires this step's executable transitions (asking `chooser` on conflicts),
    /// then lets running sub-plans fire theirs: a higher plan's transitions,
    /// interrupts included, take effect before those of the plans below it.
    fn fire<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<(), ExecError> {
        if self.status != Status::Running {
            return Ok(());
        }
        let mut executable = std::mem::take(&mut self.executable);
        executable.clear();
        for t in self.enabled.iter() {
            let t = TransitionId::new(t);
            let holds = self.plan.transition(t).guard.eval(&|atom| match atom {
                AtomRef::Fact(id) => world.holds(id),
                AtomRef::Internal(i) => self.actions.internal_holds(i, world),
            });
            if holds {
                executable.push(t);
            }
        }
        let result = if executable.is_empty() {
            Ok(())
        } else {
            self.fire_executable(world, chooser, &executable)
        };
        self.executable = executable;
        result?;
        self.actions.fire(self.active.iter(), world, chooser)
    }

    activation_accessors!();
}
