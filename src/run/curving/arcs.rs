//! The quasi-static values of each wheelset over each constant-curvature
//! arc of the track ([`super::elements`]), EN 14363:2016 §7.6 style: over
//! the samples whose track position lies in the arc, the **quasi-static
//! value** is the 50 % percentile of the signal (Y_qst, Q_qst), and the
//! 2 m sliding means ([`super::windows`]; windows wholly inside the arc)
//! give the **estimated extremes** as their 0.15 % and 99.85 %
//! percentiles. The signals are not low-passed (the output interval sets
//! the bandwidth, as for Nadal's criterion).

use runtime::results::WheelsetSeries;
use serde::Serialize;

use super::elements::{ElementKind, TrackElement};
use super::safety::position_m;
use super::windows::{percentile, sliding_means};
use crate::run::nadal::NADAL_WINDOW_M;

/// The percentiles of the evaluation (%): quasi-static value, and the
/// lower and upper estimated extremes of the 2 m means (EN 14363 §7.6).
pub const QUASI_STATIC_PERCENTILE: f64 = 50.0;
pub const LOW_PERCENTILE: f64 = 0.15;
pub const HIGH_PERCENTILE: f64 = 99.85;

/// One quantity over one arc.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct QuasiStatic {
    /// Its name, e.g. "sum_y", "y_left", and its unit.
    pub quantity: &'static str,
    pub units: &'static str,
    /// Samples with a value.
    pub samples: u64,
    /// The 50 % percentile of the samples.
    pub quasi_static: Option<f64>,
    /// Valid 2 m windows inside the arc, and the 0.15 % and 99.85 %
    /// percentiles of their means.
    pub windows: u64,
    pub low_2m: Option<f64>,
    pub high_2m: Option<f64>,
}

/// One wheelset over one arc.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ArcWheelset {
    pub name: String,
    /// Track length of the arc the wheelset's samples cover (m).
    pub covered_m: f64,
    pub quantities: Vec<QuasiStatic>,
}

/// One arc with every wheelset's quasi-static values.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ArcSummary {
    pub start_s_m: f64,
    pub end_s_m: f64,
    /// + left-hand curve (m).
    pub radius_m: f64,
    /// Applied cant of the arc as a height over the cant base e0,
    /// positive raising the outer rail (mm): from the track's mean cant
    /// angle φ over the arc, D = e0 · sin|φ|, signed by whether it leans
    /// into the curve (docs/reference/01-units-frames.md §1.5); NaN
    /// without track tables.
    pub cant_mm: f64,
    /// Cant deficiency at the leading wheelset's mean speed V over the
    /// arc (mm): I = e0 · V²/(g |R|) − D (EN 13803; + under-canted, the
    /// vehicle pushed outwards). NaN without a speed or a cant.
    pub cant_deficiency_mm: f64,
    pub wheelsets: Vec<ArcWheelset>,
}

/// Standard gravity (m/s²), for the cant deficiency.
const G_M_S2: f64 = 9.806_65;

/// The applied cant D (mm, + raising the outer rail) of an arc of radius
/// `radius_m` (+ left) with mean cant angle `cant_rad` (+ left rail up)
/// over cant base `e0_m` (m): a left-hand curve's outer rail is the right
/// one, raised by a negative cant.
pub fn applied_cant_mm(radius_m: f64, cant_rad: f64, e0_m: f64) -> f64 {
    -radius_m.signum() * e0_m * cant_rad.sin() * 1e3
}

/// The cant deficiency I = e0 V²/(g |R|) − D (mm) at speed `speed_m_s`.
pub fn cant_deficiency_mm(radius_m: f64, applied_cant_mm: f64, e0_m: f64, speed_m_s: f64) -> f64 {
    e0_m * speed_m_s * speed_m_s / (G_M_S2 * radius_m.abs()) * 1e3 - applied_cant_mm
}

/// A quantity's value at sample `i` (None: no value there).
type Pick = fn(&WheelsetSeries, usize) -> Option<f64>;

fn finite(v: Option<&f64>, scale: f64) -> Option<f64> {
    v.copied().filter(|v| v.is_finite()).map(|v| v * scale)
}

/// The quantities of the evaluation: name, unit, value.
const QUANTITIES: [(&str, &str, Pick); 12] = [
    ("lateral", "mm", |w, i| finite(w.lateral_m.get(i), 1e3)),
    ("angle_of_attack", "mrad", |w, i| {
        finite(w.yaw_rad.get(i), 1e3)
    }),
    ("sum_y", "kN", |w, i| finite(w.sum_y_n.get(i), 1e-3)),
    ("y_left", "kN", |w, i| finite(w.wheels[0].y_n.get(i), 1e-3)),
    ("y_right", "kN", |w, i| finite(w.wheels[1].y_n.get(i), 1e-3)),
    ("q_left", "kN", |w, i| finite(w.wheels[0].q_n.get(i), 1e-3)),
    ("q_right", "kN", |w, i| finite(w.wheels[1].q_n.get(i), 1e-3)),
    // Y/Q of the loaded samples (Q > 0), as for Nadal's criterion.
    ("y_over_q_left", "1", |w, i| {
        let q = w.wheels[0].q_n.get(i).copied().filter(|q| *q > 0.0);
        q.and_then(|_| finite(w.wheels[0].y_over_q.get(i), 1.0))
    }),
    ("y_over_q_right", "1", |w, i| {
        let q = w.wheels[1].q_n.get(i).copied().filter(|q| *q > 0.0);
        q.and_then(|_| finite(w.wheels[1].y_over_q.get(i), 1.0))
    }),
    ("wear_number_left", "N", |w, i| {
        finite(w.wheels[0].wear_number_n.get(i), 1.0)
    }),
    ("wear_number_right", "N", |w, i| {
        finite(w.wheels[1].wear_number_n.get(i), 1.0)
    }),
    ("speed", "m/s", |w, i| finite(w.speed_m_s.get(i), 1.0)),
];

/// One wheelset over the arc [from, to] (track s, m).
pub fn arc_wheelset(w: &WheelsetSeries, from_m: f64, to_m: f64) -> ArcWheelset {
    let idx: Vec<usize> = (0..w.distance_m.len())
        .filter(|&i| position_m(w, i).is_some_and(|s| s >= from_m && s <= to_m))
        .collect();
    let covered_m = match (idx.first(), idx.last()) {
        (Some(&a), Some(&b)) => position_m(w, b).unwrap_or(0.0) - position_m(w, a).unwrap_or(0.0),
        _ => 0.0,
    };
    let distance: Vec<f64> = idx.iter().map(|&i| w.distance_m[i]).collect();
    let quantities = QUANTITIES
        .iter()
        .map(|&(quantity, units, pick)| {
            let v: Vec<Option<f64>> = idx.iter().map(|&i| pick(w, i)).collect();
            let means: Vec<f64> = sliding_means(&v, &distance, NADAL_WINDOW_M)
                .into_iter()
                .flatten()
                .collect();
            let raw: Vec<f64> = v.iter().flatten().copied().collect();
            QuasiStatic {
                quantity,
                units,
                samples: raw.len() as u64,
                quasi_static: percentile(&raw, QUASI_STATIC_PERCENTILE),
                windows: means.len() as u64,
                low_2m: percentile(&means, LOW_PERCENTILE),
                high_2m: percentile(&means, HIGH_PERCENTILE),
            }
        })
        .collect();
    ArcWheelset {
        name: w.name.clone(),
        covered_m,
        quantities,
    }
}

/// Every arc of `elements` that some wheelset's samples reach, with the
/// quasi-static values of every wheelset; `cant` gives the track's cant
/// angle (rad) at a distance s (m) and `e0_m` the cant base (m).
pub fn arc_summaries(
    wheelsets: &[WheelsetSeries],
    elements: &[TrackElement],
    cant: &dyn Fn(f64) -> Option<f64>,
    e0_m: f64,
) -> Vec<ArcSummary> {
    elements
        .iter()
        .filter(|e| e.kind == ElementKind::Arc)
        .map(|e| {
            let radius_m = e.radius_m.unwrap_or(f64::NAN);
            let ws: Vec<ArcWheelset> = wheelsets
                .iter()
                .map(|w| arc_wheelset(w, e.start_s_m, e.end_s_m))
                .collect();
            // Mean cant over the arc, from 21 points.
            let angles: Vec<f64> = (0..=20)
                .filter_map(|k| cant(e.start_s_m + (e.end_s_m - e.start_s_m) * k as f64 / 20.0))
                .collect();
            let cant_mm = if angles.is_empty() {
                f64::NAN
            } else {
                applied_cant_mm(
                    radius_m,
                    angles.iter().sum::<f64>() / angles.len() as f64,
                    e0_m,
                )
            };
            let speed = ws
                .first()
                .and_then(|w| w.quantities.iter().find(|q| q.quantity == "speed"))
                .map_or(f64::NAN, |q| q.quasi_static.unwrap_or(f64::NAN));
            ArcSummary {
                start_s_m: e.start_s_m,
                end_s_m: e.end_s_m,
                radius_m,
                cant_mm,
                cant_deficiency_mm: cant_deficiency_mm(radius_m, cant_mm, e0_m, speed),
                wheelsets: ws,
            }
        })
        .filter(|a| a.wheelsets.iter().any(|w| w.covered_m > 0.0))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cant_deficiency_of_a_canted_left_curve() {
        // R 250 m to the left, 150 mm of cant on e0 = 1.5 m (right rail
        // up: φ = −asin(0.1)); at 20 m/s the balancing cant is
        // 1500 · 400/(9.80665 · 250) = 244.732 mm, so I = 94.732 mm.
        let d = applied_cant_mm(250.0, -(0.1f64).asin(), 1.5);
        assert!((d - 150.0).abs() < 1e-9, "{d}");
        let i = cant_deficiency_mm(250.0, d, 1.5, 20.0);
        assert!((i - 94.732).abs() < 1e-3, "{i}");
        // The same curve to the right with the left rail raised.
        assert!((applied_cant_mm(-250.0, (0.1f64).asin(), 1.5) - 150.0).abs() < 1e-9);
        // A cant leaning the wrong way counts negative.
        assert!((applied_cant_mm(250.0, (0.1f64).asin(), 1.5) + 150.0).abs() < 1e-9);
    }

    #[test]
    fn quasi_static_values_are_taken_over_the_arc_only() {
        // 0.5 m per sample over s = 0 … 100 m; ΣY 5 kN outside the arc
        // [40, 80] m, inside 20 kN with one 60 kN sample at s = 60 m.
        let n = 201;
        let mut w = WheelsetSeries::new("front");
        w.distance_m = (0..n).map(|k| 0.5 * k as f64).collect();
        w.track_s_m = w.distance_m.clone();
        w.sum_y_n = w
            .track_s_m
            .iter()
            .map(|&s| {
                if s == 60.0 {
                    60e3
                } else if (40.0..=80.0).contains(&s) {
                    20e3
                } else {
                    5e3
                }
            })
            .collect();
        let a = arc_wheelset(&w, 40.0, 80.0);
        assert_eq!(a.covered_m, 40.0);
        let q = a.quantities.iter().find(|q| q.quantity == "sum_y").unwrap();
        assert_eq!(q.samples, 81);
        assert_eq!(q.quasi_static, Some(20.0));
        // Windows inside the arc: ending at 42 … 80 m (77); the spike's 4
        // windows average (60 + 3·20)/4 = 30 kN; 99.85 % of 77 means
        // interpolates between the two largest (both 30).
        assert_eq!(q.windows, 77);
        assert!((q.high_2m.unwrap() - 30.0).abs() < 1e-9, "{q:?}");
        assert!((q.low_2m.unwrap() - 20.0).abs() < 1e-9, "{q:?}");
        // Quantities without samples have no values.
        let y = a
            .quantities
            .iter()
            .find(|q| q.quantity == "y_left")
            .unwrap();
        assert_eq!((y.samples, y.quasi_static), (0, None));
        // Arcs the run does not reach are left out.
        let e = TrackElement {
            kind: ElementKind::Arc,
            start_s_m: 200.0,
            end_s_m: 300.0,
            mean_curvature_1_m: 1e-3,
            radius_m: Some(1e3),
        };
        assert!(arc_summaries(&[w.clone()], &[e], &|_| None, 1.5).is_empty());
        let e = TrackElement {
            start_s_m: 40.0,
            end_s_m: 80.0,
            ..e
        };
        assert_eq!(arc_summaries(&[w], &[e], &|_| None, 1.5).len(), 1);
    }
}
