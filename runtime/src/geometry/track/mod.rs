//! Track databases in memory (paper §2, Fig. 1; docs/reference/03-track-preproc.md §3–4) and their O(1)
//! linear interpolation. Built by the pre-processor, read and written by
//! [`crate::io::schema`].

mod centerline_table;
mod design_elements;
mod frame;
pub(crate) mod grid;
mod rail_table;
mod straight;

pub use centerline_table::{
    CENTERLINE_COLUMNS, CENTERLINE_UNITS, CenterlinePoint, CenterlineRow, CenterlineTable,
};
pub use design_elements::{
    DesignElement, JOINT_TOLERANCE_M, MAX_CANT_RAD, MIN_RADIUS_M, PlanElementKind,
    check_design_elements,
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
    /// Spline scheme of the cant ("pchip", …; "design" for a track from
    /// design elements, "exact" for an ideal straight). Files written
    /// before it was recorded read as `scheme` (the cant used the
    /// centreline's scheme then).
    pub cant_scheme: String,
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
    /// The rail profile the track was built for, when it was given
    /// (`track-preproc build --rail`, a scene's tables); `None` for tracks
    /// built without one and for files written before it was recorded.
    pub rail_profile: Option<crate::geometry::profile::rail_cant::RailProfileRecord>,
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
    /// The plan elements of the design file the track was built from
    /// (clipped to the tables' stretch); empty for a track from control
    /// points or an ideal straight.
    pub design_elements: Vec<DesignElement>,
}

impl TrackTables {
    /// Checks that the tables describe one track (`docs/reference/04-table-files.md`):
    /// at sampled rows, every frame is orthonormal and right-handed
    /// (b = t × n), and each rail lies beside the centreline at about half
    /// the rail spacing along the centreline's lateral vector (left rail
    /// on its + side). Catches a table whose columns were relabelled or
    /// permuted (positions y ↔ z, a swapped vector) and tables of two
    /// different tracks, which would otherwise give wrong positions
    /// silently. Tolerances: 1e-3 on the frames; the rail offset within
    /// 25–150 % of half the spacing and within about 25° of the lateral
    /// vector (cant and irregularities stay far inside both).
    pub fn check_consistency(&self) -> Result<(), TrackError> {
        fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
            a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
        }
        fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        }
        fn frame(
            table: &'static str,
            row: usize,
            t: [f64; 3],
            n: [f64; 3],
            b: [f64; 3],
        ) -> Result<(), TrackError> {
            let txn = cross(t, n);
            let off = [
                (dot(t, t) - 1.0).abs(),
                (dot(n, n) - 1.0).abs(),
                dot(t, n).abs(),
                (0..3).map(|i| (b[i] - txn[i]).abs()).fold(0.0, f64::max),
            ];
            if off.iter().any(|e| e.is_nan() || *e >= 1e-3) {
                return Err(TrackError::InvalidTable {
                    table,
                    row,
                    rule: "the frame t, n, b is not orthonormal with b = t × n (permuted or relabelled columns?)".into(),
                });
            }
            Ok(())
        }
        let rows = self.centerline.rows();
        let samples = 64.min(rows.len());
        let half_spacing = 0.5 * self.meta.rail_spacing_m;
        for j in 0..samples {
            let k = j * (rows.len() - 1) / (samples - 1).max(1);
            let c = &rows[k];
            frame("centerline", k, c.t, c.n, c.b)?;
            for (rail, l_m, sign) in [
                (&self.left, c.l_left_m, 1.0),
                (&self.right, c.l_right_m, -1.0),
            ] {
                let (l0, _) = rail.range_m();
                let r_rows = rail.rows();
                let i =
                    (((l_m - l0) / rail.step_m()).round().max(0.0) as usize).min(r_rows.len() - 1);
                let r = &r_rows[i];
                frame(rail.side().rail_name(), i, r.t, r.n, r.b)?;
                let d = [
                    r.position[0] - c.position[0],
                    r.position[1] - c.position[1],
                    r.position[2] - c.position[2],
                ];
                let dist = dot(d, d).sqrt();
                let lateral = sign * dot(d, c.n);
                let ok = half_spacing > 0.0
                    && (0.25 * half_spacing..=1.5 * half_spacing).contains(&dist)
                    && lateral >= 0.9 * dist;
                if !ok {
                    return Err(TrackError::InvalidTable {
                        table: rail.side().rail_name(),
                        row: i,
                        rule: format!(
                            "the rail is {dist:.3} m from the centreline at s = {:.2} m, {:.3} m of it along the lateral vector (expected about {half_spacing:.3} m, on the {} side): the tables do not describe one track (permuted or relabelled columns?)",
                            c.s_m,
                            lateral,
                            if sign > 0.0 { "left" } else { "right" }
                        ),
                    });
                }
            }
        }
        Ok(())
    }

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
