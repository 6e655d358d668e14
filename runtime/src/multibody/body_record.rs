//! The track-relative state of every rigid body at an output sample, for
//! the `bodies/` series of the results (frames, angle sequence, signs and
//! the car-body rule in [`crate::results::bodies`]). Read through the
//! body API of the system after its evaluation at the sample
//! ([`VehicleSystem::states`], [`VehicleSystem::wrenches`],
//! [`VehicleSystem::snapshots`]), never from raw state indices.

use nalgebra::{Matrix3, Rotation3, Vector3};

use super::DynamicsError;
use super::system::VehicleSystem;
use super::track_motion::{frame_rotation, project_s};
use crate::geometry::track::TrackError;
use crate::results::bodies::recognise_car_body;
use crate::results::{BodyKind, BodySample, BodySeries, CarBody};

/// Empty series for every body of the system's vehicle (wheelsets first,
/// then the free bodies) and the car body among them, if any.
pub(super) fn body_series(system: &VehicleSystem<'_>) -> (Vec<BodySeries>, Option<CarBody>) {
    let v = system.vehicle();
    let mut out = Vec::with_capacity(v.wheelsets.len() + v.bodies.len());
    for w in &v.wheelsets {
        let mut b = BodySeries::new(w.name.clone(), BodyKind::Wheelset, w.body.mass_kg);
        b.assembly_x_m = w.x_m;
        out.push(b);
    }
    for fb in &v.bodies {
        let mut b = BodySeries::new(fb.name.clone(), BodyKind::Free, fb.body.mass_kg);
        b.assembly_x_m = fb.cg_m.x;
        b.assembly_height_m = fb.cg_m.z;
        out.push(b);
    }
    let car = recognise_car_body(v.bodies.iter().map(|b| (b.name.as_str(), b.body.mass_kg)));
    (out, car)
}

/// Yaw ψ, roll φ, pitch θ (rad) of a relative rotation written
/// R_z(ψ) R_x(φ) R_y(θ) (docs of [`crate::results::bodies`]): its second
/// column is (−sin ψ cos φ, cos ψ cos φ, sin φ), its last row
/// (−cos φ sin θ, sin φ, cos φ cos θ).
pub fn yaw_roll_pitch(m: &Matrix3<f64>) -> (f64, f64, f64) {
    let roll = m[(2, 1)].clamp(-1.0, 1.0).asin();
    let yaw = (-m[(0, 1)]).atan2(m[(1, 1)]);
    let pitch = (-m[(2, 0)]).atan2(m[(2, 2)]);
    (yaw, roll, pitch)
}

/// R_z(ψ) R_x(φ): the axes of a body yawed and rolled, not pitched (a
/// wheelset's non-spinning axle frame), relative to the track axes.
fn yawed_and_rolled(yaw: f64, roll: f64) -> Matrix3<f64> {
    (Rotation3::from_axis_angle(&Vector3::z_axis(), yaw)
        * Rotation3::from_axis_angle(&Vector3::x_axis(), roll))
    .into_inner()
}

/// One sample of every body at the system's last evaluation, at time `t_s`.
/// `s_guess` holds each body's track position at the previous sample (NaN
/// before the first), updated here.
pub(super) fn body_samples(
    system: &VehicleSystem<'_>,
    t_s: f64,
    s_guess: &mut [f64],
) -> Result<Vec<BodySample>, DynamicsError> {
    let v = system.vehicle();
    let c = &system.track().centerline;
    let s_ref = system.s_vehicle_m(t_s);
    let g = system.settings().gravity_m_s2;
    let n_ws = v.wheelsets.len();
    let track_err = |name: &str| {
        let what = format!("recording body '{name}'");
        move |source: TrackError| DynamicsError::Track { what, t_s, source }
    };
    let bodies = v
        .wheelsets
        .iter()
        .map(|w| (w.name.as_str(), w.x_m, w.body.mass_kg))
        .chain(
            v.bodies
                .iter()
                .map(|b| (b.name.as_str(), b.cg_m.x, b.body.mass_kg)),
        );
    let mut out = Vec::with_capacity(s_guess.len());
    for (k, (name, x0, mass_kg)) in bodies.enumerate() {
        let (Some(st), Some(wrench)) = (system.states().get(k), system.wrenches().get(k)) else {
            break;
        };
        let s = match system.snapshots().get(k) {
            // A wheelset: its section as the evaluation found it.
            Some(snap) if k < n_ws => snap.relative.s_m,
            _ => {
                let guess = if s_guess[k].is_finite() {
                    s_guess[k]
                } else {
                    s_ref + x0
                };
                project_s(c, &st.position_m, guess).map_err(track_err(name))?
            }
        };
        s_guess[k] = s;
        // One lookup for the origin and the axes (`track_rotation`'s value).
        let centre = c.at(s).map_err(track_err(name))?;
        let origin = centre.position;
        let t = frame_rotation(&centre.frame);
        let (tt, nn, bb) = (t.column(0), t.column(1), t.column(2));
        let d = st.position_m - origin;
        let rel = t.transpose() * st.rotation();
        let (yaw, roll, pitch) = yaw_roll_pitch(&rel);
        let v_cg = st.velocity_m_s;
        let w = st.angular_velocity_global();
        // Specific force (a − g) = applied force / m, in the body's axes.
        let f = wrench.force_n / mass_kg;
        let axes = if k < n_ws {
            t * yawed_and_rolled(yaw, roll)
        } else {
            st.rotation()
        };
        out.push(BodySample {
            track_s_m: s,
            longitudinal_m: s - (s_ref + x0),
            lateral_m: d.dot(&nn),
            vertical_m: d.dot(&bb),
            roll_rad: roll,
            pitch_rad: pitch,
            yaw_rad: yaw,
            longitudinal_velocity_m_s: v_cg.dot(&tt),
            lateral_velocity_m_s: v_cg.dot(&nn),
            vertical_velocity_m_s: v_cg.dot(&bb),
            roll_rate_rad_s: w.dot(&tt),
            pitch_rate_rad_s: w.dot(&nn),
            yaw_rate_rad_s: w.dot(&bb),
            lateral_acceleration_m_s2: f.dot(&axes.column(1)),
            vertical_acceleration_m_s2: f.dot(&axes.column(2)) - g,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn angles_come_back_from_their_rotation() {
        for &(yaw, roll, pitch) in &[
            (0.01, -0.02, 0.03),
            (-0.3, 0.2, 2.9),
            (0.0, 0.0, -3.0),
            (1.0, -0.5, 1.55),
        ] {
            let m = yawed_and_rolled(yaw, roll)
                * Rotation3::from_axis_angle(&Vector3::y_axis(), pitch).into_inner();
            let (y, r, p) = yaw_roll_pitch(&m);
            assert!((y - yaw).abs() < 1e-12, "{y} {yaw}");
            assert!((r - roll).abs() < 1e-12, "{r} {roll}");
            assert!((p - pitch).abs() < 1e-12, "{p} {pitch}");
            // The axle (second column) as the wheelset columns define yaw
            // and roll: η·t = −sin ψ cos φ, η·b = sin φ.
            let axle = m.column(1);
            assert!((axle[2] - roll.sin()).abs() < 1e-12);
            assert!(((-axle[0]).atan2(axle[1]) - yaw).abs() < 1e-12);
        }
        // Signs: a yaw turns the nose (x) left (+y); a roll raises the
        // left side (+y up); a pitch turns the nose down.
        let nose = yawed_and_rolled(0.1, 0.0).column(0).into_owned();
        assert!(nose.y > 0.0);
        let left = yawed_and_rolled(0.0, 0.1).column(1).into_owned();
        assert!(left.z > 0.0);
        let pitched = Rotation3::from_axis_angle(&Vector3::y_axis(), 0.1).into_inner();
        assert!(pitched.column(0).z < 0.0);
    }
}
