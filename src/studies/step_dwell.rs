//! The step-and-dwell continuation of the hunting limit cycle (`sim
//! bifurcation --continuation step-dwell`, docs/guide/critical-speed.md):
//! one run from the hunting state at the top speed whose references hold
//! each speed max, max − Δv, … down to min for a dwell, joined by short
//! ramps at the ramp deceleration (a piecewise-linear `[initial]
//! speed_profile`, docs/reference/10-scene-files.md); per dwell and per
//! wheelset the cycle's amplitude is the largest |lateral| over the
//! dwell's second half (the first half lets the cycle settle after the
//! step; the usual way bifurcation diagrams are made).

use anyhow::{Result, bail};
use runtime::results::RunResults;
use serde::Serialize;

use crate::config::Variation;
use crate::config::scene::LoadedScene;
use crate::studies::cycle_death::{
    CycleDeaths, HuntingCriterion, Peak, cycle_deaths, wheelset_death,
};

/// One dwell of the schedule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Dwell {
    /// The speed held (m/s).
    pub speed_m_s: f64,
    /// Start and end of the dwell (s).
    pub from_s: f64,
    pub to_s: f64,
}

/// The speed schedule of a continuation: its knots `[t_s, speed_m_s]`
/// (as `[initial] speed_profile` takes them) and its dwells.
#[derive(Debug, Clone, PartialEq)]
pub struct StepDwellSchedule {
    pub knots: Vec<[f64; 2]>,
    pub dwells: Vec<Dwell>,
}

impl StepDwellSchedule {
    /// The schedule's end (s).
    pub fn duration_s(&self) -> f64 {
        self.knots.last().map_or(0.0, |k| k[0])
    }
}

/// The schedule from `max_m_s` down to `min_m_s` in steps of `step_m_s`
/// (the last step shorter if the range is not a whole number of steps),
/// each speed held `dwell_s`, the steps ramped at `deceleration_m_s2`
/// (a step of Δv takes Δv/a).
pub fn schedule(
    max_m_s: f64,
    min_m_s: f64,
    step_m_s: f64,
    dwell_s: f64,
    deceleration_m_s2: f64,
) -> Result<StepDwellSchedule> {
    let ok = |v: f64| v.is_finite() && v > 0.0;
    if !(ok(min_m_s) && max_m_s.is_finite() && max_m_s > min_m_s) {
        bail!("step-dwell speed range {min_m_s} … {max_m_s} m/s: need 0 < min < max");
    }
    if !(ok(step_m_s) && ok(dwell_s) && ok(deceleration_m_s2)) {
        bail!(
            "step-dwell: speed step {step_m_s} m/s, dwell {dwell_s} s and deceleration {deceleration_m_s2} m/s² must be finite and > 0"
        );
    }
    // The number of whole steps (a range within 1e-9 of a whole number
    // of steps counts as one).
    let n = ((max_m_s - min_m_s) / step_m_s + 1e-9).floor() as usize;
    let mut speeds: Vec<f64> = (0..=n).map(|k| max_m_s - step_m_s * k as f64).collect();
    if speeds.last().is_some_and(|v| *v > min_m_s + 1e-9) {
        speeds.push(min_m_s);
    }
    let mut knots = Vec::new();
    let mut dwells = Vec::new();
    let mut t = 0.0;
    for (k, v) in speeds.iter().copied().enumerate() {
        if k > 0 {
            t += (speeds[k - 1] - v) / deceleration_m_s2;
        }
        knots.push([t, v]);
        dwells.push(Dwell {
            speed_m_s: v,
            from_s: t,
            to_s: t + dwell_s,
        });
        t += dwell_s;
        knots.push([t, v]);
    }
    Ok(StepDwellSchedule { knots, dwells })
}

/// One dwell's amplitude of one wheelset.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DwellAmplitude {
    pub wheelset: String,
    pub wheelset_index: usize,
    /// The dwell's speed (m/s).
    pub speed_m_s: f64,
    /// Largest |lateral| over the dwell's second half (mm); NaN when the
    /// run ended before it (a derailment).
    pub amplitude_mm: f64,
}

/// Per wheelset (vehicle order) and per dwell (schedule order), the
/// largest |lateral| over the dwell's second half; dwells the run did not
/// reach in full are left out.
pub fn dwell_amplitudes(r: &RunResults, dwells: &[Dwell]) -> Vec<Vec<DwellAmplitude>> {
    let t_end = r.time_s.last().copied().unwrap_or(0.0);
    r.wheelsets
        .iter()
        .enumerate()
        .map(|(i, w)| {
            dwells
                .iter()
                .filter(|d| d.to_s <= t_end + 1e-9)
                .map(|d| {
                    let from = 0.5 * (d.from_s + d.to_s);
                    let amp = r
                        .time_s
                        .iter()
                        .zip(&w.lateral_m)
                        .filter(|(t, _)| **t >= from - 1e-9 && **t <= d.to_s + 1e-9)
                        .fold(0.0_f64, |m, (_, y)| m.max(y.abs()));
                    DwellAmplitude {
                        wheelset: w.name.clone(),
                        wheelset_index: i,
                        speed_m_s: d.speed_m_s,
                        amplitude_mm: amp * 1e3,
                    }
                })
                .collect()
        })
        .collect()
}

/// The cycle deaths of a step-dwell run by `criterion`: the dwells'
/// amplitudes are the peaks of the rule of [`crate::studies::cycle_death`].
pub fn dwell_deaths(
    amplitudes: &[Vec<DwellAmplitude>],
    dwells: &[Dwell],
    criterion: HuntingCriterion,
    max_m_s: f64,
    min_m_s: f64,
) -> CycleDeaths {
    let deaths = amplitudes
        .iter()
        .enumerate()
        .map(|(i, amps)| {
            let peaks: Vec<Peak> = amps
                .iter()
                .zip(dwells)
                .map(|(a, d)| Peak {
                    t_s: d.to_s,
                    speed_m_s: a.speed_m_s,
                    amplitude_m: a.amplitude_mm * 1e-3,
                })
                .collect();
            let name = amps.first().map_or(String::new(), |a| a.wheelset.clone());
            wheelset_death(&name, i, &peaks, min_m_s)
        })
        .collect();
    cycle_deaths(deaths, criterion, max_m_s, min_m_s)
}

/// Longest ideal straight, in intervals of its table, that a continuation
/// builds at the scene's step (a straight of ~80 km at 0.1 m would hold
/// 2.4 million rows of three tables): beyond it the step is made a whole
/// multiple of the scene's, which changes nothing on an ideal straight
/// (its tables are interpolated linearly, exact on a straight line).
pub const MAX_STRAIGHT_INTERVALS: f64 = 1e5;

/// The track step for an ideal straight of `length_m` (m): the scene's, or
/// a coarser whole multiple of it ([`MAX_STRAIGHT_INTERVALS`]) with the
/// note that says so. At most 5 m (the scene's bound).
pub fn straight_step(scene: &LoadedScene, length_m: f64) -> Option<(f64, String)> {
    let step = scene.scene.track.step_m;
    if length_m / step <= MAX_STRAIGHT_INTERVALS {
        return None;
    }
    let coarse = ((length_m / MAX_STRAIGHT_INTERVALS / step).ceil() * step).min(5.0);
    Some((
        coarse,
        format!(
            "the step-dwell straight of {:.1} km is tabulated at track.step_m = {coarse} m instead of the scene's {step} m (at most {MAX_STRAIGHT_INTERVALS:e} intervals; exact on an ideal straight)",
            length_m / 1e3
        ),
    ))
}

/// The variations of a step-dwell run: the schedule as the references'
/// speed profile for its whole duration on an ideal straight long enough,
/// and the note of a coarsened track step.
pub fn variations(
    scene: &LoadedScene,
    sched: &StepDwellSchedule,
) -> Result<(Vec<Variation>, Option<String>)> {
    let profile = runtime::multibody::speed_profile::SpeedSchedule::new(
        sched
            .knots
            .iter()
            .map(
                |[t_s, speed_m_s]| runtime::multibody::speed_profile::SpeedKnot {
                    t_s: *t_s,
                    speed_m_s: *speed_m_s,
                },
            )
            .collect(),
    );
    let duration = sched.duration_s();
    let distance = profile.distance_m(duration);
    let length = distance + scene.scene.initial.s_m + 100.0;
    let top = sched.knots.first().map_or(0.0, |k| k[1]);
    let knots = toml::Value::Array(
        sched
            .knots
            .iter()
            .map(|[t, v]| toml::Value::Array(vec![toml::Value::Float(*t), toml::Value::Float(*v)]))
            .collect(),
    );
    let mut out = vec![
        Variation::Speed(top),
        Variation::Set("initial.speed_profile".into(), knots),
        Variation::Set("run.duration_s".into(), toml::Value::Float(duration)),
        Variation::StraightTrack(length),
    ];
    let i = &scene.scene.initial;
    for (key, set) in [
        ("initial.deceleration_m_s2", i.deceleration_m_s2 != 0.0),
        ("initial.acceleration_m_s2", i.acceleration_m_s2 != 0.0),
        ("initial.final_speed_m_s", i.final_speed_m_s.is_some()),
        ("run.distance_m", scene.scene.run.distance_m.is_some()),
    ] {
        if set {
            out.push(Variation::Remove(key.into()));
        }
    }
    out.extend(Variation::track_inputs_removed(&scene.scene));
    let note = straight_step(scene, length).map(|(step, note)| {
        out.push(Variation::Set(
            "track.step_m".into(),
            toml::Value::Float(step),
        ));
        note
    });
    Ok((out, note))
}

#[cfg(test)]
mod tests {
    use super::*;
    use runtime::results::WheelsetSample;

    #[test]
    fn the_schedule_holds_each_step_and_ramps_between() {
        let s = schedule(2.0, 1.0, 0.5, 10.0, 0.5).unwrap();
        assert_eq!(
            s.knots,
            vec![
                [0.0, 2.0],
                [10.0, 2.0],
                [11.0, 1.5],
                [21.0, 1.5],
                [22.0, 1.0],
                [32.0, 1.0]
            ]
        );
        let spans: Vec<(f64, f64, f64)> = s
            .dwells
            .iter()
            .map(|d| (d.speed_m_s, d.from_s, d.to_s))
            .collect();
        assert_eq!(
            spans,
            vec![(2.0, 0.0, 10.0), (1.5, 11.0, 21.0), (1.0, 22.0, 32.0)]
        );
        assert_eq!(s.duration_s(), 32.0);
        // A range that is not a whole number of steps ends at min.
        let s = schedule(2.0, 1.2, 0.5, 10.0, 0.5).unwrap();
        // (the last step of 0.3 m/s takes 0.6 s.)
        assert!((s.knots[4][0] - 21.6).abs() < 1e-12 && s.knots[4][1] == 1.2);
        assert_eq!(s.knots.len(), 6);
        assert!(schedule(1.0, 2.0, 0.5, 10.0, 0.5).is_err());
        assert!(schedule(2.0, 1.0, 0.0, 10.0, 0.5).is_err());
    }

    #[test]
    fn a_dwell_amplitude_is_the_largest_over_its_second_half() {
        // Two dwells of the schedule above (max 2, min 1.5): the front
        // wheelset has a 9 mm spike in the first half of the first dwell
        // (ignored) and 4 mm in its second half, 1 mm in the second dwell;
        // the rear 2 mm then 3 mm.
        let s = schedule(2.0, 1.5, 0.5, 10.0, 0.5).unwrap();
        let mut r = RunResults::with_wheelsets(["front", "rear"]);
        for i in 0..=2100 {
            let t = i as f64 * 0.01;
            let osc = (std::f64::consts::TAU * 2.0 * t).sin();
            let (front, rear) = if t < 2.0 {
                (0.009 * osc, 0.002 * osc)
            } else if t <= 10.0 {
                (0.004 * osc, 0.002 * osc)
            } else {
                (0.001 * osc, 0.003 * osc)
            };
            let w = |y| WheelsetSample {
                lateral_m: y,
                ..Default::default()
            };
            r.push(t, &[w(front), w(rear)]).unwrap();
        }
        let a = dwell_amplitudes(&r, &s.dwells);
        let mm = |ws: usize| -> Vec<f64> { a[ws].iter().map(|d| d.amplitude_mm).collect() };
        let close = |got: Vec<f64>, want: [f64; 2]| {
            got.len() == 2 && got.iter().zip(want).all(|(g, w)| (g - w).abs() < 0.01)
        };
        assert!(close(mm(0), [4.0, 1.0]), "{a:?}");
        assert!(close(mm(1), [2.0, 3.0]), "{a:?}");
        assert_eq!(a[1][1].wheelset, "rear");
        assert_eq!(a[1][1].speed_m_s, 1.5);
        // A run that ended within the second dwell: only the first.
        let mut short = r.clone();
        let keep = 1500;
        short.time_s.truncate(keep);
        for w in &mut short.wheelsets {
            w.lateral_m.truncate(keep);
        }
        assert_eq!(dwell_amplitudes(&short, &s.dwells)[0].len(), 1);
    }

    #[test]
    fn dwell_deaths_by_the_criterion() {
        // Dwells 100, 90, 80, 70, 60 m/s; front hunts (5 mm) down to 90,
        // rear down to 70.
        let s = schedule(100.0, 60.0, 10.0, 10.0, 0.5).unwrap();
        let amp = |ws: usize, last: f64| -> Vec<DwellAmplitude> {
            s.dwells
                .iter()
                .map(|d| DwellAmplitude {
                    wheelset: ["front", "rear"][ws].into(),
                    wheelset_index: ws,
                    speed_m_s: d.speed_m_s,
                    amplitude_mm: if d.speed_m_s >= last { 5.0 } else { 0.01 },
                })
                .collect()
        };
        let a = vec![amp(0, 90.0), amp(1, 70.0)];
        let all = dwell_deaths(&a, &s.dwells, HuntingCriterion::All, 100.0, 60.0);
        assert_eq!(all.speed_m_s, Some(70.0));
        assert_eq!(all.last_hunting.as_deref(), Some("rear"));
        let lead = dwell_deaths(&a, &s.dwells, HuntingCriterion::Leading, 100.0, 60.0);
        assert_eq!(lead.speed_m_s, Some(90.0));
        assert_eq!(lead.last_hunting.as_deref(), Some("front"));
    }
}
