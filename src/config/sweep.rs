//! Study files (`SWEEP.toml`, docs/guide/sweeps.md): a base scene, the scene
//! keys to vary (lists, ranges, grids, seeded random draws), what to compute
//! per variant and what to keep — typed and checked by one
//! [`SweepFile::validate`] that names the violated rule.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use serde::{Deserialize, Serialize};

use super::choices::{CreepLawName, CriticalSpeedMethod};

/// Largest number of variants of one study (a typo in a range step would
/// otherwise ask for millions of runs).
pub const MAX_VARIANTS: usize = 1_000_000;

/// A study file as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SweepFile {
    /// What the study is (plots' and tables' title).
    pub title: String,
    /// The base scene, relative to the study file.
    pub scene: PathBuf,
    /// Overrides of every variant (`key = value`, dotted scene keys).
    #[serde(default)]
    pub set: BTreeMap<String, toml::Value>,
    /// Grid axes: the variants are their cartesian product (the last
    /// axis varies fastest).
    #[serde(default)]
    pub vary: Vec<Axis>,
    /// Seeded random draws (Monte Carlo): each grid point is run for each
    /// draw.
    #[serde(default)]
    pub random: Option<RandomDraws>,
    /// What each variant computes.
    pub compute: Compute,
    /// What is kept of each variant.
    #[serde(default)]
    pub keep: Keep,
    /// The study's plots: a figure against one varied key, one line per
    /// value of another.
    #[serde(default)]
    pub plot: Option<PlotSpec>,
}

/// One grid axis: a scene key and its values (exactly one of `values`,
/// `range`, `linspace`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axis {
    /// Dotted scene key, e.g. `contact.friction`.
    pub key: String,
    /// The values as written (numbers, strings, booleans).
    #[serde(default)]
    pub values: Option<Vec<toml::Value>>,
    /// `{ from, to, step }`: from, from + step, … up to `to` inclusive.
    #[serde(default)]
    pub range: Option<Range>,
    /// `{ from, to, count }`: `count` values evenly spaced, ends included.
    #[serde(default)]
    pub linspace: Option<Linspace>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    pub from: f64,
    pub to: f64,
    pub step: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Linspace {
    pub from: f64,
    pub to: f64,
    pub count: usize,
}

/// Random draws: `draws` variants per grid point, the draw `d` of every
/// grid point equal (common random numbers), reproducible from `seed`
/// on any machine (ChaCha8).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RandomDraws {
    pub draws: usize,
    pub seed: u64,
    pub params: Vec<RandomParam>,
}

/// A randomly drawn scene key. (Unknown fields are refused by
/// [`Distribution`]: serde cannot deny them on a struct that flattens.)
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RandomParam {
    pub key: String,
    #[serde(flatten)]
    pub distribution: Distribution,
}

/// The distribution of a drawn key.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "distribution", rename_all = "snake_case", deny_unknown_fields)]
pub enum Distribution {
    /// Uniform on [low, high).
    Uniform { low: f64, high: f64 },
    /// Normal (Gaussian) with mean and standard deviation.
    Normal { mean: f64, std: f64 },
    /// A whole number in [low, high], e.g. an irregularity seed.
    Integer { low: i64, high: i64 },
}

/// What a variant computes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Compute {
    /// One run of the variant's scene; the figures are paths into its
    /// summary (`sim run --json`), e.g. `wheelsets.0.peak_lateral_mm`.
    Run { figures: Vec<String> },
    /// The variant's critical speed (its scene's creep law) by one
    /// method, as `sim critical-speed` finds it; the figures are
    /// `critical_speed_m_s`, `frequency_hz`, `bracket_low_m_s`,
    /// `bracket_high_m_s`.
    CriticalSpeed {
        method: CriticalSpeedMethod,
        #[serde(default = "default_min")]
        min_m_s: f64,
        #[serde(default = "default_max")]
        max_m_s: f64,
        #[serde(default = "default_tol")]
        tol_m_s: f64,
    },
    /// A point of the speed/accuracy trade (`sim tradeoff`): the variant's
    /// run against a fine reference run — the variant's scene with the
    /// `reference` overrides (e.g. RK4 at 0.1 ms), computed once per
    /// distinct reference scene. Figures: `lateral_error_max_um`,
    /// `lateral_error_rms_um` (leading wheelset, at equal time),
    /// `frequency_error_hz`, `wall_time_s`, `real_time_factor`, `steps`,
    /// `rhs_evaluations` (the timings differ from run to run).
    Tradeoff {
        reference: BTreeMap<String, toml::Value>,
        /// Start transient left out of the frequency (s).
        #[serde(default = "default_skip")]
        skip_s: f64,
    },
}

fn default_skip() -> f64 {
    1.0
}

/// The figures of a tradeoff variant, in table order.
pub const TRADEOFF_FIGURES: [&str; 7] = [
    "lateral_error_max_um",
    "lateral_error_rms_um",
    "frequency_error_hz",
    "wall_time_s",
    "real_time_factor",
    "steps",
    "rhs_evaluations",
];

fn default_min() -> f64 {
    10.0
}
fn default_max() -> f64 {
    120.0
}
fn default_tol() -> f64 {
    0.5
}

/// The figures of a critical-speed variant, in table order.
pub const CRITICAL_SPEED_FIGURES: [&str; 4] = [
    "critical_speed_m_s",
    "frequency_hz",
    "bracket_low_m_s",
    "bracket_high_m_s",
];

impl Compute {
    /// The figure columns of the table, in order.
    pub fn figures(&self) -> Vec<String> {
        match self {
            Compute::Run { figures } => figures.clone(),
            Compute::CriticalSpeed { .. } => CRITICAL_SPEED_FIGURES
                .iter()
                .map(|s| s.to_string())
                .collect(),
            Compute::Tradeoff { .. } => TRADEOFF_FIGURES.iter().map(|s| s.to_string()).collect(),
        }
    }
}

/// What is kept of each variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Keep {
    /// The table row only.
    #[default]
    Summary,
    /// The row and the variant's results file (`runs/variant_K.h5`; for
    /// a critical speed, its runs' folder).
    Full,
}

/// A figure against one varied key, one line per value of another.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlotSpec {
    /// The varied key, or a figure, on the horizontal axis (numeric
    /// values), e.g. the speed, or the cant deficiency a run reports.
    pub x: String,
    /// The varied key whose values make the lines (none: one line).
    #[serde(default)]
    pub lines: Option<String>,
    /// Axis label of `x` (default: the key).
    #[serde(default)]
    pub x_label: Option<String>,
    /// The figures plotted, one chart each (default: every figure).
    #[serde(default)]
    pub figures: Vec<String>,
    /// Axis labels of figures, by figure (default: the figure's path).
    #[serde(default)]
    pub labels: BTreeMap<String, String>,
}

/// A study file with where it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedSweep {
    pub sweep: SweepFile,
    /// The study file.
    pub path: PathBuf,
    /// Its text, for the study's fingerprint.
    pub text: String,
}

impl LoadedSweep {
    /// Read and check a study file.
    pub fn load(path: &Path) -> Result<LoadedSweep> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("reading the study {}", path.display()))?;
        let sweep: SweepFile =
            toml::from_str(&text).with_context(|| format!("in the study {}", path.display()))?;
        sweep
            .validate()
            .with_context(|| format!("in the study {}", path.display()))?;
        Ok(LoadedSweep {
            sweep,
            path: path.to_path_buf(),
            text,
        })
    }

    /// The base scene's path (relative paths are from the study file).
    pub fn scene_path(&self) -> PathBuf {
        let dir = self.path.parent().unwrap_or(Path::new(""));
        dir.join(&self.sweep.scene)
    }
}

impl Axis {
    /// The axis's values (checked by [`SweepFile::validate`]).
    pub fn values(&self) -> Result<Vec<toml::Value>> {
        let key = &self.key;
        match (&self.values, &self.range, &self.linspace) {
            (Some(v), None, None) => {
                ensure!(!v.is_empty(), "[[vary]] {key}: `values` is empty");
                Ok(v.clone())
            }
            (None, Some(r), None) => {
                ensure!(
                    r.from.is_finite()
                        && r.to.is_finite()
                        && r.step.is_finite()
                        && r.step > 0.0
                        && r.to >= r.from,
                    "[[vary]] {key}: a range needs finite from <= to and step > 0, got {r:?}"
                );
                let n = ((r.to - r.from) / r.step + 1e-9).floor() as usize + 1;
                ensure!(
                    n <= MAX_VARIANTS,
                    "[[vary]] {key}: the range has {n} values (more than {MAX_VARIANTS}: check the step)"
                );
                // from + k·step, rounded to 12 significant digits so that
                // 0.1 + 2·0.1 reads 0.3 in the table.
                Ok((0..n)
                    .map(|k| toml::Value::Float(round12(r.from + k as f64 * r.step)))
                    .collect())
            }
            (None, None, Some(l)) => {
                ensure!(
                    l.from.is_finite() && l.to.is_finite() && l.count >= 1,
                    "[[vary]] {key}: a linspace needs finite ends and count >= 1, got {l:?}"
                );
                ensure!(
                    l.count <= MAX_VARIANTS,
                    "[[vary]] {key}: count {} is more than {MAX_VARIANTS}",
                    l.count
                );
                if l.count == 1 {
                    return Ok(vec![toml::Value::Float(l.from)]);
                }
                Ok((0..l.count)
                    .map(|k| {
                        let f = k as f64 / (l.count - 1) as f64;
                        toml::Value::Float(round12(l.from + f * (l.to - l.from)))
                    })
                    .collect())
            }
            _ => bail!("[[vary]] {key}: give exactly one of `values`, `range`, `linspace`"),
        }
    }
}

/// `x` rounded to 12 significant digits.
fn round12(x: f64) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    format!("{x:.11e}").parse().unwrap_or(x)
}

impl SweepFile {
    /// Checks every rule, naming it.
    pub fn validate(&self) -> Result<()> {
        ensure!(!self.title.trim().is_empty(), "`title` is empty");
        let mut keys: Vec<&str> = Vec::new();
        let mut count: usize = 1;
        for a in &self.vary {
            ensure!(!a.key.trim().is_empty(), "[[vary]]: empty key");
            ensure!(
                !keys.contains(&a.key.as_str()),
                "[[vary]] {}: the key is varied twice",
                a.key
            );
            keys.push(&a.key);
            count = count.saturating_mul(a.values()?.len());
        }
        if let Some(r) = &self.random {
            ensure!(r.draws >= 1, "[random] draws must be >= 1");
            ensure!(
                !r.params.is_empty(),
                "[random] needs at least one [[random.params]]"
            );
            for p in &r.params {
                ensure!(
                    !keys.contains(&p.key.as_str()),
                    "[[random.params]] {}: the key is also varied",
                    p.key
                );
                keys.push(&p.key);
                match p.distribution {
                    Distribution::Uniform { low, high } => ensure!(
                        low.is_finite() && high.is_finite() && low < high,
                        "[[random.params]] {}: uniform needs finite low < high",
                        p.key
                    ),
                    Distribution::Normal { mean, std } => ensure!(
                        mean.is_finite() && std.is_finite() && std > 0.0,
                        "[[random.params]] {}: normal needs a finite mean and std > 0",
                        p.key
                    ),
                    Distribution::Integer { low, high } => ensure!(
                        low <= high,
                        "[[random.params]] {}: integer needs low <= high",
                        p.key
                    ),
                }
            }
            count = count.saturating_mul(r.draws);
        }
        ensure!(
            count <= MAX_VARIANTS,
            "the study has {count} variants (more than {MAX_VARIANTS}: check the ranges)"
        );
        for k in self.set.keys() {
            ensure!(
                !keys.contains(&k.as_str()),
                "[set] {k}: the key is also varied"
            );
        }
        match &self.compute {
            Compute::Run { figures } => {
                ensure!(
                    !figures.is_empty(),
                    "[compute] run: list at least one figure (a path into the run summary, e.g. wheelsets.0.peak_lateral_mm)"
                );
                for (i, f) in figures.iter().enumerate() {
                    ensure!(!f.trim().is_empty(), "[compute] figure {i} is empty");
                    ensure!(
                        !figures[..i].contains(f),
                        "[compute] figure '{f}' is listed twice"
                    );
                }
            }
            Compute::CriticalSpeed {
                min_m_s,
                max_m_s,
                tol_m_s,
                ..
            } => {
                ensure!(
                    *min_m_s > 0.0 && max_m_s > min_m_s && max_m_s.is_finite(),
                    "[compute] critical_speed: need 0 < min_m_s < max_m_s"
                );
                ensure!(
                    *tol_m_s > 0.0 && *tol_m_s < max_m_s - min_m_s,
                    "[compute] critical_speed: need 0 < tol_m_s < max_m_s - min_m_s"
                );
            }
            Compute::Tradeoff { reference, skip_s } => {
                ensure!(
                    !reference.is_empty(),
                    "[compute] tradeoff: give the reference's overrides, e.g. reference = {{ \"run.integrator\" = \"rk4\", \"run.step_s\" = 1e-4 }}"
                );
                ensure!(
                    skip_s.is_finite() && *skip_s >= 0.0,
                    "[compute] tradeoff: skip_s must be >= 0"
                );
            }
        }
        if let Some(p) = &self.plot {
            let figures = self.compute.figures();
            ensure!(
                keys.contains(&p.x.as_str()) || figures.contains(&p.x),
                "[plot] x = '{}' is neither a varied key ({}) nor a figure",
                p.x,
                keys.join(", ")
            );
            if let Some(l) = &p.lines {
                ensure!(
                    keys.contains(&l.as_str()),
                    "[plot] lines = '{l}' is not a varied key ({})",
                    keys.join(", ")
                );
                ensure!(l != &p.x, "[plot] lines and x are the same key");
            }
            for f in p.labels.keys() {
                ensure!(
                    figures.contains(f),
                    "[plot.labels] '{f}' is not one of the study's figures ({})",
                    figures.join(", ")
                );
            }
            for f in &p.figures {
                ensure!(
                    figures.contains(f),
                    "[plot] figure '{f}' is not one of the study's figures ({})",
                    figures.join(", ")
                );
            }
        }
        Ok(())
    }

    /// Every varied key (grid axes, then random draws), in table order.
    pub fn varied_keys(&self) -> Vec<String> {
        let mut k: Vec<String> = self.vary.iter().map(|a| a.key.clone()).collect();
        if let Some(r) = &self.random {
            k.extend(r.params.iter().map(|p| p.key.clone()));
        }
        k
    }
}

/// The creep law a critical-speed variant searches with: its scene's.
pub fn variant_creep_law(scene: &crate::config::scene::LoadedScene) -> CreepLawName {
    scene.scene.contact.creep_law
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<SweepFile> {
        let s: SweepFile = toml::from_str(text)?;
        s.validate()?;
        Ok(s)
    }

    const BASE: &str = r#"
        title = "t"
        scene = "s.toml"
        [compute]
        kind = "critical_speed"
        method = "linear"
    "#;

    #[test]
    fn ranges_and_linspaces_give_clean_values() {
        let s = parse(&format!(
            "{BASE}\n[[vary]]\nkey = \"contact.friction\"\nrange = {{ from = 0.1, to = 0.4, step = 0.1 }}\n[[vary]]\nkey = \"initial.speed_m_s\"\nlinspace = {{ from = 10.0, to = 20.0, count = 3 }}"
        ))
        .unwrap();
        let f: Vec<f64> = s.vary[0]
            .values()
            .unwrap()
            .iter()
            .map(|v| v.as_float().unwrap())
            .collect();
        assert_eq!(f, vec![0.1, 0.2, 0.3, 0.4]);
        let v: Vec<f64> = s.vary[1]
            .values()
            .unwrap()
            .iter()
            .map(|v| v.as_float().unwrap())
            .collect();
        assert_eq!(v, vec![10.0, 15.0, 20.0]);
    }

    #[test]
    fn rules_are_named() {
        for (extra, rule) in [
            (
                "[[vary]]\nkey = \"a\"\nvalues = [1]\nrange = { from = 0.0, to = 1.0, step = 0.5 }",
                "exactly one",
            ),
            (
                "[[vary]]\nkey = \"a\"\nrange = { from = 0.0, to = 1.0, step = 0.0 }",
                "step > 0",
            ),
            (
                "[[vary]]\nkey = \"a\"\nvalues = [1]\n[[vary]]\nkey = \"a\"\nvalues = [2]",
                "varied twice",
            ),
            (
                "[[vary]]\nkey = \"a\"\nrange = { from = 0.0, to = 1.0, step = 1e-9 }",
                "check the step",
            ),
            ("[plot]\nx = \"b\"", "neither a varied key"),
            (
                "[random]\ndraws = 2\nseed = 1\n[[random.params]]\nkey = \"s\"\ndistribution = \"normal\"\nmean = 0.0\nstd = -1.0",
                "std > 0",
            ),
        ] {
            let e = parse(&format!("{BASE}\n{extra}")).unwrap_err();
            assert!(format!("{e:#}").contains(rule), "{extra}: {e:#}");
        }
        let e = parse("title = \"t\"\nscene = \"s\"\n[compute]\nkind = \"run\"\nfigures = []")
            .unwrap_err();
        assert!(format!("{e:#}").contains("at least one figure"), "{e:#}");
        let e = toml::from_str::<SweepFile>(
            "title = \"t\"\nscene = \"s\"\n[compute]\nkind = \"guess\"",
        )
        .unwrap_err();
        assert!(e.to_string().contains("guess"), "{e}");
        // A misspelt field of a random draw is refused, not ignored.
        let e = toml::from_str::<SweepFile>(&format!(
            "{BASE}\n[random]\ndraws = 2\nseed = 1\n[[random.params]]\nkey = \"s\"\ndistribution = \"uniform\"\nlow = 0.0\nhgh = 1.0"
        ))
        .unwrap_err();
        assert!(
            e.to_string().contains("hgh") || e.to_string().contains("high"),
            "{e}"
        );
    }
}
