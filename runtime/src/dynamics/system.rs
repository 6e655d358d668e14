//! The vehicle on the track as a first-order system y′ = f(t, y) (paper
//! §4.1, Fig. 8; SPEC §8). One evaluation of f is the paper's step:
//!
//! a. the state of every body (wheelsets first, then free bodies; 13
//!    variables each, [`crate::body::BodyState`]);
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
    TrackRelative, project_s, reference_anchor, track_relative, track_rotation, vehicle_point,
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
    /// speed): V(t) = max(V0 − a t, 0). Used to ramp the speed down through
    /// the nonlinear critical speed; bodies not tied to a reference (an
    /// unsuspended wheelset) keep their own speed.
    pub deceleration_m_s2: f64,
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
            s_start_m: 5.0,
            derailment_lateral_m: 0.05,
            gravity_m_s2: GRAVITY_M_S2,
        }
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
}

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
        let speed = settings.speed_m_s;
        if !(speed.is_finite() && speed >= 0.0) {
            return Err(DynamicsError::Setting {
                setting: "speed (m/s)",
                value: speed,
                rule: "must be finite and >= 0",
            });
        }
        if !(settings.deceleration_m_s2.is_finite() && settings.deceleration_m_s2 >= 0.0) {
            return Err(DynamicsError::Setting {
                setting: "deceleration (m/s²)",
                value: settings.deceleration_m_s2,
                rule: "must be finite and >= 0",
            });
        }
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
            solver.reset();
            // Time stepping: consecutive poses are micrometres apart.
            solver.options.reuse_clear_pieces = true;
            let st = settle_at(w.y_m + initial.lateral_m, initial.yaw_rad, &mut solver)
                .map_err(|e| assembly_err(format!("settling at the initial conditions: {e}")))?;
            // Rigid-body state: axle frame (no spin angle yet), moving with
            // the track frame at the set speed, spinning at V/r₀.
            let frame = st.pose.frame;
            let orientation =
                UnitQuaternion::from_matrix_eps(&frame, 1e-12, 100, UnitQuaternion::identity());
            let track_motion =
                reference_anchor(c, s0, &Vector3::new(w.x_m, 0.0, 0.0), speed, REFERENCE_DS_M)
                    .map_err(track_err(&w.name))?;
            let omega_global = frame.column(1) * (speed / w.nominal_radius_m)
                + track_motion.angular_velocity_rad_s;
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
            st.write_to(&mut y0[13 * k..13 * k + 13]);
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
            s_stop_m: s_end - 2.0 - max_x.max(0.0),
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

    /// Speed of the references at time `t_s` (m/s): V0 − a t, not below 0.
    pub fn speed_at_m_s(&self, t_s: f64) -> f64 {
        (self.settings.speed_m_s - self.settings.deceleration_m_s2 * t_s).max(0.0)
    }

    /// Track distance of the vehicle reference point at time `t_s` (m): the
    /// integral of [`Self::speed_at_m_s`].
    pub fn s_vehicle_m(&self, t_s: f64) -> f64 {
        let (v0, a) = (self.settings.speed_m_s, self.settings.deceleration_m_s2);
        let t = if a > 0.0 { t_s.min(v0 / a) } else { t_s };
        self.settings.s_start_m + v0 * t - 0.5 * a * t * t
    }

    /// Track distance beyond which the run stops (m).
    pub fn s_stop_m(&self) -> f64 {
        self.s_stop_m
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
            let st = BodyState::read_from(&y[13 * i..13 * i + 13]);
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
            let st = BodyState::read_from(&y[13 * k..13 * k + 13]);
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
                &mut dydt[13 * k..13 * k + 13],
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
        let end_of_track = self.s_vehicle_m(t) > self.s_stop_m;
        Ok(if stop_requested || end_of_track {
            Control::Stop
        } else {
            Control::Continue
        })
    }
}
