//! Reports of results: plots (PNG) of a run.

pub mod run_plots;
