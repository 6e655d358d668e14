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
//!
//! # Example: a scene run in memory
//!
//! The shipped single-wheelset scene, on an ideal 60 m straight instead of
//! its CSV track, for 5 m at 10 m/s; the results stay in memory (a caller
//! writes them with [`report::run_files::write_run`]).
//!
//! ```
//! use railsim::config::Variation;
//! use railsim::config::scene::LoadedScene;
//!
//! let scene = LoadedScene::default_scene(&[])?.varied(&[
//!     Variation::Remove("track.centerline".into()),
//!     Variation::StraightTrack(60.0),
//!     Variation::Distance(5.0),
//! ])?;
//! let outcome = railsim::run::run_scene(&scene, &mut |_| {}, None)?;
//! let wheelset = &outcome.results.wheelsets[0];
//! // Released 2 mm right of the centreline (the scene's `lateral_m = -0.002`, + left).
//! assert!((wheelset.lateral_m[0] + 0.002).abs() < 1e-4);
//! let summary = outcome.into_result("memory")?;
//! assert!((summary.simulated_time_s - 0.5).abs() < 0.01);
//! assert_eq!(summary.wheelsets.len(), 1);
//! # Ok::<(), anyhow::Error>(())
//! ```

pub mod cli;
pub mod config;
pub mod error_text;
pub mod report;
pub mod run;
pub mod session;
pub mod studies;
