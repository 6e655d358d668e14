//! Fixed-step classical Runge–Kutta method of order 4 with cubic Hermite
//! dense output.
//!
//! # Method (Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., §II.1,
//! Table 1.2, "the" Runge–Kutta method of Kutta 1901)
//!
//! ```text
//! k1 = f(t, y)
//! k2 = f(t + h/2, y + h/2·k1)
//! k3 = f(t + h/2, y + h/2·k2)
//! k4 = f(t + h,   y + h·k3)
//! y⁺ = y + h/6·(k1 + 2k2 + 2k3 + k4)
//! ```
//!
//! Step times are t_n = t0 + n·h (computed from n, not accumulated); the last
//! step is shortened to land exactly on t_end. A remainder below 10⁻⁹·h is
//! absorbed into the previous step instead (so 1/0.1 gives 10 steps, not 10
//! plus one of 10⁻¹⁷ s). k1 of the next step, f(t⁺, y⁺), is evaluated right
//! after the step and [`OdeSystem::accept`] is called at (t⁺, y⁺) right
//! after it — likewise at (t0, y0) before the first step — so a run of N
//! steps makes 4N + 1 evaluations, and every accepted state's derivative is
//! known.
//!
//! # Dense output (HNW §II.6, eq. 6.7: cubic Hermite interpolation)
//!
//! With θ = (t − t_n)/h, Δ = y⁺ − y and f, f⁺ the derivatives at both ends
//! (k1 of consecutive steps):
//!
//! ```text
//! u(θ) = (1 − θ)·y + θ·y⁺ + θ(θ − 1)·[(1 − 2θ)·Δ + (θ − 1)·h f + θ·h f⁺]
//! ```
//!
//! It matches value and slope at both ends; its interpolation error is
//! O(h⁴) (h⁴/384·max|y⁗|), the same order as RK4's global error, so output
//! at any time is 4th-order accurate (measured in tests).
//!
//! # Failures
//!
//! A stage derivative or the new state with a NaN or infinite entry is
//! [`IntegratorError::NonFinite`] with the time of that evaluation (or of the
//! new state) and the entry's index: a fixed step cannot retreat.

use super::{
    Control, IntegrationStats, IntegratorError, Observer, OdeSystem, OutputCursor, OutputGrid,
    StepRange, eval, first_non_finite, invalid,
};

/// Fixed-step RK4 settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rk4 {
    /// Step size h (s), finite and > 0; the last step is shortened to land on
    /// t_end. It must resolve time at t_end (h > 4·ε_mach·max(|t0|, |t_end|))
    /// and give at most 10¹⁵ steps.
    pub step_s: f64,
}

/// Largest number of RK4 steps accepted by validation (keeps the step index
/// exact in f64 and u64).
const MAX_RK4_STEPS: f64 = 1e15;

/// A remainder of (t_end − t0)/h below this fraction of a step is absorbed
/// into the previous step.
const REMAINDER_ABSORB: f64 = 1e-9;

/// Number of steps for the span, after validation.
fn step_count<E>(settings: &Rk4, t0: f64, t_end: f64) -> Result<u64, IntegratorError<E>> {
    let h = settings.step_s;
    if !(h.is_finite() && h > 0.0) {
        return Err(invalid("step_s", h, "must be finite and > 0"));
    }
    if h <= 4.0 * f64::EPSILON * t0.abs().max(t_end.abs()) {
        return Err(invalid(
            "step_s",
            h,
            "must exceed the time resolution 4·eps·max(|t0|, |t_end|)",
        ));
    }
    let ratio = (t_end - t0) / h;
    if ratio > MAX_RK4_STEPS {
        return Err(invalid(
            "step_s",
            h,
            "must give at most 1e15 steps over [t0, t_end]",
        ));
    }
    let whole = ratio.floor();
    let n = if ratio - whole <= REMAINDER_ABSORB {
        whole
    } else {
        whole + 1.0
    };
    // `ratio` ≥ 0 and ≤ 1e15: the conversion is exact. A span below 1e-9·h
    // gives 0 steps only when t_end == t0; otherwise take one short step.
    let n = n as u64;
    Ok(if n == 0 && t_end > t0 { 1 } else { n })
}

/// Cubic Hermite interpolation (HNW §II.6, eq. 6.7) at `theta` ∈ [0, 1]
/// between (y0, f0) and (y1, f1), a step of `h` s apart.
pub(super) fn hermite(
    theta: f64,
    h: f64,
    y0: &[f64],
    f0: &[f64],
    y1: &[f64],
    f1: &[f64],
    out: &mut [f64],
) {
    let th1 = theta - 1.0;
    for i in 0..out.len() {
        let d = y1[i] - y0[i];
        out[i] = (1.0 - theta) * y0[i]
            + theta * y1[i]
            + theta * th1 * ((1.0 - 2.0 * theta) * d + th1 * h * f0[i] + theta * h * f1[i]);
    }
}

pub(super) fn integrate_rk4<S: OdeSystem>(
    settings: &Rk4,
    system: &mut S,
    t0: f64,
    y0: &[f64],
    t_end: f64,
    output: &OutputGrid,
    observer: &mut Observer<'_, S>,
) -> Result<IntegrationStats, IntegratorError<S::Error>> {
    let n_steps = step_count(settings, t0, t_end)?;
    let h_nominal = settings.step_s;
    let n = y0.len();

    // Work vectors, allocated once.
    let mut y = y0.to_vec();
    let mut y_new = vec![0.0; n];
    let mut y_stage = vec![0.0; n];
    let mut k1 = vec![0.0; n];
    let mut k2 = vec![0.0; n];
    let mut k3 = vec![0.0; n];
    let mut k4 = vec![0.0; n];
    let mut k1_new = vec![0.0; n];
    let mut y_out = vec![0.0; n];

    let mut evaluations = 0u64;
    let mut cursor = OutputCursor::new(t0, t_end, output);
    let mut range = StepRange::new();
    let mut steps = 0u64;

    // The initial state: evaluate, accept, output.
    if let Some(component) = eval(system, t0, &y, &mut k1, &mut evaluations)? {
        return Err(IntegratorError::NonFinite { t: t0, component });
    }
    let mut stopped = system.accept(t0, &y).map_err(IntegratorError::System)? == Control::Stop;
    let mut t = t0;
    cursor.emit_step(
        system,
        observer,
        t0,
        &y,
        stopped || n_steps == 0,
        &mut y_out,
        &mut |_, _| {},
    )?;

    while !stopped && steps < n_steps {
        let t_new = if steps + 1 == n_steps {
            t_end
        } else {
            t0 + (steps + 1) as f64 * h_nominal
        };
        let h = t_new - t;
        let t_half = t + 0.5 * h;

        for i in 0..n {
            y_stage[i] = y[i] + 0.5 * h * k1[i];
        }
        if let Some(component) = eval(system, t_half, &y_stage, &mut k2, &mut evaluations)? {
            return Err(IntegratorError::NonFinite {
                t: t_half,
                component,
            });
        }
        for i in 0..n {
            y_stage[i] = y[i] + 0.5 * h * k2[i];
        }
        if let Some(component) = eval(system, t_half, &y_stage, &mut k3, &mut evaluations)? {
            return Err(IntegratorError::NonFinite {
                t: t_half,
                component,
            });
        }
        for i in 0..n {
            y_stage[i] = y[i] + h * k3[i];
        }
        if let Some(component) = eval(system, t_new, &y_stage, &mut k4, &mut evaluations)? {
            return Err(IntegratorError::NonFinite {
                t: t_new,
                component,
            });
        }
        for i in 0..n {
            y_new[i] = y[i] + h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
        }
        if let Some(component) = first_non_finite(&y_new) {
            return Err(IntegratorError::NonFinite {
                t: t_new,
                component,
            });
        }
        // k1 of the next step at the accepted state, then accept right after.
        if let Some(component) = eval(system, t_new, &y_new, &mut k1_new, &mut evaluations)? {
            return Err(IntegratorError::NonFinite {
                t: t_new,
                component,
            });
        }
        stopped = system
            .accept(t_new, &y_new)
            .map_err(IntegratorError::System)?
            == Control::Stop;
        steps += 1;
        range.record(h);

        let is_final = stopped || steps == n_steps;
        {
            let (y_prev, f_prev, y_next, f_next) = (&y, &k1, &y_new, &k1_new);
            cursor.emit_step(
                system,
                observer,
                t_new,
                &y_new,
                is_final,
                &mut y_out,
                &mut |tk, out| {
                    hermite((tk - t) / h, h, y_prev, f_prev, y_next, f_next, out);
                },
            )?;
        }

        std::mem::swap(&mut y, &mut y_new);
        std::mem::swap(&mut k1, &mut k1_new);
        t = t_new;
    }

    let (min_step_s, max_step_s) = range.get();
    Ok(IntegrationStats {
        steps,
        rejected: 0,
        rhs_evaluations: evaluations,
        jacobian_evaluations: 0,
        dense_lu_fallbacks: 0,
        outputs: cursor.emitted,
        t_end_reached: t,
        stopped,
        min_step_s,
        max_step_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrators::{Method, integrate};
    use std::convert::Infallible;

    #[test]
    fn hermite_is_exact_for_cubics_and_matches_ends() {
        // y = 1 + 2t − 3t² + 0.5t³ on [0.4, 1.1].
        let y = |t: f64| 1.0 + 2.0 * t - 3.0 * t * t + 0.5 * t * t * t;
        let f = |t: f64| 2.0 - 6.0 * t + 1.5 * t * t;
        let (ta, tb) = (0.4, 1.1);
        let h = tb - ta;
        let mut out = [0.0];
        for k in 0..=20 {
            let theta = k as f64 / 20.0;
            hermite(theta, h, &[y(ta)], &[f(ta)], &[y(tb)], &[f(tb)], &mut out);
            let t = ta + theta * h;
            assert!(
                (out[0] - y(t)).abs() < 1e-14,
                "θ {theta}: {} vs {}",
                out[0],
                y(t)
            );
        }
    }

    #[test]
    fn step_count_absorbs_round_off_and_shortens_the_last_step() {
        let c = |h: f64, t0: f64, t1: f64| step_count::<Infallible>(&Rk4 { step_s: h }, t0, t1);
        assert_eq!(c(0.1, 0.0, 1.0).unwrap(), 10);
        assert_eq!(c(0.1, 0.0, 0.3).unwrap(), 3);
        assert_eq!(c(0.3, 0.0, 1.0).unwrap(), 4);
        assert_eq!(c(0.3, 0.0, 0.0).unwrap(), 0);
        assert_eq!(c(10.0, 0.0, 1.0).unwrap(), 1);
        for bad in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                c(bad, 0.0, 1.0),
                Err(IntegratorError::InvalidSettings {
                    setting: "step_s",
                    ..
                })
            ));
        }
        // Below the time resolution at t = 1e6 s.
        assert!(c(1e-12, 1e6, 1e6 + 1.0).is_err());
        // Too many steps.
        assert!(c(1e-16, 0.0, 1.0).is_err());
    }

    /// y′ = y (y = e^t): the shortened last step and the stats.
    struct Growth;

    impl OdeSystem for Growth {
        type Error = Infallible;
        fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), Infallible> {
            dydt[0] = y[0];
            Ok(())
        }
        fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Infallible> {
            Ok(Control::Continue)
        }
    }

    #[test]
    fn last_step_lands_on_t_end() {
        let mut last = (0.0, 0.0);
        let stats = integrate(
            &Method::Rk4(Rk4 { step_s: 0.3 }),
            &mut Growth,
            0.0,
            &[1.0],
            1.0,
            &OutputGrid { interval_s: 1.0 },
            &mut |_, t, y| {
                last = (t, y[0]);
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(stats.steps, 4);
        assert_eq!(stats.rhs_evaluations, 17);
        assert_eq!(stats.t_end_reached, 1.0);
        assert!(
            (stats.min_step_s - 0.1).abs() < 1e-15,
            "{}",
            stats.min_step_s
        );
        assert!(
            (stats.max_step_s - 0.3).abs() < 1e-15,
            "{}",
            stats.max_step_s
        );
        assert_eq!(last.0, 1.0);
        // Local errors h⁵/120 per step: 3 × 2e-5 + ..., global ≈ 1e-4 e.
        assert!((last.1 - 1f64.exp()).abs() < 2e-4, "{}", last.1);
    }
}
