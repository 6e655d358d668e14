//! The HDF5 table-file schema (docs/reference/04-table-files.md §4): the one place that reads and writes
//! table files, so the pre-processor's writer and the run-time reader cannot
//! drift apart.
//!
//! Layout of schema version 1:
//!
//! ```text
//! /                         attributes: schema_version (u32), tool, tool_version,
//!                           scheme, cant_scheme, step_m, gauge_m, rail_spacing_m, cant_base_m,
//!                           rail_inclination, rail_inclination_rad, length_m;
//!                           with a rail profile: rail_profile, rail_profile_sha256,
//!                           rail_profile_cant_rad, rail_profile_cant_source
//! /centerline/database      N×23 f64, attributes `columns`, `units`
//! /left_rail/database       M×13 f64 (L x y z tx ty tz nx ny nz bx by bz)
//! /right_rail/database      K×13 f64
//! /design/…                 optional: the plan elements of a design file, 1-D
//!                           datasets (layout in `design_elements`)
//! /contact_table/…          optional: the contact lookup table (see below)
//! /imported_contact_table/… optional: a contact table from another code
//!                           (`track-preproc import-contact-table`; layout in `imported`)
//! /input/command_line       string
//! /input/<role>             string: the input file's text, attribute `path`
//! ```
//!
//! A file may hold only `/contact_table` (`track-preproc contact-table`),
//! only the track, or both (`track-preproc build --wheel … --rail …`).
//!
//! Every table is a 2-D `f64` dataset whose `columns` attribute names its
//! columns and whose `units` attribute gives each column's unit ("1" for
//! dimensionless). Readers look columns up by name, so columns may be added
//! in later versions without breaking old readers; anything that changes the
//! meaning of an existing column bumps [`SCHEMA_VERSION`].
//!
//! Files are written atomically: to a hidden temporary name in the target
//! directory, renamed into place only when complete ([`crate::io::atomic`]).
//!
//! The same module writes and reads the simulation results file (its own
//! schema, `railsim-results`, layout in `results_file`): [`write_results`],
//! [`read_results`]. The results themselves are plain data in
//! [`crate::results`].

mod attrs;
mod columns;
mod contact_table;
mod design_elements;
mod imported;
mod raw_series;
mod results_bodies;
mod results_file;
mod results_series;
mod results_writer;
mod study_table;
mod track;

pub use imported::{read_imported_contact_table, write_imported_contact_table_file};
pub use results_file::{
    RESULTS_SCHEMA, RESULTS_SCHEMA_VERSION, RESULTS_TOOL, read_results, write_results,
};
pub use results_writer::{RESULTS_CHUNK_SAMPLES, ResultsWriter};
pub use study_table::{StudyColumn, read_study_table, write_study_table};
pub use track::{
    TableFileWriter, read_contact_table, read_provenance, read_track, read_track_meta,
    write_contact_table_file, write_track_file,
};

use std::path::PathBuf;

use crate::geometry::track::TrackError;

/// Version of the table-file layout this build writes and reads.
pub const SCHEMA_VERSION: u32 = 1;

/// Errors reading or writing a table file. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum SchemaError {
    #[error("cannot open '{path}' as an HDF5 table file: {source}")]
    Open {
        path: PathBuf,
        #[source]
        source: hdf5::Error,
    },
    /// Creating an output file failed (a missing or read-only directory,
    /// a full disk): nothing was written.
    #[error("cannot create '{path}' (does its directory exist, and is it writable?): {source}")]
    Create {
        path: PathBuf,
        #[source]
        source: hdf5::Error,
    },
    #[error(
        "'{path}' has table schema version {found}, which this build does not read (it reads version {supported}); rebuild the tables with this version of track-preproc"
    )]
    UnsupportedVersion {
        path: PathBuf,
        found: u32,
        supported: u32,
    },
    #[error("'{path}' is not a table file of this toolkit: {what} is missing")]
    Missing { path: PathBuf, what: String },
    #[error("'{path}', {object}: {rule}")]
    Invalid {
        path: PathBuf,
        object: String,
        rule: String,
    },
    #[error("'{path}': HDF5 error while {action}: {source}")]
    Hdf5 {
        path: PathBuf,
        action: String,
        #[source]
        source: hdf5::Error,
    },
    #[error("'{path}': {source}")]
    Table {
        path: PathBuf,
        #[source]
        source: TrackError,
    },
    #[error(
        "'{path}' is not a results file of this toolkit (root attribute 'schema' is {}, expected \"railsim-results\")",
        match found { Some(s) => format!("\"{s}\""), None => "missing".to_string() }
    )]
    NotResults {
        path: PathBuf,
        found: Option<String>,
    },
    #[error(
        "'{path}' has results schema version {found}, which this build does not read (it reads versions 1 to {supported}); read it with the version of sim that wrote it"
    )]
    UnsupportedResultsVersion {
        path: PathBuf,
        found: u32,
        supported: u32,
    },
    #[error("'{path}': the run results are inconsistent: {source}")]
    InvalidResults {
        path: PathBuf,
        #[source]
        source: crate::results::ResultsError,
    },
    #[error("cannot write '{path}': {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}
