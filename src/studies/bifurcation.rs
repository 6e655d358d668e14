//! `sim bifurcation`: the bifurcation diagram of the hunting motion — every
//! wheelset's lateral amplitude against speed, three branches:
//!
//! - **up-scan**: one run per speed from the scene's small initial offset;
//!   per wheelset the amplitude is the largest |lateral| over the last
//!   quarter of the run (decayed runs give ≈ 0, hunting runs their limit
//!   cycle);
//! - **ramp-down continuation** (`--continuation ramp`, the default): one
//!   run that starts hunting at the top speed and decelerates slowly on a
//!   long ideal straight; every peak of every wheelset's lateral motion is
//!   plotted at the speed it occurs at, so the branch follows the limit
//!   cycle down to where it dies (the nonlinear critical speed);
//! - **step-and-dwell continuation** (`--continuation step-dwell`): one run
//!   from the hunting state at the top speed that holds each speed for a
//!   dwell, stepping down ([`super::step_dwell`]); per dwell and wheelset
//!   the largest |lateral| over the dwell's second half.
//!
//! Each continuation's death speed is taken per wheelset, and the
//! vehicle's by `--criterion` ([`super::cycle_death`]: every wheelset's
//! cycle dead, by default, or the leading one's).
//!
//! Between the linear critical speed (where the up-scan jumps) and the
//! nonlinear one (where the continuation's cycle dies) both a centred run
//! and a hunting cycle are stable: the hysteresis of a subcritical
//! bifurcation.

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
use crate::studies::cycle_death::{CycleDeaths, HuntingCriterion, ramp_deaths};
use crate::studies::step_dwell;

crate::config::choices::choice! {
    /// How the hunting branch is followed down (`--continuation`; module docs).
    Continuation {
        /// One run decelerating at `--ramp-deceleration`.
        Ramp = "ramp",
        /// One run holding each speed `--dwell-s`, `--speed-step` apart.
        StepDwell = "step-dwell",
    }
}

/// Settings of a diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct BifurcationSettings {
    pub min_m_s: f64,
    pub max_m_s: f64,
    /// Speed step of the up-scan (m/s).
    pub step_m_s: f64,
    /// Deceleration of the ramp-down and of the step-dwell's steps (m/s²).
    pub deceleration_m_s2: f64,
    pub jobs: usize,
    pub out_dir: PathBuf,
    /// Whose cycles must have died.
    pub criterion: HuntingCriterion,
    /// The continuations run (at least one, none twice).
    pub continuations: Vec<Continuation>,
    /// Speed step of the step-dwell continuation (m/s).
    pub dwell_step_m_s: f64,
    /// Time each step-dwell speed is held (s).
    pub dwell_s: f64,
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
        if self.continuations.is_empty() {
            bail!("give at least one continuation (ramp, step-dwell)");
        }
        for (i, c) in self.continuations.iter().enumerate() {
            if self.continuations[..i].contains(c) {
                bail!("continuation '{c}' is given twice");
            }
        }
        if self.continuations.contains(&Continuation::StepDwell) {
            if !(self.dwell_step_m_s > 0.0 && self.dwell_step_m_s <= self.max_m_s - self.min_m_s) {
                bail!(
                    "--speed-step {} m/s must lie in (0, max − min]",
                    self.dwell_step_m_s
                );
            }
            // Below a second the cycle (3–5 Hz) has no settled second half;
            // above an hour a unit slip (ms for s).
            if !(self.dwell_s >= 1.0 && self.dwell_s <= 3600.0) {
                bail!(
                    "--dwell-s {} s must lie in [1, 3600] s (check the unit: seconds)",
                    self.dwell_s
                );
            }
        }
        Ok(())
    }
}

/// One point of a branch: one wheelset at one speed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BranchPoint {
    /// The wheelset's name in the vehicle.
    pub wheelset: String,
    /// Its index (0 = leading).
    pub wheelset_index: usize,
    pub speed_m_s: f64,
    /// Lateral amplitude of the wheelset (mm).
    pub amplitude_mm: f64,
}

/// The diagram.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Bifurcation {
    pub scene: String,
    pub criterion: HuntingCriterion,
    /// Every wheelset at every speed.
    pub up_scan: Vec<BranchPoint>,
    /// Every peak of every wheelset (empty without the ramp).
    pub ramp_down: Vec<BranchPoint>,
    /// Every dwell of every wheelset (empty without the step-dwell).
    pub step_dwell: Vec<BranchPoint>,
    /// Lowest up-scan speed whose run hunts (by the criterion: any
    /// wheelset's amplitude, or the leading one's, above half the largest)
    /// (m/s).
    pub up_scan_jump_m_s: Option<f64>,
    /// The speed at which the ramp's cycles have died by the criterion (m/s).
    pub ramp_death_m_s: Option<f64>,
    /// Per wheelset, and the one that hunts last.
    pub ramp_deaths: Option<CycleDeaths>,
    /// The lowest dwell speed with a cycle by the criterion (m/s).
    pub step_dwell_death_m_s: Option<f64>,
    pub step_dwell_deaths: Option<CycleDeaths>,
    /// Wall time of the up-scan and of each continuation (s).
    pub up_scan_wall_s: f64,
    pub ramp_wall_s: Option<f64>,
    pub step_dwell_wall_s: Option<f64>,
    /// What was changed or dropped on the way (warnings).
    pub notes: Vec<String>,
    pub files: Vec<String>,
}

/// The outcome of one continuation run.
#[derive(Debug, Clone, PartialEq)]
pub struct Continued {
    /// Every wheelset's points of the branch.
    pub points: Vec<BranchPoint>,
    pub deaths: CycleDeaths,
    pub wall_s: f64,
    pub note: Option<String>,
}

/// The largest |lateral| of every wheelset over the last quarter of `r`.
fn last_quarter_amplitudes(r: &runtime::results::RunResults, v: f64) -> Vec<BranchPoint> {
    let t_end = r.time_s.last().copied().unwrap_or(0.0);
    r.wheelsets
        .iter()
        .enumerate()
        .map(|(i, w)| {
            let amp = r
                .time_s
                .iter()
                .zip(&w.lateral_m)
                .filter(|(t, _)| **t >= 0.75 * t_end)
                .fold(0.0_f64, |m, (_, y)| m.max(y.abs()));
            BranchPoint {
                wheelset: w.name.clone(),
                wheelset_index: i,
                speed_m_s: v,
                amplitude_mm: amp * 1e3,
            }
        })
        .collect()
}

/// The lowest speed of the up-scan that hunts (by the criterion).
pub fn up_scan_jump(up_scan: &[BranchPoint], criterion: HuntingCriterion) -> Option<f64> {
    let counted = |p: &&BranchPoint| criterion == HuntingCriterion::All || p.wheelset_index == 0;
    let largest = up_scan
        .iter()
        .filter(counted)
        .map(|p| p.amplitude_mm)
        .fold(0.0, f64::max);
    up_scan
        .iter()
        .filter(counted)
        .filter(|p| largest > 0.1 && p.amplitude_mm > 0.5 * largest)
        .map(|p| p.speed_m_s)
        .min_by(f64::total_cmp)
}

/// Runs `s` and writes its results to `output`: the results (those so far
/// if the run failed, with the error) or the error alone.
fn run_and_write(
    s: &LoadedScene,
    output: &std::path::Path,
    stop: Arc<AtomicBool>,
    what: &str,
) -> Result<(runtime::results::RunResults, Result<()>)> {
    let outcome =
        run_scene(s, &mut |_| {}, Some(stop)).with_context(|| format!("the {what} run"))?;
    runtime::io::schema::write_results(output, &outcome.results)
        .with_context(|| format!("writing the {what} run {}", output.display()))?;
    let (results, summary) = outcome.into_parts(&output.display().to_string());
    Ok((results, summary.map(|_| ())))
}

/// The ramp-down continuation (module docs).
fn ramp_down(
    scene: &LoadedScene,
    settings: &BifurcationSettings,
    runs: &std::path::Path,
    stop: Arc<AtomicBool>,
) -> Result<Continued> {
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
    let start = Instant::now();
    let (r, ended) = run_and_write(&s, &runs.join("ramp_down.h5"), stop, "ramp-down")?;
    let wall_s = start.elapsed().as_secs_f64();
    let (deaths, peaks) = ramp_deaths(&r, v0, v1, a, settings.criterion);
    let points: Vec<BranchPoint> = peaks
        .iter()
        .enumerate()
        .flat_map(|(i, p)| {
            let name = r.wheelsets[i].name.clone();
            p.iter()
                .filter(|q| q.amplitude_m > 1e-7)
                .map(move |q| BranchPoint {
                    wheelset: name.clone(),
                    wheelset_index: i,
                    speed_m_s: q.speed_m_s,
                    amplitude_mm: q.amplitude_m * 1e3,
                })
        })
        .collect();
    if let Err(e) = &ended
        && points.is_empty()
    {
        bail!(
            "the ramp-down run failed: {}",
            crate::error_text::chain_text(e)
        );
    }
    let note = ended.err().map(|e| {
        format!(
            "the ramp-down run ended early ({}): its branch stops there",
            crate::error_text::chain_text(&e)
        )
    });
    Ok(Continued {
        points,
        deaths,
        wall_s,
        note,
    })
}

/// The step-and-dwell continuation ([`step_dwell`]): the branch's points
/// are the dwells' amplitudes; its results go to `runs/step_dwell.h5`.
pub fn step_and_dwell(
    scene: &LoadedScene,
    settings: &BifurcationSettings,
    runs: &std::path::Path,
    stop: Arc<AtomicBool>,
) -> Result<Continued> {
    let sched = step_dwell::schedule(
        settings.max_m_s,
        settings.min_m_s,
        settings.dwell_step_m_s,
        settings.dwell_s,
        settings.deceleration_m_s2,
    )?;
    let (extra, step_note) = step_dwell::variations(scene, &sched)?;
    let s = scene.varied(&extra)?;
    let start = Instant::now();
    let (r, ended) = run_and_write(&s, &runs.join("step_dwell.h5"), stop, "step-dwell")?;
    let wall_s = start.elapsed().as_secs_f64();
    let amps = step_dwell::dwell_amplitudes(&r, &sched.dwells);
    let deaths = step_dwell::dwell_deaths(
        &amps,
        &sched.dwells,
        settings.criterion,
        settings.max_m_s,
        settings.min_m_s,
    );
    let reached = amps.first().map_or(0, Vec::len);
    let points: Vec<BranchPoint> = amps
        .into_iter()
        .flatten()
        .map(|a| BranchPoint {
            wheelset: a.wheelset,
            wheelset_index: a.wheelset_index,
            speed_m_s: a.speed_m_s,
            amplitude_mm: a.amplitude_mm,
        })
        .collect();
    if let Err(e) = &ended
        && points.is_empty()
    {
        bail!(
            "the step-dwell run failed: {}",
            crate::error_text::chain_text(e)
        );
    }
    let mut notes: Vec<String> = step_note.into_iter().collect();
    if let Err(e) = ended {
        notes.push(format!(
            "the step-dwell run ended early ({}): {} of {} dwells measured, the others dropped",
            crate::error_text::chain_text(&e),
            reached,
            sched.dwells.len()
        ));
    }
    Ok(Continued {
        points,
        deaths,
        wall_s,
        note: (!notes.is_empty()).then(|| notes.join("; ")),
    })
}

/// Computes the diagram (module docs); [`Bifurcation::write`] writes
/// `bifurcation.csv` and `bifurcation.png`.
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
    // The continuations (long single runs) start first, side by side with
    // the up-scan's runs on the same threads.
    let (continued, (up, up_scan_wall_s)) = pool.install(|| {
        rayon::join(
            || -> Vec<(Continuation, Result<Continued>)> {
                settings
                    .continuations
                    .par_iter()
                    .map(|c| {
                        let r = match c {
                            Continuation::Ramp => ramp_down(scene, settings, &runs, stop.clone()),
                            Continuation::StepDwell => {
                                step_and_dwell(scene, settings, &runs, stop.clone())
                            }
                        };
                        (*c, r)
                    })
                    .collect()
            },
            || {
                let start = Instant::now();
                let up: Vec<Result<Vec<BranchPoint>>> = speeds
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
                        Ok(last_quarter_amplitudes(&r, v))
                    })
                    .collect();
                (up, start.elapsed().as_secs_f64())
            },
        )
    });
    let up_scan: Vec<BranchPoint> = up
        .into_iter()
        .collect::<Result<Vec<_>>>()?
        .into_iter()
        .flatten()
        .collect();
    let mut out = Bifurcation {
        scene: scene.origin.clone(),
        criterion: settings.criterion,
        up_scan_jump_m_s: up_scan_jump(&up_scan, settings.criterion),
        up_scan,
        ramp_down: Vec::new(),
        step_dwell: Vec::new(),
        ramp_death_m_s: None,
        ramp_deaths: None,
        step_dwell_death_m_s: None,
        step_dwell_deaths: None,
        up_scan_wall_s,
        ramp_wall_s: None,
        step_dwell_wall_s: None,
        notes: Vec::new(),
        files: Vec::new(),
    };
    for (c, r) in continued {
        let r = r.with_context(|| format!("the {c} continuation"))?;
        out.notes.extend(r.note);
        match c {
            Continuation::Ramp => {
                out.ramp_down = r.points;
                out.ramp_death_m_s = r.deaths.speed_m_s;
                out.ramp_deaths = Some(r.deaths);
                out.ramp_wall_s = Some(r.wall_s);
            }
            Continuation::StepDwell => {
                out.step_dwell = r.points;
                out.step_dwell_death_m_s = r.deaths.speed_m_s;
                out.step_dwell_deaths = Some(r.deaths);
                out.step_dwell_wall_s = Some(r.wall_s);
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(i: usize, v: f64, a: f64) -> BranchPoint {
        BranchPoint {
            wheelset: format!("ws{i}"),
            wheelset_index: i,
            speed_m_s: v,
            amplitude_mm: a,
        }
    }

    #[test]
    fn the_up_scan_jumps_where_any_wheelset_or_the_leading_one_hunts() {
        // At 80 m/s only the trailing wheelset hunts; at 90 both.
        let up = vec![
            point(0, 70.0, 0.0),
            point(1, 70.0, 0.0),
            point(0, 80.0, 0.01),
            point(1, 80.0, 6.0),
            point(0, 90.0, 5.0),
            point(1, 90.0, 6.0),
        ];
        assert_eq!(up_scan_jump(&up, HuntingCriterion::All), Some(80.0));
        assert_eq!(up_scan_jump(&up, HuntingCriterion::Leading), Some(90.0));
    }

    #[test]
    fn settings_name_the_violated_rule() {
        let good = BifurcationSettings {
            min_m_s: 50.0,
            max_m_s: 100.0,
            step_m_s: 5.0,
            deceleration_m_s2: 0.5,
            jobs: 2,
            out_dir: PathBuf::new(),
            criterion: HuntingCriterion::All,
            continuations: vec![Continuation::Ramp, Continuation::StepDwell],
            dwell_step_m_s: 0.5,
            dwell_s: 10.0,
        };
        assert!(good.validate().is_ok());
        let err = |edit: fn(&mut BifurcationSettings)| {
            let mut s = good.clone();
            edit(&mut s);
            s.validate().unwrap_err().to_string()
        };
        assert!(
            err(|s| s.continuations.push(Continuation::Ramp)).contains("'ramp' is given twice")
        );
        assert!(err(|s| s.continuations.clear()).contains("at least one continuation"));
        assert!(err(|s| s.dwell_s = 0.01).contains("check the unit"));
        assert!(err(|s| s.dwell_step_m_s = 0.0).contains("--speed-step"));
        assert_eq!(
            "step-dwell".parse::<Continuation>(),
            Ok(Continuation::StepDwell)
        );
    }
}
