//! Settings of a run that the vehicle system needs (how contact is found,
//! speed and its ramp, axle torques, start, derailment limit, gravity),
//! their validation, and the wheelsets' initial conditions (paper §5;
//! docs/reference/08-multibody.md §8).

use std::sync::Arc;

use super::error::DynamicsError;
use super::imported_contact::ImportedContactMethod;
use super::speed_profile::{SpeedKnot, SpeedProfile, SpeedSchedule};
use super::track_motion::SpeedRamp;
use crate::contact::ContactOptions;
use crate::contact::table::ContactTable;
use crate::multibody::contact_force::ContactForceSettings;

/// Rim speed (m/s) below which the friction brake's torque
/// ([`SystemSettings::axle_brake_torque_nm`]) is proportional to the spin
/// (regularised Coulomb friction; exact Coulomb friction, a set-valued
/// torque at Ω = 0, has no ODE form). Below it the brake is a rotary
/// damper c = T_b r₀/v_ε; its time constant on a wheelset,
/// (I_spin + m r₀²) v_ε/(T_b r₀), is 0.8 ms for the ML95-like wheelset
/// braked at 1 kN·m — far slower than the creep forces at standstill
/// (`crate::forces::creepage`, ~10 µs), so it does not limit the step, and a
/// wheelset stops within a few of them instead of creeping to rest.
pub const BRAKE_STICK_SPEED_M_S: f64 = 1e-3;

/// Standard gravity (m/s²), docs/reference/01-units-frames.md §1.
pub const GRAVITY_M_S2: f64 = 9.81;

/// How the contact geometry is found at each evaluation: the run's choice,
/// made into one [`super::ContactSource`] per wheelset at assembly
/// ([`ContactMethod::sources`]).
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
    /// A piecewise-linear speed schedule of the references instead of the
    /// ramp ([`SpeedSchedule`]): knots (t s, V m/s), the first at t = 0
    /// with V = `speed_m_s`, t strictly increasing, V finite and ≥ 0; the
    /// last speed is held. Exclusive with `deceleration_m_s2`,
    /// `acceleration_m_s2` and `final_speed_m_s`.
    pub speed_profile: Option<Vec<SpeedKnot>>,
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
    /// Switchable choices of the equations of motion (ours by default;
    /// [`super::formulation`]).
    pub formulation: super::formulation::Formulation,
    /// Flangeway clearance of every wheelset towards [left, right] (m, ≥ 0;
    /// `None` where the flange does not touch), in vehicle order, as
    /// `crate::contact::quasi_static::flange_clearance_m` gives it for the
    /// wheelset's contact model: the caller's cached sweep. Used with the
    /// flange search `auto` only; `None` (the default): assembly sweeps
    /// (identical wheelsets once), about 0.1 s per contact model.
    pub flange_clearances_m: Option<Vec<FlangeClearances>>,
}

/// The flangeway clearances of one wheelset, [left, right] (m; `None`
/// where the flange does not touch; [`SystemSettings::flange_clearances_m`]).
pub type FlangeClearances = [Option<f64>; 2];

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
            speed_profile: None,
            axle_torque_nm: 0.0,
            axle_brake_torque_nm: 0.0,
            s_start_m: 5.0,
            derailment_lateral_m: 0.05,
            gravity_m_s2: GRAVITY_M_S2,
            formulation: Default::default(),
            flange_clearances_m: None,
        }
    }
}

impl SystemSettings {
    /// The references' speed against time: the schedule of
    /// `speed_profile` if given, else the ramp from V0 = `speed_m_s` at the
    /// rate `acceleration_m_s2 − deceleration_m_s2` to `final_speed_m_s`.
    pub fn speed_profile(&self) -> SpeedProfile {
        match &self.speed_profile {
            Some(knots) => SpeedProfile::Schedule(SpeedSchedule::new(knots.clone())),
            None => SpeedProfile::Ramp(SpeedRamp {
                initial_m_s: self.speed_m_s,
                rate_m_s2: self.acceleration_m_s2 - self.deceleration_m_s2,
                final_m_s: self.final_speed_m_s,
            }),
        }
    }

    /// Checks the knots of `speed_profile` (struct docs), naming the rule.
    fn validate_schedule(&self, knots: &[SpeedKnot]) -> Result<(), DynamicsError> {
        let bad = |setting, value, rule| {
            Err(DynamicsError::Setting {
                setting,
                value,
                rule,
            })
        };
        if self.acceleration_m_s2 != 0.0
            || self.deceleration_m_s2 != 0.0
            || self.final_speed_m_s.is_some()
        {
            return bad(
                "speed profile (knots)",
                knots.len() as f64,
                "give a speed profile or an acceleration, deceleration and final speed, not both",
            );
        }
        let Some(first) = knots.first() else {
            return bad(
                "speed profile (knots)",
                0.0,
                "needs at least one knot [t_s, speed_m_s]",
            );
        };
        if first.t_s != 0.0 {
            return bad(
                "speed profile time (s)",
                first.t_s,
                "of the first knot must be 0",
            );
        }
        for (k, knot) in knots.iter().enumerate() {
            if !(knot.t_s.is_finite() && (k == 0 || knot.t_s > knots[k - 1].t_s)) {
                return bad(
                    "speed profile time (s)",
                    knot.t_s,
                    "must be finite and greater than the previous knot's (strictly increasing)",
                );
            }
            if !(knot.speed_m_s.is_finite() && knot.speed_m_s >= 0.0) {
                return bad(
                    "speed profile speed (m/s)",
                    knot.speed_m_s,
                    "must be finite and >= 0",
                );
            }
        }
        if self.speed_m_s != first.speed_m_s {
            return bad(
                "speed (m/s)",
                self.speed_m_s,
                "must equal the speed profile's first speed",
            );
        }
        Ok(())
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
        if let Some(knots) = &self.speed_profile {
            return self.validate_schedule(knots);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn knot(t_s: f64, speed_m_s: f64) -> SpeedKnot {
        SpeedKnot { t_s, speed_m_s }
    }

    /// The rule a schedule breaks, or "" when it is accepted.
    fn rule(speed_m_s: f64, knots: Vec<SpeedKnot>, edit: fn(&mut SystemSettings)) -> String {
        let mut s = SystemSettings {
            speed_m_s,
            speed_profile: Some(knots),
            ..SystemSettings::default()
        };
        edit(&mut s);
        match s.validate_motion() {
            Ok(()) => String::new(),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn a_speed_profile_is_checked_rule_by_rule() {
        let good = vec![knot(0.0, 20.0), knot(5.0, 20.0), knot(7.0, 19.0)];
        assert_eq!(rule(20.0, good.clone(), |_| {}), "");
        let s = SystemSettings {
            speed_m_s: 20.0,
            speed_profile: Some(good.clone()),
            ..SystemSettings::default()
        };
        assert!((s.speed_profile().distance_m(6.0) - 119.75).abs() < 1e-12);
        assert!(
            rule(20.0, good.clone(), |s| s.deceleration_m_s2 = 0.5).contains("not both"),
            "exclusive with a ramp"
        );
        assert!(rule(20.0, good.clone(), |s| s.final_speed_m_s = Some(3.0)).contains("not both"));
        assert!(rule(20.0, vec![], |_| {}).contains("at least one knot"));
        assert!(
            rule(20.0, vec![knot(1.0, 20.0)], |_| {})
                .contains("speed profile time (s) = 1: of the first knot must be 0")
        );
        assert!(
            rule(20.0, vec![knot(0.0, 20.0), knot(0.0, 10.0)], |_| {})
                .contains("strictly increasing")
        );
        assert!(
            rule(20.0, vec![knot(0.0, 20.0), knot(f64::NAN, 10.0)], |_| {})
                .contains("strictly increasing")
        );
        assert!(
            rule(20.0, vec![knot(0.0, 20.0), knot(1.0, -1.0)], |_| {})
                .contains("speed profile speed (m/s) = -1: must be finite and >= 0")
        );
        assert!(
            rule(25.0, good, |_| {})
                .contains("speed (m/s) = 25: must equal the speed profile's first speed")
        );
    }
}
