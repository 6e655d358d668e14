//! Where a body is relative to the track, and the motion of track-following
//! references (SPEC §1 frames: `t` forward, `n` left, `b = t × n` up).

use nalgebra::{Matrix3, Vector3};

use crate::element::Anchor;
use crate::track::{CenterlineTable, TrackError};

/// Fixed-point iterations of [`project_s`]; each one is exact on a straight
/// and contracts by the factor (lateral offset × curvature) on a curve.
const PROJECTION_ITERATIONS: usize = 3;

/// Track distance s (m) of the centreline point nearest to `position`
/// (global, m), from a guess `s_guess` (the previous value): the fixed point
/// of s ← s + (position − c(s))·t(s).
pub fn project_s(
    centerline: &CenterlineTable,
    position: &Vector3<f64>,
    s_guess: f64,
) -> Result<f64, TrackError> {
    let (lo, hi) = centerline.range_m();
    let mut s = s_guess.clamp(lo, hi);
    for _ in 0..PROJECTION_ITERATIONS {
        let c = centerline.at(s)?;
        s += (position - c.position).dot(&c.frame.t.normalize());
        if !(s >= lo && s <= hi) {
            // Report the point itself as off the tables.
            return Err(TrackError::OutOfRange {
                table: "centerline",
                coordinate: "s",
                value_m: s,
                min_m: lo,
                max_m: hi,
            });
        }
    }
    Ok(s)
}

/// A wheelset's position and attitude relative to the track.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrackRelative {
    /// Track distance of the centre (m).
    pub s_m: f64,
    /// Lateral displacement of the centre from the centreline (m), + left.
    pub lateral_m: f64,
    /// Height of the centre above the centreline (rail-top plane) (m).
    pub vertical_m: f64,
    /// Yaw relative to the track (rad), + nose left.
    pub yaw_rad: f64,
    /// Roll relative to the track (rad), + raising the left wheel.
    pub roll_rad: f64,
    /// Velocity of the centre along the track tangent (m/s).
    pub forward_speed_m_s: f64,
}

/// Track-relative position of a wheelset with centre `position`, axle
/// direction `axle` (unit, pointing left) and centre velocity `velocity`
/// at track distance `s_m`. Yaw ψ: the axle turned by ψ about `b` has
/// η·t = −sin ψ, η·n = cos ψ; roll: η·b = sin(roll).
pub fn track_relative(
    centerline: &CenterlineTable,
    s_m: f64,
    position: &Vector3<f64>,
    axle: &Vector3<f64>,
    velocity: &Vector3<f64>,
) -> Result<TrackRelative, TrackError> {
    let c = centerline.at(s_m)?;
    let (t, n, b) = (
        c.frame.t.normalize(),
        c.frame.n.normalize(),
        c.frame.b.normalize(),
    );
    let d = position - c.position;
    Ok(TrackRelative {
        s_m,
        lateral_m: d.dot(&n),
        vertical_m: d.dot(&b),
        yaw_rad: (-axle.dot(&t)).atan2(axle.dot(&n)),
        roll_rad: axle.dot(&b).clamp(-1.0, 1.0).asin(),
        forward_speed_m_s: velocity.dot(&t),
    })
}

/// Rotation (columns t, n, b, orthonormalised) of the track frame at `s_m`.
pub fn track_rotation(centerline: &CenterlineTable, s_m: f64) -> Result<Matrix3<f64>, TrackError> {
    let f = centerline.at(s_m)?.frame;
    let t = f.t.normalize();
    let n = (f.n - t * t.dot(&f.n)).normalize();
    Ok(Matrix3::from_columns(&[t, n, t.cross(&n)]))
}

/// Global position of a point given in the vehicle frame (x along the
/// track from the vehicle reference at `s_vehicle_m`, y left, z up).
pub fn vehicle_point(
    centerline: &CenterlineTable,
    s_vehicle_m: f64,
    point: &Vector3<f64>,
) -> Result<Vector3<f64>, TrackError> {
    let c = centerline.at(s_vehicle_m + point.x)?;
    let r = track_rotation(centerline, s_vehicle_m + point.x)?;
    Ok(c.position + r.column(1) * point.y + r.column(2) * point.z)
}

/// Anchor of a track-following reference whose origin is `origin` in the
/// vehicle frame, the vehicle reference being at `s_vehicle_m` and moving
/// along the track at `speed_m_s`: axes = track frame at s_vehicle + x,
/// velocity and angular velocity from the change of the track frame along
/// s (central difference over `ds_m`), times the speed.
pub fn reference_anchor(
    centerline: &CenterlineTable,
    s_vehicle_m: f64,
    origin: &Vector3<f64>,
    speed_m_s: f64,
    ds_m: f64,
) -> Result<Anchor, TrackError> {
    let s = s_vehicle_m + origin.x;
    let position = vehicle_point(centerline, s_vehicle_m, origin)?;
    let rotation = track_rotation(centerline, s)?;
    let (lo, hi) = centerline.range_m();
    let (s0, s1) = ((s - ds_m).max(lo), (s + ds_m).min(hi));
    let (velocity, angular_velocity) = if s1 > s0 {
        let p0 = vehicle_point(centerline, s_vehicle_m - (s - s0), origin)?;
        let p1 = vehicle_point(centerline, s_vehicle_m + (s1 - s), origin)?;
        let r0 = track_rotation(centerline, s0)?;
        let r1 = track_rotation(centerline, s1)?;
        let dr = (r1 - r0) / (s1 - s0);
        // ω̃ = Ṙ Rᵀ (skew), ω = its axial vector.
        let w = dr * rotation.transpose() * speed_m_s;
        let omega = Vector3::new(
            0.5 * (w[(2, 1)] - w[(1, 2)]),
            0.5 * (w[(0, 2)] - w[(2, 0)]),
            0.5 * (w[(1, 0)] - w[(0, 1)]),
        );
        ((p1 - p0) / (s1 - s0) * speed_m_s, omega)
    } else {
        (rotation.column(0) * speed_m_s, Vector3::zeros())
    };
    Ok(Anchor {
        position_m: position,
        rotation,
        velocity_m_s: velocity,
        angular_velocity_rad_s: angular_velocity,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track::straight_track;

    #[test]
    fn projection_and_relative_position_on_a_straight() {
        let track = straight_track(100.0, 0.1, 1.435, 1.5, 0.0);
        let c = &track.centerline;
        let p = c.at(40.0).unwrap().position + Vector3::new(0.0, 0.003, 0.43);
        let s = project_s(c, &p, 35.0).unwrap();
        assert!((s - 40.0).abs() < 1e-9, "{s}");
        let psi: f64 = 0.01;
        let axle = Vector3::new(-psi.sin(), psi.cos(), 0.0);
        let v = Vector3::new(20.0, 0.0, 0.0);
        let r = track_relative(c, s, &p, &axle, &v).unwrap();
        assert!((r.lateral_m - 0.003).abs() < 1e-12);
        assert!((r.vertical_m - 0.43).abs() < 1e-12);
        assert!((r.yaw_rad - psi).abs() < 1e-12);
        assert!(r.roll_rad.abs() < 1e-12);
        assert!((r.forward_speed_m_s - 20.0).abs() < 1e-12);
        assert!(project_s(c, &(p + Vector3::new(500.0, 0.0, 0.0)), 40.0).is_err());
    }

    #[test]
    fn reference_on_a_straight_moves_with_the_track() {
        let track = straight_track(100.0, 0.1, 1.435, 1.5, 0.0);
        let a = reference_anchor(
            &track.centerline,
            50.0,
            &Vector3::new(1.0, 0.0, 1.5),
            30.0,
            0.05,
        )
        .unwrap();
        let c = track.centerline.at(51.0).unwrap();
        assert!((a.position_m - (c.position + Vector3::new(0.0, 0.0, 1.5))).norm() < 1e-9);
        assert!((a.velocity_m_s - Vector3::new(30.0, 0.0, 0.0)).norm() < 1e-9);
        assert!(a.angular_velocity_rad_s.norm() < 1e-12);
    }
}
