//! A shipped vehicle of `runtime::fixtures::vehicles` (the ML95-like bogie
//! by default) on its straight at 20 m/s, 1 mm off centre, online contact,
//! flange `auto` (arguments: `[bogie|car|wheelset] [span_s] [speed_m_s]
//! [atol] [offset_m]`), integrated by
//! - RK4 at 0.1 ms (the reference),
//! - our Rosenbrock-W ROS34PW2 at its defaults (atol 5e-6 or the argument),
//! - diffsol's BDF and ESDIRK34 at the same tolerances (rtol 1e-9, atol
//!   5e-6 or the argument), the right-hand side's Jacobian–vector product by a forward
//!   difference (the same increment as ours), the accept protocol kept:
//!   after each diffsol step the accepted state is evaluated and committed
//!   (`OdeSystem::accept`).
//! Prints the wall time of the integration, the right-hand sides and the largest lateral
//! displacement difference against the reference at the output times.

use std::cell::RefCell;
use std::time::Instant;

use diffsol::{NalgebraLU, NalgebraMat, OdeBuilder, OdeSolverMethod, Vector};
use runtime::fixtures::vehicles::ShippedVehicle;
use runtime::integrators::{Method, OdeSystem, OutputGrid, Rk4, Rosenbrock, integrate};
use runtime::multibody::{InitialConditions, VehicleSystem};

const SPEED_M_S: f64 = 20.0;
const OFFSET_M: f64 = 0.001;
const OUTPUT_S: f64 = 0.01;
const ATOL: f64 = 5e-6;
const RTOL: f64 = 1e-9;

/// `[bogie|car|wheelset] [span_s] [speed_m_s] [atol] [offset_m]` from the
/// command line.
fn arg(k: usize) -> Option<String> {
    std::env::args().nth(k)
}
fn vehicle_choice() -> ShippedVehicle {
    match arg(1).as_deref() {
        Some("car") => ShippedVehicle::CooperriderCar,
        Some("wheelset") => ShippedVehicle::Ml95Wheelset,
        _ => ShippedVehicle::Ml95Bogie,
    }
}
fn span_s() -> f64 {
    arg(2).and_then(|s| s.parse().ok()).unwrap_or(2.0)
}
fn offset_m() -> f64 {
    arg(5).and_then(|s| s.parse().ok()).unwrap_or(OFFSET_M)
}
fn atol() -> f64 {
    arg(4).and_then(|s| s.parse().ok()).unwrap_or(ATOL)
}
fn speed() -> f64 {
    arg(3).and_then(|s| s.parse().ok()).unwrap_or(SPEED_M_S)
}

fn system_and_state<'a>(
    track: &'a runtime::geometry::track::TrackTables,
    vehicle: &'a runtime::multibody::VehicleModel,
) -> (VehicleSystem<'a>, Vec<f64>) {
    VehicleSystem::assemble(
        track,
        vehicle,
        vehicle_choice().settings(speed()),
        InitialConditions {
            lateral_m: offset_m(),
            yaw_rad: 0.0,
        },
    )
    .expect("assembles")
}

/// Lateral displacement of every wheelset at (t, y) (m).
fn laterals(system: &mut VehicleSystem<'_>, t: f64, y: &[f64]) -> Vec<f64> {
    let mut dydt = vec![0.0; y.len()];
    system.rhs(t, y, &mut dydt).expect("evaluates");
    system
        .snapshots()
        .iter()
        .map(|s| s.relative.lateral_m)
        .collect()
}

/// [`laterals`] at every sampled (t, y).
fn sampled_laterals(system: &mut VehicleSystem<'_>, samples: &[(f64, Vec<f64>)]) -> Vec<Vec<f64>> {
    samples
        .iter()
        .map(|(t, y)| laterals(system, *t, y))
        .collect()
}

fn ours(method: Method, name: &str, reference: Option<&[Vec<f64>]>) -> Vec<Vec<f64>> {
    let which = vehicle_choice();
    let (vehicle, track) = which.build().expect("profiles");
    let (mut system, y0) = system_and_state(&track, &vehicle);
    let mut out: Vec<(f64, Vec<f64>)> = Vec::new();
    let start = Instant::now();
    let stats = integrate(
        &method,
        &mut system,
        0.0,
        &y0,
        span_s(),
        &OutputGrid {
            interval_s: OUTPUT_S,
        },
        &mut |_, t, y| {
            out.push((t, y.to_vec()));
            Ok(())
        },
    )
    .expect("integrates");
    let wall_s = start.elapsed().as_secs_f64();
    let evaluations = system.counters();
    let lat = sampled_laterals(&mut system, &out);
    report(
        name,
        wall_s,
        &format!("{stats:?} {evaluations:?}"),
        &lat,
        reference,
    );
    lat
}

fn report(name: &str, wall_s: f64, counts: &str, lat: &[Vec<f64>], reference: Option<&[Vec<f64>]>) {
    let err = reference.map(|r| {
        r.iter()
            .zip(lat)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
            .fold(0.0_f64, f64::max)
    });
    println!(
        "{name}: {wall_s:.3} s wall, lateral error {} µm, {} samples\n    {counts}",
        err.map_or("-".into(), |e| format!("{:.3}", e * 1e6)),
        lat.len()
    );
}

#[derive(Clone, Copy)]
enum Which {
    Bdf,
    Esdirk34,
}

fn with_diffsol(which: Which, reference: &[Vec<f64>]) {
    let v = vehicle_choice();
    let (vehicle, track) = v.build().expect("profiles");
    let (system, y0) = system_and_state(&track, &vehicle);
    let n = y0.len();
    let system = RefCell::new(system);
    let rhs_calls = RefCell::new(0_usize);
    // f(x) of the last Jacobian-vector product's x (reused while x repeats).
    let base: RefCell<(Vec<f64>, f64, Vec<f64>)> =
        RefCell::new((Vec::new(), f64::NAN, vec![0.0; n]));
    let eval = |t: f64, x: &[f64], y: &mut [f64]| {
        *rhs_calls.borrow_mut() += 1;
        system.borrow_mut().rhs(t, x, y).expect("evaluates");
    };
    let y0c = y0.clone();
    let problem = OdeBuilder::<NalgebraMat<f64>>::new()
        .rtol(RTOL)
        .atol([atol()])
        .h0(1e-4)
        .rhs_implicit(
            |x: &[f64], _p: &[f64], t: f64, y: &mut [f64]| eval(t, x, y),
            |x: &[f64], _p: &[f64], t: f64, v: &[f64], y: &mut [f64]| {
                {
                    let mut b = base.borrow_mut();
                    if b.1 != t || b.0.as_slice() != x {
                        let mut f = vec![0.0; n];
                        eval(t, x, &mut f);
                        *b = (x.to_vec(), t, f);
                    }
                }
                // Forward difference along v, the increment of our
                // Jacobian's columns: 1e-6 max(|x_i|, 1) over v's support.
                let scale = x
                    .iter()
                    .zip(v)
                    .filter(|(_, vi)| **vi != 0.0)
                    .map(|(xi, _)| xi.abs().max(1.0))
                    .fold(0.0_f64, f64::max);
                let vnorm = v.iter().fold(0.0_f64, |m, vi| m.max(vi.abs()));
                if vnorm == 0.0 {
                    y.iter_mut().for_each(|yi| *yi = 0.0);
                    return;
                }
                let eps = 1e-6 * scale / vnorm;
                let xp: Vec<f64> = x.iter().zip(v).map(|(xi, vi)| xi + eps * vi).collect();
                let mut fp = vec![0.0; n];
                eval(t, &xp, &mut fp);
                let b = base.borrow();
                for i in 0..n {
                    y[i] = (fp[i] - b.2[i]) / eps;
                }
            },
        )
        .init(
            move |_p: &[f64], _t: f64, y: &mut [f64]| y.copy_from_slice(&y0c),
            n,
        )
        .build()
        .expect("problem");
    let start = Instant::now();
    // The initial state evaluated and committed, as our integrators do.
    {
        let mut dydt = vec![0.0; n];
        let mut s = system.borrow_mut();
        s.rhs(0.0, &y0, &mut dydt).expect("evaluates");
        s.accept(0.0, &y0).expect("accepts");
    }
    let mut outputs: Vec<(f64, Vec<f64>)> = vec![(0.0, y0.clone())];
    let mut next = OUTPUT_S;
    let mut steps = 0_usize;
    let name = match which {
        Which::Bdf => "diffsol BDF",
        Which::Esdirk34 => "diffsol ESDIRK34",
    };
    macro_rules! run {
        ($solver:expr) => {{
            let mut solver = $solver;
            while solver.state().t < span_s() - 1e-12 {
                if let Err(e) = solver.step() {
                    println!(
                        "{name}: failed at t = {:.4} s after {steps} steps: {e}",
                        solver.state().t
                    );
                    return;
                }
                steps += 1;
                let t = solver.state().t;
                let y: Vec<f64> = solver.state().y.clone_as_vec();
                // The accept protocol: evaluate the accepted state, commit.
                {
                    let mut dydt = vec![0.0; n];
                    let mut s = system.borrow_mut();
                    s.rhs(t, &y, &mut dydt).expect("evaluates");
                    s.accept(t, &y).expect("accepts");
                }
                while next <= t.min(span_s()) + 1e-12 {
                    let yi: Vec<f64> = solver
                        .interpolate(next)
                        .expect("interpolates")
                        .clone_as_vec();
                    outputs.push((next, yi));
                    next += OUTPUT_S;
                }
            }
            format!("{:?}", solver.get_statistics())
        }};
    }
    let jacobians = match which {
        Which::Bdf => run!(problem.bdf::<NalgebraLU<f64>>().expect("bdf")),
        Which::Esdirk34 => run!(problem.esdirk34::<NalgebraLU<f64>>().expect("esdirk34")),
    };
    let wall_s = start.elapsed().as_secs_f64();
    let calls = *rhs_calls.borrow();
    let mut s = system.into_inner();
    let lat = sampled_laterals(&mut s, &outputs);
    report(
        name,
        wall_s,
        &format!(
            "{steps} steps, {calls} right-hand sides (+{steps} accepted-state evaluations), {jacobians}"
        ),
        &lat,
        Some(reference),
    );
}

fn main() {
    let reference = ours(
        Method::Rk4(Rk4 { step_s: 1e-4 }),
        "RK4 0.1 ms (reference)",
        None,
    );
    ours(
        Method::Rk4(Rk4 { step_s: 5e-4 }),
        "RK4 0.5 ms",
        Some(&reference),
    );
    ours(
        Method::Rosenbrock(Rosenbrock {
            atol: atol(),
            ..Rosenbrock::default()
        }),
        "our Rosenbrock-W",
        Some(&reference),
    );
    with_diffsol(Which::Bdf, &reference);
    with_diffsol(Which::Esdirk34, &reference);
}
