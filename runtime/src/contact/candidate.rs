//! A solved contact candidate: the quantities paper §4.2–4.4 needs from
//! the geometry (penetration, contact frame, angle, radii, curvatures).

use nalgebra::Vector3;

use super::geometry::{PairEval, SurfaceParams};
use crate::geometry::profile::Zone;
use crate::geometry::track::Side;

/// Principal curvatures at a contact (1/m), positive where the body is
/// convex towards the other (docs/reference/07-contact-forces.md §7.1).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Curvatures {
    /// Wheel, rolling direction: cos γ_w / r_roll (the surface of revolution).
    pub wheel_rolling_1_m: f64,
    /// Wheel, lateral: the profile's curvature (negative on a hollow tread).
    pub wheel_lateral_1_m: f64,
    /// Rail, rolling direction: the rail's own curvature seen along the
    /// contact normal (zero on straight track).
    pub rail_rolling_1_m: f64,
    /// Rail, lateral: the head profile's curvature.
    pub rail_lateral_1_m: f64,
}

/// How a candidate was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveMethod {
    /// Newton's method on the four contact equations (paper §4.2).
    Newton,
    /// Direct minimisation of the cross-sectional distance (s_w = 0), used
    /// where Newton's method fails because the contact is nearly conformal
    /// (singular Jacobian); see [`super::ContactOptions::minimisation_fallback`].
    Minimisation,
}

/// The solution of the contact equations for one wheel, rail and zone.
/// It is a contact when `penetration_m ≥ 0`; otherwise it is the closest
/// pair of points and `−penetration_m` is the gap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    pub side: Side,
    pub zone: Zone,
    /// Index of the wheel-profile piece it lies on ([`crate::geometry::profile::WheelProfile::segments`]).
    pub segment: usize,
    /// Surface parameters (paper's s_r, u_r, s_w, u_w).
    pub params: SurfaceParams,
    /// Newton iterations this solve took.
    pub iterations: u32,
    /// True when the solve had to start from the coarse search.
    pub cold_start: bool,
    /// Newton, or the minimisation fallback.
    pub method: SolveMethod,
    /// Penetration δ = −dᵀn (m), d = r_w − r_r (paper eq. 20–21).
    pub penetration_m: f64,
    /// Contact points on the wheel and on the rail (global, m).
    pub wheel_point: Vector3<f64>,
    pub rail_point: Vector3<f64>,
    /// Contact frame (docs/reference/01-units-frames.md §1): normal from the rail into the wheel, rolling
    /// direction (rail tangent projected ⟂ normal) and `lateral = normal × tangent`.
    pub normal: Vector3<f64>,
    pub tangent: Vector3<f64>,
    pub lateral: Vector3<f64>,
    /// Contact angle in the track's cross-section (rad): the tilt of the
    /// contact normal from the track-plane normal, positive towards the track
    /// centre (flange contact ≈ +1.2 rad), same sign rule on both sides.
    pub contact_angle_rad: f64,
    /// Rolling radius: distance of the wheel point from the axle (m).
    pub rolling_radius_m: f64,
    pub curvatures: Curvatures,
    /// The contact points in the profile files' own coordinates (y, z) (m),
    /// before any mirroring for the left side.
    pub wheel_profile_point_m: (f64, f64),
    pub rail_profile_point_m: (f64, f64),
}

impl Candidate {
    /// True when the bodies overlap (δ ≥ 0).
    pub fn in_contact(&self) -> bool {
        self.penetration_m >= 0.0
    }

    /// Lead/lag of a contact point: its distance ahead of the axle along the
    /// wheelset's forward direction (m), r·sin s_w.
    pub fn lead_m(&self) -> f64 {
        self.rolling_radius_m * self.params.s_wheel_rad.sin()
    }

    /// True when the solution is a local minimum of the gap across the
    /// profiles (a contact, or the closest approach of a piece), false at a
    /// maximum — the stationary point between two patches on one wheel,
    /// which solves the same equations (docs/reference/06-contact-detection.md §6.1).
    ///
    /// Moving the wheel point by an arc length ds along its profile changes
    /// the gap G = −δ by ½·(κ_w + κ_r/(1 + κ_r·G))·ds² at a stationary
    /// point: κ_w the wheel profile's curvature (convex towards the rail
    /// positive), κ_r/(1 + κ_r·G) the curvature of the rail head's parallel
    /// curve through the wheel point (κ_r convex positive). A minimum needs
    /// this relative lateral curvature to be positive; it is compared with
    /// −[`super::FLAT_RELATIVE_CURVATURE_1_M`] so that a flat pair (a cone on a
    /// flat rail top, relative curvature zero up to spline round-off) still
    /// counts as a contact. Where the parallel curve degenerates
    /// (1 + κ_r·G ≤ 0: an overlap deeper than the rail's radius of
    /// curvature) the solution is kept.
    pub fn is_gap_minimum(&self) -> bool {
        let (kw, kr) = (
            self.curvatures.wheel_lateral_1_m,
            self.curvatures.rail_lateral_1_m,
        );
        let scale = 1.0 - kr * self.penetration_m;
        scale <= 0.0 || kw + kr / scale > -FLAT_RELATIVE_CURVATURE_1_M
    }
}

/// Relative lateral curvature (1/m) below which a pair counts as flat when
/// telling minima of the gap from maxima ([`Candidate::is_gap_minimum`]):
/// a relative radius of 20 m, flat for a contact patch of millimetres (the
/// same floor as the settling's non-Hertzian contacts,
/// docs/reference/06-contact-detection.md §6.6).
pub const FLAT_RELATIVE_CURVATURE_1_M: f64 = 0.05;

/// Build a candidate from a converged evaluation.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn from_eval(
    side: Side,
    zone: Zone,
    segment: usize,
    params: SurfaceParams,
    iterations: u32,
    cold_start: bool,
    e: &PairEval,
    sigma: f64,
    nominal_radius_m: f64,
    inclination_rad: f64,
    wheel_to_file: impl Fn(f64, f64) -> (f64, f64),
    rail_to_file: impl Fn(f64, f64) -> (f64, f64),
) -> Candidate {
    let normal = e.rail_normal.normalize();
    let d = e.wheel_point - e.rail_point;
    let penetration_m = -d.dot(&normal);
    let tangent = (e.rail_ds - normal * e.rail_ds.dot(&normal)).normalize();
    let lateral = normal.cross(&tangent);
    let (rp, wp) = (e.rail_profile, e.wheel_profile);
    let rolling_radius_m = nominal_radius_m - wp.z_m;
    let curvatures = Curvatures {
        // cos γ_w of the wheel profile's slope angle γ_w = atan f_w'.
        wheel_rolling_1_m: wp.slope_cos() / rolling_radius_m,
        wheel_lateral_1_m: wp.curvature_1_m(),
        rail_rolling_1_m: -e.rail_d.t.dot(&normal),
        rail_lateral_1_m: -rp.curvature_1_m(),
    };
    Candidate {
        side,
        zone,
        segment,
        params,
        iterations,
        cold_start,
        method: SolveMethod::Newton,
        penetration_m,
        wheel_point: e.wheel_point,
        rail_point: e.rail_point,
        normal,
        tangent,
        lateral,
        contact_angle_rad: (-rp.dz).atan() + inclination_rad,
        rolling_radius_m,
        curvatures,
        wheel_profile_point_m: wheel_to_file(sigma * params.u_wheel_m, wp.z_m),
        rail_profile_point_m: rail_to_file(sigma * params.u_rail_m, rp.z_m),
    }
}

#[cfg(test)]
#[cfg(feature = "fixtures")] // the shared S1002/UIC60 wheelset
mod tests {
    use super::*;

    use crate::fixtures::wheelsets::centred_s1002_left_tread as tread_contact;

    fn with(kw: f64, kr: f64, penetration_m: f64) -> Candidate {
        let mut c = tread_contact();
        c.curvatures.wheel_lateral_1_m = kw;
        c.curvatures.rail_lateral_1_m = kr;
        c.penetration_m = penetration_m;
        c
    }

    /// Convex on convex, or a hollow wheel on a sharper rail: a minimum; a
    /// hollow wheel sharper than the rail: a maximum (between two patches);
    /// a flat pair counts as a contact.
    #[test]
    fn minima_and_maxima_of_the_gap_by_the_relative_curvature() {
        assert!(with(2.0, 3.3, 0.0).is_gap_minimum());
        assert!(with(-3.0, 3.3, 0.0).is_gap_minimum());
        assert!(!with(-4.0, 3.3, 0.0).is_gap_minimum());
        assert!(with(0.0, 0.0, 0.0).is_gap_minimum());
        assert!(with(-0.04, 0.0, 0.0).is_gap_minimum());
        assert!(!with(-0.06, 0.0, 0.0).is_gap_minimum());
    }

    /// Overlapping, the rail's parallel curve through the wheel point is
    /// sharper: a 12.9 mm throat on a 13 mm gauge corner is a maximum at
    /// touch and a minimum 0.2 mm deep; deeper than the rail's radius the
    /// solution is kept.
    #[test]
    fn the_overlap_sharpens_the_rail() {
        let (kw, kr) = (-1.0 / 0.0129, 1.0 / 0.013);
        assert!(!with(kw, kr, 0.0).is_gap_minimum());
        assert!(with(kw, kr, 2e-4).is_gap_minimum());
        assert!(with(kw, kr, 0.02).is_gap_minimum());
    }
}
