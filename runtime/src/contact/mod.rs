//! Online contact detection (paper §4.2–4.3, docs/reference/06-contact-detection.md §6): for each wheel and
//! rail, the four surface parameters (s_r, u_r, s_w, u_w) solving the
//! contact equations by Newton's method with an analytic Jacobian, for the
//! tread and flange functions of the wheel separately — so the flange point
//! may lie ahead of or behind the axle (lead/lag contact, s_w ≠ 0).
//!
//! Layers: `pose` (where the wheelset is) → `geometry` (the equations;
//! `small_angle`: the wheel angle's sine and cosine) → `newton` → `search` (cold start) and `predictor` (warm start: the
//! last solve linearised and moved to the new pose; [`FollowedPatch`]
//! follows one patch with it) → [`WheelsetContactModel`] (profiles
//! of one wheelset, pair solves) → [`ContactSolver`] (a step: both wheels,
//! zones, warm start, flange rule) → [`quasi_static`] (wheelset settled
//! under load, flangeway clearance); [`nadal`]: the flange-climbing limit.
//!
//! "No contact" and "solve failed" are distinct: a pair solve returns
//! `Ok(None)` or a [`Candidate`] with negative penetration when the bodies do
//! not touch, and [`ContactError::NotConverged`] (with the state) when no
//! start converges.
//!
//! # Example: the contact of a centred S1002 wheelset on UIC60 rails
//!
//! ```
//! # #[cfg(feature = "io")] {
//! use runtime::contact::{ContactOptions, ContactSolver, WheelsetContactModel, WheelsetPose};
//! use runtime::geometry::profile::{RailPlacement, RailProfileOptions, Zone};
//! use runtime::io::profile_import::{ImportOptions, load_rail, load_wheel};
//! use runtime::geometry::track::{Side, straight_track};
//!
//! let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tables/profiles");
//! let opts = ImportOptions::default();
//! let wheel = load_wheel(&dir.join("MBench_S1002_v3.prw"), &opts, Default::default())?.profile;
//! let rail = load_rail(&dir.join("MBench_UIC60_v3.prr"), &opts, RailProfileOptions::default())?.profile;
//! // Gauge 1435 mm, flange backs 1360 mm apart, rail origins 1507 mm apart
//! // (the rail file is already canted 1:40).
//! let placement = RailPlacement { gauge_m: 1.435, rail_spacing_m: 1.507, inclination_rad: 0.0 };
//! let model = WheelsetContactModel::new(wheel.clone(), wheel, 1.360, &rail, &rail, placement)?;
//! let track = straight_track(20.0, 0.1, 1.435, 1.507, 0.0);
//! // Centred, unyawed, the axle 0.4597 m above the track plane: the treads
//! // penetrate by a fraction of a millimetre.
//! let pose = WheelsetPose::on_track(&track, 10.0, 0.0, 0.4597, 0.0, 0.0)?;
//! let mut solver = ContactSolver::new(ContactOptions::default());
//! let contacts = solver.solve(&model, &track, &pose)?;
//! let tread = contacts.get(Side::Left, Zone::Tread).expect("the left tread touches");
//! assert!(tread.penetration_m > 0.0 && tread.penetration_m < 1e-3, "{tread:?}");
//! // Near the nominal radius of 0.46 m, the contact angle small.
//! assert!((tread.rolling_radius_m - 0.46).abs() < 5e-3);
//! assert!(tread.contact_angle_rad.abs() < 0.1);
//! # }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod candidate;
mod follow;
mod geometry;
pub mod imported;
pub mod imported_lookup;
mod lu4;
mod model;
pub mod nadal;
mod newton;
pub mod patch_centre;
mod pose;
mod predictor;
pub mod quasi_static;
mod search;
mod small_angle;
mod solver;
pub mod table;

pub use candidate::{Candidate, Curvatures, FLAT_RELATIVE_CURVATURE_1_M, SolveMethod};
pub use follow::FollowedPatch;
pub use geometry::SurfaceParams;
pub use model::{DUPLICATE_M, WheelsetContactModel};
pub use patch_centre::{PatchCentre, patch_centre};
pub use pose::WheelsetPose;
pub use solver::{
    ContactOptions, ContactSolver, FlangeSearch, SECOND_PATCH_GAP_M, SolverStats, WheelsetContacts,
};

use crate::geometry::profile::Zone;
use crate::geometry::track::{Side, TrackError};

/// Why a contact could not be determined.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ContactError {
    #[error(
        "{side} wheel, {zone}: the contact equations did not converge after {iterations} Newton iterations (residual {residual:.3e}) at s_r = {:.4} m, u_r = {:.2} mm, s_w = {:.4} rad, u_w = {:.2} mm; wheelset at s = {s_track_m:.3} m, position [{:.4}, {:.4}, {:.4}] m",
        params.s_rail_m,
        params.u_rail_m * 1e3,
        params.s_wheel_rad,
        params.u_wheel_m * 1e3,
        position_m[0],
        position_m[1],
        position_m[2],
        zone = zone.name()
    )]
    NotConverged {
        side: Side,
        zone: Zone,
        iterations: u32,
        residual: f64,
        params: SurfaceParams,
        s_track_m: f64,
        position_m: [f64; 3],
    },
    #[error(
        "the {side} wheel touches its rail in more than {capacity} patches (separate minima of the gap in contact): more than the solver's slots; the profiles are too wavy to be modelled (check the profile files)"
    )]
    TooManyPatches { side: Side, capacity: usize },
    #[error(transparent)]
    Track(#[from] TrackError),
    #[error("{0}")]
    Setup(String),
}
