//! Track databases in memory (paper §2, Fig. 1; docs/reference/03-track-preproc.md §3–4) and their O(1)
//! linear interpolation. Built by the pre-processor, read and written by
//! [`crate::io::schema`].

mod centerline_table;
mod frame;
pub(crate) mod grid;
mod rail_table;
mod straight;

pub use centerline_table::{
    CENTERLINE_COLUMNS, CENTERLINE_UNITS, CenterlinePoint, CenterlineRow, CenterlineTable,
};
pub use frame::{Frame, rail_roll_rad};
pub use rail_table::{
    RAIL_COLUMNS, RAIL_UNITS, RailPoint, RailPointDerivative, RailRow, RailTable,
};
pub use straight::straight_track;

use std::fmt;

/// Left or right, as seen facing the direction of increasing track distance.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    Left,
    Right,
}

impl Side {
    /// Both sides, left first.
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    /// +1 for left, −1 for right: the sign of the side's lateral offset along `n`.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }

    /// "left rail" / "right rail".
    pub fn rail_name(self) -> &'static str {
        match self {
            Side::Left => "left rail",
            Side::Right => "right rail",
        }
    }

    /// "left" / "right".
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

impl fmt::Display for Side {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Errors of table look-ups and table validation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TrackError {
    #[error("{coordinate} = {value_m} m is outside the {table} table ({min_m} … {max_m} m)")]
    OutOfRange {
        table: &'static str,
        coordinate: &'static str,
        value_m: f64,
        min_m: f64,
        max_m: f64,
    },
    #[error("{table} table, row {row}: {rule}")]
    InvalidTable {
        table: &'static str,
        row: usize,
        rule: String,
    },
}

/// Parameters a track was built with (root attributes of the table file).
#[derive(Debug, Clone, PartialEq)]
pub struct TrackMeta {
    /// Spline scheme of the centreline and rails ("cubic", "akima", …).
    pub scheme: String,
    /// Table step Δs (m).
    pub step_m: f64,
    /// Nominal track gauge (m).
    pub gauge_m: f64,
    /// Nominal lateral distance between the two rail profile origins (m).
    pub rail_spacing_m: f64,
    /// Distance between rail contact points used to convert a cant height to
    /// an angle, φ = asin(h/e0) (m).
    pub cant_base_m: f64,
    /// Rail inclination as given ("1:40", "0", …).
    pub rail_inclination: String,
    /// Rail inclination angle towards the track centre (rad).
    pub rail_inclination_rad: f64,
    /// Program and version that wrote the file.
    pub tool: String,
    pub tool_version: String,
}

/// Provenance stored under `/input`: the exact input files and the command line.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Provenance {
    /// The command line that built the file.
    pub command_line: String,
    /// Input files: role ("centerline", "cant", "irregularities", …), path as
    /// given, and full text.
    pub inputs: Vec<InputFile>,
}

/// One input file kept for provenance.
#[derive(Debug, Clone, PartialEq)]
pub struct InputFile {
    pub role: String,
    pub path: String,
    pub text: String,
}

/// A whole track: centreline and both rail databases.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackTables {
    pub meta: TrackMeta,
    pub centerline: CenterlineTable,
    pub left: RailTable,
    pub right: RailTable,
}

impl TrackTables {
    /// The database of one rail.
    pub fn rail(&self, side: Side) -> &RailTable {
        match side {
            Side::Left => &self.left,
            Side::Right => &self.right,
        }
    }

    /// Position and frame of rail `side` at centreline distance `s_m`:
    /// maps s → L with the centreline table, then interpolates the rail.
    pub fn rail_at_s(&self, side: Side, s_m: f64) -> Result<RailPoint, TrackError> {
        let l = self.centerline.rail_l(side, s_m)?;
        self.rail(side).at(l)
    }
}
