//! What the speed/accuracy study measures on a run and against the
//! reference: the lateral displacement's errors, the hunting frequency,
//! the growth rate and the peak forces; the Pareto front.

use anyhow::Result;
use runtime::results::RunResults;

use super::{Errors, Measures};
use crate::studies::critical_speed::growth_rate;
use crate::studies::run_difference::{Abscissa, lateral_difference_by};

/// Amplitudes below this are not motion (m): zero crossings after the
/// motion has died out are not counted.
const NOISE_M: f64 = 1e-7;

/// Hunting frequency (Hz) from the zero crossings (both ways, linearly
/// interpolated) of `y(t)` while the motion lasts (|y| above 1e-3 of its
/// peak and 0.1 µm); `None` below 3 crossings.
pub fn hunting_frequency_hz(t: &[f64], y: &[f64]) -> Option<f64> {
    let peak = y
        .iter()
        .filter(|v| v.is_finite())
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let floor = (1e-3 * peak).max(NOISE_M);
    let last = y.iter().rposition(|v| v.abs() > floor)?;
    let n = (last + 1).min(y.len().saturating_sub(1));
    let crossings: Vec<f64> = (0..n)
        .filter(|&i| {
            y[i].is_finite()
                && y[i + 1].is_finite()
                && ((y[i] < 0.0 && y[i + 1] >= 0.0) || (y[i] > 0.0 && y[i + 1] <= 0.0))
        })
        .map(|i| t[i] + (t[i + 1] - t[i]) * y[i] / (y[i] - y[i + 1]))
        .collect();
    if crossings.len() < 3 {
        return None;
    }
    let span = crossings[crossings.len() - 1] - crossings[0];
    (span > 0.0).then(|| (crossings.len() - 1) as f64 / (2.0 * span))
}

fn or_zero(v: f64) -> f64 {
    if v.is_finite() { v } else { 0.0 }
}

/// What a run measures by itself after the start transient `skip_s` (the
/// peaks and the growth-rate fit; the frequency takes every crossing).
pub fn measures(r: &RunResults, skip_s: f64) -> Measures {
    let (mut y_peak, mut n_peak) = (0.0_f64, 0.0_f64);
    for ws in &r.wheelsets {
        for wheel in &ws.wheels {
            let [a, b] = &wheel.zones;
            for i in 0..a.lateral_force_n.len() {
                if r.time_s[i] < skip_s {
                    continue;
                }
                y_peak = y_peak
                    .max((or_zero(a.lateral_force_n[i]) + or_zero(b.lateral_force_n[i])).abs());
                n_peak = n_peak.max(or_zero(a.normal_n[i]) + or_zero(b.normal_n[i]));
            }
        }
    }
    let (frequency, rate) = match r.wheelsets.first() {
        Some(w) => (
            hunting_frequency_hz(&r.time_s, &w.lateral_m),
            growth_rate(r, 0, skip_s)
                .map(|f| f.rate_1_s)
                .filter(|v| v.is_finite()),
        ),
        None => (None, None),
    };
    Measures {
        hunting_frequency_hz: frequency,
        growth_rate_1_s: rate,
        peak_lateral_force_n: y_peak,
        peak_normal_force_n: n_peak,
    }
}

/// Max and RMS of wheelset `wheelset`'s lateral difference (m) between
/// `run` and `reference` (0 = the leading wheelset) at equal time (runs of
/// one scene at one speed: the same time is the same place), over the
/// reference's samples within the run's span, and that span (s); the
/// shared helper [`crate::studies::run_difference`].
pub fn lateral_difference(
    reference: &RunResults,
    run: &RunResults,
    wheelset: usize,
) -> Result<(f64, f64, f64)> {
    let d = lateral_difference_by(reference, run, wheelset, Abscissa::Time)?;
    Ok((d.max_m, d.rms_m, d.span()))
}

/// Errors of `run` against `reference` (module docs).
pub fn compare(reference: &RunResults, run: &RunResults, skip_s: f64) -> Result<Errors> {
    let (max, rms, span) = lateral_difference(reference, run, 0)?;
    let (a, b) = (measures(reference, skip_s), measures(run, skip_s));
    let diff = |x: Option<f64>, y: Option<f64>| x.zip(y).map(|(x, y)| (x - y).abs());
    Ok(Errors {
        lateral_max_m: max,
        lateral_rms_m: rms,
        compared_s: span,
        frequency_hz: diff(a.hunting_frequency_hz, b.hunting_frequency_hz),
        growth_rate_1_s: diff(a.growth_rate_1_s, b.growth_rate_1_s),
        peak_lateral_force_n: (a.peak_lateral_force_n - b.peak_lateral_force_n).abs(),
        peak_normal_force_n: (a.peak_normal_force_n - b.peak_normal_force_n).abs(),
    })
}

/// Which points `(cost, error)` are on the Pareto front (no other point is
/// at most as costly and as wrong, and better in one). Non-finite points
/// are never on it.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .map(|&(c, e)| {
            c.is_finite()
                && e.is_finite()
                && !points.iter().any(|&(c2, e2)| {
                    c2.is_finite() && e2.is_finite() && c2 <= c && e2 <= e && (c2 < c || e2 < e)
                })
        })
        .collect()
}

pub(super) fn median(v: &[f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    Some(if n % 2 == 1 {
        s[n / 2]
    } else {
        0.5 * (s[n / 2 - 1] + s[n / 2])
    })
}
