//! `sim sweep`: parameter studies over any scene key, run on the local
//! cores, sharded deterministically, resumable, merged into one table
//! (docs/guide/sweeps.md). A study is a study file ([`crate::config::sweep`])
//! expanded into numbered variants ([`variants`]); each shard computes its
//! variants ([`runner`], [`compute`]) and appends one row per variant to its
//! table ([`table`]); [`merge`] joins the shards; [`slurm`] writes the
//! job-array scripts of a cluster.
//!
//! The output folder `DIR`:
//!
//! - `study.json`: the study's title, fingerprint and variant count;
//! - `shards/shard_I_of_N.csv`: the rows of shard I of N, appended as each
//!   variant finishes (the resumable log), and `shard_I_of_N.h5` (the same
//!   table in HDF5, rewritten all or nothing); `shard_I_of_N.log.csv`: one
//!   line per computation (variant, status, wall time);
//! - `runs/`: the kept results (`keep = "full"`);
//! - `table.csv`, `table.h5`, `plots/`: the merged study.

pub mod compute;
pub mod merge;
pub mod runner;
pub mod slurm;
pub mod table;
pub mod variants;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::config::Variation;
use crate::config::scene::LoadedScene;
use crate::config::sweep::LoadedSweep;
pub use variants::Variant;

/// A study ready to run: the file, its base scene (with `[set]`) and every
/// variant, each checked before any work.
#[derive(Debug, Clone)]
pub struct Study {
    pub file: LoadedSweep,
    /// The base scene with the study's `[set]` applied.
    pub base: LoadedScene,
    pub variants: Vec<Variant>,
    /// SHA-256 of the study file, the base scene and its vehicle file: a
    /// folder holds the rows of one study only.
    pub fingerprint: String,
}

impl Study {
    /// Loads a study file, expands its variants and checks every
    /// variant's scene (a key that is not a scene key, a value out of its
    /// rule) before any run.
    pub fn load(path: &Path) -> Result<Study> {
        let file = LoadedSweep::load(path)?;
        let scene_path = file.scene_path();
        let scene = LoadedScene::load(&scene_path, &[])?;
        let set: Vec<Variation> = file
            .sweep
            .set
            .iter()
            .map(|(k, v)| Variation::Set(k.clone(), v.clone()))
            .collect();
        let base = if set.is_empty() {
            scene
        } else {
            scene.varied(&set).context("the study's [set]")?
        };
        let variants = variants::expand(&file.sweep)?;
        let study = Study {
            fingerprint: fingerprint(&file, &base)?,
            file,
            base,
            variants,
        };
        for v in &study.variants {
            study
                .scene_of(v)
                .with_context(|| format!("variant {} ({})", v.index, v.describe()))?;
        }
        Ok(study)
    }

    /// The scene of variant `v`.
    pub fn scene_of(&self, v: &Variant) -> Result<LoadedScene> {
        let set: Vec<Variation> = v
            .params
            .iter()
            .map(|(k, value)| Variation::Set(k.clone(), value.clone()))
            .collect();
        if set.is_empty() {
            return Ok(self.base.clone());
        }
        self.base.varied(&set)
    }

    /// The table's columns.
    pub fn layout(&self) -> table::Layout {
        table::Layout {
            keys: self.file.sweep.varied_keys(),
            figures: self.file.sweep.compute.figures(),
        }
    }

    /// The variants of shard `shard` (every variant for 0/1).
    pub fn shard_variants(&self, shard: Shard) -> Vec<&Variant> {
        self.variants
            .iter()
            .filter(|v| v.index % shard.count == shard.index)
            .collect()
    }
}

fn fingerprint(file: &LoadedSweep, base: &LoadedScene) -> Result<String> {
    let mut h = Sha256::new();
    h.update(file.text.as_bytes());
    h.update([0]);
    h.update(base.text.as_bytes());
    h.update([0]);
    let vehicle = base.path(&base.scene.vehicle.file);
    let text = std::fs::read(&vehicle)
        .with_context(|| format!("reading the vehicle file {}", vehicle.display()))?;
    h.update(&text);
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

/// Shard `index` of `count` (`--shard I/N`): the variants whose number
/// modulo N is I — the same set for the same study on any machine, and
/// balanced (the shards' sizes differ by one at most; neighbouring grid
/// points, which cost alike, go to different shards).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    /// The whole study.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// File stem of the shard's table: `shard_I_of_N`.
    pub fn stem(self) -> String {
        format!("shard_{}_of_{}", self.index, self.count)
    }
}

impl std::str::FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (i, n) = s
            .split_once('/')
            .ok_or_else(|| format!("'{s}': a shard is I/N, e.g. 0/4 (the first of four)"))?;
        let index: usize = i
            .trim()
            .parse()
            .map_err(|_| format!("'{s}': I is not a whole number"))?;
        let count: usize = n
            .trim()
            .parse()
            .map_err(|_| format!("'{s}': N is not a whole number"))?;
        if count == 0 || index >= count {
            return Err(format!("'{s}': need N >= 1 and 0 <= I < N"));
        }
        Ok(Shard { index, count })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// `DIR/study.json`: which study a folder holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub title: String,
    pub study_file: String,
    pub fingerprint: String,
    pub variants: usize,
    pub keys: Vec<String>,
    pub figures: Vec<String>,
}

/// The folders and files of a study's output folder.
#[derive(Debug, Clone)]
pub struct Dir {
    pub root: PathBuf,
}

impl Dir {
    pub fn manifest(&self) -> PathBuf {
        self.root.join("study.json")
    }
    pub fn shards(&self) -> PathBuf {
        self.root.join("shards")
    }
    pub fn shard_csv(&self, s: Shard) -> PathBuf {
        self.shards().join(format!("{}.csv", s.stem()))
    }
    pub fn shard_h5(&self, s: Shard) -> PathBuf {
        self.shards().join(format!("{}.h5", s.stem()))
    }
    pub fn shard_log(&self, s: Shard) -> PathBuf {
        self.shards().join(format!("{}.log.csv", s.stem()))
    }
    pub fn runs(&self) -> PathBuf {
        self.root.join("runs")
    }
    pub fn table_csv(&self) -> PathBuf {
        self.root.join("table.csv")
    }
    pub fn table_h5(&self) -> PathBuf {
        self.root.join("table.h5")
    }
    pub fn plots(&self) -> PathBuf {
        self.root.join("plots")
    }
    pub fn slurm(&self) -> PathBuf {
        self.root.join("slurm")
    }

    /// Reads the manifest, if the folder has one.
    pub fn read_manifest(&self) -> Result<Option<Manifest>> {
        let p = self.manifest();
        match std::fs::read_to_string(&p) {
            Ok(text) => Ok(Some(
                serde_json::from_str(&text).with_context(|| format!("reading {}", p.display()))?,
            )),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(e) => Err(e).with_context(|| format!("reading {}", p.display())),
        }
    }

    /// Makes the folder for `study` (its manifest written all or
    /// nothing), or checks that it already holds this study.
    pub fn prepare(&self, study: &Study) -> Result<()> {
        let manifest = Manifest {
            title: study.file.sweep.title.clone(),
            study_file: study.file.path.display().to_string(),
            fingerprint: study.fingerprint.clone(),
            variants: study.variants.len(),
            keys: study.layout().keys,
            figures: study.layout().figures,
        };
        std::fs::create_dir_all(self.shards())
            .with_context(|| format!("creating {}", self.shards().display()))?;
        match self.read_manifest()? {
            Some(m) if m.fingerprint == manifest.fingerprint => Ok(()),
            Some(m) => bail!(
                "{} holds the rows of another study ('{}' from {}; its study file, scene or vehicle differ): give another --out, or remove the folder to start again",
                self.root.display(),
                m.title,
                m.study_file
            ),
            None => {
                let text = serde_json::to_string_pretty(&manifest)? + "\n";
                runtime::io::atomic::write_atomically(&self.manifest(), |tmp| {
                    std::fs::write(tmp, &text)
                })
                .with_context(|| format!("writing {}", self.manifest().display()))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shards_parse_and_are_named() {
        let s: Shard = "2/4".parse().unwrap();
        assert_eq!(s, Shard { index: 2, count: 4 });
        assert_eq!(s.stem(), "shard_2_of_4");
        for bad in ["4/4", "1", "a/2", "0/0"] {
            assert!(bad.parse::<Shard>().is_err(), "{bad}");
        }
    }
}
