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

mod curve;
mod rail;
pub mod rail_cant;
mod wheel;

pub use curve::{CurvePoint, ProfileCurve};
pub use rail::{PlacedRailProfile, RailPlacement, RailProfile, RailProfileOptions};
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
    #[error("{path}: {source}")]
    Spline {
        path: PathBuf,
        #[source]
        source: SplineError,
    },
}

/// Widest lateral span of a profile (m): wheel and rail profiles span
/// about 0.15 m, so anything beyond 2 m is a unit error or a broken file.
pub const MAX_PROFILE_SPAN_M: f64 = 2.0;

/// Convert file points to sorted internal `(u, z)` points (right-hand
/// convention, z up) and the mapping back. Points are kept in order of
/// increasing `u`; the steep ends (faces steeper than `trim_angle_rad`, and
/// any part where the profile folds back in `u`) are dropped, since the
/// contact model describes a profile as a function z(u). A span wider than
/// [`MAX_PROFILE_SPAN_M`] is refused.
pub(crate) fn internal_points(
    path: &std::path::Path,
    points_file_m: &[[f64; 2]],
    z_down: bool,
    y_offset_m: f64,
    trim_angle_rad: f64,
) -> Result<(Vec<f64>, Vec<f64>, FileMapping), ProfileError> {
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
    if pts.len() >= 2 && pts[0].0 > pts[pts.len() - 1].0 {
        pts.reverse();
    }
    let invalid = |rule: String| ProfileError::Invalid {
        path: path.to_path_buf(),
        rule,
    };
    if pts.len() < 4 {
        return Err(invalid(format!(
            "a profile needs at least 4 points, found {}",
            pts.len()
        )));
    }
    // Keep the longest run of segments that advance in u and are not steeper
    // than the trim angle.
    let max_slope = trim_angle_rad.tan();
    let ok = |k: usize| {
        let (a, b) = (pts[k], pts[k + 1]);
        let du = b.0 - a.0;
        du > 0.0 && ((b.1 - a.1) / du).abs() <= max_slope
    };
    let (mut best, mut run_start) = ((0usize, 0usize), None);
    for k in 0..pts.len() - 1 {
        match (ok(k), run_start) {
            (true, None) => run_start = Some(k),
            (false, Some(s)) => {
                if k - s > best.1 - best.0 {
                    best = (s, k);
                }
                run_start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = run_start
        && pts.len() - 1 - s > best.1 - best.0
    {
        best = (s, pts.len() - 1);
    }
    let (first, last) = best; // segments first..last → points first..=last
    if last - first < 3 {
        return Err(invalid(format!(
            "no usable stretch of at least 4 points where the profile is a function of the lateral coordinate with faces flatter than {:.0}°",
            trim_angle_rad.to_degrees()
        )));
    }
    let kept = &pts[first..=last];
    // Wheel and rail profiles span about 0.15 m; the profiles are scanned
    // every 0.05 mm, so a span of 10²² m (found by fuzzing) overflowed the
    // scan grid's capacity, and one of 1 km would take 2 × 10⁷ points.
    let span_m = kept[kept.len() - 1].0 - kept[0].0;
    if span_m.is_nan() || span_m > MAX_PROFILE_SPAN_M {
        return Err(invalid(format!(
            "the profile spans {span_m:.4e} m laterally, more than {MAX_PROFILE_SPAN_M} m (a wheel or rail profile spans about 0.15 m): check the file's length unit"
        )));
    }
    // Report interior fold-backs the trimming would silently cut away.
    let dropped = pts.len() - kept.len();
    if dropped * 2 > pts.len() {
        return Err(invalid(format!(
            "only {} of {} points form a single-valued profile z(y) (the rest are steep faces or fold back); check the file's point order and convention",
            kept.len(),
            pts.len()
        )));
    }
    Ok((
        kept.iter().map(|p| p.0).collect(),
        kept.iter().map(|p| p.1).collect(),
        mapping,
    ))
}
