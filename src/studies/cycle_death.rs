//! Where a hunting limit cycle dies, per wheelset, and the nonlinear
//! critical speed of the vehicle by a criterion (`--criterion`,
//! docs/guide/critical-speed.md): the speed at which **every** wheelset's
//! cycle has died (`all`, the default: the leading wheelset can stop
//! hunting while the trailing bogie still hunts) or the leading
//! wheelset's alone (`leading`, the paper's definition, §5).
//!
//! The rule per wheelset (the same as the leading wheelset's before): the
//! cycle's saturated amplitude is the [`SATURATION_QUANTILE`] quantile of
//! its peak amplitudes of at least [`MIN_CYCLE_M`] (robust to the impacts
//! of the run-up, and to the many small peaks after an early death); the cycle
//! dies after the last peak of at least [`DEATH_FRACTION`] of it; a
//! saturated amplitude below [`MIN_CYCLE_M`] is no cycle.

use runtime::results::RunResults;
use serde::Serialize;

crate::config::choices::choice! {
    /// Which wheelsets' cycles must have died (`--criterion`; module docs).
    HuntingCriterion {
        /// Every wheelset's: the lowest death speed of all.
        All = "all",
        /// The leading wheelset's (the first in the vehicle file).
        Leading = "leading",
    }
}

/// Quantile of the peak amplitudes taken as the saturated amplitude
/// (0.9: the largest peaks are the run-up's flange impacts, not the cycle).
pub const SATURATION_QUANTILE: f64 = 0.9;

/// Fraction of the saturated amplitude below which the cycle has died
/// (0.25: the cycle's amplitude collapses through it within a few periods
/// at the fold, so the death speed hardly depends on it).
pub const DEATH_FRACTION: f64 = 0.25;

/// Saturated amplitude below which a wheelset has no limit cycle (m):
/// 0.1 mm, well below a flange-limited cycle (several mm) and well above
/// the integration noise.
pub const MIN_CYCLE_M: f64 = 1e-4;

/// One peak of a wheelset's lateral motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// When (s).
    pub t_s: f64,
    /// The references' speed then (m/s).
    pub speed_m_s: f64,
    /// |lateral| (m).
    pub amplitude_m: f64,
}

/// What became of one wheelset's cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CycleFate {
    /// It died at [`WheelsetDeath::death_m_s`].
    Died,
    /// It survives down to the lowest speed.
    Survives,
    /// There was no cycle (saturated amplitude below [`MIN_CYCLE_M`]).
    NoCycle,
}

impl CycleFate {
    pub fn as_str(self) -> &'static str {
        match self {
            CycleFate::Died => "died",
            CycleFate::Survives => "survives",
            CycleFate::NoCycle => "no_cycle",
        }
    }
}

/// The death of one wheelset's cycle (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WheelsetDeath {
    /// The wheelset's name in the vehicle.
    pub wheelset: String,
    /// Its index (0 = the leading one, vehicle order).
    pub index: usize,
    /// Saturated amplitude of its cycle (mm).
    pub saturated_mm: f64,
    /// Speed of the last peak of at least [`DEATH_FRACTION`] of it (m/s),
    /// when the cycle died above the lowest speed.
    pub death_m_s: Option<f64>,
    /// Time of that peak (s).
    pub death_time_s: Option<f64>,
    pub fate: CycleFate,
}

/// The death of one wheelset's cycle from its peaks in time order: it
/// survives when its last large peak is the last peak of all (nothing
/// smaller follows: the run ended first) or lies at `lowest_m_s` or below.
pub fn wheelset_death(
    wheelset: &str,
    index: usize,
    peaks: &[Peak],
    lowest_m_s: f64,
) -> WheelsetDeath {
    // The cycle's peaks only: a cycle that dies early in a long run leaves
    // far more decayed peaks (or dwells) than cycle peaks, and a quantile
    // over all of them would be one of the decayed ones.
    let mut amps: Vec<f64> = peaks
        .iter()
        .map(|p| p.amplitude_m)
        .filter(|a| *a >= MIN_CYCLE_M)
        .collect();
    amps.sort_by(f64::total_cmp);
    let saturated = amps
        .get((amps.len() as f64 * SATURATION_QUANTILE) as usize)
        .copied()
        .unwrap_or(0.0);
    let last = peaks
        .iter()
        .enumerate()
        .rev()
        .find(|(_, p)| p.amplitude_m >= DEATH_FRACTION * saturated);
    // A cycle whose last large peak is the run's last peak, or lies at the
    // lowest speed, has not died within the run.
    let (fate, death) = match last {
        // (A NaN amplitude is no cycle either.)
        _ if saturated.is_nan() || saturated < MIN_CYCLE_M => (CycleFate::NoCycle, None),
        Some((k, p)) if k + 1 < peaks.len() && p.speed_m_s > lowest_m_s + 1e-9 => {
            (CycleFate::Died, Some(*p))
        }
        _ => (CycleFate::Survives, None),
    };
    WheelsetDeath {
        wheelset: wheelset.to_string(),
        index,
        saturated_mm: saturated * 1e3,
        death_m_s: death.map(|p| p.speed_m_s),
        death_time_s: death.map(|p| p.t_s),
        fate,
    }
}

/// The nonlinear critical speed of the vehicle by a criterion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CycleDeaths {
    pub criterion: HuntingCriterion,
    /// Every wheelset, vehicle order.
    pub wheelsets: Vec<WheelsetDeath>,
    /// The speed at which the criterion's cycles have all died (m/s).
    pub speed_m_s: Option<f64>,
    /// The wheelset (by name) that hunts last: the one whose death gives
    /// `speed_m_s`, or one still hunting at the lowest speed.
    pub last_hunting: Option<String>,
    /// Index of that wheelset.
    pub last_hunting_index: Option<usize>,
    /// What happened when there is no speed.
    pub note: Option<String>,
}

/// Applies `criterion` to the wheelsets' deaths (module docs); `top_m_s`
/// and `lowest_m_s` (m/s) are the range, for the notes.
pub fn cycle_deaths(
    wheelsets: Vec<WheelsetDeath>,
    criterion: HuntingCriterion,
    top_m_s: f64,
    lowest_m_s: f64,
) -> CycleDeaths {
    let considered: Vec<&WheelsetDeath> = match criterion {
        HuntingCriterion::All => wheelsets
            .iter()
            .filter(|w| w.fate != CycleFate::NoCycle)
            .collect(),
        HuntingCriterion::Leading => wheelsets
            .iter()
            .take(1)
            .filter(|w| w.fate != CycleFate::NoCycle)
            .collect(),
    };
    let surviving = considered.iter().find(|w| w.fate == CycleFate::Survives);
    let last = considered
        .iter()
        .filter(|w| w.fate == CycleFate::Died)
        .min_by(|a, b| {
            a.death_m_s
                .unwrap_or(0.0)
                .total_cmp(&b.death_m_s.unwrap_or(0.0))
        });
    let (speed, who, note) = if considered.is_empty() {
        let whose = match criterion {
            HuntingCriterion::All => "of any wheelset",
            HuntingCriterion::Leading => "of the leading wheelset",
        };
        (
            None,
            None,
            Some(format!(
                "no limit cycle {whose} at {top_m_s} m/s: start the ramp above the linear critical speed"
            )),
        )
    } else if let Some(w) = surviving {
        (
            None,
            Some(*w),
            Some(format!(
                "the limit cycle of wheelset '{}' survives down to {lowest_m_s} m/s: nonlinear critical speed below it",
                w.wheelset
            )),
        )
    } else {
        (last.and_then(|w| w.death_m_s), last.copied(), None)
    };
    CycleDeaths {
        criterion,
        speed_m_s: speed,
        last_hunting: who.map(|w| w.wheelset.clone()),
        last_hunting_index: who.map(|w| w.index),
        note,
        wheelsets,
    }
}

/// The peaks of every wheelset's lateral motion in `r` (extrema refined by
/// a parabola, `critical_speed::extrema`), each at the speed
/// `speed_at(t)` (m/s), above `floor_m`.
pub fn wheelset_peaks(
    r: &RunResults,
    speed_at: &dyn Fn(f64) -> f64,
    floor_m: f64,
) -> Vec<Vec<Peak>> {
    r.wheelsets
        .iter()
        .map(|w| {
            super::critical_speed::extrema(&r.time_s, &w.lateral_m)
                .into_iter()
                .filter(|(_, a)| *a > floor_m)
                .map(|(t_s, amplitude_m)| Peak {
                    t_s,
                    speed_m_s: speed_at(t_s),
                    amplitude_m,
                })
                .collect()
        })
        .collect()
}

/// The deaths of a ramp-down run `r` from `top_m_s` to `lowest_m_s` at
/// `deceleration_m_s2` (V = top − a t), by `criterion`; also the peaks.
pub fn ramp_deaths(
    r: &RunResults,
    top_m_s: f64,
    lowest_m_s: f64,
    deceleration_m_s2: f64,
    criterion: HuntingCriterion,
) -> (CycleDeaths, Vec<Vec<Peak>>) {
    let speed_at = |t: f64| (top_m_s - deceleration_m_s2 * t).max(0.0);
    let peaks = wheelset_peaks(r, &speed_at, 0.0);
    let deaths = r
        .wheelsets
        .iter()
        .zip(&peaks)
        .enumerate()
        .map(|(i, (w, p))| wheelset_death(&w.name, i, p, lowest_m_s))
        .collect();
    (cycle_deaths(deaths, criterion, top_m_s, lowest_m_s), peaks)
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use runtime::results::WheelsetSample;

    /// A ramp from 100 m/s at 0.5 m/s² over 100 s (down to 50 m/s): every
    /// wheelset hunts at 5 mm and 3 Hz until `dies_at_s` (its own), then
    /// its cycle decays with a rate of 3 1/s.
    pub(crate) fn two_wheelset_ramp(dies_at_s: [f64; 2]) -> RunResults {
        let mut r = RunResults::with_wheelsets(["front", "rear"]);
        for i in 0..10_000 {
            let t = i as f64 * 0.01;
            let y = |death: f64| {
                let decay = if t > death {
                    (-3.0 * (t - death)).exp()
                } else {
                    1.0
                };
                0.005 * decay * (std::f64::consts::TAU * 3.0 * t).sin()
            };
            let sample = |death| WheelsetSample {
                lateral_m: y(death),
                ..Default::default()
            };
            r.push(t, &[sample(dies_at_s[0]), sample(dies_at_s[1])])
                .unwrap();
        }
        r
    }

    #[test]
    fn every_wheelset_or_the_leading_one() {
        // The leading cycle dies at 40 s (80 m/s), the trailing one at
        // 60 s (70 m/s); a peak of 5 mm e^{−3τ} falls below 1.25 mm
        // within τ = ln 4 / 3 = 0.46 s (0.23 m/s).
        let r = two_wheelset_ramp([40.0, 60.0]);
        let (all, _) = ramp_deaths(&r, 100.0, 50.0, 0.5, HuntingCriterion::All);
        let v = all.speed_m_s.unwrap();
        assert!((69.7..=70.0).contains(&v), "{all:?}");
        assert_eq!(all.last_hunting.as_deref(), Some("rear"));
        assert_eq!(all.last_hunting_index, Some(1));
        let front = all.wheelsets[0].death_m_s.unwrap();
        assert!((79.7..=80.0).contains(&front), "{all:?}");
        assert!((all.wheelsets[0].saturated_mm - 5.0).abs() < 0.05);
        assert_eq!(all.wheelsets[1].fate, CycleFate::Died);
        let (leading, _) = ramp_deaths(&r, 100.0, 50.0, 0.5, HuntingCriterion::Leading);
        assert_eq!(leading.speed_m_s, Some(front));
        assert_eq!(leading.last_hunting.as_deref(), Some("front"));
        // Both still list every wheelset.
        assert_eq!(leading.wheelsets, all.wheelsets);
    }

    #[test]
    fn a_cycle_that_survives_or_never_was() {
        // The trailing cycle never dies: no speed, and the note names it.
        let r = two_wheelset_ramp([40.0, 1e9]);
        let (all, _) = ramp_deaths(&r, 100.0, 50.0, 0.5, HuntingCriterion::All);
        assert_eq!(all.speed_m_s, None);
        assert_eq!(all.wheelsets[1].fate, CycleFate::Survives);
        assert!(
            all.note
                .as_deref()
                .unwrap()
                .contains("'rear' survives down to 50 m/s"),
            "{all:?}"
        );
        let (leading, _) = ramp_deaths(&r, 100.0, 50.0, 0.5, HuntingCriterion::Leading);
        assert!(leading.speed_m_s.is_some());
        // No cycle at all.
        let r = two_wheelset_ramp([-10.0, -10.0]);
        let (all, _) = ramp_deaths(&r, 100.0, 50.0, 0.5, HuntingCriterion::All);
        assert_eq!(all.speed_m_s, None);
        assert!(all.note.unwrap().contains("no limit cycle of any wheelset"));
        assert!(all.wheelsets.iter().all(|w| w.fate == CycleFate::NoCycle));
    }

    #[test]
    fn an_early_death_in_a_long_run_is_found() {
        // 16 dwells of a 4 mm cycle, then 145 dwells of a decayed motion
        // (µm and below, each above the plotting floor): the saturated
        // amplitude is the cycle's, not a decayed dwell's, so the cycle
        // dies at the 16th dwell's speed.
        let peaks: Vec<Peak> = (0..161)
            .map(|k| Peak {
                t_s: 11.0 * k as f64,
                speed_m_s: 120.0 - 0.5 * k as f64,
                amplitude_m: if k < 16 { 4e-3 } else { 1e-6 / (k as f64) },
            })
            .collect();
        let d = wheelset_death("front", 0, &peaks, 40.0);
        assert_eq!(d.fate, CycleFate::Died);
        assert_eq!(d.death_m_s, Some(112.5));
        assert!((d.saturated_mm - 4.0).abs() < 1e-12);
    }

    #[test]
    fn criteria_parse_from_the_command_line() {
        assert_eq!("all".parse::<HuntingCriterion>(), Ok(HuntingCriterion::All));
        assert_eq!(
            "leading".parse::<HuntingCriterion>(),
            Ok(HuntingCriterion::Leading)
        );
        assert!(
            "last"
                .parse::<HuntingCriterion>()
                .unwrap_err()
                .contains("not one of all, leading")
        );
    }
}
