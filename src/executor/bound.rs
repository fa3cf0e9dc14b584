//! The actions a running plan or machine has bound, and the internal
//! conditions its guards ask them: stepping the active ones, crediting reward
//! to running sub-plans, answering `A.finished`, `A.failed` and declared
//! conditions. Shared by both kinds of node of the activation tree.

use super::activation::Activation;
use super::{Action, Chooser, ExecError, Status, World};
use crate::plan::InternalKind;

/// What runs for one action: a primitive action or a sub-plan `S` (a
/// sub-plan instance or a sub-machine run).
pub(crate) enum Executable<W, S> {
    /// A primitive action.
    Primitive(Box<dyn Action<W>>),
    /// A sub-plan or sub-machine.
    Sub(Box<S>),
}

/// An internal condition bound to the executable that answers it.
#[derive(Debug, Clone, Copy)]
enum Binding {
    Finished(usize),
    Failed(usize),
    Declared(usize, usize),
}

/// Collects a node's executables, in action order, before their conditions are bound.
pub(crate) struct Binder<'r, W, S> {
    executables: Vec<Executable<W, S>>,
    declared: Vec<&'r [String]>,
}

impl<'r, W: World, S: Activation<W>> Binder<'r, W, S> {
    /// Room for `actions` executables.
    pub(crate) fn with_capacity(actions: usize) -> Self {
        Binder {
            executables: Vec::with_capacity(actions),
            declared: Vec::with_capacity(actions),
        }
    }

    /// The next action is primitive, declaring the conditions `declared`.
    pub(crate) fn primitive(&mut self, action: Box<dyn Action<W>>, declared: &'r [String]) {
        self.executables.push(Executable::Primitive(action));
        self.declared.push(declared);
    }

    /// The next action is a sub-plan (it declares no conditions).
    pub(crate) fn sub(&mut self, sub: S) {
        self.executables.push(Executable::Sub(Box::new(sub)));
        self.declared.push(&[]);
    }

    /// Binds the internal conditions `internal` (action index and kind, in
    /// `AtomRef::Internal` order) of plan `plan`, whose action `a` is named
    /// `name(a)`; refuses a condition its action does not declare.
    pub(crate) fn bind<'n>(
        self,
        plan: &str,
        name: impl Fn(usize) -> &'n str,
        internal: impl IntoIterator<Item = (usize, &'n InternalKind)>,
    ) -> Result<BoundActions<W, S>, ExecError> {
        let internal = internal.into_iter();
        let mut bindings = Vec::with_capacity(internal.size_hint().0);
        for (a, kind) in internal {
            bindings.push(match kind {
                InternalKind::Finished => Binding::Finished(a),
                InternalKind::Failed => Binding::Failed(a),
                InternalKind::Declared(condition) => {
                    let declared = self.declared[a];
                    let index =
                        declared
                            .iter()
                            .position(|d| d == condition)
                            .ok_or_else(|| ExecError::UndeclaredCondition {
                                plan: plan.to_string(),
                                action: name(a).to_string(),
                                condition: condition.clone(),
                                declared: if declared.is_empty() {
                                    "nothing".to_string()
                                } else {
                                    declared.join(", ")
                                },
                            })?;
                    Binding::Declared(a, index)
                }
            });
        }
        Ok(BoundActions {
            executables: self.executables,
            bindings,
        })
    }
}

/// A node's executables and its guards' internal conditions bound to them.
pub(crate) struct BoundActions<W, S> {
    executables: Vec<Executable<W, S>>,
    bindings: Vec<Binding>,
}

impl<W: World, S: Activation<W>> BoundActions<W, S> {
    /// How many executables.
    pub(crate) fn len(&self) -> usize {
        self.executables.len()
    }

    /// The executable of action `a`.
    #[inline]
    pub(crate) fn get_mut(&mut self, a: usize) -> &mut Executable<W, S> {
        &mut self.executables[a]
    }

    /// Resets every primitive action of the sub-tree for a new episode.
    pub(crate) fn reset(&mut self) {
        for e in &mut self.executables {
            match e {
                Executable::Primitive(x) => x.reset(),
                Executable::Sub(s) => s.reset_actions(),
            }
        }
    }

    /// Steps the `active` actions; running sub-plans step theirs.
    #[inline]
    pub(crate) fn act(&mut self, active: impl IntoIterator<Item = usize>, world: &mut W) {
        for a in active {
            match &mut self.executables[a] {
                Executable::Primitive(x) => x.step(world),
                Executable::Sub(s) if s.status() == Status::Running => s.act(world),
                Executable::Sub(_) => {}
            }
        }
    }

    /// Credits one step and its reward to the running sub-plans among `active`.
    #[inline]
    pub(crate) fn accrue(&mut self, active: impl IntoIterator<Item = usize>, reward: f64) {
        for a in active {
            if let Executable::Sub(s) = &mut self.executables[a]
                && s.status() == Status::Running
            {
                s.accrue(reward);
            }
        }
    }

    /// Lets the running sub-plans among `active` that did not start in this step fire.
    #[inline]
    pub(crate) fn fire<C: Chooser + ?Sized>(
        &mut self,
        active: impl IntoIterator<Item = usize>,
        world: &mut W,
        chooser: &mut C,
    ) -> Result<(), ExecError> {
        for a in active {
            if let Executable::Sub(s) = &mut self.executables[a]
                && !s.fresh()
                && s.status() == Status::Running
            {
                s.fire(world, chooser)?;
            }
        }
        Ok(())
    }

    /// Whether internal condition `index` holds: `A.finished` / `A.failed` of a
    /// primitive action as it answers, of a sub-plan when in a goal / fail
    /// marking; a declared condition as the action answers (never for a sub-plan).
    #[inline]
    pub(crate) fn internal_holds(&self, index: u32, world: &W) -> bool {
        match self.bindings[index as usize] {
            Binding::Finished(a) => match &self.executables[a] {
                Executable::Primitive(x) => x.finished(world),
                Executable::Sub(s) => s.status() == Status::Goal,
            },
            Binding::Failed(a) => match &self.executables[a] {
                Executable::Primitive(x) => x.failed(world),
                Executable::Sub(s) => s.status() == Status::Failed,
            },
            Binding::Declared(a, i) => match &self.executables[a] {
                Executable::Primitive(x) => x.condition(i, world),
                Executable::Sub(_) => false,
            },
        }
    }
}
