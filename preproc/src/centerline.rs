//! The track centreline (paper §2a–c, docs/reference/03-track-preproc.md §3a–c): a [`SpaceCurve`] through
//! the control points, the cant φ(s) splined against the control points'
//! track distance (or a separate cant table) with its own scheme, and the
//! track frame of docs/reference/03-track-preproc.md §3c at every s — or a
//! track from design elements ([`crate::design`], §3h), whose position,
//! derivatives and cant are the element formulas'.

use std::path::{Path, PathBuf};

use runtime::geometry::spline::{PiecewiseCubic, Scheme, SplineError};
use runtime::geometry::track::Frame;

use crate::bounds::MIN_CURVE_RADIUS_M;
use crate::design::DesignTrack;
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

/// The largest |cant| of the input and where it is, to tell a cant the
/// input asked for from a spline's overshoot (docs/reference/03-track-preproc.md §3g).
#[derive(Debug, Clone, PartialEq)]
pub struct CantPeak {
    /// |φ| (rad).
    pub cant_rad: f64,
    pub path: PathBuf,
    /// 1-based line of the value.
    pub line: usize,
}

/// Where the centreline's geometry comes from.
#[derive(Debug, Clone)]
enum Geometry {
    /// A spline through control points, with a splined cant.
    Fitted {
        curve: Box<SpaceCurve>,
        cant: Box<Cant>,
    },
    /// Design elements, evaluated in closed form.
    Design(Box<DesignTrack>),
}

/// The centreline: fitted through control points, or from design elements.
#[derive(Debug, Clone)]
pub struct Centerline {
    geometry: Geometry,
    cant_peak: Option<CantPeak>,
}

impl Centerline {
    /// Fit the centreline of `input`; the cant comes from `cant_table` when
    /// given (it overrides a cant column of the centreline file), else from
    /// the centreline's own cant column, else zero. The cant is splined
    /// with `cant_scheme` (default `pchip`, shape-preserving: no overshoot
    /// of a cant ramp, docs/reference/03-track-preproc.md §3c), the
    /// centreline with `scheme`. The fitted curve's radius must nowhere be
    /// below [`MIN_CURVE_RADIUS_M`].
    pub fn build(
        input: &CenterlineInput,
        cant_table: Option<&CantInput>,
        scheme: Scheme,
        cant_scheme: Scheme,
        cant_base_m: f64,
    ) -> Result<Self, BuildError> {
        let curve = SpaceCurve::fit(scheme, &input.points).map_err(|e| curve_error(input, e))?;
        check_radius(input, &curve)?;
        let length = curve.length();
        let (cant, cant_peak) = if let Some(table) = cant_table {
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
            (
                spline_cant(
                    cant_scheme,
                    &table.s_m,
                    &phi,
                    &table.path,
                    table.cant.lines(),
                )?,
                cant_peak(&phi, table.cant.lines(), &table.path),
            )
        } else if let Some(col) = &input.cant {
            let phi = col.radians(cant_base_m)?;
            (
                spline_cant(
                    cant_scheme,
                    curve.knot_arc_lengths(),
                    &phi,
                    &input.path,
                    col.lines(),
                )?,
                cant_peak(&phi, col.lines(), &input.path),
            )
        } else {
            (Cant::Zero, None)
        };
        Ok(Self {
            geometry: Geometry::Fitted {
                curve: Box::new(curve),
                cant: Box::new(cant),
            },
            cant_peak,
        })
    }

    /// The centreline of a design track: positions, derivatives and cant
    /// are the element formulas' (docs/reference/03-track-preproc.md §3h).
    pub fn from_design(track: DesignTrack) -> Self {
        Self {
            geometry: Geometry::Design(Box::new(track)),
            cant_peak: None,
        }
    }

    /// The design track, if the centreline is one.
    pub fn design(&self) -> Option<&DesignTrack> {
        match &self.geometry {
            Geometry::Design(d) => Some(d),
            Geometry::Fitted { .. } => None,
        }
    }

    /// The largest |cant| of the input, if it has a cant.
    pub fn cant_peak(&self) -> Option<&CantPeak> {
        self.cant_peak.as_ref()
    }

    /// Length of the centreline (m).
    pub fn length_m(&self) -> f64 {
        match &self.geometry {
            Geometry::Fitted { curve, .. } => curve.length(),
            Geometry::Design(d) => d.length_m(),
        }
    }

    /// Track distance of each control point (m); of a design track, of
    /// each element joint.
    pub fn control_point_s(&self) -> &[f64] {
        match &self.geometry {
            Geometry::Fitted { curve, .. } => curve.knot_arc_lengths(),
            Geometry::Design(d) => d.joints_s_m(),
        }
    }

    /// Cant φ(s) (rad); the table is held constant beyond its ends (within
    /// the coverage tolerance).
    pub fn cant_at(&self, s_m: f64) -> f64 {
        match &self.geometry {
            Geometry::Design(d) => d.cant_at(s_m),
            Geometry::Fitted { cant, .. } => match cant.as_ref() {
                Cant::Zero => 0.0,
                Cant::Spline { spline, s_max } => {
                    let (lo, _) = spline.domain();
                    spline.value(s_m.clamp(lo, *s_max))
                }
            },
        }
    }

    /// The centreline at the increasing track distances `s`.
    pub fn sample(&self, s: &[f64]) -> Result<Vec<CenterlineSample>, BuildError> {
        let points: Vec<(CurvePoint, f64)> = match &self.geometry {
            Geometry::Fitted { curve, .. } => curve
                .at_arc_lengths(s)
                .into_iter()
                .map(|p| (p, f64::NAN))
                .collect(),
            Geometry::Design(d) => s
                .iter()
                .map(|&s_m| {
                    let p = d.at(s_m);
                    (p.curve_point(), p.cant_rad)
                })
                .collect(),
        };
        points
            .into_iter()
            .zip(s)
            .map(|((point, design_cant), &s_m)| {
                let cant_rad = if design_cant.is_nan() {
                    self.cant_at(s_m)
                } else {
                    design_cant
                };
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
    path: &Path,
    lines: &[usize],
) -> Result<Cant, BuildError> {
    let spline = PiecewiseCubic::fit(scheme, s, phi)
        .map_err(|source| spline_error(path, lines, "cant spline", source))?;
    Ok(Cant::Spline {
        s_max: s[s.len() - 1],
        spline,
    })
}

/// The input's largest |cant| (the first, if several are equal).
fn cant_peak(phi: &[f64], lines: &[usize], path: &Path) -> Option<CantPeak> {
    crate::inputs::peak(phi).map(|(k, cant_rad)| CantPeak {
        cant_rad,
        path: path.to_path_buf(),
        line: lines[k],
    })
}

/// Refuse a centreline that bends more sharply than a radius of
/// [`MIN_CURVE_RADIUS_M`] anywhere (checked on the fitted curve, so a
/// spline's overshoot counts too), naming the control points around it.
fn check_radius(input: &CenterlineInput, curve: &SpaceCurve) -> Result<(), BuildError> {
    let bend = curve.sharpest_bend();
    if bend.curvature_1_m * MIN_CURVE_RADIUS_M <= 1.0 {
        return Ok(());
    }
    let line = |i: usize| input.lines.get(i).copied();
    Err(InputError::new(
        &input.path,
        line(bend.piece),
        format!(
            "the fitted centreline has a radius of curvature of {:.3} m at s = {:.3} m (between this control point and the next, line {}), below the {MIN_CURVE_RADIUS_M} m of the tightest tram curves (check the unit: coordinates are in metres; a 600 m curve written in km has a radius of 0.6 m)",
            1.0 / bend.curvature_1_m,
            bend.s_m,
            line(bend.piece + 1).unwrap_or(0)
        ),
    )
    .into())
}

/// A spline of values read from `path` that could not be fitted: at the
/// line of the point the spline names, if it names one.
pub(crate) fn spline_error(
    path: &Path,
    lines: &[usize],
    what: &str,
    source: SplineError,
) -> BuildError {
    let index = match &source {
        SplineError::NonFinite { index, .. } | SplineError::NotIncreasing { index, .. } => {
            Some(*index)
        }
        _ => None,
    };
    match index.and_then(|i| lines.get(i)) {
        Some(&line) => InputError::new(path, Some(line), format!("{what}: {source}")).into(),
        None => BuildError::Spline {
            what: format!("{}: {what}", path.display()),
            source,
        },
    }
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
        CurveError::Spline(source) => {
            spline_error(&input.path, &input.lines, "centreline spline", source)
        }
    }
}
