//! Contact from the contact lookup table (paper §2, SPEC §0): instead of
//! solving the contact equations, the contact points of each wheel and zone
//! are interpolated linearly from the wheelset's table at its lateral
//! displacement relative to the track, and evaluated for the actual pose —
//! penetration along the rail normal, contact frame and curvatures at those
//! points ([`WheelsetContactModel::candidate_at`]). Cheaper than Newton, and
//! exact where the wheelset's roll, height and yaw match the table's
//! settled state; elsewhere the points are first-order approximations (the
//! contact point is stationary, so the penetration error is second order).
//! Only the table's zero-yaw rows are used: the lead of a yawed wheelset's
//! flange contact is that of the unyawed one (document the limit when using
//! the table with large yaw).

use super::track_motion::TrackRelative;
use crate::contact::{
    ContactError, SurfaceParams, WheelsetContactModel, WheelsetContacts, WheelsetPose,
};
use crate::contact_table::{ContactTable, ContactTableError};
use crate::profile::Zone;
use crate::track::{Side, TrackError, TrackTables};

/// Tolerance when matching a table point to a piece of the wheel (m).
const PIECE_TOL_M: f64 = 1e-4;

/// The wheelset's candidates from `table` at its track-relative position.
pub fn table_contacts(
    model: &WheelsetContactModel,
    track: &TrackTables,
    pose: &WheelsetPose,
    relative: &TrackRelative,
    table: &ContactTable,
) -> Result<WheelsetContacts, ContactError> {
    let mut out = WheelsetContacts::default();
    for (k, side) in Side::BOTH.into_iter().enumerate() {
        let sigma = match side {
            Side::Left => -1.0,
            Side::Right => 1.0,
        };
        let wheel = model.wheel(side);
        let rail = model.rail(side);
        let l_rail = track.centerline.rail_l(side, pose.s_track_m)?;
        for (z, zone) in [Zone::Tread, Zone::Flange].into_iter().enumerate() {
            let entry = table
                .zone_at(relative.lateral_m, k, z)
                .map_err(|e| table_error(e, relative.lateral_m))?;
            let Some(e) = entry else { continue };
            let (u_wheel, _) = wheel.from_file_m(e.y_wheel_m, e.z_wheel_m);
            let (u_rail, _) = rail.from_file_m(e.y_rail_m, e.z_rail_m);
            let Some(segment) = wheel
                .segments()
                .iter()
                .position(|s| s.zone == zone && s.curve.contains(u_wheel, PIECE_TOL_M))
            else {
                continue;
            };
            let params = SurfaceParams {
                s_rail_m: l_rail + e.lead_m,
                u_rail_m: sigma * u_rail,
                s_wheel_rad: e.s_wheel_rad,
                u_wheel_m: sigma * u_wheel,
            };
            out.candidates[k][segment] = model.candidate_at(track, pose, side, segment, params)?;
        }
    }
    Ok(out)
}

/// A table look-up outside the table's lateral range is reported as a
/// track-range error on the wheelset's lateral coordinate.
fn table_error(e: ContactTableError, lateral_m: f64) -> ContactError {
    match e {
        ContactTableError::OutOfRange { min_m, max_m, .. } => {
            ContactError::Track(TrackError::OutOfRange {
                table: "contact_table",
                coordinate: "lateral shift",
                value_m: lateral_m,
                min_m,
                max_m,
            })
        }
        ContactTableError::Malformed(_) => ContactError::Track(TrackError::OutOfRange {
            table: "contact_table (malformed)",
            coordinate: "lateral shift",
            value_m: lateral_m,
            min_m: f64::NAN,
            max_m: f64::NAN,
        }),
    }
}
