//! Piecewise cubic interpolation: the three schemes of the paper (§2, §3;
//! docs/reference/03-track-preproc.md §3a) in one representation.
//!
//! | [`Scheme`]            | slopes at the knots                          | matches                                   |
//! |-----------------------|----------------------------------------------|-------------------------------------------|
//! | `Cubic`               | C² spline, not-a-knot ends                   | SciPy `CubicSpline(bc_type="not-a-knot")`, MATLAB `spline` |
//! | `CubicNatural`        | C² spline, zero second derivative at the ends| SciPy `CubicSpline(bc_type="natural")`    |
//! | `Akima`               | Akima (1970) weighted slopes                 | SciPy `Akima1DInterpolator(method="akima")` |
//! | `Pchip`               | Fritsch–Carlson / Fritsch–Butland harmonic mean, shape preserving | SciPy `PchipInterpolator`, MATLAB `pchip` |
//!
//! All four are stored as cubic Hermite pieces `y = c0 + c1·t + c2·t² + c3·t³`
//! with `t = x − x_i` on `[x_i, x_{i+1}]`, exactly as SciPy's `PPoly` does, so
//! values and derivatives agree with SciPy to round-off (checked against
//! committed SciPy reference values in `runtime/tests/spline_scipy.rs`).
//!
//! Evaluation outside the knot range extends the end pieces (SciPy's
//! `extrapolate=True`). At an interior knot the piece on the right is used
//! (SciPy's rule), which matters only for the second derivative of the C¹
//! schemes (Akima, PCHIP).
//!
//! Lookup of the piece is O(1) on uniform knots; on irregular knots a
//! bucket table (the piece at equally spaced abscissae) gives the start of a
//! short walk, with a binary search past [`MAX_WALK`] steps.

mod akima;
mod cubic;
mod pchip;

use std::fmt;
use std::str::FromStr;

/// Interpolation scheme (paper §2: cubic, Akima and shape-preserving splines).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Scheme {
    /// Cubic spline, not-a-knot end conditions (the paper's and MATLAB's default).
    #[default]
    Cubic,
    /// Cubic spline, natural end conditions (zero second derivative at both ends).
    CubicNatural,
    /// Akima spline (Akima 1970), local, C¹.
    Akima,
    /// Shape-preserving piecewise cubic Hermite (Fritsch–Carlson, PCHIP), C¹.
    Pchip,
}

impl Scheme {
    /// All schemes, in the order the CLI lists them.
    pub const ALL: [Scheme; 4] = [
        Scheme::Cubic,
        Scheme::CubicNatural,
        Scheme::Akima,
        Scheme::Pchip,
    ];

    /// The name used on command lines and in table files.
    pub fn name(self) -> &'static str {
        match self {
            Scheme::Cubic => "cubic",
            Scheme::CubicNatural => "cubic-natural",
            Scheme::Akima => "akima",
            Scheme::Pchip => "pchip",
        }
    }
}

impl fmt::Display for Scheme {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Scheme {
    type Err = SplineError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "cubic" | "not-a-knot" | "spline" => Ok(Scheme::Cubic),
            "cubic-natural" | "natural" => Ok(Scheme::CubicNatural),
            "akima" => Ok(Scheme::Akima),
            "pchip" | "shape-preserving" => Ok(Scheme::Pchip),
            other => Err(SplineError::UnknownScheme {
                name: other.to_string(),
            }),
        }
    }
}

/// Why a spline could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SplineError {
    #[error("need at least {min} points for a {scheme} spline, got {got}")]
    TooFewPoints {
        scheme: Scheme,
        min: usize,
        got: usize,
    },
    #[error("x and y have different lengths ({x_len} and {y_len})")]
    LengthMismatch { x_len: usize, y_len: usize },
    #[error("point {index}: value is not finite (x = {x}, y = {y})")]
    NonFinite { index: usize, x: f64, y: f64 },
    #[error(
        "point {index}: abscissae must be strictly increasing (x[{prev}] = {x_prev}, x[{index}] = {x})"
    )]
    NotIncreasing {
        index: usize,
        prev: usize,
        x_prev: f64,
        x: f64,
    },
    #[error("unknown spline scheme '{name}' (expected cubic, cubic-natural, akima or pchip)")]
    UnknownScheme { name: String },
}

/// How the piece containing `x` is found.
#[derive(Debug, Clone, PartialEq)]
enum Lookup {
    /// Knots equally spaced (to 1e-10 relative): index = ⌊(x − x0)/h⌋, then a
    /// one-step correction for round-off.
    Uniform { x0: f64, inv_h: f64 },
    /// Irregular knots: `start[j]` is the piece at `x0 + j·w`
    /// (`inv_w = 1/w`, [`BUCKETS_PER_PIECE`] buckets per piece), from which
    /// the piece of `x` is walked to, or binary searched past [`MAX_WALK`]
    /// steps — the same piece as the binary search in every case.
    Search {
        x0: f64,
        inv_w: f64,
        start: Vec<u32>,
    },
}

/// Buckets of the irregular-knot lookup per piece.
const BUCKETS_PER_PIECE: usize = 4;
/// Steps of the walk from a bucket's piece before the binary search takes
/// over (knots much denser than the average).
pub const MAX_WALK: usize = 8;

/// A piecewise cubic function of one variable (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseCubic {
    scheme: Scheme,
    knots: Vec<f64>,
    /// `[c0, c1, c2, c3]` of each piece, in the local variable `t = x − x_i`.
    coeffs: Vec<[f64; 4]>,
    lookup: Lookup,
}

/// Value and first three derivatives at one abscissa.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Derivatives {
    pub value: f64,
    pub d1: f64,
    pub d2: f64,
    pub d3: f64,
}

impl PiecewiseCubic {
    /// Fit `y(x)` with `scheme`. `x` must be finite and strictly increasing.
    ///
    /// Minimum point counts: 2 for every scheme (two points give the straight
    /// line, as SciPy does). Three points with `Cubic` give the parabola
    /// through them (SciPy's rule for not-a-knot at both ends).
    pub fn fit(scheme: Scheme, x: &[f64], y: &[f64]) -> Result<Self, SplineError> {
        validate(scheme, x, y)?;
        let slopes = match scheme {
            Scheme::Cubic => cubic::slopes(x, y, cubic::EndCondition::NotAKnot),
            Scheme::CubicNatural => cubic::slopes(x, y, cubic::EndCondition::Natural),
            Scheme::Akima => akima::slopes(x, y),
            Scheme::Pchip => pchip::slopes(x, y),
        };
        Ok(Self::from_hermite(scheme, x, y, &slopes))
    }

    /// Build the pieces from values and slopes at the knots (cubic Hermite
    /// form; coefficients as SciPy's `CubicHermiteSpline`).
    fn from_hermite(scheme: Scheme, x: &[f64], y: &[f64], d: &[f64]) -> Self {
        let coeffs = x
            .windows(2)
            .zip(y.windows(2))
            .zip(d.windows(2))
            .map(|((xw, yw), dw)| {
                let h = xw[1] - xw[0];
                let slope = (yw[1] - yw[0]) / h;
                let t = (dw[0] + dw[1] - 2.0 * slope) / h;
                [yw[0], dw[0], (slope - dw[0]) / h - t, t / h]
            })
            .collect();
        Self {
            scheme,
            knots: x.to_vec(),
            coeffs,
            lookup: detect_uniform(x),
        }
    }

    /// The same function translated: `g(x) = f(x − dx) + dy`.
    pub fn translated(&self, dx: f64, dy: f64) -> Self {
        let knots: Vec<f64> = self.knots.iter().map(|k| k + dx).collect();
        let coeffs = self
            .coeffs
            .iter()
            .map(|c| [c[0] + dy, c[1], c[2], c[3]])
            .collect();
        Self {
            scheme: self.scheme,
            lookup: detect_uniform(&knots),
            knots,
            coeffs,
        }
    }

    /// The scheme this function was fitted with.
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// The knots (abscissae of the fitted points).
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }

    /// Coefficients `[c0, c1, c2, c3]` of each piece in `t = x − x_i`.
    pub fn coefficients(&self) -> &[[f64; 4]] {
        &self.coeffs
    }

    /// First and last knot.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// True when the knots are uniform and the piece lookup is O(1).
    pub fn has_uniform_knots(&self) -> bool {
        matches!(self.lookup, Lookup::Uniform { .. })
    }

    /// Index of the piece used at `x`: `i` with `x_i ≤ x < x_{i+1}`, clamped
    /// to the first and last piece outside the knots (and the last knot
    /// belongs to the last piece).
    #[inline]
    pub fn piece_index(&self, x: f64) -> usize {
        let last = self.coeffs.len() - 1;
        match &self.lookup {
            &Lookup::Uniform { x0, inv_h } => {
                let guess = ((x - x0) * inv_h).floor();
                let mut i = if guess.is_nan() || guess <= 0.0 {
                    0
                } else if guess >= last as f64 {
                    last
                } else {
                    guess as usize
                };
                // One-step correction for round-off in (x − x0)/h.
                if i > 0 && x < self.knots[i] {
                    i -= 1;
                } else if i < last && x >= self.knots[i + 1] {
                    i += 1;
                }
                i
            }
            Lookup::Search { x0, inv_w, start } => {
                let g = (x - x0) * inv_w;
                if g.is_nan() || g < 0.0 {
                    // Below the knots, or NaN: the binary search's answer.
                    return self.binary_search(x);
                }
                let j = (g as usize).min(start.len() - 1);
                let mut i = start[j] as usize;
                // The binary search's piece is the one whose interior knots
                // up to it are ≤ x and whose next knot is > x (x not NaN).
                for _ in 0..MAX_WALK {
                    if i > 0 && x < self.knots[i] {
                        i -= 1;
                    } else if i < last && x >= self.knots[i + 1] {
                        i += 1;
                    } else {
                        return i;
                    }
                }
                self.binary_search(x)
            }
        }
    }

    /// The piece of `x` by binary search (the reference lookup).
    fn binary_search(&self, x: f64) -> usize {
        let last = self.coeffs.len() - 1;
        // partition_point: number of interior knots ≤ x.
        self.knots[1..=last].partition_point(|&k| k <= x).min(last)
    }

    /// [`Self::piece_index`], trying the piece `hint` and its two
    /// neighbours first (a solver's iterates move little between two
    /// evaluations): the same index in every case, found in O(1) when `x`
    /// lies in or next to the hinted piece, by the full lookup otherwise.
    /// Both lookups return the piece whose knots bracket `x` (for uniform
    /// knots: ⌊(x − x0)/h⌋ is off by at most one through round-off, which
    /// its one-step correction undoes); the bracket test needs no floor,
    /// which the baseline x86-64 target computes by a library call.
    #[inline(always)]
    pub fn piece_index_near(&self, x: f64, hint: usize) -> usize {
        let last = self.coeffs.len() - 1;
        if hint <= last {
            // The piece the binary search returns for a non-NaN x: the
            // interior knots up to it are ≤ x, the next one is > x.
            let brackets =
                |i: usize| (i == 0 || self.knots[i] <= x) && (i == last || x < self.knots[i + 1]);
            if brackets(hint) {
                return hint;
            }
            if hint < last && brackets(hint + 1) {
                return hint + 1;
            }
            if hint > 0 && brackets(hint - 1) {
                return hint - 1;
            }
        }
        self.piece_index(x)
    }

    /// Value at `x`.
    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        let i = self.piece_index(x);
        let c = &self.coeffs[i];
        let t = x - self.knots[i];
        ((c[3] * t + c[2]) * t + c[1]) * t + c[0]
    }

    /// First derivative at `x`.
    #[inline]
    pub fn d1(&self, x: f64) -> f64 {
        let i = self.piece_index(x);
        let c = &self.coeffs[i];
        let t = x - self.knots[i];
        (3.0 * c[3] * t + 2.0 * c[2]) * t + c[1]
    }

    /// Second derivative at `x`.
    #[inline]
    pub fn d2(&self, x: f64) -> f64 {
        let i = self.piece_index(x);
        let c = &self.coeffs[i];
        let t = x - self.knots[i];
        6.0 * c[3] * t + 2.0 * c[2]
    }

    /// Value and first three derivatives at `x` (one piece lookup).
    #[inline]
    pub fn derivatives(&self, x: f64) -> Derivatives {
        let i = self.piece_index(x);
        self.derivatives_in_piece(i, x)
    }

    /// Value and derivatives at `x` using piece `i` (no lookup; `x` may lie
    /// outside the piece, which then extrapolates it).
    #[inline]
    pub fn derivatives_in_piece(&self, i: usize, x: f64) -> Derivatives {
        let c = &self.coeffs[i];
        let t = x - self.knots[i];
        Derivatives {
            value: ((c[3] * t + c[2]) * t + c[1]) * t + c[0],
            d1: (3.0 * c[3] * t + 2.0 * c[2]) * t + c[1],
            d2: 6.0 * c[3] * t + 2.0 * c[2],
            d3: 6.0 * c[3],
        }
    }
}

fn validate(scheme: Scheme, x: &[f64], y: &[f64]) -> Result<(), SplineError> {
    if x.len() != y.len() {
        return Err(SplineError::LengthMismatch {
            x_len: x.len(),
            y_len: y.len(),
        });
    }
    if x.len() < 2 {
        return Err(SplineError::TooFewPoints {
            scheme,
            min: 2,
            got: x.len(),
        });
    }
    for (index, (&xi, &yi)) in x.iter().zip(y).enumerate() {
        if !xi.is_finite() || !yi.is_finite() {
            return Err(SplineError::NonFinite {
                index,
                x: xi,
                y: yi,
            });
        }
        if index > 0 && xi <= x[index - 1] {
            return Err(SplineError::NotIncreasing {
                index,
                prev: index - 1,
                x_prev: x[index - 1],
                x: xi,
            });
        }
    }
    Ok(())
}

fn detect_uniform(x: &[f64]) -> Lookup {
    let n = x.len();
    let h = (x[n - 1] - x[0]) / (n - 1) as f64;
    let uniform = x.windows(2).all(|w| ((w[1] - w[0]) - h).abs() <= 1e-10 * h);
    if uniform {
        Lookup::Uniform {
            x0: x[0],
            inv_h: 1.0 / h,
        }
    } else {
        let pieces = n - 1;
        let buckets = BUCKETS_PER_PIECE * pieces;
        let w = (x[n - 1] - x[0]) / buckets as f64;
        let last = pieces - 1;
        let start = (0..=buckets)
            .map(|j| {
                let xj = x[0] + j as f64 * w;
                x[1..=last].partition_point(|&k| k <= xj).min(last) as u32
            })
            .collect();
        Lookup::Search {
            x0: x[0],
            inv_w: 1.0 / w,
            start,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line_data() -> (Vec<f64>, Vec<f64>) {
        let x: Vec<f64> = vec![0.0, 0.5, 1.7, 2.0, 3.1, 4.0];
        let y = x.iter().map(|v| 2.0 * v - 1.0).collect();
        (x, y)
    }

    #[test]
    fn every_scheme_reproduces_a_straight_line() {
        let (x, y) = line_data();
        for scheme in Scheme::ALL {
            let s = PiecewiseCubic::fit(scheme, &x, &y).unwrap();
            for k in 0..=80 {
                let xi = -0.5 + 5.0 * k as f64 / 80.0;
                assert!((s.value(xi) - (2.0 * xi - 1.0)).abs() < 1e-12, "{scheme}");
                assert!((s.d1(xi) - 2.0).abs() < 1e-12, "{scheme}");
                assert!(s.d2(xi).abs() < 1e-11, "{scheme}");
            }
        }
    }

    #[test]
    fn cubic_reproduces_a_cubic_polynomial() {
        // Not-a-knot reproduces any cubic exactly (its end conditions hold for it).
        let x: Vec<f64> = vec![-1.0, -0.2, 0.3, 1.1, 2.0, 2.4];
        let f = |v: f64| 0.5 * v * v * v - v * v + 3.0;
        let y: Vec<f64> = x.iter().map(|&v| f(v)).collect();
        let s = PiecewiseCubic::fit(Scheme::Cubic, &x, &y).unwrap();
        for k in 0..=50 {
            let v = -1.0 + 3.4 * k as f64 / 50.0;
            assert!((s.value(v) - f(v)).abs() < 1e-12);
            assert!((s.d2(v) - (3.0 * v - 2.0)).abs() < 1e-10);
            assert!((s.derivatives(v).d3 - 3.0).abs() < 1e-9);
        }
    }

    #[test]
    fn natural_spline_has_zero_curvature_at_the_ends() {
        let x: Vec<f64> = (0..7).map(|i| i as f64).collect();
        let y: Vec<f64> = x.iter().map(|v| v.sin()).collect();
        let s = PiecewiseCubic::fit(Scheme::CubicNatural, &x, &y).unwrap();
        assert!(s.d2(0.0).abs() < 1e-13);
        assert!(s.d2(6.0).abs() < 1e-13);
    }

    #[test]
    fn pchip_preserves_monotonicity_where_cubic_overshoots() {
        // A step: the C² spline overshoots, PCHIP must not.
        let x: Vec<f64> = (0..8).map(|i| i as f64).collect();
        let y = vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0];
        let p = PiecewiseCubic::fit(Scheme::Pchip, &x, &y).unwrap();
        let c = PiecewiseCubic::fit(Scheme::Cubic, &x, &y).unwrap();
        let mut cubic_overshoot = 0.0_f64;
        for k in 0..=700 {
            let v = 7.0 * k as f64 / 700.0;
            let yp = p.value(v);
            assert!((-1e-15..=1.0 + 1e-15).contains(&yp));
            cubic_overshoot = cubic_overshoot.max(c.value(v) - 1.0).max(-c.value(v));
        }
        assert!(cubic_overshoot > 0.05);
    }

    #[test]
    fn knots_are_interpolated_and_pieces_found_on_both_grid_kinds() {
        let uniform: Vec<f64> = (0..11).map(|i| 0.1 * i as f64).collect();
        let mut irregular = uniform.clone();
        irregular[5] += 0.03;
        for x in [uniform, irregular] {
            let y: Vec<f64> = x.iter().map(|v| (3.0 * v).cos()).collect();
            for scheme in Scheme::ALL {
                let s = PiecewiseCubic::fit(scheme, &x, &y).unwrap();
                for (i, (&xi, &yi)) in x.iter().zip(&y).enumerate() {
                    assert!((s.value(xi) - yi).abs() < 1e-14);
                    let expect = i.min(x.len() - 2);
                    assert_eq!(s.piece_index(xi), expect);
                }
                assert_eq!(s.piece_index(-5.0), 0);
                assert_eq!(s.piece_index(5.0), x.len() - 2);
                assert_eq!(s.piece_index(f64::NAN), 0);
            }
        }
    }

    /// The hinted lookup returns the full lookup's piece for every hint,
    /// on uniform and irregular knots, inside, outside, at the knots and
    /// for NaN.
    #[test]
    fn hinted_piece_lookup_agrees_with_the_full_lookup() {
        let uniform: Vec<f64> = (0..21).map(|i| 0.05 * i as f64).collect();
        let irregular: Vec<f64> = (0..21).map(|i| (0.05 * i as f64).powi(2)).collect();
        for x in [uniform, irregular] {
            let y: Vec<f64> = x.iter().map(|v| v.sin()).collect();
            let s = PiecewiseCubic::fit(Scheme::Akima, &x, &y).unwrap();
            let mut probes: Vec<f64> = (0..=300).map(|k| -0.2 + 1.4 * k as f64 / 300.0).collect();
            probes.extend(&x);
            probes.push(f64::NAN);
            for &p in &probes {
                let expect = s.piece_index(p);
                for hint in [0, 1, 5, 10, 19, 20, 21, usize::MAX] {
                    assert_eq!(s.piece_index_near(p, hint), expect, "x = {p}, hint {hint}");
                }
                if expect > 0 {
                    assert_eq!(s.piece_index_near(p, expect - 1), expect);
                }
            }
        }
    }

    /// The bucket lookup returns the binary search's piece everywhere,
    /// also where the knots are a thousand times denser than the average
    /// (the walk gives way to the binary search there).
    #[test]
    fn bucket_lookup_agrees_with_the_binary_search() {
        let mut x: Vec<f64> = (0..40).map(|i| i as f64 * 0.1).collect();
        x.extend((1..200).map(|i| 3.9 + i as f64 * 1e-4));
        x.extend((0..30).map(|i| 4.0 + i as f64 * 0.37));
        let y: Vec<f64> = x.iter().map(|v| v.cos()).collect();
        let s = PiecewiseCubic::fit(Scheme::Pchip, &x, &y).unwrap();
        assert!(!s.has_uniform_knots());
        let mut probes: Vec<f64> = (0..=20_000)
            .map(|k| -1.0 + 16.0 * k as f64 / 20_000.0)
            .collect();
        probes.extend(&x);
        probes.extend(x.iter().map(|v| v * (1.0 + f64::EPSILON)));
        probes.extend(x.iter().map(|v| v * (1.0 - f64::EPSILON)));
        probes.extend([f64::NAN, f64::INFINITY, f64::NEG_INFINITY]);
        for &p in &probes {
            assert_eq!(s.piece_index(p), s.binary_search(p), "x = {p}");
        }
    }

    #[test]
    fn uniform_detection() {
        let x: Vec<f64> = (0..1001).map(|i| 0.1 * i as f64).collect();
        let y = vec![0.0; x.len()];
        assert!(
            PiecewiseCubic::fit(Scheme::Cubic, &x, &y)
                .unwrap()
                .has_uniform_knots()
        );
        let x2 = vec![0.0, 1.0, 2.5, 3.0];
        assert!(
            !PiecewiseCubic::fit(Scheme::Cubic, &x2, &[0.0; 4])
                .unwrap()
                .has_uniform_knots()
        );
    }

    #[test]
    fn bad_input_is_reported() {
        assert!(matches!(
            PiecewiseCubic::fit(Scheme::Cubic, &[0.0], &[1.0]),
            Err(SplineError::TooFewPoints { got: 1, .. })
        ));
        assert!(matches!(
            PiecewiseCubic::fit(Scheme::Akima, &[0.0, 1.0, 1.0], &[1.0, 2.0, 3.0]),
            Err(SplineError::NotIncreasing { index: 2, .. })
        ));
        assert!(matches!(
            PiecewiseCubic::fit(Scheme::Pchip, &[0.0, 1.0, 2.0], &[1.0, f64::NAN, 3.0]),
            Err(SplineError::NonFinite { index: 1, .. })
        ));
        assert!(matches!(
            PiecewiseCubic::fit(Scheme::Pchip, &[0.0, 1.0], &[1.0]),
            Err(SplineError::LengthMismatch { .. })
        ));
        assert_eq!("pchip".parse::<Scheme>().unwrap(), Scheme::Pchip);
        assert!("quintic".parse::<Scheme>().is_err());
    }
}
