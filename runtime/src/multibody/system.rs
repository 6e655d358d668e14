//! The vehicle on the track as a first-order system y′ = f(t, y) for
//! [`crate::integrators`] (paper §4.1, Fig. 8; docs/reference/08-multibody.md §8): the
//! [`VehicleSystem`] and its state, the per-wheelset results of an
//! evaluation ([`WheelsetSnapshot`]), and the [`OdeSystem`] implementation
//! (f and the accepted-state bookkeeping: hysteresis memory, counters,
//! stop at the end of the track). Built by [`VehicleSystem::assemble`]
//! (`assemble.rs`), evaluated by [`VehicleSystem::evaluate`]
//! (`evaluate.rs`); settings in `settings.rs`, errors in `error.rs`, the
//! energy ledger in `energy.rs`.

use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use nalgebra::Vector3;

use super::contact_source::ContactSource;
use super::formulation::LongitudinalMotion;
use super::speed_profile::SpeedProfile;
use super::track_motion::TrackRelative;
use super::vehicle::{End, VehicleModel};
use crate::contact::{ContactSolver, WheelsetContacts};
use crate::forces::normal::ContactMemory;
use crate::geometry::profile::{MAX_SEGMENTS, Zone};
use crate::geometry::track::{Side, TrackTables};
use crate::integrators::{
    ColoredColumns, ColumnColor, Control, JacobianBlocks, KinematicBlock, OdeSystem,
};
use crate::multibody::axle_frame::axle_frame_derivatives;
use crate::multibody::body::{BodyState, Wrench, derivatives};
use crate::multibody::contact_force::ContactForce;
use crate::multibody::element::{Anchor, ElementForce, SpringDamper};
use crate::multibody::{DynamicsError, EnergyLedger, SystemSettings};

/// Step of the central difference giving a reference's velocity and
/// angular velocity from the track frame (m).
pub(super) const REFERENCE_DS_M: f64 = 0.05;

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

/// Counters of a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RunCounters {
    /// Right-hand-side evaluations: integrator stages, and output samples
    /// that fall between accepted states (a sample at an accepted state
    /// reuses that state's evaluation, [`VehicleSystem::evaluated_at`]).
    pub evaluations: u64,
    /// Accepted states.
    pub accepted: u64,
    /// Accepted states at which each wheel (wheelset-major, left then right)
    /// had flange contact — summed over wheels.
    pub flange_contact_states: u64,
}

pub(super) fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

pub(super) type Memories = [[ContactMemory; MAX_SEGMENTS]; 2];

/// The vehicle on the track (module docs). Built by [`VehicleSystem::assemble`].
pub struct VehicleSystem<'a> {
    pub(super) track: &'a TrackTables,
    pub(super) vehicle: &'a VehicleModel,
    pub(super) settings: SystemSettings,
    pub(super) elements: Vec<SpringDamper>,
    /// Index in `internal` (and in the state after the bodies') of each
    /// element's first internal state.
    pub(super) internal_offsets: Vec<usize>,
    /// The elements' internal states at the last evaluation (series
    /// strokes, m), and their rates (m/s).
    pub(super) internal: Vec<f64>,
    pub(super) internal_rates: Vec<f64>,
    pub(super) solvers: Vec<ContactSolver>,
    /// Where each wheelset's contacts come from.
    pub(super) sources: Vec<Box<dyn ContactSource>>,
    pub(super) s_guess: Vec<f64>,
    pub(super) memory: Vec<Memories>,
    pub(super) pending: Vec<Memories>,
    pub(super) snapshots: Vec<WheelsetSnapshot>,
    pub(super) states: Vec<BodyState>,
    pub(super) anchors: Vec<Anchor>,
    /// The axes the elements act along when they are the track's
    /// (`ElementAxes::Track`), per body anchor; empty otherwise.
    pub(super) element_axes: Vec<Anchor>,
    /// Power of the imposed longitudinal motion's constraint at the last
    /// evaluation (W; `LongitudinalMotion::Imposed`, else 0).
    pub(super) imposed_power_w: f64,
    /// Power of the published formulation's extra wheelset moments
    /// (`GyroscopicMoments::AxleFrameEuler`, `RollMoment::AxleArmOnly`) at
    /// the last evaluation (W).
    pub(super) formulation_power_w: f64,
    pub(super) wrenches: Vec<Wrench>,
    pub(super) counters: RunCounters,
    pub(super) flange_states: Vec<[u64; 2]>,
    pub(super) stop: Option<Arc<AtomicBool>>,
    pub(super) progress: Option<Box<dyn FnMut(f64) + 'a>>,
    /// Stop when the vehicle reference passes this track distance (m).
    pub(super) s_stop_m: f64,
    /// The references' speed against time.
    pub(super) ramp: SpeedProfile,
    /// Energy bookkeeping, when enabled ([`Self::enable_energy_ledger`]).
    pub(super) ledger: Option<EnergyLedger>,
    /// The run was stopped because a wheelset or the vehicle reference
    /// came within [`TRACK_END_MARGIN_M`] of the end of the tables (or
    /// [`TRACK_START_MARGIN_M`] of their start).
    pub(super) track_end_reached: bool,
    /// Per contact candidate at the last accepted state: 0 apart, 1 in
    /// contact on the tread, 2 on the flange ([`OdeSystem::structure_changed`]).
    pub(super) contact_pattern: Vec<u8>,
    /// The last accepted state (t s, y), and whether the last evaluation
    /// is still that state's ([`VehicleSystem::evaluated_at`]).
    pub(super) accepted: AcceptedState,
    /// Per wheelset, the wrench of its contacts, axle torque and
    /// formulation moments (before the elements') at the last evaluation.
    pub(super) contact_wrenches: Vec<Wrench>,
    /// Per wheelset at the last accepted state: what Jacobian columns
    /// reuse ([`OdeSystem::rhs_column`]).
    pub(super) accepted_parts: Vec<WheelsetPart>,
    /// What the current evaluation, a Jacobian column, perturbs (the
    /// rest is reused from the accepted state); `None` for a full
    /// evaluation.
    pub(super) column: Option<ColumnPerturbation>,
    /// Every element's force at the last evaluation, and at the last
    /// accepted state (reused by Jacobian columns).
    pub(super) element_forces: Vec<ElementForce>,
    pub(super) accepted_element_forces: Vec<ElementForce>,
    /// Per wheelset, whether the last evaluation reused its contacts from
    /// the accepted state instead of computing them.
    pub(super) contacts_reused: Vec<bool>,
}

/// What a Jacobian column perturbs ([`OdeSystem::rhs_column`]): a set of
/// bodies (bit k: anchor index k, which is the wheelset index for a
/// wheelset; at most 64 bodies) or one element's internal state (its index
/// among the internal states).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct ColumnPerturbation {
    pub(super) bodies: u64,
    pub(super) internal: Option<usize>,
}

impl ColumnPerturbation {
    /// Whether body (anchor) `k` is perturbed.
    pub(super) fn has_body(&self, k: usize) -> bool {
        k < 64 && self.bodies & (1 << k) != 0
    }

    /// Whether element `idx`, between anchors `ia` and `ib` with internal
    /// states `internal` (indices among all internal states), must be
    /// evaluated again: one of its ends or internal states is perturbed.
    pub(super) fn touches(
        &self,
        ia: Option<usize>,
        ib: Option<usize>,
        internal: std::ops::Range<usize>,
    ) -> bool {
        let body = ia.is_some_and(|k| self.has_body(k)) || ib.is_some_and(|k| self.has_body(k));
        body || self.internal.is_some_and(|i| internal.contains(&i))
    }
}

/// What a wheelset's contacts give the rest of an evaluation: its state,
/// its axle-frame anchor and the wrench of its contacts, axle torque and
/// formulation moments (before the elements').
#[derive(Debug, Clone, Copy)]
pub(super) struct WheelsetPart {
    pub(super) state: BodyState,
    pub(super) anchor: Anchor,
    pub(super) wrench: Wrench,
}

/// The last accepted state and whether nothing was evaluated since.
#[derive(Debug, Clone, Default)]
pub(super) struct AcceptedState {
    pub(super) t_s: f64,
    pub(super) y: Vec<f64>,
    /// Whether the last evaluation is the one at (`t_s`, `y`): set by
    /// `accept`, cleared by every evaluation.
    pub(super) current: bool,
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

    /// Per wheelset, whether the last evaluation reused its contacts
    /// from the accepted state (a Jacobian column) instead of computing
    /// them: its snapshot is then not this evaluation's.
    pub fn contacts_reused(&self) -> &[bool] {
        &self.contacts_reused
    }

    /// The per-wheelset results of the last evaluation.
    pub fn snapshots(&self) -> &[WheelsetSnapshot] {
        &self.snapshots
    }

    /// The body states of the last evaluation (wheelsets first).
    pub fn states(&self) -> &[BodyState] {
        &self.states
    }

    /// The resultant applied force and moment (contact, suspension, axle
    /// torque; gravity apart) on every body at the last evaluation, global,
    /// in the order of [`Self::states`]: the right-hand side's
    /// accelerations are `force_n / m + g`.
    pub fn wrenches(&self) -> &[Wrench] {
        &self.wrenches[..self.states.len()]
    }

    /// The elements' internal states at the last evaluation (the series
    /// dampers' strokes, m; element order, after the bodies' states in y).
    pub fn internal_states(&self) -> &[f64] {
        &self.internal
    }

    /// The internal states of element `index` at the last evaluation.
    pub(super) fn element_internal(&self, index: usize) -> &[f64] {
        let start = self.internal_offsets[index];
        &self.internal[start..start + self.elements[index].internal_len()]
    }

    /// Speed of the references at time `t_s` (m/s): the ramp of
    /// [`SystemSettings::speed_profile`] (constant, braking to a stop or to
    /// a final speed, accelerating, or a piecewise-linear schedule).
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

    /// Whether everything computed for (t, y) — snapshots, states,
    /// wrenches, element forces — is already the last evaluation's: (t, y)
    /// is the last accepted state, bit for bit, and nothing was evaluated
    /// since (the integrators call `rhs` then `accept` at every accepted
    /// state, [`crate::integrators`] "Protocol"). Evaluating again would
    /// recompute the same values; an output sample at an accepted state
    /// uses this to skip that evaluation ([`super::Recorder::record`]).
    pub fn evaluated_at(&self, t: f64, y: &[f64]) -> bool {
        let a = &self.accepted;
        a.current
            && a.t_s.to_bits() == t.to_bits()
            && a.y.len() == y.len()
            && a.y.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits())
    }

    pub(super) fn anchor_index(&self, end: End) -> Option<usize> {
        let n_ws = self.vehicle.wheelsets.len();
        let n_b = self.vehicle.bodies.len();
        match end {
            End::Ground => None,
            End::Wheelset(i) => Some(i),
            End::Body(i) => Some(n_ws + i),
            End::Reference(i) => Some(n_ws + n_b + i),
        }
    }
}

impl VehicleSystem<'_> {
    /// Bodies whose Jacobian columns may be perturbed together (Curtis,
    /// Powell & Reid; docs/reference/08-multibody.md §8.5, "Colours"): a
    /// body's state acts on the derivatives of that body, of the bodies an
    /// element joins it to and of those elements' internal states, nothing
    /// else (a contact acts on its own wheelset, a reference moves with time
    /// only). Bodies whose sets of rows are disjoint share a colour, greedy,
    /// largest set first. None when no two bodies can share one (a bogie,
    /// whose wheelsets both hang on the frame), or with more than 64 bodies.
    fn column_colors(&self, n: usize) -> Vec<ColumnColor> {
        let n_bodies = self.vehicle.wheelsets.len() + self.vehicle.bodies.len();
        let n_body_states = self.vehicle.body_state_len();
        if n_bodies > 64 || n_body_states > n {
            return Vec::new();
        }
        let mut neighbours = vec![vec![false; n_bodies]; n_bodies];
        let mut internal_rows: Vec<Vec<Range<usize>>> = vec![Vec::new(); n_bodies];
        for (k, row) in neighbours.iter_mut().enumerate() {
            row[k] = true;
        }
        for (idx, (e, spec)) in self.elements.iter().zip(&self.vehicle.elements).enumerate() {
            let ends: Vec<usize> = [self.anchor_index(spec.a), self.anchor_index(spec.b)]
                .into_iter()
                .flatten()
                .filter(|&k| k < n_bodies)
                .collect();
            let start = n_body_states + self.internal_offsets[idx];
            let internal = start..start + e.internal_len();
            for &a in &ends {
                for &b in &ends {
                    neighbours[a][b] = true;
                }
                if !internal.is_empty() {
                    internal_rows[a].push(internal.clone());
                }
            }
        }
        let rows: Vec<Vec<Range<usize>>> = (0..n_bodies)
            .map(|a| {
                let mut r: Vec<Range<usize>> = (0..n_bodies)
                    .filter(|&b| neighbours[a][b])
                    .map(BodyState::slot)
                    .collect();
                r.extend(internal_rows[a].iter().cloned());
                r
            })
            .collect();
        let size = |a: usize| rows[a].iter().map(|r| r.len()).sum::<usize>();
        let mut order: Vec<usize> = (0..n_bodies).collect();
        order.sort_by_key(|&a| std::cmp::Reverse(size(a)));
        let mut colors: Vec<(Vec<usize>, Vec<bool>)> = Vec::new();
        for a in order {
            let mut mine = vec![false; n];
            for r in &rows[a] {
                mine[r.clone()].iter_mut().for_each(|m| *m = true);
            }
            match colors
                .iter_mut()
                .find(|(_, taken)| !taken.iter().zip(&mine).any(|(t, m)| *t && *m))
            {
                Some((members, taken)) => {
                    members.push(a);
                    taken.iter_mut().zip(&mine).for_each(|(t, m)| *t |= *m);
                }
                None => colors.push((vec![a], mine)),
            }
        }
        if colors.len() == n_bodies {
            return Vec::new();
        }
        colors
            .into_iter()
            .map(|(members, _)| ColumnColor {
                members: members
                    .into_iter()
                    .map(|a| ColoredColumns {
                        columns: BodyState::slot(a),
                        rows: rows[a].clone(),
                    })
                    .collect(),
            })
            .collect()
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
        // Wheelsets in their axle frame (docs/reference/08-multibody.md
        // §8.1, "Wheelsets in their axle frame"), the other bodies in body axes.
        let n_ws = vehicle.wheelsets.len();
        for (k, body) in bodies.enumerate() {
            let f = if k < n_ws {
                axle_frame_derivatives
            } else {
                derivatives
            };
            f(
                body,
                &self.states[k],
                &self.wrenches[k],
                &g,
                &mut dydt[BodyState::slot(k)],
            );
        }
        self.imposed_power_w = 0.0;
        if self.settings.formulation.longitudinal_motion == LongitudinalMotion::Imposed {
            self.impose_longitudinal_motion(t, dydt)?;
        }
        let n = vehicle.body_state_len();
        if let Some(d) = dydt.get_mut(n..n + self.internal_rates.len()) {
            d.copy_from_slice(&self.internal_rates);
        }
        Ok(())
    }

    fn accept(&mut self, t: f64, y: &[f64]) -> Result<Control, DynamicsError> {
        // The last rhs call was at this state: its hysteresis memory is the
        // one to keep, and its wheelsets' contacts are the ones Jacobian
        // columns at this state reuse.
        self.memory.clone_from(&self.pending);
        let n_ws = self.vehicle.wheelsets.len();
        self.accepted_parts.clear();
        self.accepted_parts.extend((0..n_ws).map(|i| WheelsetPart {
            state: self.states[i],
            anchor: self.anchors[i],
            wrench: self.contact_wrenches[i],
        }));
        self.accepted_element_forces
            .clone_from(&self.element_forces);
        self.accepted.t_s = t;
        self.accepted.y.clear();
        self.accepted.y.extend_from_slice(y);
        self.accepted.current = true;
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
            let e_el = self.non_gradient_elastic_energy_j();
            if let Some(l) = &mut self.ledger {
                l.add(t, p, e, e_el);
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

    /// One dense block (the primary suspensions couple wheelsets and
    /// frames as stiffly as the contacts; docs/reference/08-multibody.md
    /// §8.5), with every body's position and orientation rows eliminated
    /// from the solves: their derivative is the body's own velocity and
    /// angular velocity ([`crate::integrators::kinematic`]).
    fn jacobian_blocks(&self, n: usize) -> JacobianBlocks {
        let bodies = self.vehicle.wheelsets.len() + self.vehicle.bodies.len();
        let kinematics = (0..bodies)
            .map(|k| {
                let slot = BodyState::slot(k);
                KinematicBlock {
                    positions: slot.start..slot.start + BodyState::VELOCITY_OFFSET,
                    velocities: slot.start + BodyState::VELOCITY_OFFSET..slot.end,
                }
            })
            .collect();
        JacobianBlocks {
            colors: self.column_colors(n),
            ..JacobianBlocks::dense_kinematic(n, kinematics)
        }
    }

    /// A Jacobian column at the accepted state: what the perturbed
    /// component cannot change is reused from the accepted state's
    /// evaluation — every other wheelset's contacts (a contact depends on
    /// its own wheelset's state and on time only) and every element with
    /// neither end on the perturbed body nor the perturbed internal state.
    /// A wheelset column solves that wheelset's contacts, a frame or car
    /// body column none. Bit for bit the accepted state's forces, which a
    /// new evaluation would reproduce to the contact solver's tolerance.
    fn rhs_column(
        &mut self,
        t: f64,
        y: &[f64],
        changed: &[usize],
        dydt: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let n_ws = self.vehicle.wheelsets.len();
        let n_body_states = self.vehicle.body_state_len();
        let at_accepted = t == self.accepted.t_s
            && y.len() == self.accepted.y.len()
            && changed.iter().all(|&c| c < y.len())
            && self.accepted_parts.len() == n_ws
            && self.accepted_element_forces.len() == self.elements.len()
            && y.iter()
                .zip(&self.accepted.y)
                .enumerate()
                .all(|(i, (a, b))| a == b || changed.contains(&i));
        if at_accepted {
            // Bodies by bit; one internal state at most (else a full
            // evaluation).
            let mut column = Some(ColumnPerturbation {
                bodies: 0,
                internal: None,
            });
            for &c in changed {
                let Some(p) = column.as_mut() else { break };
                if c < n_body_states && c / BodyState::LEN < 64 {
                    p.bodies |= 1 << (c / BodyState::LEN);
                } else if c >= n_body_states && p.internal.is_none() {
                    p.internal = Some(c - n_body_states);
                } else {
                    column = None;
                }
            }
            self.column = column;
        }
        let result = self.rhs(t, y, dydt);
        self.column = None;
        result
    }

    /// Which contact candidates touch, and in which zone, at the accepted
    /// state, against the previous call's (the stiff integrator renews its
    /// Jacobian where it changed).
    fn structure_changed(&mut self) -> bool {
        let first = self.contact_pattern.is_empty();
        let mut changed = false;
        let mut k = 0;
        for snap in &self.snapshots {
            for c in snap.contacts.candidates.iter().flatten() {
                let code = match c {
                    Some(c) if c.in_contact() && c.zone == Zone::Flange => 2u8,
                    Some(c) if c.in_contact() => 1,
                    _ => 0,
                };
                if first {
                    self.contact_pattern.push(code);
                } else if self.contact_pattern[k] != code {
                    self.contact_pattern[k] = code;
                    changed = true;
                }
                k += 1;
            }
        }
        changed
    }
}
