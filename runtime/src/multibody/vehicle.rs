//! The vehicle as the simulator sees it (docs/reference/08-multibody.md §8): wheelsets with their
//! contact models, free rigid bodies, track-following references and
//! linear spring–dampers, all positioned at the **assembly
//! configuration** in the vehicle's reference frame (origin on the track
//! centreline in the plane of the rail tops, x forward, y left, z up; the
//! frame follows the track, so x is a distance along the centreline).
//! Plain data: the `sim` binary builds it from a vehicle file.

use nalgebra::Vector3;

use crate::contact::WheelsetContactModel;
use crate::multibody::body::{BodyState, RigidBody};
use crate::multibody::element::AxisLaws;

/// What an element end is attached to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    /// The fixed ground (global frame).
    Ground,
    /// Wheelset `i` (its non-spinning axle frame).
    Wheelset(usize),
    /// Free body `i`.
    Body(usize),
    /// Track-following reference `i`.
    Reference(usize),
}

/// A wheelset: a rigid body spinning freely about its axle, with its wheel
/// and rail profiles.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetSpec {
    pub name: String,
    /// Mass and inertia about the CG in axle axes (x roll, y spin along the
    /// axle, z yaw).
    pub body: RigidBody,
    pub contact: WheelsetContactModel,
    /// Axle position ahead of the vehicle reference point (m).
    pub x_m: f64,
    /// Lateral position at assembly (m).
    pub y_m: f64,
    /// Rolling radius at the taping line (m): sets the initial spin V/r₀.
    pub nominal_radius_m: f64,
    /// Static vertical load per wheel at assembly (N): the wheelset is
    /// settled on the rails under it before the run.
    pub static_wheel_load_n: f64,
}

/// A free rigid body (6 DOF).
#[derive(Debug, Clone, PartialEq)]
pub struct BodySpec {
    pub name: String,
    pub body: RigidBody,
    /// Centre of gravity at assembly, vehicle frame (m).
    pub cg_m: Vector3<f64>,
}

/// A body whose motion is prescribed: it follows the track at the run's
/// speed, its axes the track frame (the car body above a single bogie).
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceSpec {
    pub name: String,
    /// Origin of its axes, vehicle frame (m).
    pub origin_m: Vector3<f64>,
}

/// A spring–damper between two ends, linear with optional nonlinear
/// additions per axis (see [`crate::multibody::element`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ElementSpec {
    pub name: String,
    /// End whose axes give the element's directions.
    pub a: End,
    pub b: End,
    /// Attachment points at assembly, vehicle frame (m).
    pub point_a_m: Vector3<f64>,
    pub point_b_m: Vector3<f64>,
    /// Along a's x, y, z (N/m).
    pub stiffness_n_m: [f64; 3],
    /// Along a's x, y, z (N·s/m).
    pub damping_n_s_m: [f64; 3],
    /// Force on b at assembly, in a's axes (N).
    pub preload_n: Vector3<f64>,
    /// Nonlinear additions along a's x, y, z
    /// ([`crate::multibody::element::law`]); default: none.
    pub laws: [AxisLaws; 3],
}

impl ElementSpec {
    /// Number of internal states (one per series spring–damper axis).
    pub fn internal_len(&self) -> usize {
        self.laws.iter().filter(|l| l.series.is_some()).count()
    }
}

/// A whole vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct VehicleModel {
    pub name: String,
    pub wheelsets: Vec<WheelsetSpec>,
    pub bodies: Vec<BodySpec>,
    pub references: Vec<ReferenceSpec>,
    pub elements: Vec<ElementSpec>,
}

impl VehicleModel {
    /// Total mass of the free bodies and wheelsets (kg).
    pub fn moving_mass_kg(&self) -> f64 {
        self.wheelsets.iter().map(|w| w.body.mass_kg).sum::<f64>()
            + self.bodies.iter().map(|b| b.body.mass_kg).sum::<f64>()
    }

    /// Number of state variables of the bodies ([`BodyState::LEN`] per
    /// wheelset and free body), wheelsets first.
    pub fn body_state_len(&self) -> usize {
        BodyState::LEN * (self.wheelsets.len() + self.bodies.len())
    }

    /// Number of the elements' internal states (series spring–dampers),
    /// stored after the bodies' states in element order.
    pub fn internal_state_len(&self) -> usize {
        self.elements.iter().map(ElementSpec::internal_len).sum()
    }

    /// Number of state variables: the bodies' ([`Self::body_state_len`])
    /// then the elements' internal states ([`Self::internal_state_len`]),
    /// so body state indices do not depend on the elements.
    pub fn state_len(&self) -> usize {
        self.body_state_len() + self.internal_state_len()
    }
}
