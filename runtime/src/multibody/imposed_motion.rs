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
        let masses: Vec<f64> = vehicle
            .wheelsets
            .iter()
            .map(|w| w.body.mass_kg)
            .chain(vehicle.bodies.iter().map(|b| b.body.mass_kg))
            .collect();
        let mut power_w = 0.0;
        let guesses: Vec<(String, f64)> = vehicle
            .wheelsets
            .iter()
            .enumerate()
            .map(|(i, w)| (w.name.clone(), self.s_guess[i]))
            .chain(
                vehicle
                    .bodies
                    .iter()
                    .map(|b| (b.name.clone(), s_vehicle + b.cg_m.x)),
            )
            .collect();
        for (k, (name, guess)) in guesses.into_iter().enumerate() {
            let track_error = |source| DynamicsError::Track {
                what: if k < n_ws {
                    format!("wheelset '{name}'")
                } else {
                    format!("body '{name}'")
                },
                t_s: t,
                source,
            };
            let position = self.states[k].position_m;
            let s = project_s(c, &position, guess).map_err(track_error)?;
            let tangent = track_rotation(c, s)
                .map_err(track_error)?
                .column(0)
                .into_owned();
            let slot = &mut dydt[BodyState::slot(k)];
            let mut accel = nalgebra::Vector3::new(slot[7], slot[8], slot[9]);
            // The constraint's force along the tangent, m (dV/dt − a_t),
            // and its power on the body's velocity.
            let constraint_n = masses[k] * (rate_m_s2 - accel.dot(&tangent));
            power_w += constraint_n * self.states[k].velocity_m_s.dot(&tangent);
            accel += tangent * (rate_m_s2 - accel.dot(&tangent));
            slot[7..10].copy_from_slice(accel.as_slice());
        }
        self.imposed_power_w = power_w;
        Ok(())
    }
}
