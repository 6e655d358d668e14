//! Scalar attributes (numbers and strings) on any HDF5 object.

use std::path::Path;

use hdf5::types::VarLenUnicode;

use super::SchemaError;
use super::columns::to_vlu;
use crate::results::AttrValue;

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

pub(super) fn write_i64(
    path: &Path,
    loc: &hdf5::Location,
    name: &str,
    v: i64,
) -> Result<(), SchemaError> {
    loc.new_attr::<i64>()
        .shape(())
        .create(name)
        .and_then(|a| a.write_scalar(&v))
        .map_err(err(path, format!("writing attribute {name}")))
}

/// A run attribute: text as a UTF-8 string, a float as f64, an integer as
/// i64, a flag as HDF5's boolean enum (h5py reads a numpy bool).
pub(super) fn write_value(
    path: &Path,
    loc: &hdf5::Location,
    name: &str,
    v: &AttrValue,
) -> Result<(), SchemaError> {
    match v {
        AttrValue::Text(s) => write_str(path, loc, name, s),
        AttrValue::Float(x) => write_f64(path, loc, name, *x),
        AttrValue::Int(i) => write_i64(path, loc, name, *i),
        AttrValue::Bool(b) => loc
            .new_attr::<bool>()
            .shape(())
            .create(name)
            .and_then(|a| a.write_scalar(b))
            .map_err(err(path, format!("writing attribute {name}"))),
    }
}

/// A run attribute of any scalar type: integers (signed or not) as
/// [`AttrValue::Int`], floats as [`AttrValue::Float`], booleans as
/// [`AttrValue::Bool`], anything else read as a string (the files written
/// before the values were typed hold only strings: they stay text).
pub(super) fn read_value(
    path: &Path,
    loc: &hdf5::Location,
    what: &str,
    name: &str,
) -> Result<AttrValue, SchemaError> {
    use hdf5::types::TypeDescriptor as T;
    let attr = loc.attr(name).map_err(|_| SchemaError::Missing {
        path: path.to_path_buf(),
        what: format!("attribute '{name}' of {what}"),
    })?;
    let descriptor = attr.dtype().and_then(|d| d.to_descriptor()).map_err(err(
        path,
        format!("reading the type of attribute {name} of {what}"),
    ))?;
    let action = || format!("reading attribute {name} of {what}");
    Ok(match descriptor {
        T::Integer(_) | T::Unsigned(_) => {
            AttrValue::Int(attr.read_scalar::<i64>().map_err(err(path, action()))?)
        }
        T::Float(_) => AttrValue::Float(attr.read_scalar::<f64>().map_err(err(path, action()))?),
        T::Boolean => AttrValue::Bool(attr.read_scalar::<bool>().map_err(err(path, action()))?),
        _ => AttrValue::Text(read_str(path, loc, what, name)?),
    })
}
