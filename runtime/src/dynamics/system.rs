//! The vehicle on the track as a first-order system y′ = f(t, y) (paper
//! §4.1, Fig. 8; SPEC §8). One evaluation of f is the paper's step:
//!
//! a. the state of every body (wheelsets first, then free bodies;
//!    [`BodyState::LEN`] variables each, [`crate::body::BodyState`]);
//! b. contact search of every wheel, tread and flange, warm-started from the
//!    previous solve ([`ContactSolver`]), or the contact lookup table;
//! c. normal forces (Hertz with hysteresis, [`crate::normal`]);
//! d. creepages and creep forces ([`crate::contact_force`]);
//! e. suspension forces (elements between bodies, wheelsets and the
//!    track-following references) and gravity;
//! f. Newton–Euler accelerations ([`crate::body::derivatives`]).
//!
//! The surface parameters of the last solve are the next initial guess;
//! the hysteresis memory of each contact is committed only at accepted
//! states ([`OdeSystem::accept`]), so rejected trial steps leave no trace.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use super::imported_contact::{
    ImportedContactMethod, imported_contacts, imported_force, settle_imported,
};
use super::table_contact::table_contacts;
use super::track_motion::{
    SpeedRamp, TrackRelative, project_s, reference_anchor, track_relative, track_rotation,
    vehicle_point,
};
use super::vehicle::{End, VehicleModel};
use crate::body::{BodyError, BodyState, Wrench, derivatives};
use crate::contact::quasi_static::{Support, flange_clearance_m, settle};
use crate::contact::{
    ContactError, ContactOptions, ContactSolver, FlangeSearch, WheelsetContacts, WheelsetPose,
};
use crate::contact_force::{
    ContactForce, ContactForceError, ContactForceSettings, WheelsetMotion, evaluate_contact,
};
use crate::contact_table::ContactTable;
use crate::element::{Anchor, ElementError, SpringDamper};
use crate::integrator::{Control, OdeSystem};
use crate::normal::ContactMemory;
use crate::profile::{MAX_SEGMENTS, Zone};
use crate::track::{Side, TrackError, TrackTables};

/// Rim speed (m/s) below which the friction brake's torque
/// ([`SystemSettings::axle_brake_torque_nm`]) is proportional to the spin
/// (regularised Coulomb friction; exact Coulomb friction, a set-valued
/// torque at Ω = 0, has no ODE form). Below it the brake is a rotary
/// damper c = T_b r₀/v_ε; its time constant on a wheelset,
/// (I_spin + m r₀²) v_ε/(T_b r₀), is 0.8 ms for the ML95-like wheelset
/// braked at 1 kN·m — far slower than the creep forces at standstill
/// (`crate::creepage`, ~10 µs), so it does not limit the step, and a
/// wheelset stops within a few of them instead of creeping to rest.
pub const BRAKE_STICK_SPEED_M_S: f64 = 1e-3;

/// Standard gravity (m/s²), SPEC §1.
pub const GRAVITY_M_S2: f64 = 9.81;

/// Step of the central difference giving a reference's velocity and
/// angular velocity from the track frame (m).
const REFERENCE_DS_M: f64 = 0.05;

/// How the contact geometry is found at each evaluation.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactMethod {
    /// Newton on the surface parameters at every evaluation (paper §4.2–4.3).
    Online,
    /// Contact points interpolated from the wheelset's contact lookup
    /// table at its lateral displacement, the penetration and contact
    /// frame evaluated at those points for the actual pose (one table per
    /// wheelset, in vehicle order).
    Table(Vec<Arc<ContactTable>>),
    /// One contact per wheel from a contact table computed by another code
    /// (one table per wheelset, in vehicle order), with that code's normal
    /// force and creep model and an optional shear modulus of its own
    /// ([`super::imported_contact`]).
    Imported(ImportedContactMethod),
}

/// Settings of a run that the system needs.
#[derive(Debug, Clone, PartialEq)]
pub struct SystemSettings {
    pub forces: ContactForceSettings,
    /// Contact search options (flange search off | on | auto, iterations).
    pub contact: ContactOptions,
    pub method: ContactMethod,
    /// Set speed (m/s): initial forward speed of every body and the speed of
    /// the track-following references at t = 0.
    pub speed_m_s: f64,
    /// Constant deceleration of the references (m/s², ≥ 0; 0 = constant
    /// speed): V(t) = max(V0 − a t, V_f), V_f = `final_speed_m_s` or 0 (the
    /// references stop and stay stopped). Used to ramp the speed down
    /// through the nonlinear critical speed, and to brake to a stop;
    /// bodies not tied to a reference (an unsuspended wheelset) keep their
    /// own speed (brake them with `axle_brake_torque_nm`).
    pub deceleration_m_s2: f64,
    /// Constant acceleration of the references (m/s², ≥ 0; exclusive with
    /// `deceleration_m_s2`): V(t) = min(V0 + a t, V_f), from rest if V0 = 0
    /// ([`SpeedRamp`]).
    pub acceleration_m_s2: f64,
    /// Speed where the ramp ends and is held (m/s); `None`: 0 when braking,
    /// unbounded when accelerating. Below 0 when braking asks for a
    /// reversal (the references run backwards).
    pub final_speed_m_s: Option<f64>,
    /// Torque about every wheelset's axle (N·m), + driving forwards (the
    /// sense of the forward rolling spin, +axle = left): a traction motor
    /// (> 0) or a constant braking torque (< 0; it does not stop at
    /// standstill — it would drive the wheelset backwards). Its reaction,
    /// on a motor or brake in an unmodelled car body, is applied to no
    /// modelled body.
    pub axle_torque_nm: f64,
    /// Friction brake on every wheelset's axle (N·m, ≥ 0): a torque
    /// −T_b·Ω/max(|Ω|, Ω_ε) opposing the spin Ω (regularised Coulomb
    /// friction, Ω_ε = [`BRAKE_STICK_SPEED_M_S`]/r₀), so that it stops the
    /// wheelset and holds it instead of reversing it.
    pub axle_brake_torque_nm: f64,
    /// Track distance of the vehicle reference point at t = 0 (m).
    pub s_start_m: f64,
    /// A wheelset farther than this from the centreline is derailed (m).
    pub derailment_lateral_m: f64,
    /// Gravity (m/s², acting along −Z).
    pub gravity_m_s2: f64,
}

impl Default for SystemSettings {
    fn default() -> Self {
        SystemSettings {
            forces: ContactForceSettings::default(),
            contact: ContactOptions::default(),
            method: ContactMethod::Online,
            speed_m_s: 10.0,
            deceleration_m_s2: 0.0,
            acceleration_m_s2: 0.0,
            final_speed_m_s: None,
            axle_torque_nm: 0.0,
            axle_brake_torque_nm: 0.0,
            s_start_m: 5.0,
            derailment_lateral_m: 0.05,
            gravity_m_s2: GRAVITY_M_S2,
        }
    }
}

impl SystemSettings {
    /// The references' speed against time: V0 = `speed_m_s`, rate
    /// `acceleration_m_s2 − deceleration_m_s2`, end speed `final_speed_m_s`.
    pub fn speed_ramp(&self) -> SpeedRamp {
        SpeedRamp {
            initial_m_s: self.speed_m_s,
            rate_m_s2: self.acceleration_m_s2 - self.deceleration_m_s2,
            final_m_s: self.final_speed_m_s,
        }
    }

    /// Checks the speed, ramp and axle torques, naming the setting and the
    /// rule.
    pub fn validate_motion(&self) -> Result<(), DynamicsError> {
        let bad = |setting, value, rule| {
            Err(DynamicsError::Setting {
                setting,
                value,
                rule,
            })
        };
        let speed = self.speed_m_s;
        if !(speed.is_finite() && speed >= 0.0) {
            return bad("speed (m/s)", speed, "must be finite and >= 0");
        }
        for (setting, value) in [
            ("deceleration (m/s²)", self.deceleration_m_s2),
            ("acceleration (m/s²)", self.acceleration_m_s2),
            ("axle brake torque (N·m)", self.axle_brake_torque_nm),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return bad(setting, value, "must be finite and >= 0");
            }
        }
        if !self.axle_torque_nm.is_finite() {
            return bad("axle torque (N·m)", self.axle_torque_nm, "must be finite");
        }
        if self.acceleration_m_s2 > 0.0 && self.deceleration_m_s2 > 0.0 {
            return bad(
                "acceleration (m/s²)",
                self.acceleration_m_s2,
                "give an acceleration or a deceleration, not both",
            );
        }
        if let Some(vf) = self.final_speed_m_s {
            let rate = self.acceleration_m_s2 - self.deceleration_m_s2;
            if !vf.is_finite() {
                return bad("final speed (m/s)", vf, "must be finite");
            }
            if rate == 0.0 {
                return bad(
                    "final speed (m/s)",
                    vf,
                    "needs an acceleration or a deceleration",
                );
            }
            if rate > 0.0 && vf < speed {
                return bad(
                    "final speed (m/s)",
                    vf,
                    "must be >= the initial speed when accelerating",
                );
            }
            if rate < 0.0 && vf > speed {
                return bad(
                    "final speed (m/s)",
                    vf,
                    "must be <= the initial speed when braking",
                );
            }
        }
        Ok(())
    }
}

/// Initial conditions of the wheelsets (the paper's §5 cases start with a
/// lateral misalignment): every wheelset is shifted and yawed by these
/// amounts from its assembly position and settled on the rails; the other
/// bodies start at their assembly positions.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InitialConditions {
    /// Lateral shift of every wheelset (m), + left.
    pub lateral_m: f64,
    /// Yaw of every wheelset (rad), + nose left.
    pub yaw_rad: f64,
}

/// Why the simulation cannot go on.
#[derive(Debug, thiserror::Error)]
pub enum DynamicsError {
    #[error("wheelset '{wheelset}' at t = {t_s:.6} s: contact search failed: {source}")]
    Contact {
        wheelset: String,
        t_s: f64,
        #[source]
        source: ContactError,
    },
    #[error("wheelset '{wheelset}' at t = {t_s:.6} s: contact force: {source}")]
    Force {
        wheelset: String,
        t_s: f64,
        #[source]
        source: ContactForceError,
    },
    #[error("{what} at t = {t_s:.6} s is off the track tables: {source}")]
    Track {
        what: String,
        t_s: f64,
        #[source]
        source: TrackError,
    },
    #[error(
        "wheelset '{wheelset}' derailed at t = {t_s:.6} s: lateral displacement {lateral_mm:.1} mm exceeds {limit_mm:.1} mm"
    )]
    Derailed {
        wheelset: String,
        t_s: f64,
        lateral_mm: f64,
        limit_mm: f64,
    },
    #[error("body '{name}': {source}")]
    Body {
        name: String,
        #[source]
        source: BodyError,
    },
    #[error("element '{name}': {source}")]
    Element {
        name: String,
        #[source]
        source: ElementError,
    },
    #[error("setting {setting} = {value}: {rule}")]
    Setting {
        setting: &'static str,
        value: f64,
        rule: &'static str,
    },
    #[error("wheelset '{wheelset}': {reason}")]
    Assembly { wheelset: String, reason: String },
}

/// Everything computed for one wheelset at one evaluation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetSnapshot {
    pub relative: TrackRelative,
    pub contacts: WheelsetContacts,
    /// Forces of the candidates in contact, `[left, right][piece]`.
    pub forces: [[Option<ContactForce>; MAX_SEGMENTS]; 2],
    /// Spin about the axle (rad/s).
    pub spin_rad_s: f64,
    /// Torque applied about the axle (N·m), + driving forwards: the axle
    /// torque plus the friction brake's ([`SystemSettings`]).
    pub axle_torque_nm: f64,
}

impl WheelsetSnapshot {
    /// Whether any flange piece of `side` is in contact.
    pub fn flange_contact(&self, side: Side) -> bool {
        let i = side_index(side);
        self.contacts.candidates[i]
            .iter()
            .flatten()
            .any(|c| c.zone == Zone::Flange && c.in_contact())
    }
}

/// Energy bookkeeping of a run (J): the mechanical energy E
/// ([`VehicleSystem::mechanical_energy_j`]) at the first and the last
/// accepted state, and the work of every non-conservative force between
/// them, integrated over the accepted states by the trapezoidal rule
/// (second order in the step). Balance (work–energy theorem):
///
/// E − E0 = W_torque + W_references + W_turning − D_creep − D_contact − D_dampers,
///
/// with the powers at a state (W = watts, all ≥ 0 for the D's):
/// - axle torques: Σ T·Ω (T about the axle, Ω the spin about it);
/// - references (prescribed motion): −Σ F·v, F the elements' forces on
///   them at their attachment points, v those points' velocities (what
///   drives a reference does the opposite work on the elements);
/// - creep: −Σ (Fx s_x + Fy s_y + Mz s_φ) over the contacts, the forces
///   on the wheel times the slip velocities of the wheel's material point
///   against the (fixed) rail (`crate::creepage`), ≥ 0 for every creep law
///   (they oppose the slip);
/// - contact damping: Σ N_d δ̇ (the hysteresis part of paper eq. 22, with
///   the sign of δ̇);
/// - dampers: Σ Δ̇ᵀ C Δ̇ of the elements;
/// - element turning: Σ F_b·(ω_a × (p_b − p_a)), the work of the
///   elements' forces beyond their potential ½ΔᵀKΔ − f₀·Δ, which is exact
///   only while body a does not rotate (`crate::element`): the forces are
///   along a's turning axes (f₀ the preload; −f₀·Δ the preload's energy).
///
/// The Hertz elastic energy in E is 0.4 K δ^2.5 with the stiffness K of
/// the current contact geometry; K changes as the contact point moves
/// across the profiles, which leaves a small residual.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyLedger {
    /// E at the first accepted state (J).
    pub initial_energy_j: f64,
    /// E at the last accepted state (J).
    pub energy_j: f64,
    pub axle_torque_work_j: f64,
    pub reference_work_j: f64,
    pub creep_dissipation_j: f64,
    pub contact_damping_dissipation_j: f64,
    pub damper_dissipation_j: f64,
    pub element_turning_work_j: f64,
    /// Time (s) and powers (W) at the last accepted state: torque,
    /// references, creep, contact damping, dampers, element turning.
    last: Option<(f64, [f64; 6])>,
}

impl EnergyLedger {
    /// The balance's residual (J): E − E0 − (W_torque + W_references +
    /// W_turning − D_creep − D_contact − D_dampers); zero but for the
    /// integration and quadrature errors (struct docs).
    pub fn residual_j(&self) -> f64 {
        self.energy_j
            - self.initial_energy_j
            - (self.axle_torque_work_j + self.reference_work_j + self.element_turning_work_j
                - self.creep_dissipation_j
                - self.contact_damping_dissipation_j
                - self.damper_dissipation_j)
    }

    /// Adds the powers `p` (W; order of `last`) at the accepted time `t_s`
    /// (trapezoidal rule) and the energy there.
    fn add(&mut self, t_s: f64, p: [f64; 6], energy_j: f64) {
        match self.last {
            None => self.initial_energy_j = energy_j,
            Some((t0, p0)) => {
                let w = |k: usize| 0.5 * (p0[k] + p[k]) * (t_s - t0);
                self.axle_torque_work_j += w(0);
                self.reference_work_j += w(1);
                self.creep_dissipation_j += w(2);
                self.contact_damping_dissipation_j += w(3);
                self.damper_dissipation_j += w(4);
                self.element_turning_work_j += w(5);
            }
        }
        self.energy_j = energy_j;
        self.last = Some((t_s, p));
    }
}

/// Counters of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RunCounters {
    /// Right-hand-side evaluations (integrator stages and output samples).
    pub evaluations: u64,
    /// Accepted states.
    pub accepted: u64,
    /// Accepted states at which each wheel (wheelset-major, left then right)
    /// had flange contact — summed over wheels.
    pub flange_contact_states: u64,
}

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

type Memories = [[ContactMemory; MAX_SEGMENTS]; 2];

/// The vehicle on the track (module docs). Built by [`VehicleSystem::assemble`].
pub struct VehicleSystem<'a> {
    track: &'a TrackTables,
    vehicle: &'a VehicleModel,
    settings: SystemSettings,
    elements: Vec<SpringDamper>,
    solvers: Vec<ContactSolver>,
    s_guess: Vec<f64>,
    memory: Vec<Memories>,
    pending: Vec<Memories>,
    snapshots: Vec<WheelsetSnapshot>,
    states: Vec<BodyState>,
    anchors: Vec<Anchor>,
    wrenches: Vec<Wrench>,
    counters: RunCounters,
    flange_states: Vec<[u64; 2]>,
    stop: Option<Arc<AtomicBool>>,
    progress: Option<Box<dyn FnMut(f64) + 'a>>,
    /// Stop when the vehicle reference passes this track distance (m).
    s_stop_m: f64,
    /// The references' speed against time.
    ramp: SpeedRamp,
    /// Energy bookkeeping, when enabled ([`Self::enable_energy_ledger`]).
    ledger: Option<EnergyLedger>,
    /// The run was stopped because a wheelset or the vehicle reference
    /// came within [`TRACK_END_MARGIN_M`] of the end of the tables (or
    /// [`TRACK_START_MARGIN_M`] of their start).
    track_end_reached: bool,
}

/// A run stops when the vehicle reference point or a wheelset comes this
/// close to an end of the track tables (m): a contact point may lead or lag
/// its axle, and the reference anchors look ±5 cm along (`REFERENCE_DS_M`).
pub const TRACK_END_MARGIN_M: f64 = 2.0;

/// The same at the start of the tables (m), reached only by running
/// backwards: smaller, so that a run may start close to the start (a
/// contact point lags its axle by a few centimetres at most).
pub const TRACK_START_MARGIN_M: f64 = 0.5;

impl<'a> VehicleSystem<'a> {
    /// Builds the system and its initial state y0 (module docs; the
    /// assembly rules are in [`InitialConditions`] and
    /// [`super::vehicle`]): every wheelset is first settled centred under
    /// its static wheel load (its assembly position, where the element
    /// preloads are exact), the elements are assembled there, then the
    /// wheelsets are moved to the initial conditions and settled again. All
    /// bodies move at the set speed; wheelsets spin at V/r₀.
    pub fn assemble(
        track: &'a TrackTables,
        vehicle: &'a VehicleModel,
        settings: SystemSettings,
        initial: InitialConditions,
    ) -> Result<(VehicleSystem<'a>, Vec<f64>), DynamicsError> {
        settings
            .forces
            .validate()
            .map_err(|e| DynamicsError::Assembly {
                wheelset: String::from("(all)"),
                reason: e.to_string(),
            })?;
        if let ContactMethod::Imported(m) = &settings.method {
            m.validate(&settings.forces, vehicle.wheelsets.len())
                .map_err(|reason| DynamicsError::Assembly {
                    wheelset: String::from("(all)"),
                    reason,
                })?;
        }
        settings.validate_motion()?;
        let speed = settings.speed_m_s;
        for (name, v) in [
            ("initial lateral shift (m)", initial.lateral_m),
            ("initial yaw (rad)", initial.yaw_rad),
        ] {
            if !(v.is_finite() && v.abs() < 0.05) {
                return Err(DynamicsError::Setting {
                    setting: name,
                    value: v,
                    rule: "must be finite and smaller than 0.05 in magnitude",
                });
            }
        }
        for w in &vehicle.wheelsets {
            w.body.validate().map_err(|source| DynamicsError::Body {
                name: w.name.clone(),
                source,
            })?;
        }
        for b in &vehicle.bodies {
            b.body.validate().map_err(|source| DynamicsError::Body {
                name: b.name.clone(),
                source,
            })?;
        }
        let c = &track.centerline;
        let s0 = settings.s_start_m;
        let track_err = |what: &str| {
            let what = what.to_string();
            move |source| DynamicsError::Track {
                what: what.clone(),
                t_s: 0.0,
                source,
            }
        };
        let material = settings.forces.material;
        let mut solvers = Vec::new();
        let mut nominal_anchors = Vec::new();
        let mut initial_states = Vec::new();
        let mut memory = Vec::new();
        let mut s_guess = Vec::new();
        for (i, w) in vehicle.wheelsets.iter().enumerate() {
            let assembly_err = |reason: String| DynamicsError::Assembly {
                wheelset: w.name.clone(),
                reason,
            };
            let mut options = settings.contact;
            if options.flange == FlangeSearch::Auto {
                // Identical wheelsets (the usual case) share one computation.
                let same = vehicle
                    .wheelsets
                    .iter()
                    .zip(&solvers)
                    .find(|(other, _)| other.contact == w.contact)
                    .map(|(_, s): (_, &ContactSolver)| s.options.flange_clearance_m);
                match same {
                    Some(c) => options.flange_clearance_m = c,
                    None => {
                        for side in Side::BOTH {
                            let clearance = flange_clearance_m(&w.contact, side)
                                .map_err(|e| assembly_err(format!("flangeway clearance: {e}")))?;
                            options.flange_clearance_m[side_index(side)] = clearance.unwrap_or(0.0);
                        }
                    }
                }
            }
            let mut solver = ContactSolver::new(options);
            let s_w = s0 + w.x_m;
            let support = Support::Elastic {
                load_per_wheel_n: w.static_wheel_load_n,
                material,
            };
            // The imported method seats the wheelset from its table
            // (`settle_imported`); the others settle it on its profiles.
            let settle_at = |y: f64, yaw: f64, solver: &mut ContactSolver| match &settings.method {
                ContactMethod::Imported(m) => {
                    settle_imported(track, &m.tables[i], s_w, y, yaw, w.static_wheel_load_n)
                }
                _ => settle(&w.contact, track, s_w, y, yaw, support, solver),
            };
            let nominal = settle_at(w.y_m, 0.0, &mut solver)
                .map_err(|e| assembly_err(format!("settling at assembly: {e}")))?;
            nominal_anchors.push(Anchor::fixed(nominal.pose.position, nominal.pose.frame));
            // Free rolling of the centred wheelset: Ω = V / r, r the mean
            // rolling radius of its two tread contacts when centred (an
            // imported table's r at y = 0 need not be the nominal radius:
            // 0.424883 m against 0.425 m for the Cooperrider car, which at
            // V/r₀ would start — and linearise — with a longitudinal creepage
            // of 2.8e-4 on every wheel). The nominal radius without contact.
            let rolling_radius_m = match (
                nominal.contacts.candidates[0][0].filter(|c| c.in_contact()),
                nominal.contacts.candidates[1][0].filter(|c| c.in_contact()),
            ) {
                (Some(l), Some(r)) => 0.5 * (l.rolling_radius_m + r.rolling_radius_m),
                _ => w.nominal_radius_m,
            };
            solver.reset();
            // Time stepping: consecutive poses are micrometres apart.
            solver.options.reuse_clear_pieces = true;
            let st = settle_at(w.y_m + initial.lateral_m, initial.yaw_rad, &mut solver)
                .map_err(|e| assembly_err(format!("settling at the initial conditions: {e}")))?;
            // Rigid-body state: axle frame (no spin angle yet), moving with
            // the track frame at the set speed, spinning at V/r.
            let frame = st.pose.frame;
            let orientation =
                UnitQuaternion::from_matrix_eps(&frame, 1e-12, 100, UnitQuaternion::identity());
            let track_motion =
                reference_anchor(c, s0, &Vector3::new(w.x_m, 0.0, 0.0), speed, REFERENCE_DS_M)
                    .map_err(track_err(&w.name))?;
            let omega_global =
                frame.column(1) * (speed / rolling_radius_m) + track_motion.angular_velocity_rad_s;
            initial_states.push(BodyState {
                position_m: st.pose.position,
                orientation,
                velocity_m_s: track_motion.velocity_m_s,
                angular_velocity_rad_s: orientation.inverse_transform_vector(&omega_global),
            });
            // The paper's start-up rule for contacts that exist at t = 0.
            let mut m: Memories = Default::default();
            for (k, slot) in m.iter_mut().enumerate() {
                for (seg, mem) in slot.iter_mut().enumerate() {
                    if st.contacts.candidates[k][seg].is_some_and(|c| c.in_contact()) {
                        *mem = ContactMemory::started_in_contact();
                    }
                }
            }
            memory.push(m);
            s_guess.push(s_w);
            solvers.push(solver);
        }
        for b in &vehicle.bodies {
            let position = vehicle_point(c, s0, &b.cg_m).map_err(track_err(&b.name))?;
            let rotation = track_rotation(c, s0 + b.cg_m.x).map_err(track_err(&b.name))?;
            let motion = reference_anchor(c, s0, &b.cg_m, speed, REFERENCE_DS_M)
                .map_err(track_err(&b.name))?;
            let orientation =
                UnitQuaternion::from_matrix_eps(&rotation, 1e-12, 100, UnitQuaternion::identity());
            initial_states.push(BodyState {
                position_m: position,
                orientation,
                velocity_m_s: motion.velocity_m_s,
                angular_velocity_rad_s: orientation
                    .inverse_transform_vector(&motion.angular_velocity_rad_s),
            });
        }
        // Assembly anchors: wheelsets centred and settled, bodies at their
        // assembly positions, references at t = 0, ground.
        let assembly_anchor = |end: End| -> Result<Anchor, DynamicsError> {
            Ok(match end {
                End::Ground => Anchor::fixed(Vector3::zeros(), Matrix3::identity()),
                End::Wheelset(i) => nominal_anchors[i],
                End::Body(i) => {
                    let b = &vehicle.bodies[i];
                    Anchor::fixed(
                        vehicle_point(c, s0, &b.cg_m).map_err(track_err(&b.name))?,
                        track_rotation(c, s0 + b.cg_m.x).map_err(track_err(&b.name))?,
                    )
                }
                End::Reference(i) => {
                    let r = &vehicle.references[i];
                    reference_anchor(c, s0, &r.origin_m, speed, REFERENCE_DS_M)
                        .map_err(track_err(&r.name))?
                }
            })
        };
        let mut elements = Vec::new();
        for e in &vehicle.elements {
            let a = assembly_anchor(e.a)?;
            let b = assembly_anchor(e.b)?;
            let pa = vehicle_point(c, s0, &e.point_a_m).map_err(track_err(&e.name))?;
            let pb = vehicle_point(c, s0, &e.point_b_m).map_err(track_err(&e.name))?;
            let element = SpringDamper::assembled(
                &a,
                &b,
                &pa,
                &pb,
                e.stiffness_n_m,
                e.damping_n_s_m,
                e.preload_n,
            )
            .map_err(|source| DynamicsError::Element {
                name: e.name.clone(),
                source,
            })?;
            elements.push(element);
        }
        let n_bodies = vehicle.wheelsets.len() + vehicle.bodies.len();
        let mut y0 = vec![0.0; vehicle.state_len()];
        for (k, st) in initial_states.iter().enumerate() {
            st.write_to(&mut y0[BodyState::slot(k)]);
        }
        let n_ws = vehicle.wheelsets.len();
        let (_, s_end) = c.range_m();
        let max_x = vehicle
            .wheelsets
            .iter()
            .map(|w| w.x_m)
            .fold(f64::NEG_INFINITY, f64::max);
        let system = VehicleSystem {
            track,
            vehicle,
            elements,
            solvers,
            s_guess,
            pending: memory.clone(),
            memory,
            snapshots: vec![WheelsetSnapshot::default(); n_ws],
            states: initial_states,
            anchors: vec![
                Anchor::fixed(Vector3::zeros(), Matrix3::identity());
                n_bodies + vehicle.references.len()
            ],
            wrenches: vec![Wrench::zero(); n_bodies],
            counters: RunCounters::default(),
            flange_states: vec![[0; 2]; n_ws],
            stop: None,
            progress: None,
            // Leave 2 m of table ahead of the leading wheelset.
            s_stop_m: s_end - TRACK_END_MARGIN_M - max_x.max(0.0),
            ramp: settings.speed_ramp(),
            ledger: None,
            track_end_reached: false,
            settings,
        };
        Ok((system, y0))
    }

    /// Stop cleanly (at the next accepted state) when `flag` becomes true
    /// (Ctrl-C).
    pub fn set_stop_flag(&mut self, flag: Arc<AtomicBool>) {
        self.stop = Some(flag);
    }

    /// Called with the time of every accepted state (progress reporting;
    /// the library never prints).
    pub fn set_progress(&mut self, progress: Box<dyn FnMut(f64) + 'a>) {
        self.progress = Some(progress);
    }

    pub fn track(&self) -> &'a TrackTables {
        self.track
    }

    pub fn settings(&self) -> &SystemSettings {
        &self.settings
    }

    pub fn vehicle(&self) -> &VehicleModel {
        self.vehicle
    }

    pub fn counters(&self) -> RunCounters {
        self.counters
    }

    /// Accepted states with flange contact, per wheelset `[left, right]`.
    pub fn flange_contact_states(&self) -> &[[u64; 2]] {
        &self.flange_states
    }

    /// The contact solvers (statistics: solves, iterations, cold starts).
    pub fn solvers(&self) -> &[ContactSolver] {
        &self.solvers
    }

    /// The per-wheelset results of the last evaluation.
    pub fn snapshots(&self) -> &[WheelsetSnapshot] {
        &self.snapshots
    }

    /// The body states of the last evaluation (wheelsets first).
    pub fn states(&self) -> &[BodyState] {
        &self.states
    }

    /// Speed of the references at time `t_s` (m/s): the ramp of
    /// [`SystemSettings::speed_ramp`] (constant, braking to a stop or to
    /// a final speed, accelerating).
    pub fn speed_at_m_s(&self, t_s: f64) -> f64 {
        self.ramp.speed_m_s(t_s)
    }

    /// Track distance of the vehicle reference point at time `t_s` (m): the
    /// integral of [`Self::speed_at_m_s`].
    pub fn s_vehicle_m(&self, t_s: f64) -> f64 {
        self.settings.s_start_m + self.ramp.distance_m(t_s)
    }

    /// Track distance beyond which the run stops (m).
    pub fn s_stop_m(&self) -> f64 {
        self.s_stop_m
    }

    /// Whether the run was stopped at an end of the track tables (the
    /// vehicle reference or a wheelset within [`TRACK_END_MARGIN_M`] of
    /// the end or [`TRACK_START_MARGIN_M`] of the start).
    pub fn track_end_reached(&self) -> bool {
        self.track_end_reached
    }

    /// Keeps an [`EnergyLedger`] from the next accepted state on (costs one
    /// energy and power evaluation per accepted state).
    pub fn enable_energy_ledger(&mut self) {
        self.ledger = Some(EnergyLedger::default());
    }

    /// The energy bookkeeping so far, if enabled.
    pub fn energy_ledger(&self) -> Option<&EnergyLedger> {
        self.ledger.as_ref()
    }

    /// The non-conservative powers (W) at the last evaluated state, in the
    /// order of [`EnergyLedger`]: axle torques, references, creep
    /// dissipation, contact damping dissipation, damper dissipation, the
    /// elements' work beyond their potential.
    fn powers_w(&self) -> [f64; 6] {
        let mut p = [0.0; 6];
        for snap in &self.snapshots {
            p[0] += snap.axle_torque_nm * snap.spin_rad_s;
            for f in snap.forces.iter().flatten().flatten() {
                let (c, slip) = (&f.tangential.creep, &f.tangential.creepages.slip);
                p[2] -= c.fx_n * slip.longitudinal_m_s
                    + c.fy_n * slip.lateral_m_s
                    + c.mz_nm * slip.spin_rad_s;
                p[3] += f.normal.damping_n * slip.penetration_rate_m_s;
            }
        }
        let vehicle = self.vehicle;
        let n_refs_from = vehicle.wheelsets.len() + vehicle.bodies.len();
        let ground = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        for (el, spec) in self.elements.iter().zip(&vehicle.elements) {
            let ia = self.anchor_index(spec.a);
            let ib = self.anchor_index(spec.b);
            let a = ia.map_or(ground, |k| self.anchors[k]);
            let b = ib.map_or(ground, |k| self.anchors[k]);
            let f = el.evaluate(&a, &b);
            // Velocity of a point p of an anchor: v + ω × (p − origin).
            let point_velocity = |an: &Anchor, point: &Vector3<f64>| {
                an.velocity_m_s + an.angular_velocity_rad_s.cross(&(point - an.position_m))
            };
            // The reference's driver does on the element the work the
            // element does on the reference, negated.
            if ia.is_some_and(|k| k >= n_refs_from) {
                p[1] -= f.force_on_a_n().dot(&point_velocity(&a, &f.point_a_m));
            }
            if ib.is_some_and(|k| k >= n_refs_from) {
                p[1] -= f.force_on_b_n.dot(&point_velocity(&b, &f.point_b_m));
            }
            p[4] += el.dissipated_power_w(&f.rate_m_s);
            // The elements' directions turn with a: their forces on the
            // bodies do F_b·(ω_a × (p_b − p_a)) more work than their
            // potential and dampers account for.
            p[5] += f
                .force_on_b_n
                .dot(&a.angular_velocity_rad_s.cross(&(f.point_b_m - f.point_a_m)));
        }
        p
    }

    fn anchor_index(&self, end: End) -> Option<usize> {
        let n_ws = self.vehicle.wheelsets.len();
        let n_b = self.vehicle.bodies.len();
        match end {
            End::Ground => None,
            End::Wheelset(i) => Some(i),
            End::Body(i) => Some(n_ws + i),
            End::Reference(i) => Some(n_ws + n_b + i),
        }
    }

    /// Evaluates everything at (t, y): contacts, forces, wrenches (module
    /// docs, steps a–e). Fills the snapshots and the pending hysteresis
    /// memories; commits nothing.
    pub fn evaluate(&mut self, t: f64, y: &[f64]) -> Result<(), DynamicsError> {
        self.counters.evaluations += 1;
        let track = self.track;
        let vehicle = self.vehicle;
        let c = &track.centerline;
        let n_ws = vehicle.wheelsets.len();
        for (i, w) in vehicle.wheelsets.iter().enumerate() {
            let st = BodyState::read_from(&y[BodyState::slot(i)]);
            let s = project_s(c, &st.position_m, self.s_guess[i]).map_err(|source| {
                DynamicsError::Track {
                    what: format!("wheelset '{}'", w.name),
                    t_s: t,
                    source,
                }
            })?;
            self.s_guess[i] = s;
            let up = track_rotation(c, s)
                .map_err(|source| DynamicsError::Track {
                    what: format!("wheelset '{}'", w.name),
                    t_s: t,
                    source,
                })?
                .column(2)
                .into_owned();
            let rotation = st.rotation();
            let axle = rotation.column(1).into_owned();
            let pose = WheelsetPose::from_body(s, st.position_m, axle, up);
            let relative = track_relative(c, s, &st.position_m, &axle, &st.velocity_m_s).map_err(
                |source| DynamicsError::Track {
                    what: format!("wheelset '{}'", w.name),
                    t_s: t,
                    source,
                },
            )?;
            if relative.lateral_m.abs() > self.settings.derailment_lateral_m {
                return Err(DynamicsError::Derailed {
                    wheelset: w.name.clone(),
                    t_s: t,
                    lateral_mm: relative.lateral_m * 1e3,
                    limit_mm: self.settings.derailment_lateral_m * 1e3,
                });
            }
            // Written in place: a snapshot holds a dozen candidates and
            // forces (kilobytes), copying them costs more than their maths.
            let snap = &mut self.snapshots[i];
            let mut imported_rows = None;
            snap.contacts = match &self.settings.method {
                ContactMethod::Online => self.solvers[i].solve(&w.contact, track, &pose),
                ContactMethod::Table(tables) => {
                    table_contacts(&w.contact, track, &pose, &relative, &tables[i])
                }
                ContactMethod::Imported(m) => {
                    imported_contacts(track, &pose, relative.lateral_m, &m.tables[i]).map(
                        |(contacts, rows)| {
                            imported_rows = Some(rows);
                            contacts
                        },
                    )
                }
            }
            .map_err(|source| DynamicsError::Contact {
                wheelset: w.name.clone(),
                t_s: t,
                source,
            })?;
            let omega = st.angular_velocity_global();
            let motion = WheelsetMotion {
                centre_m: st.position_m,
                velocity_m_s: st.velocity_m_s,
                angular_velocity_rad_s: omega,
                forward_speed_m_s: relative.forward_speed_m_s,
            };
            snap.relative = relative;
            snap.spin_rad_s = omega.dot(&axle);
            let mut wrench = Wrench::zero();
            for (k, forces_k) in snap.forces.iter_mut().enumerate() {
                for (seg, force_slot) in forces_k.iter_mut().enumerate() {
                    let pending = &mut self.pending[i][k][seg];
                    *pending = ContactMemory::not_in_contact();
                    *force_slot = None;
                    let Some(cand) = &snap.contacts.candidates[k][seg] else {
                        continue;
                    };
                    let f = match (&self.settings.method, &imported_rows) {
                        (ContactMethod::Imported(m), Some(rows)) => imported_force(
                            &self.settings.forces,
                            m.shear_modulus_pa(&self.settings.forces),
                            &rows[k],
                            cand,
                            &motion,
                        ),
                        _ => evaluate_contact(
                            &self.settings.forces,
                            cand,
                            &self.memory[i][k][seg],
                            &motion,
                        ),
                    }
                    .map_err(|source| DynamicsError::Force {
                        wheelset: w.name.clone(),
                        t_s: t,
                        source,
                    })?;
                    if let Some(f) = f {
                        wrench.add_force_at(&st.position_m, &f.point_m, &f.force_on_wheel_n);
                        wrench.add_moment(&f.moment_on_wheel_nm);
                        *pending = f.normal.next_memory;
                        *force_slot = Some(f);
                    }
                }
            }
            // Axle torque: drive (constant) and friction brake (module docs
            // of `SystemSettings::axle_brake_torque_nm`), about the axle.
            let brake_eps_rad_s = BRAKE_STICK_SPEED_M_S / w.nominal_radius_m;
            snap.axle_torque_nm = self.settings.axle_torque_nm
                - self.settings.axle_brake_torque_nm * snap.spin_rad_s
                    / snap.spin_rad_s.abs().max(brake_eps_rad_s);
            wrench.add_moment(&(axle * snap.axle_torque_nm));
            // Elements attach to the non-spinning axle frame.
            self.anchors[i] = Anchor {
                position_m: st.position_m,
                rotation: pose.frame,
                velocity_m_s: st.velocity_m_s,
                angular_velocity_rad_s: omega - axle * omega.dot(&axle),
            };
            self.wrenches[i] = wrench;
            self.states[i] = st;
        }
        for (j, _) in vehicle.bodies.iter().enumerate() {
            let k = n_ws + j;
            let st = BodyState::read_from(&y[BodyState::slot(k)]);
            self.anchors[k] = Anchor::from_body(&st);
            self.wrenches[k] = Wrench::zero();
            self.states[k] = st;
        }
        let s_vehicle = self.s_vehicle_m(t);
        let n_bodies = n_ws + vehicle.bodies.len();
        for (j, r) in vehicle.references.iter().enumerate() {
            self.anchors[n_bodies + j] = reference_anchor(
                c,
                s_vehicle,
                &r.origin_m,
                self.speed_at_m_s(t),
                REFERENCE_DS_M,
            )
            .map_err(|source| DynamicsError::Track {
                what: format!("reference '{}'", r.name),
                t_s: t,
                source,
            })?;
        }
        let ground = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        for (e, spec) in self.elements.iter().zip(&vehicle.elements) {
            let ia = self.anchor_index(spec.a);
            let ib = self.anchor_index(spec.b);
            let a = ia.map_or(ground, |k| self.anchors[k]);
            let b = ib.map_or(ground, |k| self.anchors[k]);
            let f = e.evaluate(&a, &b);
            if let Some(k) = ia.filter(|&k| k < n_bodies) {
                let cg = self.states[k].position_m;
                self.wrenches[k].add_force_at(&cg, &f.point_a_m, &f.force_on_a_n());
            }
            if let Some(k) = ib.filter(|&k| k < n_bodies) {
                let cg = self.states[k].position_m;
                self.wrenches[k].add_force_at(&cg, &f.point_b_m, &f.force_on_b_n);
            }
        }
        Ok(())
    }

    /// Mechanical energy (J) at the last evaluated state: kinetic energy of
    /// every body, gravitational potential (zero at Z = 0), the elements'
    /// potential, and the elastic energy of the Hertz contacts,
    /// ∫ K δ^1.5 dδ = 0.4 K δ^2.5 (SPEC §7.1). With restitution 1, no creep
    /// and no dampers it is conserved; the references' prescribed motion can
    /// do work on the elements (none on a straight track at constant speed).
    pub fn mechanical_energy_j(&self) -> f64 {
        let g = Vector3::new(0.0, 0.0, -self.settings.gravity_m_s2);
        let vehicle = self.vehicle;
        let bodies = vehicle
            .wheelsets
            .iter()
            .map(|w| &w.body)
            .chain(vehicle.bodies.iter().map(|b| &b.body));
        let mut e = 0.0;
        for (st, body) in self.states.iter().zip(bodies) {
            e += st.kinetic_energy_j(body) + st.potential_energy_j(body, &g);
        }
        let ground = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        for (el, spec) in self.elements.iter().zip(&vehicle.elements) {
            let a = self
                .anchor_index(spec.a)
                .map_or(ground, |k| self.anchors[k]);
            let b = self
                .anchor_index(spec.b)
                .map_or(ground, |k| self.anchors[k]);
            e += el.potential_energy_j(&el.evaluate(&a, &b).deflection_m);
        }
        for snap in &self.snapshots {
            for f in snap.forces.iter().flatten().flatten() {
                // δ from the elastic part of the normal force, N_el = K δ^1.5.
                let k = f.tangential.hertz.stiffness_n_m15;
                if k > 0.0 && f.normal.elastic_n > 0.0 {
                    let delta = (f.normal.elastic_n / k).powf(2.0 / 3.0);
                    e += 0.4 * k * delta * delta * delta.sqrt();
                }
            }
        }
        e
    }
}

impl OdeSystem for VehicleSystem<'_> {
    type Error = DynamicsError;

    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), DynamicsError> {
        self.evaluate(t, y)?;
        let g = Vector3::new(0.0, 0.0, -self.settings.gravity_m_s2);
        let vehicle = self.vehicle;
        let bodies = vehicle
            .wheelsets
            .iter()
            .map(|w| &w.body)
            .chain(vehicle.bodies.iter().map(|b| &b.body));
        for (k, body) in bodies.enumerate() {
            derivatives(
                body,
                &self.states[k],
                &self.wrenches[k],
                &g,
                &mut dydt[BodyState::slot(k)],
            );
        }
        Ok(())
    }

    fn accept(&mut self, t: f64, _y: &[f64]) -> Result<Control, DynamicsError> {
        // The last rhs call was at this state: its hysteresis memory is the
        // one to keep.
        self.memory.clone_from(&self.pending);
        self.counters.accepted += 1;
        for (i, snap) in self.snapshots.iter().enumerate() {
            for side in Side::BOTH {
                if snap.flange_contact(side) {
                    self.flange_states[i][side_index(side)] += 1;
                    self.counters.flange_contact_states += 1;
                }
            }
        }
        if let Some(p) = &mut self.progress {
            p(t);
        }
        let stop_requested = self
            .stop
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed));
        if self.ledger.is_some() {
            let (p, e) = (self.powers_w(), self.mechanical_energy_j());
            if let Some(l) = &mut self.ledger {
                l.add(t, p, e);
            }
        }
        // Forwards: the vehicle reference or a wheelset near the far end;
        // backwards (a reversal, or a wheelset driven back): near the start.
        let (lo, hi) = self.track.centerline.range_m();
        let s_vehicle = self.s_vehicle_m(t);
        let min_x = self
            .vehicle
            .wheelsets
            .iter()
            .map(|w| w.x_m)
            .fold(0.0_f64, f64::min);
        let end_of_track = s_vehicle > self.s_stop_m
            || s_vehicle + min_x < lo + TRACK_START_MARGIN_M
            || self
                .s_guess
                .iter()
                .any(|&s| s > hi - TRACK_END_MARGIN_M || s < lo + TRACK_START_MARGIN_M);
        self.track_end_reached |= end_of_track;
        Ok(if stop_requested || end_of_track {
            Control::Stop
        } else {
            Control::Continue
        })
    }
}
