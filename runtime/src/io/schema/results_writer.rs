//! The results file written while the run goes on (layout in
//! `results_file`): [`ResultsWriter::create`] makes the file (under its
//! temporary name, [`AtomicFile`]); [`ResultsWriter::append`] adds the
//! samples of each chunk the run hands over, to datasets chunked and
//! extendable, each made with its first samples
//! ([`super::results_series`]); [`ResultsWriter::finish`] makes any
//! dataset not made yet (empty), writes the run's attributes and scene,
//! closes the file and renames it into place. So the memory a
//! run needs does not grow with its length, and nothing appears at the
//! destination unless the whole file was written (a run that fails or is
//! interrupted is still finished, with its `status` saying so).

use std::path::{Path, PathBuf};

use super::raw_series::SeriesMaker;
use super::results_file::{
    NADAL_ATTRIBUTES, RESULTS_SCHEMA, RESULTS_SCHEMA_VERSION, RESULTS_TOOL, hdf5_err,
};
use super::results_series::{SeriesCursor, SeriesSlot, add_columns};
use super::{SchemaError, attrs};
use crate::io::AtomicFile;
use crate::results::{
    ResultsSink, RunResults, SinkError, TIME_S, WHEEL_COLUMNS, WHEEL_GROUPS, WHEELSET_COLUMNS,
    ZONE_COLUMNS, ZONE_GROUPS, wheelset_group,
};

/// Samples per HDF5 chunk of every dataset (8 KiB of f64): the unit in
/// which the file grows and is read back.
pub const RESULTS_CHUNK_SAMPLES: usize = 1024;

/// Half the number of children of a node of a dataset's chunk-index
/// B-tree (HDF5's `istore_k`, default 32): a run's series have a chunk
/// per 1 024 samples, a few to a few dozen.
const RESULTS_BTREE_K: u32 = 2;

/// Hash slots of each series' chunk cache (HDF5's default 521 is for
/// random access to many chunks). The cache itself holds no bytes (HDF5's
/// default is 1 MiB per dataset): `sim run` hands its samples over in
/// whole chunks (`FLUSH_SAMPLES`, four chunks, then the rest at the end),
/// so each chunk is written once and a cached copy would only cost memory
/// — 8 KiB per series, 890 of the car's page faults. A chunk written in
/// part (the last, or any with another caller's chunking) is read back
/// and completed by the library.
const RESULTS_CHUNK_CACHE_SLOTS: usize = 7;

/// Bytes of each series' chunk cache (see [`RESULTS_CHUNK_CACHE_SLOTS`]).
const RESULTS_CHUNK_CACHE_BYTES: usize = 0;

/// Size of the file's metadata cache (bytes), fixed: HDF5's default
/// starts at 2 MiB and grows to 32 MiB. The writer touches each object
/// header while it makes and writes that series, then not again until the
/// next flush, so a cache of a few headers serves it; a larger one only
/// keeps the headers of the whole file in memory until it is closed. The
/// car's run (438 series): 4 280 → 3 250 page faults, −7 M instructions;
/// a 100 s run (3 flushes) as fast; the same file.
const RESULTS_METADATA_CACHE_BYTES: usize = 64 << 10;

/// The metadata cache configuration of a results file being written
/// ([`RESULTS_METADATA_CACHE_BYTES`], neither grown nor shrunk).
fn metadata_cache() -> hdf5::plist::file_access::MetadataCacheConfig {
    use hdf5::plist::file_access::{
        CacheDecreaseMode, CacheIncreaseMode, FlashIncreaseMode, MetadataCacheConfig,
    };
    MetadataCacheConfig {
        set_initial_size: true,
        initial_size: RESULTS_METADATA_CACHE_BYTES,
        min_size: RESULTS_METADATA_CACHE_BYTES,
        max_size: RESULTS_METADATA_CACHE_BYTES,
        incr_mode: CacheIncreaseMode::Off,
        flash_incr_mode: FlashIncreaseMode::Off,
        decr_mode: CacheDecreaseMode::Off,
        ..MetadataCacheConfig::default()
    }
}

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
    /// Every series, in the order [`Self::append_chunk`] appends in
    /// (`time_s`, the wheelsets' columns, the bodies' columns), each made
    /// with its first samples and open only while it is written
    /// ([`super::results_series`]).
    series: Vec<SeriesSlot>,
    /// The property lists, dataspace and string type every series shares.
    maker: SeriesMaker,
    written: usize,
    last_time_s: Option<f64>,
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
        // Memory per series: chunk-index B-tree nodes of K = 2 (HDF5's
        // default 32 sizes each node for 64 chunks, where a run has a few)
        // and no chunk cache (above). The car's run: 7 710 → 6 610 page
        // faults with K = 2 and a one-chunk cache, −5 M instructions;
        // 6 660 → 5 780 without the cache; readers see the same file.
        let file = hdf5::File::with_options()
            .with_fcpl(|p| {
                p.attr_creation_order(hdf5::plist::file_create::AttrCreationOrder::Indexed)
                    .istore_k(RESULTS_BTREE_K)
            })
            .with_fapl(|p| {
                p.chunk_cache(RESULTS_CHUNK_CACHE_SLOTS, RESULTS_CHUNK_CACHE_BYTES, 0.75)
                    .mdc_config(&metadata_cache())
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
        let time = SeriesSlot::new(&file, TIME_S);
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
            add_columns(&g, &WHEELSET_COLUMNS, &mut self.series);
            for (wheel, wg) in ws.wheels.iter().zip(WHEEL_GROUPS) {
                let g = create_group(path, &g, wg)?;
                add_columns(&g, &WHEEL_COLUMNS, &mut self.series);
                if let Some(n) = &wheel.nadal {
                    let values = [n.flange_angle_rad, n.friction, n.limit];
                    for (name, v) in NADAL_ATTRIBUTES.into_iter().zip(values) {
                        attrs::write_f64(path, &g, name, v)?;
                    }
                }
                for zg in ZONE_GROUPS {
                    let g = create_group(path, &g, zg)?;
                    add_columns(&g, &ZONE_COLUMNS, &mut self.series);
                }
            }
        }
        super::results_bodies::create(path, &self.file, record, &mut self.series)?;
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
        self.append_nothing(0)?;
        self.written = 0;
        self.last_time_s = None;
        Ok(())
    }

    /// Append no sample to every series from sample `from` on: from 0,
    /// every series back to length 0; from the end, only the series not
    /// made yet are made (empty).
    fn append_nothing(&mut self, from: usize) -> Result<(), SchemaError> {
        let no_wheelsets = vec![Default::default(); self.wheelsets.unwrap_or(0)];
        let no_bodies = vec![crate::results::BodySeries::default(); self.bodies];
        self.append_series_of(&[], &no_wheelsets, &no_bodies, from)
    }

    /// Append the time, wheelset and body series to every series, in
    /// their order, from sample `from` on ([`Self::append_nothing`]: no
    /// samples).
    fn append_series_of(
        &mut self,
        time_s: &[f64],
        wheelsets: &[crate::results::WheelsetSeries],
        bodies: &[crate::results::BodySeries],
        from: usize,
    ) -> Result<(), SchemaError> {
        let mut series = SeriesCursor::new(&self.path, &self.maker, &mut self.series, self.written);
        series.append(from, time_s)?;
        for ws in wheelsets {
            series.append_columns(&WHEELSET_COLUMNS, ws, from)?;
            for wheel in &ws.wheels {
                series.append_columns(&WHEEL_COLUMNS, wheel, from)?;
                for zone in &wheel.zones {
                    series.append_columns(&ZONE_COLUMNS, zone, from)?;
                }
            }
        }
        super::results_bodies::append(&mut series, bodies, from)
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
        // The series of a run that ended before its first sample are made
        // now, empty.
        self.append_nothing(self.written)?;
        let path = self.path;
        for (name, value) in &record.attributes {
            attrs::write_value(&path, &self.file, name, value)?;
        }
        super::results_file::write_scene(&path, &self.maker, &self.file, &record.scene_toml)?;
        // Every handle into the file is released before it is closed, so
        // that the close writes everything out (and reports a failure)
        // before the file is moved into place.
        drop(std::mem::take(&mut self.series));
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
