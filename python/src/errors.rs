//! Errors as Python exceptions: a refused input is a `ValueError` whose
//! message is the CLI's (`sim`'s "error: …" line, then one
//! "  caused by: …" line per cause); a run that failed part-way is a
//! `railsim.RunFailed` carrying the results so far.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    _railsim,
    RunFailed,
    PyRuntimeError,
    "A run that ended early with an error (derailment, a contact that cannot be solved). `args[0]` is the message, `args[1]` the `railsim.Results` of the samples so far."
);

/// The message of `e` as the CLI prints it, without its "error: " prefix.
pub fn message(e: &anyhow::Error) -> String {
    railsim::error_text::chain_messages(e).join("\n  caused by: ")
}

/// `e` as a `ValueError` with the CLI's message.
pub fn value_error(e: anyhow::Error) -> PyErr {
    PyValueError::new_err(message(&e))
}

/// `Result<T, anyhow::Error>` → `PyResult<T>` (a `ValueError`).
pub trait OrValueError<T> {
    fn or_value_error(self) -> PyResult<T>;
}

impl<T> OrValueError<T> for anyhow::Result<T> {
    fn or_value_error(self) -> PyResult<T> {
        self.map_err(value_error)
    }
}

/// Each warning through Python's `warnings.warn` (a `UserWarning`), where
/// the CLI prints it on standard error.
pub fn warn_all(py: Python<'_>, warnings: &[String]) -> PyResult<()> {
    if warnings.is_empty() {
        return Ok(());
    }
    let warn = py.import("warnings")?.getattr("warn")?;
    for w in warnings {
        warn.call1((
            w.as_str(),
            py.get_type::<pyo3::exceptions::PyUserWarning>(),
            2,
        ))?;
    }
    Ok(())
}
