//! Track irregularities as cubic splines of the track distance (paper §2d,
//! docs/reference/03-track-preproc.md §3d), and the check that the table
//! step resolves them.

use runtime::geometry::spline::{PiecewiseCubic, Scheme};

use crate::bounds::UNRESOLVED_IRREGULARITY_M;
use crate::centerline::{COVERAGE_TOLERANCE_M, spline_error};
use crate::error::{BuildError, InputError};
use crate::inputs::IrregularityInput;
use crate::model::grid;

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
    /// must cover the track `[0, track_length_m]`, and the table step
    /// `step_m` must resolve it ([`check_resolved`]).
    pub fn build(
        input: &IrregularityInput,
        track_length_m: f64,
        step_m: f64,
    ) -> Result<Self, BuildError> {
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
            PiecewiseCubic::fit(Scheme::Cubic, &input.s_m, v)
                .map_err(|source| spline_error(&input.path, &input.lines, name, source))
        };
        let irr = Self {
            splines: [
                fit(&input.align_left_m, "align_left")?,
                fit(&input.align_right_m, "align_right")?,
                fit(&input.level_left_m, "level_left")?,
                fit(&input.level_right_m, "level_right")?,
            ],
            s_range: (lo, hi),
            min_spacing_m: input.min_spacing_m(),
        };
        check_resolved(input, &irr, track_length_m, step_m)?;
        Ok(irr)
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

/// The table step must resolve the irregularities (sampling theorem: rows
/// every h hold no wavelength shorter than 2h; docs/reference/03-track-preproc.md §3d).
/// A file sampled no finer than h holds none either and passes. A finer
/// file must carry nothing that varies between the table's nodes: each
/// per-rail spline, sampled at the nodes (0, h, 2h, … of the track) and
/// re-interpolated through them with the same not-a-knot cubic, must
/// reproduce every sample of the file on the track within
/// [`UNRESOLVED_IRREGULARITY_M`]. Otherwise the file is refused at the
/// first sample (lowest s) that is not: the rails would follow content
/// the tables cannot show (they would come out longer than the track,
/// and the table would show irregularities that are not the file's).
pub fn check_resolved(
    input: &IrregularityInput,
    irr: &Irregularities,
    track_length_m: f64,
    step_m: f64,
) -> Result<(), BuildError> {
    let spacing = input.min_spacing_m();
    if spacing >= step_m * (1.0 - 1e-9) {
        return Ok(());
    }
    let nodes = grid(track_length_m, step_m);
    // (residual, component, row)
    // The first sample (lowest s) off by more than the bound, as
    // (row, component, residual), and the largest residual of the file.
    let mut first: Option<(usize, usize, f64)> = None;
    let mut largest = 0.0_f64;
    for (c, spline) in irr.splines.iter().enumerate() {
        let (lo, hi) = irr.s_range;
        let at_nodes: Vec<f64> = nodes
            .iter()
            .map(|&s| spline.value(s.clamp(lo, hi)))
            .collect();
        let refit = PiecewiseCubic::fit(Scheme::Cubic, &nodes, &at_nodes).map_err(|source| {
            BuildError::Spline {
                what: format!(
                    "{}: {} re-interpolated at the table step",
                    input.path.display(),
                    input.sources[c].what
                ),
                source,
            }
        })?;
        for (k, (&s, &v)) in input.s_m.iter().zip(input.components()[c]).enumerate() {
            if !(0.0..=track_length_m).contains(&s) {
                continue;
            }
            let r = (refit.value(s) - v).abs();
            largest = largest.max(r);
            if r > UNRESOLVED_IRREGULARITY_M && first.is_none_or(|(k0, _, _)| k < k0) {
                first = Some((k, c, r));
            }
        }
    }
    let Some((k, c, residual)) = first else {
        return Ok(());
    };
    // The spacing to a micrometre, as a user would type it.
    let spacing = (spacing * 1e6).round() / 1e6;
    Err(InputError::at_value(
        &input.path,
        input.lines[k],
        input.sources[c].column,
        format!(
            "{} varies between the rows of the {step_m} m table step: re-interpolated from the table's rows it is off by {:.3} mm at s = {} m (more than {} mm; up to {:.3} mm in the file). The file is sampled every {spacing} m and holds wavelengths shorter than 2 × step = {} m, which the table cannot represent (sampling theorem). Use --step {spacing} or finer, or low-pass filter the file to wavelengths of 2 × step and longer",
            input.sources[c].what,
            residual * 1e3,
            input.s_m[k],
            UNRESOLVED_IRREGULARITY_M * 1e3,
            largest * 1e3,
            2.0 * step_m
        ),
    )
    .into())
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;
    use std::path::Path;

    use super::*;

    /// An irregularity file of sines (wavelength m, amplitude mm) on
    /// align_left, sampled every `spacing_m` over 0…`length_m`.
    fn sine(length_m: f64, spacing_m: f64, sines: &[(f64, f64)]) -> IrregularityInput {
        let n = (length_m / spacing_m).round() as usize;
        let mut text =
            String::from("s,align_left_mm,align_right_mm,level_left_mm,level_right_mm\n");
        for k in 0..=n {
            let s = k as f64 * spacing_m;
            let v: f64 = sines
                .iter()
                .map(|(wavelength, amplitude)| amplitude * (2.0 * PI * s / wavelength).sin())
                .sum();
            text += &format!("{s},{v},0,0,0\n");
        }
        IrregularityInput::parse(Path::new("irr.csv"), &text).unwrap()
    }

    /// A 5 mm sine of wavelength 0.05 m sampled every 0.01 m vanishes at
    /// every row of a 0.1 m table (it is below the 0.2 m Nyquist
    /// wavelength): refused at its line and column, naming the step.
    #[test]
    fn content_below_twice_the_step_is_refused() {
        let input = sine(10.0, 0.01, &[(0.05, 5.0)]);
        let e = Irregularities::build(&input, 10.0, 0.1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("irr.csv, line ")
                && e.contains(", column 2")
                && e.contains("align_left_mm varies between the rows of the 0.1 m table step")
                && e.contains("2 × step = 0.2 m")
                && e.contains("--step 0.01"),
            "{e}"
        );
        // The same file on a 0.01 m table holds it.
        assert!(Irregularities::build(&input, 10.0, 0.01).is_ok());
    }

    /// Content well above the Nyquist wavelength passes however finely the
    /// file is sampled (3 m, 4 mm: the EN 13848 D1 band's shortest), and a
    /// file sampled no finer than the step is not checked at all.
    #[test]
    fn resolved_content_passes() {
        assert!(Irregularities::build(&sine(30.0, 0.01, &[(3.0, 4.0)]), 30.0, 0.1).is_ok());
        assert!(Irregularities::build(&sine(30.0, 0.25, &[(1.0, 4.0)]), 30.0, 0.1).is_ok());
        // Tiny short-wave content (below 0.1 mm) is what the table may drop.
        let tiny = sine(30.0, 0.01, &[(3.0, 4.0), (0.05, 0.09)]);
        assert!(Irregularities::build(&tiny, 30.0, 0.1).is_ok());
    }
}
