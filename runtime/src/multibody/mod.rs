//! Multibody dynamics of wheelsets and bogies on tabulated track (paper
//! §4.1, Fig. 8, and §5; docs/reference/08-multibody.md §8).
//!
//! - [`body`]: rigid bodies, their state and Newton–Euler equations;
//! - [`element`]: spring–dampers between bodies (linear, nonlinear laws,
//!   series spring–dampers with internal states);
//! - [`preload`]: the static preload solve at assembly;
//! - [`contact_force`]: the per-contact pipeline from a contact point to
//!   the forces on the wheel (Hertz, normal force, creepages, creep law);
//! - [`vehicle`]: the vehicle as plain data (wheelsets, free bodies,
//!   track-following references, spring–dampers) at its assembly
//!   configuration;
//! - [`track_motion`]: positions relative to the track, reference motion;
//! - [`speed_profile`]: the references' speed against time (ramp or schedule);
//! - [`system`]: the vehicle on the track as a first-order system for
//!   [`crate::integrators`]; its settings (`settings`), errors (`error`),
//!   assembly (`assemble`), evaluation — the paper's per-step algorithm
//!   (`evaluate`) — and energy bookkeeping (`energy`);
//! - [`contact_source`]: where a wheelset's contacts come from, one
//!   [`ContactSource`] per wheelset (online, table, imported);
//! - [`table_contact`]: contact from the lookup table instead of Newton;
//! - [`imported_contact`]: contact from a table computed by another code;
//! - [`recorder`]: sampled outputs into [`crate::results::RunResults`]
//!   (the bodies' track-relative states from [`body_record`]);
//! - [`linear`]: linearisation around the centred run, modes, hunting.
//!
//! State: [`crate::multibody::body::BodyState::LEN`] (13) variables per wheelset and
//! free body (position, unit quaternion, velocity, body angular velocity;
//! [`crate::multibody::body::BodyState`]), wheelsets first, then the
//! elements' internal states (one per series spring–damper axis, element
//! order; [`VehicleModel::internal_state_len`]) — after the bodies, so body
//! state indices do not depend on the elements. Wheelsets are ordinary
//! rigid bodies whose spin about the axle is part of their angular
//! velocity; their contact geometry and the elements attached to them use
//! the non-spinning axle frame.

mod assemble;
pub mod axle_frame;
pub mod body;
pub mod body_record;
pub mod contact_force;
pub mod contact_source;
pub mod element;
mod energy;
mod error;
mod evaluate;
pub mod formulation;
pub mod imported_contact;
mod imposed_motion;
pub mod linear;
pub mod loaded_wheelset;
pub mod preload;
pub mod recorder;
mod settings;
pub mod speed_profile;
pub mod system;
pub mod table_contact;
pub mod track_motion;
pub mod vehicle;

pub use contact_source::{ContactContext, ContactSource, OnlineContact};
pub use energy::EnergyLedger;
pub use error::DynamicsError;
pub use imported_contact::ImportedContact;
pub use recorder::Recorder;
pub use settings::{
    BRAKE_STICK_SPEED_M_S, ContactMethod, FlangeClearances, GRAVITY_M_S2, InitialConditions,
    SystemSettings,
};
pub use system::{
    RunCounters, TRACK_END_MARGIN_M, TRACK_START_MARGIN_M, VehicleSystem, WheelsetSnapshot,
};
pub use table_contact::TableContact;
pub use track_motion::TrackRelative;
pub use vehicle::{BodySpec, ElementSpec, End, ReferenceSpec, VehicleModel, WheelsetSpec};
