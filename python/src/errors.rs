//! The exceptions `learnpnp` raises, and the conversion of the core's errors.

use learnpnp::LoadError;
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    learnpnp,
    PlanFileError,
    PyValueError,
    "A plan file that cannot be loaded: `file`, `element` and `token` say where (the last two None when the error names none)."
);
create_exception!(
    learnpnp,
    PlanCheckError,
    PyValueError,
    "A plan that fails the structural checks of `learnpnp check` (pass `unchecked=True` to run it anyway)."
);
create_exception!(
    learnpnp,
    PlanStalledError,
    PyRuntimeError,
    "A plan that waits on atoms that do not hold while no action runs."
);

/// `error` as a `PlanFileError` carrying its file, element and token.
pub fn load_error(py: Python<'_>, error: &LoadError) -> PyErr {
    let err = PlanFileError::new_err(error.to_string());
    let value = err.value(py);
    let attributes = [
        ("file", Some(error.path().display().to_string())),
        ("element", error.element()),
        ("token", error.token()),
    ];
    for (name, text) in attributes {
        if let Err(e) = value.setattr(name, text) {
            return e;
        }
    }
    err
}

/// A message as a `ValueError`.
pub fn value_error(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(message.to_string())
}
