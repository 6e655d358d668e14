//! Reports of results: a run's results file, plots and text summary.

pub mod run_files;
pub mod run_plots;
pub mod run_text;
pub mod tradeoff;
