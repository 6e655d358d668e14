//! The bifurcation diagram's reports: `bifurcation.csv` (every branch point
//! of every wheelset), `bifurcation_deaths.csv` (every wheelset's death
//! speed per continuation), `bifurcation.png` and the text summary
//! (`docs/guide/critical-speed.md`).

use anyhow::Result;

use crate::studies::bifurcation::{Bifurcation, BranchPoint};
use crate::studies::cycle_death::CycleDeaths;

/// The branches as the CSV and the plot name them.
const UP_SCAN: &str = "up_scan";
const RAMP_DOWN: &str = "ramp_down";
const STEP_DWELL: &str = "step-dwell";

impl Bifurcation {
    /// The branches with their CSV names.
    fn branches(&self) -> [(&'static str, &Vec<BranchPoint>); 3] {
        [
            (UP_SCAN, &self.up_scan),
            (RAMP_DOWN, &self.ramp_down),
            (STEP_DWELL, &self.step_dwell),
        ]
    }

    /// The continuations' deaths with their CSV names.
    fn deaths(&self) -> Vec<(&'static str, &CycleDeaths)> {
        [
            (RAMP_DOWN, self.ramp_deaths.as_ref()),
            (STEP_DWELL, self.step_dwell_deaths.as_ref()),
        ]
        .into_iter()
        .filter_map(|(n, d)| d.map(|d| (n, d)))
        .collect()
    }

    /// `bifurcation.csv`: `branch,wheelset,speed_m_s,amplitude_mm`.
    pub fn csv(&self) -> String {
        let mut csv = String::from("branch,wheelset,speed_m_s,amplitude_mm\n");
        for (name, pts) in self.branches() {
            for p in pts.iter() {
                csv += &format!("{name},{},{},{}\n", p.wheelset, p.speed_m_s, p.amplitude_mm);
            }
        }
        csv
    }

    /// Writes `bifurcation.csv`, `bifurcation_deaths.csv` and
    /// `bifurcation.png` into `dir`.
    pub fn write(&mut self, dir: &std::path::Path) -> Result<()> {
        use preproc::plot::{LineChart, Series, SeriesStyle, write_line_chart};
        let csv_path = dir.join("bifurcation.csv");
        super::write_text(&csv_path, &self.csv())?;
        let mut deaths = String::from(
            "continuation,criterion,wheelset_index,wheelset,saturated_mm,death_speed_m_s,fate,hunts_last\n",
        );
        for (name, d) in self.deaths() {
            deaths += &d.csv_rows(&format!("{name},{},", d.criterion));
        }
        let deaths_path = dir.join("bifurcation_deaths.csv");
        super::write_text(&deaths_path, &deaths)?;
        let mut chart = LineChart::new(
            format!("Bifurcation diagram, {}", self.scene),
            "speed [m/s]",
            "lateral amplitude of each wheelset [mm]",
        );
        let names: Vec<(usize, String)> = {
            let mut n: Vec<(usize, String)> = self
                .up_scan
                .iter()
                .chain(&self.ramp_down)
                .chain(&self.step_dwell)
                .map(|p| (p.wheelset_index, p.wheelset.clone()))
                .collect();
            n.sort();
            n.dedup();
            n
        };
        let of = |pts: &[BranchPoint], i: usize| -> Vec<(f64, f64)> {
            pts.iter()
                .filter(|p| p.wheelset_index == i)
                .map(|p| (p.speed_m_s, p.amplitude_mm))
                .collect()
        };
        for (i, name) in &names {
            let ramp = of(&self.ramp_down, *i);
            if !ramp.is_empty() {
                chart
                    .series
                    .push(Series::points(format!("ramp-down peaks, {name}"), ramp).with_colour(*i));
            }
            let dwell = of(&self.step_dwell, *i);
            if !dwell.is_empty() {
                chart.series.push(
                    Series::line(format!("step-dwell, {name}"), dwell)
                        .with_style(SeriesStyle::LineAndPoints)
                        .with_colour(*i),
                );
            }
            chart.series.push(
                Series::line(format!("up-scan, {name}"), of(&self.up_scan, *i)).with_colour(*i),
            );
        }
        // The death speeds: a vertical line each, to the largest amplitude.
        let top = self
            .branches()
            .iter()
            .flat_map(|(_, p)| p.iter().map(|p| p.amplitude_mm))
            .fold(0.0, f64::max);
        for (k, (name, d)) in self.deaths().into_iter().enumerate() {
            if let (Some(v), Some(who)) = (d.speed_m_s, &d.last_hunting) {
                chart.series.push(
                    Series::line(
                        format!(
                            "{}: every cycle dead at {v:.2} m/s ('{who}' last, criterion {})",
                            name.replace('_', "-"),
                            d.criterion
                        ),
                        vec![(v, 0.0), (v, top)],
                    )
                    .with_colour(names.len() + k),
                );
            }
        }
        let png = dir.join("bifurcation.png");
        write_line_chart(&png, &chart, (1600, 900))?;
        self.files = vec![
            csv_path.display().to_string(),
            deaths_path.display().to_string(),
            png.display().to_string(),
        ];
        Ok(())
    }

    /// The text summary.
    pub fn to_text(&self) -> String {
        let f = |v: Option<f64>| v.map_or("—".to_string(), |v| format!("{v:.2} m/s"));
        let speeds = {
            let mut v: Vec<f64> = self.up_scan.iter().map(|p| p.speed_m_s).collect();
            v.dedup();
            v.len()
        };
        let mut s = format!(
            "bifurcation diagram, {} (criterion {})\n  up-scan: {speeds} speeds in {:.1} s wall, hunting from {}\n",
            self.scene,
            self.criterion,
            self.up_scan_wall_s,
            f(self.up_scan_jump_m_s),
        );
        if let (Some(d), Some(wall)) = (&self.ramp_deaths, self.ramp_wall_s) {
            s += &format!(
                "  ramp-down: {} peaks in {wall:.1} s wall, cycles dead at {}{}\n",
                self.ramp_down.len(),
                f(self.ramp_death_m_s),
                d.note.as_ref().map_or(String::new(), |n| format!(" ({n})"))
            );
            s += &d.to_text("    ");
        }
        if let (Some(d), Some(wall)) = (&self.step_dwell_deaths, self.step_dwell_wall_s) {
            s += &format!(
                "  step-dwell: {} dwells in {wall:.1} s wall, last hunting dwell {}{}\n",
                self.step_dwell
                    .iter()
                    .filter(|p| p.wheelset_index == 0)
                    .count(),
                f(self.step_dwell_death_m_s),
                d.note.as_ref().map_or(String::new(), |n| format!(" ({n})"))
            );
            s += &d.to_text("    ");
        }
        for n in &self.notes {
            s += &format!("  warning: {n}\n");
        }
        for p in &self.files {
            s += &format!("  wrote {p}\n");
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use crate::studies::bifurcation::{Bifurcation, BranchPoint};
    use crate::studies::cycle_death::{HuntingCriterion, ramp_deaths, tests::two_wheelset_ramp};

    #[test]
    fn every_wheelset_in_the_csv_the_text_and_the_plot() {
        let r = two_wheelset_ramp([40.0, 60.0]);
        let (deaths, _) = ramp_deaths(&r, 100.0, 50.0, 0.5, HuntingCriterion::All);
        let p = |w: &str, i, v, a| BranchPoint {
            wheelset: w.into(),
            wheelset_index: i,
            speed_m_s: v,
            amplitude_mm: a,
        };
        let mut b = Bifurcation {
            scene: "synthetic".into(),
            criterion: HuntingCriterion::All,
            up_scan: vec![p("front", 0, 90.0, 5.0), p("rear", 1, 90.0, 4.0)],
            ramp_down: vec![p("rear", 1, 70.0, 4.9)],
            step_dwell: vec![p("front", 0, 80.0, 4.5)],
            up_scan_jump_m_s: Some(90.0),
            ramp_death_m_s: deaths.speed_m_s,
            ramp_deaths: Some(deaths),
            step_dwell_death_m_s: None,
            step_dwell_deaths: None,
            up_scan_wall_s: 1.0,
            ramp_wall_s: Some(2.0),
            step_dwell_wall_s: None,
            notes: vec!["a note".into()],
            files: vec![],
        };
        let csv = b.csv();
        assert!(csv.starts_with("branch,wheelset,speed_m_s,amplitude_mm\n"));
        assert!(csv.contains("up_scan,rear,90,4\n"), "{csv}");
        assert!(csv.contains("ramp_down,rear,70,4.9\n"), "{csv}");
        assert!(csv.contains("step-dwell,front,80,4.5\n"), "{csv}");
        let dir = std::env::temp_dir().join(format!("bif_report_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        b.write(&dir).unwrap();
        let d = std::fs::read_to_string(dir.join("bifurcation_deaths.csv")).unwrap();
        assert!(d.contains("ramp_down,all,1,rear,"), "{d}");
        assert!(d.lines().nth(2).unwrap().ends_with(",died,true"), "{d}");
        assert!(dir.join("bifurcation.png").exists());
        let t = b.to_text();
        assert!(
            t.contains("wheelset 0 'front': saturated 5.00 mm, cycle dies at 79."),
            "{t}"
        );
        assert!(t.contains("criterion all: hunts last 'rear'"), "{t}");
        assert!(t.contains("warning: a note"), "{t}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
