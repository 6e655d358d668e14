//! Location and linear interpolation in tabulated data, shared by every
//! table of the run time: the track's centreline and rail tables
//! (`super::centerline_table`, `super::rail_table`; paper §2g), the
//! contact lookup table ([`crate::contact::table`]; docs/reference/07-contact-forces.md §7.4) and the
//! imported contact table ([`crate::contact::imported`]).
//!
//! A table's first column is a grid x_0 < x_1 < … < x_n. Its rows are
//! equally spaced (step h), except that a track table's last interval may
//! be shorter (the table ends exactly at the end of the track). The grid
//! is located in O(1): the interval is computed from h, not searched.
//! Linear interpolation between rows i and i + 1 at fraction f ∈ [0, 1]
//! is a + f (b − a) ([`lerp`], [`lerp3`]).
//!
//! Range checks stay with each table (its own error, its own slack at the
//! ends: [`within`]); the locators never fail and never panic: an abscissa
//! outside the grid or not finite gives the first or the last interval
//! (NaN: the first), and its fraction extrapolates (or is NaN).

use nalgebra::Vector3;

use super::TrackError;

/// Whether `x` lies in `[lo − slack, hi + slack]` (false for NaN).
#[inline]
pub(crate) fn within(x: f64, lo: f64, hi: f64, slack: f64) -> bool {
    x >= lo - slack && x <= hi + slack
}

/// A grid of equally spaced rows x_i = x0 + i h, i = 0 … `intervals`
/// (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct UniformGrid {
    x0: f64,
    h: f64,
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
            h,
            inv_h: 1.0 / h,
            intervals: rows - 1,
        })
    }

    /// The grid of `rows` rows from `first` to `last` (step
    /// (last − first)/(rows − 1)), without checking the rows in between
    /// (their table does); `None` with fewer than 2 rows or a step that is
    /// not finite and > 0.
    pub(crate) fn spanning(first: f64, last: f64, rows: usize) -> Option<Self> {
        if rows < 2 {
            return None;
        }
        let h = (last - first) / (rows - 1) as f64;
        if !(h > 0.0 && h.is_finite()) {
            return None;
        }
        Some(Self {
            x0: first,
            h,
            inv_h: 1.0 / h,
            intervals: rows - 1,
        })
    }

    /// Interval `i` (rows `i`, `i+1`) holding `x`: key(i) ≤ x < key(i + 1),
    /// the first interval below the table, the last at and above its last
    /// row. `key(i)` is the abscissa of row `i`: the interval computed from
    /// the step is corrected against the stored rows (round-off, and a
    /// shorter last interval), so the answer is that of a search of the
    /// rows for any increasing grid (O(1) when it is uniform).
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
        while i > 0 && x < key(i) {
            i -= 1;
        }
        while i < last && x >= key(i + 1) {
            i += 1;
        }
        i
    }

    /// [`Self::locate`], trying the interval `hint` first (a solver's
    /// iterates move little between two evaluations) and leaving the
    /// interval used in it: the same interval and fraction in every case
    /// ([`Self::interval`]'s is the one interval whose rows bracket `x`, the
    /// first and the last open-ended), found without the grid formula
    /// while `x` stays in the hinted one.
    #[inline]
    pub(crate) fn locate_near(
        &self,
        x: f64,
        hint: &std::cell::Cell<usize>,
        key: impl Fn(usize) -> f64,
    ) -> (usize, f64) {
        let last = self.intervals - 1;
        let h = hint.get();
        let i = if h <= last && (h == 0 || key(h) <= x) && (h == last || x < key(h + 1)) {
            h
        } else {
            self.interval(x, &key)
        };
        hint.set(i);
        let (a, b) = (key(i), key(i + 1));
        (i, (x - a) / (b - a))
    }

    /// Interval and fraction of `x` against the stored rows:
    /// `(i, (x − key(i))/(key(i + 1) − key(i)))` with `i` from
    /// [`Self::interval`]; the fraction lies outside [0, 1] outside the
    /// table (linear extrapolation).
    #[inline]
    pub(crate) fn locate(&self, x: f64, key: impl Fn(usize) -> f64) -> (usize, f64) {
        let i = self.interval(x, &key);
        let (a, b) = (key(i), key(i + 1));
        (i, (x - a) / (b - a))
    }

    /// Interval and fraction of `x` from the grid formula alone, clamped to
    /// the grid: g = (x − x0)/h in [0, intervals], i = min(⌊g⌋,
    /// intervals − 1), fraction g − i ∈ [0, 1] (for tables whose stored
    /// abscissae only approximate x0 + i h, the imported contact table's).
    #[inline]
    pub(crate) fn cell(&self, x: f64) -> (usize, f64) {
        let g = ((x - self.x0) / self.h).clamp(0.0, self.intervals as f64);
        let i = (g.floor() as usize).min(self.intervals - 1);
        (i, g - i as f64)
    }

    /// Row spacing (m).
    pub(crate) fn step(&self) -> f64 {
        self.h
    }
}

/// `a + f (b − a)`: linear interpolation at fraction `f` from `a` to `b`.
#[inline]
pub(crate) fn lerp(f: f64, a: f64, b: f64) -> f64 {
    a + f * (b - a)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows every 0.1 from 2.0, the last interval 0.04 long.
    fn track_like() -> (Vec<f64>, UniformGrid) {
        let mut xs: Vec<f64> = (0..=10).map(|k| 2.0 + 0.1 * k as f64).collect();
        xs.push(3.04);
        let g = UniformGrid::detect(|k| xs[k], xs.len()).unwrap();
        (xs, g)
    }

    /// The interval of a search of the rows (what the locators must give).
    fn searched(xs: &[f64], x: f64) -> usize {
        xs.partition_point(|&v| v <= x).clamp(1, xs.len() - 1) - 1
    }

    #[test]
    fn rows_and_points_between_them_find_their_interval() {
        let (xs, g) = track_like();
        assert_eq!(g.step(), xs[1] - xs[0]);
        for (k, &x) in xs.iter().enumerate() {
            let (i, f) = g.locate(x, |j| xs[j]);
            // A row starts its interval; the last row ends the last one.
            let expected = k.min(xs.len() - 2);
            assert_eq!(i, expected, "row {k}");
            assert_eq!(f, if k == xs.len() - 1 { 1.0 } else { 0.0 });
        }
        for x in [2.0, 2.05, 2.1 - 1e-15, 2.999, 3.0, 3.02, 3.04] {
            assert_eq!(g.interval(x, |j| xs[j]), searched(&xs, x), "{x}");
        }
        // The shorter last interval: the fraction uses its own length.
        let (i, f) = g.locate(3.02, |j| xs[j]);
        assert_eq!(i, 10);
        assert!((f - 0.5).abs() < 1e-12);
    }

    #[test]
    fn out_of_range_gives_the_end_intervals_and_extrapolates() {
        let (xs, g) = track_like();
        let (i, f) = g.locate(1.95, |j| xs[j]);
        assert_eq!(i, 0);
        assert!((f + 0.5).abs() < 1e-12);
        let (i, f) = g.locate(3.06, |j| xs[j]);
        assert_eq!(i, 10);
        assert!((f - 1.5).abs() < 1e-12);
        // The tables' range checks.
        assert!(within(3.04 + 5e-10, 2.0, 3.04, 1e-9));
        assert!(!within(3.04 + 2e-9, 2.0, 3.04, 1e-9));
        assert!(within(2.0, 2.0, 3.04, 0.0) && within(3.04, 2.0, 3.04, 0.0));
        assert!(!within(2.0 - 1e-15, 2.0, 3.04, 0.0));
    }

    #[test]
    fn non_finite_abscissae_neither_panic_nor_pass_the_range_check() {
        let (xs, g) = track_like();
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(!within(x, 2.0, 3.04, 1e-9), "{x}");
            let (i, _) = g.locate(x, |j| xs[j]);
            assert!(i < xs.len() - 1);
            let s = UniformGrid::spanning(-0.01, 0.01, 21).unwrap();
            let (i, _) = s.cell(x);
            assert!(i < 20);
        }
        assert_eq!(g.interval(f64::NAN, |j| xs[j]), 0);
        assert_eq!(g.interval(f64::INFINITY, |j| xs[j]), 10);
        assert_eq!(g.interval(f64::NEG_INFINITY, |j| xs[j]), 0);
        assert!(g.locate(f64::NAN, |j| xs[j]).1.is_nan());
        // Grids that are not grids.
        assert!(UniformGrid::spanning(0.0, 1.0, 1).is_none());
        assert!(UniformGrid::spanning(1.0, 0.0, 5).is_none());
        assert!(UniformGrid::spanning(0.0, f64::NAN, 5).is_none());
        assert!(UniformGrid::spanning(0.0, f64::INFINITY, 5).is_none());
        assert_eq!(UniformGrid::detect(|_| 0.0, 1), Err(1));
        assert_eq!(UniformGrid::detect(|k| [0.0, f64::NAN][k], 2), Err(1));
        assert_eq!(UniformGrid::detect(|k| [0.0, 0.1, 0.25][k], 3), Err(2));
        assert_eq!(
            UniformGrid::detect(|k| [0.0, 0.1, 0.2, 0.35, 0.4][k], 5),
            Err(3)
        );
    }

    #[test]
    fn any_increasing_grid_is_located_as_by_a_search() {
        // Not uniform: the correction walks to the right interval.
        let xs = [0.0, 0.01, 0.5, 0.52, 0.9, 1.0];
        let g = UniformGrid::spanning(xs[0], xs[5], xs.len()).unwrap();
        for k in 0..=200 {
            let x = -0.05 + 1.1 * k as f64 / 200.0;
            assert_eq!(g.interval(x, |j| xs[j]), searched(&xs, x), "{x}");
        }
    }

    #[test]
    fn cell_is_the_grid_formula_clamped() {
        let g = UniformGrid::spanning(-0.01, 0.01, 21).unwrap();
        assert!((g.step() - 1e-3).abs() < 1e-18);
        assert_eq!(g.cell(-0.01), (0, 0.0));
        assert_eq!(g.cell(0.01), (19, 1.0));
        assert_eq!(g.cell(-0.02), (0, 0.0));
        assert_eq!(g.cell(0.02), (19, 1.0));
        let (i, f) = g.cell(0.00025);
        assert_eq!(i, 10);
        assert!((f - 0.25).abs() < 1e-9);
    }

    #[test]
    fn lerp_is_exact_at_the_ends_and_linear_between() {
        assert_eq!(lerp(0.0, 3.0, 7.0), 3.0);
        assert_eq!(lerp(1.0, 3.0, 7.0), 7.0);
        assert_eq!(lerp(0.25, 3.0, 7.0), 4.0);
        assert_eq!(lerp(-0.5, 3.0, 7.0), 1.0);
        assert!(lerp(f64::NAN, 3.0, 7.0).is_nan());
        let v = lerp3(0.5, &[0.0, 2.0, -4.0], &[2.0, 2.0, 4.0]);
        assert_eq!(v, Vector3::new(1.0, 2.0, 0.0));
    }
}
