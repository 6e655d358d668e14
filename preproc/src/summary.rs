//! The short report printed after a build (text, or JSON with `--json`).

use runtime::track::TrackTables;
use serde::Serialize;

/// Rows of each table.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RowCounts {
    pub centerline: usize,
    pub left_rail: usize,
    pub right_rail: usize,
}

/// What a build produced.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BuildSummary {
    /// Output file.
    pub output: String,
    /// Spline scheme.
    pub scheme: String,
    /// Table step (m).
    pub step_m: f64,
    /// Centreline length (m).
    pub length_m: f64,
    /// Length of each rail (m).
    pub left_rail_length_m: f64,
    pub right_rail_length_m: f64,
    /// Rows per table.
    pub rows: RowCounts,
    /// Smallest radius of curvature of the centreline (m); `None` on a
    /// track without curvature.
    pub min_curve_radius_m: Option<f64>,
    /// Largest |cant| (rad) and the same as a height over the cant base (mm).
    pub max_cant_rad: f64,
    pub max_cant_mm: f64,
    /// Largest |irregularity| over the four components (m).
    pub max_irregularity_m: f64,
    /// Wall time of the build including writing (s).
    pub elapsed_s: f64,
}

/// Curvature below which a track counts as straight (1/m): radius 1e6 m.
const STRAIGHT_CURVATURE: f64 = 1e-6;

impl BuildSummary {
    /// Summarise built tables.
    pub fn new(tables: &TrackTables, output: &str, elapsed_s: f64) -> Self {
        let rows = tables.centerline.rows();
        let max_curv = rows.iter().fold(0.0_f64, |m, r| m.max(r.curvature_1_m));
        let max_cant = rows.iter().fold(0.0_f64, |m, r| m.max(r.cant_rad.abs()));
        let max_irr = rows.iter().fold(0.0_f64, |m, r| {
            m.max(r.align_left_m.abs())
                .max(r.align_right_m.abs())
                .max(r.level_left_m.abs())
                .max(r.level_right_m.abs())
        });
        let (_, left_len) = tables.left.range_m();
        let (_, right_len) = tables.right.range_m();
        Self {
            output: output.to_string(),
            scheme: tables.meta.scheme.clone(),
            step_m: tables.meta.step_m,
            length_m: tables.centerline.length_m(),
            left_rail_length_m: left_len,
            right_rail_length_m: right_len,
            rows: RowCounts {
                centerline: rows.len(),
                left_rail: tables.left.rows().len(),
                right_rail: tables.right.rows().len(),
            },
            min_curve_radius_m: (max_curv > STRAIGHT_CURVATURE).then(|| 1.0 / max_curv),
            max_cant_rad: max_cant,
            max_cant_mm: tables.meta.cant_base_m * max_cant.sin() * 1e3,
            max_irregularity_m: max_irr,
            elapsed_s,
        }
    }

    /// Human-readable form.
    pub fn to_text(&self) -> String {
        let radius = match self.min_curve_radius_m {
            Some(r) => format!("{r:.1} m"),
            None => "straight (no curvature)".into(),
        };
        format!(
            "wrote {}\n  length            {:.3} m (rails: left {:.3} m, right {:.3} m)\n  scheme, step      {}, {} m\n  rows              centerline {}, left rail {}, right rail {}\n  min curve radius  {radius}\n  max cant          {:.4} rad ({:.1} mm)\n  max irregularity  {:.2} mm\n  time              {:.3} s\n",
            self.output,
            self.length_m,
            self.left_rail_length_m,
            self.right_rail_length_m,
            self.scheme,
            self.step_m,
            self.rows.centerline,
            self.rows.left_rail,
            self.rows.right_rail,
            self.max_cant_rad,
            self.max_cant_mm,
            self.max_irregularity_m * 1e3,
            self.elapsed_s,
        )
    }
}
