//! The curving plot page of a run, `curving.png`
//! (docs/guide/curving-and-safety.md): against the track position s (m,
//! [`runtime::results::WheelsetSeries::track_s_m`]; the distance travelled
//! in older files), eight panels in two columns:
//!
//! - lateral displacement from the track centre (mm, + left) and angle of
//!   attack (mrad, + nose left) of every wheelset;
//! - ΣY (kN, + left) of every wheelset with Prud'homme's limit ±α(10 + P/3)
//!   kN ([`crate::run::curving::safety`]), and Y/Q of every wheel with its
//!   Nadal limit;
//! - Y (kN, + towards the track centre) and Q (kN) of every wheel;
//! - Tγ (N) of every wheel, and the track's horizontal curvature (1/km,
//!   + left) from the elements found.
//!
//! Every panel shades the track's elements (the design file's when the
//! tables carry them, [`crate::run::curving::design`], else found from the
//! curvature, [`crate::run::curving::elements`]; the title says which):
//! transitions orange, arcs blue, straights unshaded. Wheel series take
//! palette colour 2i + k (wheelset i, wheel k: 0 left, 1 right); limit
//! lines are black.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use preproc::plot::{LineChart, Series, XBand, write_multi_panel};
use runtime::results::{RunResults, WHEEL_GROUPS, WheelSeries, WheelsetSeries};

use crate::run::curving::design::ElementSource;
use crate::run::curving::elements::{ElementKind, TrackElement};
use crate::run::curving::safety::{PRUDHOMME_ALPHA, position_m, static_axle_load_n};

/// File name of the page.
pub const CURVING_PNG: &str = "curving.png";

/// Band colours of transitions and arcs (Okabe–Ito orange and sky blue).
const TRANSITION_RGB: (u8, u8, u8) = (0xE6, 0x9F, 0x00);
const ARC_RGB: (u8, u8, u8) = (0x56, 0xB4, 0xE9);
/// Palette index of the limit lines (black).
const LIMIT_COLOUR: usize = 6;
const S_LABEL: &str = "track position s [m]";
const PAGE_PX: (u32, u32) = (1900, 2400);

/// The bands of the elements.
fn bands(elements: &[TrackElement]) -> Vec<XBand> {
    elements
        .iter()
        .filter_map(|e| {
            let rgb = match e.kind {
                ElementKind::Straight => return None,
                ElementKind::Transition => TRANSITION_RGB,
                ElementKind::Arc => ARC_RGB,
            };
            Some(XBand {
                from: e.start_s_m,
                to: e.end_s_m,
                rgb,
            })
        })
        .collect()
}

/// `(s, scale · value)` of every sample.
fn against_s(w: &WheelsetSeries, values: &[f64], scale: f64) -> Vec<(f64, f64)> {
    values
        .iter()
        .enumerate()
        .map(|(i, v)| (position_m(w, i).unwrap_or(f64::NAN), scale * v))
        .collect()
}

/// The s range of the samples.
fn s_range(r: &RunResults) -> Option<(f64, f64)> {
    let all = r
        .wheelsets
        .iter()
        .flat_map(|w| (0..w.distance_m.len()).filter_map(move |i| position_m(w, i)));
    all.fold(None, |acc, s| match acc {
        None => Some((s, s)),
        Some((a, b)) => Some((a.min(s), b.max(s))),
    })
}

/// A horizontal line at `y` over `range`.
fn level(label: impl Into<String>, range: (f64, f64), y: f64) -> Series {
    Series::line(label, vec![(range.0, y), (range.1, y)]).with_colour(LIMIT_COLOUR)
}

/// The eight panels (module docs).
pub fn curving_panels(r: &RunResults, elements: &[TrackElement]) -> Vec<LineChart> {
    let bands = bands(elements);
    let range = s_range(r).unwrap_or((0.0, 1.0));
    let chart = |title: &str, y: &str| LineChart {
        x_bands: bands.clone(),
        x_range: Some(range),
        ..LineChart::new(title, S_LABEL, y)
    };
    let mut lateral = chart(
        "lateral displacement from the track centre",
        "lateral [mm] (+ left)",
    );
    let mut aoa = chart("angle of attack", "angle of attack [mrad] (+ nose left)");
    let mut sum_y = chart("track shifting force ΣY", "ΣY [kN] (+ left)");
    let mut yq = chart("derailment quotient Y/Q", "Y/Q [–]");
    let mut y = chart(
        "lateral wheel force Y",
        "Y [kN] (+ towards the track centre)",
    );
    let mut q = chart("vertical wheel force Q", "Q [kN]");
    let mut wear = chart("wear number Tγ", "Tγ [N]");
    let mut curvature = chart(
        "track curvature (shaded: transitions, arcs)",
        "κ [1/km] (+ left)",
    );
    let (mut nadal_limits, mut prudhomme_limits) = (Vec::<f64>::new(), Vec::<f64>::new());
    for (i, w) in r.wheelsets.iter().enumerate() {
        let name = if w.name.is_empty() {
            format!("wheelset {i}")
        } else {
            w.name.clone()
        };
        lateral
            .series
            .push(Series::line(name.clone(), against_s(w, &w.lateral_m, 1e3)).with_colour(2 * i));
        aoa.series
            .push(Series::line(name.clone(), against_s(w, &w.yaw_rad, 1e3)).with_colour(2 * i));
        sum_y
            .series
            .push(Series::line(name.clone(), against_s(w, &w.sum_y_n, 1e-3)).with_colour(2 * i));
        if let Some((p, _)) = static_axle_load_n(w) {
            let l = PRUDHOMME_ALPHA * (10.0 + p / 1e3 / 3.0);
            // One line per distinct limit (0.1 kN apart, as printed).
            if !prudhomme_limits.iter().any(|m| (m - l).abs() < 0.05) {
                prudhomme_limits.push(l);
            }
        }
        for (k, (wheel, side)) in w.wheels.iter().zip(WHEEL_GROUPS).enumerate() {
            let label = format!("{name} {side}");
            let line = |values: &[f64], scale: f64| {
                Series::line(label.clone(), against_s(w, values, scale)).with_colour(2 * i + k)
            };
            yq.series.push(line(&loaded_y_over_q(wheel), 1.0));
            y.series.push(line(&wheel.y_n, 1e-3));
            q.series.push(line(&wheel.q_n, 1e-3));
            wear.series.push(line(&wheel.wear_number_n, 1.0));
            if let Some(n) = wheel.nadal
                && !nadal_limits.iter().any(|l| (l - n.limit).abs() < 1e-9)
            {
                nadal_limits.push(n.limit);
            }
        }
    }
    for l in prudhomme_limits {
        let label = format!("Prud'homme limit ±{l:.1} kN");
        sum_y.series.push(level(label, range, l));
        sum_y.series.push(level("", range, -l));
    }
    for l in nadal_limits {
        yq.series
            .push(level(format!("Nadal limit {l:.3}"), range, l));
    }
    curvature.series.push(
        Series::line("elements (arcs: mean κ)", element_outline(elements))
            .with_colour(LIMIT_COLOUR),
    );
    vec![lateral, aoa, sum_y, yq, y, q, wear, curvature]
}

/// The curvature (1/km) of the elements: straights 0, arcs their mean,
/// transitions a straight ramp from the previous element's end value to
/// the next element's level. Between two transitions (a reverse curve's
/// clothoid pair) the joint's value is the one that gives the first its
/// mean, 2·mean − start (exact for a ramp linear in s).
fn element_outline(elements: &[TrackElement]) -> Vec<(f64, f64)> {
    let level = |e: &TrackElement| match e.kind {
        ElementKind::Straight => 0.0,
        _ => 1e3 * e.mean_curvature_1_m,
    };
    let mut points = Vec::new();
    let mut end = 0.0;
    for (k, e) in elements.iter().enumerate() {
        let start = if k == 0 { level(e) } else { end };
        if e.kind == ElementKind::Transition {
            let start = if k == 0 { 0.0 } else { start };
            end = match elements.get(k + 1) {
                Some(next) if next.kind != ElementKind::Transition => level(next),
                Some(_) => 2.0 * level(e) - start,
                None => 0.0,
            };
            points.extend([(e.start_s_m, start), (e.end_s_m, end)]);
        } else {
            end = level(e);
            points.extend([(e.start_s_m, end), (e.end_s_m, end)]);
        }
    }
    points
}

/// Y/Q where the wheel is loaded (Q > 0), NaN elsewhere.
fn loaded_y_over_q(w: &WheelSeries) -> Vec<f64> {
    w.y_over_q
        .iter()
        .zip(&w.q_n)
        .map(|(&v, &q)| if q > 0.0 { v } else { f64::NAN })
        .collect()
}

/// Write `curving.png` of `results` into `dir` under `title`; `source`
/// (where `elements` come from) is named in the page's title.
pub fn write_curving_plot(
    results: &RunResults,
    elements: &[TrackElement],
    source: ElementSource,
    dir: &Path,
    title: &str,
) -> Result<PathBuf> {
    ensure!(
        !results.wheelsets.is_empty(),
        "the run results have no wheelsets to plot"
    );
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create the plot directory {}", dir.display()))?;
    let path = dir.join(CURVING_PNG);
    write_multi_panel(
        &path,
        &format!(
            "{title}: curving (shaded: transitions orange, arcs blue; elements: {})",
            source.text()
        ),
        &curving_panels(results, elements),
        2,
        PAGE_PX,
    )
    .context("writing the curving plot")?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;
    use runtime::contact::nadal::NadalLimit;
    use runtime::results::{WheelSample, WheelsetSample, ZoneSample};

    fn element(kind: ElementKind, from: f64, to: f64, k: f64) -> TrackElement {
        TrackElement {
            kind,
            start_s_m: from,
            end_s_m: to,
            mean_curvature_1_m: k,
            radius_m: (kind == ElementKind::Arc).then(|| 1.0 / k),
        }
    }

    #[test]
    fn a_reverse_curves_clothoid_pair_meets_at_zero_curvature() {
        // Arc −2 /km, clothoid to 0, clothoid to +2 /km, arc +2 /km: the
        // transitions' means are −1 and +1 /km.
        let elements = [
            element(ElementKind::Arc, 0.0, 10.0, -2e-3),
            element(ElementKind::Transition, 10.0, 20.0, -1e-3),
            element(ElementKind::Transition, 20.0, 30.0, 1e-3),
            element(ElementKind::Arc, 30.0, 40.0, 2e-3),
        ];
        let points = element_outline(&elements);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
        let want = [
            (0.0, -2.0),
            (10.0, -2.0),
            (10.0, -2.0),
            (20.0, 0.0),
            (20.0, 0.0),
            (30.0, 2.0),
            (30.0, 2.0),
            (40.0, 2.0),
        ];
        assert_eq!(points.len(), want.len());
        for (p, w) in points.iter().zip(want) {
            assert!(close(p.0, w.0) && close(p.1, w.1), "{points:?}");
        }
    }

    #[test]
    fn the_page_has_its_panels_limits_and_shading() {
        // One wheelset, 50 kN per wheel: P = 100 kN, limit 43.3 kN.
        let mut r = RunResults::with_wheelsets(["front"]);
        let zone = ZoneSample {
            in_contact: true,
            vertical_force_n: 50e3,
            lateral_force_n: 1e3,
            ..ZoneSample::NO_CONTACT
        };
        for k in 0..40 {
            let wheel = WheelSample {
                travelled_m: 0.5 * f64::from(k),
                zones: [zone, ZoneSample::NO_CONTACT],
            };
            let s = WheelsetSample {
                distance_m: 0.5 * f64::from(k),
                track_s_m: 40.0 + 0.5 * f64::from(k),
                wheels: [wheel, wheel],
                ..WheelsetSample::default()
            };
            r.push(0.01 * f64::from(k), &[s]).unwrap();
        }
        let nadal = NadalLimit {
            flange_angle_rad: 70f64.to_radians(),
            friction: 0.3,
            limit: 1.342,
        };
        r.wheelsets[0].wheels[0].nadal = Some(nadal);
        r.wheelsets[0].wheels[1].nadal = Some(nadal);
        let elements = [
            element(ElementKind::Straight, 0.0, 45.0, 0.0),
            element(ElementKind::Transition, 45.0, 50.0, 1e-3),
            element(ElementKind::Arc, 50.0, 70.0, 2e-3),
        ];
        let p = curving_panels(&r, &elements);
        assert_eq!(p.len(), 8);
        // Two bands on every panel (the straight is unshaded).
        assert!(p.iter().all(|c| c.x_bands.len() == 2));
        assert_eq!(p[0].x_range, Some((40.0, 59.5)));
        // ΣY: the series and ±(10 + 100/3) kN.
        let lim: Vec<f64> = p[2].series[1..].iter().map(|s| s.points[0].1).collect();
        assert!(
            (lim[0] - 43.333).abs() < 1e-3 && (lim[1] + 43.333).abs() < 1e-3,
            "{lim:?}"
        );
        // ΣY = 1 + 1 kN (both zones push left).
        assert!((p[2].series[0].points[0].1 - 2.0).abs() < 1e-12);
        // Y/Q: two wheels and one Nadal line.
        assert_eq!(p[3].series.len(), 3);
        assert_eq!(p[3].series[2].points[0].1, 1.342);
        // Curvature: straight 0, ramp to the arc's 2 /km, arc 2 /km.
        assert_eq!(
            p[7].series[0].points,
            [
                (0.0, 0.0),
                (45.0, 0.0),
                (45.0, 0.0),
                (50.0, 2.0),
                (50.0, 2.0),
                (70.0, 2.0)
            ]
        );
    }
}
