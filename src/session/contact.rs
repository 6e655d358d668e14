//! The contact data a scene needs besides online contact: imported contact
//! tables (another code's, one contact per wheel) and our contact lookup
//! tables (built on demand for the wheel/rail pair and cached).

use std::path::Path;
use std::sync::Arc;

use anyhow::{Context, Result};
use preproc::NoProgress;
use preproc::contact_table::{ContactTableConfig, TableSupport, build_contact_table};
use runtime::contact::imported::ImportedContactTable;
use runtime::contact::table::ContactTable;
use runtime::forces::hertz::Material;
use runtime::geometry::track::{InputFile, Provenance, TrackTables};

use crate::config::vehicle::VehicleFile;
use crate::session::cache::{Fnv64, cache_dir};

/// An imported contact table: a `.h5`/`.hdf5` file written by
/// `track-preproc import-contact-table`, or any other file read as a DYTSI
/// RSGEO text table (`preproc::rsgeo`).
pub fn imported_table(path: &Path) -> Result<ImportedContactTable> {
    let hdf5 = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("h5") || e.eq_ignore_ascii_case("hdf5"));
    if hdf5 {
        runtime::io::schema::read_imported_contact_table(path)
            .with_context(|| format!("imported contact table {}", path.display()))
    } else {
        preproc::rsgeo::read_rsgeo(path)
            .with_context(|| format!("imported contact table {} (RSGEO)", path.display()))
    }
}

/// Contact lookup tables of every wheelset (built on demand for the
/// wheel/rail pair, the track's rail placement and the wheelset's static
/// load, and cached): lateral shifts ±15 mm every 0.1 mm, zero yaw. The
/// rail profile's carried cant is `declared_cant_rad` (the scene's
/// `rail_profile_cant`), else detected; each table records it with the
/// profile's SHA-256.
pub fn contact_tables(
    v: &VehicleFile,
    track: &TrackTables,
    rail: &Path,
    declared_cant_rad: Option<f64>,
    material: Material,
    keep_longest_stretch: bool,
) -> Result<Vec<Arc<ContactTable>>> {
    let mut out: Vec<Arc<ContactTable>> = Vec::new();
    let mut built: Vec<(u64, Arc<ContactTable>)> = Vec::new();
    for w in &v.wheelsets {
        let config = ContactTableConfig {
            wheel_profile: v.profile_path(w),
            rail_profile: rail.to_path_buf(),
            wheel_radius_m: w.nominal_radius_m,
            back_to_back_m: w.back_to_back_m,
            gauge_m: track.meta.gauge_m,
            rail_spacing_m: track.meta.rail_spacing_m,
            rail_inclination_rad: track.meta.rail_inclination_rad,
            rail_profile_cant_rad: declared_cant_rad,
            y_min_m: -0.015,
            y_max_m: 0.015,
            y_step_m: 1e-4,
            yaw_rad: vec![0.0],
            support: TableSupport::Elastic {
                wheel_load_n: v.static_wheel_load_n(w),
                material,
            },
            keep_longest_stretch,
            ..Default::default()
        };
        let mut key = Fnv64::default();
        key.write_str(env!("CARGO_PKG_VERSION"))
            .write_str(&format!("{config:?}"));
        for p in [&config.wheel_profile, &config.rail_profile] {
            key.write_str(
                &std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?,
            );
        }
        let key = key.finish();
        if let Some((_, t)) = built.iter().find(|(k, _)| *k == key) {
            out.push(t.clone());
            continue;
        }
        let path = cache_dir()?.join(format!("contact-{key:016x}.h5"));
        let cached = path
            .exists()
            .then(|| {
                runtime::io::schema::read_contact_table(&path)
                    .ok()
                    .flatten()
            })
            .flatten();
        let table = match cached {
            Some(t) => t,
            None => {
                // The profiles' warnings are those of the vehicle model
                // (the same files, the same option), which the session
                // reports.
                let (model, _) = config.model()?;
                let table = build_contact_table(&model, &config, &NoProgress)
                    .with_context(|| format!("contact table of wheelset '{}'", w.name))?;
                let inputs = [
                    ("wheel_profile", &config.wheel_profile),
                    ("rail_profile", &config.rail_profile),
                ]
                .iter()
                .map(|(role, p)| {
                    Ok(InputFile {
                        role: (*role).into(),
                        path: p.display().to_string(),
                        text: std::fs::read_to_string(p)?,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
                runtime::io::schema::write_contact_table_file(
                    &path,
                    &table,
                    &Provenance {
                        command_line: "sim run (contact table built on demand)".into(),
                        inputs,
                    },
                )?;
                table
            }
        };
        let t = Arc::new(table);
        built.push((key, t.clone()));
        out.push(t);
    }
    Ok(out)
}
