//! Dynamic simulation of wheelsets and bogies on tabulated track (paper
//! §4.1, Fig. 8, and §5; SPEC §8).
//!
//! - [`vehicle`]: the vehicle as plain data (wheelsets, free bodies,
//!   track-following references, spring–dampers) at its assembly
//!   configuration;
//! - [`track_motion`]: positions relative to the track, reference motion;
//! - [`system`]: the vehicle on the track as a first-order system for
//!   [`crate::integrator`] (the paper's per-step algorithm);
//! - [`table_contact`]: contact from the lookup table instead of Newton;
//! - [`imported_contact`]: contact from a table computed by another code;
//! - [`recorder`]: sampled outputs into [`crate::results::RunResults`];
//! - [`linear`]: linearisation around the centred run, modes, hunting.
//!
//! State: 13 variables per wheelset and free body (position, unit
//! quaternion, velocity, body angular velocity; [`crate::body::BodyState`]),
//! wheelsets first. Wheelsets are ordinary rigid bodies whose spin about
//! the axle is part of their angular velocity; their contact geometry and
//! the elements attached to them use the non-spinning axle frame.

pub mod imported_contact;
pub mod linear;
pub mod recorder;
pub mod system;
pub mod table_contact;
pub mod track_motion;
pub mod vehicle;

pub use recorder::Recorder;
pub use system::{
    ContactMethod, DynamicsError, GRAVITY_M_S2, InitialConditions, RunCounters, SystemSettings,
    VehicleSystem, WheelsetSnapshot,
};
pub use track_motion::TrackRelative;
pub use vehicle::{BodySpec, ElementSpec, End, ReferenceSpec, VehicleModel, WheelsetSpec};
