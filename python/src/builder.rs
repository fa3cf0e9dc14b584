//! `learnpnp.PlanBuilder`: the Rust plan builder, operator by operator, with
//! its method names.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use learnpnp::plan::{ActionNet, PlaceRef, SensingNet, Tracker, TransitionRef};
use learnpnp::{AllowedAtoms, AtomTable, PlanBuilder};
use pyo3::prelude::*;

use crate::errors::value_error;
use crate::plan::PyPlan;

/// Numbers builders, so a place of one cannot be used in another.
static NEXT_BUILDER: AtomicU64 = AtomicU64::new(1);

/// A place added by a `PlanBuilder` (valid in that builder only).
#[pyclass(name = "Place", module = "learnpnp", frozen)]
#[derive(Clone, Copy)]
pub struct PyPlace {
    builder: u64,
    place: PlaceRef,
}

/// A transition added by a `PlanBuilder` (valid in that builder only).
#[pyclass(name = "Transition", module = "learnpnp", frozen)]
#[derive(Clone, Copy)]
pub struct PyTransition {
    builder: u64,
    transition: TransitionRef,
}

/// The places of an ordinary action: `exec` (running), `done` (ended), and its
/// `start` transition.
#[pyclass(name = "ActionNet", module = "learnpnp", frozen, get_all)]
pub struct PyActionNet {
    /// The action's name.
    name: String,
    /// The execution place (`name.exec`).
    exec: PyPlace,
    /// The place reached when it ends.
    done: PyPlace,
    /// The start transition.
    start: PyTransition,
}

/// The places of a sensing action: `exec` and one place per outcome.
#[pyclass(name = "SensingNet", module = "learnpnp", frozen, get_all)]
pub struct PySensingNet {
    /// The execution place.
    exec: PyPlace,
    /// One place per outcome, in the order given.
    outcomes: Vec<PyPlace>,
}

/// An environment-tracking sub-net: `holds` marked while the atom holds,
/// `not_holds` while it does not.
#[pyclass(name = "Tracker", module = "learnpnp", frozen, get_all)]
pub struct PyTracker {
    /// Marked while the atom holds.
    holds: PyPlace,
    /// Marked while it does not (initially marked).
    not_holds: PyPlace,
}

/// Builds a plan with the thesis's operators, as `learnpnp::PlanBuilder` does
/// in Rust (same methods, same names). `build()` returns a `Plan`; the builder
/// is spent afterwards.
#[pyclass(name = "PlanBuilder", module = "learnpnp")]
pub struct PyPlanBuilder {
    inner: Option<PlanBuilder>,
    id: u64,
}

impl PyPlanBuilder {
    fn builder(&mut self) -> PyResult<&mut PlanBuilder> {
        self.inner
            .as_mut()
            .ok_or_else(|| value_error("this PlanBuilder has already built its plan"))
    }

    fn place_of(&self, p: &PyPlace) -> PyResult<PlaceRef> {
        if p.builder == self.id {
            Ok(p.place)
        } else {
            Err(value_error("the place belongs to another PlanBuilder"))
        }
    }

    fn places_of(&self, places: &[PyRef<'_, PyPlace>]) -> PyResult<Vec<PlaceRef>> {
        places.iter().map(|p| self.place_of(p)).collect()
    }

    fn wrap(&self, place: PlaceRef) -> PyPlace {
        PyPlace {
            builder: self.id,
            place,
        }
    }

    fn wrap_action(&self, net: ActionNet) -> PyActionNet {
        PyActionNet {
            name: net.name,
            exec: self.wrap(net.exec),
            done: self.wrap(net.done),
            start: PyTransition {
                builder: self.id,
                transition: net.start,
            },
        }
    }

    fn action_net(&self, net: &PyActionNet) -> PyResult<ActionNet> {
        Ok(ActionNet {
            name: net.name.clone(),
            exec: self.place_of(&net.exec)?,
            done: self.place_of(&net.done)?,
            start: self.transition_of(&net.start)?,
        })
    }

    fn transition_of(&self, t: &PyTransition) -> PyResult<TransitionRef> {
        if t.builder == self.id {
            Ok(t.transition)
        } else {
            Err(value_error("the transition belongs to another PlanBuilder"))
        }
    }

    fn weighted(&self, arcs: Vec<(PyRef<'_, PyPlace>, u8)>) -> PyResult<Vec<(PlaceRef, u8)>> {
        arcs.iter().map(|(p, w)| Ok((self.place_of(p)?, *w))).collect()
    }
}

#[pymethods]
impl PyPlanBuilder {
    /// A builder for a plan called `name`.
    #[new]
    fn new(name: String) -> Self {
        PyPlanBuilder {
            inner: Some(PlanBuilder::new(name)),
            id: NEXT_BUILDER.fetch_add(1, Ordering::Relaxed),
        }
    }

    /// A new place labelled `label`.
    fn place(&mut self, label: String) -> PyResult<PyPlace> {
        let p = self.builder()?.place(label);
        Ok(self.wrap(p))
    }

    /// A new place holding the initial token.
    fn initial_place(&mut self, label: String) -> PyResult<PyPlace> {
        let p = self.builder()?.initial_place(label);
        Ok(self.wrap(p))
    }

    /// A goal place (label `goal`).
    fn goal_place(&mut self) -> PyResult<PyPlace> {
        let p = self.builder()?.goal_place();
        Ok(self.wrap(p))
    }

    /// A memory place (thesis 5.2.2) labelled `label`.
    fn memory_place(&mut self, label: String) -> PyResult<PyPlace> {
        let p = self.builder()?.memory_place(label);
        Ok(self.wrap(p))
    }

    /// Sets the initial tokens of `place`.
    fn set_tokens(&mut self, place: PyRef<'_, PyPlace>, tokens: u8) -> PyResult<()> {
        let p = self.place_of(&place)?;
        self.builder()?.set_tokens(p, tokens);
        Ok(())
    }

    /// A transition with `label` (PNP label syntax), consuming from `inputs`
    /// and producing into `outputs` (lists of `(place, weight)`).
    fn transition(
        &mut self,
        label: String,
        inputs: Vec<(PyRef<'_, PyPlace>, u8)>,
        outputs: Vec<(PyRef<'_, PyPlace>, u8)>,
    ) -> PyResult<PyTransition> {
        let (i, o) = (self.weighted(inputs)?, self.weighted(outputs)?);
        let t = self.builder()?.transition(label, &i, &o);
        Ok(PyTransition {
            builder: self.id,
            transition: t,
        })
    }

    /// An arc from `transition` into `place` with weight `weight`.
    fn produce(&mut self, transition: PyRef<'_, PyTransition>, place: PyRef<'_, PyPlace>, weight: u8) -> PyResult<()> {
        let (t, p) = (self.transition_of(&transition)?, self.place_of(&place)?);
        self.builder()?.produce(t, p, weight);
        Ok(())
    }

    /// Ordinary action `name` started from `from_`; ends (when it finishes) into a new place.
    fn action(&mut self, from_: PyRef<'_, PyPlace>, name: &str) -> PyResult<PyActionNet> {
        let f = self.place_of(&from_)?;
        let net = self.builder()?.action(f, name);
        Ok(self.wrap_action(net))
    }

    /// Ordinary action `name` from `from_` ending into `done` (sequence by place merging).
    fn action_into(
        &mut self,
        from_: PyRef<'_, PyPlace>,
        name: &str,
        done: PyRef<'_, PyPlace>,
    ) -> PyResult<PyActionNet> {
        let (f, d) = (self.place_of(&from_)?, self.place_of(&done)?);
        let net = self.builder()?.action_into(f, name, d);
        Ok(self.wrap_action(net))
    }

    /// A call of sub-plan `name`: structurally an action whose executable is a plan.
    fn call(&mut self, from_: PyRef<'_, PyPlace>, name: &str) -> PyResult<PyActionNet> {
        let f = self.place_of(&from_)?;
        let net = self.builder()?.call(f, name);
        Ok(self.wrap_action(net))
    }

    /// Sensing action `name`: it ends into the outcome whose condition holds
    /// (conditions in the guard syntax, e.g. `not ballSeen`).
    fn sensing(&mut self, from_: PyRef<'_, PyPlace>, name: &str, outcomes: Vec<String>) -> PyResult<PySensingNet> {
        let f = self.place_of(&from_)?;
        let outcomes: Vec<&str> = outcomes.iter().map(String::as_str).collect();
        let net: SensingNet = self.builder()?.sensing(f, name, &outcomes);
        Ok(PySensingNet {
            exec: self.wrap(net.exec),
            outcomes: net.outcomes.into_iter().map(|p| self.wrap(p)).collect(),
        })
    }

    /// Fork: one transition giving a token to each of `n` new places.
    fn fork(&mut self, from_: PyRef<'_, PyPlace>, n: usize) -> PyResult<Vec<PyPlace>> {
        let f = self.place_of(&from_)?;
        let places = self.builder()?.fork(f, n);
        Ok(places.into_iter().map(|p| self.wrap(p)).collect())
    }

    /// Join: one transition waiting for a token in each of `inputs`; returns its output place.
    fn join(&mut self, inputs: Vec<PyRef<'_, PyPlace>>) -> PyResult<PyPlace> {
        let inputs = self.places_of(&inputs)?;
        let p = self.builder()?.join(&inputs);
        Ok(self.wrap(p))
    }

    /// Interrupt: leaves the execution of `action` for `to` when `condition`
    /// (guard syntax) holds.
    fn interrupt(
        &mut self,
        action: PyRef<'_, PyActionNet>,
        condition: &str,
        to: PyRef<'_, PyPlace>,
    ) -> PyResult<PyTransition> {
        let (net, to) = (self.action_net(&action)?, self.place_of(&to)?);
        let t = self.builder()?.interrupt(&net, condition, to);
        Ok(PyTransition {
            builder: self.id,
            transition: t,
        })
    }

    /// Non-deterministic choice: `n` unguarded conflicting transitions from
    /// `from_`, each into a new place (a choice point for the learner).
    fn choice(&mut self, from_: PyRef<'_, PyPlace>, n: usize) -> PyResult<Vec<PyPlace>> {
        let f = self.place_of(&from_)?;
        let places = self.builder()?.choice(f, n);
        Ok(places.into_iter().map(|p| self.wrap(p)).collect())
    }

    /// A choice among actions (thesis Figure 5.1): each start transition is an option.
    fn choice_of_actions(&mut self, from_: PyRef<'_, PyPlace>, names: Vec<String>) -> PyResult<Vec<PyActionNet>> {
        let f = self.place_of(&from_)?;
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        let nets = self.builder()?.choice_of_actions(f, &names);
        Ok(nets.into_iter().map(|n| self.wrap_action(n)).collect())
    }

    /// An environment-tracking sub-net for `atom` (thesis Figure 5.9).
    fn tracker(&mut self, atom: &str) -> PyResult<PyTracker> {
        let t: Tracker = self.builder()?.tracker(atom);
        Ok(PyTracker {
            holds: self.wrap(t.holds),
            not_holds: self.wrap(t.not_holds),
        })
    }

    /// The plan as built. With `atoms` (the world's atom names) a guard naming
    /// any other atom is refused; without, the plan collects its own atoms.
    #[pyo3(signature = (atoms = None))]
    fn build(&mut self, atoms: Option<Vec<String>>) -> PyResult<PyPlan> {
        let builder = self
            .inner
            .take()
            .ok_or_else(|| value_error("this PlanBuilder has already built its plan"))?;
        let table: Option<AtomTable> = atoms.map(|a| a.iter().map(String::as_str).collect());
        let vocabulary = match &table {
            Some(t) => AllowedAtoms::Closed(t),
            None => AllowedAtoms::Open,
        };
        let plan = builder.build(vocabulary).map_err(value_error)?;
        Ok(PyPlan { inner: Arc::new(plan) })
    }
}
