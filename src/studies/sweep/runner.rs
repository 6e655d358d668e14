//! Runs a shard of a study on the local cores: the variants not already
//! done (an `ok` row in any of the folder's shard tables) are computed in
//! parallel (rayon, `jobs` threads); each finished variant's row is
//! appended to the shard's CSV and flushed, and the shard's HDF5 table is
//! rewritten (all or nothing) at most once a second and at the end. A
//! failed variant records its error and the study goes on; a failed row is
//! computed again by the next run. Ctrl-C (`stop`) lets the running
//! variants end as interrupted (no row: computed again next time).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use anyhow::{Context, Result};
use rayon::prelude::*;

use super::compute::{Outcome, References, compute};
use super::table::{self, Row, Status};
use super::{Dir, Shard, Study};

/// How far a shard is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Variants computed in this run, and to compute.
    pub done: usize,
    pub total: usize,
    /// Of the computed, failed.
    pub failed: usize,
}

/// What a shard run did.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ShardReport {
    pub shard: String,
    /// The shard's variants.
    pub variants: usize,
    /// Skipped: already done in an earlier run.
    pub already_done: usize,
    /// Computed now, and of those failed.
    pub computed: usize,
    pub failed: usize,
    /// Rows of failed variants dropped to be computed again, and a last
    /// line cut short by a kill, dropped.
    pub retried: usize,
    pub torn_lines: usize,
    pub interrupted: bool,
    pub wall_s: f64,
}

/// Ok rows of every shard table of the folder except `own`.
fn done_elsewhere(dir: &Dir, own: Shard, layout: &table::Layout) -> Result<Vec<usize>> {
    let mut done = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir.shards()) else {
        return Ok(done);
    };
    let own_csv = dir.shard_csv(own);
    for e in entries {
        let p = e?.path();
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or_default();
        if p == own_csv
            || !name.starts_with("shard_")
            || !name.ends_with(".csv")
            || name.ends_with(".log.csv")
        {
            continue;
        }
        let (rows, _) = table::read_csv(&p, layout)?;
        done.extend(
            rows.iter()
                .filter(|r| r.status == Status::Ok)
                .map(|r| r.variant),
        );
    }
    Ok(done)
}

struct Shared {
    rows: Vec<Row>,
    done: usize,
    failed: usize,
    last_h5: Instant,
    error: Option<anyhow::Error>,
}

/// Runs shard `shard` of `study` into `dir` with `jobs` threads.
pub fn run_shard(
    study: &Study,
    dir: &Dir,
    shard: Shard,
    jobs: usize,
    stop: Arc<AtomicBool>,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<ShardReport> {
    let started = Instant::now();
    dir.prepare(study)?;
    if study.file.sweep.keep == crate::config::sweep::Keep::Full {
        std::fs::create_dir_all(dir.runs())
            .with_context(|| format!("creating {}", dir.runs().display()))?;
    }
    let layout = study.layout();
    let csv = dir.shard_csv(shard);
    let (own, torn) = table::read_csv(&csv, &layout)?;
    let kept: Vec<Row> = own
        .iter()
        .filter(|r| r.status == Status::Ok)
        .cloned()
        .collect();
    let retried = own.len() - kept.len();
    if retried > 0 || torn > 0 {
        table::write_csv(&csv, &layout, &kept)?;
    }
    let mut done: Vec<usize> = kept.iter().map(|r| r.variant).collect();
    done.extend(done_elsewhere(dir, shard, &layout)?);
    done.sort_unstable();
    let mine = study.shard_variants(shard);
    let todo: Vec<_> = mine
        .iter()
        .filter(|v| done.binary_search(&v.index).is_err())
        .collect();
    let total = todo.len();
    let shared = Mutex::new(Shared {
        rows: kept,
        done: 0,
        failed: 0,
        last_h5: Instant::now(),
        error: None,
    });
    let title = &study.file.sweep.title;
    let write_h5 = |rows: &[Row]| -> Result<()> {
        let mut sorted = rows.to_vec();
        sorted.sort_by_key(|r| r.variant);
        table::write_h5(
            &dir.shard_h5(shard),
            title,
            &study.fingerprint,
            &layout,
            &sorted,
        )
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs.max(1))
        .build()
        .context("starting the worker threads")?;
    let references = References::default();
    progress(Progress {
        done: 0,
        total,
        failed: 0,
    });
    pool.install(|| {
        todo.par_iter().for_each(|v| {
            if stop.load(Ordering::Relaxed) {
                return;
            }
            let t0 = Instant::now();
            let Outcome::Row(row) = compute(study, v, &dir.root, &stop, &references) else {
                return;
            };
            let wall_s = t0.elapsed().as_secs_f64();
            let Ok(mut s) = shared.lock() else { return };
            let logged = table::append_row(&csv, &layout, &row)
                .and_then(|_| append_log(dir, shard, row.variant, row.status, wall_s));
            if let Err(e) = logged {
                s.error.get_or_insert(e);
                stop.store(true, Ordering::Relaxed);
                return;
            }
            s.done += 1;
            if row.status == Status::Failed {
                s.failed += 1;
            }
            s.rows.push(row);
            if s.last_h5.elapsed().as_secs_f64() > 1.0 {
                if let Err(e) = write_h5(&s.rows) {
                    s.error.get_or_insert(e);
                    stop.store(true, Ordering::Relaxed);
                }
                s.last_h5 = Instant::now();
            }
            progress(Progress {
                done: s.done,
                total,
                failed: s.failed,
            });
        })
    });
    let s = shared
        .into_inner()
        .map_err(|_| anyhow::anyhow!("a worker thread panicked"))?;
    if let Some(e) = s.error {
        return Err(e);
    }
    write_h5(&s.rows)?;
    Ok(ShardReport {
        shard: shard.to_string(),
        variants: mine.len(),
        already_done: mine.len() - total,
        computed: s.done,
        failed: s.failed,
        retried,
        torn_lines: torn,
        interrupted: stop.load(Ordering::Relaxed),
        wall_s: started.elapsed().as_secs_f64(),
    })
}

/// One line per computation in the shard's log (variant, status, wall time).
fn append_log(dir: &Dir, shard: Shard, variant: usize, status: Status, wall_s: f64) -> Result<()> {
    use std::io::Write;
    let p = dir.shard_log(shard);
    let new = !p.exists();
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&p)
        .with_context(|| format!("opening {}", p.display()))?;
    let mut text = String::new();
    if new {
        text.push_str("variant,status,wall_s\n");
    }
    text.push_str(&format!("{variant},{},{wall_s:.3}\n", status.as_str()));
    f.write_all(text.as_bytes())
        .with_context(|| format!("appending to {}", p.display()))
}
