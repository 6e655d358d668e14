//! One rail's database (paper Fig. 1, docs/reference/03-track-preproc.md §3g): rows at a uniform step of
//! the rail's own arc length `L`, with the position of the rail's profile
//! origin and its frame `(t, n, b)` (cant and rail inclination included).
//! Looked up by linear interpolation in O(1) (paper §2g).

use std::cell::Cell;

use nalgebra::Vector3;

use super::grid::{UniformGrid, check_rows, lerp3, within};
use super::{Frame, Side, TrackError};

/// Column names of a rail database, in file order (docs/reference/03-track-preproc.md §3g).
pub const RAIL_COLUMNS: [&str; 13] = [
    "L", "x", "y", "z", "tx", "ty", "tz", "nx", "ny", "nz", "bx", "by", "bz",
];
/// Units of [`RAIL_COLUMNS`] ("1" = dimensionless).
pub const RAIL_UNITS: [&str; 13] = [
    "m", "m", "m", "m", "1", "1", "1", "1", "1", "1", "1", "1", "1",
];

/// One row of a rail database.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RailRow {
    /// Arc length along this rail from its start (m).
    pub l_m: f64,
    /// Global position of the rail profile origin (m).
    pub position: [f64; 3],
    /// Unit tangent.
    pub t: [f64; 3],
    /// Unit lateral vector (pointing left, rolled by cant ± inclination).
    pub n: [f64; 3],
    /// Unit normal `t × n` (up-ish).
    pub b: [f64; 3],
}

impl RailRow {
    /// The row as the 13 values of [`RAIL_COLUMNS`].
    pub fn to_columns(&self) -> [f64; 13] {
        let p = self.position;
        let (t, n, b) = (self.t, self.n, self.b);
        [
            self.l_m, p[0], p[1], p[2], t[0], t[1], t[2], n[0], n[1], n[2], b[0], b[1], b[2],
        ]
    }

    /// A row from the 13 values of [`RAIL_COLUMNS`].
    pub fn from_columns(c: &[f64; 13]) -> Self {
        RailRow {
            l_m: c[0],
            position: [c[1], c[2], c[3]],
            t: [c[4], c[5], c[6]],
            n: [c[7], c[8], c[9]],
            b: [c[10], c[11], c[12]],
        }
    }
}

/// Interpolated rail point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailPoint {
    /// Rail arc length (m).
    pub l_m: f64,
    /// Position of the profile origin (m).
    pub position: Vector3<f64>,
    /// Frame, interpolated component-wise: not re-normalised, its vectors are
    /// unit to within (Δθ)²/8, Δθ the frame's rotation over one table step
    /// (1.4e-8 for a 0.1 m step on a 300 m curve).
    pub frame: Frame,
}

/// A rail database held in memory.
#[derive(Debug, Clone, PartialEq)]
pub struct RailTable {
    side: Side,
    rows: Vec<RailRow>,
    grid: UniformGrid,
    /// L of the first and the last row (m).
    range_m: (f64, f64),
}

impl RailTable {
    /// Wrap rows, checking that `L` is finite, starts the table, and is
    /// uniformly spaced (the last interval may be shorter).
    pub fn new(side: Side, rows: Vec<RailRow>) -> Result<Self, TrackError> {
        let table = side.rail_name();
        check_rows(table, rows.iter().map(RailRow::to_columns))?;
        let grid = UniformGrid::detect(|k| rows[k].l_m, rows.len()).map_err(|row| {
            TrackError::InvalidTable {
                table,
                row,
                rule: "L must increase in uniform steps (the last step may be shorter)".into(),
            }
        })?;
        let range_m = match (rows.first(), rows.last()) {
            (Some(first), Some(last)) => (first.l_m, last.l_m),
            // check_rows has refused a table of fewer than two rows.
            _ => (f64::NAN, f64::NAN),
        };
        Ok(Self {
            side,
            rows,
            grid,
            range_m,
        })
    }

    /// Which rail this is.
    pub fn side(&self) -> Side {
        self.side
    }

    /// The rows.
    pub fn rows(&self) -> &[RailRow] {
        &self.rows
    }

    /// Table step in L (m).
    pub fn step_m(&self) -> f64 {
        self.grid.step()
    }

    /// Range of L covered: `(first, last)` (m).
    pub fn range_m(&self) -> (f64, f64) {
        self.range_m
    }

    /// Position and frame at arc length `l_m` by linear interpolation between
    /// the two neighbouring rows (paper §2g). O(1).
    ///
    /// Errors with [`TrackError::OutOfRange`] outside the table (a tolerance
    /// of 1e-9 m is allowed at both ends).
    #[inline]
    pub fn at(&self, l_m: f64) -> Result<RailPoint, TrackError> {
        let (i, f) = self.locate_checked(l_m)?;
        let (r0, r1) = self.interval_rows(l_m, i)?;
        Ok(interpolate(l_m, r0, r1, f))
    }

    /// The position of [`Self::at`] alone (m): the same values, without
    /// interpolating the frame.
    #[inline]
    pub fn position_at(&self, l_m: f64) -> Result<Vector3<f64>, TrackError> {
        let (i, f) = self.locate_checked(l_m)?;
        let (r0, r1) = self.interval_rows(l_m, i)?;
        Ok(lerp3(f, &r0.position, &r1.position))
    }

    /// Interval and fraction of `l_m`, or [`TrackError::OutOfRange`].
    #[inline]
    fn locate_checked(&self, l_m: f64) -> Result<(usize, f64), TrackError> {
        self.check_range(l_m)?;
        Ok(self.grid.locate(l_m, |k| self.rows[k].l_m))
    }

    /// [`TrackError::OutOfRange`] unless `l_m` lies in the table (1e-9 m
    /// of slack at both ends).
    #[inline]
    fn check_range(&self, l_m: f64) -> Result<(), TrackError> {
        let (lo, hi) = self.range_m();
        if !within(l_m, lo, hi, 1e-9) {
            return Err(self.out_of_range(l_m));
        }
        Ok(())
    }

    /// The error for `l_m` outside the table.
    #[cold]
    fn out_of_range(&self, l_m: f64) -> TrackError {
        let (lo, hi) = self.range_m();
        TrackError::OutOfRange {
            table: self.side.rail_name(),
            coordinate: "L",
            value_m: l_m,
            min_m: lo,
            max_m: hi,
        }
    }

    /// Rows `i` and `i + 1`, the ends of interval `i` (one bounds check for
    /// both); the interval of a located `l_m` always has them, an error
    /// otherwise.
    #[inline(always)]
    fn interval_rows(&self, l_m: f64, i: usize) -> Result<(&RailRow, &RailRow), TrackError> {
        match self.rows.get(i..) {
            Some([r0, r1, ..]) => Ok((r0, r1)),
            _ => Err(self.out_of_range(l_m)),
        }
    }

    /// [`Self::locate_checked`] from the interval `hint`
    /// ([`UniformGrid::locate_near`]: the same interval and fraction).
    #[inline]
    fn locate_checked_near(
        &self,
        l_m: f64,
        hint: &Cell<usize>,
    ) -> Result<(usize, f64), TrackError> {
        self.check_range(l_m)?;
        Ok(self.grid.locate_near(l_m, hint, |k| self.rows[k].l_m))
    }
}

/// The point at fraction `f` of the interval from row `r0` to row `r1`.
#[inline(always)]
fn interpolate(l_m: f64, r0: &RailRow, r1: &RailRow, f: f64) -> RailPoint {
    let lerp = |a, b| lerp3(f, a, b);
    RailPoint {
        l_m,
        position: lerp(&r0.position, &r1.position),
        frame: Frame {
            t: lerp(&r0.t, &r1.t),
            n: lerp(&r0.n, &r1.n),
            b: lerp(&r0.b, &r1.b),
        },
    }
}

/// Derivatives with respect to L of the linearly interpolated rail
/// quantities: constant over each table interval (the row difference over
/// the step), consistent with the linear interpolation of paper §2g.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RailPointDerivative {
    /// dp/dL (–), ≈ t.
    pub position: Vector3<f64>,
    /// dt/dL, dn/dL, db/dL (1/m).
    pub t: Vector3<f64>,
    pub n: Vector3<f64>,
    pub b: Vector3<f64>,
}

impl RailTable {
    /// Position, frame and their L-derivatives at `l_m` (see [`Self::at`]).
    #[inline]
    pub fn at_with_derivative(
        &self,
        l_m: f64,
    ) -> Result<(RailPoint, RailPointDerivative), TrackError> {
        // One interval lookup serves the point and its derivatives (the
        // same interval `at` finds, so the same values).
        let (i, f) = self.locate_checked(l_m)?;
        self.with_derivative(l_m, i, f)
    }

    /// [`Self::at_with_derivative`], looking the interval up from `hint`
    /// first and leaving the interval used in it (the same values bit for
    /// bit; see [`Self::locate_checked_near`]).
    #[inline]
    pub(crate) fn at_with_derivative_near(
        &self,
        l_m: f64,
        hint: &Cell<usize>,
    ) -> Result<(RailPoint, RailPointDerivative), TrackError> {
        let (i, f) = self.locate_checked_near(l_m, hint)?;
        self.with_derivative(l_m, i, f)
    }

    /// Point and derivatives at fraction `f` of interval `i`.
    #[inline(always)]
    fn with_derivative(
        &self,
        l_m: f64,
        i: usize,
        f: f64,
    ) -> Result<(RailPoint, RailPointDerivative), TrackError> {
        let (r0, r1) = self.interval_rows(l_m, i)?;
        let p = interpolate(l_m, r0, r1, f);
        let inv = 1.0 / (r1.l_m - r0.l_m);
        let diff = |a: &[f64; 3], b: &[f64; 3]| {
            Vector3::new(
                (b[0] - a[0]) * inv,
                (b[1] - a[1]) * inv,
                (b[2] - a[2]) * inv,
            )
        };
        Ok((
            p,
            RailPointDerivative {
                position: diff(&r0.position, &r1.position),
                t: diff(&r0.t, &r1.t),
                n: diff(&r0.n, &r1.n),
                b: diff(&r0.b, &r1.b),
            },
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight(step: f64, length: f64) -> RailTable {
        let mut rows = Vec::new();
        let mut k = 0;
        loop {
            let l = (k as f64 * step).min(length);
            rows.push(RailRow {
                l_m: l,
                position: [l, 0.75, 0.0],
                t: [1.0, 0.0, 0.0],
                n: [0.0, 1.0, 0.0],
                b: [0.0, 0.0, 1.0],
            });
            if l >= length {
                break;
            }
            k += 1;
        }
        RailTable::new(Side::Left, rows).unwrap()
    }

    #[test]
    fn interpolates_inside_and_at_the_short_last_interval() {
        let t = straight(0.1, 10.05);
        assert_eq!(t.rows().len(), 102);
        for l in [0.0, 0.05, 3.333, 9.99, 10.02, 10.05] {
            let p = t.at(l).unwrap();
            assert!((p.position.x - l).abs() < 1e-12, "{l}");
            assert_eq!(p.frame.n, Vector3::y());
        }
    }

    #[test]
    fn out_of_range_is_an_error() {
        let t = straight(0.5, 3.0);
        let e = t.at(3.1).unwrap_err();
        assert!(matches!(e, TrackError::OutOfRange { .. }));
        assert!(e.to_string().contains("left rail"), "{e}");
        assert!(t.at(-0.2).is_err());
        assert!(t.at(f64::NAN).is_err());
    }

    #[test]
    fn non_uniform_rows_are_rejected() {
        let mut rows: Vec<RailRow> = straight(1.0, 5.0).rows().to_vec();
        rows[2].l_m += 0.3;
        let e = RailTable::new(Side::Right, rows).unwrap_err();
        assert!(matches!(e, TrackError::InvalidTable { row: 2, .. }), "{e}");
    }

    #[test]
    fn columns_round_trip() {
        let r = straight(1.0, 2.0).rows()[1];
        assert_eq!(RailRow::from_columns(&r.to_columns()), r);
    }
}
