//! Wheel profile: the tread and flange functions of paper Fig. 6, found
//! automatically from the profile's curvature.
//!
//! # How the profile is split
//!
//! With `z` up and the wheel's material above its profile, a stretch is
//! **convex** where its curvature κ = z''/(1 + z'²)^{3/2} ≥ 0 (the flange
//! tip; a cone counts as convex) and concave where κ < 0 (the throat
//! between tread and flange, a hollow tread). Curvatures are measured over a
//! 2 mm window (the change of the slope angle across it), so that
//! measurement noise in the points does not count as shape.
//!
//! 1. Every stretch whose concave radius is below `throat_radius_m` (20 mm)
//!    — the **throat**, and on worn profiles any kink of a hollow tread — is
//!    a place where a rail head cannot rest: the profile is **split** at its
//!    most concave point. (A flange always gets its own piece: without a
//!    sharp throat the split is the most concave point within 25 mm before
//!    the flange's inflection.)
//! 2. The piece holding the flange tip (the lowest point) is a **flange**
//!    function, and so is any steep piece (mean slope above 45°) between the
//!    tread and it (a flank with a dent); the others are **tread** functions
//!    (usually one).
//!
//! Each piece is thus convex except for concave stretches milder than the
//! throat limit, which is what the Newton search needs. A piece can still
//! hold several minima of the gap where its concave stretches meet rail
//! arcs of another radius (S1002's tread and flange root on UIC60 around
//! 5 mm of shift): the contact search returns every one of them
//! (docs/reference/06-contact-detection.md §6.7). A profile that cannot be split into
//! at most [`MAX_SEGMENTS`] pieces (a noisy or badly worn measurement) is an
//! error; a rail head must be convex everywhere ([`super::RailProfile`]).
//!
//! The paper drops the throat altogether. For a conical profile such as the
//! ML95-like one no contact ever lies there, but S1002 on UIC60 1:40 rolls
//! through its throat between about 5.5 and 7 mm of lateral displacement
//! (the classic jump to flange contact), and worn profiles (EN 15302's
//! profile H) have kinks on the tread: dropping those stretches would leave
//! the wheel unsupported. Splitting at the most concave point keeps each
//! function's Newton search well posed while no part of the profile is
//! lost. Whether a
//! contact on a concave stretch is Hertzian is then decided by its relative
//! curvature ([`crate::forces::hertz`]).
//!
//! Every wheel has a flange: a flange height (depth of the flange tip
//! below the tread at the taping line) outside
//! [`MIN_FLANGE_HEIGHT_M`](super::MIN_FLANGE_HEIGHT_M) …
//! [`MAX_FLANGE_HEIGHT_M`](super::MAX_FLANGE_HEIGHT_M) is refused ("check
//! the unit").

use std::path::{Path, PathBuf};

use super::{
    FileMapping, ProfileCurve, ProfileError, ProfileWarning, StretchOptions, bounds,
    internal_points,
};
use crate::geometry::spline::Scheme;

/// Concave curvature tolerated where a region must be convex (1/m): a
/// concave radius larger than 1 m counts as straight (spline round-off on
/// straight flanks and cones).
pub const CONVEXITY_TOLERANCE_1_M: f64 = 1.0;

/// Most pieces a wheel profile may be split into.
pub const MAX_SEGMENTS: usize = 6;

/// Sampling step used to locate the regions (m).
const SCAN_STEP_M: f64 = 5e-5;

/// How far before the flange's inflection a split is looked for when the
/// profile has no sharp throat (m).
const THROAT_SEARCH_M: f64 = 0.025;

/// Window over which curvatures are measured (m).
const CURVATURE_WINDOW_M: f64 = 0.002;

/// A first piece narrower than this (m) lying wholly beyond
/// [`FIELD_SIDE_M`] on the field side is the wheel's outer chamfer and is
/// dropped.
const MIN_END_SEGMENT_M: f64 = 0.010;
const FIELD_SIDE_M: f64 = 0.040;

/// How much lower than the kept profile's lowest point the file's lowest
/// point may lie before the trimming is said to have cut the flange off (m).
const FLANGE_LOST_TOLERANCE_M: f64 = 0.001;

/// The trimming of steep faces at the profile's ends (the usable stretch,
/// [`super::internal_points`]) must not cut away the flange: a flank
/// steeper than the trim angle beyond which the profile never flattens
/// again (a steep face inside the stretch is refused at its line already),
/// or the longest stretch kept with `keep_longest_stretch`, would otherwise
/// leave a wheel without its flange, and the wheelset would run through its
/// rails. That is an error naming the tip and the steepest face.
fn check_flange_kept(
    path: &Path,
    points_file_m: &[[f64; 2]],
    mapping: &FileMapping,
    kept_u: &[f64],
    kept_z: &[f64],
    trim_angle_rad: f64,
) -> Result<(), ProfileError> {
    let all: Vec<(f64, f64)> = points_file_m
        .iter()
        .map(|p| mapping.from_file(p[0], p[1]))
        .collect();
    let Some(&(tip_u, tip_z)) = all.iter().min_by(|a, b| a.1.total_cmp(&b.1)) else {
        return Ok(());
    };
    let kept_min = kept_z.iter().copied().fold(f64::INFINITY, f64::min);
    if tip_z >= kept_min - FLANGE_LOST_TOLERANCE_M || !tip_z.is_finite() {
        return Ok(());
    }
    // The steepest face between the kept stretch and the tip.
    let (lo, hi) = if tip_u > kept_u[kept_u.len() - 1] {
        (kept_u[kept_u.len() - 1], tip_u)
    } else {
        (tip_u, kept_u[0])
    };
    let mut sorted = all.clone();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let steepest = sorted
        .windows(2)
        .filter(|w| w[0].0 >= lo && w[1].0 <= hi && w[1].0 > w[0].0)
        .map(|w| (((w[1].1 - w[0].1) / (w[1].0 - w[0].0)).abs().atan(), w[0]))
        .max_by(|a, b| a.0.total_cmp(&b.0));
    let (tip_y, tip_zf) = mapping.to_file(tip_u, tip_z);
    let face = steepest.map_or(String::new(), |(angle, (u, z))| {
        let (y, _) = mapping.to_file(u, z);
        format!(
            ", up to {:.1}° near file y = {:.2} mm",
            angle.to_degrees(),
            y * 1e3
        )
    });
    Err(ProfileError::Invalid {
        path: path.to_path_buf(),
        rule: format!(
            "the flange tip (file y = {:.2} mm, z = {:.2} mm) lies beyond faces steeper than {:.0}°{face}: the profile would lose its flange. A flank that steep puts the contact normal within {:.0}° of horizontal, outside the contact model (raise the trim angle only for a profile whose flank really is that steep)",
            tip_y * 1e3,
            tip_zf * 1e3,
            trim_angle_rad.to_degrees(),
            90.0 - trim_angle_rad.to_degrees(),
        ),
    })
}

/// The two contact zones of a wheel (paper §4.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Zone {
    Tread,
    Flange,
}

impl Zone {
    /// Both zones, tread first.
    pub const BOTH: [Zone; 2] = [Zone::Tread, Zone::Flange];

    /// "tread" / "flange".
    pub fn name(self) -> &'static str {
        match self {
            Zone::Tread => "tread",
            Zone::Flange => "flange",
        }
    }
}

/// Options of a wheel profile.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelProfileOptions {
    /// Spline scheme of the profile functions (paper §3: cubic).
    pub scheme: Scheme,
    /// Rolling radius at the taping line (m).
    pub nominal_radius_m: f64,
    /// Lateral distance from the taping line to the flange back (m); 0.070
    /// for S1002 and most European profiles (EN 13715).
    pub flange_back_m: f64,
    /// File `y` of the taping line (m); 0 when the file's origin is there.
    pub taping_line_y_m: f64,
    /// Concave radius below which the profile is split (m).
    pub throat_radius_m: f64,
    /// Faces steeper than this (rad) at the profile's ends are dropped.
    pub trim_angle_rad: f64,
    /// Keep the longest usable stretch of a profile that folds back,
    /// repeats its lateral coordinate or breaks inside, instead of refusing
    /// it; the profile then carries a warning naming the dropped lines
    /// ([`WheelProfile::warnings`]).
    pub keep_longest_stretch: bool,
}

impl Default for WheelProfileOptions {
    fn default() -> Self {
        Self {
            scheme: Scheme::Cubic,
            nominal_radius_m: 0.46,
            flange_back_m: 0.070,
            taping_line_y_m: 0.0,
            throat_radius_m: 0.020,
            trim_angle_rad: 80f64.to_radians(),
            keep_longest_stretch: false,
        }
    }
}

/// One convex piece of a wheel profile.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelSegment {
    pub zone: Zone,
    pub curve: ProfileCurve,
}

/// A wheel profile split into tread and flange functions.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelProfile {
    path: PathBuf,
    options: WheelProfileOptions,
    /// Pieces in order of increasing u (field side first, flange last).
    segments: Vec<WheelSegment>,
    /// Split points between the pieces (u, m).
    splits_m: Vec<f64>,
    flange_tip_u_m: Option<f64>,
    mapping: FileMapping,
    warnings: Vec<ProfileWarning>,
}

impl WheelProfile {
    /// Build from profile-file points (m, file convention; `z_down` as the
    /// file's format says). `path` and `lines` (the file line of each
    /// point; empty for points not read from a file) are used in messages.
    pub fn from_points(
        path: &Path,
        points_file_m: &[[f64; 2]],
        lines: &[usize],
        z_down: bool,
        options: WheelProfileOptions,
    ) -> Result<Self, ProfileError> {
        let invalid = |rule: String| ProfileError::Invalid {
            path: path.to_path_buf(),
            rule,
        };
        if !(options.nominal_radius_m > 0.05 && options.nominal_radius_m < 2.0) {
            return Err(invalid(format!(
                "nominal wheel radius {} m must lie in 0.05 … 2 m",
                options.nominal_radius_m
            )));
        }
        let kept = internal_points(
            path,
            points_file_m,
            lines,
            z_down,
            options.taping_line_y_m,
            StretchOptions {
                trim_angle_rad: options.trim_angle_rad,
                keep_longest_stretch: options.keep_longest_stretch,
            },
        )?;
        let (u, z, mut mapping) = (kept.u, kept.z, kept.mapping);
        let warnings: Vec<ProfileWarning> = kept.warning.into_iter().collect();
        check_flange_kept(
            path,
            points_file_m,
            &mapping,
            &u,
            &z,
            options.trim_angle_rad,
        )?;
        let (u0, u1) = (u[0], u[u.len() - 1]);
        if !(u0 <= 0.0 && u1 >= 0.0) {
            return Err(invalid(format!(
                "the taping line (file y = {} mm) lies outside the profile (file y from {:.1} to {:.1} mm)",
                options.taping_line_y_m * 1e3,
                mapping.to_file(u1, 0.0).0 * 1e3,
                mapping.to_file(u0, 0.0).0 * 1e3,
            )));
        }
        let whole = ProfileCurve::fit(options.scheme, &u, &z, u0, u1).map_err(|source| {
            ProfileError::Spline {
                path: path.to_path_buf(),
                source,
            }
        })?;
        // z = 0 at the taping line.
        let z_ref = whole.at(0.0).z_m;
        let whole = whole.shifted(0.0, -z_ref);
        mapping.z_offset_m = mapping.z_sign * z_ref;

        let n = ((u1 - u0) / SCAN_STEP_M).ceil() as usize;
        let grid: Vec<f64> = (0..=n)
            .map(|k| u0 + (u1 - u0) * k as f64 / n as f64)
            .collect();
        let zs: Vec<f64> = grid.iter().map(|&x| whole.at(x).z_m).collect();
        let kappa: Vec<f64> = grid
            .iter()
            .map(|&x| windowed_curvature(&whole, x, u0, u1))
            .collect();
        let (tip, tip_z) = zs
            .iter()
            .copied()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("non-empty grid");
        bounds::check_flange_height(path, -tip_z)?;
        if grid[tip] <= 0.0 {
            return Err(invalid(
                "the flange lies on the field side of the taping line: the file's lateral axis seems mirrored (y must grow towards the field side, flange at negative y); import it with mirror_y".into(),
            ));
        }
        // The flange's inflection: walking from the tip towards the tread, the
        // first point where the profile turns concave.
        let inflection = {
            let mut k = tip;
            while k > 0 && kappa[k] >= -CONVEXITY_TOLERANCE_1_M {
                k -= 1;
            }
            k
        };
        // Split at the most concave point of every sharply concave stretch
        // (on the flange side only up to the tip).
        let kappa_throat = 1.0 / options.throat_radius_m;
        let last = tip;
        let mut splits = Vec::new();
        let mut i = 0;
        while i <= last {
            if kappa[i] < -kappa_throat {
                let start = i;
                while i < last && kappa[i + 1] < -kappa_throat {
                    i += 1;
                }
                let deepest = (start..=i)
                    .min_by(|&a, &b| kappa[a].total_cmp(&kappa[b]))
                    .expect("non-empty stretch");
                splits.push(grid[deepest]);
            }
            i += 1;
        }
        // A flange always gets its own piece: without a sharp throat, split at
        // the most concave point of the 25 mm before the inflection.
        if !splits.iter().any(|&u| u > 0.0 && u < grid[tip]) {
            let k = inflection;
            let taping = grid.partition_point(|&x| x < 0.0).min(n);
            let reach = (THROAT_SEARCH_M / SCAN_STEP_M) as usize;
            let lo = k.saturating_sub(reach).max(taping);
            let at = (lo..=k)
                .min_by(|&a, &b| kappa[a].total_cmp(&kappa[b]))
                .unwrap_or(k);
            splits.push(grid[at]);
            splits.sort_by(f64::total_cmp);
        }
        // Pieces between the splits; drop narrow end pieces (chamfers).
        let mut bounds = vec![u0];
        bounds.extend(splits.iter().copied());
        bounds.push(u1);
        let mut pieces: Vec<(f64, f64)> = bounds.windows(2).map(|w| (w[0], w[1])).collect();
        // A narrow first piece far out on the field side is the chamfer.
        if pieces.len() > 1
            && pieces[0].1 - pieces[0].0 < MIN_END_SEGMENT_M
            && pieces[0].1 < -FIELD_SIDE_M
        {
            pieces.remove(0);
        }
        if pieces.len() > MAX_SEGMENTS {
            return Err(invalid(format!(
                "the profile has {} sharply concave kinks (radius below {:.0} mm): too worn or too noisy to be split into at most {MAX_SEGMENTS} convex pieces",
                pieces.len() - 1,
                options.throat_radius_m * 1e3
            )));
        }
        if !pieces.iter().any(|p| p.0 <= 0.0 && p.1 >= 0.0) {
            return Err(invalid(
                "the taping line falls on a sharply concave kink: not a usable wheel profile"
                    .into(),
            ));
        }
        // Flange pieces: the one holding the tip, and steep pieces (mean slope
        // above 45°) between the tread and it.
        let segments = pieces
            .iter()
            .map(|&(a, b)| {
                let holds_tip = a <= grid[tip] + 1e-12 && b >= grid[tip] - 1e-12;
                let steep = ((whole.at(b).z_m - whole.at(a).z_m) / (b - a)).abs() > 1.0;
                WheelSegment {
                    zone: if holds_tip || (steep && a > 0.0) {
                        Zone::Flange
                    } else {
                        Zone::Tread
                    },
                    curve: whole.restricted(a, b),
                }
            })
            .collect();
        let splits_m = pieces.windows(2).map(|w| w[0].1).collect();
        Ok(Self {
            path: path.to_path_buf(),
            options,
            segments,
            splits_m,
            flange_tip_u_m: Some(grid[tip]),
            mapping,
            warnings,
        })
    }

    /// The convex pieces, field side first.
    #[inline]
    pub fn segments(&self) -> &[WheelSegment] {
        &self.segments
    }

    /// The pieces of one zone.
    pub fn zone_segments(&self, zone: Zone) -> impl Iterator<Item = &WheelSegment> {
        self.segments.iter().filter(move |s| s.zone == zone)
    }

    /// The piece of `zone` containing internal position `u_m`, or the
    /// zone's first piece.
    pub fn zone(&self, zone: Zone) -> Option<&ProfileCurve> {
        self.zone_segments(zone).next().map(|s| &s.curve)
    }

    /// The split points between the pieces (internal u, m).
    pub fn splits_m(&self) -> &[f64] {
        &self.splits_m
    }

    /// The options it was built with.
    pub fn options(&self) -> &WheelProfileOptions {
        &self.options
    }

    /// Rolling radius at the taping line (m).
    pub fn nominal_radius_m(&self) -> f64 {
        self.options.nominal_radius_m
    }

    /// Wheel radius at internal lateral position `u_m` (m).
    pub fn radius_m(&self, u_m: f64) -> f64 {
        let curve = self
            .segments
            .iter()
            .find(|s| s.curve.contains(u_m, 0.0))
            .unwrap_or(&self.segments[0]);
        self.options.nominal_radius_m - curve.curve.at(u_m).z_m
    }

    /// Internal u of the flange tip (m).
    pub fn flange_tip_u_m(&self) -> Option<f64> {
        self.flange_tip_u_m
    }

    /// Depth of the flange tip below the taping line (m), 0 without flange.
    pub fn flange_depth_m(&self) -> f64 {
        self.flange_tip_u_m
            .map_or(0.0, |u| self.options.nominal_radius_m - self.radius_m(u))
            .abs()
    }

    /// Lateral distance from the taping line to the flange back (m).
    pub fn flange_back_m(&self) -> f64 {
        self.options.flange_back_m
    }

    /// File coordinates (m) of an internal point.
    pub fn to_file_m(&self, u_m: f64, z_m: f64) -> (f64, f64) {
        self.mapping.to_file(u_m, z_m)
    }

    /// Internal coordinates (m) of a file point (inverse of
    /// [`Self::to_file_m`]).
    pub fn from_file_m(&self, y_m: f64, z_m: f64) -> (f64, f64) {
        self.mapping.from_file(y_m, z_m)
    }

    /// The file the profile came from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Warnings of the build: the points dropped when the longest usable
    /// stretch was kept ([`WheelProfileOptions::keep_longest_stretch`]).
    pub fn warnings(&self) -> &[ProfileWarning] {
        &self.warnings
    }
}

/// Curvature over a window: the change of the slope angle across
/// [`CURVATURE_WINDOW_M`] divided by the arc length (1/m).
fn windowed_curvature(curve: &ProfileCurve, u: f64, lo: f64, hi: f64) -> f64 {
    let h = 0.5 * CURVATURE_WINDOW_M;
    let (a, b) = ((u - h).max(lo), (u + h).min(hi));
    let (pa, pb) = (curve.at(a), curve.at(b));
    let arc = (b - a) * (1.0 + (0.5 * (pa.dz + pb.dz)).powi(2)).sqrt();
    (pb.dz.atan() - pa.dz.atan()) / arc
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1:20 cone with a flange: tread z = −u/20 … (internal convention),
    /// written in file convention (y = −u, z up).
    fn cone_with_flange() -> Vec<[f64; 2]> {
        let mut pts = Vec::new();
        // tread from u = −0.06 to 0.030
        let mut u = -0.06;
        while u < 0.030 {
            pts.push([-u, -u / 20.0]);
            u += 0.0005;
        }
        // concave fillet radius 12 mm, then flank at 70°, round tip radius 10 mm:
        // approximate with a dense polyline of a smooth function for the test.
        let z_at = |u: f64| -> f64 {
            let t = (u - 0.030) / 0.020; // 0 … 1 over the flank
            -0.0015 - 0.028 * (3.0 * t * t - 2.0 * t * t * t)
        };
        let mut u = 0.0305;
        while u <= 0.050 {
            pts.push([-u, z_at(u)]);
            u += 0.0002;
        }
        pts
    }

    /// Found by fuzzing (tests/extremes/fuzz.rs): a point at y = 10²² m
    /// overflowed the scan grid's capacity (a panic); a profile wider than
    /// 0.5 m is now an error, for wheels and rails alike.
    #[test]
    fn a_profile_spanning_kilometres_is_refused() {
        let pts = [
            [-0.06, 0.03],
            [-0.03, 0.002],
            [-0.02, 0.0005],
            [0.0, 0.0],
            [0.02, 0.0009],
            [1e22, 0.0021],
            [0.06, 0.0035],
        ];
        let path = Path::new("w.dat");
        let e = WheelProfile::from_points(path, &pts, &[], false, WheelProfileOptions::default())
            .unwrap_err();
        assert!(e.to_string().contains("lateral span"), "{e}");
        assert!(e.to_string().contains("check the unit"), "{e}");
        let wide: Vec<[f64; 2]> = (0..50).map(|k| [k as f64 * 0.1, 0.0]).collect();
        let e = crate::geometry::profile::RailProfile::from_points(
            path,
            &wide,
            &[],
            false,
            crate::geometry::profile::RailProfileOptions::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("is 4900.000 mm"), "{e}");
    }

    /// Every wheel has a flange (tables/ ships none without one): a plain
    /// cone is refused with its flange height and the bound.
    #[test]
    fn a_wheel_without_a_flange_is_refused() {
        let pts: Vec<[f64; 2]> = (0..200)
            .map(|k| {
                let u = -0.06 + k as f64 * 0.0006;
                [-u, -u / 20.0]
            })
            .collect();
        let e = WheelProfile::from_points(
            Path::new("cone"),
            &pts,
            &[],
            false,
            WheelProfileOptions::default(),
        )
        .unwrap_err();
        let msg = e.to_string();
        assert!(
            // The lowest point, 1:20 below the taping line at u = 59.4 mm.
            matches!(e, ProfileError::Implausible { value_mm, .. } if (value_mm - 2.97).abs() < 1e-6),
            "{msg}"
        );
        for needle in ["flange height", "10–50 mm", "check the unit", "cone"] {
            assert!(msg.contains(needle), "{needle}: {msg}");
        }
    }

    #[test]
    fn flanged_profile_splits_into_tread_and_flange() {
        let w = WheelProfile::from_points(
            Path::new("flanged"),
            &cone_with_flange(),
            &[],
            false,
            WheelProfileOptions::default(),
        )
        .unwrap();
        let zones: Vec<Zone> = w.segments().iter().map(|s| s.zone).collect();
        assert_eq!(zones.last(), Some(&Zone::Flange));
        assert!(zones.contains(&Zone::Tread));
        let tip = w.flange_tip_u_m().unwrap();
        assert!(tip > 0.045, "{tip}");
        assert!(w.flange_depth_m() > 0.025);
    }

    #[test]
    fn mirrored_file_is_reported() {
        let pts: Vec<[f64; 2]> = cone_with_flange().iter().map(|p| [-p[0], p[1]]).collect();
        let e = WheelProfile::from_points(
            Path::new("mirrored"),
            &pts,
            &[],
            false,
            WheelProfileOptions::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("mirror"), "{e}");
    }

    #[test]
    fn dented_flank_gives_a_second_flange_piece() {
        // A flange whose flank has a sharply concave dent.
        let mut pts = cone_with_flange();
        for p in pts.iter_mut() {
            let u = -p[0];
            if (0.040..0.046).contains(&u) {
                let t = (u - 0.043) / 0.003;
                p[1] += 0.0015 * (1.0 - t * t);
            }
        }
        let w = WheelProfile::from_points(
            Path::new("dented"),
            &pts,
            &[],
            false,
            WheelProfileOptions::default(),
        )
        .unwrap();
        let flange_pieces = w.zone_segments(Zone::Flange).count();
        assert_eq!(flange_pieces, 2, "{:?}", w.splits_m());
    }

    #[test]
    fn a_noisy_profile_is_an_error() {
        // Sharp zig-zags every 2 mm on the tread: far more kinks than pieces
        // allowed.
        let pts: Vec<[f64; 2]> = cone_with_flange()
            .into_iter()
            .enumerate()
            .map(|(k, [y, z])| {
                let zig = if -y < 0.02 && (k / 4) % 2 == 1 {
                    0.0004
                } else {
                    0.0
                };
                [y, z + zig]
            })
            .collect();
        let e = WheelProfile::from_points(
            Path::new("noisy"),
            &pts,
            &[],
            false,
            WheelProfileOptions::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("kinks"), "{e}");
    }
}
