//! Where a body is relative to the track, and the motion of track-following
//! references (docs/reference/01-units-frames.md §1 frames: `t` forward, `n` left, `b = t × n` up).

use nalgebra::{Matrix3, Vector3};

use crate::geometry::track::{CenterlinePoint, CenterlineTable, Frame, TrackError};
use crate::multibody::element::Anchor;

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
        let step = (position - c.position).dot(&c.frame.t.normalize());
        if step == 0.0 {
            // A fixed point: the remaining iterations would repeat this one.
            break;
        }
        s += step;
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
    Ok(relative_to(&centerline.at(s_m)?, position, axle, velocity))
}

/// [`track_relative`] at a centreline point already looked up (the same
/// values: one lookup serves the rotation and the relative position of a
/// wheelset, [`crate::multibody::VehicleSystem::evaluate`]).
pub(crate) fn relative_to(
    c: &CenterlinePoint,
    position: &Vector3<f64>,
    axle: &Vector3<f64>,
    velocity: &Vector3<f64>,
) -> TrackRelative {
    let s_m = c.s_m;
    let (t, n, b) = (
        c.frame.t.normalize(),
        c.frame.n.normalize(),
        c.frame.b.normalize(),
    );
    let d = position - c.position;
    TrackRelative {
        s_m,
        lateral_m: d.dot(&n),
        vertical_m: d.dot(&b),
        yaw_rad: (-axle.dot(&t)).atan2(axle.dot(&n)),
        roll_rad: axle.dot(&b).clamp(-1.0, 1.0).asin(),
        forward_speed_m_s: velocity.dot(&t),
    }
}

/// Rotation (columns t, n, b, orthonormalised) of the track frame at `s_m`.
pub fn track_rotation(centerline: &CenterlineTable, s_m: f64) -> Result<Matrix3<f64>, TrackError> {
    Ok(frame_rotation(&centerline.at(s_m)?.frame))
}

/// [`track_rotation`] of a centreline frame already looked up.
pub(crate) fn frame_rotation(f: &Frame) -> Matrix3<f64> {
    let t = f.t.normalize();
    let n = (f.n - t * t.dot(&f.n)).normalize();
    Matrix3::from_columns(&[t, n, t.cross(&n)])
}

/// Global position of a point given in the vehicle frame (x along the
/// track from the vehicle reference at `s_vehicle_m`, y left, z up).
pub fn vehicle_point(
    centerline: &CenterlineTable,
    s_vehicle_m: f64,
    point: &Vector3<f64>,
) -> Result<Vector3<f64>, TrackError> {
    Ok(point_at(&centerline.at(s_vehicle_m + point.x)?, point))
}

/// [`vehicle_point`] from the centreline point at its station, already
/// looked up (position and rotation from one lookup).
fn point_at(c: &CenterlinePoint, point: &Vector3<f64>) -> Vector3<f64> {
    let r = frame_rotation(&c.frame);
    c.position + r.column(1) * point.y + r.column(2) * point.z
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
    // One centreline lookup per distinct station (the position and the
    // rotation at a station share it; a station whose rounded abscissa
    // equals the rotation's reuses that lookup too): the same values as
    // separate lookups, at a third of the cost.
    let s = s_vehicle_m + origin.x;
    let centre = centerline.at(s)?;
    let position = point_at(&centre, origin);
    let rotation = frame_rotation(&centre.frame);
    let (lo, hi) = centerline.range_m();
    let (s0, s1) = ((s - ds_m).max(lo), (s + ds_m).min(hi));
    let (velocity, angular_velocity) = if s1 > s0 {
        let (a0, a1) = (
            s_vehicle_m - (s - s0) + origin.x,
            s_vehicle_m + (s1 - s) + origin.x,
        );
        let (c0, c1) = (centerline.at(a0)?, centerline.at(a1)?);
        let (p0, p1) = (point_at(&c0, origin), point_at(&c1, origin));
        let at_or_reuse = |station: f64, a: f64, c: &CenterlinePoint| {
            if station.to_bits() == a.to_bits() {
                Ok(frame_rotation(&c.frame))
            } else {
                track_rotation(centerline, station)
            }
        };
        let r0 = at_or_reuse(s0, a0, &c0)?;
        let r1 = at_or_reuse(s1, a1, &c1)?;
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

/// Prescribed speed of the track-following references against time (the
/// vehicle reference point's motion along the centreline): a constant
/// acceleration a from V0 until the speed reaches V_f, then V_f held,
///
/// V(t) = V0 + a·min(t, t_f),  t_f = (V_f − V0)/a  (a ≠ 0),
/// s(t) − s0 = ∫₀ᵗ V dτ = V0·t_r + a·t_r²/2 + V_f·(t − t_r),  t_r = min(t, t_f)
///
/// (uniformly accelerated motion; V in m/s along the track tangent `t`,
/// positive forwards, t in s). Braking (a < 0) ends at V_f = 0 unless a
/// final speed is given: the references stop and stay stopped; a negative
/// V_f asks for a reversal (running backwards; see
/// [`crate::forces::creepage`] on what that means for the creepages).
/// Accelerating (a > 0) goes on without bound unless V_f is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedRamp {
    /// V0 (m/s), at t = 0.
    pub initial_m_s: f64,
    /// a (m/s²): > 0 accelerates, < 0 brakes, 0 keeps V0.
    pub rate_m_s2: f64,
    /// V_f (m/s), where the ramp ends; `None`: 0 when braking, none when
    /// accelerating.
    pub final_m_s: Option<f64>,
}

impl SpeedRamp {
    /// A constant speed V0 (m/s).
    pub fn constant(speed_m_s: f64) -> Self {
        SpeedRamp {
            initial_m_s: speed_m_s,
            rate_m_s2: 0.0,
            final_m_s: None,
        }
    }

    /// The speed where the ramp ends (m/s): V_f, 0 when braking without
    /// one, `None` for an unbounded acceleration or a constant speed.
    pub fn end_speed_m_s(&self) -> Option<f64> {
        if self.rate_m_s2 < 0.0 {
            Some(self.final_m_s.unwrap_or(0.0))
        } else if self.rate_m_s2 > 0.0 {
            self.final_m_s
        } else {
            None
        }
    }

    /// t_f (s), when the ramp reaches its end speed; `None` if it never
    /// ends (constant speed, unbounded acceleration). A ramp whose end
    /// speed lies behind V0 (a check of the caller) ends at 0.
    pub fn end_time_s(&self) -> Option<f64> {
        self.end_speed_m_s()
            .map(|vf| ((vf - self.initial_m_s) / self.rate_m_s2).max(0.0))
    }

    /// V(t) (m/s), struct docs.
    pub fn speed_m_s(&self, t_s: f64) -> f64 {
        let t_r = self.end_time_s().map_or(t_s, |tf| t_s.min(tf));
        self.initial_m_s + self.rate_m_s2 * t_r
    }

    /// s(t) − s0 (m), the distance covered since t = 0, struct docs.
    pub fn distance_m(&self, t_s: f64) -> f64 {
        let t_r = self.end_time_s().map_or(t_s, |tf| t_s.min(tf));
        let ramp = self.initial_m_s * t_r + 0.5 * self.rate_m_s2 * t_r * t_r;
        ramp + self.speed_m_s(t_r) * (t_s - t_r)
    }

    /// The first time (s) at which the distance covered reaches `d_m` (> 0),
    /// or `None` if it never does (the references stop, or reverse, first).
    pub fn time_to_cover_s(&self, d_m: f64) -> Option<f64> {
        let (v0, a) = (self.initial_m_s, self.rate_m_s2);
        // On the ramp: v0 t + a t²/2 = d, the smallest root t ≥ 0, written
        // as 2d / (v0 + √(v0² + 2 a d)) (no cancellation as a → 0).
        let disc = v0 * v0 + 2.0 * a * d_m;
        let on_ramp = if disc >= 0.0 && v0 + disc.sqrt() > 0.0 {
            Some(2.0 * d_m / (v0 + disc.sqrt()))
        } else {
            None
        };
        match self.end_time_s() {
            None => on_ramp,
            Some(tf) => match on_ramp {
                Some(t) if t <= tf => Some(t),
                _ => {
                    // After the ramp, at the held speed V_f.
                    let (s_f, v_f) = (self.distance_m(tf), self.speed_m_s(tf));
                    (v_f > 0.0).then(|| tf + (d_m - s_f) / v_f)
                }
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::track::straight_track;

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
    fn speed_ramps_start_stop_hold_and_reverse() {
        // Constant speed.
        let c = SpeedRamp::constant(12.0);
        assert_eq!((c.speed_m_s(3.0), c.distance_m(3.0)), (12.0, 36.0));
        assert_eq!(c.end_time_s(), None);
        assert_eq!(c.time_to_cover_s(60.0), Some(5.0));
        // From rest, unbounded: s = a t²/2.
        let up = SpeedRamp {
            initial_m_s: 0.0,
            rate_m_s2: 2.0,
            final_m_s: None,
        };
        assert_eq!(up.speed_m_s(1.5), 3.0);
        assert!((up.distance_m(3.0) - 9.0).abs() < 1e-12);
        assert!((up.time_to_cover_s(9.0).unwrap() - 3.0).abs() < 1e-12);
        // From rest to 4 m/s (reached at 2 s after 4 m), then held.
        let held = SpeedRamp {
            final_m_s: Some(4.0),
            ..up
        };
        assert_eq!(held.end_time_s(), Some(2.0));
        assert_eq!(held.speed_m_s(10.0), 4.0);
        assert!((held.distance_m(3.0) - 8.0).abs() < 1e-12);
        assert!((held.time_to_cover_s(8.0).unwrap() - 3.0).abs() < 1e-12);
        // Braking from 10 m/s at 2 m/s²: stops at 5 s after 25 m, stays.
        let brake = SpeedRamp {
            initial_m_s: 10.0,
            rate_m_s2: -2.0,
            final_m_s: None,
        };
        assert_eq!(brake.end_time_s(), Some(5.0));
        assert_eq!(brake.speed_m_s(7.0), 0.0);
        assert!((brake.distance_m(7.0) - 25.0).abs() < 1e-12);
        assert!((brake.time_to_cover_s(16.0).unwrap() - 2.0).abs() < 1e-12);
        assert_eq!(brake.time_to_cover_s(26.0), None);
        // Reversal asked: through zero at 5 s, −4 m/s from 7 s on.
        let back = SpeedRamp {
            final_m_s: Some(-4.0),
            ..brake
        };
        assert_eq!(back.end_time_s(), Some(7.0));
        assert_eq!(back.speed_m_s(5.0), 0.0);
        assert_eq!(back.speed_m_s(9.0), -4.0);
        assert!((back.distance_m(7.0) - 21.0).abs() < 1e-12);
        assert!((back.distance_m(9.0) - 13.0).abs() < 1e-12);
        assert_eq!(back.time_to_cover_s(26.0), None);
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
