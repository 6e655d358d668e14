//! The series of a results file being written ([`super::ResultsWriter`]):
//! each is listed when its group is made ([`SeriesSlot`]), made with its
//! first samples, and open only while it is written.
//!
//! Why (docs/reference/04-table-files.md, the results file): an open
//! HDF5 dataset holds about 20 kB of the library's memory (its shared
//! state, a copy of its creation properties, its chunk index). With the
//! 438 series of the Cooperrider car's file all open at once, those were
//! 2 000 of the run's 5 800 page faults, the first touches of fresh heap
//! pages, each a few µs of system time. Made, written and closed one
//! after the other, the series reuse the same memory (the library's free
//! lists). A run's first flush makes every series with its samples
//! (no second open); a later flush, every 4 096 samples, reopens each
//! series by name, which costs a few hundredths of the samples' cost.

use std::path::Path;

use super::SchemaError;
use super::raw_series::{self, SeriesMaker, SeriesValue};
use super::results_file::hdf5_err;
use crate::results::{Column, Dataset, Values};

/// A series of the file: its group and definition, and whether the
/// dataset was made yet.
#[derive(Debug)]
pub(super) struct SeriesSlot {
    group: hdf5::Group,
    dataset: Dataset,
    made: bool,
}

impl SeriesSlot {
    /// The series `dataset` of `group`, not made yet.
    pub(super) fn new(group: &hdf5::Group, dataset: Dataset) -> Self {
        Self {
            group: group.clone(),
            dataset,
            made: false,
        }
    }

    /// Its path in the file, for messages.
    fn name(&self) -> String {
        format!(
            "{}/{}",
            self.group.name().trim_end_matches('/'),
            self.dataset.name
        )
    }
}

/// List the series of `columns` in `group`.
pub(super) fn add_columns<S, V>(
    group: &hdf5::Group,
    columns: &[Column<S, V>],
    series: &mut Vec<SeriesSlot>,
) {
    series.extend(columns.iter().map(|c| SeriesSlot::new(group, c.dataset)));
}

/// Writes the series of a file in their listed order, from one sample on.
pub(super) struct SeriesCursor<'a> {
    path: &'a Path,
    maker: &'a SeriesMaker,
    slots: std::slice::IterMut<'a, SeriesSlot>,
    /// Samples the made series hold.
    held: usize,
}

impl<'a> SeriesCursor<'a> {
    /// A cursor on the first of `slots`, whose made series hold `held`
    /// samples.
    pub(super) fn new(
        path: &'a Path,
        maker: &'a SeriesMaker,
        slots: &'a mut [SeriesSlot],
        held: usize,
    ) -> Self {
        Self {
            path,
            maker,
            slots: slots.iter_mut(),
            held,
        }
    }

    /// Write `values` to the next series from sample `from` on (`from`
    /// ≤ the samples it holds; the series ends after them): made now with
    /// its attributes if it was not, else opened by name; closed when
    /// written. A made series given nothing at its end is left alone.
    pub(super) fn append<T: SeriesValue>(
        &mut self,
        from: usize,
        values: &[T],
    ) -> Result<(), SchemaError> {
        let path = self.path;
        let slot = self.slots.next().ok_or_else(|| SchemaError::Invalid {
            path: path.to_path_buf(),
            object: "/".into(),
            rule: "a chunk holds more series than the file was made with".into(),
        })?;
        if slot.made && values.is_empty() && from == self.held {
            return Ok(());
        }
        let d = &slot.dataset;
        let dataset = if slot.made {
            slot.group
                .dataset(d.name)
                .map_err(|e| hdf5_err(path, format!("opening {}", slot.name()))(e))?
        } else {
            self.maker
                .create::<T>(&slot.group, d.name, d.units, d.description)
                .map_err(|e| hdf5_err(path, format!("creating {}", slot.name()))(e))?
        };
        slot.made = true;
        raw_series::append(&dataset, from, values)
            .map_err(|e| hdf5_err(path, format!("writing {}", slot.name()))(e))
    }

    /// Write the columns of `s` to the next series (those [`add_columns`]
    /// listed for `columns`).
    pub(super) fn append_columns<S, V>(
        &mut self,
        columns: &[Column<S, V>],
        s: &S,
        from: usize,
    ) -> Result<(), SchemaError> {
        for c in columns {
            match &c.values {
                Values::F64(a) => self.append(from, (a.series)(s))?,
                Values::Flags { access, .. } => self.append(from, (access.series)(s))?,
            }
        }
        Ok(())
    }
}
