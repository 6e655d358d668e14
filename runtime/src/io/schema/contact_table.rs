//! Reading and writing `/contact_table` (docs/reference/04-table-files.md §4): the contact lookup table
//! of a wheel/rail profile pair.
//!
//! ```text
//! /contact_table            attributes: the ContactTableMeta fields
//! /contact_table/database   rows × (5 + 4·14) f64: y yaw height roll delta_r, then for
//!                           each of left_tread left_flange right_tread right_flange the
//!                           fields y_wheel z_wheel y_rail z_rail rolling_radius
//!                           contact_angle penetration kw_roll kw_lat kr_roll kr_lat
//!                           normal_force s_wheel lead (NaN where a zone has no contact
//!                           candidate); rows y-major, yaw-minor
//! /contact_table/y          the lateral grid (m), /contact_table/yaw the yaw grid (rad)
//! /contact_table/conicity   amplitude, tan_gamma_e (EN 15302, yaw 0)
//! /contact_table/delta_r_en15302   y, delta_r: the level wheelset's Δr(y) it
//!                           was computed from (EN 15302's idealisation)
//! ```

use std::path::Path;

use super::columns::{read_columns, write_table};
use super::{SchemaError, attrs};
use crate::contact::table::{
    ConicityTable, ContactTable, ContactTableMeta, ContactTableRow, ZONE_FIELDS, ZONE_UNITS,
    ZoneEntry,
};

const GROUP: &str = "contact_table";
const WHEELS: [&str; 2] = ["left", "right"];
const ZONES: [&str; 2] = ["tread", "flange"];

fn column_names() -> (Vec<String>, Vec<String>) {
    let mut names: Vec<String> = ["y", "yaw", "height", "roll", "delta_r"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    let mut units: Vec<String> = ["m", "rad", "m", "rad", "m"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    for w in WHEELS {
        for z in ZONES {
            for (f, u) in ZONE_FIELDS.iter().zip(ZONE_UNITS) {
                names.push(format!("{w}_{z}_{f}"));
                units.push(u.to_string());
            }
        }
    }
    (names, units)
}

fn row_values(r: &ContactTableRow) -> Vec<f64> {
    let mut v = vec![r.y_m, r.yaw_rad, r.height_m, r.roll_rad, r.delta_r_m];
    for wheel in &r.zones {
        for zone in wheel {
            match zone {
                Some(z) => v.extend_from_slice(&z.to_values()),
                None => v.extend_from_slice(&[f64::NAN; 14]),
            }
        }
    }
    v
}

/// Write `table` as `/contact_table` of `file`.
pub(super) fn write(
    path: &Path,
    file: &hdf5::File,
    table: &ContactTable,
) -> Result<(), SchemaError> {
    let hdf = |action: &str| {
        let action = action.to_string();
        move |source| SchemaError::Hdf5 {
            path: path.to_path_buf(),
            action,
            source,
        }
    };
    let g = file
        .create_group(GROUP)
        .map_err(hdf("creating /contact_table"))?;
    let m = &table.meta;
    attrs::write_str(path, &g, "wheel_profile", &m.wheel_profile)?;
    attrs::write_str(path, &g, "rail_profile", &m.rail_profile)?;
    if let Some(r) = &m.rail_record {
        super::track::write_rail_record(path, &g, r)?;
    }
    attrs::write_f64(path, &g, "wheel_radius_m", m.wheel_radius_m)?;
    attrs::write_f64(path, &g, "back_to_back_m", m.back_to_back_m)?;
    attrs::write_f64(path, &g, "gauge_m", m.gauge_m)?;
    attrs::write_f64(path, &g, "rail_spacing_m", m.rail_spacing_m)?;
    attrs::write_f64(path, &g, "rail_inclination_rad", m.rail_inclination_rad)?;
    attrs::write_str(path, &g, "support", &m.support)?;
    attrs::write_f64(path, &g, "wheel_load_n", m.wheel_load_n)?;
    attrs::write_f64(path, &g, "young_pa", m.young_pa)?;
    attrs::write_f64(path, &g, "poisson", m.poisson)?;
    attrs::write_str(path, &g, "source", &m.source)?;
    attrs::write_u32(path, &g, "n_y", table.y_m.len() as u32)?;
    attrs::write_u32(path, &g, "n_yaw", table.yaw_rad.len() as u32)?;

    let (names, units) = column_names();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let units: Vec<&str> = units.iter().map(String::as_str).collect();
    write_table(
        path,
        &g,
        "database",
        &names,
        &units,
        &table.rows,
        row_values,
    )?;
    for (name, grid, unit) in [("y", &table.y_m, "m"), ("yaw", &table.yaw_rad, "rad")] {
        let ds = g
            .new_dataset_builder()
            .with_data(grid.as_slice())
            .create(name)
            .map_err(hdf("writing a contact-table grid"))?;
        attrs::write_str(path, &ds, "units", unit)?;
    }
    let c = &table.conicity;
    let pairs: Vec<[f64; 2]> = c
        .amplitude_m
        .iter()
        .zip(&c.tan_gamma_e)
        .map(|(a, t)| [*a, *t])
        .collect();
    write_table(
        path,
        &g,
        "conicity",
        &["amplitude", "tan_gamma_e"],
        &["m", "1"],
        &pairs,
        |p| *p,
    )?;
    let level: Vec<[f64; 2]> = c
        .level_y_m
        .iter()
        .zip(&c.level_delta_r_m)
        .map(|(y, d)| [*y, *d])
        .collect();
    write_table(
        path,
        &g,
        "delta_r_en15302",
        &["y", "delta_r"],
        &["m", "m"],
        &level,
        |p| *p,
    )
}

/// Read `/contact_table` of an open file; `None` when the file has none.
pub(super) fn read(path: &Path, file: &hdf5::File) -> Result<Option<ContactTable>, SchemaError> {
    if !file.link_exists(GROUP) {
        return Ok(None);
    }
    let g = file.group(GROUP).map_err(|source| SchemaError::Hdf5 {
        path: path.to_path_buf(),
        action: "opening /contact_table".into(),
        source,
    })?;
    let what = "/contact_table";
    let meta = ContactTableMeta {
        wheel_profile: attrs::read_str(path, &g, what, "wheel_profile")?,
        rail_profile: attrs::read_str(path, &g, what, "rail_profile")?,
        wheel_radius_m: attrs::read_f64(path, &g, what, "wheel_radius_m")?,
        back_to_back_m: attrs::read_f64(path, &g, what, "back_to_back_m")?,
        gauge_m: attrs::read_f64(path, &g, what, "gauge_m")?,
        rail_spacing_m: attrs::read_f64(path, &g, what, "rail_spacing_m")?,
        rail_inclination_rad: attrs::read_f64(path, &g, what, "rail_inclination_rad")?,
        rail_record: super::track::read_rail_record(
            path,
            &g,
            what,
            attrs::read_str(path, &g, what, "rail_profile")?,
        )?,
        support: attrs::read_str(path, &g, what, "support")?,
        wheel_load_n: attrs::read_f64(path, &g, what, "wheel_load_n")?,
        young_pa: attrs::read_f64(path, &g, what, "young_pa")?,
        poisson: attrs::read_f64(path, &g, what, "poisson")?,
        source: attrs::read_str(path, &g, what, "source")?,
    };
    let (names, _) = column_names();
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    let cols = read_columns(path, file, "contact_table/database", &names)?;
    let n = cols[0].len();
    let rows = (0..n)
        .map(|i| {
            let mut zones = [[None; 2]; 2];
            for (w, wheel) in zones.iter_mut().enumerate() {
                for (z, zone) in wheel.iter_mut().enumerate() {
                    let base = 5 + (w * 2 + z) * 14;
                    let v: Vec<f64> = (0..14).map(|k| cols[base + k][i]).collect();
                    *zone = ZoneEntry::from_values(&v);
                }
            }
            ContactTableRow {
                y_m: cols[0][i],
                yaw_rad: cols[1][i],
                height_m: cols[2][i],
                roll_rad: cols[3][i],
                delta_r_m: cols[4][i],
                zones,
            }
        })
        .collect();
    let grid = |name: &str| -> Result<Vec<f64>, SchemaError> {
        g.dataset(name)
            .and_then(|d| d.read_raw::<f64>())
            .map_err(|source| SchemaError::Hdf5 {
                path: path.to_path_buf(),
                action: format!("reading /contact_table/{name}"),
                source,
            })
    };
    let conicity = if g.link_exists("conicity") {
        let c = read_columns(
            path,
            file,
            "contact_table/conicity",
            &["amplitude", "tan_gamma_e"],
        )?;
        let level = if g.link_exists("delta_r_en15302") {
            read_columns(
                path,
                file,
                "contact_table/delta_r_en15302",
                &["y", "delta_r"],
            )?
        } else {
            vec![Vec::new(), Vec::new()]
        };
        ConicityTable {
            amplitude_m: c[0].clone(),
            tan_gamma_e: c[1].clone(),
            level_y_m: level[0].clone(),
            level_delta_r_m: level[1].clone(),
        }
    } else {
        ConicityTable::default()
    };
    let table = ContactTable {
        meta,
        y_m: grid("y")?,
        yaw_rad: grid("yaw")?,
        rows,
        conicity,
    };
    table.validate().map_err(|e| SchemaError::Invalid {
        path: path.to_path_buf(),
        object: "/contact_table".into(),
        rule: e.to_string(),
    })?;
    Ok(Some(table))
}
