//! How a run reads an imported contact table between its rows: linearly
//! (ours, [`ImportedContactTable::row_at`]) or by a natural cubic spline
//! through every column (the published Cooperrider formulation: DYTSI
//! interpolates each RSGEO column with a GSL natural cubic spline,
//! docs/guide/cooperrider-cross-code.md, "Audit").
//!
//! The natural cubic spline (zero second derivative at both ends; de Boor,
//! *A Practical Guide to Splines*, 1978, ch. IV) is fitted once per column
//! on the table's uniform grid and evaluated in O(1). It is C² where the
//! linear interpolant is only C⁰: the slopes the dynamics feel between two
//! rows (the contact angle's dδ/dy, the rolling radius difference's dΔr/dy)
//! are continuous instead of piecewise constant. A spline can overshoot
//! between rows where a column bends sharply; a value that breaks a row's
//! rule (a force, semi-axis or penetration ≤ 0) is refused, naming y,
//! never clamped.

use std::sync::Arc;

use super::imported::{ImportedContactTable, ImportedRow, ImportedTableError, ROW_COLUMNS};
use crate::geometry::spline::{PiecewiseCubic, Scheme};
use crate::geometry::track::Side;
use crate::geometry::track::grid::within;

/// Interpolation of an imported table's columns between its rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TableInterpolation {
    /// Linear between neighbouring rows (ours).
    #[default]
    Linear,
    /// A natural cubic spline through each column (DYTSI's).
    CubicSpline,
}

impl TableInterpolation {
    pub fn name(self) -> &'static str {
        match self {
            TableInterpolation::Linear => "linear",
            TableInterpolation::CubicSpline => "cubic_spline",
        }
    }
}

/// The rows of both wheels of a wheelset, however they are interpolated.
pub trait ImportedRows {
    /// The row of one wheel at wheelset lateral displacement `y_m` (m, +
    /// left): the left wheel's at y, the right wheel's at −y
    /// ([`ImportedContactTable::wheel_row`], "the mirror").
    fn wheel_row(&self, side: Side, y_m: f64) -> Result<ImportedRow, ImportedTableError>;
    /// Lateral displacements at which both wheels have a row (m).
    fn wheelset_range_m(&self) -> (f64, f64);
}

impl ImportedRows for ImportedContactTable {
    fn wheel_row(&self, side: Side, y_m: f64) -> Result<ImportedRow, ImportedTableError> {
        ImportedContactTable::wheel_row(self, side, y_m)
    }

    fn wheelset_range_m(&self) -> (f64, f64) {
        ImportedContactTable::wheelset_range_m(self)
    }
}

/// A table read through one natural cubic spline per column (module docs).
#[derive(Debug, Clone)]
pub struct SplinedTable {
    table: Arc<ImportedContactTable>,
    /// One spline per column of [`ROW_COLUMNS`], in that order.
    columns: Vec<PiecewiseCubic>,
}

impl SplinedTable {
    /// Fits the splines of a valid table.
    pub fn fit(table: Arc<ImportedContactTable>) -> Result<Self, ImportedTableError> {
        table.validate()?;
        let values: Vec<[f64; 11]> = table.rows.iter().map(ImportedRow::to_values).collect();
        let columns = (0..ROW_COLUMNS.len())
            .map(|k| {
                let col: Vec<f64> = values.iter().map(|v| v[k]).collect();
                PiecewiseCubic::fit(Scheme::CubicNatural, &table.y_m, &col).map_err(|e| {
                    ImportedTableError::Invalid {
                        row: None,
                        rule: format!("column {}: no cubic spline: {e}", ROW_COLUMNS[k]),
                    }
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SplinedTable { table, columns })
    }

    /// The table the splines go through.
    pub fn table(&self) -> &ImportedContactTable {
        &self.table
    }

    /// The row at lateral displacement `y_m` (m) from the splines; out of
    /// range as [`ImportedContactTable::row_at`]; a spline value that breaks
    /// a row's rule is refused naming y (module docs).
    pub fn row_at(&self, y_m: f64) -> Result<ImportedRow, ImportedTableError> {
        let (lo, hi) = self.table.range_m();
        // The same hair of slack as the linear lookup (round-off of the
        // grid's last knot).
        let slack = 1e-6 * self.table.step_m();
        if !within(y_m, lo, hi, slack) {
            return Err(ImportedTableError::OutOfRange {
                y_mm: y_m * 1e3,
                min_mm: lo * 1e3,
                max_mm: hi * 1e3,
            });
        }
        let y = y_m.clamp(lo, hi);
        let mut v = [0.0; 11];
        for (out, s) in v.iter_mut().zip(&self.columns) {
            *out = s.value(y);
        }
        let row = ImportedRow::from_values(&v);
        row.check().map_err(|rule| ImportedTableError::Invalid {
            row: None,
            rule: format!(
                "the cubic spline through the columns gives, at y = {:.4} mm, {rule} (an overshoot between rows; use linear interpolation for this table)",
                y_m * 1e3
            ),
        })?;
        Ok(row)
    }
}

impl ImportedRows for SplinedTable {
    fn wheel_row(&self, side: Side, y_m: f64) -> Result<ImportedRow, ImportedTableError> {
        match side {
            Side::Left => self.row_at(y_m),
            Side::Right => self.row_at(-y_m),
        }
    }

    fn wheelset_range_m(&self) -> (f64, f64) {
        self.table.wheelset_range_m()
    }
}

/// The lookup a run uses: the table itself (linear) or its splines.
#[derive(Debug, Clone)]
pub enum ImportedLookup {
    Linear(Arc<ImportedContactTable>),
    CubicSpline(Arc<SplinedTable>),
}

impl ImportedLookup {
    /// The lookup of `table` with `interpolation` (splines fitted here).
    pub fn new(
        table: Arc<ImportedContactTable>,
        interpolation: TableInterpolation,
    ) -> Result<Self, ImportedTableError> {
        Ok(match interpolation {
            TableInterpolation::Linear => ImportedLookup::Linear(table),
            TableInterpolation::CubicSpline => {
                ImportedLookup::CubicSpline(Arc::new(SplinedTable::fit(table)?))
            }
        })
    }

    /// The table behind the lookup.
    pub fn table(&self) -> &ImportedContactTable {
        match self {
            ImportedLookup::Linear(t) => t,
            ImportedLookup::CubicSpline(s) => s.table(),
        }
    }
}

impl ImportedRows for ImportedLookup {
    fn wheel_row(&self, side: Side, y_m: f64) -> Result<ImportedRow, ImportedTableError> {
        match self {
            ImportedLookup::Linear(t) => ImportedRows::wheel_row(t.as_ref(), side, y_m),
            ImportedLookup::CubicSpline(s) => s.wheel_row(side, y_m),
        }
    }

    fn wheelset_range_m(&self) -> (f64, f64) {
        self.table().wheelset_range_m()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A table whose columns are a cubic in y (which a natural spline does
    /// not reproduce exactly at the ends, but to 1e-9 of the range inside)
    /// and a straight line.
    fn table(f: impl Fn(f64) -> f64) -> ImportedContactTable {
        let y_m: Vec<f64> = (0..=40).map(|i| -0.01 + 5e-4 * i as f64).collect();
        let rows = y_m
            .iter()
            .map(|&y| ImportedRow {
                normal_force_n: 66_000.0 + 1e6 * y,
                contact_angle_rad: f(y),
                a_m: 6e-3,
                b_m: 6.5e-3,
                wheel_lateral_m: 0.756 + 0.1 * y,
                rolling_radius_m: 0.425 + 0.05 * y,
                c11: 4.1,
                c22: 3.6,
                c23: 1.4,
                rail_vertical_m: -6e-5,
                penetration_m: 7e-5,
            })
            .collect();
        ImportedContactTable {
            source: "test".into(),
            format: "test".into(),
            y_m,
            rows,
        }
    }

    #[test]
    fn the_spline_goes_through_the_rows_and_follows_a_smooth_column_between_them() {
        let smooth = |y: f64| 0.014 + 3.0 * y + 2e3 * y * y;
        let t = Arc::new(table(smooth));
        let s = SplinedTable::fit(t.clone()).unwrap();
        for (y, r) in t.y_m.iter().zip(&t.rows) {
            let at = s.row_at(*y).unwrap();
            assert!((at.contact_angle_rad - r.contact_angle_rad).abs() < 1e-12);
            assert!((at.normal_force_n - r.normal_force_n).abs() < 1e-6);
        }
        // Half-way between rows inside the table: the spline follows the
        // parabola (error ~1e-9 rad), the linear interpolant misses it by
        // 2e3·(h/2)² = 1.25e-4 rad.
        let y = 0.00025;
        let exact = smooth(y);
        let spline = s.row_at(y).unwrap().contact_angle_rad;
        let linear = t.row_at(y).unwrap().contact_angle_rad;
        assert!((spline - exact).abs() < 1e-7, "{spline} vs {exact}");
        assert!((linear - exact).abs() > 1e-4, "{linear} vs {exact}");
    }

    #[test]
    fn the_lookup_mirrors_the_right_wheel_and_refuses_out_of_range() {
        let t = Arc::new(table(|y| 0.014 + 3.0 * y));
        let l = ImportedLookup::new(t.clone(), TableInterpolation::CubicSpline).unwrap();
        let y = 0.0031;
        assert_eq!(
            l.wheel_row(Side::Right, y).unwrap(),
            l.wheel_row(Side::Left, -y).unwrap()
        );
        assert!(matches!(
            l.wheel_row(Side::Left, 0.0105),
            Err(ImportedTableError::OutOfRange { .. })
        ));
        let lin = ImportedLookup::new(t.clone(), TableInterpolation::Linear).unwrap();
        assert_eq!(lin.wheel_row(Side::Left, y).unwrap(), t.row_at(y).unwrap());
    }

    #[test]
    fn an_overshoot_that_breaks_a_row_rule_is_refused_naming_y() {
        // A step in the normal force down to almost nothing: the spline
        // undershoots below zero next to it.
        let mut t = table(|y| 0.014 + 3.0 * y);
        for (i, r) in t.rows.iter_mut().enumerate() {
            r.normal_force_n = if i < 20 { 66_000.0 } else { 1.0 };
        }
        let s = SplinedTable::fit(Arc::new(t.clone())).unwrap();
        let bad = t
            .y_m
            .windows(2)
            .map(|w| 0.5 * (w[0] + w[1]))
            .find_map(|y| s.row_at(y).err());
        let e = bad.expect("an undershoot below zero").to_string();
        assert!(e.contains("normal_force") && e.contains("y = "), "{e}");
    }
}
