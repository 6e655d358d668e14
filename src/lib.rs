//! The `sim` application on top of the `runtime` library and the `preproc`
//! pre-processor, in layers that only import downwards
//! (`docs/reference/09-architecture.md`):
//!
//! - [`cli`]: the command line (parse, check, call, print);
//! - [`studies`]: critical speed, bifurcation, the speed/accuracy trade,
//!   comparisons, contact and creep-curve evaluations; they vary a run
//!   through a typed [`config::Variation`] and use its results in memory;
//! - [`report`]: text, JSON, CSV and plots of results;
//! - [`run`]: a session integrated in time → results in memory and a summary;
//! - [`session`]: a runnable model assembled from a configuration (track,
//!   vehicle, contact data, settings) and the planner's decisions;
//! - [`config`]: scene and vehicle files → typed, validated structs.
//!
//! [`error_text`] (error chains as text) is a leaf used by every layer.

pub mod cli;
pub mod config;
pub mod error_text;
pub mod report;
pub mod run;
pub mod session;
pub mod studies;
