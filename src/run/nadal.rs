//! Nadal's criterion per wheel of a run: the derailment quotient Y/Q of
//! the samples against the wheel's limit, judged as EN 14363 judges it.
//!
//! # The criterion (docs/guide/extremes-and-diagnostics.md, "Nadal's criterion")
//!
//! - **Limit**: (tan γ − μ)/(1 + μ tan γ) for the wheel's steepest flange
//!   angle γ and the friction μ (Nadal 1908; [`runtime::contact::nadal`]).
//! - **Assessed quantity**: the sliding mean of Y/Q over
//!   [`NADAL_WINDOW_M`] = 2 m of track, EN 14363:2016 §7.6's (Y/Q)_2m (the
//!   standard, like UIC 518, slides the 2 m window in 0.5 m steps over the
//!   20 Hz low-passed signal; an impact's spike of a few milliseconds does
//!   not climb a flange). Here a window ends at every sample once the run
//!   has covered 2 m — at least as many windows as the 0.5 m steps give —
//!   and the samples are not filtered (the output interval sets the
//!   bandwidth: 5 ms keeps up to 100 Hz), so the mean is never milder than
//!   the standard's.
//! - **Samples without load** (Q ≤ 0 or no contact: the wheel is
//!   airborne; their Y/Q is undefined) are left out of a window's mean,
//!   which is the mean of Y/Q over the window's **loaded** samples. The
//!   standard's measured forces have no flight phases and say nothing of
//!   them; our rule, so that a few samples cannot make a verdict: a window
//!   is **valid** only when at least [`MIN_LOADED_SAMPLES`] of its samples
//!   are loaded and they are more than [`MIN_LOADED_FRACTION`] of its
//!   samples (a window half or mostly in the air is not one in which the
//!   wheel rolled on its rail). Invalid windows are counted and reported.
//! - **Verdict** ([`NadalVerdict`]): "derailment risk" when the largest
//!   mean of a valid window exceeds the limit; "below the limit" when
//!   valid windows exist and none does; no verdict when the run covered
//!   less than 2 m, when no window is valid, or for a wheel without
//!   flange. The largest sample, the time above the limit and the
//!   fraction of airborne samples are reported beside it.

use runtime::results::{WHEEL_GROUPS, WheelSeries, WheelsetSeries};
use serde::Serialize;

/// Length of track of the sliding mean of Y/Q (m): EN 14363:2016 §7.6,
/// (Y/Q)_2m.
pub const NADAL_WINDOW_M: f64 = 2.0;

/// Least number of loaded samples (Q > 0) in a valid window: a mean of
/// one or two samples is a spike and at most one neighbour (at 100 m/s and
/// a 5 ms output interval a window holds 4 samples).
pub const MIN_LOADED_SAMPLES: usize = 3;

/// The loaded samples of a valid window are more than this fraction of
/// its samples: a window half or mostly in the air is not one of rolling
/// on the rail.
pub const MIN_LOADED_FRACTION: f64 = 0.5;

/// What the 2 m criterion says of one wheel (module docs).
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum NadalVerdict {
    /// A valid window's mean exceeds the limit.
    DerailmentRisk,
    /// Valid windows exist; no mean exceeds the limit.
    BelowLimit,
    /// The run covered less than [`NADAL_WINDOW_M`] (or stood still).
    ShorterThanWindow,
    /// Complete windows exist, none valid (too few loaded samples).
    NoValidWindow,
    /// The wheel has no flange: no limit.
    NoFlange,
}

impl NadalVerdict {
    /// A few words for the text summary.
    pub fn text(self) -> &'static str {
        match self {
            NadalVerdict::DerailmentRisk => "DERAILMENT RISK",
            NadalVerdict::BelowLimit => "below the limit",
            NadalVerdict::ShorterThanWindow => "no verdict: the run covered less than 2 m",
            NadalVerdict::NoValidWindow => "no verdict: no valid 2 m window",
            NadalVerdict::NoFlange => "no flange",
        }
    }
}

/// Nadal's criterion for one wheel of a run (module docs).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelNadal {
    /// "left" / "right".
    pub wheel: String,
    /// Largest Y/Q of the samples (Y + towards the track centre), and when.
    pub max_y_over_q: Option<f64>,
    pub max_at_s: Option<f64>,
    /// Largest mean of Y/Q over a valid [`NADAL_WINDOW_M`] window (its
    /// loaded samples), and the time of the window's last sample; `None`
    /// without a valid window.
    pub max_y_over_q_2m: Option<f64>,
    pub max_2m_at_s: Option<f64>,
    /// Complete 2 m windows (one ending at each sample once 2 m are
    /// covered) and the valid ones among them.
    pub windows: u64,
    pub valid_windows: u64,
    /// Samples without load (Q ≤ 0 or no contact: airborne), and their
    /// fraction of all samples (0 without samples).
    pub airborne_samples: u64,
    pub airborne_fraction: f64,
    /// Steepest flange angle γ (deg), friction μ and the limit
    /// (tan γ − μ)/(1 + μ tan γ); `None` for a wheel without a flange.
    pub flange_angle_deg: Option<f64>,
    pub friction: Option<f64>,
    pub nadal_limit: Option<f64>,
    /// Time with Y/Q above the limit (s, from the samples).
    pub time_above_limit_s: f64,
    pub verdict: NadalVerdict,
    /// `verdict == DerailmentRisk`.
    pub derailment_risk: bool,
}

/// A sample's Y/Q when the wheel is loaded (Q > 0, Y/Q finite).
fn loaded_quotient(wheel: &WheelSeries, i: usize) -> Option<f64> {
    let q = *wheel.q_n.get(i)?;
    let v = *wheel.y_over_q.get(i)?;
    (q.is_finite() && q > 0.0 && v.is_finite()).then_some(v)
}

/// The sliding windows of one wheel: complete windows, valid windows and
/// the largest valid mean with the index of its last sample.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Windows {
    complete: u64,
    valid: u64,
    best: Option<(f64, usize)>,
}

/// Trailing windows (d − `window_m`, d] over `distance_m` (non-decreasing),
/// one ending at each sample once `window_m` is covered; `quotient[i]` is
/// the sample's Y/Q when loaded (module docs for validity).
fn sliding_windows(quotient: &[Option<f64>], distance_m: &[f64], window_m: f64) -> Windows {
    let means = crate::run::curving::windows::sliding_means(quotient, distance_m, window_m);
    let Some(&start) = distance_m.first() else {
        return Windows::default();
    };
    // NaN distances never complete a window.
    let complete = distance_m[..means.len()]
        .iter()
        .filter(|&&d| d - start >= window_m)
        .count() as u64;
    let mut best: Option<(f64, usize)> = None;
    for (i, mean) in means.iter().enumerate() {
        if let Some(m) = *mean
            && best.is_none_or(|(b, _)| m > b)
        {
            best = Some((m, i));
        }
    }
    Windows {
        complete,
        valid: means.iter().flatten().count() as u64,
        best,
    }
}

/// Nadal's criterion for both wheels of a wheelset's series.
pub fn nadal_summary(w: &WheelsetSeries, time_s: &[f64]) -> Vec<WheelNadal> {
    let dt = |i: usize| match (time_s.get(i), time_s.get(i + 1)) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    let n = time_s.len();
    w.wheels
        .iter()
        .zip(WHEEL_GROUPS)
        .map(|(wheel, name)| {
            let quotient: Vec<Option<f64>> = (0..n).map(|i| loaded_quotient(wheel, i)).collect();
            let max = quotient
                .iter()
                .enumerate()
                .filter_map(|(i, v)| v.map(|v| (i, v)))
                .max_by(|a, b| a.1.total_cmp(&b.1));
            let limit = wheel.nadal.map(|l| l.limit);
            let windows = sliding_windows(&quotient, &w.distance_m, NADAL_WINDOW_M);
            let time_above_limit_s = match limit {
                Some(l) => {
                    0.0 + quotient
                        .iter()
                        .enumerate()
                        .filter(|(_, v)| v.is_some_and(|v| v > l))
                        .map(|(i, _)| dt(i))
                        .sum::<f64>()
                }
                None => 0.0,
            };
            let airborne = quotient.iter().filter(|v| v.is_none()).count();
            let verdict = match (limit, windows.best) {
                (None, _) => NadalVerdict::NoFlange,
                (Some(l), Some((m, _))) if m > l => NadalVerdict::DerailmentRisk,
                (Some(_), Some(_)) => NadalVerdict::BelowLimit,
                (Some(_), None) if windows.complete == 0 => NadalVerdict::ShorterThanWindow,
                (Some(_), None) => NadalVerdict::NoValidWindow,
            };
            WheelNadal {
                wheel: name.to_string(),
                max_y_over_q: max.map(|(_, v)| v),
                max_at_s: max.and_then(|(i, _)| time_s.get(i).copied()),
                max_y_over_q_2m: windows.best.map(|(m, _)| m),
                max_2m_at_s: windows.best.and_then(|(_, i)| time_s.get(i).copied()),
                windows: windows.complete,
                valid_windows: windows.valid,
                airborne_samples: airborne as u64,
                airborne_fraction: if n > 0 {
                    airborne as f64 / n as f64
                } else {
                    0.0
                },
                flange_angle_deg: wheel.nadal.map(|l| l.flange_angle_rad.to_degrees()),
                friction: wheel.nadal.map(|l| l.friction),
                nadal_limit: limit,
                time_above_limit_s,
                verdict,
                derailment_risk: verdict == NadalVerdict::DerailmentRisk,
            }
        })
        .collect()
}

/// One line per wheelset: per wheel the largest Y/Q, the largest 2 m mean
/// with its valid windows, the airborne samples and the verdict.
pub fn nadal_text(name: &str, wheels: &[WheelNadal]) -> String {
    let mut s = format!("  wheelset {name}: Y/Q");
    for (k, w) in wheels.iter().enumerate() {
        let max = w
            .max_y_over_q
            .map_or("—".to_string(), |v| format!("{v:.3}"));
        let mean = w
            .max_y_over_q_2m
            .map_or("—".to_string(), |v| format!("{v:.3}"));
        let limit = w.nadal_limit.map_or("no flange".to_string(), |l| {
            format!(
                "Nadal limit {l:.3} at {:.1}°, μ {}",
                w.flange_angle_deg.unwrap_or(f64::NAN),
                w.friction.unwrap_or(f64::NAN)
            )
        });
        s += &format!(
            "{} {}: max {max}, 2 m mean {mean} ({} of {} windows valid), airborne {:.1} % of samples ({limit})",
            if k == 0 { "" } else { ";" },
            w.wheel,
            w.valid_windows,
            w.windows,
            100.0 * w.airborne_fraction,
        );
        match w.verdict {
            NadalVerdict::DerailmentRisk => {
                s += &format!(
                    " — DERAILMENT RISK: 2 m mean above the limit; samples above it for {:.3} s",
                    w.time_above_limit_s
                );
            }
            NadalVerdict::BelowLimit if w.time_above_limit_s > 0.0 => {
                s += &format!(
                    " — peaks above the limit for {:.3} s, 2 m mean below",
                    w.time_above_limit_s
                );
            }
            NadalVerdict::BelowLimit | NadalVerdict::NoFlange => {}
            NadalVerdict::NoValidWindow => {
                s += &format!(
                    " — {} (each needs ≥ {MIN_LOADED_SAMPLES} loaded samples, more than half of its samples)",
                    w.verdict.text()
                );
            }
            NadalVerdict::ShorterThanWindow => s += &format!(" — {}", w.verdict.text()),
        }
    }
    s + "\n"
}

#[cfg(test)]
mod tests {
    use super::*;
    use runtime::contact::nadal::NadalLimit;

    #[test]
    fn windows_average_the_loaded_samples() {
        // 0.5 m between samples: a window (d − 2 m, d] holds 4 samples.
        let d: Vec<f64> = (0..10).map(|k| 0.5 * k as f64).collect();
        let mut q: Vec<Option<f64>> = vec![Some(1.0); 10];
        q[6] = Some(6.0); // a spike: the windows holding it average (6 + 3·1)/4
        q[2] = None; // airborne: left out of its windows' means
        let w = sliding_windows(&q, &d, 2.0);
        let (m, _) = w.best.unwrap();
        assert!((m - 2.25).abs() < 1e-12, "{m}");
        // Windows end at samples 4 … 9 (2 m covered from sample 4 on).
        assert_eq!((w.complete, w.valid), (6, 6));
        // Shorter than the window: nothing to judge.
        assert_eq!(sliding_windows(&q[..3], &d[..3], 2.0).complete, 0);
        // Standstill: no window ever completes.
        assert_eq!(sliding_windows(&q, &[0.0; 10], 2.0), Windows::default());
    }

    #[test]
    fn a_mostly_airborne_window_is_not_valid() {
        // One loaded sample of 2.4 among airborne ones: before, the 2 m
        // "mean" was that sample alone and flagged a derailment risk.
        let d: Vec<f64> = (0..12).map(|k| 0.5 * k as f64).collect();
        let mut q: Vec<Option<f64>> = vec![None; 12];
        q[5] = Some(2.4);
        let w = sliding_windows(&q, &d, 2.0);
        assert_eq!(w.best, None);
        assert!(w.complete > 0 && w.valid == 0);
        // Two loaded of four: half in the air, not valid.
        q[6] = Some(0.4);
        assert_eq!(sliding_windows(&q, &d, 2.0).best, None);
        // Three of four: valid, the mean of the three.
        q[4] = Some(0.2);
        let w = sliding_windows(&q, &d, 2.0);
        assert!(w.best.is_some_and(|b| (b.0 - 1.0).abs() < 1e-12), "{w:?}");
        // Three of seven (a finer sampling): mostly airborne.
        let d: Vec<f64> = (0..12).map(|k| 0.3 * k as f64).collect();
        let w = sliding_windows(&q, &d, 2.0);
        assert_eq!(w.best, None, "{w:?}");
    }

    fn series(yq: &[f64], step_m: f64) -> (WheelsetSeries, Vec<f64>) {
        let mut w = WheelsetSeries::default();
        let n = yq.len();
        w.distance_m = (0..n).map(|k| step_m * k as f64).collect();
        for wheel in &mut w.wheels {
            wheel.q_n = yq
                .iter()
                .map(|v| if v.is_nan() { f64::NAN } else { 7000.0 })
                .collect();
            wheel.y_over_q = yq.to_vec();
            wheel.nadal = Some(NadalLimit {
                flange_angle_rad: 70f64.to_radians(),
                friction: 0.3,
                limit: 1.3416,
            });
        }
        let t = (0..n).map(|k| 0.005 * k as f64).collect();
        (w, t)
    }

    #[test]
    fn the_verdict_follows_the_valid_windows() {
        let nan = f64::NAN;
        // Airborne 3 samples of 4: one 2.4 sample is no verdict.
        let (w, t) = series(&[nan, 2.4, nan, nan, nan, 2.4, nan, nan, nan, 2.4], 0.5);
        let n = &nadal_summary(&w, &t)[0];
        assert_eq!(n.verdict, NadalVerdict::NoValidWindow);
        assert!(!n.derailment_risk);
        assert_eq!(n.max_y_over_q, Some(2.4));
        assert!((n.airborne_fraction - 0.7).abs() < 1e-12);
        assert_eq!(n.airborne_samples, 7);
        let text = nadal_text("front", &nadal_summary(&w, &t));
        assert!(text.contains("no valid 2 m window"), "{text}");
        assert!(text.contains("airborne 70.0 % of samples"), "{text}");
        // Loaded throughout, above the limit: a risk.
        let (w, t) = series(&[1.5; 10], 0.5);
        let n = &nadal_summary(&w, &t)[0];
        assert_eq!(n.verdict, NadalVerdict::DerailmentRisk);
        assert!(n.derailment_risk && n.valid_windows == n.windows && n.windows == 6);
        // A spike among low values: below.
        let mut v = [0.3; 10];
        v[5] = 3.0;
        let (w, t) = series(&v, 0.5);
        let n = &nadal_summary(&w, &t)[0];
        assert_eq!(n.verdict, NadalVerdict::BelowLimit);
        assert!(n.time_above_limit_s > 0.0);
        // Shorter than 2 m: no verdict, even above the limit.
        let (w, t) = series(&[2.0; 3], 0.5);
        assert_eq!(
            nadal_summary(&w, &t)[0].verdict,
            NadalVerdict::ShorterThanWindow
        );
        // Q = 0 counts as airborne even where a Y/Q value was written.
        let (mut w, t) = series(&[1.5; 10], 0.5);
        w.wheels[0].q_n = vec![0.0; 10];
        assert_eq!(nadal_summary(&w, &t)[0].airborne_samples, 10);
    }
}
