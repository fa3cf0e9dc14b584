//! `learnpnp.Plan`: a plan loaded from a file or built, its checks and drawing.

use std::path::PathBuf;
use std::sync::Arc;

use learnpnp::agent::stepwise;
use learnpnp::analysis::{self, CheckReport};
use learnpnp::condition::AtomTable;
use learnpnp::generate;
use learnpnp::learning::by_choice::group_by_choice;
use learnpnp::pnml::{self, Dialect};
use learnpnp::{AllowedAtoms, Plan, dot, load_plan, persist, schema};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::agent::PyPlanAgent;
use crate::errors::{load_error, value_error};

/// A Petri Net Plan (or a plan schema's constructed process), ready to check,
/// draw and learn in.
///
/// Load one with `Plan.load(path)` or build one with `PlanBuilder`.
#[pyclass(name = "Plan", module = "learnpnp", frozen)]
pub struct PyPlan {
    pub(crate) inner: Arc<Plan>,
}

impl PyPlan {
    /// `generated` with `rules` applied (atoms checked against `atoms`), as a plan.
    fn generated(
        mut generated: generate::GeneratedPlan,
        rules: Option<&str>,
        atoms: Option<Vec<String>>,
    ) -> PyResult<Self> {
        if let Some(text) = rules {
            let rules = generate::rules::parse_rules(text).map_err(value_error)?;
            let table: Option<AtomTable> = atoms.as_ref().map(|a| a.iter().map(String::as_str).collect());
            generated.apply_rules(&rules, table.as_ref()).map_err(value_error)?;
        }
        let plan = generated.into_plan(AllowedAtoms::Open).map_err(value_error)?;
        Ok(PyPlan { inner: Arc::new(plan) })
    }

    /// The failures of the structural checks (`learnpnp check`), as lines.
    pub(crate) fn failures(&self) -> Vec<String> {
        match self.inner.schema_process() {
            Some(process) => {
                let (report, _) = schema::check_report(&process);
                report
                    .lines()
                    .filter_map(|l| l.trim_start().strip_prefix("FAIL "))
                    .map(str::to_string)
                    .collect()
            }
            None => analysis::check(&self.inner, analysis::DEFAULT_LIMIT)
                .failures
                .iter()
                .map(ToString::to_string)
                .collect(),
        }
    }
}

#[pymethods]
impl PyPlan {
    /// Loads the plan in `path`: JARP or standard PNML, or a plan schema
    /// (`.schema`). Raises `PlanFileError` (with `file`, `element`, `token`)
    /// when it cannot be loaded.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let plan = load_plan(&path, AllowedAtoms::Open).map_err(|e| load_error(py, &e))?;
        Ok(PyPlan { inner: Arc::new(plan) })
    }

    /// A plan generated from linear plans (`learnpnp generate`): each plan a
    /// list of actions (`"move_a_b"`, or PNPgen's `"goto|30"` with a
    /// timeout); several plans merge into one with a choice point wherever
    /// they differ. `rules`: execution rules (`*if* COND *during* ACTION *do*
    /// RECOVERY`, one a line); `atoms`: the atoms their conditions may test
    /// (any by default). Raises `ValueError` naming what cannot be generated.
    #[staticmethod]
    #[pyo3(signature = (name, plans, rules = None, atoms = None))]
    fn from_plans(
        name: &str,
        plans: Vec<Vec<String>>,
        rules: Option<&str>,
        atoms: Option<Vec<String>>,
    ) -> PyResult<Self> {
        let plans = plans
            .iter()
            .map(|p| generate::linear::parse_pnpgen_line(&p.join(";")))
            .collect::<Result<Vec<_>, _>>()
            .map_err(value_error)?;
        let generated = generate::GeneratedPlan::merged(name, &plans).map_err(value_error)?;
        Self::generated(generated, rules, atoms)
    }

    /// A plan generated from a conditional plan in PNPgen's form (states,
    /// actions, edges labelled by sensing outcomes), with optional execution
    /// `rules` as in `from_plans`.
    #[staticmethod]
    #[pyo3(signature = (name, text, rules = None, atoms = None))]
    fn from_conditional(name: &str, text: &str, rules: Option<&str>, atoms: Option<Vec<String>>) -> PyResult<Self> {
        let generated = generate::GeneratedPlan::conditional(name, text).map_err(value_error)?;
        Self::generated(generated, rules, atoms)
    }

    /// The plan's name.
    #[getter]
    fn name(&self) -> &str {
        self.inner.name()
    }

    /// The atoms it tests (its guards', or a schema's events and conditions).
    #[getter]
    fn atoms(&self) -> Vec<String> {
        stepwise::atom_table(&self.inner).names().map(str::to_string).collect()
    }

    /// The primitive actions it runs (of every machine, for a schema), in
    /// order of appearance.
    #[getter]
    fn actions(&self) -> Vec<String> {
        stepwise::action_names(&self.inner)
    }

    /// What is unusual in the plan but accepted, as the PNP library accepts it.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings().iter().map(ToString::to_string).collect()
    }

    /// The report of `learnpnp check` as data: `passed`, `failures`, `text`
    /// (the report as the command prints it) and, for a Petri Net Plan,
    /// `verdicts` (property -> `passed` / `failed` / `inconclusive` /
    /// `not applicable`), `choice_points`, `notes`, `warnings`, `places`,
    /// `transitions`, `markings`, `complete`. `limit` bounds the markings explored.
    #[pyo3(signature = (limit = analysis::DEFAULT_LIMIT))]
    fn check<'py>(&self, py: Python<'py>, limit: usize) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        out.set_item("plan", self.inner.name())?;
        if let Some(process) = self.inner.schema_process() {
            let (text, passed) = schema::check_report(&process);
            out.set_item("passed", passed)?;
            out.set_item("failures", self.failures())?;
            out.set_item("text", text)?;
            return Ok(out);
        }
        let report: CheckReport = analysis::check(&self.inner, limit);
        out.set_item("passed", report.passed())?;
        out.set_item(
            "failures",
            report.failures.iter().map(ToString::to_string).collect::<Vec<_>>(),
        )?;
        out.set_item("text", report.to_string())?;
        let verdicts = PyDict::new(py);
        for (property, verdict) in &report.verdicts {
            verdicts.set_item(property.name(), verdict.summary())?;
        }
        out.set_item("verdicts", verdicts)?;
        out.set_item(
            "choice_points",
            report
                .choice_points
                .iter()
                .map(|c| format!("{c:?}"))
                .collect::<Vec<_>>(),
        )?;
        out.set_item(
            "notes",
            report.notes.iter().map(ToString::to_string).collect::<Vec<_>>(),
        )?;
        out.set_item("warnings", report.warnings.clone())?;
        out.set_item("places", report.places)?;
        out.set_item("transitions", report.transitions)?;
        out.set_item("markings", report.markings)?;
        out.set_item("complete", report.complete)?;
        Ok(out)
    }

    /// The plan in Graphviz DOT, as `learnpnp dot` draws it; with `values` (a
    /// `PlanAgent` learning in this plan, or the path of a values file) each
    /// choice point's options carry their learned values.
    #[pyo3(signature = (values = None, limit = analysis::DEFAULT_LIMIT))]
    fn to_dot(&self, values: Option<&Bound<'_, PyAny>>, limit: usize) -> PyResult<String> {
        let saved = match values {
            None => None,
            Some(v) => Some(if let Ok(agent) = v.cast::<PyPlanAgent>() {
                agent.borrow().saved()?
            } else {
                let path: PathBuf = v.extract()?;
                persist::load(&path).map_err(value_error)?
            }),
        };
        match (saved, self.inner.schema_process()) {
            (None, Some(process)) => Ok(schema::to_dot(&process)),
            (None, None) => Ok(dot::to_dot_with_values(&self.inner, limit, None)),
            (Some(saved), _) => {
                let learned = group_by_choice(&[&self.inner], &saved).map_err(value_error)?;
                Ok(dot::to_dot_with_values(&self.inner, limit, Some(&learned)))
            }
        }
    }

    /// Writes the plan's net as PNML (`dialect`: `jarp`, as the PNP editor
    /// writes it, or `standard`); a plan schema has no net file of its own.
    #[pyo3(signature = (path, dialect = "jarp"))]
    fn save(&self, path: PathBuf, dialect: &str) -> PyResult<()> {
        if self.inner.schema_process().is_some() {
            return Err(value_error("a plan schema is saved as its .schema text, not as PNML"));
        }
        let dialect: Dialect = dialect.parse().map_err(value_error)?;
        pnml::write_file(self.inner.net(), dialect, &path).map_err(|e| value_error(format!("{}: {e}", path.display())))
    }

    fn __repr__(&self) -> String {
        format!(
            "Plan({:?}: {} atoms, {} actions)",
            self.inner.name(),
            self.atoms().len(),
            self.actions().len()
        )
    }
}
