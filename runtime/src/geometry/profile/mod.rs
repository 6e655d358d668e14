//! Wheel and rail profiles in the toolkit's internal convention (paper §3,
//! docs/reference/05-surfaces.md §5), built from points read by [`crate::io::profile_import`].
//!
//! # Internal convention
//!
//! Every profile is stored as the profile of the **right-hand** wheel or
//! rail, in its cross-section plane:
//!
//! * `u` (m), lateral, positive **towards the track centre** — towards the
//!   flange of a wheel, towards the gauge face of a rail. For right-hand
//!   wheels and rails this is the direction of the track's lateral vector `n`
//!   (which points left); left-hand profiles are the mirror images
//!   (`u → −u`), applied by the contact code with σ = −1.
//! * `z` (m), vertical, positive **up** (away from the rail, towards the
//!   wheel's axle).
//! * Wheel origin: the taping line (nominal rolling circle), `z = 0` on the
//!   tread there; the wheel radius at `u` is `R0 − z(u)`.
//! * Rail origin: set by [`RailProfile::placed`]: the top of the rail, laterally
//!   where the rail's space curve of the track tables runs, with the gauge
//!   point (14 mm below the top) at half the gauge from the track centre.
//!
//! Profile files (SIMPACK, EN 15302 / Miniprof plain columns, CSV) use
//! `y` positive towards the field side (flange and gauge face at negative
//! `y`); SIMPACK's `z` points down, the others' up. So `u = −y` and
//! `z_up = ±z`. A [`FileMapping`] keeps the way back, so contact points can
//! be reported in the file's own coordinates.
//!
//! # Which points are used
//!
//! One rule for every file format (module `stretch`,
//! docs/reference/05-surfaces.md §5.3): the steep faces at a profile's ends are trimmed; a profile that
//! folds back, repeats its lateral coordinate or breaks inside its usable
//! stretch is refused at the file line of the first offending point, unless
//! `keep_longest_stretch` asks for its longest usable stretch, which then
//! comes with a [`ProfileWarning`] naming every dropped line. A profile
//! whose size is implausible (lateral span, [`MIN_PROFILE_SPAN_M`] …
//! [`MAX_PROFILE_SPAN_M`]; wheel flange height, [`MIN_FLANGE_HEIGHT_M`] …
//! [`MAX_FLANGE_HEIGHT_M`]) is refused with "check the unit".

mod bounds;
mod curve;
mod rail;
pub mod rail_cant;
mod stretch;
mod wheel;

pub use bounds::{
    MAX_FLANGE_HEIGHT_M, MAX_PROFILE_SPAN_M, MIN_FLANGE_HEIGHT_M, MIN_PROFILE_SPAN_M,
};
pub use curve::{CurvePoint, ProfileCurve};
pub use rail::{PlacedRailProfile, RailPlacement, RailProfile, RailProfileOptions};
pub use stretch::ProfileWarning;
pub use wheel::{MAX_SEGMENTS, WheelProfile, WheelProfileOptions, WheelSegment, Zone};

use std::path::PathBuf;

use crate::geometry::spline::SplineError;

/// How internal coordinates map back to the profile file's coordinates:
/// `y_file = y_sign·u + y_offset`, `z_file = z_sign·z + z_offset` (metres;
/// divide by the file's length unit for file units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FileMapping {
    pub y_sign: f64,
    pub y_offset_m: f64,
    pub z_sign: f64,
    pub z_offset_m: f64,
}

impl FileMapping {
    /// File coordinates (m) of the internal point `(u, z)`.
    pub fn to_file(&self, u_m: f64, z_m: f64) -> (f64, f64) {
        (
            self.y_sign * u_m + self.y_offset_m,
            self.z_sign * z_m + self.z_offset_m,
        )
    }

    /// Internal coordinates of the file point `(y, z)` (m).
    pub fn from_file(&self, y_m: f64, z_m: f64) -> (f64, f64) {
        (
            (y_m - self.y_offset_m) * self.y_sign,
            (z_m - self.z_offset_m) * self.z_sign,
        )
    }
}

/// Why a profile cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    #[error("{path}: {rule}")]
    Invalid { path: PathBuf, rule: String },
    #[error(
        "{path}: the {region} must be convex but is concave (radius {radius_mm:.1} mm) at y = {y_file_mm:.2} mm of the file"
    )]
    NotConvex {
        path: PathBuf,
        region: &'static str,
        radius_mm: f64,
        y_file_mm: f64,
    },
    /// A rule broken at one point of the profile (e.g. the lateral
    /// coordinate turning back), named by its file line.
    #[error("'{path}', {}: {rule}", point_name(*line, *point))]
    AtPoint {
        path: PathBuf,
        /// 1-based file line of the point; `None` for points not read from
        /// a file.
        line: Option<usize>,
        /// 1-based number of the point in the order given.
        point: usize,
        rule: String,
    },
    /// A size outside its plausible range: most likely a wrong length
    /// unit (docs/reference/02-inputs.md §2.6).
    #[error(
        "{path}: the {quantity} is {value_mm:.3} mm, outside the plausible {min_mm}–{max_mm} mm ({typical}): check the unit of the file's lengths"
    )]
    Implausible {
        path: PathBuf,
        quantity: &'static str,
        value_mm: f64,
        min_mm: f64,
        max_mm: f64,
        /// Typical values, for the message.
        typical: &'static str,
    },
    #[error("{path}: {source}")]
    Spline {
        path: PathBuf,
        #[source]
        source: SplineError,
    },
}

fn point_name(line: Option<usize>, point: usize) -> String {
    match line {
        Some(l) => format!("line {l}"),
        None => format!("point {point}"),
    }
}

impl ProfileError {
    /// The 1-based file line the error is about, when it is about one.
    pub fn line(&self) -> Option<usize> {
        match self {
            Self::AtPoint { line, .. } => *line,
            _ => None,
        }
    }
}

/// The points of a profile in the internal convention, ready to fit.
pub(crate) struct InternalPoints {
    /// Kept points, u increasing (m).
    pub u: Vec<f64>,
    pub z: Vec<f64>,
    pub mapping: FileMapping,
    /// Set when the longest stretch was kept instead of refusing the profile.
    pub warning: Option<ProfileWarning>,
}

/// How to choose the points of a profile: the trim angle and whether to
/// keep the longest usable stretch of a profile the rule refuses.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StretchOptions {
    pub trim_angle_rad: f64,
    pub keep_longest_stretch: bool,
}

/// Convert file points to internal `(u, z)` points (right-hand convention,
/// z up), oriented so that `u` increases, and the mapping back; `lines` are
/// the file lines of the points (empty when they were not read from a file:
/// messages then number the points). The points span laterally between
/// [`MIN_PROFILE_SPAN_M`] and [`MAX_PROFILE_SPAN_M`] ("check the unit"
/// otherwise), and the usable stretch is chosen by the rule of
/// [`stretch`]: steep faces at the ends are trimmed, a profile that folds
/// back, repeats its lateral coordinate or breaks inside is refused naming
/// the line (or, with `keep_longest_stretch`, cut to its longest usable
/// stretch with a warning).
pub(crate) fn internal_points(
    path: &std::path::Path,
    points_file_m: &[[f64; 2]],
    lines: &[usize],
    z_down: bool,
    y_offset_m: f64,
    options: StretchOptions,
) -> Result<InternalPoints, ProfileError> {
    let mapping = FileMapping {
        y_sign: -1.0,
        y_offset_m,
        z_sign: if z_down { -1.0 } else { 1.0 },
        z_offset_m: 0.0,
    };
    let mut pts: Vec<(f64, f64)> = points_file_m
        .iter()
        .map(|p| mapping.from_file(p[0], p[1]))
        .collect();
    let mut lines: Vec<usize> = if lines.len() == pts.len() {
        lines.to_vec()
    } else {
        Vec::new()
    };
    let reversed = pts.len() >= 2 && pts[0].0 > pts[pts.len() - 1].0;
    if reversed {
        pts.reverse();
        lines.reverse();
    }
    if pts.len() < 4 {
        return Err(ProfileError::Invalid {
            path: path.to_path_buf(),
            rule: format!("a profile needs at least 4 points, found {}", pts.len()),
        });
    }
    let names = stretch::PointNames {
        lines: &lines,
        reversed,
        n: pts.len(),
    };
    if let Some(p) = pts
        .iter()
        .position(|p| !(p.0.is_finite() && p.1.is_finite()))
    {
        return Err(ProfileError::AtPoint {
            path: path.to_path_buf(),
            line: (!lines.is_empty()).then(|| names.number(p)),
            point: names.position(p),
            rule: "the point is not finite".into(),
        });
    }
    bounds::check_span(path, pts.iter().map(|p| p.0))?;
    let kept = stretch::usable_stretch(
        path,
        &pts,
        &names,
        &mapping,
        options.trim_angle_rad,
        options.keep_longest_stretch,
    )?;
    let kept_pts = &pts[kept.first..=kept.last];
    Ok(InternalPoints {
        u: kept_pts.iter().map(|p| p.0).collect(),
        z: kept_pts.iter().map(|p| p.1).collect(),
        mapping,
        warning: kept.warning,
    })
}
