//! The vehicle on the track as a first-order system y′ = f(t, y) (paper
//! §4.1, Fig. 8; docs/reference/08-multibody.md §8). One evaluation of f is the paper's step:
//!
//! a. the state of every body (wheelsets first, then free bodies;
//!    [`BodyState::LEN`] variables each, [`crate::multibody::body::BodyState`]);
//! b. the contacts of every wheel, tread and flange, from the wheelset's
//!    [`super::ContactSource`] (online: a contact search warm-started from
//!    the previous solve, [`crate::contact::ContactSolver`]; or the
//!    contact lookup table; or an imported table);
//! c. normal forces (online and table: Hertz with hysteresis,
//!    [`crate::forces::normal`]) and
//! d. creepages and creep forces ([`crate::multibody::contact_force`]), from the
//!    same source;
//! e. suspension forces (elements between bodies, wheelsets and the
//!    track-following references; their internal states, after the
//!    bodies' in y, and the rates of those) and gravity;
//! f. Newton–Euler accelerations ([`crate::multibody::body::derivatives`]).
//!
//! The surface parameters of the last solve are the next initial guess;
//! the hysteresis memory of each contact is committed only at accepted
//! states ([`crate::integrators::OdeSystem::accept`]), so rejected trial
//! steps leave no trace.

use nalgebra::{Matrix3, Vector3};

use super::contact_source::ContactContext;
use super::error::DynamicsError;
use super::formulation::{
    ElementAxes, GyroscopicMoments, RollMoment, axle_frame_euler_correction, roll_arm_correction,
};
use super::settings::BRAKE_STICK_SPEED_M_S;
use super::system::{REFERENCE_DS_M, VehicleSystem};
use super::track_motion::{frame_rotation, project_s, reference_anchor, relative_to};
use crate::contact::WheelsetPose;
use crate::forces::normal::ContactMemory;
use crate::multibody::body::{BodyState, Wrench};
use crate::multibody::contact_force::WheelsetMotion;
use crate::multibody::element::Anchor;

impl VehicleSystem<'_> {
    /// Evaluates everything at (t, y): contacts, forces, wrenches (module
    /// docs, steps a–e). Fills the snapshots and the pending hysteresis
    /// memories; commits nothing.
    pub fn evaluate(&mut self, t: f64, y: &[f64]) -> Result<(), DynamicsError> {
        self.counters.evaluations += 1;
        self.accepted.current = false;
        let track = self.track;
        let vehicle = self.vehicle;
        let c = &track.centerline;
        let n_ws = vehicle.wheelsets.len();
        self.formulation_power_w = 0.0;
        self.contacts_reused.resize(n_ws, false);
        for (i, w) in vehicle.wheelsets.iter().enumerate() {
            // A Jacobian column (`rhs_column`): this wheelset is at the
            // accepted state, its contacts are that state's.
            let reuse = self.column.is_some_and(|c| !c.has_body(i));
            self.contacts_reused[i] = reuse;
            if reuse {
                let part = self.accepted_parts[i];
                self.states[i] = part.state;
                self.anchors[i] = part.anchor;
                self.wrenches[i] = part.wrench;
                continue;
            }
            let st = BodyState::read_from(&y[BodyState::slot(i)]);
            let s = project_s(c, &st.position_m, self.s_guess[i]).map_err(|source| {
                DynamicsError::Track {
                    what: format!("wheelset '{}'", w.name),
                    t_s: t,
                    source,
                }
            })?;
            self.s_guess[i] = s;
            // One centreline lookup at s serves the rotation and the
            // relative position (the same values as two).
            let centre = c.at(s).map_err(|source| DynamicsError::Track {
                what: format!("wheelset '{}'", w.name),
                t_s: t,
                source,
            })?;
            let frame = frame_rotation(&centre.frame);
            let up = frame.column(2).into_owned();
            let roll_axis = frame.column(0).into_owned();
            let rotation = st.rotation();
            let axle = rotation.column(1).into_owned();
            let pose = WheelsetPose::from_body(s, st.position_m, axle, up);
            let relative = relative_to(&centre, &st.position_m, &axle, &st.velocity_m_s);
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
            let source = &mut self.sources[i];
            let ctx = ContactContext {
                track,
                wheelset: w,
                solver: &mut self.solvers[i],
            };
            source
                .contacts_into(ctx, &pose, &relative, &mut snap.contacts)
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
                    let f = source
                        .force(
                            &self.settings.forces,
                            cand,
                            &self.memory[i][k][seg],
                            &motion,
                        )
                        .map_err(|source| DynamicsError::Force {
                            wheelset: w.name.clone(),
                            t_s: t,
                            source,
                        })?;
                    if let Some(f) = f {
                        wrench.add_force_at(&st.position_m, &f.point_m, &f.force_on_wheel_n);
                        wrench.add_moment(&f.moment_on_wheel_nm);
                        if self.settings.formulation.roll_moment == RollMoment::AxleArmOnly {
                            let m = roll_arm_correction(
                                &st.position_m,
                                &axle,
                                &roll_axis,
                                &f.point_m,
                                &f.force_on_wheel_n,
                            );
                            self.formulation_power_w += m.dot(&omega);
                            wrench.add_moment(&m);
                        }
                        *pending = f.normal.next_memory;
                        *force_slot = Some(f);
                    }
                }
            }
            if self.settings.formulation.gyroscopic == GyroscopicMoments::AxleFrameEuler {
                let m =
                    axle_frame_euler_correction(&rotation, &w.body.inertia_kg_m2, &omega, &axle);
                self.formulation_power_w += m.dot(&omega);
                wrench.add_moment(&m);
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
            self.contact_wrenches[i] = wrench;
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
        // The elements' internal states follow the bodies' in y.
        let n_y = vehicle.body_state_len();
        if let Some(q) = y.get(n_y..n_y + self.internal.len()) {
            self.internal.copy_from_slice(q);
        }
        let ground = Anchor::fixed(Vector3::zeros(), Matrix3::identity());
        // Element axes of the published formulation: the track frame at
        // each body's nominal station (`ElementAxes::Track`); references
        // already have those axes.
        self.element_axes.clear();
        if self.settings.formulation.element_axes == ElementAxes::Track {
            let speed = self.speed_at_m_s(t);
            let stations = vehicle
                .wheelsets
                .iter()
                .map(|w| (w.name.as_str(), w.x_m))
                .chain(vehicle.bodies.iter().map(|b| (b.name.as_str(), b.cg_m.x)));
            for (name, x) in stations {
                let axes = reference_anchor(
                    c,
                    s_vehicle,
                    &Vector3::new(x, 0.0, 0.0),
                    speed,
                    REFERENCE_DS_M,
                )
                .map_err(|source| DynamicsError::Track {
                    what: format!("the track axes of '{name}'"),
                    t_s: t,
                    source,
                })?;
                self.element_axes.push(axes);
            }
        }
        for (idx, (e, spec)) in self.elements.iter().zip(&vehicle.elements).enumerate() {
            let ia = self.anchor_index(spec.a);
            let ib = self.anchor_index(spec.b);
            let (start, len) = (self.internal_offsets[idx], e.internal_len());
            // A Jacobian column (`rhs_column`) that does not touch this
            // element: its force is the accepted state's.
            // Written in place and read by reference (an anchor and a
            // force are a hundred bytes or more each: copies showed in the
            // profile).
            match self.column {
                Some(c) if !c.touches(ia, ib, start..start + len) => {
                    self.element_forces[idx] = self.accepted_element_forces[idx];
                }
                _ => {
                    let a = ia.map_or(&ground, |k| &self.anchors[k]);
                    let b = ib.map_or(&ground, |k| &self.anchors[k]);
                    // Only body anchors have track axes; references' are the track's.
                    let axes = ia.and_then(|k| self.element_axes.get(k));
                    let internal = &self.internal[start..start + len];
                    e.evaluate_along_into(a, b, internal, axes, &mut self.element_forces[idx]);
                }
            }
            let f = &self.element_forces[idx];
            self.internal_rates[start..start + len].copy_from_slice(&f.internal_rate_m_s[..len]);
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
}
