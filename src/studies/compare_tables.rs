//! `sim compare-contact-tables`: our contact lookup table of a wheel/rail
//! pair (`track-preproc contact-table`) against a table computed by another
//! code and imported (`track-preproc import-contact-table`, or the RSGEO
//! `.dat` itself): rolling radius, contact angle, contact ellipse semi-axes,
//! lateral position of the contact point on the wheel and the rolling radius
//! difference, against the wheelset's lateral displacement y (left wheel;
//! the imported rows describe the left wheel, see
//! `runtime::contact::imported`).
//!
//! Our table stores curvatures, not semi-axes: a and b are computed with
//! [`HertzContact`] from the main contact's principal relative curvatures
//! (docs/reference/07-contact-forces.md §7.1) at the **imported table's N0(y)**, with our table's E and ν,
//! so that the two ellipses are compared at the same load and differ only by
//! the geometry (and the material). The main contact of a wheel is its zone
//! with the larger normal force (elastic table) or penetration (rigid).
//!
//! Outputs in the directory: `rolling_radius.png`, `contact_angle.png`,
//! `semi_axes.png`, `contact_position.png`, `delta_r.png`, and
//! `comparison.csv` (both tables on our grid).

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use preproc::plot::{LineChart, Series, write_line_chart};
use runtime::contact::imported::ImportedContactTable;
use runtime::contact::table::{ContactTable, ZoneEntry};
use runtime::forces::hertz::{HertzContact, Material};
use runtime::geometry::profile::WheelProfileOptions;
use runtime::io::profile_import::{ImportOptions, load_wheel};
use serde::Serialize;

/// Contact angle above which a contact counts as a flange contact when
/// locating the flange-contact onset (rad): 0.5 rad (29°), between the
/// tread's < 0.15 rad and the flange's ≈ 1.2 rad in both tables.
const FLANGE_ANGLE_RAD: f64 = 0.5;

/// One quantity compared: values at y = 0 and the largest difference
/// (ours − imported) over |y| ≤ `tread_range_mm` of the summary.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct QuantityComparison {
    pub quantity: String,
    pub unit: String,
    pub ours_at_0: f64,
    pub imported_at_0: f64,
    /// Largest |ours − imported| on the tread range, and where (mm).
    pub max_abs_difference: f64,
    pub at_y_mm: f64,
}

/// What `sim compare-contact-tables` found.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TableComparison {
    pub ours: String,
    pub imported: String,
    pub plots: Vec<String>,
    pub csv: String,
    /// Lateral displacements compared (our grid inside the imported range).
    pub points: usize,
    /// Differences are taken over |y| ≤ this (mm): both tables on the tread.
    pub tread_range_mm: f64,
    /// Smallest y > 0 at which the left wheel's contact angle exceeds 0.5
    /// rad (flange contact), mm; `None` when it never does in the range.
    pub flange_onset_ours_mm: Option<f64>,
    pub flange_onset_imported_mm: Option<f64>,
    pub quantities: Vec<QuantityComparison>,
}

impl TableComparison {
    /// Human-readable summary.
    pub fn to_text(&self) -> String {
        let onset = |o: Option<f64>| o.map_or("none".to_string(), |v| format!("{v:+.2} mm"));
        let mut s = format!(
            "ours {}\nimported {}\n  {} lateral displacements; flange contact (δ > 0.5 rad) from y = {} (ours), {} (imported)\n  quantity (left wheel)          at y = 0: ours / imported    max |ours − imported| for |y| ≤ {:.1} mm\n",
            self.ours,
            self.imported,
            self.points,
            onset(self.flange_onset_ours_mm),
            onset(self.flange_onset_imported_mm),
            self.tread_range_mm
        );
        for q in &self.quantities {
            s += &format!(
                "  {:<30} {:>12.5} / {:<12.5} {:>10.5} {} (at y = {:+.1} mm)\n",
                format!("{} [{}]", q.quantity, q.unit),
                q.ours_at_0,
                q.imported_at_0,
                q.max_abs_difference,
                q.unit,
                q.at_y_mm
            );
        }
        for p in &self.plots {
            s += &format!("  plot {p}\n");
        }
        s += &format!("  values {}\n", self.csv);
        s
    }
}

/// The left wheel's main contact in a zero-yaw row of our table.
fn main_entry(table: &ContactTable, i: usize) -> Option<ZoneEntry> {
    let row = table.row(i, table.zero_yaw_index());
    let elastic = table.meta.support == "elastic";
    row.zones[0]
        .iter()
        .flatten()
        .filter(|e| e.penetration_m >= -1e-7)
        .max_by(|a, b| {
            if elastic {
                a.normal_force_n.total_cmp(&b.normal_force_n)
            } else {
                a.penetration_m.total_cmp(&b.penetration_m)
            }
        })
        .copied()
}

/// One y of the comparison (SI units).
#[derive(Debug, Clone, Copy)]
struct Point {
    y_m: f64,
    ours: [f64; 6],
    imported: [f64; 6],
}

/// Names and units (as plotted) of the six compared quantities, in the
/// order of [`Point::ours`]; the factor converts SI to the plotted unit.
const QUANTITIES: [(&str, &str, f64); 6] = [
    ("rolling radius", "mm", 1e3),
    ("contact angle", "rad", 1.0),
    ("semi-axis a (rolling)", "mm", 1e3),
    ("semi-axis b (lateral)", "mm", 1e3),
    ("contact point from the wheelset centre", "mm", 1e3),
    ("rolling radius difference r_L - r_R", "mm", 1e3),
];

/// Compares the two tables and writes the plots and the CSV into `out_dir`
/// (module docs).
pub fn compare_contact_tables(
    ours_path: &Path,
    imported_path: &Path,
    out_dir: &Path,
) -> Result<TableComparison> {
    let ours = runtime::io::schema::read_contact_table(ours_path)
        .with_context(|| format!("reading {}", ours_path.display()))?
        .with_context(|| {
            format!(
                "{} has no /contact_table (write it with track-preproc contact-table)",
                ours_path.display()
            )
        })?;
    let imported = crate::session::contact::imported_table(imported_path)?;
    let points = compare_points(&ours, &imported)?;
    ensure!(
        !points.is_empty(),
        "the tables have no lateral displacement in common (ours {:?} m, imported {:?} m)",
        (ours.y_m.first(), ours.y_m.last()),
        imported.wheelset_range_m()
    );
    std::fs::create_dir_all(out_dir).with_context(|| format!("creating {}", out_dir.display()))?;
    let plots = write_plots(&points, &ours, &imported, out_dir)?;
    let csv = out_dir.join("comparison.csv");
    write_csv(&csv, &points)?;
    let tread_range_mm = 5.0;
    let onset = |f: &dyn Fn(&Point) -> f64| {
        points
            .iter()
            .find(|p| p.y_m > 0.0 && f(p) > FLANGE_ANGLE_RAD)
            .map(|p| p.y_m * 1e3)
    };
    let at0 = points
        .iter()
        .min_by(|a, b| a.y_m.abs().total_cmp(&b.y_m.abs()))
        .copied()
        .context("no point")?;
    let quantities = QUANTITIES
        .iter()
        .enumerate()
        .map(|(k, (name, unit, f))| {
            let (diff, y) = points
                .iter()
                .filter(|p| p.y_m.abs() <= tread_range_mm * 1e-3 + 1e-9)
                .map(|p| ((p.ours[k] - p.imported[k]).abs() * f, p.y_m * 1e3))
                .filter(|(d, _)| d.is_finite())
                .fold((0.0, f64::NAN), |m, v| if v.0 > m.0 { v } else { m });
            QuantityComparison {
                quantity: name.to_string(),
                unit: unit.to_string(),
                ours_at_0: at0.ours[k] * f,
                imported_at_0: at0.imported[k] * f,
                max_abs_difference: diff,
                at_y_mm: y,
            }
        })
        .collect();
    Ok(TableComparison {
        ours: ours_path.display().to_string(),
        imported: imported_path.display().to_string(),
        plots: plots.iter().map(|p| p.display().to_string()).collect(),
        csv: csv.display().to_string(),
        points: points.len(),
        tread_range_mm,
        flange_onset_ours_mm: onset(&|p| p.ours[1]),
        flange_onset_imported_mm: onset(&|p| p.imported[1]),
        quantities,
    })
}

/// Both tables at our grid's zero-yaw rows inside the imported range.
fn compare_points(ours: &ContactTable, imported: &ImportedContactTable) -> Result<Vec<Point>> {
    let material = Material {
        young_pa: ours.meta.young_pa,
        poisson: ours.meta.poisson,
    };
    material
        .validate()
        .context("the material of our contact table")?;
    let options = WheelProfileOptions {
        nominal_radius_m: ours.meta.wheel_radius_m,
        ..Default::default()
    };
    let wheel_path = Path::new(&ours.meta.wheel_profile);
    // Distance of the taping line from the wheelset centre (m).
    let taping_m = 0.5 * ours.meta.back_to_back_m + options.flange_back_m;
    // Default options: a profile is built from all its usable points or
    // refused, never cut down, so there is no warning to show.
    let wheel = load_wheel(wheel_path, &ImportOptions::default(), options)
        .with_context(|| {
            format!(
                "the wheel profile of our table, {} (needed for the contact position)",
                wheel_path.display()
            )
        })?
        .profile;
    let (lo, hi) = imported.wheelset_range_m();
    let mut out = Vec::new();
    for (i, &y) in ours.y_m.iter().enumerate() {
        if y < lo || y > hi {
            continue;
        }
        let left = imported.wheel_row(runtime::geometry::track::Side::Left, y)?;
        let right = imported.wheel_row(runtime::geometry::track::Side::Right, y)?;
        let imported_values = [
            left.rolling_radius_m,
            left.contact_angle_rad,
            left.a_m,
            left.b_m,
            left.wheel_lateral_m,
            left.rolling_radius_m - right.rolling_radius_m,
        ];
        let ours_values = match main_entry(ours, i) {
            Some(e) => {
                let a_curv = 0.5 * (e.wheel_rolling_curvature_1_m + e.rail_rolling_curvature_1_m);
                let b_curv = 0.5 * (e.wheel_lateral_curvature_1_m + e.rail_lateral_curvature_1_m);
                // Non-Hertzian (conformal) points have no ellipse: NaN.
                let (a, b) = HertzContact::new(a_curv, b_curv, left.normal_force_n, &material)
                    .map_or((f64::NAN, f64::NAN), |h| (h.a_rolling_m, h.b_lateral_m));
                let (u, _) = wheel.from_file_m(e.y_wheel_m, e.z_wheel_m);
                [
                    e.rolling_radius_m,
                    e.contact_angle_rad,
                    a,
                    b,
                    taping_m - u,
                    ours.row(i, ours.zero_yaw_index()).delta_r_m,
                ]
            }
            None => [f64::NAN; 6],
        };
        out.push(Point {
            y_m: y,
            ours: ours_values,
            imported: imported_values,
        });
    }
    Ok(out)
}

fn write_plots(
    points: &[Point],
    ours: &ContactTable,
    imported: &ImportedContactTable,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let ours_label = format!(
        "ours: {} on {}",
        file_name(&ours.meta.wheel_profile),
        file_name(&ours.meta.rail_profile)
    );
    let imported_label = format!("imported: {}", imported.format);
    let series = |k: usize, f: f64, which: bool| -> Vec<(f64, f64)> {
        points
            .iter()
            .map(|p| {
                let v = if which { p.ours[k] } else { p.imported[k] };
                (p.y_m * 1e3, v * f)
            })
            .collect()
    };
    let x_label = "wheelset lateral displacement y [mm] (+ left; left wheel)";
    let mut written = Vec::new();
    let mut chart = |file: &str, title: &str, y_label: &str, list: Vec<Series>| -> Result<()> {
        let mut c = LineChart::new(title, x_label, y_label);
        c.series = list;
        let path = dir.join(file);
        write_line_chart(&path, &c, (1100, 700))?;
        written.push(path);
        Ok(())
    };
    for (file, k, title) in [
        ("rolling_radius.png", 0, "Rolling radius of the left wheel"),
        (
            "contact_angle.png",
            1,
            "Contact angle of the left wheel (+ towards the track centre)",
        ),
        (
            "contact_position.png",
            4,
            "Contact point on the left wheel, lateral distance from the wheelset centre",
        ),
        (
            "delta_r.png",
            5,
            "Rolling radius difference r_left − r_right",
        ),
    ] {
        let (_, unit, f) = QUANTITIES[k];
        chart(
            file,
            title,
            &format!("{} [{unit}]", QUANTITIES[k].0),
            vec![
                Series::line(ours_label.clone(), series(k, f, true)).with_colour(0),
                Series::line(imported_label.clone(), series(k, f, false)).with_colour(1),
            ],
        )?;
    }
    chart(
        "semi_axes.png",
        "Semi-axes of the left wheel at the imported N0(y) (ours: Hertz, our curvatures)",
        "semi-axis [mm]",
        vec![
            Series::line(format!("a, {ours_label}"), series(2, 1e3, true)).with_colour(0),
            Series::line(format!("b, {ours_label}"), series(3, 1e3, true)).with_colour(2),
            Series::line(format!("a, {imported_label}"), series(2, 1e3, false)).with_colour(1),
            Series::line(format!("b, {imported_label}"), series(3, 1e3, false)).with_colour(3),
        ],
    )?;
    Ok(written)
}

/// Written all-or-nothing (`runtime::io::atomic`).
fn write_csv(path: &Path, points: &[Point]) -> Result<()> {
    runtime::io::write_atomically(path, |tmp| csv_rows(tmp, points))
        .with_context(|| format!("writing {}", path.display()))
}

fn csv_rows(path: &Path, points: &[Point]) -> std::io::Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path)?);
    let names = [
        "r_m",
        "contact_angle_rad",
        "a_m",
        "b_m",
        "wheel_lateral_m",
        "delta_r_m",
    ];
    let mut header = vec!["y_m".to_string()];
    for who in ["ours", "imported"] {
        for n in names {
            header.push(format!("{who}_{n}"));
        }
    }
    writeln!(f, "{}", header.join(","))?;
    for p in points {
        let mut row = vec![format!("{:.6e}", p.y_m)];
        for v in p.ours.iter().chain(&p.imported) {
            row.push(format!("{v:.9e}"));
        }
        writeln!(f, "{}", row.join(","))?;
    }
    f.flush()
}

fn file_name(path: &str) -> String {
    Path::new(path)
        .file_name()
        .map_or_else(|| path.to_string(), |n| n.to_string_lossy().into_owned())
}
