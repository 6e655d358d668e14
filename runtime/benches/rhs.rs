//! Criterion bench: one full right-hand-side evaluation
//! (`OdeSystem::rhs` of `VehicleSystem`: contacts, forces, suspension,
//! Newton–Euler) and one RK4 step, for the shipped ML95-like wheelset, the
//! ML95-like bogie and the Cooperrider car (`runtime::fixtures::vehicles`,
//! checked against their files by tests/vehicle_fixtures.rs) on a straight
//! track at 20 m/s, online contact, flange `auto`.
//!
//! Warm contact: the system is assembled 1 mm off centre and evaluated
//! [`WARM_EVALUATIONS`] times at that state first, so the contact solver
//! starts from its last solution as in a run. One RK4 step is
//! `integrate` over one 0.5 ms step (the shipped scenes' step) with one
//! output interval: five evaluations (the initial state's, three stages,
//! the accepted state's), one accept and two observer calls (t0 and t1,
//! which do nothing), from a system already warm at y0.
//!
//! The same 0.1 s of motion (`span_0.1s/…`) with RK4 at 0.5 ms (200 steps)
//! and with the stiff Rosenbrock-W method at its defaults (its Jacobians
//! included; docs/reference/08-multibody.md §8.5): the cost per simulated
//! time the two integrators are compared by.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use runtime::fixtures::vehicles::ShippedVehicle;
use runtime::integrators::{Method, OdeSystem, OutputGrid, Rk4, Rosenbrock, integrate};
use runtime::multibody::{InitialConditions, VehicleSystem};

/// Evaluations at the start state before timing (contact solver warm).
const WARM_EVALUATIONS: usize = 5;
/// Speed of the runs (m/s).
const SPEED_M_S: f64 = 20.0;
/// Lateral offset of the start state (m).
const OFFSET_M: f64 = 0.001;
/// The shipped scenes' RK4 step (s).
const STEP_S: f64 = 5e-4;
/// The span of the integrator comparison (s).
const SPAN_S: f64 = 0.1;

fn bench(c: &mut Criterion) {
    for which in ShippedVehicle::ALL {
        let (vehicle, track) = which.build().expect("the shipped profiles");
        let (mut system, y0) = VehicleSystem::assemble(
            &track,
            &vehicle,
            which.settings(SPEED_M_S),
            InitialConditions {
                lateral_m: OFFSET_M,
                yaw_rad: 0.0,
            },
        )
        .expect("assembles");
        let mut dydt = vec![0.0; y0.len()];
        for _ in 0..WARM_EVALUATIONS {
            system.rhs(0.0, &y0, &mut dydt).expect("evaluates");
        }
        c.bench_function(&format!("rhs/{}", which.name()), |b| {
            b.iter(|| {
                system
                    .rhs(0.0, black_box(&y0), &mut dydt)
                    .expect("evaluates");
                black_box(dydt[0])
            })
        });
        let method = Method::Rk4(Rk4 { step_s: STEP_S });
        c.bench_function(&format!("rk4_step/{}", which.name()), |b| {
            b.iter(|| {
                integrate(
                    &method,
                    &mut system,
                    0.0,
                    black_box(&y0),
                    STEP_S,
                    &OutputGrid { interval_s: STEP_S },
                    &mut |_, _, y| {
                        black_box(y[0]);
                        Ok(())
                    },
                )
                .expect("one step")
            })
        });
        for (name, method) in [
            ("rk4_0.5ms", Method::Rk4(Rk4 { step_s: STEP_S })),
            ("rosenbrock", Method::Rosenbrock(Rosenbrock::default())),
        ] {
            c.bench_function(&format!("span_0.1s/{name}/{}", which.name()), |b| {
                b.iter(|| {
                    integrate(
                        &method,
                        &mut system,
                        0.0,
                        black_box(&y0),
                        SPAN_S,
                        &OutputGrid { interval_s: SPAN_S },
                        &mut |_, _, y| {
                            black_box(y[0]);
                            Ok(())
                        },
                    )
                    .expect("0.1 s")
                })
            });
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
