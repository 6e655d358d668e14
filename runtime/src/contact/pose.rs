//! The pose of a wheelset as the contact search needs it: the position of
//! its centre and the orientation of its **axle frame** (ξ forward, η along
//! the axle to the left, ζ = ξ × η up), which does not spin with the wheels:
//! the wheel surfaces are surfaces of revolution, so the spin angle does not
//! change the geometry.

use nalgebra::{Matrix3, Rotation3, Unit, Vector3};

use crate::geometry::track::{TrackError, TrackTables};

/// Position and axle frame of a wheelset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelsetPose {
    /// Track distance of the wheelset centre along the centreline (m): a
    /// hint for locating the rails (the cold-start search starts there).
    pub s_track_m: f64,
    /// Global position of the wheelset centre (on the axle, midway between
    /// the wheels) (m).
    pub position: Vector3<f64>,
    /// Columns ξ, η, ζ of the axle frame in global coordinates.
    pub frame: Matrix3<f64>,
}

impl WheelsetPose {
    /// A pose given relative to the track at centreline distance `s_m`:
    /// centre at `y_m` along the track's lateral vector (positive left) and
    /// `z_m` along its normal (the height of the axle above the rail tops'
    /// plane, about the wheel radius); yaw `yaw_rad` about the track normal
    /// (positive turns the wheelset's nose to the left) then roll `roll_rad`
    /// about the wheelset's longitudinal axis (positive raises the left
    /// wheel, like cant).
    pub fn on_track(
        track: &TrackTables,
        s_m: f64,
        y_m: f64,
        z_m: f64,
        yaw_rad: f64,
        roll_rad: f64,
    ) -> Result<Self, TrackError> {
        let c = track.centerline.at(s_m)?;
        // Re-orthonormalise the interpolated frame.
        let t = c.frame.t.normalize();
        let n = (c.frame.n - t * t.dot(&c.frame.n)).normalize();
        let b = t.cross(&n);
        let base = Matrix3::from_columns(&[t, n, b]);
        let yaw = Rotation3::from_axis_angle(&Vector3::z_axis(), yaw_rad);
        let roll = Rotation3::from_axis_angle(&Vector3::x_axis(), roll_rad);
        Ok(Self {
            s_track_m: s_m,
            position: c.position + n * y_m + b * z_m,
            frame: base * yaw.matrix() * roll.matrix(),
        })
    }

    /// The axle direction η (unit, pointing left).
    pub fn axle(&self) -> Vector3<f64> {
        self.frame.column(1).into_owned()
    }

    /// A pose whose frame is the axle frame of a body orientation that may
    /// include the wheel spin: η is the body's lateral axis, ξ is made
    /// perpendicular to η and to the track normal `up`.
    pub fn from_body(
        s_track_m: f64,
        position: Vector3<f64>,
        axle: Vector3<f64>,
        up: Vector3<f64>,
    ) -> Self {
        let eta = Unit::new_normalize(axle).into_inner();
        let xi = eta.cross(&up).normalize();
        let zeta = xi.cross(&eta);
        Self {
            s_track_m,
            position,
            frame: Matrix3::from_columns(&[xi, eta, zeta]),
        }
    }
}
