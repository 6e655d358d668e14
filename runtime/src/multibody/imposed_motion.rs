//! The imposed longitudinal motion of [`LongitudinalMotion::Imposed`]
//! (docs/guide/cooperrider-cross-code.md, "Audit": the published
//! Cooperrider formulation has no longitudinal degree of freedom).

use super::body::BodyState;
use super::error::DynamicsError;
#[cfg(doc)]
use super::formulation::LongitudinalMotion;
use super::system::VehicleSystem;
use super::track_motion::{project_s, track_rotation};

/// Half-width of the central difference of the references' speed (s): the
/// schedule is piecewise linear, so dV/dt is exact except within this of a
/// knot (where it is the mean of the two slopes).
const SPEED_RATE_DT_S: f64 = 1e-6;

impl VehicleSystem<'_> {
    /// Replaces the tangential component of every body's centre-of-mass
    /// acceleration in `dydt` by the references' dV/dt at `t`
    /// ([`LongitudinalMotion::Imposed`]), the tangent that of the track at
    /// the body's projection. The constraint's power is kept for the energy
    /// ledger, booked with the references' work (docs/reference/08-multibody.md §8.6).
    pub(super) fn impose_longitudinal_motion(
        &mut self,
        t: f64,
        dydt: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let t0 = (t - SPEED_RATE_DT_S).max(0.0);
        let t1 = t + SPEED_RATE_DT_S;
        let rate_m_s2 = (self.speed_at_m_s(t1) - self.speed_at_m_s(t0)) / (t1 - t0);
        let c = &self.track().centerline;
        let vehicle = self.vehicle();
        let n_ws = vehicle.wheelsets.len();
        let s_vehicle = self.s_vehicle_m(t);
        let mut power_w = 0.0;
        for k in 0..n_ws + vehicle.bodies.len() {
            let track_error = |source| DynamicsError::Track {
                what: if k < n_ws {
                    format!("wheelset '{}'", vehicle.wheelsets[k].name)
                } else {
                    format!("body '{}'", vehicle.bodies[k - n_ws].name)
                },
                t_s: t,
                source,
            };
            // A wheelset's s is the one `evaluate` projected for this state;
            // a body is projected from its nominal station.
            let (s, mass_kg) = if k < n_ws {
                (self.s_guess[k], vehicle.wheelsets[k].body.mass_kg)
            } else {
                let b = &vehicle.bodies[k - n_ws];
                let position = self.states[k].position_m;
                let s = project_s(c, &position, s_vehicle + b.cg_m.x).map_err(track_error)?;
                (s, b.body.mass_kg)
            };
            let tangent = track_rotation(c, s)
                .map_err(track_error)?
                .column(0)
                .into_owned();
            let slot = &mut dydt[BodyState::slot(k)];
            let mut accel = nalgebra::Vector3::new(slot[7], slot[8], slot[9]);
            // The constraint's force along the tangent, m (dV/dt − a_t),
            // and its power on the body's velocity.
            let constraint_n = mass_kg * (rate_m_s2 - accel.dot(&tangent));
            power_w += constraint_n * self.states[k].velocity_m_s.dot(&tangent);
            accel += tangent * (constraint_n / mass_kg);
            slot[7..10].copy_from_slice(accel.as_slice());
        }
        self.imposed_power_w = power_w;
        Ok(())
    }
}
