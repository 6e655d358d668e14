//! The running-safety and wear figures of one wheelset over a whole run:
//! the track shifting force ΣY against Prud'homme's limit, the wheel
//! unloading ΔQ/Q0, the angle of attack and the wear number Tγ
//! (docs/guide/curving-and-safety.md).
//!
//! - **Static loads**: P, the static axle load, is the mean of
//!   Q_left + Q_right (a wheel without contact counts 0) over the samples of
//!   the run's first [`STATIC_LOAD_WINDOW_M`] = 2 m; Q0 = P/2 is the
//!   static wheel load of either wheel. Every wheelset is settled under
//!   its static wheel load before the run (docs/reference/08-multibody.md
//!   §8.3), so on a straight start these are the vehicle's static loads as
//!   the run itself measures them. A run that starts inside a curve starts
//!   away from its quasi-static state there (the bodies start at their
//!   assembly positions, §8.3): P is then the mean over the first
//!   transient, and the sum along the track's up axis differs from the
//!   level-track load by the cant's cos φ and the centrifugal force's
//!   sin φ (under 1 % for 150 mm of cant). Start on the straight before
//!   the curve for the vehicle's static loads.
//! - **Prud'homme** (Prud'homme 1970, "La résistance de la voie aux efforts
//!   transversaux exercés par le matériel roulant", Revue générale des
//!   chemins de fer; EN 14363:2016 §7.6 with the limit
//!   (ΣY_2m)_lim = α (10 + 2 Q0 / 3) kN = α (10 + P/3) kN, α = 1 for
//!   locomotives, multiple units and passenger vehicles, 0.85 for freight
//!   wagons): here α = [`PRUDHOMME_ALPHA`] = 1, the original form
//!   10 + P/3 kN. Assessed on the 2 m sliding mean of ΣY
//!   ([`super::windows`]), its magnitude (a wheelset shifting the track
//!   either way).
//! - **Wheel unloading** ΔQ/Q0 = (Q0 − Q)/Q0 per wheel (a wheel without
//!   contact has Q = 0: ΔQ/Q0 = 1), against [`UNLOADING_LIMIT`] = 0.6
//!   (EN 14363:2016, the wheel-unloading limit of the safety against
//!   derailment on twisted track, ΔQ/Q0 ≤ 0.6), assessed on its 2 m
//!   sliding mean (the twist test's loads are quasi-static; a single
//!   sample's unloading is reported beside it).
//! - **Angle of attack**: the wheelset's yaw relative to the track tangent
//!   at its section (the results' `yaw_rad`), mrad, + nose left.
//! - **Wear**: Tγ of each wheel (N, the results' `wear_number_n`), its
//!   mean and maximum over the samples in contact. The wear index used is
//!   this per-wheel Tγ (N): the results do not store the contact ellipse's
//!   semi-axes, so the BRR/Pearce & Sherratt index Tγ/A (N/mm²) is not
//!   formed.

use runtime::results::{WHEEL_GROUPS, WheelsetSeries};
use serde::Serialize;

use super::windows::sliding_means;
use crate::run::nadal::NADAL_WINDOW_M;

/// Length of the run's start over which the static loads are measured (m).
pub const STATIC_LOAD_WINDOW_M: f64 = 2.0;
/// α of Prud'homme's limit α (10 + P/3) kN (module docs).
pub const PRUDHOMME_ALPHA: f64 = 1.0;
/// Limit of ΔQ/Q0 (module docs).
pub const UNLOADING_LIMIT: f64 = 0.6;
/// The criteria as the summaries name them.
pub const PRUDHOMME_CRITERION: &str =
    "Prud'homme: 2 m mean of |ΣY| ≤ α (10 + P/3) kN, α = 1 (EN 14363 §7.6)";
pub const UNLOADING_CRITERION: &str = "wheel unloading: 2 m mean of ΔQ/Q0 ≤ 0.6 (EN 14363)";

/// What a 2 m criterion says.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SafetyVerdict {
    /// A valid window's mean exceeds the limit.
    AboveLimit,
    /// Valid windows exist; none exceeds the limit.
    BelowLimit,
    /// The run covered less than 2 m.
    ShorterThanWindow,
    /// Complete windows exist, none valid.
    NoValidWindow,
    /// No static load could be measured (no contact in the first 2 m).
    NoStaticLoad,
}

impl SafetyVerdict {
    /// A few words for the text summary.
    pub fn text(self) -> &'static str {
        match self {
            SafetyVerdict::AboveLimit => "ABOVE THE LIMIT",
            SafetyVerdict::BelowLimit => "below the limit",
            SafetyVerdict::ShorterThanWindow => "no verdict: the run covered less than 2 m",
            SafetyVerdict::NoValidWindow => "no verdict: no valid 2 m window",
            SafetyVerdict::NoStaticLoad => "no verdict: no static load measured",
        }
    }
}

/// Prud'homme's criterion for one wheelset (module docs).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Prudhomme {
    pub criterion: &'static str,
    pub alpha: f64,
    /// α (10 + P/3) (kN).
    pub limit_kn: Option<f64>,
    /// Largest |ΣY| of a sample (kN) and its track position (m).
    pub max_abs_sum_y_kn: Option<f64>,
    pub max_at_track_s_m: Option<f64>,
    /// Largest |2 m mean of ΣY| (kN) and the track position of its
    /// window's end (m).
    pub max_abs_sum_y_2m_kn: Option<f64>,
    pub max_2m_at_track_s_m: Option<f64>,
    pub windows: u64,
    pub valid_windows: u64,
    pub verdict: SafetyVerdict,
}

/// Wheel unloading of one wheel (module docs).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelUnloading {
    pub wheel: String,
    pub criterion: &'static str,
    pub limit: f64,
    /// Largest ΔQ/Q0 of a sample and its track position (m).
    pub max_delta_q_over_q0: Option<f64>,
    pub max_at_track_s_m: Option<f64>,
    /// Largest 2 m mean of ΔQ/Q0 and its window's end (m).
    pub max_delta_q_over_q0_2m: Option<f64>,
    pub max_2m_at_track_s_m: Option<f64>,
    pub verdict: SafetyVerdict,
}

/// Tγ of one wheel over the run (N).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelWear {
    pub wheel: String,
    /// Mean and largest Tγ over the samples in contact (N); the mean is
    /// the wear index used (module docs).
    pub mean_wear_number_n: Option<f64>,
    pub max_wear_number_n: Option<f64>,
    /// Mean Tγ of the tread and the flange zone over the samples each is
    /// in contact (N).
    pub tread_mean_n: Option<f64>,
    pub flange_mean_n: Option<f64>,
}

/// The safety and wear figures of one wheelset (module docs).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelsetSafety {
    /// P, the static axle load (kN), the samples it is the mean of, and
    /// how it was obtained.
    pub static_axle_load_kn: Option<f64>,
    pub static_load_samples: u64,
    pub static_load_source: &'static str,
    pub prudhomme: Prudhomme,
    /// Left, right.
    pub unloading: Vec<WheelUnloading>,
    /// Largest |angle of attack| (mrad, signed value: + nose left) and its
    /// track position (m).
    pub max_angle_of_attack_mrad: Option<f64>,
    pub max_angle_of_attack_at_track_s_m: Option<f64>,
    /// Left, right.
    pub wear: Vec<WheelWear>,
}

const STATIC_SOURCE: &str = "mean of Q_left + Q_right over the run's first 2 m";

/// The track position of sample `i`: `track_s_m`, or the distance
/// travelled where it is unknown (older files).
pub fn position_m(w: &WheelsetSeries, i: usize) -> Option<f64> {
    let s = w.track_s_m.get(i).copied().filter(|s| s.is_finite());
    s.or_else(|| w.distance_m.get(i).copied())
}

/// Zero for a value out of contact (NaN).
fn or_zero(v: f64) -> f64 {
    if v.is_finite() { v } else { 0.0 }
}

/// P (N) and the number of samples it is the mean of (module docs).
pub fn static_axle_load_n(w: &WheelsetSeries) -> Option<(f64, usize)> {
    let d0 = *w.distance_m.first()?;
    let mut sum = 0.0;
    let mut n = 0;
    for (i, d) in w.distance_m.iter().enumerate() {
        // A NaN distance ends the start too.
        let in_start = d - d0 <= STATIC_LOAD_WINDOW_M;
        if !in_start {
            break;
        }
        let (l, r) = (w.wheels[0].q_n.get(i)?, w.wheels[1].q_n.get(i)?);
        if l.is_finite() || r.is_finite() {
            sum += or_zero(*l) + or_zero(*r);
            n += 1;
        }
    }
    (n > 0 && sum > 0.0).then(|| (sum / n as f64, n))
}

/// Index of the largest `key` among `Some` values.
fn arg_max(v: &[Option<f64>], key: impl Fn(f64) -> f64) -> Option<(usize, f64)> {
    v.iter()
        .enumerate()
        .filter_map(|(i, x)| x.map(|x| (i, x)))
        .max_by(|a, b| key(a.1).total_cmp(&key(b.1)))
}

/// The verdict of a criterion from its windows' means.
fn verdict(means: &[Option<f64>], covered: bool, worst: Option<f64>, limit: f64) -> SafetyVerdict {
    match worst {
        Some(m) if m > limit => SafetyVerdict::AboveLimit,
        Some(_) => SafetyVerdict::BelowLimit,
        None if !covered || means.is_empty() => SafetyVerdict::ShorterThanWindow,
        None => SafetyVerdict::NoValidWindow,
    }
}

/// Complete 2 m windows: one ending at each sample once 2 m are covered.
pub fn complete_windows(w: &WheelsetSeries) -> u64 {
    let Some(&d0) = w.distance_m.first() else {
        return 0;
    };
    w.distance_m
        .iter()
        .filter(|d| *d - d0 >= NADAL_WINDOW_M)
        .count() as u64
}

/// The run covered a 2 m window.
fn covered(w: &WheelsetSeries) -> bool {
    match (w.distance_m.first(), w.distance_m.last()) {
        (Some(a), Some(b)) => b - a >= NADAL_WINDOW_M,
        _ => false,
    }
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = v
        .filter(|x| x.is_finite())
        .fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| s / n as f64)
}

fn max(v: impl Iterator<Item = f64>) -> Option<f64> {
    v.filter(|x| x.is_finite()).reduce(f64::max)
}

/// The safety and wear figures of a wheelset's series (module docs).
pub fn wheelset_safety(w: &WheelsetSeries) -> WheelsetSafety {
    let n = w.distance_m.len();
    let pos = |i: Option<usize>| i.and_then(|i| position_m(w, i));
    let covered = covered(w);
    let load = static_axle_load_n(w);
    // ΣY.
    let sum_y: Vec<Option<f64>> = (0..n)
        .map(|i| w.sum_y_n.get(i).copied().filter(|v| v.is_finite()))
        .collect();
    let means = sliding_means(&sum_y, &w.distance_m, NADAL_WINDOW_M);
    let worst_2m = arg_max(&means, f64::abs);
    let worst = arg_max(&sum_y, f64::abs);
    let limit_kn = load.map(|(p, _)| PRUDHOMME_ALPHA * (10.0 + p / 1e3 / 3.0));
    let prudhomme = Prudhomme {
        criterion: PRUDHOMME_CRITERION,
        alpha: PRUDHOMME_ALPHA,
        limit_kn,
        max_abs_sum_y_kn: worst.map(|(_, v)| v.abs() / 1e3),
        max_at_track_s_m: pos(worst.map(|(i, _)| i)),
        max_abs_sum_y_2m_kn: worst_2m.map(|(_, v)| v.abs() / 1e3),
        max_2m_at_track_s_m: pos(worst_2m.map(|(i, _)| i)),
        windows: complete_windows(w),
        valid_windows: means.iter().flatten().count() as u64,
        verdict: match limit_kn {
            None => SafetyVerdict::NoStaticLoad,
            Some(l) => verdict(&means, covered, worst_2m.map(|(_, v)| v.abs() / 1e3), l),
        },
    };
    // ΔQ/Q0.
    let unloading = w
        .wheels
        .iter()
        .zip(WHEEL_GROUPS)
        .map(|(wheel, name)| {
            let q0 = load.map(|(p, _)| p / 2.0);
            let ratio: Vec<Option<f64>> = (0..n)
                .map(|i| {
                    let q = or_zero(wheel.q_n.get(i).copied().unwrap_or(f64::NAN));
                    q0.map(|q0| (q0 - q) / q0)
                })
                .collect();
            let means = sliding_means(&ratio, &w.distance_m, NADAL_WINDOW_M);
            let worst = arg_max(&ratio, |v| v);
            let worst_2m = arg_max(&means, |v| v);
            WheelUnloading {
                wheel: name.to_string(),
                criterion: UNLOADING_CRITERION,
                limit: UNLOADING_LIMIT,
                max_delta_q_over_q0: worst.map(|(_, v)| v),
                max_at_track_s_m: pos(worst.map(|(i, _)| i)),
                max_delta_q_over_q0_2m: worst_2m.map(|(_, v)| v),
                max_2m_at_track_s_m: pos(worst_2m.map(|(i, _)| i)),
                verdict: match q0 {
                    None => SafetyVerdict::NoStaticLoad,
                    Some(_) => verdict(&means, covered, worst_2m.map(|(_, v)| v), UNLOADING_LIMIT),
                },
            }
        })
        .collect();
    let aoa: Vec<Option<f64>> = w
        .yaw_rad
        .iter()
        .map(|v| v.is_finite().then_some(v * 1e3))
        .collect();
    let aoa_max = arg_max(&aoa, f64::abs);
    let wear = w
        .wheels
        .iter()
        .zip(WHEEL_GROUPS)
        .map(|(wheel, name)| WheelWear {
            wheel: name.to_string(),
            mean_wear_number_n: mean(wheel.wear_number_n.iter().copied()),
            max_wear_number_n: max(wheel.wear_number_n.iter().copied()),
            tread_mean_n: mean(wheel.zones[0].wear_number_n.iter().copied()),
            flange_mean_n: mean(wheel.zones[1].wear_number_n.iter().copied()),
        })
        .collect();
    WheelsetSafety {
        static_axle_load_kn: load.map(|(p, _)| p / 1e3),
        static_load_samples: load.map_or(0, |(_, k)| k as u64),
        static_load_source: STATIC_SOURCE,
        prudhomme,
        unloading,
        max_angle_of_attack_mrad: aoa_max.map(|(_, v)| v),
        max_angle_of_attack_at_track_s_m: pos(aoa_max.map(|(i, _)| i)),
        wear,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wheelset at 0.5 m per sample: Q = 50 kN on both wheels, ΣY and
    /// the left wheel's Q as given from sample 4 (past the first 2 m).
    fn series(n: usize, sum_y_n: f64, q_left_n: f64) -> WheelsetSeries {
        let mut w = WheelsetSeries::new("front");
        w.distance_m = (0..n).map(|k| 0.5 * k as f64).collect();
        w.track_s_m = w.distance_m.iter().map(|d| 100.0 + d).collect();
        w.yaw_rad = (0..n).map(|k| if k == 7 { -4e-3 } else { 1e-3 }).collect();
        w.sum_y_n = (0..n).map(|k| if k < 5 { 0.0 } else { sum_y_n }).collect();
        for (side, wheel) in w.wheels.iter_mut().enumerate() {
            wheel.q_n = (0..n)
                .map(|k| if k >= 5 && side == 0 { q_left_n } else { 50e3 })
                .collect();
            wheel.wear_number_n = (0..n).map(|k| 10.0 * k as f64).collect();
            wheel.zones[0].wear_number_n = wheel.wear_number_n.clone();
            wheel.zones[1].wear_number_n = vec![f64::NAN; n];
        }
        w
    }

    #[test]
    fn static_load_is_the_first_two_metres_mean() {
        let mut w = series(20, 0.0, 50e3);
        w.wheels[1].q_n[0] = f64::NAN; // one wheel airborne: counts 0
        let (p, n) = static_axle_load_n(&w).unwrap();
        assert_eq!(n, 5); // 0, 0.5, … 2.0 m
        assert!((p - (100e3 * 4.0 + 50e3) / 5.0).abs() < 1e-6, "{p}");
        w.wheels[0].q_n = vec![f64::NAN; 20];
        w.wheels[1].q_n = vec![f64::NAN; 20];
        assert_eq!(static_axle_load_n(&w), None);
    }

    #[test]
    fn prudhomme_limit_is_10_plus_p_over_3() {
        // P = 100 kN: the limit is 10 + 100/3 = 43.33 kN.
        let s = wheelset_safety(&series(30, -45e3, 50e3));
        let p = &s.prudhomme;
        assert!((s.static_axle_load_kn.unwrap() - 100.0).abs() < 1e-9);
        assert!((p.limit_kn.unwrap() - 43.333_333).abs() < 1e-5);
        // |ΣY| of 45 kN over whole windows: above the limit.
        assert!((p.max_abs_sum_y_2m_kn.unwrap() - 45.0).abs() < 1e-9);
        assert_eq!(p.verdict, SafetyVerdict::AboveLimit);
        assert_eq!(p.windows, 26);
        assert_eq!(p.valid_windows, 26);
        let s = wheelset_safety(&series(30, 40e3, 50e3));
        assert_eq!(s.prudhomme.verdict, SafetyVerdict::BelowLimit);
        // A spike of 80 kN in one sample: the 2 m mean (4 samples) is
        // (80 + 3·40)/4 = 50 kN; the sample maximum is reported beside.
        let mut w = series(30, 40e3, 50e3);
        w.sum_y_n[20] = 80e3;
        let s = wheelset_safety(&w);
        assert!((s.prudhomme.max_abs_sum_y_kn.unwrap() - 80.0).abs() < 1e-9);
        assert!((s.prudhomme.max_abs_sum_y_2m_kn.unwrap() - 50.0).abs() < 1e-9);
        assert_eq!(s.prudhomme.max_at_track_s_m, Some(110.0));
        // Shorter than 2 m.
        let s = wheelset_safety(&series(3, 40e3, 50e3));
        assert_eq!(s.prudhomme.verdict, SafetyVerdict::ShorterThanWindow);
    }

    #[test]
    fn unloading_is_q0_minus_q_over_q0() {
        // Q0 = 50 kN; the left wheel at 15 kN: ΔQ/Q0 = 0.7 > 0.6.
        let s = wheelset_safety(&series(30, 0.0, 15e3));
        let l = &s.unloading[0];
        assert!((l.max_delta_q_over_q0.unwrap() - 0.7).abs() < 1e-12);
        assert!((l.max_delta_q_over_q0_2m.unwrap() - 0.7).abs() < 1e-12);
        assert_eq!(l.verdict, SafetyVerdict::AboveLimit);
        assert_eq!(s.unloading[1].verdict, SafetyVerdict::BelowLimit);
        assert_eq!(s.unloading[1].max_delta_q_over_q0, Some(0.0));
        // Airborne (no contact): Q = 0, full unloading.
        let mut w = series(30, 0.0, 40e3);
        w.wheels[0].q_n[12] = f64::NAN;
        let s = wheelset_safety(&w);
        assert_eq!(s.unloading[0].max_delta_q_over_q0, Some(1.0));
        assert_eq!(s.unloading[0].verdict, SafetyVerdict::BelowLimit);
        // No contact at the start: no static load, no verdict.
        let mut w = series(30, 0.0, 40e3);
        for wheel in &mut w.wheels {
            wheel.q_n[..5].fill(f64::NAN);
        }
        let s = wheelset_safety(&w);
        assert_eq!(s.unloading[0].verdict, SafetyVerdict::NoStaticLoad);
        assert_eq!(s.prudhomme.verdict, SafetyVerdict::NoStaticLoad);
    }

    #[test]
    fn angle_of_attack_and_wear() {
        let s = wheelset_safety(&series(10, 0.0, 50e3));
        assert_eq!(s.max_angle_of_attack_mrad, Some(-4.0));
        assert_eq!(s.max_angle_of_attack_at_track_s_m, Some(103.5));
        let w = &s.wear[0];
        // 0, 10, … 90 N.
        assert_eq!(w.mean_wear_number_n, Some(45.0));
        assert_eq!(w.max_wear_number_n, Some(90.0));
        assert_eq!(w.tread_mean_n, Some(45.0));
        assert_eq!(w.flange_mean_n, None);
    }
}
