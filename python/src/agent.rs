//! `learnpnp.PlanAgent`: learning in a plan, in any environment the caller steps.

use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard};

use learnpnp::agent::stepwise::{ActionOutcome, StepError, StepwiseAgent};
use learnpnp::experiment::defaults::{Overrides, plan_learner};
use learnpnp::experiment::spec::Algorithm;
use learnpnp::feed::Source;
use learnpnp::learning::WatchedLearner;
use learnpnp::learning::migrate;
use learnpnp::learning::persist::{self, SavedValues};
use learnpnp::rng::seeded;
use learnpnp::{AtomId, EpisodeMode, Named, Status};
use learnpnp_view::{View, ViewOptions};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};

use crate::errors::{PlanCheckError, PlanStalledError, value_error};
use crate::plan::PyPlan;

/// The names `algo=` takes, as `learnpnp experiment --algo` takes them.
pub fn algorithm_names() -> Vec<&'static str> {
    Algorithm::ALL.iter().map(|a| a.name()).collect()
}

/// A plan with a learner at its choice points, stepped by the caller's
/// environment loop.
///
/// `PlanAgent(plan, algo="eps-sosmc", seed=0, unchecked=False, actions=None,
/// **params)`: `algo` and `params` are those of `learnpnp experiment` (the
/// flags without dashes: `alpha`, `epsilon`, `lambda` (or `lambda_`),
/// `initial_value`, ...), checked against the same ranges. A plan that fails
/// `learnpnp check` is refused unless `unchecked=True`; `actions`, when given,
/// lists the environment's actions and the plan may name no other.
/// `view="127.0.0.1:8765"` serves the live view of the agent learning (the
/// page and the Foxglove WebSocket protocol; port 0 picks a free one, see
/// `view_address`); `record_mcap=PATH` records the same channels to an MCAP
/// file, completed when the agent is deleted.
///
/// Each environment step: `agent.reward(r)` for what the last action earned,
/// then `agent.act(atoms)` with what holds now returns the action the plan runs
/// next (`None` once the plan has ended); `agent.end_episode()` when the
/// environment's episode ends. A durative action (lasting several environment
/// steps) is reported with `act(atoms, status="running")` until it finishes
/// (`"finished"`, the default) or fails (`"failed"`).
#[pyclass(name = "PlanAgent", module = "learnpnp")]
pub struct PyPlanAgent {
    inner: Mutex<StepwiseAgent>,
    plan: Arc<learnpnp::Plan>,
    algo: Algorithm,
    /// What `load` did to carry the values into the plan, as JSON.
    migration: Option<String>,
    /// The live view the learner publishes to, when one was asked for.
    view: Option<Arc<View>>,
}

/// The live view a `PlanAgent` was asked to serve or record.
#[derive(Default)]
struct ViewRequest {
    /// `view=`: the address of the page and the Foxglove protocol.
    address: Option<String>,
    /// `record_mcap=`: the MCAP recording's path.
    record_mcap: Option<PathBuf>,
}

impl ViewRequest {
    /// Starts the view, or `None` when none was asked for.
    fn start(self) -> PyResult<Option<Arc<View>>> {
        if self.address.is_none() && self.record_mcap.is_none() {
            return Ok(None);
        }
        let address = match self.address {
            Some(text) => Some(
                text.parse()
                    .map_err(|_| value_error(format!("view: '{text}' is not an address such as 127.0.0.1:8765")))?,
            ),
            None => None,
        };
        let view = View::start(ViewOptions {
            address,
            record_mcap: self.record_mcap,
            ..ViewOptions::default()
        })
        .map_err(|e| PyRuntimeError::new_err(format!("the live view did not start: {e}")))?;
        Ok(Some(Arc::new(view)))
    }
}

impl PyPlanAgent {
    fn agent(&self) -> PyResult<MutexGuard<'_, StepwiseAgent>> {
        self.inner
            .lock()
            .map_err(|_| PyRuntimeError::new_err("the agent was left inconsistent by an earlier panic"))
    }

    /// What has been learned, as `learnpnp values` reads it.
    pub(crate) fn saved(&self) -> PyResult<SavedValues> {
        let agent = self.agent()?;
        Ok(SavedValues::new(
            self.algo.name(),
            agent.learner().values(),
            &self.plan.activation_plans(),
        ))
    }

    fn build(
        plan: &PyPlan,
        algo: &str,
        seed: u64,
        unchecked: bool,
        actions: Option<Vec<String>>,
        view: ViewRequest,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let algorithm = Algorithm::from_name(algo).map_err(value_error)?;
        if !unchecked {
            let failures = plan.failures();
            if !failures.is_empty() {
                return Err(PlanCheckError::new_err(format!(
                    "plan '{}' fails the structural checks (pass unchecked=True to run it anyway):\n  {}",
                    plan.inner.name(),
                    failures.join("\n  ")
                )));
            }
        }
        let mut overrides = Overrides::default();
        if let Some(params) = params {
            for (key, value) in params.iter() {
                let key: String = key.extract()?;
                let name = key.strip_suffix('_').unwrap_or(&key);
                overrides.set(name, &parameter_text(&value)?).map_err(value_error)?;
            }
        }
        let mut spec = plan_learner(algorithm);
        overrides.apply(&mut spec);
        spec.validate().map_err(value_error)?;
        let view = view.start()?;
        let mut learner = spec.build(seeded(seed));
        if let Some(view) = &view {
            let source = Source { run: 0, agent: 0 };
            learner = Box::new(WatchedLearner::new(learner, &plan.inner, source, view.clone()));
        }
        let agent = StepwiseAgent::new(Arc::clone(&plan.inner), learner).map_err(value_error)?;
        if let Some(known) = actions
            && let Some(missing) = agent.action_names().iter().find(|a| !known.contains(a))
        {
            return Err(value_error(format!(
                "the plan runs action '{missing}', which the environment does not have: its actions are {}",
                known.join(", ")
            )));
        }
        Ok(PyPlanAgent {
            inner: Mutex::new(agent),
            plan: Arc::clone(&plan.inner),
            algo: algorithm,
            migration: None,
            view,
        })
    }
}

/// A parameter value as its flag would be written: numbers in Python's
/// shortest round-trip form, switches as `true` / `false`, text as given.
fn parameter_text(value: &Bound<'_, PyAny>) -> PyResult<String> {
    if value.is_instance_of::<PyBool>() {
        Ok(if value.extract::<bool>()? { "true" } else { "false" }.to_string())
    } else if value.is_instance_of::<PyInt>() || value.is_instance_of::<PyFloat>() || value.is_instance_of::<PyString>()
    {
        Ok(value.str()?.to_string())
    } else {
        Err(value_error(format!(
            "parameter value {} is neither a number, a bool nor a string",
            value.repr()?
        )))
    }
}

/// The atoms that hold, from a set (or any iterable) of names or a dict of name -> bool.
fn true_atoms(agent: &StepwiseAgent, atoms: &Bound<'_, PyAny>) -> PyResult<Vec<AtomId>> {
    let mut out = Vec::new();
    if let Ok(dict) = atoms.cast::<PyDict>() {
        for (name, holds) in dict.iter() {
            let id = agent.atom(&name.extract::<String>()?).map_err(step_error)?;
            if holds.is_truthy()? {
                out.push(id);
            }
        }
    } else {
        for name in atoms.try_iter()? {
            out.push(agent.atom(&name?.extract::<String>()?).map_err(step_error)?);
        }
    }
    Ok(out)
}

fn step_error(error: StepError) -> PyErr {
    match error {
        StepError::Stalled { .. } => PlanStalledError::new_err(error.to_string()),
        _ => value_error(error),
    }
}

fn mode_name(mode: EpisodeMode) -> &'static str {
    match mode {
        EpisodeMode::Learn => "learn",
        EpisodeMode::Evaluate => "evaluate",
        EpisodeMode::Greedy => "greedy",
    }
}

#[pymethods]
impl PyPlanAgent {
    #[new]
    #[pyo3(signature = (plan, algo = "eps-sosmc", seed = 0, unchecked = false, actions = None, view = None, record_mcap = None, **params))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        plan: PyRef<'_, PyPlan>,
        algo: &str,
        seed: u64,
        unchecked: bool,
        actions: Option<Vec<String>>,
        view: Option<String>,
        record_mcap: Option<PathBuf>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let view = ViewRequest {
            address: view,
            record_mcap,
        };
        Self::build(&plan, algo, seed, unchecked, actions, view, params)
    }

    /// The address the live view is served on (`"127.0.0.1:PORT"`), or `None`
    /// when the agent was made without `view=`.
    #[getter]
    fn view_address(&self) -> Option<String> {
        self.view.as_ref().and_then(|v| v.address()).map(|a| a.to_string())
    }

    /// An agent for `plan` starting from the values saved in `path` (by
    /// `save` or by `learnpnp`); `algo` defaults to the one that saved them.
    /// The values may have been learned on this plan or on an earlier revision
    /// of it: they are then carried over by the names of their choice points,
    /// options and marked places, and `agent.migration` says what was kept,
    /// dropped, ambiguous and new. A plan that shares nothing with the values
    /// is refused (`ValueError`).
    #[staticmethod]
    #[pyo3(signature = (path, plan, algo = None, seed = 0, unchecked = false, actions = None, **params))]
    fn load(
        path: PathBuf,
        plan: PyRef<'_, PyPlan>,
        algo: Option<&str>,
        seed: u64,
        unchecked: bool,
        actions: Option<Vec<String>>,
        params: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let saved = persist::load(&path).map_err(value_error)?;
        let (saved, report) = migrate::migrate(&saved, &plan.inner.activation_plans())
            .map_err(|e| value_error(format!("{}: {e}", path.display())))?;
        let algo = algo.unwrap_or(&saved.algorithm);
        let mut agent = Self::build(&plan, algo, seed, unchecked, actions, ViewRequest::default(), params)?;
        {
            let mut inner = agent.agent()?;
            let learner = inner.learner_mut();
            let table = saved.to_table(learner.values().initial_value());
            *learner.values_mut() = table;
        }
        agent.migration = Some(report.to_json().to_string());
        Ok(agent)
    }

    /// What `PlanAgent.load` did to carry the saved values into this plan (a
    /// dict: `unchanged` (learned on this very plan), `by_names_only` (a
    /// version 1 file), `kept` (a count), `dropped`, `ambiguous` (lists of
    /// `{plan, marking}`), `new_options` (`{plan, choice, at, option}`),
    /// `changed_choices` (`{plan, choice, added, removed}`), `new_choices`,
    /// `removed_choices` and `visits_reset`); `None` for an agent not loaded.
    #[getter]
    fn migration<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        match &self.migration {
            Some(text) => Ok(Some(py.import("json")?.call_method1("loads", (text.as_str(),))?)),
            None => Ok(None),
        }
    }

    /// Reports `atoms` (what holds now: a set of atom names, or a dict of atom
    /// -> bool) and the outcome of the action in progress (`status`:
    /// `"finished"`, `"running"` or `"failed"`), and returns the name of the
    /// action the plan runs next, or `None` once the plan has reached its goal
    /// (or its fail state). Starts an episode if none is in progress.
    #[pyo3(signature = (atoms, status = "finished"))]
    fn act(&self, atoms: &Bound<'_, PyAny>, status: &str) -> PyResult<Option<String>> {
        let outcome = match status {
            "finished" => ActionOutcome::Finished,
            "running" => ActionOutcome::Running,
            "failed" => ActionOutcome::Failed,
            other => {
                return Err(value_error(format!(
                    "status '{other}': it must be finished, running or failed"
                )));
            }
        };
        let mut agent = self.agent()?;
        let truth = true_atoms(&agent, atoms)?;
        agent.set_atoms(&truth);
        let next = agent.act(outcome).map_err(step_error)?;
        Ok(next.map(|i| agent.action_names()[i].clone()))
    }

    /// Adds `reward` to what the plan earned since the previous `act` (a
    /// `ValueError` if it is NaN or infinite).
    fn reward(&self, reward: f64) -> PyResult<()> {
        self.agent()?.reward(reward).map_err(step_error)
    }

    /// Ends the episode in progress: the learner learns from it (in learning mode).
    fn end_episode(&self) -> PyResult<()> {
        self.agent()?.end_episode();
        Ok(())
    }

    /// What the next episodes are for: `"learn"` (the default), `"evaluate"`
    /// (values frozen, choices as while learning) or `"greedy"` (values frozen,
    /// every choice greedy).
    #[getter]
    fn get_mode(&self) -> PyResult<&'static str> {
        Ok(mode_name(self.agent()?.mode()))
    }

    #[setter]
    fn set_mode(&self, mode: &str) -> PyResult<()> {
        let mode = match mode {
            "learn" => EpisodeMode::Learn,
            "evaluate" => EpisodeMode::Evaluate,
            "greedy" => EpisodeMode::Greedy,
            other => {
                return Err(value_error(format!(
                    "mode '{other}': it must be learn, evaluate or greedy"
                )));
            }
        };
        self.agent()?.set_mode(mode);
        Ok(())
    }

    /// Whether the next episodes are greedy (setting it is `mode = "greedy"` or `"learn"`).
    #[getter]
    fn get_greedy(&self) -> PyResult<bool> {
        Ok(self.agent()?.mode() == EpisodeMode::Greedy)
    }

    #[setter]
    fn set_greedy(&self, greedy: bool) -> PyResult<()> {
        self.agent()?.set_mode(if greedy {
            EpisodeMode::Greedy
        } else {
            EpisodeMode::Learn
        });
        Ok(())
    }

    /// Whether the current (or just ended) episode explores.
    #[getter]
    fn exploratory(&self) -> PyResult<bool> {
        Ok(self.agent()?.learner().exploratory())
    }

    /// Whether an episode is in progress.
    #[getter]
    fn in_episode(&self) -> PyResult<bool> {
        Ok(self.agent()?.in_episode())
    }

    /// The plan's status: `"running"`, `"goal"` or `"failed"`.
    #[getter]
    fn status(&self) -> PyResult<&'static str> {
        Ok(match self.agent()?.status() {
            Status::Running => "running",
            Status::Goal => "goal",
            Status::Failed => "failed",
        })
    }

    /// The actions running now.
    #[getter]
    fn running(&self) -> PyResult<Vec<String>> {
        Ok(self.agent()?.running().into_iter().map(str::to_string).collect())
    }

    /// The plan.
    #[getter]
    fn plan(&self) -> PyPlan {
        PyPlan {
            inner: Arc::clone(&self.plan),
        }
    }

    /// The algorithm's name.
    #[getter]
    fn algo(&self) -> &'static str {
        self.algo.name()
    }

    /// The plan's actions.
    #[getter]
    fn actions(&self) -> PyResult<Vec<String>> {
        Ok(self.agent()?.action_names().to_vec())
    }

    /// The plan's atoms.
    #[getter]
    fn atoms(&self) -> PyResult<Vec<String>> {
        Ok(self.agent()?.atoms().names().map(str::to_string).collect())
    }

    /// What has been learned, as `learnpnp values` lists it: one dict per
    /// entry with `plan`, `marking` (the marked places' names), `value`
    /// (`-inf`: no estimate yet) and `visits`.
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let rows = persist::rows(&self.saved()?).map_err(value_error)?;
        rows.into_iter()
            .map(|row| {
                let d = PyDict::new(py);
                d.set_item("plan", row.plan)?;
                d.set_item("marking", row.marking)?;
                d.set_item("value", row.value)?;
                d.set_item("visits", row.visits)?;
                Ok(d)
            })
            .collect()
    }

    /// Saves what has been learned to `path` in the format of `learnpnp`
    /// (`learnpnp values PATH` lists it); the previous file is kept as `PATH.prev`.
    fn save(&self, path: PathBuf) -> PyResult<()> {
        persist::save(&path, &self.saved()?).map_err(value_error)
    }

    /// A context manager: greedy episodes inside the `with` block, the
    /// previous mode after it.
    #[pyo3(signature = (mode = "greedy"))]
    fn evaluate(slf: Bound<'_, Self>, mode: &str) -> PyResult<ModeScope> {
        let previous = slf.borrow().get_mode()?;
        slf.borrow().set_mode(mode)?;
        Ok(ModeScope {
            agent: slf.unbind(),
            previous,
        })
    }

    fn __repr__(&self) -> String {
        format!("PlanAgent(plan={:?}, algo={:?})", self.plan.name(), self.algo.name())
    }
}

/// Restores an agent's mode when its `with agent.evaluate():` block ends.
#[pyclass(module = "learnpnp")]
pub struct ModeScope {
    agent: Py<PyPlanAgent>,
    previous: &'static str,
}

#[pymethods]
impl ModeScope {
    fn __enter__(slf: PyRef<'_, Self>) -> Py<PyPlanAgent> {
        slf.agent.clone_ref(slf.py())
    }

    fn __exit__(
        &self,
        py: Python<'_>,
        _kind: Option<&Bound<'_, PyAny>>,
        _value: Option<&Bound<'_, PyAny>>,
        _trace: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<bool> {
        self.agent.borrow(py).set_mode(self.previous)?;
        Ok(false)
    }
}
