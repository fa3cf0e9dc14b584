//! Executing a schema's process with the semantics of thesis section 3.1.1.
//!
//! A running machine is in one plan state, whose actions run. Each executor step:
//! 1. every action of the current state is stepped (running sub-machines step theirs);
//! 2. the step's reward is credited to the machine and to every running
//!    sub-machine below it (a sub-machine's reward accrues to the calling state);
//! 3. from the root down, a machine senses the events of its current state's
//!    edges, named events in order of first appearance and the empty event
//!    (always triggered) last; the first event sensed is the step's event
//!    (the thesis assumes no two happen at once). The conditions that hold pick
//!    its constituent state <s, e, C>, reported to the chooser with the reward
//!    and time since the last change; if C has several plan-actions the chooser
//!    picks one among their afterstates; the plan-action (zero time) enters the
//!    target state: actions not in it end, new ones start, common ones keep
//!    running. If no condition holds, the event loops on the state (reported,
//!    nothing changes). A machine that followed an edge preempts the machines
//!    below it for this step; a sub-machine started in this step waits for the next.
//!
//! Final states are absorbing: the machine has finished (or failed) and runs
//! nothing; its caller senses `M.finished` (or `M.failed`).

use std::sync::Arc;

use super::construct::ProcessStateId;
use super::model::StateKind;
use super::{MachineProcess, Process};
use crate::condition::{AtomRef, Condition};
use crate::executor::{Action, Chooser, ExecError, PlanKey, Status, World};
use crate::executor::{Entry, Registry};
use crate::net::{Marking, PlaceId};
use crate::plan::InternalKind;

/// What runs for one action of a machine.
enum Executable<W> {
    Primitive(Box<dyn Action<W>>),
    Machine(Box<MachineRun<W>>),
}

/// An internal condition bound to the action that answers it.
#[derive(Debug, Clone, Copy)]
enum Binding {
    Finished(usize),
    Failed(usize),
    Declared(usize, usize),
}

/// One running machine (a node of the activation tree).
pub(crate) struct MachineRun<W> {
    process: Arc<Process>,
    machine: usize,
    key: PlanKey,
    state: usize,
    place: ProcessStateId,
    pub(crate) marking: Marking,
    executables: Vec<Executable<W>>,
    bindings: Vec<Binding>,
    pub(crate) status: Status,
    fresh: bool,
    pub(crate) pending_reward: f64,
    pub(crate) elapsed: u32,
    options: Vec<Marking>,
}

impl<W: World> MachineRun<W> {
    /// Instantiates machine `machine` of `process` and, recursively, the
    /// machines it calls; primitive actions come from `registry`.
    pub(crate) fn new(process: Arc<Process>, machine: usize, registry: &Registry<W>) -> Result<Self, ExecError> {
        let mp = &process.machines()[machine];
        let mut executables = Vec::with_capacity(mp.actions().len());
        let mut declared_lists: Vec<Vec<String>> = Vec::with_capacity(mp.actions().len());
        for action in mp.actions() {
            match action.machine {
                Some(m) => {
                    executables.push(Executable::Machine(Box::new(MachineRun::new(
                        Arc::clone(&process),
                        m,
                        registry,
                    )?)));
                    declared_lists.push(Vec::new());
                }
                None => match registry.resolve(&action.name) {
                    Some(Entry::Primitive { declared, factory }) => {
                        executables.push(Executable::Primitive(factory(&action.name)));
                        declared_lists.push(declared.to_vec());
                    }
                    _ => {
                        return Err(registry.unknown_action(mp.name(), &action.name));
                    }
                },
            }
        }
        let mut bindings = Vec::with_capacity(mp.internal.len());
        for (a, kind) in &mp.internal {
            bindings.push(match kind {
                InternalKind::Finished => Binding::Finished(*a),
                InternalKind::Failed => Binding::Failed(*a),
                InternalKind::Declared(name) => {
                    let declared = &declared_lists[*a];
                    let index =
                        declared
                            .iter()
                            .position(|d| d == name)
                            .ok_or_else(|| ExecError::UndeclaredCondition {
                                plan: mp.name().to_string(),
                                action: mp.actions()[*a].name.clone(),
                                condition: name.clone(),
                                declared: if declared.is_empty() {
                                    "nothing".to_string()
                                } else {
                                    declared.join(", ")
                                },
                            })?;
                    Binding::Declared(*a, index)
                }
            });
        }
        let initial = mp.machine().initial();
        let mut marking = Marking::empty(mp.states().len());
        marking.set(PlaceId::new(initial), 1);
        Ok(MachineRun {
            key: PlanKey(machine as u16),
            machine,
            state: initial,
            place: initial,
            marking,
            executables,
            bindings,
            status: Status::Running,
            fresh: true,
            pending_reward: 0.0,
            elapsed: 0,
            options: Vec::new(),
            process,
        })
    }

    fn process(&self) -> &MachineProcess {
        &self.process.machines()[self.machine]
    }

    /// Resets every primitive action of the tree for a new episode.
    pub(crate) fn reset_actions(&mut self) {
        for e in &mut self.executables {
            match e {
                Executable::Primitive(a) => a.reset(),
                Executable::Machine(m) => m.reset_actions(),
            }
        }
    }

    fn set_place(&mut self, place: ProcessStateId) {
        self.marking.set(PlaceId::new(self.place), 0);
        self.marking.set(PlaceId::new(place), 1);
        self.place = place;
    }

    /// Enters the initial state and starts its actions.
    pub(crate) fn start<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) {
        let initial = self.process().machine().initial();
        self.state = initial;
        self.set_place(initial);
        self.status = Status::Running;
        self.fresh = true;
        self.pending_reward = 0.0;
        self.elapsed = 0;
        chooser.plan_started(self.key, &self.marking);
        let process = Arc::clone(&self.process);
        for &a in process.machines()[self.machine].state_actions(initial) {
            self.start_action(a, world, chooser);
        }
    }

    fn start_action<C: Chooser + ?Sized>(&mut self, a: usize, world: &mut W, chooser: &mut C) {
        match &mut self.executables[a] {
            Executable::Primitive(x) => x.start(world),
            Executable::Machine(m) => m.start(world, chooser),
        }
    }

    fn end_action(&mut self, a: usize, world: &mut W) {
        match &mut self.executables[a] {
            Executable::Primitive(x) => x.end(world),
            Executable::Machine(m) => m.end(world),
        }
    }

    /// Ends the actions of the current state (the machine was left by its caller).
    fn end(&mut self, world: &mut W) {
        let process = Arc::clone(&self.process);
        for &a in process.machines()[self.machine].state_actions(self.state) {
            self.end_action(a, world);
        }
    }

    /// Steps every action of the current state; running sub-machines step theirs.
    pub(crate) fn act(&mut self, world: &mut W) {
        self.fresh = false;
        let Self {
            process,
            machine,
            state,
            executables,
            ..
        } = self;
        for &a in process.machines()[*machine].state_actions(*state) {
            match &mut executables[a] {
                Executable::Primitive(x) => x.step(world),
                Executable::Machine(m) if m.status == Status::Running => m.act(world),
                Executable::Machine(_) => {}
            }
        }
    }

    /// Adds one step and its reward to this machine and its running sub-machines.
    pub(crate) fn accrue(&mut self, reward: f64) {
        self.pending_reward += reward;
        self.elapsed += 1;
        let Self {
            process,
            machine,
            state,
            executables,
            ..
        } = self;
        for &a in process.machines()[*machine].state_actions(*state) {
            if let Executable::Machine(m) = &mut executables[a]
                && m.status == Status::Running
            {
                m.accrue(reward);
            }
        }
    }

    fn internal_holds(&self, index: u32, world: &W) -> bool {
        match self.bindings[index as usize] {
            Binding::Finished(a) => match &self.executables[a] {
                Executable::Primitive(x) => x.finished(world),
                Executable::Machine(m) => m.status == Status::Goal,
            },
            Binding::Failed(a) => match &self.executables[a] {
                Executable::Primitive(x) => x.failed(world),
                Executable::Machine(m) => m.status == Status::Failed,
            },
            Binding::Declared(a, i) => match &self.executables[a] {
                Executable::Primitive(x) => x.condition(i, world),
                Executable::Machine(_) => false,
            },
        }
    }

    fn holds(&self, condition: &Condition, world: &W) -> bool {
        condition.eval(&|atom| match atom {
            AtomRef::Fact(id) => world.holds(id),
            AtomRef::Internal(i) => self.internal_holds(i, world),
        })
    }

    /// Follows an edge if an event of the current state is sensed (see the
    /// module documentation), then lets the running sub-machines do the same
    /// unless this machine changed state.
    pub(crate) fn fire<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<(), ExecError> {
        if self.status != Status::Running {
            return Ok(());
        }
        if self.follow(world, chooser)? {
            return Ok(());
        }
        let process = Arc::clone(&self.process);
        for &a in process.machines()[self.machine].state_actions(self.state) {
            if let Executable::Machine(m) = &mut self.executables[a]
                && m.status == Status::Running
                && !m.fresh
            {
                m.fire(world, chooser)?;
            }
        }
        Ok(())
    }

    /// Senses the current state's events; returns whether an edge was followed.
    fn follow<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<bool, ExecError> {
        let process = Arc::clone(&self.process);
        let mp = &process.machines()[self.machine];
        for group in mp.groups(self.state) {
            let triggered = group.compiled_event.as_ref().is_none_or(|e| self.holds(e, world));
            if !triggered {
                continue;
            }
            let mask = group
                .compiled_conditions
                .iter()
                .enumerate()
                .fold(0u32, |m, (i, c)| if self.holds(c, world) { m | 1 << i } else { m });
            let Some(constituent) = group.constituent(mask) else {
                // No condition holds: the event loops on the state.
                if group.loops {
                    chooser.transition(self.key, &self.marking, self.pending_reward, self.elapsed);
                    self.pending_reward = 0.0;
                    self.elapsed = 0;
                }
                return Ok(false);
            };
            // The event: a time-extended transition into <s, e, C>, carrying the reward.
            self.set_place(constituent.state);
            chooser.transition(self.key, &self.marking, self.pending_reward, self.elapsed);
            self.pending_reward = 0.0;
            self.elapsed = 0;
            let actions = &constituent.plan_actions;
            let index = if actions.len() > 1 {
                self.options
                    .resize_with(actions.len(), || Marking::empty(mp.states().len()));
                for (option, action) in self.options.iter_mut().zip(actions) {
                    option.clone_from(&self.marking);
                    option.set(PlaceId::new(constituent.state), 0);
                    option.set(PlaceId::new(action.enters), 1);
                }
                let index = chooser.choose(self.key, &self.marking, &self.options[..actions.len()]);
                if index >= actions.len() {
                    return Err(ExecError::InvalidChoice {
                        plan: mp.name().to_string(),
                        index,
                        count: actions.len(),
                    });
                }
                index
            } else {
                0
            };
            // The plan-action: zero time, no reward.
            let action = actions[index];
            let (old, new) = (mp.state_actions(self.state), mp.state_actions(action.target));
            for &a in old {
                if !new.contains(&a) {
                    self.end_action(a, world);
                }
            }
            self.state = action.target;
            self.set_place(action.enters);
            self.status = match mp.kind(action.target) {
                StateKind::Ordinary => Status::Running,
                StateKind::Final => Status::Goal,
                StateKind::Failure => Status::Failed,
            };
            for &a in new {
                if !old.contains(&a) {
                    self.start_action(a, world, chooser);
                }
            }
            chooser.transition(self.key, &self.marking, 0.0, 0);
            return Ok(true);
        }
        Ok(false)
    }
}
