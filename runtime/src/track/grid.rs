//! O(1) location of an abscissa in a table whose rows are equally spaced,
//! except that the last interval may be shorter (the table ends exactly at
//! the end of the track).

use nalgebra::Vector3;

use super::TrackError;

/// Uniform row spacing `h` from `x0`; `intervals` = rows − 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct UniformGrid {
    x0: f64,
    inv_h: f64,
    intervals: usize,
}

impl UniformGrid {
    /// Check that `xs` (the table's first column) is uniform with step
    /// `xs[1] − xs[0]` up to the last interval, which may be shorter.
    /// On failure returns the first offending row.
    pub(crate) fn detect(xs: impl Fn(usize) -> f64, rows: usize) -> Result<Self, usize> {
        if rows < 2 {
            return Err(rows);
        }
        let h = xs(1) - xs(0);
        if !(h > 0.0 && h.is_finite()) {
            return Err(1);
        }
        let tol = 1e-6 * h;
        for k in 1..rows {
            let expected = xs(0) + k as f64 * h;
            let x = xs(k);
            let ok = if k == rows - 1 {
                x > xs(k - 1) && x <= expected + tol
            } else {
                (x - expected).abs() <= tol.max(1e-12 * expected.abs())
            };
            if !ok || !x.is_finite() {
                return Err(k);
            }
        }
        Ok(Self {
            x0: xs(0),
            inv_h: 1.0 / h,
            intervals: rows - 1,
        })
    }

    /// Interval `i` (rows `i`, `i+1`) holding `x`, for `x` inside the table;
    /// `key(i)` is the abscissa of row `i` (used to correct round-off).
    #[inline]
    pub(crate) fn interval(&self, x: f64, key: impl Fn(usize) -> f64) -> usize {
        let last = self.intervals - 1;
        let g = (x - self.x0) * self.inv_h;
        let mut i = if g <= 0.0 {
            0
        } else if g >= last as f64 {
            last
        } else {
            g as usize
        };
        if i > 0 && x < key(i) {
            i -= 1;
        } else if i < last && x >= key(i + 1) {
            i += 1;
        }
        i
    }

    /// Row spacing (m).
    pub(crate) fn step(&self) -> f64 {
        1.0 / self.inv_h
    }
}

/// `a + f (b − a)` for 3-vectors stored as arrays.
#[inline]
pub(crate) fn lerp3(f: f64, a: &[f64; 3], b: &[f64; 3]) -> Vector3<f64> {
    Vector3::new(
        a[0] + f * (b[0] - a[0]),
        a[1] + f * (b[1] - a[1]),
        a[2] + f * (b[2] - a[2]),
    )
}

/// Check a table has at least two rows, all finite (`rows` yields each
/// row's values).
pub(crate) fn check_rows<const N: usize>(
    table: &'static str,
    rows: impl ExactSizeIterator<Item = [f64; N]>,
) -> Result<(), TrackError> {
    let len = rows.len();
    if len < 2 {
        return Err(TrackError::InvalidTable {
            table,
            row: len,
            rule: "a table needs at least 2 rows".into(),
        });
    }
    for (row, values) in rows.enumerate() {
        if values.iter().any(|v| !v.is_finite()) {
            return Err(TrackError::InvalidTable {
                table,
                row,
                rule: "non-finite value".into(),
            });
        }
    }
    Ok(())
}
