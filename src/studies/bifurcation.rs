//! `sim bifurcation`: the bifurcation diagram of the hunting motion — the
//! leading wheelset's lateral amplitude against speed, two branches:
//!
//! - **up-scan**: one run per speed from the scene's small initial offset;
//!   the amplitude is the largest |lateral| over the last quarter of the run
//!   (decayed runs give ≈ 0, hunting runs their limit cycle);
//! - **ramp-down continuation**: one run that starts hunting at the top
//!   speed and decelerates slowly on a long ideal straight; every peak of
//!   the lateral motion is plotted at the speed it occurs at, so the branch
//!   follows the limit cycle down to where it dies (the nonlinear critical
//!   speed).
//!
//! Between the linear critical speed (where the up-scan jumps) and the
//! nonlinear one (where the ramp's cycle dies) both a centred run and a
//! hunting cycle are stable: the hysteresis of a subcritical bifurcation.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use rayon::prelude::*;
use serde::Serialize;

use crate::config::Variation;
use crate::config::scene::LoadedScene;
use crate::run::run_scene;

/// Settings of a diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct BifurcationSettings {
    pub min_m_s: f64,
    pub max_m_s: f64,
    /// Speed step of the up-scan (m/s).
    pub step_m_s: f64,
    /// Deceleration of the ramp-down (m/s²).
    pub deceleration_m_s2: f64,
    pub jobs: usize,
    pub out_dir: PathBuf,
}

impl BifurcationSettings {
    pub fn validate(&self) -> Result<()> {
        if !(self.min_m_s > 0.0 && self.max_m_s > self.min_m_s && self.max_m_s.is_finite()) {
            bail!(
                "speed range {} … {} m/s: need 0 < min < max",
                self.min_m_s,
                self.max_m_s
            );
        }
        if !(self.step_m_s > 0.0 && self.step_m_s <= self.max_m_s - self.min_m_s) {
            bail!(
                "speed step {} m/s must lie in (0, max − min]",
                self.step_m_s
            );
        }
        if !(self.deceleration_m_s2 > 0.0 && self.deceleration_m_s2.is_finite()) {
            bail!("deceleration {} m/s² must be > 0", self.deceleration_m_s2);
        }
        if self.jobs == 0 {
            bail!("jobs must be >= 1");
        }
        Ok(())
    }
}

/// One point of a branch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BranchPoint {
    pub speed_m_s: f64,
    /// Lateral amplitude of the leading wheelset (mm).
    pub amplitude_mm: f64,
}

/// The diagram.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bifurcation {
    pub scene: String,
    pub up_scan: Vec<BranchPoint>,
    pub ramp_down: Vec<BranchPoint>,
    /// Lowest up-scan speed whose run hunts (amplitude above half the
    /// largest), and the speed at which the ramp's cycle dies (m/s).
    pub up_scan_jump_m_s: Option<f64>,
    pub ramp_death_m_s: Option<f64>,
    /// Wall time of the up-scan and of the ramp (s).
    pub up_scan_wall_s: f64,
    pub ramp_wall_s: f64,
    pub files: Vec<String>,
}

/// Computes the diagram (module docs) and writes `bifurcation.csv` and
/// `bifurcation.png`.
pub fn bifurcation(
    scene: &LoadedScene,
    settings: &BifurcationSettings,
    stop: Arc<AtomicBool>,
) -> Result<Bifurcation> {
    settings.validate()?;
    let runs = settings.out_dir.join("runs");
    std::fs::create_dir_all(&runs).with_context(|| format!("creating {}", runs.display()))?;
    let n = ((settings.max_m_s - settings.min_m_s) / settings.step_m_s).round() as usize + 1;
    let speeds: Vec<f64> = (0..n)
        .map(|i| settings.min_m_s + settings.step_m_s * i as f64)
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.jobs)
        .build()?;
    let start = Instant::now();
    let up: Vec<Result<BranchPoint>> = pool.install(|| {
        speeds
            .par_iter()
            .map(|&v| {
                let s = scene.varied(&[Variation::Speed(v)])?;
                let output = runs.join(format!("up_{v:.3}.h5"));
                // A run that fails (a derailment) still gives its samples so far.
                let r = run_scene(&s, &mut |_| {}, Some(stop.clone()))
                    .with_context(|| format!("the run at {v} m/s"))?
                    .results;
                runtime::io::schema::write_results(&output, &r)
                    .with_context(|| format!("writing the run at {v} m/s"))?;
                let w = &r.wheelsets[0];
                let t_end = r.time_s.last().copied().unwrap_or(0.0);
                let amp = r
                    .time_s
                    .iter()
                    .zip(&w.lateral_m)
                    .filter(|(t, _)| **t >= 0.75 * t_end)
                    .fold(0.0_f64, |m, (_, y)| m.max(y.abs()));
                Ok(BranchPoint {
                    speed_m_s: v,
                    amplitude_mm: amp * 1e3,
                })
            })
            .collect()
    });
    let up_scan: Vec<BranchPoint> = up.into_iter().collect::<Result<_>>()?;
    let up_scan_wall_s = start.elapsed().as_secs_f64();

    // Ramp-down from the top speed on a long straight.
    let (v0, v1, a) = (
        settings.max_m_s,
        settings.min_m_s,
        settings.deceleration_m_s2,
    );
    let distance = (v0 * v0 - v1 * v1) / (2.0 * a);
    let mut extra = vec![Variation::Speed(v0)];
    extra.extend(Variation::ramp_on_straight(
        &scene.scene,
        a,
        distance,
        distance + scene.scene.initial.s_m + 100.0,
    ));
    let s = scene.varied(&extra)?;
    let output = runs.join("ramp_down.h5");
    let start = Instant::now();
    let ramp_result = run_scene(&s, &mut |_| {}, Some(stop)).and_then(|outcome| {
        runtime::io::schema::write_results(&output, &outcome.results)
            .with_context(|| format!("writing the ramp-down run {}", output.display()))?;
        Ok(outcome.into_parts(&output.display().to_string()))
    });
    let ramp_wall_s = start.elapsed().as_secs_f64();
    let mut ramp_down = Vec::new();
    let ramp_result = match ramp_result {
        Ok((r, summary)) => {
            let y = &r.wheelsets[0].lateral_m;
            for i in 1..y.len().saturating_sub(1) {
                let (p, c, q) = (y[i - 1].abs(), y[i].abs(), y[i + 1].abs());
                if c > p && c >= q && c > 1e-7 {
                    ramp_down.push(BranchPoint {
                        speed_m_s: (v0 - a * r.time_s[i]).max(0.0),
                        amplitude_mm: c * 1e3,
                    });
                }
            }
            summary.map(|_| ())
        }
        Err(e) => Err(e),
    };
    if let Err(e) = &ramp_result
        && ramp_down.is_empty()
    {
        bail!(
            "the ramp-down run failed: {}",
            crate::error_text::chain_text(e)
        );
    }
    let largest = up_scan.iter().map(|p| p.amplitude_mm).fold(0.0, f64::max);
    let up_scan_jump_m_s = up_scan
        .iter()
        .find(|p| largest > 0.1 && p.amplitude_mm > 0.5 * largest)
        .map(|p| p.speed_m_s);
    let saturated = {
        let mut a: Vec<f64> = ramp_down.iter().map(|p| p.amplitude_mm).collect();
        a.sort_by(f64::total_cmp);
        a.get((a.len() as f64 * 0.9) as usize)
            .copied()
            .unwrap_or(0.0)
    };
    let ramp_death_m_s = ramp_down
        .iter()
        .rev()
        .find(|p| p.amplitude_mm >= 0.25 * saturated && saturated > 0.1)
        .map(|p| p.speed_m_s);
    let out = Bifurcation {
        scene: scene.origin.clone(),
        up_scan,
        ramp_down,
        up_scan_jump_m_s,
        ramp_death_m_s,
        up_scan_wall_s,
        ramp_wall_s,
        files: Vec::new(),
    };
    Ok(out)
}
