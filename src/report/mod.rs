//! Reports of results: a run's results file and plots.

pub mod run_files;
pub mod run_plots;
