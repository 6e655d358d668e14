//! The results file written while the run goes on (layout in
//! `results_file`): [`ResultsWriter::create`] makes the file (under its
//! temporary name, [`AtomicFile`]) with every dataset empty, chunked and
//! extendable; [`ResultsWriter::append`] adds the samples of each chunk
//! the run hands over; [`ResultsWriter::finish`] writes the run's
//! attributes and scene and renames the file into place. So the memory a
//! run needs does not grow with its length, and nothing appears at the
//! destination unless the whole file was written (a run that fails or is
//! interrupted is still finished, with its `status` saying so).

use std::path::{Path, PathBuf};

use super::raw_series::{self, SeriesMaker, SeriesValue};
use super::results_file::{
    NADAL_ATTRIBUTES, RESULTS_SCHEMA, RESULTS_SCHEMA_VERSION, RESULTS_TOOL, hdf5_err,
};
use super::{SchemaError, attrs};
use crate::io::AtomicFile;
use crate::results::{
    Column, Dataset, ResultsSink, RunResults, SinkError, TIME_S, Values, WHEEL_COLUMNS,
    WHEEL_GROUPS, WHEELSET_COLUMNS, ZONE_COLUMNS, ZONE_GROUPS, wheelset_group,
};

/// Samples per HDF5 chunk of every dataset (8 KiB of f64): the unit in
/// which the file grows and is read back.
pub const RESULTS_CHUNK_SAMPLES: usize = 1024;

/// Half the number of children of a node of a dataset's chunk-index
/// B-tree (HDF5's `istore_k`, default 32): a run's series have a chunk
/// per 1 024 samples, a few to a few dozen.
const RESULTS_BTREE_K: u32 = 2;

/// Hash slots of each series' chunk cache while it is written (HDF5's
/// default 521 is for random access to many chunks; a series is appended
/// one chunk at a time). The cache holds one f64 chunk
/// ([`RESULTS_CHUNK_SAMPLES`] × 8 bytes; HDF5's default is 1 MiB): a
/// chunk is written out when the next one starts instead of staying in
/// memory until the file is closed.
const RESULTS_CHUNK_CACHE_SLOTS: usize = 7;

/// A results file being written; see the module docs.
#[derive(Debug)]
pub struct ResultsWriter {
    path: PathBuf,
    atomic: AtomicFile,
    file: hdf5::File,
    /// Wheelset groups made (with the first chunk).
    wheelsets: Option<usize>,
    /// Bodies whose groups were made with the wheelset groups (`bodies/`).
    bodies: usize,
    /// Every dataset, kept open from its creation, in creation order
    /// (`time_s`, the wheelsets' columns, the bodies' columns; the order
    /// [`Self::append_chunk`] appends in): opening 200 datasets by name
    /// at every append cost as much as writing their samples.
    series: Vec<hdf5::Dataset>,
    /// The property lists, dataspace and string type every series shares.
    maker: SeriesMaker,
    written: usize,
    last_time_s: Option<f64>,
}

/// Create the empty, extendable dataset `dataset` of `group` (through
/// `maker`, [`super::raw_series`]).
fn create_series<T: SeriesValue>(
    path: &Path,
    maker: &SeriesMaker,
    group: &hdf5::Group,
    dataset: &Dataset,
) -> Result<hdf5::Dataset, SchemaError> {
    maker
        .create::<T>(group, dataset.name, dataset.units, dataset.description)
        .map_err(|source| {
            let what = format!("{}/{}", group.name().trim_end_matches('/'), dataset.name);
            hdf5_err(path, format!("creating {what}"))(source)
        })
}

/// The next of the open datasets `series` (in creation order).
pub(super) fn next_series<'a>(
    path: &Path,
    series: &mut std::slice::Iter<'a, hdf5::Dataset>,
) -> Result<&'a hdf5::Dataset, SchemaError> {
    series.next().ok_or_else(|| SchemaError::Invalid {
        path: path.to_path_buf(),
        object: "/".into(),
        rule: "a chunk holds more series than the file was made with".into(),
    })
}

/// Append `values` to `ds`, which holds `from` values.
fn append_series<T: SeriesValue>(
    path: &Path,
    ds: &hdf5::Dataset,
    from: usize,
    values: &[T],
) -> Result<(), SchemaError> {
    raw_series::append(ds, from, values)
        .map_err(|e| hdf5_err(path, format!("writing {}", ds.name()))(e))
}

/// Create the datasets of `columns` in `group`, appended to `series`.
pub(super) fn create_columns<S, V>(
    path: &Path,
    maker: &SeriesMaker,
    group: &hdf5::Group,
    columns: &[Column<S, V>],
    series: &mut Vec<hdf5::Dataset>,
) -> Result<(), SchemaError> {
    for c in columns {
        series.push(match &c.values {
            Values::F64(_) => create_series::<f64>(path, maker, group, &c.dataset)?,
            Values::Flags { .. } => create_series::<u8>(path, maker, group, &c.dataset)?,
        });
    }
    Ok(())
}

/// Append the columns of `s` to the next datasets of `series` (those
/// [`create_columns`] made for `columns`).
pub(super) fn append_columns<S, V>(
    path: &Path,
    series: &mut std::slice::Iter<'_, hdf5::Dataset>,
    columns: &[Column<S, V>],
    s: &S,
    from: usize,
) -> Result<(), SchemaError> {
    for c in columns {
        let ds = next_series(path, series)?;
        match &c.values {
            Values::F64(a) => append_series(path, ds, from, (a.series)(s))?,
            Values::Flags { access, .. } => append_series(path, ds, from, (access.series)(s))?,
        }
    }
    Ok(())
}

pub(super) fn create_group(
    path: &Path,
    parent: &hdf5::Group,
    name: &str,
) -> Result<hdf5::Group, SchemaError> {
    parent
        .create_group(name)
        .map_err(hdf5_err(path, format!("creating group {name}")))
}

impl ResultsWriter {
    /// Create the results file for `path`, written under its temporary
    /// name until [`Self::finish`]: creating it first probes the output
    /// location before any work. The wheelset groups are made with the
    /// first chunk (their names and Nadal limits).
    pub fn create(path: &Path) -> Result<Self, SchemaError> {
        let atomic = AtomicFile::new(path);
        // Memory per series (every series' first chunk is written before
        // any is closed, so each holds its own buffers): chunk-index
        // B-tree nodes of K = 2 (HDF5's default 32 sizes each node for 64
        // chunks, where a run has a few) and a chunk cache of 7 slots and
        // one chunk per dataset (defaults 521 and 1 MiB; one chunk per
        // series is written at a time). The car's run: 7 710 → 6 610 page
        // faults, −5 M instructions; the bogie's (3 chunks): 6 350 →
        // 5 500; readers see the same file.
        let file = hdf5::File::with_options()
            .with_fcpl(|p| {
                p.attr_creation_order(hdf5::plist::file_create::AttrCreationOrder::Indexed)
                    .istore_k(RESULTS_BTREE_K)
            })
            .with_fapl(|p| {
                p.chunk_cache(RESULTS_CHUNK_CACHE_SLOTS, RESULTS_CHUNK_SAMPLES * 8, 0.75)
            })
            .create(atomic.temp_path())
            .map_err(|source| SchemaError::Create {
                path: path.to_path_buf(),
                source,
            })?;
        attrs::write_str(path, &file, "schema", RESULTS_SCHEMA)?;
        attrs::write_u32(path, &file, "schema_version", RESULTS_SCHEMA_VERSION)?;
        attrs::write_str(path, &file, "tool", RESULTS_TOOL)?;
        attrs::write_str(path, &file, "tool_version", env!("CARGO_PKG_VERSION"))?;
        let maker = SeriesMaker::new().map_err(hdf5_err(path, "preparing the series"))?;
        let time = create_series::<f64>(path, &maker, &file, &TIME_S)?;
        Ok(Self {
            path: path.to_path_buf(),
            atomic,
            file,
            wheelsets: None,
            bodies: 0,
            series: vec![time],
            maker,
            written: 0,
            last_time_s: None,
        })
    }

    /// Make the wheelset groups of `record` (names, Nadal limits) unless
    /// made; refuse a record with another number of wheelsets.
    fn ensure_wheelsets(&mut self, record: &RunResults) -> Result<(), SchemaError> {
        let path = &self.path;
        match self.wheelsets {
            Some(n) if n == record.wheelsets.len() => return Ok(()),
            Some(n) => {
                return Err(SchemaError::InvalidResults {
                    path: path.to_path_buf(),
                    source: crate::results::ResultsError::WheelsetCount {
                        expected: n,
                        found: record.wheelsets.len(),
                    },
                });
            }
            None => {}
        }
        for (i, ws) in record.wheelsets.iter().enumerate() {
            let g = create_group(path, &self.file, &wheelset_group(i))?;
            attrs::write_str(path, &g, "name", &ws.name)?;
            create_columns(path, &self.maker, &g, &WHEELSET_COLUMNS, &mut self.series)?;
            for (wheel, wg) in ws.wheels.iter().zip(WHEEL_GROUPS) {
                let g = create_group(path, &g, wg)?;
                create_columns(path, &self.maker, &g, &WHEEL_COLUMNS, &mut self.series)?;
                if let Some(n) = &wheel.nadal {
                    let values = [n.flange_angle_rad, n.friction, n.limit];
                    for (name, v) in NADAL_ATTRIBUTES.into_iter().zip(values) {
                        attrs::write_f64(path, &g, name, v)?;
                    }
                }
                for zg in ZONE_GROUPS {
                    let g = create_group(path, &g, zg)?;
                    create_columns(path, &self.maker, &g, &ZONE_COLUMNS, &mut self.series)?;
                }
            }
        }
        super::results_bodies::create(path, &self.maker, &self.file, record, &mut self.series)?;
        self.bodies = record.bodies.len();
        self.wheelsets = Some(record.wheelsets.len());
        Ok(())
    }

    /// The destination.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Samples written so far.
    pub fn samples(&self) -> usize {
        self.written
    }

    /// Append the samples of `chunk`: the same wheelsets as every other
    /// chunk, a consistent record ([`RunResults::validate`]) whose times do not go
    /// back before the last sample written. Refused chunks write nothing.
    pub fn append_chunk(&mut self, chunk: &RunResults) -> Result<(), SchemaError> {
        let path = &self.path;
        let invalid = |source| SchemaError::InvalidResults {
            path: path.to_path_buf(),
            source,
        };
        chunk.validate().map_err(invalid)?;
        if let (Some(&first), Some(previous)) = (chunk.time_s.first(), self.last_time_s)
            && first < previous
        {
            return Err(invalid(crate::results::ResultsError::TimeDecreasing {
                index: self.written,
                previous,
                value: first,
            }));
        }
        self.ensure_wheelsets(chunk)?;
        let path = &self.path;
        if chunk.bodies.len() != self.bodies {
            return Err(SchemaError::InvalidResults {
                path: path.to_path_buf(),
                source: crate::results::ResultsError::BodyCount {
                    expected: self.bodies,
                    found: chunk.bodies.len(),
                },
            });
        }
        let from = self.written;
        self.append_series_of(&chunk.time_s, &chunk.wheelsets, &chunk.bodies, from)?;
        self.written += chunk.len();
        if let Some(&t) = chunk.time_s.last() {
            self.last_time_s = Some(t);
        }
        Ok(())
    }

    /// Drop every sample written (the datasets back to length 0).
    pub fn clear(&mut self) -> Result<(), SchemaError> {
        let empty = RunResults {
            wheelsets: vec![Default::default(); self.wheelsets.unwrap_or(0)],
            ..RunResults::default()
        };
        // Appending nothing from 0 resizes every dataset to 0.
        self.written = 0;
        self.last_time_s = None;
        let no_bodies = vec![crate::results::BodySeries::default(); self.bodies];
        self.append_series_of(&[], &empty.wheelsets, &no_bodies, 0)
    }

    /// Append the time, wheelset and body series to every open dataset,
    /// in creation order, from sample `from` on (nothing from 0: every
    /// dataset back to length 0).
    fn append_series_of(
        &self,
        time_s: &[f64],
        wheelsets: &[crate::results::WheelsetSeries],
        bodies: &[crate::results::BodySeries],
        from: usize,
    ) -> Result<(), SchemaError> {
        let path = &self.path;
        let mut series = self.series.iter();
        append_series(path, next_series(path, &mut series)?, from, time_s)?;
        for ws in wheelsets {
            append_columns(path, &mut series, &WHEELSET_COLUMNS, ws, from)?;
            for wheel in &ws.wheels {
                append_columns(path, &mut series, &WHEEL_COLUMNS, wheel, from)?;
                for zone in &wheel.zones {
                    append_columns(path, &mut series, &ZONE_COLUMNS, zone, from)?;
                }
            }
        }
        super::results_bodies::append(path, &mut series, bodies, from)
    }

    /// Write the run's metadata (`record`'s attributes, named as
    /// [`RunResults::attributes`] requires) and scene text, close the file
    /// and move it into place. `record`'s samples are not written (they
    /// were appended); its wheelsets make the groups of a run that ended
    /// before its first sample.
    pub fn finish(mut self, record: &RunResults) -> Result<(), SchemaError> {
        RunResults {
            attributes: record.attributes.clone(),
            ..RunResults::default()
        }
        .validate()
        .map_err(|source| SchemaError::InvalidResults {
            path: self.path.clone(),
            source,
        })?;
        self.ensure_wheelsets(record)?;
        let path = self.path;
        for (name, value) in &record.attributes {
            attrs::write_value(&path, &self.file, name, value)?;
        }
        super::results_file::write_scene(&path, &self.file, &record.scene_toml)?;
        self.file.close().map_err(hdf5_err(&path, "closing"))?;
        self.atomic.commit().map_err(|source| SchemaError::Io {
            path: path.clone(),
            source,
        })
    }
}

impl ResultsSink for ResultsWriter {
    fn append(&mut self, chunk: &RunResults) -> Result<(), SinkError> {
        self.append_chunk(chunk).map_err(|e| SinkError {
            message: e.to_string(),
        })
    }

    fn restart(&mut self) -> Result<(), SinkError> {
        self.clear().map_err(|e| SinkError {
            message: e.to_string(),
        })
    }

    fn len(&self) -> usize {
        self.written
    }
}
