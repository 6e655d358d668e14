//! The scene's track tables: an ideal straight in memory, a table file,
//! a range built in memory, or the whole track built from its CSV inputs
//! into the cache ([`crate::session::cache`]) — and the scene's rail
//! profile checked against them ([`check_rail`]).

use std::time::Instant;

use anyhow::{Context, Result, bail};
use preproc::{BuildConfig, BuildRequest, NoProgress, build_tables};
use runtime::geometry::profile::rail_cant::{RailCantCheck, Spelling, check_rail_file, slope_text};
use runtime::geometry::track::TrackTables;
use serde::Serialize;

use crate::config::scene::LoadedScene;
use crate::session::cache::cache_dir;

/// Where the track tables came from.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TrackSource {
    pub path: String,
    /// Built by this run (false: read from the cache or the scene's file).
    pub built: bool,
    pub build_time_s: f64,
}

/// Two rail inclinations (rad) this close are the same (round-off of the
/// angle through its text and back).
const SAME_INCLINATION_RAD: f64 = 1e-12;

/// The scene's rail profile checked against the rail inclination its track
/// gives it (docs/reference/10-scene-files.md, `[track]`):
///
/// - with `tables`, a stated `rail_inclination` other than the table
///   file's, or a `rail_profile` other than the one the file records
///   (compared by SHA-256), is refused naming both; the file's inclination
///   applies;
/// - the profile's carried cant (declared by `rail_profile_cant`, else
///   detected) with a non-zero inclination is refused as double canting
///   (`runtime::geometry::profile::rail_cant::check_rail_cant`).
///
/// Returns the check, whose warnings the caller shows.
pub fn check_rail(ls: &LoadedScene) -> Result<RailCantCheck> {
    let t = &ls.scene.track;
    let rail = ls.path(&t.rail_profile);
    let declared = t.declared_rail_cant()?.map(|c| c.angle_rad);
    let Some(tables) = &t.tables else {
        return Ok(check_rail_file(
            &rail,
            declared,
            t.inclination()?.angle_rad,
            Spelling::Scene,
        )?);
    };
    let path = ls.path(tables);
    let meta = runtime::io::schema::read_track_meta(&path)
        .with_context(|| format!("[track] tables = {}", path.display()))?;
    if let Some(stated) = t.stated_inclination()?
        && (stated.angle_rad - meta.rail_inclination_rad).abs() > SAME_INCLINATION_RAD
    {
        bail!(
            "[track] rail_inclination = \"{stated}\" ({:.6} rad), but the table file {} was built with the rail inclination {} ({:.6} rad); remove the key to use the table file's, or rebuild the table file with --rail-inclination {stated}",
            stated.angle_rad,
            path.display(),
            meta.rail_inclination,
            meta.rail_inclination_rad
        );
    }
    let mut check = check_rail_file(
        &rail,
        declared,
        meta.rail_inclination_rad,
        Spelling::SceneTables,
    )
    .with_context(|| {
        format!(
            "the table file {} was built with the rail inclination {}",
            path.display(),
            meta.rail_inclination
        )
    })?;
    match &meta.rail_profile {
        Some(built) if built.sha256 != check.record.sha256 => bail!(
            "[track] rail_profile = {} (sha256 {}…) is not the rail profile the table file {} was built for: {} (sha256 {}…); give that profile, or rebuild the table file with --rail {}",
            rail.display(),
            check.record.short_sha256(),
            path.display(),
            built.file,
            built.short_sha256(),
            rail.display()
        ),
        Some(_) => {}
        None => check.warnings.push(format!(
            "warning: the table file {} does not record the rail profile it was built for (built without --rail, or before table files recorded it); the scene's {} is taken to be it, with the file's rail inclination {} ({})",
            path.display(),
            rail.display(),
            meta.rail_inclination,
            slope_text(meta.rail_inclination_rad)
        )),
    }
    Ok(check)
}

/// The scene's track tables: its table file, or built from its CSV inputs
/// into the cache (module docs). The rail profile is checked first
/// ([`check_rail`]; its warnings are the caller's to show).
pub fn load_track(ls: &LoadedScene) -> Result<(TrackTables, TrackSource)> {
    let t = &ls.scene.track;
    check_rail(ls).context("[track] rail profile")?;
    if let Some(length_m) = t.straight_m {
        let inclination = t.inclination()?;
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
                    crate::session::plan::geometry_files(ls)?.paths()[0].display(),
                    t.step_m
                ),
                built: true,
                build_time_s: start.elapsed().as_secs_f64(),
            },
        ));
    }
    let geometry = crate::session::plan::geometry_files(ls)?;
    let irregularities = t.irregularities.as_ref().map(|p| ls.path(p));
    let config = crate::session::plan::build_config(ls)?;
    let mut key = crate::session::plan::track_inputs_key(ls, &config)?;
    // "design elements": the tables record a design file's elements
    // (`/design`) since this layout; older cached tables lack them.
    key.write_str("track tables with design elements");
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
        geometry,
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
