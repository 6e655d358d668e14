//! `railsim._railsim`: the Python module of the toolkit (docs/guide/python.md).
//!
//! A thin layer, like the `sim` command line: each function turns its
//! keyword arguments into the same typed settings the CLI builds (most of
//! them through the CLI's own argument parser, so that defaults, checks and
//! error messages are the CLI's), calls the library with the GIL released,
//! and returns numpy arrays. Units are in every argument's name (SI unless
//! the name says `_mm`, `_mrad`, …); the conventions are those of the
//! results file and `sim contact` (docs/reference/01-units-frames.md).

mod arrays;
mod contact;
mod creep;
mod errors;
mod results;
mod run;
mod track;

use pyo3::prelude::*;

/// The Rust extension of the `railsim` package (use `import railsim`).
#[pymodule]
fn _railsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("RunFailed", m.py().get_type::<errors::RunFailed>())?;
    m.add_function(wrap_pyfunction!(track::build_track, m)?)?;
    m.add_class::<track::Track>()?;
    m.add_function(wrap_pyfunction!(contact::contact, m)?)?;
    m.add_function(wrap_pyfunction!(contact::equivalent_conicity, m)?)?;
    m.add_function(wrap_pyfunction!(creep::creep_forces, m)?)?;
    m.add_class::<results::Results>()?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(run::critical_speed, m)?)?;
    Ok(())
}
