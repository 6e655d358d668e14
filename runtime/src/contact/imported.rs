//! A contact geometry table computed by another code and imported as is
//! (issue 6: cross-code comparisons): one contact point per wheel,
//! tabulated against the wheelset's lateral displacement y, with the
//! quasi-static normal force, the Hertz ellipse and Kalker's coefficients
//! at that point. The first such table is the `RSGEO.dat` of the open
//! simulator DYTSI (D. Bigoni, DTU, LGPL-3; the Cooperrider car), read by
//! `preproc::rsgeo`; its use in a run is [`crate::multibody::imported_contact`].
//!
//! # Which wheel a row describes, and the mirror
//!
//! The rows describe the **left** wheel (docs/reference/01-units-frames.md §1: y positive to the left).
//! In the shipped DYTSI table the left wheel's flange approaches its rail
//! as y grows — the contact angle rises from 0.014 rad at y = 0 to 0.57 rad
//! at y = +17 mm and the rolling radius from 0.4249 to 0.4508 m, while at
//! y = −17 mm the wheel rolls on its field side (δ = 0.044 rad, r = 0.4245
//! m) — and DYTSI's own reader (`WheelSetComponent::find_rsgeodata`) takes
//! the left wheel's row at y and the right wheel's at −y. Profiles are
//! symmetric, so the **right** wheel of a wheelset at y is the mirror image
//! of the left wheel of a wheelset at −y: [`ImportedContactTable::wheel_row`]
//! returns the row at −y for it, unchanged, because every quantity of a row
//! is already side-independent:
//!
//! - `wheel_lateral_m`: distance of the contact point on the wheel from the
//!   wheelset centre, positive outwards on either side;
//! - `contact_angle_rad`: tilt of the contact normal in the track
//!   cross-section, positive towards the track centre on either side (the
//!   sign rule of `crate::contact::Candidate::contact_angle_rad`);
//! - `rail_vertical_m`: height of the contact point on the rail (the rail's
//!   vertical coordinate, z up, from the rail-top plane);
//! - the others are magnitudes (force, semi-axes, radius, coefficients,
//!   penetration).
//!
//! # Interpolation
//!
//! Linear in y between rows, O(1) on the uniform grid (the row index is
//! computed, not searched). Outside the grid there is no contact data: in
//! that model the wheelset has derailed, and [`ImportedContactTable::row_at`]
//! says so, naming the range.

use crate::geometry::track::grid::{UniformGrid, lerp, within};

/// Names of the columns of [`ImportedRow::to_values`] after `y` (the HDF5
/// schema writes `y` first, then these).
pub const ROW_COLUMNS: [&str; 11] = [
    "normal_force",
    "contact_angle",
    "a",
    "b",
    "wheel_lateral",
    "rolling_radius",
    "c11",
    "c22",
    "c23",
    "rail_vertical",
    "penetration",
];

/// Units of [`ROW_COLUMNS`] ("1" for dimensionless).
pub const ROW_UNITS: [&str; 11] = ["N", "rad", "m", "m", "m", "m", "1", "1", "1", "m", "m"];

/// Relative tolerance of the uniform-grid check: every y within this
/// fraction of a step of y0 + i·h (the DYTSI file prints y to 11 significant
/// digits; its worst deviation is 5e-16 m on a 1e-5 m step).
const GRID_TOLERANCE: f64 = 1e-6;

/// The contact of one wheel at one lateral displacement (module docs for
/// the sign rules).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImportedRow {
    /// Quasi-static normal force N0 (N), > 0.
    pub normal_force_n: f64,
    /// Contact angle δ (rad), positive towards the track centre.
    pub contact_angle_rad: f64,
    /// Semi-axis of the contact ellipse in the rolling direction, a (m), at N0.
    pub a_m: f64,
    /// Lateral semi-axis, b (m), at N0.
    pub b_m: f64,
    /// Contact point on the wheel: lateral distance from the wheelset
    /// centre along the axle (m), positive outwards.
    pub wheel_lateral_m: f64,
    /// Rolling radius at the contact point (m).
    pub rolling_radius_m: f64,
    /// Kalker's coefficients at that ellipse (dimensionless).
    pub c11: f64,
    pub c22: f64,
    pub c23: f64,
    /// Vertical coordinate of the contact point on the rail (m), z up from
    /// the rail-top plane.
    pub rail_vertical_m: f64,
    /// Quasi-static penetration q0 (m), > 0: N = N0 (1 + Δq/q0)^1.5.
    pub penetration_m: f64,
}

impl ImportedRow {
    /// The values in the order of [`ROW_COLUMNS`].
    pub fn to_values(&self) -> [f64; 11] {
        [
            self.normal_force_n,
            self.contact_angle_rad,
            self.a_m,
            self.b_m,
            self.wheel_lateral_m,
            self.rolling_radius_m,
            self.c11,
            self.c22,
            self.c23,
            self.rail_vertical_m,
            self.penetration_m,
        ]
    }

    /// The row from values in the order of [`ROW_COLUMNS`].
    pub fn from_values(v: &[f64; 11]) -> Self {
        ImportedRow {
            normal_force_n: v[0],
            contact_angle_rad: v[1],
            a_m: v[2],
            b_m: v[3],
            wheel_lateral_m: v[4],
            rolling_radius_m: v[5],
            c11: v[6],
            c22: v[7],
            c23: v[8],
            rail_vertical_m: v[9],
            penetration_m: v[10],
        }
    }

    /// (1 − w) self + w other, field by field.
    fn lerp(&self, other: &ImportedRow, w: f64) -> ImportedRow {
        let (a, b) = (self.to_values(), other.to_values());
        let mut v = [0.0; 11];
        for (k, out) in v.iter_mut().enumerate() {
            *out = lerp(w, a[k], b[k]);
        }
        ImportedRow::from_values(&v)
    }

    /// Checks one row: every value finite; N0, q0, a, b, the rolling radius,
    /// the lateral position and C11, C22 > 0; |δ| < π/2.
    pub(crate) fn check(&self) -> Result<(), String> {
        let names = ROW_COLUMNS;
        for (name, v) in names.iter().zip(self.to_values()) {
            if !v.is_finite() {
                return Err(format!("{name} = {v} is not finite"));
            }
        }
        for (name, v) in [
            ("normal_force", self.normal_force_n),
            ("penetration", self.penetration_m),
            ("a", self.a_m),
            ("b", self.b_m),
            ("rolling_radius", self.rolling_radius_m),
            ("wheel_lateral", self.wheel_lateral_m),
            ("c11", self.c11),
            ("c22", self.c22),
        ] {
            if v <= 0.0 {
                return Err(format!("{name} = {v} must be > 0"));
            }
        }
        if self.contact_angle_rad.abs() >= std::f64::consts::FRAC_PI_2 {
            return Err(format!(
                "contact_angle = {} rad must lie within ±π/2",
                self.contact_angle_rad
            ));
        }
        Ok(())
    }
}

/// Why an imported table cannot be used or looked up.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImportedTableError {
    /// The lateral displacement lies outside the table: derailment in that
    /// model.
    #[error(
        "lateral displacement y = {y_mm:.3} mm is outside the imported contact table ({min_mm:.3} … {max_mm:.3} mm): the wheelset has derailed in that model"
    )]
    OutOfRange { y_mm: f64, min_mm: f64, max_mm: f64 },
    /// The table breaks a rule (row index 0-based, `None` for the whole table).
    #[error("imported contact table{}: {rule}", match row { Some(r) => format!(", row {r}"), None => String::new() })]
    Invalid { row: Option<usize>, rule: String },
}

/// A contact geometry table from another code (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedContactTable {
    /// Where it came from (file, code, commit), free text.
    pub source: String,
    /// The format it was read from (`rsgeo`).
    pub format: String,
    /// Lateral displacements of the wheelset (m): increasing, uniform.
    pub y_m: Vec<f64>,
    /// The left wheel's contact at each `y_m` (module docs).
    pub rows: Vec<ImportedRow>,
}

impl ImportedContactTable {
    /// Checks the table: at least two rows, as many rows as y values, y
    /// finite, increasing and uniform, rows on both sides of y = 0 (each
    /// wheel of a wheelset reads the table at ±y, "the mirror": a table
    /// that misses y = 0 cannot seat the centred wheelset), every row
    /// valid.
    pub fn validate(&self) -> Result<(), ImportedTableError> {
        let invalid = |row: Option<usize>, rule: String| ImportedTableError::Invalid { row, rule };
        let n = self.y_m.len();
        if n < 2 {
            return Err(invalid(None, format!("{n} rows; at least 2 are needed")));
        }
        if self.rows.len() != n {
            return Err(invalid(
                None,
                format!("{} rows for {n} lateral displacements", self.rows.len()),
            ));
        }
        if let Some(i) = self.y_m.iter().position(|y| !y.is_finite()) {
            return Err(invalid(Some(i), "y is not finite".into()));
        }
        let (y0, h) = (self.y_m[0], self.step_m());
        if h.is_nan() || h <= 0.0 {
            return Err(invalid(None, "y must increase".into()));
        }
        for (i, y) in self.y_m.iter().enumerate() {
            let expected = y0 + i as f64 * h;
            if (y - expected).abs() > GRID_TOLERANCE * h {
                return Err(invalid(
                    Some(i),
                    format!(
                        "y = {y} m is not on the uniform grid {y0} + i·{h} m (expected {expected} m): the table must be uniform in y"
                    ),
                ));
            }
        }
        let (lo, hi) = self.wheelset_range_m();
        if !(lo <= 0.0 && hi >= 0.0) {
            let (first, last) = self.range_m();
            return Err(invalid(
                None,
                format!(
                    "its rows cover y = {:.3} … {:.3} mm, which does not contain the centred \
                     wheelset (each wheel reads the table at ±y, so it needs rows on both sides \
                     of y = 0)",
                    first * 1e3,
                    last * 1e3
                ),
            ));
        }
        for (i, r) in self.rows.iter().enumerate() {
            r.check().map_err(|rule| invalid(Some(i), rule))?;
        }
        Ok(())
    }

    /// Step of the y grid (m).
    pub fn step_m(&self) -> f64 {
        let n = self.y_m.len();
        if n < 2 {
            return f64::NAN;
        }
        (self.y_m[n - 1] - self.y_m[0]) / (n - 1) as f64
    }

    /// Range of y covered (m).
    pub fn range_m(&self) -> (f64, f64) {
        (
            self.y_m.first().copied().unwrap_or(f64::NAN),
            self.y_m.last().copied().unwrap_or(f64::NAN),
        )
    }

    /// Lateral displacements of the wheelset at which both wheels have a
    /// row (m): the left wheel reads y, the right −y.
    pub fn wheelset_range_m(&self) -> (f64, f64) {
        let (lo, hi) = self.range_m();
        (lo.max(-hi), hi.min(-lo))
    }

    /// The row at lateral displacement `y_m` (m), interpolated linearly
    /// between the two neighbouring rows; O(1). Out of range: an error
    /// naming the range (derailment in that model).
    pub fn row_at(&self, y_m: f64) -> Result<ImportedRow, ImportedTableError> {
        let n = self.y_m.len();
        let (lo, hi) = self.range_m();
        let out_of_range = || ImportedTableError::OutOfRange {
            y_mm: y_m * 1e3,
            min_mm: lo * 1e3,
            max_mm: hi * 1e3,
        };
        if n < 2 || self.rows.len() != n {
            return Err(ImportedTableError::Invalid {
                row: None,
                rule: format!("{} rows for {n} lateral displacements", self.rows.len()),
            });
        }
        let grid = UniformGrid::spanning(lo, hi, n).ok_or_else(|| ImportedTableError::Invalid {
            row: None,
            rule: "y must increase".into(),
        })?;
        // A hair of slack at the ends: y_m[n − 1] computed from the grid
        // may differ from the stored one by round-off.
        let slack = GRID_TOLERANCE * grid.step();
        if !within(y_m, lo, hi, slack) {
            return Err(out_of_range());
        }
        // The row index from the grid formula, clamped (the stored y only
        // approximate y0 + i·h: `GRID_TOLERANCE`).
        let (i, w) = grid.cell(y_m);
        Ok(self.rows[i].lerp(&self.rows[i + 1], w))
    }

    /// The row of one wheel of a wheelset at lateral displacement `y_m`
    /// (m, + left): the left wheel's at y, the right wheel's at −y (module
    /// docs, "the mirror").
    pub fn wheel_row(
        &self,
        side: crate::geometry::track::Side,
        y_m: f64,
    ) -> Result<ImportedRow, ImportedTableError> {
        match side {
            crate::geometry::track::Side::Left => self.row_at(y_m),
            crate::geometry::track::Side::Right => self.row_at(-y_m),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::track::Side;

    fn row(y: f64) -> ImportedRow {
        ImportedRow {
            normal_force_n: 66_000.0 + 1e5 * y,
            contact_angle_rad: 0.014 + 10.0 * y,
            a_m: 6e-3,
            b_m: 6.5e-3,
            wheel_lateral_m: 0.756 - y,
            rolling_radius_m: 0.425 + 0.1 * y,
            c11: 4.1,
            c22: 3.6,
            c23: 1.4,
            rail_vertical_m: -6e-5,
            penetration_m: 7e-5,
        }
    }

    fn table() -> ImportedContactTable {
        let y_m: Vec<f64> = (0..=20).map(|i| -0.01 + 1e-3 * i as f64).collect();
        ImportedContactTable {
            source: "test".into(),
            format: "test".into(),
            rows: y_m.iter().map(|&y| row(y)).collect(),
            y_m,
        }
    }

    #[test]
    fn linear_interpolation_is_exact_on_linear_data() {
        let t = table();
        t.validate().unwrap();
        for y in [-0.01, -0.00731, 0.0, 0.00299, 0.01] {
            let r = t.row_at(y).unwrap();
            let e = row(y);
            for (a, b) in r.to_values().iter().zip(e.to_values()) {
                assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{y}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn out_of_range_names_the_range() {
        let t = table();
        let e = t.row_at(0.0105).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("10.500 mm"), "{msg}");
        assert!(msg.contains("-10.000 … 10.000 mm"), "{msg}");
        assert!(msg.contains("derailed"), "{msg}");
        assert!(t.row_at(f64::NAN).is_err());
        assert!(t.row_at(f64::INFINITY).is_err());
        // Within the hair of slack at the ends: the end rows.
        assert_eq!(t.row_at(0.01 + 1e-10).unwrap(), t.row_at(0.01).unwrap());
        // A table whose y do not increase is refused, not interpolated.
        let mut t = table();
        t.y_m.reverse();
        assert!(matches!(
            t.row_at(0.0),
            Err(ImportedTableError::Invalid { row: None, .. })
        ));
    }

    #[test]
    fn the_right_wheel_reads_the_mirrored_row() {
        let t = table();
        for y in [-0.004, 0.0, 0.0072] {
            assert_eq!(
                t.wheel_row(Side::Right, y).unwrap(),
                t.wheel_row(Side::Left, -y).unwrap()
            );
        }
        assert_eq!(t.wheelset_range_m(), (-0.01, 0.01));
    }

    #[test]
    fn bad_tables_are_refused_with_the_row() {
        let mut t = table();
        t.y_m[5] += 3e-4;
        let e = t.validate().unwrap_err().to_string();
        assert!(e.contains("row 5") && e.contains("uniform"), "{e}");
        let mut t = table();
        t.rows[3].penetration_m = 0.0;
        let e = t.validate().unwrap_err().to_string();
        assert!(e.contains("row 3") && e.contains("penetration"), "{e}");
        let mut t = table();
        t.rows.pop();
        assert!(t.validate().is_err());
        // Rows on one side of y = 0 only: the centred wheelset has none.
        let mut t = table();
        t.y_m.truncate(8);
        t.rows.truncate(8);
        let e = t.validate().unwrap_err().to_string();
        assert!(
            e.contains("-10.000 … -3.000 mm") && e.contains("centred wheelset"),
            "{e}"
        );
    }
}
