//! Rail profile: one convex head function, placed on the track by its gauge
//! point.

use std::path::{Path, PathBuf};

use super::{
    FileMapping, ProfileCurve, ProfileError, ProfileWarning, StretchOptions, internal_points,
};
use crate::geometry::spline::Scheme;

/// Sampling step for the convexity check (m).
const SCAN_STEP_M: f64 = 5e-5;

/// A profile origin within this distance below the highest point of the
/// head is taken as the nominal top of rail (m).
const NOMINAL_TOP_TOLERANCE_M: f64 = 0.001;

/// Options of a rail profile.
#[derive(Debug, Clone, PartialEq)]
pub struct RailProfileOptions {
    /// Spline scheme of the head function.
    pub scheme: Scheme,
    /// Faces steeper than this (rad) at the profile's ends are dropped
    /// (the gauge point is still found on the full profile).
    pub trim_angle_rad: f64,
    /// Height of the gauge measuring point below the top of the rail (m):
    /// 14 mm (EN 13848-1).
    pub gauge_height_m: f64,
    /// Concave curvature tolerated on the head (1/m); larger is an error.
    pub max_concave_curvature_1_m: f64,
    /// Keep the longest usable stretch of a profile that folds back,
    /// repeats its lateral coordinate or breaks inside, instead of refusing
    /// it; the profile then carries a warning naming the dropped lines
    /// ([`RailProfile::warnings`]).
    pub keep_longest_stretch: bool,
}

impl Default for RailProfileOptions {
    fn default() -> Self {
        Self {
            scheme: Scheme::Cubic,
            trim_angle_rad: 80f64.to_radians(),
            gauge_height_m: 0.014,
            max_concave_curvature_1_m: super::wheel::CONVEXITY_TOLERANCE_1_M,
            keep_longest_stretch: false,
        }
    }
}

/// Where a rail sits: the track's gauge, the distance between the rail
/// space curves of its tables, and the rail inclination.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RailPlacement {
    /// Track gauge, between the gauge points (m).
    pub gauge_m: f64,
    /// Distance between the two rail space curves (m).
    pub rail_spacing_m: f64,
    /// Rail inclination towards the track centre (rad).
    pub inclination_rad: f64,
}

/// A rail profile as read (internal convention, not yet placed).
#[derive(Debug, Clone, PartialEq)]
pub struct RailProfile {
    path: PathBuf,
    options: RailProfileOptions,
    /// All points (internal u, z), for the gauge point.
    outline: Vec<(f64, f64)>,
    head: ProfileCurve,
    mapping: FileMapping,
    warnings: Vec<ProfileWarning>,
}

/// A rail profile placed on its rail space curve: `z(u)` in the rail frame
/// (u along the rail's lateral axis towards the track centre, z along the
/// rail's normal), origin on the rail space curve.
#[derive(Debug, Clone, PartialEq)]
pub struct PlacedRailProfile {
    head: ProfileCurve,
    mapping: FileMapping,
    /// Placement shift applied in the rail frame (m).
    pub shift_u_m: f64,
    pub shift_z_m: f64,
    /// The gauge point in the placed coordinates (m).
    pub gauge_point_m: (f64, f64),
}

impl RailProfile {
    /// Build from profile-file points (m, file convention). `path` and
    /// `lines` (the file line of each point; empty for points not read from
    /// a file) are used in messages.
    pub fn from_points(
        path: &Path,
        points_file_m: &[[f64; 2]],
        lines: &[usize],
        z_down: bool,
        options: RailProfileOptions,
    ) -> Result<Self, ProfileError> {
        let kept = internal_points(
            path,
            points_file_m,
            lines,
            z_down,
            0.0,
            StretchOptions {
                trim_angle_rad: options.trim_angle_rad,
                keep_longest_stretch: options.keep_longest_stretch,
            },
        )?;
        let (u, z, mapping) = (kept.u, kept.z, kept.mapping);
        let warnings: Vec<ProfileWarning> = kept.warning.into_iter().collect();
        let head =
            ProfileCurve::fit(options.scheme, &u, &z, u[0], u[u.len() - 1]).map_err(|source| {
                ProfileError::Spline {
                    path: path.to_path_buf(),
                    source,
                }
            })?;
        let (u0, u1) = head.domain_m();
        let n = ((u1 - u0) / SCAN_STEP_M).ceil() as usize;
        for k in 0..=n {
            let x = u0 + (u1 - u0) * k as f64 / n as f64;
            let p = head.at(x);
            if p.d2z_1_m > options.max_concave_curvature_1_m {
                return Err(ProfileError::NotConvex {
                    path: path.to_path_buf(),
                    region: "rail head",
                    radius_mm: 1e3 / p.d2z_1_m,
                    y_file_mm: mapping.to_file(x, 0.0).0 * 1e3,
                });
            }
        }
        let outline = points_file_m
            .iter()
            .map(|p| mapping.from_file(p[0], p[1]))
            .collect();
        Ok(Self {
            path: path.to_path_buf(),
            options,
            outline,
            head,
            mapping,
            warnings,
        })
    }

    /// The file it came from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Warnings of the build: the points dropped when the longest usable
    /// stretch was kept ([`RailProfileOptions::keep_longest_stretch`]).
    pub fn warnings(&self) -> &[ProfileWarning] {
        &self.warnings
    }

    /// Place the profile on its rail: rotate the outline into the track
    /// plane (the rail is inclined by `inclination_rad` towards the centre),
    /// find the top of the rail and the gauge point (`gauge_height_m` below
    /// the top, on the gauge side), and shift the profile so that the top is
    /// on the rail space curve and the gauge point is at half the gauge from
    /// the track centre, i.e. `(rail_spacing − gauge)/2` from the rail space
    /// curve towards the centre.
    ///
    /// The top of the rail is the file's origin when it lies within 1 mm of
    /// the highest point (rail files put their origin on the nominal top of
    /// rail; a rail inclined in its file, like EN 15302's rail A, has its
    /// highest point up to 0.5 mm above it), else the highest point. With
    /// the origin, the EN 15302 reference Δr functions are reproduced to
    /// 0.01–0.16 mm between their jumps (`preproc/tests/conicity_end_to_end.rs`);
    /// 14 mm below the highest point instead moves the jumps of profiles H and
    /// I by a tenth of a millimetre.
    pub fn placed(&self, placement: &RailPlacement) -> Result<PlacedRailProfile, ProfileError> {
        let (sb, cb) = placement.inclination_rad.sin_cos();
        // Rail frame (u, z) → track plane: u_t = u cos β + z sin β, z_t = −u sin β + z cos β.
        let to_track = |(u, z): (f64, f64)| (u * cb + z * sb, -u * sb + z * cb);
        let pts: Vec<(f64, f64)> = self.outline.iter().copied().map(to_track).collect();
        let highest = pts.iter().fold(f64::NEG_INFINITY, |m, p| m.max(p.1));
        // The top of the rail: the file's origin when it lies within
        // NOMINAL_TOP_TOLERANCE_M of the highest point (profile files put
        // their origin on the nominal top of rail, the running-surface
        // reference of EN 13848-1; on an inclined rail the highest point of
        // the head lies a little above it), else the highest point.
        let z_top = if highest.abs() <= NOMINAL_TOP_TOLERANCE_M {
            0.0
        } else {
            highest
        };
        let z_g = z_top - self.options.gauge_height_m;
        let mut u_g = f64::NEG_INFINITY;
        for w in pts.windows(2) {
            let ((ua, za), (ub, zb)) = (w[0], w[1]);
            if (za - z_g) * (zb - z_g) <= 0.0 && za != zb {
                let f = (z_g - za) / (zb - za);
                u_g = u_g.max(ua + f * (ub - ua));
            }
        }
        if !u_g.is_finite() {
            return Err(ProfileError::Invalid {
                path: self.path.clone(),
                rule: format!(
                    "the profile does not reach {:.1} mm below the top of the rail, where the gauge is measured",
                    self.options.gauge_height_m * 1e3
                ),
            });
        }
        let target_u = 0.5 * (placement.rail_spacing_m - placement.gauge_m);
        let (du_t, dz_t) = (target_u - u_g, -z_top);
        // Track plane → rail frame: u = u_t cos β − z_t sin β, z = u_t sin β + z_t cos β.
        let (du, dz) = (du_t * cb - dz_t * sb, du_t * sb + dz_t * cb);
        let mut mapping = self.mapping;
        mapping.y_offset_m -= mapping.y_sign * du;
        mapping.z_offset_m -= mapping.z_sign * dz;
        let g = (target_u, z_g - z_top);
        Ok(PlacedRailProfile {
            head: self.head.shifted(du, dz),
            mapping,
            shift_u_m: du,
            shift_z_m: dz,
            gauge_point_m: (g.0 * cb - g.1 * sb, g.0 * sb + g.1 * cb),
        })
    }
}

impl PlacedRailProfile {
    /// The head function z(u) in the rail frame.
    #[inline]
    pub fn head(&self) -> &ProfileCurve {
        &self.head
    }

    /// File coordinates (m) of a placed internal point.
    pub fn to_file_m(&self, u_m: f64, z_m: f64) -> (f64, f64) {
        self.mapping.to_file(u_m, z_m)
    }

    /// Placed internal coordinates (m) of a file point (inverse of
    /// [`Self::to_file_m`]).
    pub fn from_file_m(&self, y_m: f64, z_m: f64) -> (f64, f64) {
        self.mapping.from_file(y_m, z_m)
    }
}
