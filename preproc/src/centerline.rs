//! The track centreline (paper §2a–c, docs/reference/03-track-preproc.md §3a–c): a [`SpaceCurve`] through
//! the control points, the cant φ(s) splined against the control points'
//! track distance (or a separate cant table), and the track frame of
//! docs/reference/03-track-preproc.md §3c at every s.

use runtime::geometry::spline::{PiecewiseCubic, Scheme};
use runtime::geometry::track::Frame;

use crate::error::{BuildError, InputError};
use crate::inputs::{CantInput, CenterlineInput};
use crate::space_curve::{CurveError, CurvePoint, SpaceCurve};

/// Largest gap allowed between a table's end and the track's end (m): a
/// table ending 1 mm short of the track still counts as covering it.
pub const COVERAGE_TOLERANCE_M: f64 = 1e-3;

/// The centreline at one track distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CenterlineSample {
    /// Track distance (m).
    pub s_m: f64,
    /// Position and τ-derivatives.
    pub point: CurvePoint,
    /// Track frame with cant.
    pub frame: Frame,
    /// Cant (rad).
    pub cant_rad: f64,
}

/// Cant as a function of track distance.
#[derive(Debug, Clone)]
enum Cant {
    Zero,
    Spline { spline: PiecewiseCubic, s_max: f64 },
}

/// The fitted centreline.
#[derive(Debug, Clone)]
pub struct Centerline {
    curve: SpaceCurve,
    cant: Cant,
}

impl Centerline {
    /// Fit the centreline of `input`; the cant comes from `cant_table` when
    /// given (it overrides a cant column of the centreline file), else from
    /// the centreline's own cant column, else zero. Cant uses the same scheme
    /// as the centreline (use `pchip` for cant ramps without overshoot).
    pub fn build(
        input: &CenterlineInput,
        cant_table: Option<&CantInput>,
        scheme: Scheme,
        cant_base_m: f64,
    ) -> Result<Self, BuildError> {
        let curve = SpaceCurve::fit(scheme, &input.points).map_err(|e| curve_error(input, e))?;
        let length = curve.length();
        let cant = if let Some(table) = cant_table {
            let (lo, hi) = (table.s_m[0], table.s_m[table.s_m.len() - 1]);
            if lo > COVERAGE_TOLERANCE_M || hi < length - COVERAGE_TOLERANCE_M {
                return Err(InputError::new(
                    &table.path,
                    None,
                    format!(
                        "the cant table covers s = {lo} … {hi} m but the track runs from 0 to {length:.3} m"
                    ),
                )
                .into());
            }
            let phi = table.cant.radians(cant_base_m)?;
            spline_cant(scheme, &table.s_m, &phi, &table.path)?
        } else if let Some(col) = &input.cant {
            let phi = col.radians(cant_base_m)?;
            spline_cant(scheme, curve.knot_arc_lengths(), &phi, &input.path)?
        } else {
            Cant::Zero
        };
        Ok(Self { curve, cant })
    }

    /// Length of the centreline (m).
    pub fn length_m(&self) -> f64 {
        self.curve.length()
    }

    /// Track distance of each control point (m).
    pub fn control_point_s(&self) -> &[f64] {
        self.curve.knot_arc_lengths()
    }

    /// Cant φ(s) (rad); the table is held constant beyond its ends (within
    /// the coverage tolerance).
    pub fn cant_at(&self, s_m: f64) -> f64 {
        match &self.cant {
            Cant::Zero => 0.0,
            Cant::Spline { spline, s_max } => {
                let (lo, _) = spline.domain();
                spline.value(s_m.clamp(lo, *s_max))
            }
        }
    }

    /// The centreline at the increasing track distances `s`.
    pub fn sample(&self, s: &[f64]) -> Result<Vec<CenterlineSample>, BuildError> {
        self.curve
            .at_arc_lengths(s)
            .into_iter()
            .zip(s)
            .map(|(point, &s_m)| {
                let cant_rad = self.cant_at(s_m);
                let frame = Frame::from_tangent(point.d1, cant_rad).ok_or_else(|| {
                    BuildError::Geometry(format!(
                        "the centreline is vertical at s = {s_m:.3} m: no lateral direction"
                    ))
                })?;
                Ok(CenterlineSample {
                    s_m,
                    point,
                    frame,
                    cant_rad,
                })
            })
            .collect()
    }
}

fn spline_cant(
    scheme: Scheme,
    s: &[f64],
    phi: &[f64],
    path: &std::path::Path,
) -> Result<Cant, BuildError> {
    let spline = PiecewiseCubic::fit(scheme, s, phi).map_err(|source| BuildError::Spline {
        what: format!("{}: cant spline", path.display()),
        source,
    })?;
    Ok(Cant::Spline {
        s_max: s[s.len() - 1],
        spline,
    })
}

/// Name the lines of the control points involved in a curve error.
pub(crate) fn curve_error(input: &CenterlineInput, e: CurveError) -> BuildError {
    let line = |i: usize| input.lines.get(i).copied();
    match e {
        CurveError::RepeatedPoint { index } => InputError::new(
            &input.path,
            line(index),
            "control point repeats the previous one: points must be distinct",
        )
        .into(),
        CurveError::DoublesBack { index } => InputError::new(
            &input.path,
            line(index),
            format!(
                "the fitted centreline doubles back between this control point and the next (line {}); remove or move points there",
                line(index + 1).unwrap_or(0)
            ),
        )
        .into(),
        CurveError::Spline(source) => BuildError::Spline {
            what: format!("{}: centreline spline", input.path.display()),
            source,
        },
    }
}
