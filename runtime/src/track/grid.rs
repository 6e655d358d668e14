//! O(1) location of an abscissa in a table whose rows are equally spaced,
//! except that the last interval may be shorter (the table ends exactly at
//! the end of the track).

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
