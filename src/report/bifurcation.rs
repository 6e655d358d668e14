//! The bifurcation diagram's reports: `bifurcation.csv`,
//! `bifurcation.png` and the text summary (`docs/guide/critical-speed.md`).

use anyhow::Result;

use crate::studies::bifurcation::Bifurcation;

impl Bifurcation {
    /// Writes `bifurcation.csv` and `bifurcation.png` into `dir`.
    pub fn write(&mut self, dir: &std::path::Path) -> Result<()> {
        use preproc::plot::{LineChart, Series, SeriesStyle, write_line_chart};
        let mut csv = String::from("branch,speed_m_s,amplitude_mm\n");
        for (name, pts) in [("up_scan", &self.up_scan), ("ramp_down", &self.ramp_down)] {
            for p in pts.iter() {
                csv += &format!("{name},{},{}\n", p.speed_m_s, p.amplitude_mm);
            }
        }
        let csv_path = dir.join("bifurcation.csv");
        super::write_text(&csv_path, &csv)?;
        let chart = LineChart::new(
            format!("Bifurcation diagram, {}", self.scene),
            "speed [m/s]",
            "lateral amplitude of the leading wheelset [mm]",
        )
        .with_series(
            Series::points(
                "ramp-down continuation (peaks)",
                self.ramp_down
                    .iter()
                    .map(|p| (p.speed_m_s, p.amplitude_mm))
                    .collect(),
            )
            .with_colour(1),
        )
        .with_series(
            Series::line(
                "up-scan from a small offset",
                self.up_scan
                    .iter()
                    .map(|p| (p.speed_m_s, p.amplitude_mm))
                    .collect(),
            )
            .with_style(SeriesStyle::LineAndPoints)
            .with_colour(0),
        );
        let png = dir.join("bifurcation.png");
        write_line_chart(&png, &chart, (1600, 900))?;
        self.files = vec![csv_path.display().to_string(), png.display().to_string()];
        Ok(())
    }

    /// The text summary.
    pub fn to_text(&self) -> String {
        let f = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.2} m/s"));
        let mut s = format!(
            "bifurcation diagram, {}\n  up-scan: {} speeds in {:.1} s wall, hunting from {}\n  ramp-down: {} peaks in {:.1} s wall, cycle dies at {}\n",
            self.scene,
            self.up_scan.len(),
            self.up_scan_wall_s,
            f(self.up_scan_jump_m_s),
            self.ramp_down.len(),
            self.ramp_wall_s,
            f(self.ramp_death_m_s)
        );
        for p in &self.files {
            s += &format!("  wrote {p}\n");
        }
        s
    }
}
