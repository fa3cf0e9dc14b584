//! `learnpnp._native`: the Rust side of the Python package `learnpnp`.
//!
//! Plans (module `plan`), the plan builder (`builder`) and the plan agent that
//! learns in any environment (`agent`). The Python package (`learnpnp/`)
//! re-exports them and adds the gymnasium and PettingZoo environments.

mod agent;
mod builder;
mod errors;
mod keepaway;
mod plan;

use pyo3::prelude::*;

/// Panics on purpose, so a test can show a Rust panic arrives in Python as an
/// exception (`pyo3_runtime.PanicException`) instead of ending the process.
/// Built only with the cargo feature `testing` (CI's build), never in a wheel.
#[cfg(feature = "testing")]
#[pyfunction]
fn _provoke_panic() {
    panic!("a Rust panic provoked by learnpnp._native._provoke_panic");
}

/// The Rust side of `learnpnp`.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<plan::PyPlan>()?;
    m.add_class::<builder::PyPlanBuilder>()?;
    m.add_class::<builder::PyPlace>()?;
    m.add_class::<builder::PyTransition>()?;
    m.add_class::<builder::PyActionNet>()?;
    m.add_class::<builder::PySensingNet>()?;
    m.add_class::<builder::PyTracker>()?;
    m.add_class::<agent::PyPlanAgent>()?;
    m.add_class::<agent::ModeScope>()?;
    m.add_class::<keepaway::KeepawayGame>()?;
    m.add_class::<keepaway::KeepawayBatch>()?;
    m.add("PlanFileError", m.py().get_type::<errors::PlanFileError>())?;
    m.add("PlanCheckError", m.py().get_type::<errors::PlanCheckError>())?;
    m.add("PlanStalledError", m.py().get_type::<errors::PlanStalledError>())?;
    m.add("ALGORITHMS", agent::algorithm_names())?;
    m.add("PARAMETERS", learnpnp::experiment::defaults::Overrides::NAMES.to_vec())?;
    #[cfg(feature = "testing")]
    m.add_function(wrap_pyfunction!(_provoke_panic, m)?)?;
    Ok(())
}
