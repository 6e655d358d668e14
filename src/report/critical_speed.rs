//! The critical-speed study's reports: the table like the paper's Table 1
//! with every wheelset's cycle death under a ramp, `rates.csv`,
//! `rates.png` and `ramp_wheelsets.csv` (`docs/guide/critical-speed.md`).

use std::path::Path;

use anyhow::{Context, Result};

use crate::studies::critical_speed::{
    CriticalSpeed, CriticalSpeedMethod, CriticalSpeedReport, SpeedSample,
};
use crate::studies::cycle_death::CycleDeaths;

impl CycleDeaths {
    /// One line per wheelset (saturated amplitude, death speed or fate)
    /// and the one that hunts last, each indented by `indent`.
    pub fn to_text(&self, indent: &str) -> String {
        let mut s = String::new();
        for w in &self.wheelsets {
            let death = match w.death_m_s {
                Some(v) => format!("cycle dies at {v:.2} m/s ({:.1} km/h)", v * 3.6),
                None => w.fate.as_str().replace('_', " "),
            };
            s += &format!(
                "{indent}wheelset {} '{}': saturated {:.2} mm, {death}\n",
                w.index, w.wheelset, w.saturated_mm
            );
        }
        match (&self.last_hunting, self.speed_m_s) {
            (Some(name), Some(v)) => {
                s += &format!(
                    "{indent}criterion {}: hunts last '{name}', every cycle considered dead at {v:.2} m/s\n",
                    self.criterion
                )
            }
            (Some(name), None) => {
                s += &format!(
                    "{indent}criterion {}: '{name}' still hunts at the lowest speed\n",
                    self.criterion
                )
            }
            _ => {}
        }
        s
    }

    /// CSV rows `wheelset_index,wheelset,saturated_mm,death_speed_m_s,fate,hunts_last`
    /// after `prefix` (which ends with a comma).
    pub fn csv_rows(&self, prefix: &str) -> String {
        self.wheelsets
            .iter()
            .map(|w| {
                format!(
                    "{prefix}{},{},{},{},{},{}\n",
                    w.index,
                    w.wheelset,
                    w.saturated_mm,
                    w.death_m_s.map_or(String::new(), |v| v.to_string()),
                    w.fate.as_str(),
                    self.last_hunting_index == Some(w.index)
                )
            })
            .collect()
    }
}

impl CriticalSpeed {
    /// The hunting mode at the lowest and the highest speed evaluated with
    /// a known damping ratio: "76.0 m/s 3.19 Hz ζ +0.053; 96.0 m/s …".
    pub fn mode_text(&self) -> String {
        let known: Vec<&SpeedSample> = self
            .samples
            .iter()
            .filter(|s| s.damping_ratio.is_finite())
            .collect();
        let (Some(lo), Some(hi)) = (known.first(), known.last()) else {
            return String::new();
        };
        let one = |s: &SpeedSample| {
            format!(
                "{:.1} m/s {:.2} Hz ζ {:+.3}",
                s.speed_m_s, s.frequency_hz, s.damping_ratio
            )
        };
        if known.len() == 1 {
            one(lo)
        } else {
            format!("{}; {}", one(lo), one(hi))
        }
    }
}

impl CriticalSpeedReport {
    /// A table like the paper's Table 1.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "critical speed, {}\n  {:<10} {:<7} {:>9} {:>9} {:>10}  {:<22} hunting mode below and above (f, ζ)\n",
            self.scene, "creep law", "method", "m/s", "km/h", "f [Hz]", "bracket"
        );
        for r in &self.results {
            match r.speed_m_s {
                Some(v) => {
                    s += &format!(
                        "  {:<10} {:<7} {:>9.2} {:>9.1} {:>10.3}  {:<22} {}\n",
                        r.creep_law,
                        r.method,
                        v,
                        v * 3.6,
                        r.frequency_hz.unwrap_or(f64::NAN),
                        r.bracket_m_s
                            .map(|b| format!("{:.2} … {:.2} m/s", b.0, b.1))
                            .unwrap_or_default(),
                        r.mode_text()
                    )
                }
                None => {
                    s += &format!(
                        "  {:<10} {:<7} {:>9} {:>9} {:>10}  {}\n",
                        r.creep_law,
                        r.method,
                        "—",
                        "—",
                        "—",
                        r.note.clone().unwrap_or_default()
                    )
                }
            }
            if let Some(d) = &r.cycle_deaths {
                s += &d.to_text("      ");
            }
        }
        for f in &self.files {
            s += &format!("  wrote {f}\n");
        }
        s
    }

    /// Writes `rates.csv` and `rates.png` (rate against speed per law and
    /// method) into `dir`.
    pub fn write(&mut self, dir: &Path) -> Result<()> {
        use preproc::plot::{LineChart, Series, SeriesStyle, write_line_chart};
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let mut csv = String::from(
            "creep_law,method,speed_m_s,rate_1_s,frequency_hz,damping_ratio,results\n",
        );
        let mut chart = LineChart::new(
            format!("Growth rate of the hunting motion, {}", self.scene),
            "speed [m/s]",
            "growth rate σ [1/s] (> 0: unstable)",
        );
        for (k, r) in self.results.iter().enumerate() {
            if r.method == CriticalSpeedMethod::Ramp {
                continue;
            }
            let mut pts = Vec::new();
            for s in &r.samples {
                csv += &format!(
                    "{},{},{},{},{},{},{}\n",
                    r.creep_law,
                    r.method,
                    s.speed_m_s,
                    s.rate_1_s,
                    s.frequency_hz,
                    s.damping_ratio,
                    s.results.clone().unwrap_or_default()
                );
                if s.rate_1_s.is_finite() {
                    pts.push((s.speed_m_s, s.rate_1_s));
                }
            }
            chart.series.push(
                Series::line(format!("{} ({})", r.creep_law, r.method), pts)
                    .with_style(SeriesStyle::LineAndPoints)
                    .with_colour(k),
            );
        }
        let csv_path = dir.join("rates.csv");
        super::write_text(&csv_path, &csv)?;
        let ramps: Vec<(&CriticalSpeed, &CycleDeaths)> = self
            .results
            .iter()
            .filter_map(|r| r.cycle_deaths.as_ref().map(|d| (r, d)))
            .collect();
        if !ramps.is_empty() {
            let mut rows = String::from(
                "creep_law,criterion,wheelset_index,wheelset,saturated_mm,death_speed_m_s,fate,hunts_last\n",
            );
            for (r, d) in ramps {
                rows += &d.csv_rows(&format!("{},{},", r.creep_law, d.criterion));
            }
            let path = dir.join("ramp_wheelsets.csv");
            super::write_text(&path, &rows)?;
            self.files.push(path.display().to_string());
        }
        let png = dir.join("rates.png");
        write_line_chart(&png, &chart, (1600, 900))?;
        self.files.push(csv_path.display().to_string());
        self.files.push(png.display().to_string());
        Ok(())
    }
}
