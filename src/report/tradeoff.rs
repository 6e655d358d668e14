//! The speed/accuracy study's reports: `tradeoff.csv`, `tradeoff.md`, the
//! Pareto chart `pareto.png`, `tradeoff.json` and the text summary
//! (`docs/guide/speed-accuracy-tradeoff.md`).

use std::path::Path;

use anyhow::{Context, Result};

use super::write_text;
use crate::studies::tradeoff::{TradeoffReport, VariantResult};

/// Errors below this are drawn at it on the log axis of `pareto.png` (m).
pub const PLOT_ERROR_FLOOR_M: f64 = 1e-9;

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x}"))
}

fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Short number for the tables.
fn fmt(v: Option<f64>, digits: usize) -> String {
    match v {
        Some(0.0) => "0".into(),
        Some(x) if x.is_finite() && (x.abs() >= 1e4 || x.abs() < 1e-2) => {
            format!("{x:.*e}", digits.saturating_sub(1))
        }
        Some(x) if x.is_finite() => format!("{x:.*}", digits),
        Some(x) => format!("{x}"),
        None => "—".into(),
    }
}

impl TradeoffReport {
    /// `tradeoff.csv`: one row per variant, SI units.
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "name,knob,overrides,status,error,wall_time_median_s,wall_time_min_s,wall_time_max_s,setup_time_median_s,simulated_time_s,real_time_factor,steps,rejected_steps,rhs_evaluations,table_step_m,distance_per_step_m,table_step_ratio,lateral_max_error_m,lateral_rms_error_m,hunting_frequency_hz,frequency_error_hz,growth_rate_1_s,growth_rate_error_1_s,peak_lateral_force_n,peak_lateral_force_error_n,peak_normal_force_n,peak_normal_force_error_n,critical_speed_m_s,critical_speed_error_m_s,pareto,results\n",
        );
        for r in &self.variants {
            let m = r.measures;
            let e = r.errors;
            let fields = [
                csv_field(&r.name),
                csv_field(&r.knob),
                csv_field(&r.overrides.join(";")),
                csv_field(&r.status),
                csv_field(r.error.as_deref().unwrap_or("")),
                opt(r.wall_time_median_s),
                opt(r.wall_time_min_s),
                opt(r.wall_time_max_s),
                opt(r.setup_time_median_s),
                opt(r.simulated_time_s),
                opt(r.real_time_factor),
                r.steps.map_or(String::new(), |v| v.to_string()),
                r.rejected_steps.map_or(String::new(), |v| v.to_string()),
                r.rhs_evaluations.map_or(String::new(), |v| v.to_string()),
                format!("{}", r.table_step_m),
                opt(r.distance_per_step_m),
                opt(r.table_step_ratio),
                opt(e.map(|e| e.lateral_max_m)),
                opt(e.map(|e| e.lateral_rms_m)),
                opt(m.and_then(|m| m.hunting_frequency_hz)),
                opt(e.and_then(|e| e.frequency_hz)),
                opt(m.and_then(|m| m.growth_rate_1_s)),
                opt(e.and_then(|e| e.growth_rate_1_s)),
                opt(m.map(|m| m.peak_lateral_force_n)),
                opt(e.map(|e| e.peak_lateral_force_n)),
                opt(m.map(|m| m.peak_normal_force_n)),
                opt(e.map(|e| e.peak_normal_force_n)),
                opt(r.critical_speed_m_s),
                opt(r.critical_speed_error_m_s),
                r.pareto.to_string(),
                csv_field(r.results.as_deref().unwrap_or("")),
            ];
            s += &fields.join(",");
            s.push('\n');
        }
        s
    }

    /// `tradeoff.md`: the table, the rule check, the failures.
    pub fn to_markdown(&self) -> String {
        let mut s = format!(
            "# Speed against accuracy: {}\n\n{} m/s, {}, outputs every {} s; median of {} run(s) per variant, one at a time, on a machine with {} hardware thread(s); study wall time {:.1} s.\n\nReference: `{}`. Every variant applies the reference's overrides, then its own (below). Errors against the reference: the leading wheelset's lateral displacement (max, RMS), the hunting frequency (zero crossings), the peak total lateral force |Y| and normal force N over all wheels. ★: on the Pareto front of (wall time, max lateral error).\n\n",
            self.scene,
            self.speed_m_s,
            self.distance_m
                .map_or_else(|| "the scene's duration".into(), |d| format!("{d} m")),
            self.output_interval_s,
            self.repeats,
            self.threads,
            self.total_wall_time_s,
            self.reference_overrides.join(" "),
        );
        let cs = self
            .variants
            .iter()
            .any(|r| r.critical_speed_m_s.is_some() || r.critical_speed_note.is_some());
        s += "| variant | overrides | wall time [s] median (min–max) | RTF | lateral max [µm] | lateral RMS [µm] | f [Hz] (error) | σ [1/s] (error) | peak Y [kN] (error) | peak N [kN] (error) | step / (V·Δt) |";
        if cs {
            s += " critical speed [m/s] (error) |";
        }
        s += "\n|---|---|---|---|---|---|---|---|---|---|---|";
        if cs {
            s += "---|";
        }
        s.push('\n');
        for r in &self.variants {
            let m = r.measures;
            let e = r.errors;
            let name = if r.pareto {
                format!("★ {}", r.name)
            } else {
                r.name.clone()
            };
            let overrides = if r.overrides.is_empty() {
                "—".to_string()
            } else {
                format!("`{}`", r.overrides.join(" "))
            };
            if r.status == "failed" {
                s += &format!(
                    "| {name} | {overrides} | failed: {} |{}\n",
                    r.error
                        .clone()
                        .unwrap_or_default()
                        .replace('|', "/")
                        .replace('\n', " "),
                    " |".repeat(if cs { 9 } else { 8 })
                );
                continue;
            }
            let pair = |a: Option<f64>, b: Option<f64>, scale: f64, d: usize| {
                format!(
                    "{} ({})",
                    fmt(a.map(|v| v * scale), d),
                    fmt(b.map(|v| v * scale), 2)
                )
            };
            s += &format!(
                "| {name}{} | {overrides} | {} ({}–{}) | {} | {} | {} | {} | {} | {} | {} | {} |",
                if r.status == "ok" {
                    String::new()
                } else {
                    format!(" ({})", r.status)
                },
                fmt(r.wall_time_median_s, 3),
                fmt(r.wall_time_min_s, 3),
                fmt(r.wall_time_max_s, 3),
                fmt(r.real_time_factor, 2),
                fmt(e.map(|e| e.lateral_max_m * 1e6), 3),
                fmt(e.map(|e| e.lateral_rms_m * 1e6), 3),
                pair(
                    m.and_then(|m| m.hunting_frequency_hz),
                    e.and_then(|e| e.frequency_hz),
                    1.0,
                    4
                ),
                pair(
                    m.and_then(|m| m.growth_rate_1_s),
                    e.and_then(|e| e.growth_rate_1_s),
                    1.0,
                    3
                ),
                pair(
                    m.map(|m| m.peak_lateral_force_n),
                    e.map(|e| e.peak_lateral_force_n),
                    1e-3,
                    3
                ),
                pair(
                    m.map(|m| m.peak_normal_force_n),
                    e.map(|e| e.peak_normal_force_n),
                    1e-3,
                    3
                ),
                fmt(r.table_step_ratio, 2),
            );
            if cs {
                s += &format!(
                    " {} |",
                    match (r.critical_speed_m_s, &r.critical_speed_note) {
                        (Some(_), _) =>
                            pair(r.critical_speed_m_s, r.critical_speed_error_m_s, 1.0, 2),
                        (None, Some(n)) => n.clone(),
                        _ => "—".into(),
                    }
                );
            }
            s.push('\n');
        }
        if !self.rule.is_empty() {
            s += "\n## The table-step rule (paper §2: table step ≤ V·Δt)\n\nThe table step's own error: each run against the run with the same integrator and a 0.01 m table.\n\n| variant | against | table step [m] | V·Δt [m] | ratio | max lateral difference [µm] | the partner's own error [µm] |\n|---|---|---|---|---|---|---|\n";
            for r in &self.rule {
                s += &format!(
                    "| {} | {} | {} | {} | {} | {} | {} |\n",
                    r.variant,
                    r.partner,
                    r.table_step_m,
                    fmt(Some(r.distance_per_step_m), 3),
                    fmt(Some(r.ratio), 2),
                    fmt(Some(r.lateral_max_m * 1e6), 3),
                    fmt(Some(r.partner_error_m * 1e6), 3),
                );
            }
        }
        let failed: Vec<&VariantResult> =
            self.variants.iter().filter(|r| r.status != "ok").collect();
        if !failed.is_empty() {
            s += "\n## Failed or stopped\n\n";
            for r in failed {
                s += &format!(
                    "- **{}** ({}): {}\n",
                    r.name,
                    r.status,
                    r.error.clone().unwrap_or_default()
                );
            }
        }
        for k in &self.skipped {
            s += &format!("\nNot varied: {k}.\n");
        }
        s
    }

    /// Terminal summary.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "speed against accuracy, {} ({} m/s; {} repeat(s), {:.1} s)\n  {:<30} {:>9} {:>8} {:>12} {:>12} {:>10} {:>10} {:>8}\n",
            self.scene,
            self.speed_m_s,
            self.repeats,
            self.total_wall_time_s,
            "variant",
            "wall [s]",
            "RTF",
            "lat max[µm]",
            "lat rms[µm]",
            "Δf [Hz]",
            "ΔY [kN]",
            "ratio"
        );
        for r in &self.variants {
            if r.status == "failed" {
                s += &format!(
                    "  {:<30} failed: {}\n",
                    r.name,
                    r.error.clone().unwrap_or_default()
                );
                continue;
            }
            let e = r.errors;
            s += &format!(
                "  {:<30} {:>9} {:>8} {:>12} {:>12} {:>10} {:>10} {:>8}{}\n",
                format!("{}{}", if r.pareto { "* " } else { "" }, r.name),
                fmt(r.wall_time_median_s, 3),
                fmt(r.real_time_factor, 2),
                fmt(e.map(|e| e.lateral_max_m * 1e6), 3),
                fmt(e.map(|e| e.lateral_rms_m * 1e6), 3),
                fmt(e.and_then(|e| e.frequency_hz), 3),
                fmt(e.map(|e| e.peak_lateral_force_n * 1e-3), 3),
                fmt(r.table_step_ratio, 2),
                if r.status == "ok" {
                    String::new()
                } else {
                    format!("  ({})", r.status)
                }
            );
        }
        s += "  * on the Pareto front (wall time, max lateral error)\n";
        for f in &self.files {
            s += &format!("  wrote {f}\n");
        }
        s
    }

    /// The Pareto chart: log₁₀ max lateral error (mm) against log₁₀ median
    /// wall time (s), one line per knob through its values in the legend's
    /// order, the front in black.
    pub fn pareto_chart(&self) -> preproc::plot::LineChart {
        use preproc::plot::{LineChart, Series, SeriesStyle};
        let mut chart = LineChart::new(
            format!(
                "Speed against accuracy, {} ({} m/s)",
                self.scene, self.speed_m_s
            ),
            "log₁₀ wall time [s] (median)",
            "log₁₀ max lateral error of the leading wheelset [mm]",
        );
        let point = |r: &VariantResult| -> Option<(f64, f64)> {
            let w = r.wall_time_median_s?;
            let e = r.errors?.lateral_max_m;
            (r.status == "ok" && w > 0.0)
                .then(|| (w.log10(), (e.max(PLOT_ERROR_FLOOR_M) * 1e3).log10()))
        };
        // Knob groups in a fixed order (7 colours; black is the front).
        let groups: [(&str, &[&str]); 7] = [
            ("table step", &["table step"]),
            ("rk4 step", &["rk4 step"]),
            ("dopri5 rtol", &["dopri5 rtol"]),
            ("table step with rk4 1 ms", &["table step × rk4 1 ms"]),
            ("contact", &["contact"]),
            ("creep law / scheme", &["model"]),
            ("combinations", &["combination", "user"]),
        ];
        let colours = [0usize, 1, 2, 3, 4, 5, 7];
        for ((label, knobs), c) in groups.iter().zip(colours) {
            let members: Vec<&VariantResult> = self
                .variants
                .iter()
                .filter(|r| knobs.contains(&r.knob.as_str()))
                .filter(|r| point(r).is_some())
                .collect();
            if members.is_empty() {
                continue;
            }
            let names: Vec<&str> = members.iter().map(|r| r.value.as_str()).collect();
            chart.series.push(
                Series::line(
                    format!("{label}: {}", names.join(" → ")),
                    members.iter().filter_map(|r| point(r)).collect(),
                )
                .with_style(SeriesStyle::LineAndPoints)
                .with_colour(c),
            );
        }
        if let Some(r) = self.variants.iter().find(|r| r.knob == "reference") {
            chart.series.push(
                Series::points(
                    format!(
                        "reference (error 0, drawn at {:e} mm)",
                        PLOT_ERROR_FLOOR_M * 1e3
                    ),
                    point(r).into_iter().collect(),
                )
                .with_colour(6),
            );
        }
        let mut front: Vec<(f64, f64)> = self
            .variants
            .iter()
            .filter(|r| r.pareto)
            .filter_map(point)
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .series
            .push(Series::line("Pareto front", front).with_colour(6));
        chart
    }

    /// Writes `tradeoff.csv`, `tradeoff.md`, `pareto.png` and, with `json`,
    /// `tradeoff.json` into `dir`.
    pub fn write(&mut self, dir: &Path, json: bool) -> Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let csv = dir.join("tradeoff.csv");
        write_text(&csv, &self.to_csv())?;
        let md = dir.join("tradeoff.md");
        write_text(&md, &self.to_markdown())?;
        let png = dir.join("pareto.png");
        preproc::plot::write_line_chart(&png, &self.pareto_chart(), (1800, 1100))
            .context("writing the Pareto chart")?;
        self.files = vec![
            csv.display().to_string(),
            md.display().to_string(),
            png.display().to_string(),
        ];
        if json {
            let path = dir.join("tradeoff.json");
            self.files.push(path.display().to_string());
            write_text(&path, &serde_json::to_string_pretty(self)?)?;
        }
        Ok(())
    }
}
