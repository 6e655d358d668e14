//! Contact from the contact lookup table (paper §2, docs/reference/01-units-frames.md §0): instead of
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
//!
//! On an irregular track each wheel's row is read at the wheelset's shift
//! from that wheel's own rail ([`rail_offset_m`]: the rail's lateral
//! irregularity, so alignment and gauge both enter), not from the
//! centreline; the cross level enters through the evaluation at the actual
//! pose. Reading the two wheels at different shifts is first-order (the
//! table's rows hold the roll settled for equal shifts); the online contact
//! is the reference.

use std::sync::Arc;

use super::contact_source::{ContactContext, ContactSource};
use super::track_motion::TrackRelative;
use crate::contact::table::{ContactTable, ContactTableError};
use crate::contact::{
    ContactError, SurfaceParams, WheelsetContactModel, WheelsetContacts, WheelsetPose,
};
use crate::geometry::profile::Zone;
use crate::geometry::track::{Side, TrackError, TrackTables};

/// Tolerance when matching a table point to a piece of the wheel (m).
const PIECE_TOL_M: f64 = 1e-4;

/// The [`ContactSource`] of a wheelset with a contact lookup table
/// (module docs): settled on its profiles as online, contact points from
/// the table, forces as online (Hertz with hysteresis, the run's creep
/// law).
#[derive(Debug, Clone)]
pub struct TableContact {
    table: Arc<ContactTable>,
}

impl TableContact {
    pub fn new(table: Arc<ContactTable>) -> Self {
        TableContact { table }
    }
}

impl ContactSource for TableContact {
    fn contacts(
        &mut self,
        ctx: ContactContext<'_>,
        pose: &WheelsetPose,
        relative: &TrackRelative,
    ) -> Result<WheelsetContacts, ContactError> {
        table_contacts(
            &ctx.wheelset.contact,
            ctx.track,
            pose,
            relative,
            &self.table,
        )
    }
}

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
        let lateral_m = relative.lateral_m - rail_offset_m(track, side, pose.s_track_m)?;
        let sigma = match side {
            Side::Left => -1.0,
            Side::Right => 1.0,
        };
        let wheel = model.wheel(side);
        let rail = model.rail(side);
        let l_rail = track.centerline.rail_l(side, pose.s_track_m)?;
        for (z, zone) in [Zone::Tread, Zone::Flange].into_iter().enumerate() {
            let entry = table
                .zone_at(lateral_m, k, z)
                .map_err(|e| table_error(e, lateral_m))?;
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

/// Lateral offset (m, + left) of the `side` rail's profile origin from its
/// nominal place at ± half the rail spacing from the centreline, along the
/// track's lateral vector at track distance `s_m`: that rail's lateral
/// irregularity (alignment ± half the gauge deviation; zero on a track
/// without irregularities).
pub fn rail_offset_m(track: &TrackTables, side: Side, s_m: f64) -> Result<f64, TrackError> {
    let c = track.centerline.at(s_m)?;
    let l = track.centerline.rail_l(side, s_m)?;
    let p = track.rail(side).at(l)?.position;
    let nominal_m = match side {
        Side::Left => 0.5 * track.meta.rail_spacing_m,
        Side::Right => -0.5 * track.meta.rail_spacing_m,
    };
    Ok((p - c.position).dot(&c.frame.n) - nominal_m)
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
