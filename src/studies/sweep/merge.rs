//! Joins the shard tables of a study folder into `table.csv` and
//! `table.h5`: every variant present exactly once (an `ok` row; else its
//! failed row), sorted by variant — the same bytes as an unsharded run of
//! a deterministic study. Two `ok` rows of one variant, or a variant with
//! no row, are refused, naming them.

use std::collections::BTreeMap;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};

use super::table::{self, Layout, Row, Status};
use super::{Dir, Study};

/// What a merge wrote.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MergeReport {
    pub title: String,
    pub rows: usize,
    pub failed: usize,
    pub shard_tables: Vec<String>,
    pub table_csv: String,
    pub table_h5: String,
}

/// Merges the shards of `dir`; `study`, when the study file can be read,
/// names the parameters of missing variants.
pub fn merge(dir: &Dir, study: Option<&Study>) -> Result<(MergeReport, Vec<Row>)> {
    let manifest = dir.read_manifest()?.with_context(|| {
        format!(
            "{} is not a study folder (no study.json)",
            dir.root.display()
        )
    })?;
    let layout = Layout {
        keys: manifest.keys.clone(),
        figures: manifest.figures.clone(),
    };
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir.shards())
        .with_context(|| format!("reading {}", dir.shards().display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            let n = p.file_name().and_then(|n| n.to_str()).unwrap_or_default();
            n.starts_with("shard_") && n.ends_with(".csv") && !n.ends_with(".log.csv")
        })
        .collect();
    files.sort();
    let mut ok: BTreeMap<usize, (Row, PathBuf)> = BTreeMap::new();
    let mut failed: BTreeMap<usize, Row> = BTreeMap::new();
    for f in &files {
        let (rows, _) = table::read_csv(f, &layout)?;
        for r in rows {
            if r.variant >= manifest.variants {
                bail!(
                    "{}: variant {} is not one of the study's {} variants",
                    f.display(),
                    r.variant,
                    manifest.variants
                );
            }
            match r.status {
                Status::Ok => {
                    if let Some((_, first)) = ok.get(&r.variant) {
                        bail!(
                            "variant {} is done twice, in {} and {}: remove one of the shard tables",
                            r.variant,
                            first.display(),
                            f.display()
                        );
                    }
                    ok.insert(r.variant, (r, f.clone()));
                }
                Status::Failed => {
                    failed.insert(r.variant, r);
                }
            }
        }
    }
    let missing: Vec<usize> = (0..manifest.variants)
        .filter(|k| !ok.contains_key(k) && !failed.contains_key(k))
        .collect();
    if !missing.is_empty() {
        let named: Vec<String> = missing
            .iter()
            .take(20)
            .map(|&k| match study.and_then(|s| s.variants.get(k)) {
                Some(v) => format!("{k} ({})", v.describe()),
                None => k.to_string(),
            })
            .collect();
        bail!(
            "{} of the {} variants have no row in {}: {}{} — run the shards that hold them again (`sim sweep STUDY --shard I/N`)",
            missing.len(),
            manifest.variants,
            dir.shards().display(),
            named.join(", "),
            if missing.len() > 20 { ", …" } else { "" }
        );
    }
    let mut rows: Vec<Row> = Vec::with_capacity(manifest.variants);
    for k in 0..manifest.variants {
        match ok.remove(&k) {
            Some((r, _)) => rows.push(r),
            None => rows.push(failed.remove(&k).expect("checked: every variant has a row")),
        }
    }
    table::write_csv(&dir.table_csv(), &layout, &rows)?;
    table::write_h5(
        &dir.table_h5(),
        &manifest.title,
        &manifest.fingerprint,
        &layout,
        &rows,
    )?;
    let report = MergeReport {
        title: manifest.title,
        rows: rows.len(),
        failed: rows.iter().filter(|r| r.status == Status::Failed).count(),
        shard_tables: files.iter().map(|f| f.display().to_string()).collect(),
        table_csv: dir.table_csv().display().to_string(),
        table_h5: dir.table_h5().display().to_string(),
    };
    Ok((report, rows))
}
