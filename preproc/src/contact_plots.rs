//! Plots of a contact lookup table, for a report: the rolling radius
//! difference Δr(y), the contact-point locus drawn on the wheel and rail
//! profiles (in the profile files' own coordinates, mm), and the contact
//! quantities against the lateral shift.

use std::path::Path;

use runtime::contact::table::{ContactTable, ZoneEntry};
use runtime::io::profile_import::{ImportOptions, read_profile};

use crate::plot::{LineChart, PlotError, Series, SeriesStyle, write_line_chart, write_multi_panel};

/// Why plots could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ContactPlotError {
    #[error("cannot create the plot directory {path}: {source}")]
    Directory {
        path: std::path::PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(transparent)]
    Plot(#[from] PlotError),
    #[error(transparent)]
    Profile(#[from] runtime::io::profile_import::ProfileImportError),
}

const WHEEL_NAMES: [&str; 2] = ["left", "right"];
const ZONE_NAMES: [&str; 2] = ["tread", "flange"];

/// The zero-yaw rows' entries of a wheel and zone, against y (mm).
fn entries(table: &ContactTable, wheel: usize, zone: usize) -> Vec<(f64, ZoneEntry)> {
    let j = table.zero_yaw_index();
    (0..table.y_m.len())
        .filter_map(|i| {
            let e = table.row(i, j).zones[wheel][zone]?;
            (e.penetration_m >= -1e-7).then_some((table.y_m[i] * 1e3, e))
        })
        .collect()
}

/// Write `delta_r.png`, `contact_points.png` and `contact_vs_y.png` into `dir`.
pub fn write_contact_plots(dir: &Path, table: &ContactTable) -> Result<(), ContactPlotError> {
    std::fs::create_dir_all(dir).map_err(|source| ContactPlotError::Directory {
        path: dir.to_path_buf(),
        source,
    })?;
    let title_pair = format!(
        "{} on {}",
        file_name(&table.meta.wheel_profile),
        file_name(&table.meta.rail_profile)
    );

    // Δr(y).
    let dr: Vec<(f64, f64)> = table
        .delta_r_curve()
        .into_iter()
        .map(|(y, d)| (y * 1e3, d * 1e3))
        .collect();
    write_line_chart(
        &dir.join("delta_r.png"),
        &LineChart::new(
            format!("Rolling radius difference, {title_pair}"),
            "lateral shift y [mm] (positive to the left)",
            "Δr = r_left − r_right [mm]",
        )
        .with_series(Series::line("Δr(y)", dr)),
        (1000, 650),
    )?;

    // Contact points on the profiles (file coordinates, mm).
    let wheel = read_profile(
        Path::new(&table.meta.wheel_profile),
        &ImportOptions::default(),
    )?;
    let rail = read_profile(
        Path::new(&table.meta.rail_profile),
        &ImportOptions::default(),
    )?;
    // Drawn with z up: a SIMPACK file's z (down) is negated.
    let (wz, rz) = (
        if wheel.z_down { -1.0 } else { 1.0 },
        if rail.z_down { -1.0 } else { 1.0 },
    );
    let z_label = |down: bool| {
        if down {
            "−z [mm] (the file's z points down)"
        } else {
            "z [mm]"
        }
    };
    let outline = |p: &runtime::io::profile_import::ProfileFile, sz: f64| -> Vec<(f64, f64)> {
        p.points_m
            .iter()
            .map(|q| (q[0] * 1e3, sz * q[1] * 1e3))
            .collect()
    };
    let mut wheel_chart = LineChart::new(
        "Contact points on the wheel profile (file coordinates)",
        "y [mm]",
        z_label(wheel.z_down),
    )
    .with_series(Series::line("wheel profile", outline(&wheel, wz)).with_colour(6));
    let mut rail_chart = LineChart::new(
        "Contact points on the rail profile (file coordinates)",
        "y [mm]",
        z_label(rail.z_down),
    )
    .with_series(Series::line("rail profile", outline(&rail, rz)).with_colour(6));
    wheel_chart.equal_aspect = true;
    rail_chart.equal_aspect = true;
    for (w, wheel_name) in WHEEL_NAMES.iter().enumerate() {
        for (z, zone_name) in ZONE_NAMES.iter().enumerate() {
            let e = entries(table, w, z);
            if e.is_empty() {
                continue;
            }
            let label = format!("{wheel_name} {zone_name}");
            let colour = w * 2 + z;
            wheel_chart.series.push(
                Series::points(
                    label.clone(),
                    e.iter()
                        .map(|(_, e)| (e.y_wheel_m * 1e3, wz * e.z_wheel_m * 1e3))
                        .collect(),
                )
                .with_colour(colour),
            );
            rail_chart.series.push(
                Series::points(
                    label,
                    e.iter()
                        .map(|(_, e)| (e.y_rail_m * 1e3, rz * e.z_rail_m * 1e3))
                        .collect(),
                )
                .with_colour(colour),
            );
        }
    }
    write_multi_panel(
        &dir.join("contact_points.png"),
        &format!(
            "Contact-point locus, y from {:+.1} to {:+.1} mm, {title_pair}",
            table.y_m[0] * 1e3,
            table.y_m[table.y_m.len() - 1] * 1e3
        ),
        &[wheel_chart, rail_chart],
        2,
        (1800, 800),
    )?;

    // Contact quantities against y.
    let per_zone = |title: &str, unit: &str, f: &dyn Fn(&ZoneEntry) -> f64| {
        let mut chart = LineChart::new(title, "lateral shift y [mm]", unit);
        for (w, wheel_name) in WHEEL_NAMES.iter().enumerate() {
            for (z, zone_name) in ZONE_NAMES.iter().enumerate() {
                let e = entries(table, w, z);
                if !e.is_empty() {
                    chart.series.push(
                        Series::points(
                            format!("{wheel_name} {zone_name}"),
                            e.iter().map(|(y, e)| (*y, f(e))).collect(),
                        )
                        .with_style(SeriesStyle::Points)
                        .with_colour(w * 2 + z),
                    );
                }
            }
        }
        chart
    };
    let mut panels = vec![
        per_zone("Rolling radius", "r [mm]", &|e| e.rolling_radius_m * 1e3),
        per_zone(
            "Contact angle",
            "γ [°] (towards the track centre)",
            &|e| e.contact_angle_rad.to_degrees(),
        ),
        per_zone("Penetration", "δ [µm]", &|e| e.penetration_m * 1e6),
    ];
    if table.meta.support == "elastic" {
        panels.push(per_zone("Normal force", "N [kN]", &|e| {
            e.normal_force_n * 1e-3
        }));
    } else {
        panels.push(per_zone("Wheel lateral curvature", "κ [1/m]", &|e| {
            e.wheel_lateral_curvature_1_m
        }));
    }
    write_multi_panel(
        &dir.join("contact_vs_y.png"),
        &format!("Contact geometry against the lateral shift, {title_pair}"),
        &panels,
        2,
        (1600, 1100),
    )?;
    Ok(())
}

fn file_name(path: &str) -> String {
    Path::new(path)
        .file_name()
        .map_or_else(|| path.to_string(), |n| n.to_string_lossy().into_owned())
}
