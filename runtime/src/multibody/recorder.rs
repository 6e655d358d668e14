//! Sampled outputs of a run (docs/reference/08-multibody.md §8 outputs; the data model is
//! [`crate::results`], which `crate::io::schema::write_results` writes to a
//! file): at every output time the system is evaluated at the
//! (interpolated) state and each wheelset's track-relative position and
//! each wheel's contacts are appended to a [`RunResults`]; each wheel's Nadal limit (its steepest flange angle and
//! the run's friction coefficient, [`crate::contact::nadal`]) is stored with
//! its Y/Q series. Every rigid body's track-relative state (position,
//! orientation, velocities, ride accelerations) is appended too
//! (`body_record`, [`crate::results::bodies`]).

use super::DynamicsError;
use super::body_record::{body_samples, body_series};
use super::system::{VehicleSystem, WheelsetSnapshot};
use super::track_motion::track_rotation;
use crate::contact::SolveMethod;
use crate::contact::nadal::NadalLimit;
use crate::geometry::profile::{MAX_SEGMENTS, Zone};
use crate::geometry::track::Side;
use crate::results::{
    FALLBACK_HERTZ_FLOOR, FALLBACK_MINIMISATION, RunResults, WheelSample, WheelsetSample,
    ZoneSample,
};

/// Collects the samples of a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Recorder {
    pub results: RunResults,
    /// Track distance of each wheelset and rail arc length of each wheel's
    /// contact at the first sample (m).
    origin: Option<Vec<(f64, [f64; 2])>>,
    /// Each body's track position at the last sample (m; NaN before the
    /// first), the guess of the next projection.
    body_s_m: Vec<f64>,
}

impl Recorder {
    /// An empty record for the vehicle's wheelsets.
    pub fn new(system: &VehicleSystem<'_>) -> Self {
        let mut results =
            RunResults::with_wheelsets(system.vehicle().wheelsets.iter().map(|w| w.name.clone()));
        let friction = system.settings().forces.friction_coefficient;
        for (series, spec) in results
            .wheelsets
            .iter_mut()
            .zip(&system.vehicle().wheelsets)
        {
            for side in Side::BOTH {
                series.wheels[side_index(side)].nadal =
                    NadalLimit::of_wheel(spec.contact.wheel(side), friction);
            }
        }
        let (bodies, car_body) = body_series(system);
        let body_s_m = vec![f64::NAN; bodies.len()];
        results.bodies = bodies;
        results.car_body = car_body;
        Recorder {
            results,
            origin: None,
            body_s_m,
        }
    }

    /// Evaluates the system at (t, y) and appends the sample. At an
    /// accepted state whose evaluation is still the last one
    /// ([`VehicleSystem::evaluated_at`]: the output times that fall on a
    /// step) that evaluation is used as it is: the same values without a
    /// second evaluation.
    pub fn record(
        &mut self,
        system: &mut VehicleSystem<'_>,
        t: f64,
        y: &[f64],
    ) -> Result<(), DynamicsError> {
        if !system.evaluated_at(t, y) {
            system.evaluate(t, y)?;
        }
        let track = system.track();
        let snapshots = system.snapshots();
        let wheel_l = |snap: &WheelsetSnapshot, side: Side| -> Result<f64, DynamicsError> {
            let k = side_index(side);
            if let Some(c) = main_contact(snap, k, Zone::Tread) {
                return Ok(c.0.params.s_rail_m);
            }
            track
                .centerline
                .rail_l(side, snap.relative.s_m)
                .map_err(|source| DynamicsError::Track {
                    what: "wheel travelled distance".into(),
                    t_s: t,
                    source,
                })
        };
        if self.origin.is_none() {
            let mut o = Vec::new();
            for snap in snapshots {
                o.push((
                    snap.relative.s_m,
                    [wheel_l(snap, Side::Left)?, wheel_l(snap, Side::Right)?],
                ));
            }
            self.origin = Some(o);
        }
        let origin = self.origin.as_ref().expect("set above");
        let mut samples = Vec::with_capacity(snapshots.len());
        for (snap, (s0, l0)) in snapshots.iter().zip(origin) {
            let r = &snap.relative;
            let frame = track_rotation(&track.centerline, r.s_m).map_err(|source| {
                DynamicsError::Track {
                    what: "recording".into(),
                    t_s: t,
                    source,
                }
            })?;
            let (n, b) = (frame.column(1), frame.column(2));
            let mut wheels = [WheelSample::default(); 2];
            for side in Side::BOTH {
                let k = side_index(side);
                let mut zones = [ZoneSample::NO_CONTACT; 2];
                for (z, zone) in [Zone::Tread, Zone::Flange].into_iter().enumerate() {
                    let Some((c, f)) = main_contact(snap, k, zone) else {
                        continue;
                    };
                    // Forces of every piece of the zone in contact.
                    let mut lateral = 0.0;
                    let mut vertical = 0.0;
                    let mut normal = 0.0;
                    for seg in 0..MAX_SEGMENTS {
                        if let (Some(cc), Some(ff)) =
                            (&snap.contacts.candidates[k][seg], &snap.forces[k][seg])
                            && cc.zone == zone
                        {
                            lateral += ff.force_on_wheel_n.dot(&n);
                            vertical += ff.force_on_wheel_n.dot(&b);
                            normal += ff.normal.force_n;
                        }
                    }
                    let cr = &f.tangential.creepages;
                    zones[z] = ZoneSample {
                        in_contact: true,
                        normal_n: normal,
                        fx_n: f.tangential.creep.fx_n,
                        fy_n: f.tangential.creep.fy_n,
                        mz_nm: f.tangential.creep.mz_nm,
                        lateral_force_n: lateral,
                        vertical_force_n: vertical,
                        xi: cr.xi,
                        eta: cr.eta,
                        phi_1_m: cr.phi_1_m,
                        y_wheel_m: c.wheel_profile_point_m.0,
                        y_rail_m: c.rail_profile_point_m.0,
                        contact_angle_rad: c.contact_angle_rad,
                        lead_m: c.lead_m(),
                        fallback: zone_fallbacks(snap, k, zone),
                    };
                }
                wheels[k] = WheelSample {
                    travelled_m: wheel_l(snap, side)? - l0[k],
                    zones,
                };
            }
            samples.push(WheelsetSample {
                lateral_m: r.lateral_m,
                yaw_rad: r.yaw_rad,
                roll_rad: r.roll_rad,
                distance_m: r.s_m - s0,
                speed_m_s: r.forward_speed_m_s,
                track_s_m: r.s_m,
                wheels,
            });
        }
        let bodies = body_samples(system, t, &mut self.body_s_m)?;
        self.results
            .push_sample(t, &samples, &bodies)
            .map_err(|e| DynamicsError::Assembly {
                wheelset: "(recorder)".into(),
                reason: e.to_string(),
            })
    }
}

fn side_index(side: Side) -> usize {
    match side {
        Side::Left => 0,
        Side::Right => 1,
    }
}

/// The fallback bits ([`FALLBACK_MINIMISATION`], [`FALLBACK_HERTZ_FLOOR`])
/// of the zone's pieces in contact.
fn zone_fallbacks(snap: &WheelsetSnapshot, k: usize, zone: Zone) -> u8 {
    let mut bits = 0;
    for seg in 0..MAX_SEGMENTS {
        if let (Some(c), Some(f)) = (&snap.contacts.candidates[k][seg], &snap.forces[k][seg])
            && c.zone == zone
        {
            if c.method == SolveMethod::Minimisation {
                bits |= FALLBACK_MINIMISATION;
            }
            if f.hertz_fallback {
                bits |= FALLBACK_HERTZ_FLOOR;
            }
        }
    }
    bits
}

/// The zone's piece in contact carrying the largest normal force (by
/// reference: the records are hundreds of bytes).
fn main_contact(
    snap: &WheelsetSnapshot,
    k: usize,
    zone: Zone,
) -> Option<(
    &crate::contact::Candidate,
    &crate::multibody::contact_force::ContactForce,
)> {
    (0..MAX_SEGMENTS)
        .filter_map(
            |seg| match (&snap.contacts.candidates[k][seg], &snap.forces[k][seg]) {
                (Some(c), Some(f)) if c.zone == zone => Some((c, f)),
                _ => None,
            },
        )
        .max_by(|a, b| a.1.normal.force_n.total_cmp(&b.1.normal.force_n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::vehicles::ShippedVehicle;
    use crate::integrators::{
        IntegrationStats, Method, OdeSystem, OutputGrid, Rk4, Rosenbrock, integrate,
    };
    use crate::multibody::InitialConditions;

    /// RK4 step (s): 2⁻¹¹ s, about 0.5 ms, so that the grid times below are
    /// exact in binary and fall on the steps bit for bit.
    const H_S: f64 = 1.0 / 2048.0;

    /// `method` from 0 to `t_end_s` on the ML95-like wheelset, 1 mm off
    /// centre, with an output every `interval_s`: the system's evaluation
    /// count, the samples and the integrator's counters.
    fn run_with(method: &Method, t_end_s: f64, interval_s: f64) -> (u64, usize, IntegrationStats) {
        let which = ShippedVehicle::Ml95Wheelset;
        let (vehicle, track) = which.build().expect("the shipped profiles");
        let initial = InitialConditions {
            lateral_m: 0.001,
            yaw_rad: 0.0,
        };
        let (mut system, y0) =
            VehicleSystem::assemble(&track, &vehicle, which.settings(20.0), initial)
                .expect("assembles");
        let mut recorder = Recorder::new(&system);
        let stats = integrate(
            method,
            &mut system,
            0.0,
            &y0,
            t_end_s,
            &OutputGrid { interval_s },
            &mut |sys, t, y| recorder.record(sys, t, y),
        )
        .expect("integrates");
        (system.counters().evaluations, recorder.results.len(), stats)
    }

    /// RK4 over `steps` steps of [`H_S`] with an output every
    /// `interval_s`: the system's evaluation count and the samples.
    fn run(interval_s: f64, steps: u32) -> (u64, usize) {
        let rk4 = Method::Rk4(Rk4 { step_s: H_S });
        let (evaluations, samples, _) = run_with(&rk4, f64::from(steps) * H_S, interval_s);
        (evaluations, samples)
    }

    /// Samples at accepted states (the output grid on the steps) cost no
    /// evaluation; samples between steps are evaluated.
    #[test]
    fn samples_at_accepted_states_reuse_their_evaluation() {
        let steps = 8;
        // RK4: one evaluation at the start, four per step.
        let integrator_evaluations = 1 + 4 * u64::from(steps);
        let (evaluations, samples) = run(2.0 * H_S, steps);
        assert_eq!(samples, 5);
        assert_eq!(evaluations, integrator_evaluations);
        // Every 1.5 steps: 0, 1.5, 3, 4.5, 6, 7.5 and the final 8 steps;
        // 1.5, 4.5 and 7.5 fall between steps, and the final state comes
        // after the evaluation at 7.5 (no longer the last one): 4.
        let (evaluations, samples) = run(1.5 * H_S, steps);
        assert_eq!(samples, 7);
        assert_eq!(evaluations, integrator_evaluations + 4);
    }

    /// Rosenbrock steps capped by `max_step_s` end on the output times
    /// they would pass (`integrators::rosenbrock`, "Steps on the output
    /// grid"), so the samples are steps' ends and cost no evaluation of
    /// their own.
    #[test]
    fn capped_rosenbrock_steps_end_on_the_output_times() {
        // Steps capped at 0.25 ms (the error control asks for more),
        // samples every 1 ms: every fourth step ends on one.
        let method = Method::Rosenbrock(Rosenbrock {
            max_step_s: 2.5e-4,
            ..Rosenbrock::default()
        });
        let (evaluations, samples, stats) = run_with(&method, 0.05, 1e-3);
        assert_eq!(samples, 51);
        assert!(stats.steps >= 200, "{} steps", stats.steps);
        assert_eq!(
            evaluations, stats.rhs_evaluations,
            "every sample at a step's end"
        );
    }

    /// The last accepted state's evaluation is current until the next
    /// evaluation, and only for that state, bit for bit.
    #[test]
    fn evaluated_at_holds_until_the_next_evaluation() {
        let which = ShippedVehicle::Ml95Wheelset;
        let (vehicle, track) = which.build().expect("the shipped profiles");
        let (mut system, y0) = VehicleSystem::assemble(
            &track,
            &vehicle,
            which.settings(20.0),
            InitialConditions::default(),
        )
        .expect("assembles");
        let mut dydt = vec![0.0; y0.len()];
        assert!(!system.evaluated_at(0.0, &y0));
        system.rhs(0.0, &y0, &mut dydt).expect("evaluates");
        assert!(!system.evaluated_at(0.0, &y0), "not accepted yet");
        system.accept(0.0, &y0).expect("accepts");
        assert!(system.evaluated_at(0.0, &y0));
        assert!(!system.evaluated_at(1e-9, &y0));
        let mut y1 = y0.clone();
        y1[1] = f64::from_bits(y1[1].to_bits() + 1);
        assert!(!system.evaluated_at(0.0, &y1));
        system.evaluate(0.0, &y0).expect("evaluates");
        assert!(!system.evaluated_at(0.0, &y0), "evaluated since");
    }
}
