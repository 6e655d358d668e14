//! PNG plots of a run from its [`RunResults`] — the figures of Pombo,
//! Ambrósio & Silva's §5:
//!
//! - `lateral_displacement.png`: lateral displacement (mm, + left) of every
//!   wheelset against the distance travelled (m) (paper Figs. 15, 17, 18);
//! - `contact_forces.png`: one row per wheelset, three panels: lateral
//!   contact force Y (kN, + towards the track centre on both wheels: the
//!   one convention of the results file's `y_n` and of the Y/Q summary,
//!   `docs/reference/01-units-frames.md`) of the left and right wheels
//!   (tread and flange zones summed; paper Figs. 19–20), vertical contact
//!   force Q (kN, + up) and the flange normal force (kN, 0 out of flange
//!   contact);
//! - `creepages.png`: one row per wheelset, panels ξ, η (dimensionless) and
//!   φ (1/m) of the tread zones of the left and right wheels.
//!
//! [`write_comparison_plot`] draws one wheelset's lateral displacement for
//! several runs (a speed or creep-law sweep, paper Figs. 15/17/18) against
//! its track position s (or against time, [`write_comparison_plot_by`]).
//!
//! Colours are fixed: in the per-wheel panels the left wheel is always
//! palette colour 0 (blue) and the right wheel colour 1 (vermillion); in the
//! lateral-displacement chart wheelset i takes colour i; in a comparison run
//! i takes colour i. The abscissa is each wheelset's own distance along the
//! track centreline ([`WheelsetSeries::distance_m`]). Contact forces count
//! as zero in a zone out of contact (its stored values are NaN); creepages
//! of a tread out of contact are left out (the line is broken there).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use preproc::plot::{LineChart, Series, write_line_chart, write_multi_panel};
use runtime::results::{RunResults, WheelsetSeries, ZoneSeries};

use crate::studies::run_difference::{Abscissa, all_have_track_position};

/// File names written by [`write_run_plots`].
pub const LATERAL_DISPLACEMENT_PNG: &str = "lateral_displacement.png";
pub const CONTACT_FORCES_PNG: &str = "contact_forces.png";
pub const CREEPAGES_PNG: &str = "creepages.png";

/// Palette colours of the left and right wheels.
const WHEEL_COLOURS: [usize; 2] = [0, 1];
const WHEEL_LABELS: [&str; 2] = ["left wheel", "right wheel"];
/// Index of the tread and flange zones in [`runtime::results::WheelSeries::zones`].
const TREAD: usize = 0;
const FLANGE: usize = 1;

const DISTANCE_LABEL: &str = "distance travelled [m]";
const TRACK_POSITION_LABEL: &str = "track position s [m]";
/// Image sizes, px.
const SINGLE_CHART_PX: (u32, u32) = (1600, 900);
const PANEL_WIDTH_PX: u32 = 1900;
const PANEL_ROW_HEIGHT_PX: u32 = 520;
const PANEL_TITLE_HEIGHT_PX: u32 = 80;

/// Name of wheelset `i` as shown in titles and legends.
fn wheelset_label(i: usize, ws: &WheelsetSeries) -> String {
    if ws.name.is_empty() {
        format!("wheelset {i}")
    } else {
        format!("wheelset {i} ({})", ws.name)
    }
}

/// `(distance, scale · value)` for every sample.
fn against_distance(ws: &WheelsetSeries, values: &[f64], scale: f64) -> Vec<(f64, f64)> {
    ws.distance_m
        .iter()
        .zip(values)
        .map(|(&d, &v)| (d, scale * v))
        .collect()
}

/// Zero where a zone is out of contact (its stored value is NaN).
fn or_zero(v: f64) -> f64 {
    if v.is_nan() { 0.0 } else { v }
}

/// Sum over the two zones of a force series (N), zero out of contact.
fn zone_sum(zones: &[ZoneSeries; 2], get: impl Fn(&ZoneSeries) -> &Vec<f64>) -> Vec<f64> {
    get(&zones[TREAD])
        .iter()
        .zip(get(&zones[FLANGE]))
        .map(|(&a, &b)| or_zero(a) + or_zero(b))
        .collect()
}

/// The lateral displacement (mm) of every wheelset against distance (m).
pub fn lateral_displacement_chart(results: &RunResults, title: &str) -> LineChart {
    let mut chart = LineChart::new(title, DISTANCE_LABEL, "lateral displacement [mm] (+ left)");
    for (i, ws) in results.wheelsets.iter().enumerate() {
        chart.series.push(
            Series::line(
                wheelset_label(i, ws),
                against_distance(ws, &ws.lateral_m, 1e3),
            )
            .with_colour(i),
        );
    }
    chart
}

/// Per wheelset: Y (kN), Q (kN) and the flange normal force (kN), each with
/// the left and right wheels; three panels a row.
pub fn contact_force_panels(results: &RunResults) -> Vec<LineChart> {
    let mut panels = Vec::with_capacity(3 * results.wheelsets.len());
    for (i, ws) in results.wheelsets.iter().enumerate() {
        let name = wheelset_label(i, ws);
        let mut y = LineChart::new(
            format!("{name}: lateral contact force Y"),
            DISTANCE_LABEL,
            "Y [kN] (+ towards the track centre)",
        );
        let mut q = LineChart::new(
            format!("{name}: vertical contact force Q"),
            DISTANCE_LABEL,
            "Q [kN] (+ up)",
        );
        let mut flange = LineChart::new(
            format!("{name}: flange normal force"),
            DISTANCE_LABEL,
            "flange normal force [kN] (0: no flange contact)",
        );
        for (w, wheel) in ws.wheels.iter().enumerate() {
            let series = |values: Vec<f64>| {
                Series::line(WHEEL_LABELS[w], against_distance(ws, &values, 1e-3))
                    .with_colour(WHEEL_COLOURS[w])
            };
            // The wheel's Y as the results file records it (`y_n`).
            y.series.push(series(wheel.y_n.clone()));
            q.series
                .push(series(zone_sum(&wheel.zones, |z| &z.vertical_force_n)));
            let f = &wheel.zones[FLANGE];
            let normal = f
                .in_contact
                .iter()
                .zip(&f.normal_n)
                .map(|(&c, &n)| if c != 0 { or_zero(n) } else { 0.0 })
                .collect();
            flange.series.push(series(normal));
        }
        panels.extend([y, q, flange]);
    }
    panels
}

/// Picks one series of a zone.
type ZoneField = fn(&ZoneSeries) -> &Vec<f64>;

/// Per wheelset: ξ, η and φ of the left and right treads; three panels a
/// row.
pub fn creepage_panels(results: &RunResults) -> Vec<LineChart> {
    let mut panels = Vec::with_capacity(3 * results.wheelsets.len());
    for (i, ws) in results.wheelsets.iter().enumerate() {
        let name = wheelset_label(i, ws);
        let quantities: [(&str, &str, ZoneField); 3] = [
            ("longitudinal creepage ξ", "ξ [–]", |z| &z.xi),
            ("lateral creepage η", "η [–]", |z| &z.eta),
            ("spin creepage φ", "φ [1/m]", |z| &z.phi_1_m),
        ];
        for (what, y_label, get) in quantities {
            let mut chart =
                LineChart::new(format!("{name}: tread {what}"), DISTANCE_LABEL, y_label);
            for (w, wheel) in ws.wheels.iter().enumerate() {
                chart.series.push(
                    Series::line(
                        WHEEL_LABELS[w],
                        against_distance(ws, get(&wheel.zones[TREAD]), 1.0),
                    )
                    .with_colour(WHEEL_COLOURS[w]),
                );
            }
            panels.push(chart);
        }
    }
    panels
}

/// Size of a multi-panel image of `rows` rows.
fn panel_image_px(rows: usize) -> (u32, u32) {
    let rows = u32::try_from(rows.max(1)).unwrap_or(u32::MAX / PANEL_ROW_HEIGHT_PX);
    (
        PANEL_WIDTH_PX,
        PANEL_TITLE_HEIGHT_PX + PANEL_ROW_HEIGHT_PX * rows,
    )
}

/// Write `lateral_displacement.png`, `contact_forces.png` and
/// `creepages.png` of `results` into `dir` (created if missing) under the
/// common `title`; returns the files written, in that order.
pub fn write_run_plots(results: &RunResults, dir: &Path, title: &str) -> Result<Vec<PathBuf>> {
    results
        .validate()
        .context("the run results cannot be plotted")?;
    ensure!(
        !results.wheelsets.is_empty(),
        "the run results have no wheelsets to plot"
    );
    std::fs::create_dir_all(dir)
        .with_context(|| format!("cannot create the plot directory {}", dir.display()))?;

    let lateral = dir.join(LATERAL_DISPLACEMENT_PNG);
    write_line_chart(
        &lateral,
        &lateral_displacement_chart(results, title),
        SINGLE_CHART_PX,
    )
    .context("writing the lateral-displacement plot")?;

    let rows = results.wheelsets.len();
    let forces = dir.join(CONTACT_FORCES_PNG);
    write_multi_panel(
        &forces,
        &format!("{title}: contact forces on the wheels"),
        &contact_force_panels(results),
        3,
        panel_image_px(rows),
    )
    .context("writing the contact-force plot")?;

    let creepages = dir.join(CREEPAGES_PNG);
    write_multi_panel(
        &creepages,
        &format!("{title}: tread creepages"),
        &creepage_panels(results),
        3,
        panel_image_px(rows),
    )
    .context("writing the creepage plot")?;

    Ok(vec![lateral, forces, creepages])
}

/// The lateral displacement (mm) of wheelset `wheelset` in each of `runs`
/// (label, results) against the wheelset's track position s (m), or
/// against the distance travelled when a run lacks s (an older file);
/// run i takes palette colour i. [`comparison_chart_by`] with
/// [`Abscissa::TrackPosition`].
pub fn comparison_chart(
    runs: &[(String, &RunResults)],
    wheelset: usize,
    title: &str,
) -> Result<LineChart> {
    comparison_chart_by(runs, wheelset, title, Abscissa::TrackPosition)
}

/// [`comparison_chart`] against time (s) or track position (m): the
/// abscissa `sim compare` compares the runs at
/// ([`crate::studies::run_difference`]). By track position every curve is
/// drawn against `track_s_m` when every run has it, else all against
/// `distance_m` (one axis for every curve).
pub fn comparison_chart_by(
    runs: &[(String, &RunResults)],
    wheelset: usize,
    title: &str,
    by: Abscissa,
) -> Result<LineChart> {
    for (label, results) in runs {
        results
            .validate()
            .with_context(|| format!("run '{label}' cannot be plotted"))?;
        if results.wheelsets.get(wheelset).is_none() {
            bail!(
                "run '{label}' has {} wheelset(s); there is no wheelset {wheelset} to compare",
                results.wheelsets.len()
            );
        }
    }
    let all: Vec<&RunResults> = runs.iter().map(|(_, r)| *r).collect();
    let with_s = all_have_track_position(&all, wheelset);
    let x_label = match by {
        Abscissa::Time => "time [s]",
        Abscissa::TrackPosition if with_s => TRACK_POSITION_LABEL,
        Abscissa::TrackPosition => DISTANCE_LABEL,
    };
    let mut chart = LineChart::new(
        title,
        x_label,
        format!("wheelset {wheelset} lateral displacement [mm] (+ left)"),
    );
    for (i, (label, results)) in runs.iter().enumerate() {
        let ws = &results.wheelsets[wheelset];
        let x: &[f64] = match by {
            Abscissa::Time => &results.time_s,
            Abscissa::TrackPosition if with_s => &ws.track_s_m,
            Abscissa::TrackPosition => &ws.distance_m,
        };
        let points = x
            .iter()
            .zip(&ws.lateral_m)
            .map(|(&x, &y)| (x, 1e3 * y))
            .collect();
        chart
            .series
            .push(Series::line(label.clone(), points).with_colour(i));
    }
    Ok(chart)
}

/// Write [`comparison_chart`] as a PNG at `path`.
pub fn write_comparison_plot(
    runs: &[(String, &RunResults)],
    wheelset: usize,
    path: &Path,
    title: &str,
) -> Result<()> {
    write_comparison_plot_by(runs, wheelset, path, title, Abscissa::TrackPosition)
}

/// Write [`comparison_chart_by`] as a PNG at `path`.
pub fn write_comparison_plot_by(
    runs: &[(String, &RunResults)],
    wheelset: usize,
    path: &Path,
    title: &str,
    by: Abscissa,
) -> Result<()> {
    ensure!(!runs.is_empty(), "no runs to compare");
    let chart = comparison_chart_by(runs, wheelset, title, by)?;
    write_line_chart(path, &chart, SINGLE_CHART_PX).context("writing the comparison plot")?;
    Ok(())
}
