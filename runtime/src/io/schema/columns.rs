//! Named-column 2-D datasets: write with `columns`/`units` attributes, read
//! back by column name.

use std::path::Path;

use hdf5::types::VarLenUnicode;
use ndarray::Array2;

use super::SchemaError;

fn hdf5_err(path: &Path, action: String) -> impl FnOnce(hdf5::Error) -> SchemaError + '_ {
    move |source| SchemaError::Hdf5 {
        path: path.to_path_buf(),
        action,
        source,
    }
}

pub(super) fn to_vlu(s: &str) -> VarLenUnicode {
    // VarLenUnicode refuses interior NULs only; strip them rather than fail.
    s.replace('\0', "")
        .parse()
        .unwrap_or_else(|_| VarLenUnicode::new())
}

/// Rows written per HDF5 call: a small buffer reused for the whole table,
/// so writing a 10⁶-row table does not allocate a second copy of it.
const WRITE_CHUNK_ROWS: usize = 1 << 14;

/// Write `rows` as the 2-D dataset `group/name` with `columns`/`units`
/// attributes; `to_columns` gives the values of one row (as many as there
/// are columns).
pub(super) fn write_table<R, V: AsRef<[f64]>>(
    path: &Path,
    group: &hdf5::Group,
    name: &str,
    columns: &[&str],
    units: &[&str],
    rows: &[R],
    to_columns: impl Fn(&R) -> V,
) -> Result<(), SchemaError> {
    let k = columns.len();
    let what = format!("writing {}/{name}", group.name());
    let ds = group
        .new_dataset::<f64>()
        .shape((rows.len(), k))
        .create(name)
        .map_err(hdf5_err(path, what.clone()))?;
    let mut buf: Vec<f64> = Vec::with_capacity(WRITE_CHUNK_ROWS.min(rows.len()) * k);
    for (c, chunk) in rows.chunks(WRITE_CHUNK_ROWS).enumerate() {
        buf.clear();
        for r in chunk {
            let v = to_columns(r);
            debug_assert_eq!(v.as_ref().len(), k);
            buf.extend_from_slice(v.as_ref());
        }
        let start = c * WRITE_CHUNK_ROWS;
        let view = ndarray::ArrayView2::from_shape((chunk.len(), k), &buf).map_err(|e| {
            SchemaError::Invalid {
                path: path.to_path_buf(),
                object: what.clone(),
                rule: e.to_string(),
            }
        })?;
        ds.write_slice(view, ndarray::s![start..start + chunk.len(), ..])
            .map_err(hdf5_err(path, what.clone()))?;
    }
    let cols: Vec<VarLenUnicode> = columns.iter().map(|c| to_vlu(c)).collect();
    let unit: Vec<VarLenUnicode> = units.iter().map(|c| to_vlu(c)).collect();
    ds.new_attr_builder()
        .with_data(&cols)
        .create("columns")
        .map_err(hdf5_err(path, what.clone()))?;
    ds.new_attr_builder()
        .with_data(&unit)
        .create("units")
        .map_err(hdf5_err(path, what))?;
    Ok(())
}

/// Read `dataset` and return the named columns, each as a vector (in the
/// order of `wanted`).
pub(super) fn read_columns(
    path: &Path,
    file: &hdf5::File,
    dataset: &str,
    wanted: &[&str],
) -> Result<Vec<Vec<f64>>, SchemaError> {
    let (names, data) = open_named(path, file, dataset)?;
    let invalid = |rule: String| SchemaError::Invalid {
        path: path.to_path_buf(),
        object: dataset.to_string(),
        rule,
    };
    wanted
        .iter()
        .map(|want| {
            let c = names.iter().position(|n| n == want).ok_or_else(|| {
                invalid(format!(
                    "no column named '{want}' (has: {})",
                    names.join(" ")
                ))
            })?;
            Ok(data.column(c).to_vec())
        })
        .collect()
}

/// The column names and the data of a named-column dataset.
fn open_named(
    path: &Path,
    file: &hdf5::File,
    dataset: &str,
) -> Result<(Vec<String>, Array2<f64>), SchemaError> {
    let ds = file.dataset(dataset).map_err(|_| SchemaError::Missing {
        path: path.to_path_buf(),
        what: format!("dataset {dataset}"),
    })?;
    let names: Vec<VarLenUnicode> = ds
        .attr("columns")
        .map_err(|_| SchemaError::Missing {
            path: path.to_path_buf(),
            what: format!("attribute 'columns' of {dataset}"),
        })?
        .read_raw()
        .map_err(hdf5_err(path, format!("reading the columns of {dataset}")))?;
    let names: Vec<String> = names.iter().map(|n| n.as_str().to_string()).collect();
    let shape = ds.shape();
    if shape.len() != 2 || shape[1] != names.len() {
        return Err(SchemaError::Invalid {
            path: path.to_path_buf(),
            object: dataset.to_string(),
            rule: format!(
                "shape {shape:?} does not match its {} named columns",
                names.len()
            ),
        });
    }
    let data: Array2<f64> = ds
        .read_2d()
        .map_err(hdf5_err(path, format!("reading {dataset}")))?;
    Ok((names, data))
}

/// Read `dataset` and return, for each row, the values of the wanted
/// columns in the order of `wanted`.
pub(super) fn read_table<const N: usize>(
    path: &Path,
    file: &hdf5::File,
    dataset: &str,
    wanted: &[&str; N],
) -> Result<Vec<[f64; N]>, SchemaError> {
    let (names, data) = open_named(path, file, dataset)?;
    let mut index = [0usize; N];
    for (slot, want) in index.iter_mut().zip(wanted) {
        *slot = names
            .iter()
            .position(|n| n == want)
            .ok_or_else(|| SchemaError::Invalid {
                path: path.to_path_buf(),
                object: dataset.to_string(),
                rule: format!("no column named '{want}' (has: {})", names.join(" ")),
            })?;
    }
    Ok(data
        .rows()
        .into_iter()
        .map(|row| {
            let mut out = [0.0; N];
            for (o, &c) in out.iter_mut().zip(&index) {
                *o = row[c];
            }
            out
        })
        .collect())
}
