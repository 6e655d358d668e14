//! The track pre-processor of Pombo, Ambrósio & Silva (paper §2, Fig. 1;
//! docs/reference/02-inputs.md §2–4): CSV control points, cant and irregularity tables → a smooth
//! centreline, two rails re-fitted by their own arc length, and dense
//! per-rail databases written to HDF5 through [`runtime::io::schema`].
//!
//! Pipeline: [`inputs`] (CSV parsing and rules) → [`centerline`] (fit, arc
//! length, cant, frame) → [`irregularity`] → [`rails`] (nodal points, re-fit,
//! frames with cant and inclination) → [`model::TrackModel::tabulate`] →
//! [`pipeline`] (files in, table file out).
//!
//! # Example: a 300 m arc of radius 600 m, built to a table file
//!
//! ```
//! use preproc::{BuildConfig, BuildRequest, GeometryFiles, NoProgress, run_build};
//!
//! let dir = std::env::temp_dir().join(format!("preproc-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir)?;
//! // Control points of the centreline (m): an arc of radius 600 m turning
//! // left, every 5 m. (A straight joined to an arc without a transition
//! // curve would make the cubic spline overshoot the curvature step.)
//! let mut csv = String::from("x,y,z\n");
//! for i in 0..=60 {
//!     let phi = 5.0 * f64::from(i) / 600.0;
//!     csv += &format!("{},{},0\n", 600.0 * phi.sin(), 600.0 * (1.0 - phi.cos()));
//! }
//! std::fs::write(dir.join("centerline.csv"), csv)?;
//! let summary = run_build(
//!     &BuildRequest {
//!         geometry: GeometryFiles::centerline(dir.join("centerline.csv")),
//!         irregularities: None,
//!         output: dir.join("track.h5"),
//!         config: BuildConfig::default(),
//!         contact: None,
//!         command_line: "doctest".into(),
//!     },
//!     &NoProgress,
//! )?;
//! assert!((summary.length_m - 300.0).abs() < 0.5, "{}", summary.length_m);
//! let radius = summary.min_curve_radius_m.expect("a curve");
//! assert!((radius - 600.0).abs() < 6.0, "{radius}");
//! // The file reads back as the simulator reads it.
//! let tables = runtime::io::schema::read_track(&dir.join("track.h5"))?;
//! assert!(tables.centerline.range_m().1 > 299.0);
//! std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod bounds;
pub mod built;
pub mod centerline;
pub mod cli;
pub mod config;
pub mod conicity;
pub mod contact_plots;
pub mod contact_table;
pub mod csv;
pub mod design;
pub mod error;
pub mod inputs;
pub mod irregularity;
pub mod model;
pub mod pipeline;
pub mod plot;
pub mod progress;
pub mod rails;
pub mod rsgeo;
pub mod space_curve;
pub mod summary;

pub use config::{BuildConfig, Inclination, RailSpacing};
pub use error::{BuildError, InputError};
pub use model::{DesignInputs, Inputs, TrackInputs, TrackModel};
pub use pipeline::{
    BuildRequest, ContactTableReport, ContactTableRequest, GeometryFiles, build_tables, run_build,
    run_contact_table,
};
pub use progress::{NoProgress, Progress, ProgressSink};
pub use summary::BuildSummary;
