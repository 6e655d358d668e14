//! The `sim` application: scenes, runs, outputs, plots and sweeps on top of
//! the `runtime` library and the `preproc` pre-processor.

pub mod bifurcation;
pub mod cache;
pub mod cli;
pub mod compare_tables;
pub mod contact;
pub mod creep_curves;
pub mod critical_speed;
pub mod diagnostics;
pub mod error_text;
pub mod load;
pub mod planner;
pub mod probe;
pub mod run;
pub mod run_plots;
pub mod scene;
pub mod tradeoff;
pub mod vehicle_file;
