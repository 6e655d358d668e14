//! The results file's series made and appended through the HDF5 C API
//! (`hdf5-sys`), with one dataset-creation property list, one dataspace
//! and one string type shared by every series of a file.
//!
//! Why: the high-level crate builds, copies and closes a fresh set of
//! property lists, dataspaces and datatypes for every dataset, attribute
//! and write. A run's file holds 200–440 series, each with its `units` and
//! `description` attributes, and that overhead was more than half of the
//! file's cost (callgrind, 438 series of 1 000 samples: 237 M instructions
//! through the crate, 102 M here; docs/reference/04-table-files.md, the
//! results file). The layout is the crate's: chunked
//! ([`super::RESULTS_CHUNK_SAMPLES`]), extendable, fill time `alloc`,
//! attributes as variable-length UTF-8 strings.
//!
//! Every call holds the crate's library lock (`hdf5_sys::LOCK`), as the
//! crate's own calls do, so runs writing files on several threads stay
//! safe. A failed call is an [`hdf5::Error`] carrying the library's error
//! stack.

use std::ffi::CString;

use hdf5_sys::h5::herr_t;
use hdf5_sys::h5i::hid_t;
use hdf5_sys::{h5a, h5d, h5p, h5s, h5t};

use super::RESULTS_CHUNK_SAMPLES;

/// Type-conversion buffer of a text dataset's write (bytes): room for
/// hundreds of string pointers, where the library's default is 1 MiB.
const TEXT_CONVERSION_BUFFER_BYTES: usize = 4096;

/// A value type a series holds: f64 values, or 0/1 flags as u8 (the
/// file's type is the native one).
pub(super) trait SeriesValue: Copy {
    /// The HDF5 memory type of `Self`.
    fn memory_type() -> hid_t;
}

impl SeriesValue for f64 {
    fn memory_type() -> hid_t {
        *h5t::H5T_NATIVE_DOUBLE
    }
}

impl SeriesValue for u8 {
    fn memory_type() -> hid_t {
        *h5t::H5T_NATIVE_UINT8
    }
}

/// The library's error stack after a failed `call` (or the call's name if
/// the stack cannot be read).
fn failed(call: &str) -> hdf5::Error {
    hdf5::Error::query()
        .ok()
        .filter(|e| e.stack().is_some_and(|s| !s.is_empty()))
        .unwrap_or_else(|| hdf5::Error::from(format!("{call} failed")))
}

/// `id` if valid (≥ 0), else the error of `call`.
fn check_id(id: hid_t, call: &str) -> Result<hid_t, hdf5::Error> {
    if id < 0 { Err(failed(call)) } else { Ok(id) }
}

fn check(status: herr_t, call: &str) -> Result<(), hdf5::Error> {
    if status < 0 {
        Err(failed(call))
    } else {
        Ok(())
    }
}

fn c_string(s: &str) -> Result<CString, hdf5::Error> {
    CString::new(s).map_err(|_| hdf5::Error::from(format!("'{s}' holds a NUL character")))
}

/// An HDF5 id closed with `close` when dropped (under the library lock).
struct Owned {
    id: hid_t,
    close: unsafe extern "C" fn(hid_t) -> herr_t,
}

impl Drop for Owned {
    fn drop(&mut self) {
        let _lock = hdf5_sys::LOCK.lock();
        // SAFETY: `id` was returned valid by the library and is closed
        // once, here.
        unsafe {
            (self.close)(self.id);
        }
    }
}

/// What every series of a file shares (module docs).
pub(super) struct SeriesMaker {
    /// Chunked (RESULTS_CHUNK_SAMPLES), fill time alloc.
    dcpl: Owned,
    /// Empty and unlimited: (0) / (H5S_UNLIMITED).
    empty: Owned,
    /// Scalar, for the attributes.
    scalar: Owned,
    /// Variable-length UTF-8 string.
    text: Owned,
    /// Data transfer with a small type-conversion buffer, for writing a
    /// text dataset (see [`SeriesMaker::write_text_dataset`]).
    text_transfer: Owned,
}

impl std::fmt::Debug for SeriesMaker {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SeriesMaker")
    }
}

impl SeriesMaker {
    pub(super) fn new() -> Result<Self, hdf5::Error> {
        // Initialises the library (and its global type ids) if nothing else
        // has yet.
        hdf5::sync::sync(|| ());
        let _lock = hdf5_sys::LOCK.lock();
        // SAFETY: plain HDF5 C calls on ids created here; every id is owned
        // (closed on drop) as soon as it is created, before the next call
        // can fail.
        unsafe {
            let dcpl = Owned {
                id: check_id(h5p::H5Pcreate(*h5p::H5P_CLS_DATASET_CREATE), "H5Pcreate")?,
                close: h5p::H5Pclose,
            };
            let chunk = [RESULTS_CHUNK_SAMPLES as u64];
            check(
                h5p::H5Pset_chunk(dcpl.id, 1, chunk.as_ptr()),
                "H5Pset_chunk",
            )?;
            check(
                h5p::H5Pset_fill_time(dcpl.id, h5d::H5D_fill_time_t::H5D_FILL_TIME_ALLOC),
                "H5Pset_fill_time",
            )?;
            let (zero, unlimited) = ([0_u64], [h5s::H5S_UNLIMITED]);
            let empty = Owned {
                id: check_id(
                    h5s::H5Screate_simple(1, zero.as_ptr(), unlimited.as_ptr()),
                    "H5Screate_simple",
                )?,
                close: h5s::H5Sclose,
            };
            let scalar = Owned {
                id: check_id(h5s::H5Screate(h5s::H5S_class_t::H5S_SCALAR), "H5Screate")?,
                close: h5s::H5Sclose,
            };
            let text = Owned {
                id: check_id(h5t::H5Tcopy(*h5t::H5T_C_S1), "H5Tcopy")?,
                close: h5t::H5Tclose,
            };
            check(h5t::H5Tset_size(text.id, h5t::H5T_VARIABLE), "H5Tset_size")?;
            check(
                h5t::H5Tset_cset(text.id, h5t::H5T_cset_t::H5T_CSET_UTF8),
                "H5Tset_cset",
            )?;
            let text_transfer = Owned {
                id: check_id(h5p::H5Pcreate(*h5p::H5P_CLS_DATASET_XFER), "H5Pcreate")?,
                close: h5p::H5Pclose,
            };
            check(
                h5p::H5Pset_buffer(
                    text_transfer.id,
                    TEXT_CONVERSION_BUFFER_BYTES,
                    std::ptr::null_mut(),
                    std::ptr::null_mut(),
                ),
                "H5Pset_buffer",
            )?;
            Ok(Self {
                dcpl,
                empty,
                scalar,
                text,
                text_transfer,
            })
        }
    }

    /// Create the empty, extendable series `name` of `T` values in
    /// `group`, with its `units` and `description` attributes.
    pub(super) fn create<T: SeriesValue>(
        &self,
        group: &hdf5::Group,
        name: &str,
        units: &str,
        description: &str,
    ) -> Result<hdf5::Dataset, hdf5::Error> {
        let c_name = c_string(name)?;
        let file_type = T::memory_type();
        let _lock = hdf5_sys::LOCK.lock();
        // SAFETY: the group id is valid while `group` lives; the dataset id
        // is handed to an `hdf5::Dataset` (which closes it) at once.
        let dataset = unsafe {
            let id = check_id(
                h5d::H5Dcreate2(
                    group.id(),
                    c_name.as_ptr(),
                    file_type,
                    self.empty.id,
                    h5p::H5P_DEFAULT,
                    self.dcpl.id,
                    h5p::H5P_DEFAULT,
                ),
                "H5Dcreate2",
            )?;
            hdf5::from_id::<hdf5::Dataset>(id)?
        };
        self.write_text(dataset.id(), "units", units)?;
        self.write_text(dataset.id(), "description", description)?;
        Ok(dataset)
    }

    /// Create the scalar text dataset `name` = `value` in `group`, with its
    /// `description` attribute.
    ///
    /// Written with a conversion buffer of [`TEXT_CONVERSION_BUFFER_BYTES`]:
    /// with the default transfer properties the library allocates and
    /// zeroes two 1 MiB buffers to convert the one string (480 page faults
    /// of the car's run, measured with `perf record -e page-faults`).
    pub(super) fn write_text_dataset(
        &self,
        group: &hdf5::Group,
        name: &str,
        value: &str,
        description: &str,
    ) -> Result<(), hdf5::Error> {
        let (c_name, c_value) = (c_string(name)?, c_string(value)?);
        let _lock = hdf5_sys::LOCK.lock();
        // SAFETY: the group id is valid while `group` lives; the dataset id
        // is owned at once; H5Dwrite reads one `const char*` (a
        // variable-length string's memory form) that outlives the call.
        unsafe {
            let dataset = Owned {
                id: check_id(
                    h5d::H5Dcreate2(
                        group.id(),
                        c_name.as_ptr(),
                        self.text.id,
                        self.scalar.id,
                        h5p::H5P_DEFAULT,
                        h5p::H5P_DEFAULT,
                        h5p::H5P_DEFAULT,
                    ),
                    "H5Dcreate2",
                )?,
                close: h5d::H5Dclose,
            };
            let pointer = c_value.as_ptr();
            check(
                h5d::H5Dwrite(
                    dataset.id,
                    self.text.id,
                    h5s::H5S_ALL,
                    h5s::H5S_ALL,
                    self.text_transfer.id,
                    (&raw const pointer).cast(),
                ),
                "H5Dwrite",
            )?;
            self.write_text(dataset.id, "description", description)
        }
    }

    /// The string attribute `name` = `value` on the object `object`.
    fn write_text(&self, object: hid_t, name: &str, value: &str) -> Result<(), hdf5::Error> {
        let (c_name, c_value) = (c_string(name)?, c_string(value)?);
        let _lock = hdf5_sys::LOCK.lock();
        // SAFETY: `object` is a valid id held by the caller; the attribute
        // id is owned at once; H5Awrite reads one `const char*` (a
        // variable-length string's memory form) that outlives the call.
        unsafe {
            let attr = Owned {
                id: check_id(
                    h5a::H5Acreate2(
                        object,
                        c_name.as_ptr(),
                        self.text.id,
                        self.scalar.id,
                        h5p::H5P_DEFAULT,
                        h5p::H5P_DEFAULT,
                    ),
                    "H5Acreate2",
                )?,
                close: h5a::H5Aclose,
            };
            let pointer = c_value.as_ptr();
            check(
                h5a::H5Awrite(attr.id, self.text.id, (&raw const pointer).cast()),
                "H5Awrite",
            )
        }
    }
}

/// Extend the series `dataset` to `from + values.len()` values and write
/// `values` from `from` on (`from` must be its current length; with no
/// values, it is only resized).
pub(super) fn append<T: SeriesValue>(
    dataset: &hdf5::Dataset,
    from: usize,
    values: &[T],
) -> Result<(), hdf5::Error> {
    let to = [(from + values.len()) as u64];
    let _lock = hdf5_sys::LOCK.lock();
    // SAFETY: the dataset id is valid while `dataset` lives; the
    // dataspaces are owned at once; H5Dwrite reads `values.len()` values
    // of T's memory type from `values`.
    unsafe {
        check(
            h5d::H5Dset_extent(dataset.id(), to.as_ptr()),
            "H5Dset_extent",
        )?;
        if values.is_empty() {
            return Ok(());
        }
        let file_space = Owned {
            id: check_id(h5d::H5Dget_space(dataset.id()), "H5Dget_space")?,
            close: h5s::H5Sclose,
        };
        let (start, count) = ([from as u64], [values.len() as u64]);
        check(
            h5s::H5Sselect_hyperslab(
                file_space.id,
                h5s::H5S_seloper_t::H5S_SELECT_SET,
                start.as_ptr(),
                std::ptr::null(),
                count.as_ptr(),
                std::ptr::null(),
            ),
            "H5Sselect_hyperslab",
        )?;
        let memory_space = Owned {
            id: check_id(
                h5s::H5Screate_simple(1, count.as_ptr(), std::ptr::null()),
                "H5Screate_simple",
            )?,
            close: h5s::H5Sclose,
        };
        check(
            h5d::H5Dwrite(
                dataset.id(),
                T::memory_type(),
                memory_space.id,
                file_space.id,
                h5p::H5P_DEFAULT,
                values.as_ptr().cast(),
            ),
            "H5Dwrite",
        )
    }
}

#[cfg(test)]
mod tests {
    use hdf5::types::VarLenUnicode;

    use super::*;

    #[test]
    fn series_read_back_as_the_crate_writes_them() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("series.h5");
        let file = hdf5::File::create(&path).expect("file");
        let group = file.create_group("g").expect("group");
        let maker = SeriesMaker::new().expect("maker");
        let x = maker
            .create::<f64>(&group, "x_m", "m", "a length, + left")
            .expect("x");
        let flags = maker
            .create::<u8>(&group, "in_contact", "-", "0/1")
            .expect("flags");
        // Two appends, the second across the first chunk's end.
        let first: Vec<f64> = (0..1000).map(|i| f64::from(i) * 0.5).collect();
        let second: Vec<f64> = (0..100).map(|i| -f64::from(i)).collect();
        append(&x, 0, &first).expect("first");
        append(&x, first.len(), &second).expect("second");
        append(&flags, 0, &[0_u8, 1, 1]).expect("flags");
        // A name taken, or one the C API cannot hold, is an error, not a panic.
        assert!(maker.create::<f64>(&group, "x_m", "m", "again").is_err());
        assert!(maker.create::<f64>(&group, "bad\0name", "m", "").is_err());
        drop((x, flags, maker));
        file.close().expect("close");

        let file = hdf5::File::open(&path).expect("reopen");
        let x = file.dataset("g/x_m").expect("x");
        let read: Vec<f64> = x.read_raw().expect("values");
        assert_eq!(read, [first, second].concat());
        assert_eq!(x.chunk(), Some(vec![RESULTS_CHUNK_SAMPLES]));
        assert!(x.is_resizable());
        let units: VarLenUnicode = x.attr("units").unwrap().read_scalar().unwrap();
        let description: VarLenUnicode = x.attr("description").unwrap().read_scalar().unwrap();
        assert_eq!(
            (units.as_str(), description.as_str()),
            ("m", "a length, + left")
        );
        let flags = file.dataset("g/in_contact").expect("flags");
        assert_eq!(flags.read_raw::<u8>().expect("flags"), vec![0, 1, 1]);
    }
}
