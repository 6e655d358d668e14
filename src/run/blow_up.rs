//! Numerical blow-up or derailment? A run stops when a wheelset's |y|
//! passes the derailment limit, when a contact cannot be solved or a
//! state is not finite — and an integration running away (a step too large
//! for the contact's stiffness, a modulus in the wrong unit) ends the same
//! ways. The failing state tells them apart
//! (docs/guide/extremes-and-diagnostics.md, "Blow-up or derailment"):
//! each of these is a sign of a numerical blow-up, not of a wheel
//! climbing its rail —
//!
//! - a state or derivative that is not finite;
//! - the wheelset centre more than [`MAX_LIFT_FLANGE_DEPTHS`] flange depths
//!   above its rolling height (a climbing wheel lifts the centre by about
//!   half its flange depth: the wheelset rolls about the other wheel's
//!   contact), or more than one flange depth below it (the wheels sunk
//!   into their rails);
//! - a roll beyond [`MAX_CLIMB_ROLL_RAD`] relative to the track;
//! - a change of forward speed since the last sample above
//!   [`MAX_FORWARD_ACCELERATION_M_S2`] (and [`MIN_SPEED_JUMP_M_S`]);
//! - an energy balance broken at the last accepted state: its residual
//!   above [`crate::run::warnings::ENERGY_RESIDUAL_WARN_FRACTION`] of its
//!   largest term (a derailment keeps the balance: the energy goes where
//!   the forces take it).
//!
//! The diagnostic then names the blow-up and its likely cause (the step,
//! the contact's stiffness, a unit) instead of "derailed".

use crate::run::diagnostics::WheelsetState;
use crate::run::summary::EnergySummary;
use crate::run::warnings::{ENERGY_RESIDUAL_WARN_FRACTION, energy_residual_excess};

/// Largest roll relative to the track (rad) of a wheelset climbing its
/// flange: a wheel lifted by its whole flange depth (about 30 mm) over the
/// 1.5 m between the contacts rolls it by 0.02 rad; five times that is no
/// climb.
pub const MAX_CLIMB_ROLL_RAD: f64 = 0.1;

/// Largest lift of the wheelset centre above its rolling height, in flange
/// depths: a climb lifts it by about half of one (module docs).
pub const MAX_LIFT_FLANGE_DEPTHS: f64 = 2.0;

/// Largest change of forward speed per second between the last sample and
/// the failing state (m/s²): 10 g. Traction, braking and impacts stay
/// below 1 g along the track.
pub const MAX_FORWARD_ACCELERATION_M_S2: f64 = 98.1;

/// Changes of forward speed below this (m/s) are not judged (a failing
/// state right after a sample makes any change look fast).
pub const MIN_SPEED_JUMP_M_S: f64 = 1.0;

/// What a wheelset's failing state is compared with.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelsetReference {
    pub name: String,
    /// Nominal rolling radius (m): the centre's height above the rail tops
    /// rolling centred.
    pub rolling_height_m: f64,
    /// Depth of the deeper flange below its taping line (m); 0 without.
    pub flange_depth_m: f64,
    /// Time (s) and forward speed (m/s) at the last recorded sample.
    pub last_sample: Option<(f64, f64)>,
}

/// The signs of a numerical blow-up (module docs) in the wheelsets'
/// `states` at `t_s` (a wheelset whose state is unavailable was not
/// finite or left the tables: `missing`), and in the energy balance at the
/// last accepted state; empty when none.
pub fn blow_up_signs(
    t_s: f64,
    states: &[WheelsetState],
    missing: &[String],
    references: &[WheelsetReference],
    energy: Option<&EnergySummary>,
) -> Vec<String> {
    let mut signs = Vec::new();
    for name in missing {
        signs.push(format!(
            "the state of wheelset '{name}' is not finite or off the track"
        ));
    }
    for st in states {
        let Some(r) = references.iter().find(|r| r.name == st.name) else {
            continue;
        };
        let lift_m = st.height_mm * 1e-3 - r.rolling_height_m;
        if r.flange_depth_m > 0.0 && lift_m > MAX_LIFT_FLANGE_DEPTHS * r.flange_depth_m {
            signs.push(format!(
                "wheelset '{}' is {:.1} mm above its rolling height, more than {MAX_LIFT_FLANGE_DEPTHS} × its flange depth of {:.1} mm: no flange climb lifts it so",
                st.name,
                lift_m * 1e3,
                r.flange_depth_m * 1e3
            ));
        }
        if r.flange_depth_m > 0.0 && lift_m < -r.flange_depth_m {
            signs.push(format!(
                "wheelset '{}' is {:.1} mm below its rolling height, more than its flange depth of {:.1} mm: the wheels sank into the rails (a contact far too soft: check [contact] young_pa)",
                st.name,
                -lift_m * 1e3,
                r.flange_depth_m * 1e3
            ));
        }
        if st.roll_mrad.abs() * 1e-3 > MAX_CLIMB_ROLL_RAD {
            signs.push(format!(
                "wheelset '{}' rolled {:+.1} mrad, beyond the {:.0} mrad of a flange climb",
                st.name,
                st.roll_mrad,
                MAX_CLIMB_ROLL_RAD * 1e3
            ));
        }
        if let Some((t0, v0)) = r.last_sample {
            let dv = st.forward_speed_m_s - v0;
            let dt = t_s - t0;
            if dv.abs() > MIN_SPEED_JUMP_M_S
                && (dt <= 0.0 || dv.abs() / dt > MAX_FORWARD_ACCELERATION_M_S2)
            {
                signs.push(format!(
                    "wheelset '{}' went from {v0:.3} to {:.3} m/s along the track in {dt:.2e} s (more than {:.0} m/s², 10 g)",
                    st.name, st.forward_speed_m_s, MAX_FORWARD_ACCELERATION_M_S2
                ));
            }
        }
    }
    if let Some(e) = energy
        && let Some(fraction) = energy_residual_excess(e)
    {
        signs.push(format!(
            "the energy balance was broken before the failure: residual {:.3} J, {:.0} % of its largest term (above {} %)",
            e.residual_j,
            100.0 * fraction,
            100.0 * ENERGY_RESIDUAL_WARN_FRACTION
        ));
    }
    signs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(height_mm: f64, roll_mrad: f64, forward_speed_m_s: f64) -> WheelsetState {
        WheelsetState {
            name: "wheelset".into(),
            s_m: 7.0,
            lateral_mm: -50.6,
            yaw_mrad: 4.5,
            roll_mrad,
            height_mm,
            forward_speed_m_s,
            lateral_speed_m_s: -0.26,
        }
    }

    fn reference() -> WheelsetReference {
        WheelsetReference {
            name: "wheelset".into(),
            rolling_height_m: 0.43,
            flange_depth_m: 0.028,
            last_sample: Some((0.21, 9.7)),
        }
    }

    #[test]
    fn a_flange_climb_shows_no_sign() {
        // The climb of tests/extremes/contact.rs: centre 13 mm up, roll 21 mrad.
        let s = blow_up_signs(
            0.2036,
            &[state(443.1, 21.0, 9.7)],
            &[],
            &[reference()],
            None,
        );
        assert!(s.is_empty(), "{s:?}");
    }

    #[test]
    fn a_runaway_state_shows_its_signs() {
        // RK4 at 10 ms on the wheelset: |y| passes 50 mm rolled 544 mrad,
        // the centre 405 mm up.
        let s = blow_up_signs(
            0.215,
            &[state(834.8, 544.0, 9.6)],
            &[],
            &[reference()],
            None,
        );
        assert_eq!(s.len(), 2, "{s:?}");
        assert!(s[0].contains("above its rolling height"), "{}", s[0]);
        assert!(s[1].contains("rolled +544.0 mrad"), "{}", s[1]);
        // E = 1e30 Pa: 1052 m/s a step after 10 m/s.
        let mut r = reference();
        r.last_sample = Some((0.0, 10.0));
        let s = blow_up_signs(3e-4, &[state(431.0, 1.0, 1052.7)], &[], &[r], None);
        assert!(s[0].contains("from 10.000 to 1052.700 m/s"), "{s:?}");
        // A soft contact sinks the wheels.
        let s = blow_up_signs(0.1, &[state(300.0, 0.0, 9.7)], &[], &[reference()], None);
        assert!(s[0].contains("check [contact] young_pa"), "{s:?}");
        // A state that is not finite.
        let s = blow_up_signs(0.1, &[], &["front".into()], &[reference()], None);
        assert!(s[0].contains("not finite"), "{s:?}");
    }

    #[test]
    fn a_broken_energy_balance_is_a_sign() {
        let e = EnergySummary {
            initial_j: 1e5,
            final_j: 1.2e5,
            axle_torque_work_j: 0.0,
            reference_work_j: 0.0,
            creep_dissipation_j: 10.0,
            contact_damping_dissipation_j: 0.0,
            damper_dissipation_j: 0.0,
            element_turning_work_j: 0.0,
            contact_normal_work_j: 0.0,
            residual_j: 2e4 + 10.0,
        };
        let s = blow_up_signs(0.1, &[], &[], &[], Some(&e));
        assert!(s[0].contains("energy balance was broken"), "{s:?}");
    }
}
