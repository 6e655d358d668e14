//! Settings of a run that the vehicle system needs (how contact is found,
//! speed and its ramp, axle torques, start, derailment limit, gravity),
//! their validation, and the wheelsets' initial conditions (paper §5;
//! docs/reference/08-multibody.md §8).

use std::sync::Arc;

use super::error::DynamicsError;
use super::imported_contact::ImportedContactMethod;
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
            formulation: Default::default(),
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
