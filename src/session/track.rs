//! The scene's track tables: an ideal straight in memory, a table file,
//! a range built in memory, or the whole track built from its CSV inputs
//! into the cache ([`crate::session::cache`]).

use std::time::Instant;

use anyhow::{Context, Result};
use preproc::{BuildConfig, BuildRequest, Inclination, NoProgress, build_tables};
use runtime::geometry::track::TrackTables;
use serde::Serialize;

use crate::config::scene::LoadedScene;
use crate::session::cache::{Fnv64, cache_dir};

/// Where the track tables came from.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TrackSource {
    pub path: String,
    /// Built by this run (false: read from the cache or the scene's file).
    pub built: bool,
    pub build_time_s: f64,
}

/// The scene's track tables: its table file, or built from its CSV inputs
/// into the cache (module docs).
pub fn load_track(ls: &LoadedScene) -> Result<(TrackTables, TrackSource)> {
    let t = &ls.scene.track;
    if let Some(length_m) = t.straight_m {
        let inclination = t
            .rail_inclination
            .parse::<Inclination>()
            .map_err(anyhow::Error::msg)
            .context("[track] rail_inclination")?;
        let spacing = BuildConfig {
            gauge_m: t.gauge_m,
            ..BuildConfig::default()
        }
        .rail_spacing_m();
        let tables = runtime::geometry::track::straight_track(
            length_m,
            t.step_m,
            t.gauge_m,
            spacing,
            inclination.angle_rad,
        );
        return Ok((
            tables,
            TrackSource {
                path: format!("ideal straight, {length_m} m (in memory)"),
                built: true,
                build_time_s: 0.0,
            },
        ));
    }
    if let Some(p) = &t.tables {
        let path = ls.path(p);
        let tables = runtime::io::schema::read_track(&path)?;
        return Ok((
            tables,
            TrackSource {
                path: path.display().to_string(),
                built: false,
                build_time_s: 0.0,
            },
        ));
    }
    if let Some(range) = t.range_m {
        let start = Instant::now();
        let tables = crate::session::plan::build_track_range(ls, range)?;
        let (a, b) = tables.centerline.range_m();
        return Ok((
            tables,
            TrackSource {
                path: format!(
                    "{} s {a:.1} … {b:.1} m at {} m (in memory)",
                    ls.path(t.centerline.as_ref().context("no centerline")?)
                        .display(),
                    t.step_m
                ),
                built: true,
                build_time_s: start.elapsed().as_secs_f64(),
            },
        ));
    }
    let centerline = ls.path(t.centerline.as_ref().context("no centerline")?);
    let cant = t.cant.as_ref().map(|p| ls.path(p));
    let irregularities = t.irregularities.as_ref().map(|p| ls.path(p));
    let config = crate::session::plan::build_config(ls)?;
    let mut key = Fnv64::default();
    key.write_str(env!("CARGO_PKG_VERSION"))
        .write_str(&format!("{config:?}"));
    for p in [Some(&centerline), cant.as_ref(), irregularities.as_ref()]
        .into_iter()
        .flatten()
    {
        let text =
            std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
        key.write_str(&text);
    }
    let path = cache_dir()?.join(format!("track-{:016x}.h5", key.finish()));
    if path.exists()
        && let Ok(tables) = runtime::io::schema::read_track(&path)
    {
        return Ok((
            tables,
            TrackSource {
                path: path.display().to_string(),
                built: false,
                build_time_s: 0.0,
            },
        ));
    }
    let start = Instant::now();
    let req = BuildRequest {
        centerline,
        cant,
        irregularities,
        output: path.clone(),
        config,
        contact: None,
        command_line: format!("sim run {} (tables built on demand)", ls.origin),
    };
    // Built in memory and used as built; the cache file (written
    // all-or-nothing) serves the next run.
    let (tables, provenance) =
        build_tables(&req, &NoProgress).context("building the track tables")?;
    runtime::io::schema::write_track_file(&path, &tables, &provenance)
        .with_context(|| format!("caching the track tables in {}", path.display()))?;
    Ok((
        tables,
        TrackSource {
            path: path.display().to_string(),
            built: true,
            build_time_s: start.elapsed().as_secs_f64(),
        },
    ))
}
