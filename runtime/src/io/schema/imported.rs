//! Reading and writing `/imported_contact_table`: a contact geometry table
//! computed by another code ([`crate::contact::imported`]), written by
//! `track-preproc import-contact-table`.
//!
//! ```text
//! /                                 attributes: schema_version, tool, tool_version
//! /imported_contact_table           attributes: source, format, wheel ("left": the rows
//!                                   describe the left wheel, the right wheel reads the row
//!                                   at −y), n_rows, y_min_m, y_max_m, y_step_m
//! /imported_contact_table/database  rows × 12 f64: y normal_force contact_angle a b
//!                                   wheel_lateral rolling_radius c11 c22 c23 rail_vertical
//!                                   penetration (attributes `columns`, `units`)
//! /input/command_line, /input/<role>  provenance: the command and the imported file's text
//! ```
//!
//! Files are written atomically ([`crate::io::AtomicFile`] through
//! [`TableFileWriter`]); the reader checks the schema version and the
//! table's rules ([`ImportedContactTable::validate`]).

use std::path::Path;

use super::columns::{read_table, write_table};
use super::{SCHEMA_VERSION, SchemaError, TableFileWriter, attrs};
use crate::contact::imported::{ImportedContactTable, ImportedRow, ROW_COLUMNS, ROW_UNITS};
use crate::geometry::track::Provenance;

const GROUP: &str = "imported_contact_table";
const DATASET: &str = "imported_contact_table/database";

fn columns() -> ([&'static str; 12], [&'static str; 12]) {
    let mut names = ["y"; 12];
    let mut units = ["m"; 12];
    names[1..].copy_from_slice(&ROW_COLUMNS);
    units[1..].copy_from_slice(&ROW_UNITS);
    (names, units)
}

/// Write `table` with its provenance as a table file of its own, atomically.
pub fn write_imported_contact_table_file(
    path: &Path,
    table: &ImportedContactTable,
    provenance: &Provenance,
) -> Result<(), SchemaError> {
    table.validate().map_err(|e| SchemaError::Invalid {
        path: path.to_path_buf(),
        object: format!("/{GROUP}"),
        rule: e.to_string(),
    })?;
    let w = TableFileWriter::create(path)?;
    let file = w.file();
    attrs::write_str(path, file, "tool", "track-preproc import-contact-table")?;
    attrs::write_str(path, file, "tool_version", env!("CARGO_PKG_VERSION"))?;
    let g = file
        .create_group(GROUP)
        .map_err(|source| SchemaError::Hdf5 {
            path: path.to_path_buf(),
            action: format!("creating /{GROUP}"),
            source,
        })?;
    let (lo, hi) = table.range_m();
    attrs::write_str(path, &g, "source", &table.source)?;
    attrs::write_str(path, &g, "format", &table.format)?;
    attrs::write_str(path, &g, "wheel", "left")?;
    attrs::write_u32(path, &g, "n_rows", table.rows.len() as u32)?;
    attrs::write_f64(path, &g, "y_min_m", lo)?;
    attrs::write_f64(path, &g, "y_max_m", hi)?;
    attrs::write_f64(path, &g, "y_step_m", table.step_m())?;
    let (names, units) = columns();
    let rows: Vec<(f64, ImportedRow)> = table
        .y_m
        .iter()
        .copied()
        .zip(table.rows.iter().copied())
        .collect();
    write_table(path, &g, "database", &names, &units, &rows, |(y, r)| {
        let mut v = [*y; 12];
        v[1..].copy_from_slice(&r.to_values());
        v
    })?;
    w.write_provenance(provenance)?;
    w.finish()
}

/// Read the imported contact table of a file written by
/// [`write_imported_contact_table_file`].
pub fn read_imported_contact_table(path: &Path) -> Result<ImportedContactTable, SchemaError> {
    let file = hdf5::File::open(path).map_err(|source| SchemaError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    let found: u32 = attrs::read(path, &file, "the file", "schema_version")?;
    if found != SCHEMA_VERSION {
        return Err(SchemaError::UnsupportedVersion {
            path: path.to_path_buf(),
            found,
            supported: SCHEMA_VERSION,
        });
    }
    if !file.link_exists(GROUP) {
        return Err(SchemaError::Missing {
            path: path.to_path_buf(),
            what: format!("group /{GROUP} (write it with track-preproc import-contact-table)"),
        });
    }
    let g = file.group(GROUP).map_err(|source| SchemaError::Hdf5 {
        path: path.to_path_buf(),
        action: format!("opening /{GROUP}"),
        source,
    })?;
    let what = format!("/{GROUP}");
    let source = attrs::read_str(path, &g, &what, "source")?;
    let format = attrs::read_str(path, &g, &what, "format")?;
    let wheel = attrs::read_str(path, &g, &what, "wheel")?;
    if wheel != "left" {
        return Err(SchemaError::Invalid {
            path: path.to_path_buf(),
            object: what,
            rule: format!(
                "attribute wheel = \"{wheel}\": this build reads tables of the left wheel only"
            ),
        });
    }
    let (names, _) = columns();
    let data = read_table(path, &file, DATASET, &names)?;
    let table = ImportedContactTable {
        source,
        format,
        y_m: data.iter().map(|r| r[0]).collect(),
        rows: data
            .iter()
            .map(|r| {
                let mut v = [0.0; 11];
                v.copy_from_slice(&r[1..]);
                ImportedRow::from_values(&v)
            })
            .collect(),
    };
    table.validate().map_err(|e| SchemaError::Invalid {
        path: path.to_path_buf(),
        object: DATASET.into(),
        rule: e.to_string(),
    })?;
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::track::InputFile;

    #[test]
    fn round_trip_keeps_every_value() {
        let y_m: Vec<f64> = (0..7).map(|i| -3e-5 + 1e-5 * i as f64).collect();
        let rows = y_m
            .iter()
            .map(|&y| ImportedRow {
                normal_force_n: 66_661.0 + y * 1e6,
                contact_angle_rad: 0.01422 + y,
                a_m: 5.95e-3,
                b_m: 6.65e-3,
                wheel_lateral_m: 0.756301 - y,
                rolling_radius_m: 0.424883 + 0.1 * y,
                c11: 4.12,
                c22: 3.56,
                c23: 1.37,
                rail_vertical_m: -5.9e-5,
                penetration_m: 7.01e-5,
            })
            .collect();
        let table = ImportedContactTable {
            source: "unit test".into(),
            format: "rsgeo".into(),
            y_m,
            rows,
        };
        let dir = std::env::temp_dir().join(format!("imported-rt-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.h5");
        let prov = Provenance {
            command_line: "test".into(),
            inputs: vec![InputFile {
                role: "rsgeo".into(),
                path: "RSGEO.dat".into(),
                text: "#\n".into(),
            }],
        };
        write_imported_contact_table_file(&path, &table, &prov).unwrap();
        let back = read_imported_contact_table(&path).unwrap();
        assert_eq!(back, table);
        let p = crate::io::schema::read_provenance(&path).unwrap();
        assert_eq!(p.inputs[0].role, "rsgeo");
        // A track-only file has no imported table: the error says which group.
        let e = read_imported_contact_table(&dir.join("missing.h5")).unwrap_err();
        assert!(e.to_string().contains("missing.h5"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
