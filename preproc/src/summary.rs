//! The short report printed after a build (text, or JSON with `--json`).

use runtime::contact::table::ContactTable;
use runtime::geometry::track::TrackTables;
use serde::Serialize;

use crate::conicity::ConicitySummary;

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
    /// The contact lookup table, when profiles were given.
    pub contact_table: Option<ContactTableSummary>,
    /// Wall time of the build including writing (s).
    pub elapsed_s: f64,
    /// Peak resident memory of the process so far (MB = 10⁶ bytes), from
    /// `VmHWM` of `/proc/self/status` ([`peak_memory_mb`]); `None` where
    /// that is not available (not Linux) or not measured (library calls).
    pub peak_memory_mb: Option<f64>,
}

/// Peak resident set size of this process (MB = 10⁶ bytes): the `VmHWM`
/// line of `/proc/self/status` (Linux, proc(5); given there in kB =
/// 1024 bytes). `None` where the file or the line is missing.
pub fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vmhwm_mb(&status)
}

/// The `VmHWM:   1234 kB` line of a proc status text, in MB (10⁶ bytes).
fn parse_vmhwm_mb(status: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let mut fields = line["VmHWM:".len()..].split_whitespace();
    let value: f64 = fields.next()?.parse().ok()?;
    match fields.next() {
        Some("kB") => Some(value * 1024.0 / 1e6),
        _ => None,
    }
}

/// What a contact table holds.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct ContactTableSummary {
    pub wheel_profile: String,
    pub rail_profile: String,
    /// "rigid" or "elastic", and the load per wheel (N).
    pub support: String,
    pub wheel_load_n: f64,
    /// Rows (lateral shifts × yaws) and the lateral range (mm).
    pub rows: usize,
    pub y_min_mm: f64,
    pub y_max_mm: f64,
    pub yaw_count: usize,
    /// Lateral shift at which each flange first carries load (mm), from the
    /// zero-yaw column: left flange (y > 0), right flange (y < 0).
    pub flange_contact_left_mm: Option<f64>,
    pub flange_contact_right_mm: Option<f64>,
    /// EN 15302 equivalent conicity at 1…6 mm.
    pub conicity: ConicitySummary,
    /// Warnings of the profiles: what was dropped from a profile cut to its
    /// longest usable stretch (`--keep-longest-stretch`).
    pub warnings: Vec<String>,
    /// The rail inclination applied to the rail profile as drawn (rad),
    /// the cant the profile carries (rad) and how that is known
    /// (`detected`, `declared`, `unknown`; absent for tables that do not
    /// record it): the rail stands at their sum in the track.
    pub rail_inclination_rad: f64,
    pub rail_profile_cant_rad: Option<f64>,
    pub rail_profile_cant_source: Option<String>,
}

impl ContactTableSummary {
    /// Summarise a table with its conicity.
    pub fn new(table: &ContactTable, conicity: ConicitySummary) -> Self {
        let j = table.zero_yaw_index();
        let flange_at = |wheel: usize, sign: f64| {
            let mut idx: Vec<usize> = (0..table.y_m.len())
                .filter(|&i| table.y_m[i] * sign >= 0.0)
                .collect();
            idx.sort_by(|&a, &b| table.y_m[a].abs().total_cmp(&table.y_m[b].abs()));
            idx.into_iter()
                .find(|&i| {
                    table.row(i, j).zones[wheel][1].is_some_and(|z| z.penetration_m >= -1e-7)
                })
                .map(|i| table.y_m[i] * 1e3)
        };
        Self {
            wheel_profile: table.meta.wheel_profile.clone(),
            rail_profile: table.meta.rail_profile.clone(),
            support: table.meta.support.clone(),
            wheel_load_n: table.meta.wheel_load_n,
            rows: table.rows.len(),
            y_min_mm: table.y_m[0] * 1e3,
            y_max_mm: table.y_m[table.y_m.len() - 1] * 1e3,
            yaw_count: table.yaw_rad.len(),
            flange_contact_left_mm: flange_at(0, 1.0),
            flange_contact_right_mm: flange_at(1, -1.0),
            conicity,
            warnings: Vec::new(),
            rail_inclination_rad: table.meta.rail_inclination_rad,
            rail_profile_cant_rad: table.meta.rail_record.as_ref().map(|r| r.carried_cant_rad),
            rail_profile_cant_source: table
                .meta
                .rail_record
                .as_ref()
                .map(|r| r.carried_cant_source.name().to_string()),
        }
    }

    /// Human-readable lines.
    pub fn to_text(&self) -> String {
        let mm = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:+.1} mm"));
        let con: Vec<String> = self
            .conicity
            .amplitude_mm
            .iter()
            .zip(&self.conicity.tan_gamma_e)
            .map(|(a, t)| match t {
                Some(t) => format!("{a:.0} mm: {t:.3}"),
                None => format!("{a:.0} mm: –"),
            })
            .collect();
        use runtime::geometry::profile::rail_cant::slope_text;
        let warnings: String = self.warnings.iter().map(|w| format!("  {w}\n")).collect();
        let cant = match (self.rail_profile_cant_rad, &self.rail_profile_cant_source) {
            (Some(c), Some(source)) => format!(
                "{} in the file ({source}) + inclination {} = {} in the track",
                slope_text(c),
                slope_text(self.rail_inclination_rad),
                slope_text(c + self.rail_inclination_rad)
            ),
            _ => format!(
                "inclination {} (the file's own cant not recorded)",
                slope_text(self.rail_inclination_rad)
            ),
        };
        format!(
            "  contact table     {} rows ({} yaw), y {:+.1} … {:+.1} mm, {}{}\n  profiles          {} on {}\n{warnings}  rail cant         {cant}\n  flange contact    left at {}, right at {}\n  conicity tanγe    {}\n",
            self.rows,
            self.yaw_count,
            self.y_min_mm,
            self.y_max_mm,
            self.support,
            if self.support == "elastic" {
                format!(", {:.0} N per wheel", self.wheel_load_n)
            } else {
                String::new()
            },
            self.wheel_profile,
            self.rail_profile,
            mm(self.flange_contact_left_mm),
            mm(self.flange_contact_right_mm),
            con.join(", ")
        )
    }
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
            contact_table: None,
            elapsed_s,
            peak_memory_mb: None,
        }
    }

    /// Human-readable form.
    pub fn to_text(&self) -> String {
        let radius = match self.min_curve_radius_m {
            Some(r) => format!("{r:.1} m"),
            None => "straight (no curvature)".into(),
        };
        let contact = self
            .contact_table
            .as_ref()
            .map(ContactTableSummary::to_text)
            .unwrap_or_default();
        format!(
            "wrote {}\n  length            {:.3} m (rails: left {:.3} m, right {:.3} m)\n  scheme, step      {}, {} m\n  rows              centerline {}, left rail {}, right rail {}\n  min curve radius  {radius}\n  max cant          {:.4} rad ({:.1} mm)\n  max irregularity  {:.2} mm\n{contact}  time              {:.3} s\n{}",
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
            self.peak_memory_mb
                .map(|m| format!("  peak memory       {m:.1} MB\n"))
                .unwrap_or_default(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vmhwm_is_read_in_megabytes() {
        let status =
            "Name:\ttrack-preproc\nVmPeak:\t  20000 kB\nVmHWM:\t    1000 kB\nVmRSS:\t 900 kB\n";
        assert_eq!(parse_vmhwm_mb(status), Some(1.024));
        assert_eq!(parse_vmhwm_mb("VmRSS: 5 kB\n"), None);
        assert_eq!(parse_vmhwm_mb("VmHWM: lots\n"), None);
        if cfg!(target_os = "linux") {
            let m = peak_memory_mb().expect("Linux has /proc/self/status");
            assert!(m > 0.1 && m < 1e6, "{m} MB");
        }
    }
}
