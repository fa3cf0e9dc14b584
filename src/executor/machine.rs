//! Executing a schema's process with the semantics of thesis section 3.1.1.
//!
//! A running machine is in one plan state, whose actions run. Each executor step:
//! 1. every action of the current state is stepped (running sub-machines step theirs);
//! 2. the step's reward is credited to the machine and to every running
//!    sub-machine below it (a sub-machine's reward accrues to the calling state);
//! 3. from the root down, a machine senses the events of its current state's
//!    edges, named events in order of first appearance and the empty event
//!    (no event: always triggered) last. A named event is instantaneous
//!    (thesis 3.1.3: it marks the moment a region is entered, and no two are
//!    perceived at once): it is triggered when its condition starts to hold,
//!    and not again until the condition has been false. Entering a state
//!    (by any edge) takes the baseline: the condition with the world's atoms as
//!    they are and the actions' own conditions (`A.finished`, `A.failed`,
//!    declared ones) false, since the state's actions have only just started.
//!    So an action's termination is an event of the state that started it,
//!    while a world condition that already held on entry happened before and
//!    is not one. Of the events triggered in a step,
//!    the step's event (the thesis assumes no two happen at once) is the first
//!    whose guards let it be followed: the conditions that hold pick its
//!    constituent state <s, e, C>, reported to the chooser with the reward and
//!    time since the last change; if C has several plan-actions the chooser
//!    picks one among their afterstates; the plan-action (zero time) enters the
//!    target state: actions not in it end, new ones start, common ones keep
//!    running. An event whose guards all fail does not block the others; if
//!    none can be followed, the first triggered event loops on the state
//!    (reported, nothing changes). A machine that followed an edge preempts
//!    the machines below it for this step; a sub-machine started in this step
//!    waits for the next.
//!
//! Final states are absorbing: the machine has finished (or failed) and runs
//! nothing; its caller senses `M.finished` (or `M.failed`).

use std::sync::Arc;

use super::activation::Activation;
use super::bound::{Binder, BoundActions, Executable};
use super::registry::{Entry, Registry};
use super::{Chooser, ExecError, PendingReward, PlanKey, Status, World};
use crate::condition::{AtomRef, Condition};
use crate::net::{Marking, PlaceId};
use crate::schema::{DecisionProcess, DecisionStateId, MachineProcess, StateKind};

/// One running machine (a node of the activation tree).
pub(crate) struct MachineRun<W> {
    process: Arc<DecisionProcess>,
    machine: usize,
    key: PlanKey,
    state: usize,
    place: DecisionStateId,
    marking: Marking,
    actions: BoundActions<W, MachineRun<W>>,
    status: Status,
    /// Started during the current step: it senses events from the next.
    fresh: bool,
    pending: PendingReward,
    options: Vec<Marking>,
    /// Per event group of the current state: whether its event's condition
    /// held at the previous sensing in this visit (the baseline on entry).
    sensed: Vec<bool>,
}

impl<W: World> MachineRun<W> {
    /// Instantiates machine `machine` of `process` and, recursively, the
    /// machines it calls; primitive actions come from `registry`.
    pub(crate) fn new(
        process: Arc<DecisionProcess>,
        machine: usize,
        registry: &Registry<W>,
    ) -> Result<Self, ExecError> {
        let mp = &process.machines()[machine];
        let mut binder = Binder::with_capacity(mp.actions().len());
        for action in mp.actions() {
            match action.machine {
                Some(m) => binder.sub(MachineRun::new(Arc::clone(&process), m, registry)?),
                None => match registry.resolve(&action.name) {
                    Some(Entry::Primitive { declared, factory }) => binder.primitive(factory(&action.name), declared),
                    _ => return Err(registry.unknown_action(mp.name(), &action.name)),
                },
            }
        }
        let actions = binder.bind(
            mp.name(),
            |a| &mp.actions()[a].name,
            mp.internal.iter().map(|(a, kind)| (*a, kind)),
        )?;
        let initial = mp.machine().initial();
        let mut marking = Marking::empty(mp.states().len());
        marking.set(PlaceId::new(initial), 1);
        Ok(MachineRun {
            key: PlanKey(machine as u16),
            machine,
            state: initial,
            place: initial,
            marking,
            actions,
            status: Status::Running,
            fresh: true,
            pending: PendingReward::default(),
            options: Vec::new(),
            sensed: Vec::new(),
            process,
        })
    }

    fn process(&self) -> &MachineProcess {
        &self.process.machines()[self.machine]
    }

    /// A new visit of the current state: each event's baseline is its
    /// condition on the world as it is, with the actions' own conditions false.
    fn enter(&mut self, world: &W) {
        let process = Arc::clone(&self.process);
        self.sensed.clear();
        self.sensed
            .extend(process.machines()[self.machine].groups(self.state).iter().map(|group| {
                group.compiled_event.as_ref().is_some_and(|event| {
                    event.eval(&|atom| match atom {
                        AtomRef::Fact(id) => world.holds(id),
                        AtomRef::Internal(_) => false,
                    })
                })
            }));
    }

    fn set_place(&mut self, place: DecisionStateId) {
        self.marking.set(PlaceId::new(self.place), 0);
        self.marking.set(PlaceId::new(place), 1);
        self.place = place;
    }

    fn start_action<C: Chooser + ?Sized>(&mut self, a: usize, world: &mut W, chooser: &mut C) {
        match self.actions.get_mut(a) {
            Executable::Primitive(x) => x.start(world),
            Executable::Sub(m) => m.start(world, chooser),
        }
    }

    fn end_action(&mut self, a: usize, world: &mut W) {
        match self.actions.get_mut(a) {
            Executable::Primitive(x) => x.end(world),
            Executable::Sub(m) => m.end(world),
        }
    }

    /// Ends the actions of the current state (the machine was left by its caller).
    fn end(&mut self, world: &mut W) {
        let process = Arc::clone(&self.process);
        for &a in process.machines()[self.machine].state_actions(self.state) {
            self.end_action(a, world);
        }
    }

    fn holds(&self, condition: &Condition, world: &W) -> bool {
        condition.eval(&|atom| match atom {
            AtomRef::Fact(id) => world.holds(id),
            AtomRef::Internal(i) => self.actions.internal_holds(i, world),
        })
    }

    /// Reports the current marking to `chooser` with the reward and steps since the last change.
    fn report<C: Chooser + ?Sized>(&mut self, chooser: &mut C) {
        let pending = self.pending.take();
        chooser.transition(self.key, &self.marking, pending.reward, pending.elapsed);
    }

    /// Senses the current state's events; returns whether an edge was followed.
    fn follow<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<bool, ExecError> {
        let process = Arc::clone(&self.process);
        let mp = &process.machines()[self.machine];
        let mut first_triggered = None;
        let mut followed = None;
        for (i, group) in mp.groups(self.state).iter().enumerate() {
            let triggered = match group.compiled_event.as_ref() {
                None => true,
                Some(event) => {
                    let holds = self.holds(event, world);
                    let rose = holds && !self.sensed[i];
                    self.sensed[i] = holds;
                    rose
                }
            };
            if !triggered || followed.is_some() {
                continue;
            }
            first_triggered.get_or_insert(i);
            let mask = group.compiled_conditions.iter().enumerate().fold(0u32, |m, (c, cond)| {
                if self.holds(cond, world) { m | 1 << c } else { m }
            });
            followed = group.constituent(mask);
        }
        let Some(constituent) = followed else {
            // No triggered event can be followed: the first loops on the state.
            if first_triggered.is_some_and(|i| mp.groups(self.state)[i].loops) {
                self.report(chooser);
            }
            return Ok(false);
        };
        // The event: a time-extended transition into <s, e, C>, carrying the reward.
        self.set_place(constituent.state);
        self.report(chooser);
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
        self.enter(world);
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
        Ok(true)
    }
}

impl<W: World> Activation<W> for MachineRun<W> {
    fn reset_actions(&mut self) {
        self.actions.reset();
    }

    /// Enters the initial state and starts its actions.
    fn start<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) {
        let initial = self.process().machine().initial();
        self.state = initial;
        self.enter(world);
        self.set_place(initial);
        self.status = Status::Running;
        self.fresh = true;
        self.pending = PendingReward::default();
        chooser.plan_started(self.key, &self.marking);
        let process = Arc::clone(&self.process);
        for &a in process.machines()[self.machine].state_actions(initial) {
            self.start_action(a, world, chooser);
        }
    }

    /// Steps every action of the current state; running sub-machines step theirs.
    fn act(&mut self, world: &mut W) {
        self.fresh = false;
        let actions = self.process.machines()[self.machine].state_actions(self.state);
        self.actions.act(actions.iter().copied(), world);
    }

    /// Adds one step and its reward to this machine and its running sub-machines.
    fn accrue(&mut self, reward: f64) {
        self.pending.add(reward);
        let actions = self.process.machines()[self.machine].state_actions(self.state);
        self.actions.accrue(actions.iter().copied(), reward);
    }

    /// Follows an edge if an event of the current state is sensed (see the
    /// module documentation), then lets the running sub-machines do the same
    /// unless this machine changed state.
    fn fire<C: Chooser + ?Sized>(&mut self, world: &mut W, chooser: &mut C) -> Result<(), ExecError> {
        if self.status != Status::Running {
            return Ok(());
        }
        if self.follow(world, chooser)? {
            return Ok(());
        }
        let actions = self.process.machines()[self.machine].state_actions(self.state);
        self.actions.fire(actions.iter().copied(), world, chooser)
    }

    activation_accessors!();
}
