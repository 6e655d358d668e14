//! Reference tests of `runtime::integrators` against known solutions:
//! exponential decay, the harmonic oscillator and the Kepler problem
//! (convergence orders, tolerance proportionality, dense output), plus the
//! accept protocol, stopping, non-finite right-hand sides and settings.
//!
//! Measured numbers are quoted next to each assertion (development machine,
//! x86-64; they are deterministic).

use std::convert::Infallible;
use std::f64::consts::PI;

use runtime::fixtures::ode::{Decay, Kepler, Oscillator};
use runtime::integrators::{
    Control, Dopri5, IntegrationStats, IntegratorError, Method, OdeSystem, OutputGrid, Rk4,
    integrate,
};

// ---------------------------------------------------------------- systems

// Decay, the oscillator and Kepler, with their exact solutions, are the
// shared test problems of `runtime::fixtures::ode` (benches/integrators.rs
// runs the same ones).

// ---------------------------------------------------------------- helpers

type Outputs = Vec<(f64, Vec<f64>)>;

fn run<S: OdeSystem>(
    method: &Method,
    system: &mut S,
    y0: &[f64],
    t_end: f64,
    interval_s: f64,
) -> (IntegrationStats, Outputs) {
    let mut out = Vec::new();
    let stats = integrate(
        method,
        system,
        0.0,
        y0,
        t_end,
        &OutputGrid { interval_s },
        &mut |_, t, y| {
            out.push((t, y.to_vec()));
            Ok(())
        },
    )
    .unwrap_or_else(|e| panic!("{method:?}: {e}"));
    assert_eq!(stats.outputs as usize, out.len());
    (stats, out)
}

fn rk4(step_s: f64) -> Method {
    Method::Rk4(Rk4 { step_s })
}

fn dopri5(tol: f64) -> Method {
    Method::Dopri5(Dopri5 {
        rtol: tol,
        atol: tol,
        ..Dopri5::default()
    })
}

/// Least-squares slope of ln(err) against ln(x).
fn slope(xs: &[f64], errs: &[f64]) -> f64 {
    let x: Vec<f64> = xs.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = errs.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------- RK4 orders

#[test]
fn rk4_global_error_is_fourth_order() {
    // Decay, λ = 2 on [0, 2].
    let hs = [0.2, 0.1, 0.05, 0.025];
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| {
            let (_, out) = run(&rk4(h), &mut Decay { lambda: 2.0 }, &[1.0], 2.0, 2.0);
            let (t, y) = out.last().unwrap();
            assert_eq!(*t, 2.0);
            (y[0] - (-4.0f64).exp()).abs()
        })
        .collect();
    let p = slope(&hs, &errs);
    // Measured: 4.14 (errors 2.2e-5 … 4.0e-9).
    assert!((3.8..4.2).contains(&p), "decay order {p}: {errs:?}");

    // Oscillator, ω = 1, one period.
    let period = 2.0 * PI;
    let ns = [20.0, 40.0, 80.0, 160.0];
    let hs: Vec<f64> = ns.iter().map(|n| period / n).collect();
    let errs: Vec<f64> = hs
        .iter()
        .map(|&h| {
            let mut osc = Oscillator::new(1.0).recording();
            let (stats, out) = run(&rk4(h), &mut osc, &[1.0, 0.0], period, period);
            assert_eq!(stats.steps as f64, period / h);
            max_abs_diff(&out.last().unwrap().1, &osc.exact(period))
        })
        .collect();
    let p = slope(&hs, &errs);
    // Measured: 3.98 (errors 4.9e-4 … 1.2e-7).
    assert!((3.8..4.2).contains(&p), "oscillator order {p}: {errs:?}");
}

#[test]
fn rk4_hermite_output_is_fourth_order() {
    // Output every 0.0123 s, off the step grid.
    let period = 2.0 * PI;
    let ns = [20.0, 40.0, 80.0, 160.0];
    let hs: Vec<f64> = ns.iter().map(|n| period / n).collect();
    let (mut total, mut local) = (Vec::new(), Vec::new());
    for &h in &hs {
        let mut osc = Oscillator::new(1.0).recording();
        let (_, out) = run(&rk4(h), &mut osc, &[1.0, 0.0], period, 0.0123);
        assert!(out.len() > 500);
        total.push(
            out.iter()
                .map(|(t, y)| max_abs_diff(y, &osc.exact(*t)))
                .fold(0.0, f64::max),
        );
        local.push(local_output_error(&osc, &out));
    }
    let (p_total, p_local) = (slope(&hs, &total), slope(&hs, &local));
    // Measured: total 3.98, interpolation 4.09 (3.1e-5 … 6.2e-9, at most
    // 1.22·h⁴/384).
    // Total output error (dominated by the global error): order 4.
    assert!(
        (3.8..4.2).contains(&p_total),
        "output order {p_total}: {total:?}"
    );
    // The interpolation's own error (output against the exact flow from the
    // step's start): O(h⁴), h⁴/384·max|x⁗| for the cubic Hermite.
    assert!(
        (3.8..4.2).contains(&p_local),
        "interpolation order {p_local}: {local:?}"
    );
    for (&h, &e) in hs.iter().zip(&local) {
        assert!(
            e < 1.5 * h.powi(4) / 384.0,
            "h {h}: interpolation error {e}"
        );
    }
}

/// Max over outputs of |output − exact flow from the containing step's
/// start state|: the interpolant's own (local) error.
fn local_output_error(osc: &Oscillator, out: &Outputs) -> f64 {
    out.iter()
        .filter_map(|(t, y)| {
            let end = osc.accepted.partition_point(|a| a.0 < *t);
            let (ta, ya) = osc.accepted[end.checked_sub(1)?];
            Some(max_abs_diff(y, &osc.flow(&ya, t - ta)))
        })
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------- DOPRI5

#[test]
fn dopri5_error_is_proportional_to_tolerance() {
    let period = 2.0 * PI;
    let tols = [1e-4, 1e-6, 1e-8, 1e-10];
    let mut osc_errs = Vec::new();
    let mut decay_errs = Vec::new();
    for &tol in &tols {
        let mut osc = Oscillator::new(1.0).recording();
        let (_, out) = run(&dopri5(tol), &mut osc, &[1.0, 0.0], period, period);
        let err = max_abs_diff(&out.last().unwrap().1, &osc.exact(period));
        assert!(err < 3.0 * tol, "oscillator tol {tol}: error {err}");
        osc_errs.push(err);

        let (_, out) = run(&dopri5(tol), &mut Decay { lambda: 2.0 }, &[1.0], 2.0, 2.0);
        let err = (out.last().unwrap().1[0] - (-4.0f64).exp()).abs();
        assert!(err < 3.0 * tol, "decay tol {tol}: error {err}");
        decay_errs.push(err);
    }
    // Measured: oscillator 1.48e-4, 1.69e-6, 1.87e-8, 1.91e-10 (1.5–1.9·tol),
    // slope 0.98; decay 6.0e-6, 1.26e-7, 1.44e-9, 1.52e-11, slope 0.94.
    let p = slope(&tols, &osc_errs);
    let q = slope(&tols, &decay_errs);
    assert!((0.7..1.1).contains(&p), "oscillator: error ∝ tol^{p}");
    assert!((0.7..1.1).contains(&q), "decay: error ∝ tol^{q}");
}

#[test]
fn dopri5_dense_output_matches_the_exact_solution() {
    for tol in [1e-5, 1e-8] {
        let mut osc = Oscillator::new(1.0).recording();
        let t_end = 4.0 * PI;
        let (stats, out) = run(&dopri5(tol), &mut osc, &[1.0, 0.0], t_end, 0.01);
        // Many outputs per step, on the grid, t_end last.
        assert!(
            out.len() as u64 > 5 * stats.steps,
            "{} outputs, {stats:?}",
            out.len()
        );
        for (k, (t, _)) in out.iter().enumerate().take(out.len() - 1) {
            assert_eq!(*t, k as f64 * 0.01);
        }
        assert_eq!(out.last().unwrap().0, t_end);
        let dense_err = out
            .iter()
            .map(|(t, y)| max_abs_diff(y, &osc.exact(*t)))
            .fold(0.0, f64::max);
        let step_err = osc
            .accepted
            .iter()
            .map(|(t, y)| max_abs_diff(y, &osc.exact(*t)))
            .fold(0.0, f64::max);
        let local = local_output_error(&osc, &out);
        // Measured: tol 1e-5: outputs 3.88e-5, step ends 3.83e-5, interpolant
        // 4.3e-6; tol 1e-8: 3.83e-8, 3.83e-8, 3.3e-9.
        // Output error comparable to the error at the step ends.
        assert!(
            dense_err < 1.5 * step_err,
            "tol {tol}: dense {dense_err} vs step ends {step_err}"
        );
        assert!(dense_err < 10.0 * tol, "tol {tol}: dense {dense_err}");
        // The interpolant's own error is of the size of the error per step
        // the controller allows (tol · (1 + |y|), |y| ≤ 1).
        assert!(local < tol, "tol {tol}: local interpolation error {local}");
    }
}

#[test]
fn kepler_orbit_invariants_and_step_adaptation() {
    let e = 0.5;
    let y0 = Kepler::new(e).initial();
    let (e0, l0) = (Kepler::energy(&y0), Kepler::angular_momentum(&y0));
    assert!((e0 + 0.5).abs() < 1e-15 && (l0 - (1.0 - e * e).sqrt()).abs() < 1e-15);
    let periods = 3.0;
    let t_end = periods * 2.0 * PI;
    let drifts = |out: &Outputs| {
        let de = out
            .iter()
            .map(|(_, y)| (Kepler::energy(y) - e0).abs())
            .fold(0.0, f64::max);
        let dl = out
            .iter()
            .map(|(_, y)| (Kepler::angular_momentum(y) - l0).abs())
            .fold(0.0, f64::max);
        (de, dl)
    };

    // Tight tolerance: invariants and the return to perihelion.
    let mut kepler = Kepler::new(e).recording();
    let (stats, out) = run(&dopri5(1e-9), &mut kepler, &y0, t_end, 0.05);
    let (drift_e, drift_l) = drifts(&out);
    let end_err = max_abs_diff(&out.last().unwrap().1, &y0);
    // Mean accepted step near perihelion (r = 0.5) and aphelion (r = 1.5).
    let steps: Vec<(f64, f64)> = kepler
        .accepted
        .windows(2)
        .map(|w| (w[1].0 - w[0].0, 0.5 * (w[0].1 + w[1].1)))
        .collect();
    let mean = |pred: &dyn Fn(f64) -> bool| {
        let v: Vec<f64> = steps.iter().filter(|s| pred(s.1)).map(|s| s.0).collect();
        v.iter().sum::<f64>() / v.len() as f64
    };
    let (h_peri, h_aph) = (mean(&|r| r < 0.6), mean(&|r| r > 1.4));
    // Measured: 340 steps, 0 rejected; drifts 5.2e-9 (energy), 5.3e-9
    // (angular momentum); state after 3 periods 5.9e-7 off; mean step 0.022 s
    // near perihelion, 0.105 s near aphelion.
    assert!(drift_e < 2e-8, "energy drift {drift_e}");
    assert!(drift_l < 2e-8, "angular momentum drift {drift_l}");
    assert!(end_err < 3e-6, "state after {periods} periods: {end_err}");
    assert!(
        h_aph > 3.0 * h_peri,
        "aphelion {h_aph} vs perihelion {h_peri}"
    );
    assert!(stats.steps < 500, "{stats:?}");

    // Looser tolerance: the controller overshoots on the way in and rejects
    // steps; record every attempt to see where.
    let mut rec = Recorder::new(Kepler::new(e).recording());
    let (stats, out) = run(&dopri5(1e-6), &mut rec, &y0, t_end, 0.05);
    let (drift_e, drift_l) = drifts(&out);
    let segments = dopri5_segments(&rec.events);
    let r = |y: &[f64]| y[0].hypot(y[1]);
    // (r, radial velocity r·ṙ) at the start of each segment with rejections.
    let rejected_at: Vec<(f64, f64)> = segments
        .iter()
        .filter(|s| s.rejected > 0)
        .map(|s| {
            (
                r(&s.start_y),
                s.start_y[0] * s.start_y[2] + s.start_y[1] * s.start_y[3],
            )
        })
        .collect();
    // Measured: 20 rejections in 91 steps, 6–7 per orbit, from r = 1.30 down
    // to 0.62 while falling in.
    assert!(stats.rejected > 0, "{stats:?}");
    assert_eq!(
        segments.iter().map(|s| s.rejected).sum::<u64>(),
        stats.rejected
    );
    // Measured: energy 3.6e-5, angular momentum 1.0e-5.
    assert!(
        drift_e < 1e-4 && drift_l < 1e-4,
        "dE {drift_e}, dL {drift_l}"
    );
    // Rejections happen on the way in towards perihelion, where the step
    // must keep shrinking.
    for (r, rdot) in &rejected_at {
        assert!(
            *rdot < 0.0 && *r < 1.35,
            "rejection at r = {r}, r·ṙ = {rdot}"
        );
    }

    // RK4 with 1000 steps per period.
    let mut kepler = Kepler::new(e).recording();
    let (_, out) = run(&rk4(2.0 * PI / 1000.0), &mut kepler, &y0, t_end, 0.05);
    let (drift_e, drift_l) = drifts(&out);
    // Measured: energy 5.3e-9, angular momentum 1.7e-9.
    assert!(drift_e < 2e-8, "RK4 energy drift {drift_e}");
    assert!(drift_l < 2e-8, "RK4 angular momentum drift {drift_l}");
}

/// Against the exact orbit (Kepler's equation, `Kepler::exact`): the
/// global error of the outputs over 3 periods, e = 0.5.
#[test]
fn kepler_outputs_follow_the_exact_orbit() {
    let kepler = Kepler::new(0.5);
    let y0 = kepler.initial();
    let t_end = 3.0 * Kepler::PERIOD_S;
    let worst = |method: &Method| {
        let (_, out) = run(method, &mut kepler.clone(), &y0, t_end, 0.05);
        out.iter()
            .map(|(t, y)| max_abs_diff(y, &kepler.exact(*t)))
            .fold(0.0, f64::max)
    };
    let (tight, loose) = (worst(&dopri5(1e-9)), worst(&dopri5(1e-6)));
    let fixed = worst(&rk4(Kepler::PERIOD_S / 1000.0));
    // Measured: DOPRI5 1e-9 5.9e-7 (phase error, largest after 3 periods),
    // 1e-6 2.1e-3; RK4 1000 steps per period 2.7e-7.
    assert!(tight < 2e-6, "DOPRI5 1e-9: {tight}");
    assert!(loose < 5e-3, "DOPRI5 1e-6: {loose}");
    assert!(fixed < 1e-6, "RK4: {fixed}");
}

// ---------------------------------------------------------------- protocol

#[derive(Debug, Clone, PartialEq)]
enum Event {
    Rhs(f64, Vec<f64>),
    Accept(f64, Vec<f64>),
}

/// Wraps a system and logs every call; optionally stops at the first
/// accepted state with t ≥ `stop_at`.
struct Recorder<S> {
    inner: S,
    events: Vec<Event>,
    stop_at: Option<f64>,
}

impl<S> Recorder<S> {
    fn new(inner: S) -> Self {
        Self {
            inner,
            events: Vec::new(),
            stop_at: None,
        }
    }
}

impl<S: OdeSystem> OdeSystem for Recorder<S> {
    type Error = S::Error;
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), S::Error> {
        self.events.push(Event::Rhs(t, y.to_vec()));
        self.inner.rhs(t, y, dydt)
    }
    fn accept(&mut self, t: f64, y: &[f64]) -> Result<Control, S::Error> {
        self.events.push(Event::Accept(t, y.to_vec()));
        let control = self.inner.accept(t, y)?;
        Ok(match self.stop_at {
            Some(ts) if t >= ts => Control::Stop,
            _ => control,
        })
    }
}

fn bits(y: &[f64]) -> Vec<u64> {
    y.iter().map(|v| v.to_bits()).collect()
}

/// Checks common to both methods: the log starts with rhs and accept at
/// (t0, y0); every accept repeats the arguments of the rhs call right before
/// it, bit for bit; accepts are one per accepted state, in increasing time;
/// the log ends with the last accept; the counters match.
fn check_protocol(events: &[Event], stats: &IntegrationStats, y0: &[f64]) {
    assert_eq!(events[0], Event::Rhs(0.0, y0.to_vec()));
    assert_eq!(events[1], Event::Accept(0.0, y0.to_vec()));
    let mut accepts = 0u64;
    let mut rhs = 0u64;
    let mut last_t = f64::NEG_INFINITY;
    for (i, ev) in events.iter().enumerate() {
        match ev {
            Event::Rhs(..) => rhs += 1,
            Event::Accept(t, y) => {
                accepts += 1;
                match &events[i - 1] {
                    Event::Rhs(tr, yr) => {
                        assert_eq!(t.to_bits(), tr.to_bits(), "event {i}");
                        assert_eq!(bits(y), bits(yr), "event {i}");
                    }
                    other => panic!("event {i}: accept after {other:?}"),
                }
                assert!(*t > last_t, "event {i}: accept at {t} after {last_t}");
                last_t = *t;
            }
        }
    }
    assert_eq!(accepts, stats.steps + 1, "{stats:?}");
    assert_eq!(rhs, stats.rhs_evaluations, "{stats:?}");
    match events.last() {
        Some(Event::Accept(t, _)) => assert_eq!(*t, stats.t_end_reached),
        other => panic!("log ends with {other:?}"),
    }
}

/// The calls between one accept and the next.
struct Segment {
    start_t: f64,
    start_y: Vec<f64>,
    rejected: u64,
}

const DOPRI5_C: [f64; 6] = [0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];

/// Splits a DOPRI5 log into segments and checks each: 6 calls per attempt
/// at t_a + c_i·h (plus the initial-step trial call in the first segment),
/// the last attempt's h = t_b − t_a, rejected attempts longer.
fn dopri5_segments(events: &[Event]) -> Vec<Segment> {
    let accept_idx: Vec<usize> = events
        .iter()
        .enumerate()
        .filter(|(_, e)| matches!(e, Event::Accept(..)))
        .map(|(i, _)| i)
        .collect();
    let mut segments = Vec::new();
    for (n, w) in accept_idx.windows(2).enumerate() {
        let Event::Accept(ta, ya) = &events[w[0]] else {
            unreachable!()
        };
        let Event::Accept(tb, _) = &events[w[1]] else {
            unreachable!()
        };
        let mut calls: Vec<f64> = events[w[0] + 1..w[1]]
            .iter()
            .map(|e| match e {
                Event::Rhs(t, _) => *t,
                Event::Accept(..) => unreachable!(),
            })
            .collect();
        if n == 0 && calls.len() % 6 == 1 {
            // The starting-step heuristic's trial evaluation.
            calls.remove(0);
        }
        assert_eq!(calls.len() % 6, 0, "segment {n}: {} calls", calls.len());
        let attempts: Vec<&[f64]> = calls.chunks(6).collect();
        let h_acc = tb - ta;
        for (k, att) in attempts.iter().enumerate() {
            let h = att[5] - ta;
            for (c, t) in DOPRI5_C.iter().zip(att.iter()) {
                assert!(
                    (t - (ta + c * h)).abs() <= 1e-12 * (1.0 + ta.abs()),
                    "segment {n} attempt {k}: stage at {t}, expected {}",
                    ta + c * h
                );
            }
            if k + 1 < attempts.len() {
                assert!(h > h_acc, "segment {n}: rejected h {h} <= accepted {h_acc}");
            } else {
                assert_eq!(att[5], *tb);
            }
        }
        segments.push(Segment {
            start_t: *ta,
            start_y: ya.clone(),
            rejected: attempts.len() as u64 - 1,
        });
    }
    segments
}

#[test]
fn accept_follows_the_rhs_call_at_every_accepted_state_rk4() {
    let y0 = Kepler::new(0.5).initial();
    let mut rec = Recorder::new(Kepler::new(0.5).recording());
    let (stats, _) = run(&rk4(0.07), &mut rec, &y0, 2.0, 0.1);
    check_protocol(&rec.events, &stats, &y0);
    assert_eq!(stats.rhs_evaluations, 4 * stats.steps + 1);
    // Between accepts: t_a + h/2, t_a + h/2, t_b, then t_b again (k1 of the
    // next step, followed by accept).
    let accepts: Vec<usize> = rec
        .events
        .iter()
        .enumerate()
        .filter(|(_, e)| matches!(e, Event::Accept(..)))
        .map(|(i, _)| i)
        .collect();
    for w in accepts.windows(2) {
        assert_eq!(w[1] - w[0], 5);
        let t = |i: usize| match &rec.events[i] {
            Event::Rhs(t, _) | Event::Accept(t, _) => *t,
        };
        let (ta, tb) = (t(w[0]), t(w[1]));
        let half = ta + 0.5 * (tb - ta);
        assert_eq!(
            [t(w[0] + 1), t(w[0] + 2), t(w[0] + 3), t(w[0] + 4)],
            [half, half, tb, tb]
        );
    }
}

#[test]
fn accept_follows_the_rhs_call_at_every_accepted_state_dopri5() {
    let y0 = Kepler::new(0.5).initial();
    for (label, settings) in [
        (
            "heuristic first step",
            Dopri5 {
                rtol: 1e-6,
                atol: 1e-6,
                ..Dopri5::default()
            },
        ),
        // A first step far too large: rejected several times at once.
        (
            "first step 2 s",
            Dopri5 {
                rtol: 1e-6,
                atol: 1e-6,
                initial_step_s: Some(2.0),
                ..Dopri5::default()
            },
        ),
    ] {
        let mut rec = Recorder::new(Kepler::new(0.5).recording());
        let (stats, _) = run(&Method::Dopri5(settings), &mut rec, &y0, 4.0 * PI, 0.1);
        check_protocol(&rec.events, &stats, &y0);
        let segments = dopri5_segments(&rec.events);
        assert_eq!(segments.len() as u64, stats.steps, "{label}");
        assert_eq!(
            segments.iter().map(|s| s.rejected).sum::<u64>(),
            stats.rejected,
            "{label}"
        );
        assert!(stats.rejected > 0, "{label}: {stats:?}");
        let heuristic = u64::from(settings.initial_step_s.is_none());
        assert_eq!(
            stats.rhs_evaluations,
            6 * (stats.steps + stats.rejected) + 1 + heuristic,
            "{label}"
        );
        if settings.initial_step_s.is_some() {
            assert!(segments[0].rejected >= 2, "{label}");
            assert_eq!(segments[0].start_t, 0.0);
        }
    }
}

#[test]
fn observer_calling_rhs_does_not_disturb_the_integration() {
    let y0 = Kepler::new(0.5).initial();
    for method in [rk4(0.01), dopri5(1e-8)] {
        let mut plain = Kepler::new(0.5).recording();
        let (stats_a, out_a) = run(&method, &mut plain, &y0, 7.0, 0.1);
        let mut probed = Kepler::new(0.5).recording();
        let mut out_b = Vec::new();
        let mut scratch = [0.0; 4];
        let stats_b = integrate(
            &method,
            &mut probed,
            0.0,
            &y0,
            7.0,
            &OutputGrid { interval_s: 0.1 },
            &mut |sys, t, y| {
                sys.rhs(t, y, &mut scratch)?;
                out_b.push((t, y.to_vec()));
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(stats_a, stats_b, "{method:?}");
        assert_eq!(out_a, out_b, "{method:?}");
        assert_eq!(plain.accepted, probed.accepted, "{method:?}");
    }
}

// ---------------------------------------------------------------- stopping

#[test]
fn stop_ends_the_integration_at_the_accepted_state() {
    for method in [rk4(0.3), dopri5(1e-6)] {
        let mut rec = Recorder::new(Oscillator::new(1.0).recording());
        rec.stop_at = Some(1.0);
        let (stats, out) = run(&method, &mut rec, &[1.0, 0.0], 10.0, 0.25);
        check_protocol(&rec.events, &stats, &[1.0, 0.0]);
        assert!(stats.stopped);
        let Some(Event::Accept(ts, ys)) = rec.events.last() else {
            panic!("log must end with the stopping accept")
        };
        // The first accepted state at or after 1 s.
        assert!(*ts >= 1.0 && *ts < 10.0, "{method:?}: stopped at {ts}");
        assert_eq!(stats.t_end_reached, *ts);
        let accepts: Vec<f64> = rec
            .events
            .iter()
            .filter_map(|e| match e {
                Event::Accept(t, _) => Some(*t),
                Event::Rhs(..) => None,
            })
            .collect();
        assert!(accepts[accepts.len() - 2] < 1.0);
        // Outputs: the grid before the stop time, then the stop state exactly.
        let (t_last, y_last) = out.last().unwrap();
        assert_eq!((*t_last, y_last), (*ts, ys));
        for (k, (t, _)) in out[..out.len() - 1].iter().enumerate() {
            assert_eq!(*t, k as f64 * 0.25);
            assert!(*t < *ts);
        }
        assert_eq!(out.len() - 1, (*ts / 0.25).ceil() as usize);
        if let Method::Rk4(_) = method {
            assert_eq!(*ts, 1.2);
        }
    }
    // Stop at the initial state: no step, one output.
    for method in [rk4(0.3), dopri5(1e-6)] {
        let mut rec = Recorder::new(Oscillator::new(1.0).recording());
        rec.stop_at = Some(0.0);
        let (stats, out) = run(&method, &mut rec, &[1.0, 0.0], 10.0, 0.25);
        assert!(stats.stopped);
        assert_eq!((stats.steps, stats.rhs_evaluations), (0, 1));
        assert_eq!(out, vec![(0.0, vec![1.0, 0.0])]);
        assert_eq!(rec.events.len(), 2);
    }
}

// ---------------------------------------------------------------- failures

/// y′ = −y in 3 components; component 2's derivative is NaN for t > t_bad.
struct NanAfter {
    t_bad: f64,
}

impl OdeSystem for NanAfter {
    type Error = Infallible;
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), Infallible> {
        for (d, v) in dydt.iter_mut().zip(y) {
            *d = -v;
        }
        if t > self.t_bad {
            dydt[2] = f64::NAN;
        }
        Ok(())
    }
    fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Infallible> {
        Ok(Control::Continue)
    }
}

fn run_err<S: OdeSystem>(method: &Method, system: &mut S, y0: &[f64]) -> IntegratorError<S::Error> {
    let r = integrate(
        method,
        system,
        0.0,
        y0,
        2.0,
        &OutputGrid { interval_s: 0.1 },
        &mut |_, _, _| Ok(()),
    );
    match r {
        Err(e) => e,
        Ok(stats) => panic!("{method:?}: expected an error, got {stats:?}"),
    }
}

#[test]
fn non_finite_right_hand_side() {
    let y0 = [1.0, 2.0, 3.0];
    // RK4, h = 0.3: the step from 0.9 s evaluates k2 at 1.05 s.
    match run_err(&rk4(0.3), &mut NanAfter { t_bad: 1.0 }, &y0) {
        IntegratorError::NonFinite { t, component } => {
            assert!((t - 1.05).abs() < 1e-12, "t {t}");
            assert_eq!(component, 2);
        }
        other => panic!("RK4: {other:?}"),
    }
    // DOPRI5 shrinks its step against t = 1 s until it is below min_step_s.
    match run_err(&dopri5(1e-8), &mut NanAfter { t_bad: 1.0 }, &y0) {
        IntegratorError::NonFinite { t, component } => {
            // Measured: t − 1 = 7.8e-13 (default min_step_s 1e-12 s).
            assert!(t > 1.0 && t - 1.0 < 1e-9, "t {t}");
            assert_eq!(component, 2);
        }
        other => panic!("DOPRI5: {other:?}"),
    }
    // With a larger minimum step.
    let m = Method::Dopri5(Dopri5 {
        min_step_s: 1e-6,
        ..Dopri5::default()
    });
    match run_err(&m, &mut NanAfter { t_bad: 1.0 }, &y0) {
        IntegratorError::NonFinite { t, component } => {
            assert!(t > 1.0 && t - 1.0 < 1e-5, "t {t}");
            assert_eq!(component, 2);
        }
        other => panic!("DOPRI5: {other:?}"),
    }
    // NaN already at t0.
    for method in [rk4(0.3), dopri5(1e-8)] {
        match run_err(&method, &mut NanAfter { t_bad: -1.0 }, &y0) {
            IntegratorError::NonFinite { t, component } => assert_eq!((t, component), (0.0, 2)),
            other => panic!("{method:?}: {other:?}"),
        }
    }
}

/// y′ = 2/(1 − t)³, y(0) = 1: y = 1/(1 − t)² blows up at t = 1, so the
/// step size collapses while every evaluation stays finite.
struct Singular;

impl OdeSystem for Singular {
    type Error = Infallible;
    fn rhs(&mut self, t: f64, _y: &[f64], dydt: &mut [f64]) -> Result<(), Infallible> {
        dydt[0] = 2.0 / (1.0 - t).powi(3);
        Ok(())
    }
    fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Infallible> {
        Ok(Control::Continue)
    }
}

#[test]
fn step_size_too_small_at_a_singularity() {
    let m = Method::Dopri5(Dopri5 {
        min_step_s: 1e-8,
        ..Dopri5::default()
    });
    match run_err(&m, &mut Singular, &[1.0]) {
        IntegratorError::StepSizeTooSmall { t, step_s } => {
            // Measured: 1 − t = 6.5e-8, step 9.1e-9 s.
            assert!(t < 1.0 && 1.0 - t < 1e-6, "t {t}");
            assert!(step_s < 1e-8);
        }
        other => panic!("{other:?}"),
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("model broke at t = {t_s} s")]
struct Broken {
    t_s: f64,
}

/// y′ = −y that fails (rhs or observer) after `t_fail`.
struct Fails {
    t_fail: f64,
}

impl OdeSystem for Fails {
    type Error = Broken;
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) -> Result<(), Broken> {
        if t > self.t_fail {
            return Err(Broken { t_s: t });
        }
        dydt[0] = -y[0];
        Ok(())
    }
    fn accept(&mut self, _t: f64, _y: &[f64]) -> Result<Control, Broken> {
        Ok(Control::Continue)
    }
}

#[test]
fn system_and_observer_errors_are_passed_through() {
    use std::error::Error;
    for method in [rk4(0.3), dopri5(1e-6)] {
        let e = run_err(&method, &mut Fails { t_fail: 0.5 }, &[1.0]);
        match &e {
            IntegratorError::System(Broken { t_s }) => assert!(*t_s > 0.5),
            other => panic!("{method:?}: {other:?}"),
        }
        assert!(e.source().is_some());
        assert!(e.to_string().starts_with("model broke"), "{e}");

        let r = integrate(
            &method,
            &mut Fails { t_fail: 10.0 },
            0.0,
            &[1.0],
            2.0,
            &OutputGrid { interval_s: 0.1 },
            &mut |_, t, _| {
                if t > 1.0 {
                    Err(Broken { t_s: t })
                } else {
                    Ok(())
                }
            },
        );
        match r {
            Err(IntegratorError::System(Broken { t_s })) => {
                assert!((t_s - 1.1).abs() < 1e-12, "{t_s}")
            }
            other => panic!("{method:?}: {other:?}"),
        }
    }
}

#[test]
fn settings_are_validated() {
    let setting = |method: Method, t0: f64, y0: &[f64], t_end: f64| -> &'static str {
        match integrate(
            &method,
            &mut Decay { lambda: 1.0 },
            t0,
            y0,
            t_end,
            &OutputGrid { interval_s: 0.1 },
            &mut |_, _, _| Ok(()),
        ) {
            Err(IntegratorError::InvalidSettings { setting, .. }) => setting,
            other => panic!("{method:?}: expected InvalidSettings, got {other:?}"),
        }
    };
    for step_s in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        assert_eq!(setting(rk4(step_s), 0.0, &[1.0], 1.0), "step_s");
    }
    for rtol in [0.0, -1e-6, f64::NAN] {
        let m = Method::Dopri5(Dopri5 {
            rtol,
            ..Dopri5::default()
        });
        assert_eq!(setting(m, 0.0, &[1.0], 1.0), "rtol");
    }
    for method in [rk4(0.1), dopri5(1e-6)] {
        assert_eq!(setting(method, 1.0, &[1.0], 0.0), "t_end");
        assert_eq!(setting(method, 0.0, &[1.0], f64::NAN), "t_end");
        assert_eq!(setting(method, f64::NAN, &[1.0], 1.0), "t0");
        assert_eq!(setting(method, 0.0, &[], 1.0), "y0.len()");
    }
    // The message names the setting, its value and the rule.
    let e = integrate(
        &rk4(-0.5),
        &mut Decay { lambda: 1.0 },
        0.0,
        &[1.0],
        1.0,
        &OutputGrid { interval_s: 0.1 },
        &mut |_, _, _| Ok(()),
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "invalid setting step_s = -0.5: must be finite and > 0"
    );
}
