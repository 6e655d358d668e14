//! The centreline database: position, track frame, cant, curvature and
//! torsion at a uniform step of the track distance `s`, plus the arc length
//! of each rail at that `s` (the s ↔ L mapping) and the irregularities
//! applied there (docs/reference/03-track-preproc.md §3c–g, §4).

use nalgebra::Vector3;

use super::grid::{UniformGrid, check_rows, lerp, lerp3, within};
use super::{Frame, Side, TrackError};

/// Column names of the centreline database, in file order.
pub const CENTERLINE_COLUMNS: [&str; 23] = [
    "s",
    "x",
    "y",
    "z",
    "tx",
    "ty",
    "tz",
    "nx",
    "ny",
    "nz",
    "bx",
    "by",
    "bz",
    "cant",
    "curvature",
    "horizontal_curvature",
    "torsion",
    "L_left",
    "L_right",
    "align_left",
    "align_right",
    "level_left",
    "level_right",
];

/// Units of [`CENTERLINE_COLUMNS`].
pub const CENTERLINE_UNITS: [&str; 23] = [
    "m", "m", "m", "m", "1", "1", "1", "1", "1", "1", "1", "1", "1", "rad", "1/m", "1/m", "1/m",
    "m", "m", "m", "m", "m", "m",
];

/// One row of the centreline database.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CenterlineRow {
    /// Track distance along the centreline (m).
    pub s_m: f64,
    /// Global position (m).
    pub position: [f64; 3],
    /// Track frame (cant included): tangent, lateral (left), normal.
    pub t: [f64; 3],
    pub n: [f64; 3],
    pub b: [f64; 3],
    /// Cant angle φ (rad), positive when the left rail is higher.
    pub cant_rad: f64,
    /// Frenet curvature |d²r/ds²| of the centreline (1/m, ≥ 0).
    pub curvature_1_m: f64,
    /// Signed curvature of the horizontal projection (1/m), positive for a
    /// curve turning left.
    pub horizontal_curvature_1_m: f64,
    /// Frenet torsion (1/m); 0 where the curvature vanishes.
    pub torsion_1_m: f64,
    /// Arc length of the left and right rail at this `s` (m).
    pub l_left_m: f64,
    pub l_right_m: f64,
    /// Irregularities applied at this `s` (m): lateral deviation of each rail
    /// along `n` (positive to the left) and vertical deviation along `b`
    /// (positive up).
    pub align_left_m: f64,
    pub align_right_m: f64,
    pub level_left_m: f64,
    pub level_right_m: f64,
}

impl CenterlineRow {
    /// The row as the values of [`CENTERLINE_COLUMNS`].
    pub fn to_columns(&self) -> [f64; 23] {
        let (p, t, n, b) = (self.position, self.t, self.n, self.b);
        [
            self.s_m,
            p[0],
            p[1],
            p[2],
            t[0],
            t[1],
            t[2],
            n[0],
            n[1],
            n[2],
            b[0],
            b[1],
            b[2],
            self.cant_rad,
            self.curvature_1_m,
            self.horizontal_curvature_1_m,
            self.torsion_1_m,
            self.l_left_m,
            self.l_right_m,
            self.align_left_m,
            self.align_right_m,
            self.level_left_m,
            self.level_right_m,
        ]
    }

    /// A row from the values of [`CENTERLINE_COLUMNS`].
    pub fn from_columns(c: &[f64; 23]) -> Self {
        CenterlineRow {
            s_m: c[0],
            position: [c[1], c[2], c[3]],
            t: [c[4], c[5], c[6]],
            n: [c[7], c[8], c[9]],
            b: [c[10], c[11], c[12]],
            cant_rad: c[13],
            curvature_1_m: c[14],
            horizontal_curvature_1_m: c[15],
            torsion_1_m: c[16],
            l_left_m: c[17],
            l_right_m: c[18],
            align_left_m: c[19],
            align_right_m: c[20],
            level_left_m: c[21],
            level_right_m: c[22],
        }
    }

    /// Arc length of one rail at this row (m).
    pub fn rail_l_m(&self, side: Side) -> f64 {
        match side {
            Side::Left => self.l_left_m,
            Side::Right => self.l_right_m,
        }
    }
}

/// Interpolated centreline point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CenterlinePoint {
    /// Track distance (m).
    pub s_m: f64,
    /// Position (m).
    pub position: Vector3<f64>,
    /// Track frame, interpolated component-wise (see [`super::RailPoint`]).
    pub frame: Frame,
    /// Cant (rad).
    pub cant_rad: f64,
    /// Frenet curvature (1/m).
    pub curvature_1_m: f64,
}

/// The centreline database held in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct CenterlineTable {
    rows: Vec<CenterlineRow>,
    grid: UniformGrid,
}

impl CenterlineTable {
    /// Wrap rows, checking finiteness, a uniform `s` step (last interval may
    /// be shorter) and rail arc lengths that increase with `s`.
    pub fn new(rows: Vec<CenterlineRow>) -> Result<Self, TrackError> {
        let table = "centerline";
        check_rows(table, rows.iter().map(CenterlineRow::to_columns))?;
        for (row, r) in rows.iter().enumerate() {
            if row > 0
                && (r.l_left_m <= rows[row - 1].l_left_m || r.l_right_m <= rows[row - 1].l_right_m)
            {
                return Err(TrackError::InvalidTable {
                    table,
                    row,
                    rule: "L_left and L_right must increase with s".into(),
                });
            }
        }
        let grid = UniformGrid::detect(|k| rows[k].s_m, rows.len()).map_err(|row| {
            TrackError::InvalidTable {
                table,
                row,
                rule: "s must increase in uniform steps (the last step may be shorter)".into(),
            }
        })?;
        Ok(Self { rows, grid })
    }

    /// The rows.
    pub fn rows(&self) -> &[CenterlineRow] {
        &self.rows
    }

    /// Table step in s (m).
    pub fn step_m(&self) -> f64 {
        self.grid.step()
    }

    /// Range of s: `(first, last)` (m).
    pub fn range_m(&self) -> (f64, f64) {
        (self.rows[0].s_m, self.rows[self.rows.len() - 1].s_m)
    }

    /// Track length (m).
    pub fn length_m(&self) -> f64 {
        let (a, b) = self.range_m();
        b - a
    }

    /// Interval and fraction for `s_m`, or `OutOfRange`.
    #[inline]
    fn locate(&self, s_m: f64) -> Result<(usize, f64), TrackError> {
        self.check_range(s_m)?;
        Ok(self.grid.locate(s_m, |k| self.rows[k].s_m))
    }

    /// `OutOfRange` unless `s_m` lies on the table (within 1 nm).
    #[inline]
    fn check_range(&self, s_m: f64) -> Result<(), TrackError> {
        let (lo, hi) = self.range_m();
        if !within(s_m, lo, hi, 1e-9) {
            return Err(TrackError::OutOfRange {
                table: "centerline",
                coordinate: "s",
                value_m: s_m,
                min_m: lo,
                max_m: hi,
            });
        }
        Ok(())
    }

    /// Centreline point at track distance `s_m` (linear interpolation, O(1)).
    pub fn at(&self, s_m: f64) -> Result<CenterlinePoint, TrackError> {
        let (i, f) = self.locate(s_m)?;
        let (r0, r1) = (&self.rows[i], &self.rows[i + 1]);
        let lerp3 = |a, b| lerp3(f, a, b);
        let lerp = |a, b| lerp(f, a, b);
        Ok(CenterlinePoint {
            s_m,
            position: lerp3(&r0.position, &r1.position),
            frame: self.frame(i, f),
            cant_rad: lerp(r0.cant_rad, r1.cant_rad),
            curvature_1_m: lerp(r0.curvature_1_m, r1.curvature_1_m),
        })
    }

    /// The frame at fraction `f` of interval `i`, interpolated component-wise.
    #[inline]
    fn frame(&self, i: usize, f: f64) -> Frame {
        let (r0, r1) = (&self.rows[i], &self.rows[i + 1]);
        Frame {
            t: lerp3(f, &r0.t, &r1.t),
            n: lerp3(f, &r0.n, &r1.n),
            b: lerp3(f, &r0.b, &r1.b),
        }
    }

    /// Arc length of rail `side` at centreline distance `s_m` (m), O(1).
    #[inline]
    pub fn rail_l(&self, side: Side, s_m: f64) -> Result<f64, TrackError> {
        let (i, f) = self.locate(s_m)?;
        Ok(self.rail_l_in(side, i, f))
    }

    /// Arc length of rail `side` at fraction `f` of interval `i` (m).
    #[inline]
    fn rail_l_in(&self, side: Side, i: usize, f: f64) -> f64 {
        lerp(
            f,
            self.rows[i].rail_l_m(side),
            self.rows[i + 1].rail_l_m(side),
        )
    }

    /// [`Self::rail_l`] from the interval `hint` (a patch followed from
    /// solve to solve moves little), leaving the interval used in it: the
    /// same value, found without the grid formula while `s_m` stays in
    /// the hinted interval ([`UniformGrid::locate_near`]).
    #[inline]
    pub(crate) fn rail_l_near(
        &self,
        side: Side,
        s_m: f64,
        hint: &std::cell::Cell<usize>,
    ) -> Result<f64, TrackError> {
        self.check_range(s_m)?;
        let (i, f) = self.grid.locate_near(s_m, hint, |k| self.rows[k].s_m);
        Ok(self.rail_l_in(side, i, f))
    }

    /// The frame of [`Self::at`] and the arc lengths of [`Self::rail_l`]
    /// (left, right) at `s_m` (m), from one lookup: the same values, for a
    /// caller that needs only these (the contact search, once per solve).
    #[inline]
    pub fn frame_and_rail_l(&self, s_m: f64) -> Result<(Frame, [f64; 2]), TrackError> {
        let (i, f) = self.locate(s_m)?;
        Ok((
            self.frame(i, f),
            [
                self.rail_l_in(Side::Left, i, f),
                self.rail_l_in(Side::Right, i, f),
            ],
        ))
    }

    /// Centreline distance at arc length `l_m` of rail `side` (m): the inverse
    /// of [`Self::rail_l`], by binary search on the (increasing) L column.
    pub fn s_at_rail_l(&self, side: Side, l_m: f64) -> Result<f64, TrackError> {
        let n = self.rows.len();
        let (lo, hi) = (self.rows[0].rail_l_m(side), self.rows[n - 1].rail_l_m(side));
        if !(l_m >= lo - 1e-9 && l_m <= hi + 1e-9) {
            return Err(TrackError::OutOfRange {
                table: side.rail_name(),
                coordinate: "L",
                value_m: l_m,
                min_m: lo,
                max_m: hi,
            });
        }
        let k = self.rows.partition_point(|r| r.rail_l_m(side) <= l_m);
        let i = k.clamp(1, n - 1) - 1;
        let (r0, r1) = (&self.rows[i], &self.rows[i + 1]);
        let (a, b) = (r0.rail_l_m(side), r1.rail_l_m(side));
        Ok(r0.s_m + (l_m - a) / (b - a) * (r1.s_m - r0.s_m))
    }
}

#[cfg(test)]
#[cfg(feature = "fixtures")] // the shared in-memory tables
mod tests {
    use super::*;

    /// Rows every 0.5 m; the rails' arc lengths not affine in s (as in a
    /// curve's transition), so that a wrong interval would give another
    /// value.
    fn table() -> CenterlineTable {
        crate::fixtures::tracks::straight_centerline(0.5, 20, |s| {
            (s + 1e-3 * s * s, s - 1e-3 * s * s)
        })
    }

    /// From any hint (none, right, neighbouring, far, out of range) the
    /// same bits as the plain look-up, and the hint left at the interval
    /// used; off the table the same error.
    #[test]
    fn rail_l_from_a_hint_is_the_plain_lookup() {
        let c = table();
        for s in [0.0, 0.3, 0.5, 2.74, 7.5, 9.99, 10.0] {
            for side in [Side::Left, Side::Right] {
                let plain = c.rail_l(side, s).expect("on the table");
                for h in [usize::MAX, 0, 5, 14, 15, 19, 20, 1000] {
                    let hint = std::cell::Cell::new(h);
                    let near = c.rail_l_near(side, s, &hint).expect("on the table");
                    assert_eq!(near.to_bits(), plain.to_bits(), "s {s}, hint {h}");
                    let i = hint.get();
                    assert!(
                        c.rows[i].s_m <= s && (s < c.rows[i + 1].s_m || i == 19),
                        "s {s}: interval {i}"
                    );
                }
            }
        }
        let hint = std::cell::Cell::new(3);
        assert!(matches!(
            c.rail_l_near(Side::Left, 10.5, &hint),
            Err(TrackError::OutOfRange { .. })
        ));
        assert!(c.rail_l_near(Side::Left, f64::NAN, &hint).is_err());
    }
}
