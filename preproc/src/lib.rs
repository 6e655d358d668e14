//! The track pre-processor of Pombo, Ambrósio & Silva (paper §2, Fig. 1;
//! docs/reference/02-inputs.md §2–4): CSV control points, cant and irregularity tables → a smooth
//! centreline, two rails re-fitted by their own arc length, and dense
//! per-rail databases written to HDF5 through [`runtime::schema`].
//!
//! Pipeline: [`inputs`] (CSV parsing and rules) → [`centerline`] (fit, arc
//! length, cant, frame) → [`irregularity`] → [`rails`] (nodal points, re-fit,
//! frames with cant and inclination) → [`model::TrackModel::tabulate`] →
//! [`pipeline`] (files in, table file out).

pub mod centerline;
pub mod cli;
pub mod config;
pub mod conicity;
pub mod contact_plots;
pub mod contact_table;
pub mod csv;
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
pub use model::{TrackInputs, TrackModel};
pub use pipeline::{
    BuildRequest, ContactTableReport, ContactTableRequest, build_tables, run_build,
    run_contact_table,
};
pub use progress::{NoProgress, Progress, ProgressSink};
pub use summary::BuildSummary;
