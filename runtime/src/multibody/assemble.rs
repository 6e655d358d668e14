//! Assembly of the vehicle on the track ([`VehicleSystem::assemble`]):
//! settings checked, wheelsets settled on the rails at their assembly
//! position and at the initial conditions, elements assembled, the initial
//! state y0 (paper §5; docs/reference/08-multibody.md §8).

use nalgebra::{Matrix3, UnitQuaternion, Vector3};

use super::axle_frame::check_axisymmetric;
use super::contact_source::ContactContext;
use super::error::DynamicsError;
use super::settings::{InitialConditions, SystemSettings};
use super::system::{
    Memories, REFERENCE_DS_M, RunCounters, TRACK_END_MARGIN_M, VehicleSystem, WheelsetSnapshot,
    side_index,
};
use super::track_motion::{reference_anchor, track_rotation, vehicle_point};
use super::vehicle::{End, VehicleModel};
use crate::contact::quasi_static::flange_clearance_m;
use crate::contact::{ContactSolver, FlangeSearch};
use crate::forces::normal::ContactMemory;
use crate::geometry::track::{Side, TrackTables};
use crate::multibody::body::{BodyState, Wrench};
use crate::multibody::element::{Anchor, ElementForce, SpringDamper};

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
        let mut sources = settings
            .method
            .sources(&settings.forces, vehicle.wheelsets.len())?;
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
            w.body
                .validate()
                .and_then(|()| check_axisymmetric(&w.body))
                .map_err(|source| DynamicsError::Body {
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
        let mut solvers = Vec::new();
        let mut nominal_anchors = Vec::new();
        let mut initial_states = Vec::new();
        let mut memory = Vec::new();
        let mut s_guess = Vec::new();
        let given_clearances = given_flange_clearances(&settings, vehicle.wheelsets.len())?;
        for (i, (w, source)) in vehicle.wheelsets.iter().zip(&mut sources).enumerate() {
            let assembly_err = |reason: String| DynamicsError::Assembly {
                wheelset: w.name.clone(),
                reason,
            };
            let mut options = settings.contact;
            if options.flange == FlangeSearch::Auto {
                // The caller's cached sweep; else identical wheelsets (the
                // usual case) share one computation.
                if let Some(c) = given_clearances.map(|c| c[i]) {
                    options.flange_clearance_m = c.map(|side| side.unwrap_or(0.0));
                } else if let Some(c) = vehicle
                    .wheelsets
                    .iter()
                    .zip(&solvers)
                    .find(|(other, _)| other.contact == w.contact)
                    .map(|(_, s): (_, &ContactSolver)| s.options.flange_clearance_m)
                {
                    options.flange_clearance_m = c;
                } else {
                    for side in Side::BOTH {
                        let clearance = flange_clearance_m(&w.contact, side)
                            .map_err(|e| assembly_err(format!("flangeway clearance: {e}")))?;
                        options.flange_clearance_m[side_index(side)] = clearance.unwrap_or(0.0);
                    }
                }
            }
            let mut solver = ContactSolver::new(options);
            let s_w = s0 + w.x_m;
            // Seated by its contact source (on its profiles, or from an
            // imported table).
            let mut settle_at = |y: f64, yaw: f64, solver: &mut ContactSolver| {
                let ctx = ContactContext {
                    track,
                    wheelset: w,
                    solver,
                };
                source.settle(ctx, &settings.forces, s_w, y, yaw)
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
            .and_then(|el| el.with_laws(e.laws.clone()))
            .map_err(|source| DynamicsError::Element {
                name: e.name.clone(),
                source,
            })?;
            elements.push(element);
        }
        // Internal states after the bodies', zero at assembly (series
        // springs undeflected: the preload is the element's constant f₀).
        let mut internal_offsets = Vec::with_capacity(elements.len());
        let mut n_internal = 0;
        for el in &elements {
            internal_offsets.push(n_internal);
            n_internal += el.internal_len();
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
            internal_offsets,
            internal: vec![0.0; n_internal],
            internal_rates: vec![0.0; n_internal],
            element_axes: Vec::new(),
            imposed_power_w: 0.0,
            formulation_power_w: 0.0,
            solvers,
            sources,
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
            ramp: settings.speed_profile(),
            ledger: None,
            track_end_reached: false,
            contact_pattern: Vec::new(),
            accepted: Default::default(),
            contact_wrenches: vec![Wrench::zero(); vehicle.wheelsets.len()],
            accepted_parts: Vec::new(),
            column: None,
            element_forces: vec![ElementForce::default(); vehicle.elements.len()],
            accepted_element_forces: Vec::new(),
            contacts_reused: Vec::new(),
            settings,
        };
        Ok((system, y0))
    }
}

/// The caller's flangeway clearances ([`SystemSettings::flange_clearances_m`]),
/// checked: one entry per wheelset, each finite and ≥ 0.
fn given_flange_clearances(
    settings: &SystemSettings,
    n_wheelsets: usize,
) -> Result<Option<&[crate::multibody::FlangeClearances]>, DynamicsError> {
    let Some(c) = &settings.flange_clearances_m else {
        return Ok(None);
    };
    if c.len() != n_wheelsets {
        return Err(DynamicsError::Assembly {
            wheelset: String::from("(all)"),
            reason: format!(
                "{} flangeway clearances given for {n_wheelsets} wheelsets",
                c.len()
            ),
        });
    }
    for &v in c.iter().flatten().flatten() {
        if !(v.is_finite() && v >= 0.0) {
            return Err(DynamicsError::Setting {
                setting: "flangeway clearance (m)",
                value: v,
                rule: "must be finite and ≥ 0",
            });
        }
    }
    Ok(Some(c))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::vehicles::ShippedVehicle;

    /// The caller's clearances replace assembly's sweep (which gives the
    /// same values when they come from the same model); a wrong count or
    /// value is refused.
    #[test]
    fn given_flange_clearances_replace_the_sweep() {
        let which = ShippedVehicle::Ml95Bogie;
        let (vehicle, track) = which.build().expect("the shipped profiles");
        let assemble = |given: Option<Vec<[Option<f64>; 2]>>| {
            let settings = SystemSettings {
                flange_clearances_m: given,
                ..which.settings(20.0)
            };
            VehicleSystem::assemble(&track, &vehicle, settings, InitialConditions::default())
                .map(|(s, y0)| (s.solvers()[1].options.flange_clearance_m, y0))
        };
        let (swept, y0) = assemble(None).expect("assembles");
        assert!(swept.iter().all(|c| *c > 0.001), "{swept:?}");
        let same = [Some(swept[0]), Some(swept[1])];
        let (given, y0_given) = assemble(Some(vec![same; 2])).expect("assembles");
        assert_eq!(given, swept);
        assert_eq!(y0_given, y0);
        let (other, _) = assemble(Some(vec![[Some(0.123), None]; 2])).expect("assembles");
        assert_eq!(other, [0.123, 0.0]);
        assert!(matches!(
            assemble(Some(vec![same])),
            Err(DynamicsError::Assembly { .. })
        ));
        assert!(matches!(
            assemble(Some(vec![[Some(-0.001), None]; 2])),
            Err(DynamicsError::Setting { .. })
        ));
    }
}
