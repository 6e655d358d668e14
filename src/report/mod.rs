//! Reports: what runs and studies leave for the user — results files,
//! plots, CSV, markdown and text. Studies return data; these write it.

pub mod bifurcation;
pub mod critical_speed;
pub mod run_files;
pub mod run_plots;
pub mod run_text;
pub mod tradeoff;
