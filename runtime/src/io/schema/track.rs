//! Reading and writing the track part of a table file (docs/reference/04-table-files.md §4).

use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;

use super::columns::{read_table, to_vlu, write_table};
use super::{SCHEMA_VERSION, SchemaError, attrs, contact_table, design_elements};
use crate::contact::table::ContactTable;
use crate::geometry::profile::rail_cant::{CantSource, RailProfileRecord};
use crate::geometry::track::{
    CENTERLINE_COLUMNS, CENTERLINE_UNITS, CenterlineRow, CenterlineTable, InputFile, Provenance,
    RAIL_COLUMNS, RAIL_UNITS, RailRow, RailTable, Side, TrackMeta, TrackTables,
};
use crate::io::AtomicFile;

/// Dataset path of each table.
const CENTERLINE_DATASET: &str = "centerline/database";
fn rail_group(side: Side) -> &'static str {
    match side {
        Side::Left => "left_rail",
        Side::Right => "right_rail",
    }
}

/// A table file being written. Nothing appears at the destination until
/// [`TableFileWriter::finish`] succeeds.
pub struct TableFileWriter {
    file: hdf5::File,
    atomic: AtomicFile,
}

impl TableFileWriter {
    /// Start writing `path` (atomically; see [`AtomicFile`]).
    pub fn create(path: &Path) -> Result<Self, SchemaError> {
        let atomic = AtomicFile::new(path);
        let file =
            hdf5::File::create(atomic.temp_path()).map_err(|source| SchemaError::Create {
                path: path.to_path_buf(),
                source,
            })?;
        let w = Self { file, atomic };
        w.attr_u32("schema_version", SCHEMA_VERSION)?;
        Ok(w)
    }

    fn path(&self) -> PathBuf {
        self.atomic.dest_path().to_path_buf()
    }

    fn err(&self, action: &str) -> impl FnOnce(hdf5::Error) -> SchemaError {
        let path = self.path();
        let action = action.to_string();
        move |source| SchemaError::Hdf5 {
            path,
            action,
            source,
        }
    }

    fn attr_u32(&self, name: &str, v: u32) -> Result<(), SchemaError> {
        attrs::write_u32(self.atomic.dest_path(), &self.file, name, v)
    }

    fn attr_f64(&self, name: &str, v: f64) -> Result<(), SchemaError> {
        attrs::write_f64(self.atomic.dest_path(), &self.file, name, v)
    }

    fn attr_str(&self, name: &str, v: &str) -> Result<(), SchemaError> {
        attrs::write_str(self.atomic.dest_path(), &self.file, name, v)
    }

    /// Write the centreline and both rail databases with the root
    /// attributes, and `/design` when the track has design elements.
    pub fn write_track(&self, track: &TrackTables) -> Result<(), SchemaError> {
        let m = &track.meta;
        self.attr_str("tool", &m.tool)?;
        self.attr_str("tool_version", &m.tool_version)?;
        self.attr_str("scheme", &m.scheme)?;
        self.attr_str("cant_scheme", &m.cant_scheme)?;
        self.attr_f64("step_m", m.step_m)?;
        self.attr_f64("gauge_m", m.gauge_m)?;
        self.attr_f64("rail_spacing_m", m.rail_spacing_m)?;
        self.attr_f64("cant_base_m", m.cant_base_m)?;
        self.attr_str("rail_inclination", &m.rail_inclination)?;
        self.attr_f64("rail_inclination_rad", m.rail_inclination_rad)?;
        if let Some(r) = &m.rail_profile {
            self.attr_str("rail_profile", &r.file)?;
            write_rail_record(self.atomic.dest_path(), &self.file, r)?;
        }
        self.attr_f64("length_m", track.centerline.length_m())?;

        let path = self.path();
        let g = self
            .file
            .create_group("centerline")
            .map_err(self.err("creating /centerline"))?;
        write_table(
            &path,
            &g,
            "database",
            &CENTERLINE_COLUMNS,
            &CENTERLINE_UNITS,
            track.centerline.rows(),
            CenterlineRow::to_columns,
        )?;

        for side in Side::BOTH {
            let g = self
                .file
                .create_group(rail_group(side))
                .map_err(self.err("creating a rail group"))?;
            write_table(
                &path,
                &g,
                "database",
                &RAIL_COLUMNS,
                &RAIL_UNITS,
                track.rail(side).rows(),
                RailRow::to_columns,
            )?;
        }
        design_elements::write(&path, &self.file, &track.design_elements)
    }

    /// Write `/contact_table`.
    pub fn write_contact_table(&self, table: &ContactTable) -> Result<(), SchemaError> {
        contact_table::write(self.atomic.dest_path(), &self.file, table)
    }

    /// Write `/input`: the command line and the input files' text.
    pub fn write_provenance(&self, p: &Provenance) -> Result<(), SchemaError> {
        let g = self
            .file
            .create_group("input")
            .map_err(self.err("creating /input"))?;
        let write = |name: &str, text: &str| -> Result<hdf5::Dataset, hdf5::Error> {
            let ds = g.new_dataset::<VarLenUnicode>().shape(()).create(name)?;
            ds.write_scalar(&to_vlu(text))?;
            Ok(ds)
        };
        write("command_line", &p.command_line).map_err(self.err("writing /input/command_line"))?;
        for input in &p.inputs {
            let ds = write(&input.role, &input.text)
                .map_err(self.err(&format!("writing /input/{}", input.role)))?;
            ds.new_attr::<VarLenUnicode>()
                .shape(())
                .create("path")
                .and_then(|a| a.write_scalar(&to_vlu(&input.path)))
                .map_err(self.err("writing an input path"))?;
        }
        Ok(())
    }

    /// The open HDF5 file, for other modules of the schema (contact table).
    pub fn file(&self) -> &hdf5::File {
        &self.file
    }

    /// Close the file and move it into place.
    pub fn finish(self) -> Result<(), SchemaError> {
        let path = self.path();
        let Self { file, atomic } = self;
        file.close().map_err(|source| SchemaError::Hdf5 {
            path: path.clone(),
            action: "closing".into(),
            source,
        })?;
        atomic
            .commit()
            .map_err(|source| SchemaError::Io { path, source })
    }
}

/// Write a whole track table file atomically.
pub fn write_track_file(
    path: &Path,
    track: &TrackTables,
    provenance: &Provenance,
) -> Result<(), SchemaError> {
    let w = TableFileWriter::create(path)?;
    w.write_track(track)?;
    w.write_provenance(provenance)?;
    w.finish()
}

/// Open a table file and check its schema version. A results file of
/// `sim run` (root attribute `schema`, which table files do not have) is
/// refused as such.
fn open_checked(path: &Path) -> Result<hdf5::File, SchemaError> {
    let file = hdf5::File::open(path).map_err(|source| SchemaError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    if let Ok(schema) = attrs::read_str(path, &file, "the file", "schema") {
        return Err(SchemaError::Invalid {
            path: path.to_path_buf(),
            object: "the file".into(),
            rule: format!(
                "its root attribute schema = \"{schema}\" marks a results file of sim run, not a table file of track-preproc"
            ),
        });
    }
    let found: u32 = attrs::read(path, &file, "the file", "schema_version")?;
    if found != SCHEMA_VERSION {
        return Err(SchemaError::UnsupportedVersion {
            path: path.to_path_buf(),
            found,
            supported: SCHEMA_VERSION,
        });
    }
    Ok(file)
}

fn read_attr_f64(path: &Path, file: &hdf5::File, name: &str) -> Result<f64, SchemaError> {
    attrs::read_f64(path, file, "the file", name)
}

fn read_attr_str(path: &Path, file: &hdf5::File, name: &str) -> Result<String, SchemaError> {
    attrs::read_str(path, file, "the file", name)
}

/// Whether `loc` has the attribute `name`.
pub(super) fn has_attr(loc: &hdf5::Location, name: &str) -> bool {
    loc.attr_names()
        .is_ok_and(|names| names.iter().any(|n| n == name))
}

/// Write the digest and carried cant of a rail profile record (the file's
/// name is written by the caller: `rail_profile`) as attributes of `loc`
/// (docs/reference/04-table-files.md §4.1).
pub(super) fn write_rail_record(
    path: &Path,
    loc: &hdf5::Location,
    r: &RailProfileRecord,
) -> Result<(), SchemaError> {
    attrs::write_str(path, loc, "rail_profile_sha256", &r.sha256)?;
    attrs::write_f64(path, loc, "rail_profile_cant_rad", r.carried_cant_rad)?;
    attrs::write_str(
        path,
        loc,
        "rail_profile_cant_source",
        r.carried_cant_source.name(),
    )
}

/// The rail profile record of `loc` for the file `file`: `None` when the
/// digest is absent (files written before it was recorded).
pub(super) fn read_rail_record(
    path: &Path,
    loc: &hdf5::Location,
    what: &str,
    file: String,
) -> Result<Option<RailProfileRecord>, SchemaError> {
    if !has_attr(loc, "rail_profile_sha256") {
        return Ok(None);
    }
    let source = attrs::read_str(path, loc, what, "rail_profile_cant_source")?;
    Ok(Some(RailProfileRecord {
        file,
        sha256: attrs::read_str(path, loc, what, "rail_profile_sha256")?,
        carried_cant_rad: attrs::read_f64(path, loc, what, "rail_profile_cant_rad")?,
        carried_cant_source: CantSource::from_name(&source).ok_or_else(|| {
            SchemaError::Invalid {
                path: path.to_path_buf(),
                object: what.to_string(),
                rule: format!(
                    "rail_profile_cant_source is '{source}', not detected, declared or unknown"
                ),
            }
        })?,
    }))
}

/// The root attributes of a table file holding a track (no tables read).
pub fn read_track_meta(path: &Path) -> Result<TrackMeta, SchemaError> {
    read_meta(path, &open_checked(path)?)
}

fn read_meta(path: &Path, file: &hdf5::File) -> Result<TrackMeta, SchemaError> {
    let scheme = read_attr_str(path, file, "scheme")?;
    Ok(TrackMeta {
        // Older files: the cant used the centreline's scheme.
        cant_scheme: match has_attr(file, "cant_scheme") {
            true => read_attr_str(path, file, "cant_scheme")?,
            false => scheme.clone(),
        },
        scheme,
        step_m: read_attr_f64(path, file, "step_m")?,
        gauge_m: read_attr_f64(path, file, "gauge_m")?,
        rail_spacing_m: read_attr_f64(path, file, "rail_spacing_m")?,
        cant_base_m: read_attr_f64(path, file, "cant_base_m")?,
        rail_inclination: read_attr_str(path, file, "rail_inclination")?,
        rail_inclination_rad: read_attr_f64(path, file, "rail_inclination_rad")?,
        rail_profile: match has_attr(file, "rail_profile") {
            true => read_rail_record(
                path,
                file,
                "the file",
                read_attr_str(path, file, "rail_profile")?,
            )?,
            false => None,
        },
        tool: read_attr_str(path, file, "tool")?,
        tool_version: read_attr_str(path, file, "tool_version")?,
    })
}

/// Load the track databases of a table file into memory.
pub fn read_track(path: &Path) -> Result<TrackTables, SchemaError> {
    let file = open_checked(path)?;
    let meta = read_meta(path, &file)?;
    let table_err = |source| SchemaError::Table {
        path: path.to_path_buf(),
        source,
    };
    let rows = read_table(path, &file, CENTERLINE_DATASET, &CENTERLINE_COLUMNS)?;
    let centerline = CenterlineTable::new(rows.iter().map(CenterlineRow::from_columns).collect())
        .map_err(table_err)?;
    let mut rails = Vec::with_capacity(2);
    for side in Side::BOTH {
        let name = format!("{}/database", rail_group(side));
        let rows = read_table(path, &file, &name, &RAIL_COLUMNS)?;
        rails.push(
            RailTable::new(side, rows.iter().map(RailRow::from_columns).collect())
                .map_err(table_err)?,
        );
    }
    let right = rails.pop().expect("two rails");
    let left = rails.pop().expect("two rails");
    let tables = TrackTables {
        meta,
        centerline,
        left,
        right,
        design_elements: design_elements::read(path, &file)?,
    };
    tables.check_consistency().map_err(table_err)?;
    Ok(tables)
}

/// Read `/input` (command line and input files) of a table file.
pub fn read_provenance(path: &Path) -> Result<Provenance, SchemaError> {
    let file = open_checked(path)?;
    let g = file.group("input").map_err(|_| SchemaError::Missing {
        path: path.to_path_buf(),
        what: "group /input".into(),
    })?;
    let hdf = |action: String| {
        let path = path.to_path_buf();
        move |source| SchemaError::Hdf5 {
            path,
            action,
            source,
        }
    };
    let mut p = Provenance::default();
    for name in g.member_names().map_err(hdf("listing /input".into()))? {
        let ds = g
            .dataset(&name)
            .map_err(hdf(format!("opening /input/{name}")))?;
        let text: VarLenUnicode = ds
            .read_scalar()
            .map_err(hdf(format!("reading /input/{name}")))?;
        if name == "command_line" {
            p.command_line = text.as_str().to_string();
        } else {
            let input_path = ds
                .attr("path")
                .and_then(|a| a.read_scalar::<VarLenUnicode>())
                .map(|v| v.as_str().to_string())
                .unwrap_or_default();
            p.inputs.push(InputFile {
                role: name,
                path: input_path,
                text: text.as_str().to_string(),
            });
        }
    }
    Ok(p)
}

/// Read the contact lookup table of a table file, if it has one.
pub fn read_contact_table(path: &Path) -> Result<Option<ContactTable>, SchemaError> {
    let file = open_checked(path)?;
    contact_table::read(path, &file)
}

/// Write a file holding only a contact lookup table (and provenance).
pub fn write_contact_table_file(
    path: &Path,
    table: &ContactTable,
    provenance: &Provenance,
) -> Result<(), SchemaError> {
    let w = TableFileWriter::create(path)?;
    w.attr_str("tool", &table.meta.source)?;
    w.attr_str("tool_version", env!("CARGO_PKG_VERSION"))?;
    w.write_contact_table(table)?;
    w.write_provenance(provenance)?;
    w.finish()
}
