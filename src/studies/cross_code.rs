//! `sim cross-code`: one vehicle in several formulations, side by side —
//! the published formulation of a model, ours, and ours with each
//! difference switched alone (`[formulation]`, crate::config::formulation;
//! the Cooperrider car against DYTSI: docs/guide/cooperrider-cross-code.md).
//!
//! For every variant of the study file:
//!
//! - the **linear critical speed** and the hunting frequency there
//!   (eigenvalues of the centred run, [`super::critical_speed::linear_domain`]);
//! - the **nonlinear critical speed by a ramp**: the speed ramped down from
//!   a hunting cycle above the linear critical speed, the speed at which
//!   every wheelset's cycle has died ([`super::critical_speed::ramp`]);
//! - the **step-and-dwell continuation**: the speed held for a dwell at
//!   each step down from the same hunting state, the cycle amplitude of
//!   every wheelset at each dwell, and the speed at which every wheelset's
//!   cycle has died ([`super::bifurcation`]);
//! - the cycle amplitude of every wheelset at the study's speeds (from the
//!   dwells).
//!
//! The study file (TOML, paths relative to it):
//!
//! ```toml
//! title = "…"
//! scene = "../scenes/cooperrider_straight.toml"
//! set = ["initial.lateral_m=1e-4"]        # for every run of every variant
//! [linear]
//! min_m_s = 60.0
//! max_m_s = 140.0
//! tol_m_s = 0.05
//! [nonlinear]
//! start_m_s = 120.0                        # above every variant's linear critical speed
//! min_m_s = 40.0
//! start_lateral_m = 0.006                  # the offset that starts the hunting cycle
//! deceleration_m_s2 = 0.5                  # the ramp's, and the steps' between dwells
//! speed_step_m_s = 0.5
//! dwell_s = 10.0
//! amplitudes_at_m_s = [60.0, 80.0, 100.0]
//! [[variants]]
//! name = "ours"
//! plot = true
//! [[variants]]
//! name = "published"
//! vehicle = "../vehicles/cooperrider_published.toml"
//! set = ["formulation.preset=published"]
//! plot = true
//! ```

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, Result, bail, ensure};
use serde::{Deserialize, Serialize};

use super::bifurcation::{BifurcationSettings, BranchPoint, Continuation, step_and_dwell};
use super::critical_speed::{CriticalSpeedSettings, linear_domain, ramp};
use super::cycle_death::{CycleDeaths, HuntingCriterion};
use crate::config::Variation;
use crate::config::scene::LoadedScene;

/// `[linear]` of a study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinearSection {
    pub min_m_s: f64,
    pub max_m_s: f64,
    #[serde(default = "default_tol")]
    pub tol_m_s: f64,
}

fn default_tol() -> f64 {
    0.05
}

/// `[nonlinear]` of a study file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NonlinearSection {
    pub start_m_s: f64,
    pub min_m_s: f64,
    pub start_lateral_m: f64,
    #[serde(default = "default_deceleration")]
    pub deceleration_m_s2: f64,
    #[serde(default = "default_speed_step")]
    pub speed_step_m_s: f64,
    #[serde(default = "default_dwell")]
    pub dwell_s: f64,
    #[serde(default)]
    pub amplitudes_at_m_s: Vec<f64>,
}

fn default_deceleration() -> f64 {
    0.5
}
fn default_speed_step() -> f64 {
    0.5
}
fn default_dwell() -> f64 {
    10.0
}

/// One `[[variants]]` entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VariantEntry {
    pub name: String,
    /// A vehicle file instead of the scene's (relative to the study file).
    #[serde(default)]
    pub vehicle: Option<PathBuf>,
    /// Scene entries, `key=value` as `--set` takes them.
    #[serde(default)]
    pub set: Vec<String>,
    /// Drawn in the bifurcation plot.
    #[serde(default)]
    pub plot: bool,
}

/// A study file (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StudyFile {
    #[serde(default)]
    pub title: String,
    pub scene: PathBuf,
    #[serde(default)]
    pub set: Vec<String>,
    pub linear: LinearSection,
    pub nonlinear: NonlinearSection,
    pub variants: Vec<VariantEntry>,
}

impl StudyFile {
    /// Reads and checks a study file; its errors name the file (and the
    /// line and column, for TOML errors).
    pub fn load(path: &Path) -> Result<(StudyFile, PathBuf)> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("reading the study file {}", path.display()))?;
        // The TOML reader's message names the line and column.
        let study: StudyFile = toml::from_str(&text)
            .with_context(|| format!("in the study file {}", path.display()))?;
        study
            .validate()
            .with_context(|| format!("in the study file {}", path.display()))?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok((study, dir))
    }

    /// Checks every rule, naming the one violated.
    pub fn validate(&self) -> Result<()> {
        let (l, n) = (&self.linear, &self.nonlinear);
        ensure!(
            l.min_m_s > 0.0 && l.max_m_s > l.min_m_s && l.max_m_s <= 150.0,
            "[linear] min_m_s = {}, max_m_s = {}: need 0 < min < max <= 150 m/s (check the unit: m/s)",
            l.min_m_s,
            l.max_m_s
        );
        ensure!(
            l.tol_m_s > 0.0 && l.tol_m_s.is_finite(),
            "[linear] tol_m_s = {} must be > 0",
            l.tol_m_s
        );
        ensure!(
            n.min_m_s > 0.0 && n.start_m_s > n.min_m_s && n.start_m_s <= 150.0,
            "[nonlinear] min_m_s = {}, start_m_s = {}: need 0 < min < start <= 150 m/s (check the unit: m/s)",
            n.min_m_s,
            n.start_m_s
        );
        ensure!(
            n.start_lateral_m.is_finite() && n.start_lateral_m.abs() <= 0.02,
            "[nonlinear] start_lateral_m = {} must lie within ±0.02 m (check the unit: m)",
            n.start_lateral_m
        );
        for (key, v) in [
            ("deceleration_m_s2", n.deceleration_m_s2),
            ("speed_step_m_s", n.speed_step_m_s),
            ("dwell_s", n.dwell_s),
        ] {
            ensure!(
                v > 0.0 && v.is_finite(),
                "[nonlinear] {key} = {v} must be finite and > 0"
            );
        }
        for v in &n.amplitudes_at_m_s {
            ensure!(
                *v >= n.min_m_s && *v <= n.start_m_s,
                "[nonlinear] amplitudes_at_m_s: {v} m/s lies outside min_m_s … start_m_s"
            );
        }
        ensure!(!self.variants.is_empty(), "the study has no [[variants]]");
        for (i, v) in self.variants.iter().enumerate() {
            ensure!(!v.name.trim().is_empty(), "variant {} has no name", i + 1);
            if self.variants[..i].iter().any(|w| w.name == v.name) {
                bail!("variant name '{}' is given twice", v.name);
            }
        }
        Ok(())
    }
}

/// The nonlinear critical speed of one continuation: where every wheelset's
/// cycle has died, and which wheelset hunted last.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CycleDeath {
    /// `None` when the cycle survives down to the lowest speed, or none was
    /// found at the start.
    pub speed_m_s: Option<f64>,
    pub last_wheelset: Option<String>,
    /// Each wheelset's death speed (m/s), vehicle order.
    pub per_wheelset_m_s: Vec<(String, Option<f64>)>,
    pub note: Option<String>,
    pub wall_s: f64,
}

impl CycleDeath {
    fn new(
        speed_m_s: Option<f64>,
        deaths: Option<&CycleDeaths>,
        note: Option<String>,
        wall_s: f64,
    ) -> Self {
        CycleDeath {
            speed_m_s,
            last_wheelset: deaths.and_then(|d| d.last_hunting.clone()),
            per_wheelset_m_s: deaths.map_or(Vec::new(), |d| {
                d.wheelsets
                    .iter()
                    .map(|w| (w.wheelset.clone(), w.death_m_s))
                    .collect()
            }),
            note: note.or_else(|| deaths.and_then(|d| d.note.clone())),
            wall_s,
        }
    }
}

/// The results of one variant.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VariantResult {
    pub name: String,
    /// The scene entries of the variant (as `--set` takes them).
    pub set: Vec<String>,
    pub plot: bool,
    pub linear_m_s: Option<f64>,
    pub linear_frequency_hz: Option<f64>,
    pub linear_note: Option<String>,
    pub ramp: CycleDeath,
    pub step_dwell: CycleDeath,
    /// Per dwell speed and wheelset, the cycle amplitude (mm).
    pub dwell_amplitudes: Vec<BranchPoint>,
    /// The amplitudes at the study's speeds: (speed, [(wheelset, mm)]).
    pub amplitudes_at: Vec<(f64, Vec<(String, f64)>)>,
    pub wall_s: f64,
}

/// Everything `sim cross-code` reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrossCodeReport {
    pub title: String,
    pub study: String,
    pub scene: String,
    pub command: String,
    pub variants: Vec<VariantResult>,
    pub files: Vec<String>,
}

/// The scene of one variant: the study's scene with the study's entries,
/// the variant's vehicle and entries.
pub fn variant_scene(study: &StudyFile, dir: &Path, variant: &VariantEntry) -> Result<LoadedScene> {
    let mut set = study.set.clone();
    if let Some(v) = &variant.vehicle {
        let path = dir.join(v);
        let abs = std::fs::canonicalize(&path)
            .with_context(|| format!("variant '{}': vehicle {}", variant.name, path.display()))?;
        set.push(format!(
            "vehicle.file={}",
            toml_string(&abs.display().to_string())
        ));
    }
    set.extend(variant.set.iter().cloned());
    LoadedScene::load(&dir.join(&study.scene), &set)
        .with_context(|| format!("the scene of variant '{}'", variant.name))
}

/// A TOML basic string of `s`.
fn toml_string(s: &str) -> String {
    toml::Value::String(s.to_string()).to_string()
}

/// Runs the study (module docs): `jobs` variants at a time (each variant's
/// runs one after the other). `progress` receives a line per step.
pub fn cross_code(
    study: &StudyFile,
    dir: &Path,
    out_dir: &Path,
    jobs: usize,
    stop: Arc<AtomicBool>,
    progress: &mut (dyn FnMut(&str) + Send),
) -> Result<CrossCodeReport> {
    use rayon::prelude::*;
    study.validate()?;
    ensure!(jobs >= 1, "jobs must be >= 1");
    let progress = std::sync::Mutex::new(progress);
    let say = |m: String| {
        if let Ok(mut p) = progress.lock() {
            p(&m);
        }
    };
    let pool = rayon::ThreadPoolBuilder::new().num_threads(jobs).build()?;
    let variants: Vec<Result<VariantResult>> = pool.install(|| {
        study
            .variants
            .par_iter()
            .map(|v| run_variant(study, dir, out_dir, v, stop.clone(), &say))
            .collect()
    });
    Ok(CrossCodeReport {
        title: study.title.clone(),
        study: String::new(),
        scene: dir.join(&study.scene).display().to_string(),
        command: String::new(),
        variants: variants.into_iter().collect::<Result<_>>()?,
        files: Vec::new(),
    })
}

/// One variant of the study (module docs).
fn run_variant(
    study: &StudyFile,
    dir: &Path,
    out_dir: &Path,
    v: &VariantEntry,
    stop: Arc<AtomicBool>,
    say: &(dyn Fn(String) + Sync),
) -> Result<VariantResult> {
    let started = Instant::now();
    let scene = variant_scene(study, dir, v)?;
    let law = scene.scene.contact.creep_law;
    let vdir = out_dir.join(slug(&v.name));
    say(format!("{}: linear critical speed", v.name));
    let lin_settings = CriticalSpeedSettings {
        laws: vec![law],
        min_m_s: study.linear.min_m_s,
        max_m_s: study.linear.max_m_s,
        tol_m_s: study.linear.tol_m_s,
        jobs: 1,
        methods: vec![],
        out_dir: vdir.clone(),
        skip_s: 1.0,
        ramp_deceleration_m_s2: study.nonlinear.deceleration_m_s2,
        criterion: HuntingCriterion::All,
    };
    let lin = linear_domain(&scene, law, &lin_settings, stop.clone())
        .with_context(|| format!("variant '{}': the linear critical speed", v.name))?;
    let n = &study.nonlinear;
    let hunting = scene
        .varied(&[Variation::Set(
            "initial.lateral_m".into(),
            toml::Value::Float(n.start_lateral_m),
        )])
        .with_context(|| format!("variant '{}': the hunting start", v.name))?;
    say(format!(
        "{}: ramp {} → {} m/s",
        v.name, n.start_m_s, n.min_m_s
    ));
    let ramp_settings = CriticalSpeedSettings {
        min_m_s: n.min_m_s,
        max_m_s: n.start_m_s,
        ramp_deceleration_m_s2: n.deceleration_m_s2,
        ..lin_settings.clone()
    };
    let t = Instant::now();
    let r = ramp(&hunting, law, &ramp_settings, stop.clone())
        .with_context(|| format!("variant '{}': the ramp", v.name))?;
    let ramp_death = CycleDeath::new(
        r.speed_m_s,
        r.cycle_deaths.as_ref(),
        r.note.clone(),
        t.elapsed().as_secs_f64(),
    );
    say(format!(
        "{}: step-and-dwell {} → {} m/s, {} m/s steps held {} s",
        v.name, n.start_m_s, n.min_m_s, n.speed_step_m_s, n.dwell_s
    ));
    let bif_settings = BifurcationSettings {
        min_m_s: n.min_m_s,
        max_m_s: n.start_m_s,
        step_m_s: n.speed_step_m_s,
        deceleration_m_s2: n.deceleration_m_s2,
        jobs: 1,
        out_dir: vdir.clone(),
        continuations: vec![Continuation::StepDwell],
        dwell_step_m_s: n.speed_step_m_s,
        dwell_s: n.dwell_s,
        criterion: HuntingCriterion::All,
    };
    let runs = vdir.join("runs");
    std::fs::create_dir_all(&runs).with_context(|| format!("creating {}", runs.display()))?;
    let sd = step_and_dwell(&hunting, &bif_settings, &runs, stop)
        .with_context(|| format!("variant '{}': the step-and-dwell continuation", v.name))?;
    let step_death = CycleDeath::new(
        sd.deaths.speed_m_s,
        Some(&sd.deaths),
        sd.note.clone(),
        sd.wall_s,
    );
    let amplitudes_at = n
        .amplitudes_at_m_s
        .iter()
        .map(|&speed| (speed, amplitudes_near(&sd.points, speed, n.speed_step_m_s)))
        .collect();
    say(format!(
        "{}: done in {:.0} s",
        v.name,
        started.elapsed().as_secs_f64()
    ));
    Ok(VariantResult {
        name: v.name.clone(),
        set: scene_entries(v),
        plot: v.plot,
        linear_m_s: lin.speed_m_s,
        linear_frequency_hz: lin.frequency_hz,
        linear_note: lin.note.clone(),
        ramp: ramp_death,
        step_dwell: step_death,
        dwell_amplitudes: sd.points,
        amplitudes_at,
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// The variant's entries as a user would type them (vehicle first).
fn scene_entries(v: &VariantEntry) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(p) = &v.vehicle {
        out.push(format!("vehicle.file={}", p.display()));
    }
    out.extend(v.set.iter().cloned());
    out
}

/// Every wheelset's amplitude at the dwell nearest `speed_m_s` (within
/// half a step), vehicle order; none when no dwell is that near.
fn amplitudes_near(
    amplitudes: &[BranchPoint],
    speed_m_s: f64,
    step_m_s: f64,
) -> Vec<(String, f64)> {
    let nearest = amplitudes
        .iter()
        .map(|a| a.speed_m_s)
        .filter(|s| (s - speed_m_s).abs() <= 0.5 * step_m_s + 1e-9)
        .min_by(|a, b| (a - speed_m_s).abs().total_cmp(&(b - speed_m_s).abs()));
    match nearest {
        Some(s) => amplitudes
            .iter()
            .filter(|a| a.speed_m_s == s)
            .map(|a| (a.wheelset.clone(), a.amplitude_mm))
            .collect(),
        None => Vec::new(),
    }
}

/// A directory name for a variant: letters, digits and '_'.
fn slug(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn study(text: &str) -> Result<StudyFile> {
        let s: StudyFile = toml::from_str(text)?;
        s.validate()?;
        Ok(s)
    }

    const GOOD: &str = r#"
scene = "s.toml"
[linear]
min_m_s = 60.0
max_m_s = 140.0
[nonlinear]
start_m_s = 120.0
min_m_s = 40.0
start_lateral_m = 0.006
amplitudes_at_m_s = [60.0, 100.0]
[[variants]]
name = "ours"
"#;

    #[test]
    fn a_study_file_is_checked_rule_by_rule() {
        study(GOOD).unwrap();
        let e = study(&GOOD.replace("start_m_s = 120.0", "start_m_s = 432.0"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("start_m_s") && e.contains("check the unit"),
            "{e}"
        );
        let e = study(&GOOD.replace("[60.0, 100.0]", "[30.0]"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("amplitudes_at_m_s"), "{e}");
        let e = study(&format!("{GOOD}[[variants]]\nname = \"ours\"\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("given twice"), "{e}");
        assert!(study(&GOOD.replace("[[variants]]", "[[variant]]")).is_err());
    }

    #[test]
    fn the_amplitudes_at_a_speed_come_from_the_nearest_dwell() {
        let a = |s: f64, w: &str, mm: f64| BranchPoint {
            speed_m_s: s,
            wheelset: w.into(),
            wheelset_index: usize::from(w == "rear"),
            amplitude_mm: mm,
        };
        let dwells = vec![
            a(80.5, "front", 5.0),
            a(80.5, "rear", 4.0),
            a(80.0, "front", 4.9),
            a(80.0, "rear", 3.9),
        ];
        assert_eq!(
            amplitudes_near(&dwells, 80.0, 0.5),
            vec![("front".to_string(), 4.9), ("rear".to_string(), 3.9)]
        );
        assert!(amplitudes_near(&dwells, 60.0, 0.5).is_empty());
    }

    #[test]
    fn variant_names_become_directory_names() {
        assert_eq!(slug("gyroscopic (DYTSI)"), "gyroscopic__dytsi_");
    }
}
