//! The cross-code study's reports: the table (text and Markdown, the one
//! docs/guide/cooperrider-cross-code.md quotes), `cross_code.csv`,
//! `cross_code.json` and `bifurcation.png` (step-and-dwell amplitudes of
//! the variants marked `plot`).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;

use crate::studies::cross_code::{CrossCodeReport, CycleDeath, VariantResult};

fn speed(v: Option<f64>) -> String {
    v.map_or("—".into(), |v| format!("{v:.1}"))
}

fn delta(v: Option<f64>, base: Option<f64>) -> String {
    match (v, base) {
        (Some(v), Some(b)) => format!("{:+.1}", v - b),
        _ => "—".into(),
    }
}

fn death(d: &CycleDeath) -> String {
    match (&d.speed_m_s, &d.last_wheelset) {
        (Some(v), Some(w)) => format!("{v:.1} ({w})"),
        (Some(v), None) => format!("{v:.1}"),
        _ => "—".into(),
    }
}

/// "front 5.1 / … mm" at one speed.
fn amplitudes(v: &VariantResult, at: f64) -> String {
    v.amplitudes_at
        .iter()
        .find(|(s, _)| *s == at)
        .filter(|(_, a)| !a.is_empty())
        .map_or("—".into(), |(_, a)| {
            a.iter()
                .map(|(_, mm)| format!("{mm:.1}"))
                .collect::<Vec<_>>()
                .join(" / ")
        })
}

impl CrossCodeReport {
    /// The baseline of the differences: the first variant.
    fn baseline(&self) -> Option<&VariantResult> {
        self.variants.first()
    }

    /// The variant (other than the first two: the baseline and the whole
    /// other formulation) whose linear or nonlinear (step-and-dwell)
    /// critical speed moves farthest from the baseline's, and by how much
    /// (m/s).
    pub fn largest_single_difference(&self) -> Option<(String, &'static str, f64)> {
        let base = self.baseline()?;
        let mut best: Option<(String, &'static str, f64)> = None;
        for v in self.variants.iter().skip(2) {
            for (what, a, b) in [
                ("linear", v.linear_m_s, base.linear_m_s),
                (
                    "nonlinear (step-and-dwell)",
                    v.step_dwell.speed_m_s,
                    base.step_dwell.speed_m_s,
                ),
                ("nonlinear (ramp)", v.ramp.speed_m_s, base.ramp.speed_m_s),
            ] {
                if let (Some(a), Some(b)) = (a, b)
                    && best.as_ref().is_none_or(|x| (a - b).abs() > x.2.abs())
                {
                    best = Some((v.name.clone(), what, a - b));
                }
            }
        }
        best
    }

    /// The table in Markdown (speeds in m/s; amplitudes in mm, one per
    /// wheelset in vehicle order).
    pub fn to_markdown(&self) -> String {
        let base = self.baseline();
        let at: Vec<f64> = self
            .variants
            .first()
            .map(|v| v.amplitudes_at.iter().map(|(s, _)| *s).collect())
            .unwrap_or_default();
        let mut s = String::from(
            "| variant | linear critical speed | Δ | hunting frequency (Hz) | ramp: every cycle dead (last wheelset) | Δ | step-and-dwell: every cycle dead (last wheelset) | Δ |",
        );
        for v in &at {
            let _ = write!(s, " amplitude at {v:.0} m/s (mm) |");
        }
        s += "\n|---|---|---|---|---|---|---|---|";
        s += &"---|".repeat(at.len());
        s += "\n";
        for v in &self.variants {
            let b = |f: &dyn Fn(&VariantResult) -> Option<f64>| base.and_then(f);
            let _ = write!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} |",
                v.name,
                speed(v.linear_m_s),
                delta(v.linear_m_s, b(&|x| x.linear_m_s)),
                v.linear_frequency_hz
                    .map_or("—".into(), |f| format!("{f:.2}")),
                death(&v.ramp),
                delta(v.ramp.speed_m_s, b(&|x| x.ramp.speed_m_s)),
                death(&v.step_dwell),
                delta(v.step_dwell.speed_m_s, b(&|x| x.step_dwell.speed_m_s)),
            );
            for a in &at {
                let _ = write!(s, " {} |", amplitudes(v, *a));
            }
            s += "\n";
        }
        s
    }

    /// The text summary: the table, the notes, the largest single
    /// difference, the files.
    pub fn to_text(&self) -> String {
        let mut s = format!("{}\n  scene {}\n\n", self.title, self.scene);
        s += &self.to_markdown();
        for v in &self.variants {
            for (what, note) in [
                ("linear", &v.linear_note),
                ("ramp", &v.ramp.note),
                ("step-and-dwell", &v.step_dwell.note),
            ] {
                if let Some(n) = note {
                    let _ = writeln!(s, "  {}: {what}: {n}", v.name);
                }
            }
        }
        if let Some((name, what, d)) = self.largest_single_difference() {
            let _ = writeln!(
                s,
                "\n  largest single difference: '{name}' moves the {what} critical speed by {d:+.1} m/s"
            );
        }
        let total: f64 = self.variants.iter().map(|v| v.wall_s).sum();
        let _ = writeln!(s, "  wall time {total:.0} s");
        for f in &self.files {
            let _ = writeln!(s, "  wrote {f}");
        }
        s
    }

    /// Writes `cross_code.md`, `cross_code.csv`, `cross_code.json` and
    /// `bifurcation.png` into `dir` (each all or nothing).
    pub fn write(&mut self, dir: &Path) -> Result<()> {
        use preproc::plot::{LineChart, Series, SeriesStyle, write_line_chart};
        std::fs::create_dir_all(dir)?;
        let md = dir.join("cross_code.md");
        super::write_text(&md, &self.to_markdown())?;
        let mut csv = String::from("variant,continuation,speed_m_s,wheelset,amplitude_mm\n");
        for v in &self.variants {
            for a in &v.dwell_amplitudes {
                let _ = writeln!(
                    csv,
                    "{},step_dwell,{},{},{}",
                    v.name.replace(',', ";"),
                    a.speed_m_s,
                    a.wheelset.replace(',', ";"),
                    a.amplitude_mm
                );
            }
        }
        let csv_path = dir.join("cross_code.csv");
        super::write_text(&csv_path, &csv)?;
        let mut chart = LineChart::new(
            format!("Bifurcation diagram: {}", self.title),
            "speed [m/s]",
            "largest lateral cycle amplitude of any wheelset, step-and-dwell [mm]",
        );
        for (k, v) in self.variants.iter().filter(|v| v.plot).enumerate() {
            // The dwells in schedule order (the points are wheelset by
            // wheelset, each in that order).
            let speeds: Vec<f64> = v
                .dwell_amplitudes
                .iter()
                .filter(|a| a.wheelset_index == 0)
                .map(|a| a.speed_m_s)
                .collect();
            let pts: Vec<(f64, f64)> = speeds
                .iter()
                .map(|s| {
                    let m = v
                        .dwell_amplitudes
                        .iter()
                        .filter(|a| a.speed_m_s == *s)
                        .map(|a| a.amplitude_mm)
                        .fold(0.0, f64::max);
                    (*s, m)
                })
                .collect();
            let label = match v.linear_m_s {
                Some(l) => format!("{} (linear critical speed {l:.1} m/s)", v.name),
                None => v.name.clone(),
            };
            chart = chart.with_series(
                Series::line(label, pts)
                    .with_style(SeriesStyle::LineAndPoints)
                    .with_colour(k),
            );
        }
        let png = dir.join("bifurcation.png");
        write_line_chart(&png, &chart, (1600, 900))?;
        self.files = vec![
            md.display().to_string(),
            csv_path.display().to_string(),
            png.display().to_string(),
        ];
        let json = dir.join("cross_code.json");
        super::write_text(&json, &(serde_json::to_string_pretty(&self)? + "\n"))?;
        self.files.push(json.display().to_string());
        Ok(())
    }
}
