//! Track irregularities as cubic splines of the track distance (paper §2d,
//! docs/reference/03-track-preproc.md §3d).

use runtime::geometry::spline::{PiecewiseCubic, Scheme};

use crate::centerline::COVERAGE_TOLERANCE_M;
use crate::error::{BuildError, InputError};
use crate::inputs::IrregularityInput;

/// Deviations of both rails at one track distance (m): lateral along `n`
/// (positive to the left), vertical along `b` (positive up).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RailDeviations {
    pub align_left_m: f64,
    pub align_right_m: f64,
    pub level_left_m: f64,
    pub level_right_m: f64,
}

/// The irregularity splines.
#[derive(Debug, Clone)]
pub struct Irregularities {
    splines: [PiecewiseCubic; 4],
    s_range: (f64, f64),
    min_spacing_m: f64,
}

impl Irregularities {
    /// Fit the four columns with not-a-knot cubic splines of s; the table
    /// must cover the track `[0, track_length_m]`.
    pub fn build(input: &IrregularityInput, track_length_m: f64) -> Result<Self, BuildError> {
        let (lo, hi) = (input.s_m[0], input.s_m[input.s_m.len() - 1]);
        if lo > COVERAGE_TOLERANCE_M || hi < track_length_m - COVERAGE_TOLERANCE_M {
            return Err(InputError::new(
                &input.path,
                None,
                format!(
                    "the irregularity table covers s = {lo} … {hi} m but the track runs from 0 to {track_length_m:.3} m"
                ),
            )
            .into());
        }
        let fit = |v: &[f64], name: &str| {
            PiecewiseCubic::fit(Scheme::Cubic, &input.s_m, v).map_err(|source| BuildError::Spline {
                what: format!("{}: {name}", input.path.display()),
                source,
            })
        };
        Ok(Self {
            splines: [
                fit(&input.align_left_m, "align_left")?,
                fit(&input.align_right_m, "align_right")?,
                fit(&input.level_left_m, "level_left")?,
                fit(&input.level_right_m, "level_right")?,
            ],
            s_range: (lo, hi),
            min_spacing_m: input.min_spacing_m(),
        })
    }

    /// Deviations at track distance `s_m` (clamped to the table).
    pub fn at(&self, s_m: f64) -> RailDeviations {
        let s = s_m.clamp(self.s_range.0, self.s_range.1);
        let [al, ar, ll, lr] = &self.splines;
        RailDeviations {
            align_left_m: al.value(s),
            align_right_m: ar.value(s),
            level_left_m: ll.value(s),
            level_right_m: lr.value(s),
        }
    }

    /// Smallest sample spacing of the table (m).
    pub fn min_spacing_m(&self) -> f64 {
        self.min_spacing_m
    }
}
