//! Criterion bench: RK4 and DOPRI5 over the shared analytic test problems
//! of `runtime::fixtures::ode` (the ones tests/integrator_reference.rs
//! checks against their exact solutions): the harmonic oscillator over ten
//! periods and the Kepler orbit (e = 0.5) over three, with an output every
//! 0.05 s. One iteration is one whole integration.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use runtime::fixtures::ode::{Kepler, Oscillator};
use runtime::integrators::{Dopri5, Method, OdeSystem, OutputGrid, Rk4, integrate};

/// Integrate `system` from `y0` over [0, `t_end`] (s), summing the first
/// component of every output (so the outputs are not optimised away).
fn solve<S: OdeSystem>(method: &Method, system: &mut S, y0: &[f64], t_end: f64) -> f64 {
    let mut sum = 0.0;
    integrate(
        method,
        system,
        0.0,
        y0,
        t_end,
        &OutputGrid { interval_s: 0.05 },
        &mut |_, _, y| {
            sum += y[0];
            Ok(())
        },
    )
    .expect("integrates");
    sum
}

fn bench(c: &mut Criterion) {
    let rk4 = |steps_per_period: f64, period_s: f64| {
        Method::Rk4(Rk4 {
            step_s: period_s / steps_per_period,
        })
    };
    let dopri5 = |tol: f64| {
        Method::Dopri5(Dopri5 {
            rtol: tol,
            atol: tol,
            ..Dopri5::default()
        })
    };

    let osc = Oscillator::new(1.0);
    let period_s = 2.0 * std::f64::consts::PI / osc.omega;
    let osc_end = 10.0 * period_s;
    for (name, method) in [
        ("rk4_100_per_period", rk4(100.0, period_s)),
        ("dopri5_1e-8", dopri5(1e-8)),
    ] {
        c.bench_function(&format!("integrate_oscillator/{name}"), |b| {
            b.iter(|| {
                solve(
                    black_box(&method),
                    &mut osc.clone(),
                    &osc.initial(),
                    osc_end,
                )
            })
        });
    }

    let kepler = Kepler::new(0.5);
    let kepler_end = 3.0 * Kepler::PERIOD_S;
    for (name, method) in [
        ("rk4_1000_per_period", rk4(1000.0, Kepler::PERIOD_S)),
        ("dopri5_1e-9", dopri5(1e-9)),
    ] {
        c.bench_function(&format!("integrate_kepler/{name}"), |b| {
            b.iter(|| {
                solve(
                    black_box(&method),
                    &mut kepler.clone(),
                    &kepler.initial(),
                    kepler_end,
                )
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
