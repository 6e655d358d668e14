//! Scalar attributes (numbers and strings) on any HDF5 object.

use std::path::Path;

use hdf5::types::VarLenUnicode;

use super::SchemaError;
use super::columns::to_vlu;

fn err(path: &Path, action: String) -> impl FnOnce(hdf5::Error) -> SchemaError + '_ {
    move |source| SchemaError::Hdf5 {
        path: path.to_path_buf(),
        action,
        source,
    }
}

pub(super) fn write_f64(
    path: &Path,
    loc: &hdf5::Location,
    name: &str,
    v: f64,
) -> Result<(), SchemaError> {
    loc.new_attr::<f64>()
        .shape(())
        .create(name)
        .and_then(|a| a.write_scalar(&v))
        .map_err(err(path, format!("writing attribute {name}")))
}

pub(super) fn write_u32(
    path: &Path,
    loc: &hdf5::Location,
    name: &str,
    v: u32,
) -> Result<(), SchemaError> {
    loc.new_attr::<u32>()
        .shape(())
        .create(name)
        .and_then(|a| a.write_scalar(&v))
        .map_err(err(path, format!("writing attribute {name}")))
}

pub(super) fn write_str(
    path: &Path,
    loc: &hdf5::Location,
    name: &str,
    v: &str,
) -> Result<(), SchemaError> {
    loc.new_attr::<VarLenUnicode>()
        .shape(())
        .create(name)
        .and_then(|a| a.write_scalar(&to_vlu(v)))
        .map_err(err(path, format!("writing attribute {name}")))
}

/// An attribute of any HDF5 type; `what` names the object for messages.
pub(super) fn read<T: hdf5::H5Type>(
    path: &Path,
    loc: &hdf5::Location,
    what: &str,
    name: &str,
) -> Result<T, SchemaError> {
    loc.attr(name)
        .map_err(|_| SchemaError::Missing {
            path: path.to_path_buf(),
            what: format!("attribute '{name}' of {what}"),
        })?
        .read_scalar()
        .map_err(err(path, format!("reading attribute {name} of {what}")))
}

pub(super) fn read_f64(
    path: &Path,
    loc: &hdf5::Location,
    what: &str,
    name: &str,
) -> Result<f64, SchemaError> {
    read(path, loc, what, name)
}

pub(super) fn read_str(
    path: &Path,
    loc: &hdf5::Location,
    what: &str,
    name: &str,
) -> Result<String, SchemaError> {
    read::<VarLenUnicode>(path, loc, what, name).map(|v| v.as_str().to_string())
}
