//! The study table file (`sim sweep`): one row per variant, one 1-D
//! dataset per column (numbers as f64, text as UTF-8 strings), the column
//! order in the root attribute `columns`, written all or nothing
//! (docs/reference/04-table-files.md §4.6).

use std::path::Path;

use hdf5::types::VarLenUnicode;

use super::SchemaError;
use super::attrs;
use super::results_file::hdf5_err;
use crate::io::AtomicFile;

/// One column of a study table.
#[derive(Debug, Clone, PartialEq)]
pub enum StudyColumn {
    /// Numbers; NaN where a row has no value.
    Numbers(Vec<f64>),
    /// Text (status, messages, non-numeric parameters).
    Text(Vec<String>),
}

impl StudyColumn {
    fn len(&self) -> usize {
        match self {
            StudyColumn::Numbers(v) => v.len(),
            StudyColumn::Text(v) => v.len(),
        }
    }
}

/// Write the table `columns` (name, values; every column as long) to
/// `path` with the root attributes `attributes` (name, text), atomically.
pub fn write_study_table(
    path: &Path,
    attributes: &[(&str, &str)],
    columns: &[(String, StudyColumn)],
) -> Result<(), SchemaError> {
    let rows = columns.first().map_or(0, |(_, c)| c.len());
    if let Some((name, c)) = columns.iter().find(|(_, c)| c.len() != rows) {
        return Err(SchemaError::Invalid {
            path: path.to_path_buf(),
            object: format!("study table column '{name}'"),
            rule: format!("has {} rows, the first column {rows}", c.len()),
        });
    }
    let atomic = AtomicFile::new(path);
    let file = hdf5::File::create(atomic.temp_path()).map_err(|source| SchemaError::Create {
        path: path.to_path_buf(),
        source,
    })?;
    let err = |action: String| hdf5_err(path, action);
    attrs::write_str(path, &file, "schema", "railsim-study-table")?;
    let names: Vec<&str> = columns.iter().map(|(n, _)| n.as_str()).collect();
    attrs::write_str(path, &file, "columns", &names.join(","))?;
    for (name, value) in attributes {
        attrs::write_str(path, &file, name, value)?;
    }
    for (name, c) in columns {
        let what = format!("writing column {name}");
        match c {
            StudyColumn::Numbers(v) => {
                file.new_dataset_builder()
                    .with_data(v.as_slice())
                    .create(name.as_str())
                    .map_err(err(what))?;
            }
            StudyColumn::Text(v) => {
                let v: Vec<VarLenUnicode> = v.iter().map(|s| super::columns::to_vlu(s)).collect();
                file.new_dataset_builder()
                    .with_data(v.as_slice())
                    .create(name.as_str())
                    .map_err(err(what))?;
            }
        }
    }
    file.close().map_err(err("closing".into()))?;
    atomic.commit().map_err(|source| SchemaError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Read a study table: its columns in file order.
pub fn read_study_table(path: &Path) -> Result<Vec<(String, StudyColumn)>, SchemaError> {
    let file = hdf5::File::open(path).map_err(|source| SchemaError::Open {
        path: path.to_path_buf(),
        source,
    })?;
    let err = |action: String| hdf5_err(path, action);
    let names = attrs::read_str(path, &file, "/", "columns")?;
    let mut out = Vec::new();
    for name in names.split(',').filter(|n| !n.is_empty()) {
        let ds = file.dataset(name).map_err(err(format!("opening {name}")))?;
        let column = if ds
            .dtype()
            .map_err(err(format!("type of {name}")))?
            .is::<f64>()
        {
            StudyColumn::Numbers(
                ds.read_raw::<f64>()
                    .map_err(err(format!("reading {name}")))?,
            )
        } else {
            let v: Vec<VarLenUnicode> = ds.read_raw().map_err(err(format!("reading {name}")))?;
            StudyColumn::Text(v.iter().map(|s| s.as_str().to_string()).collect())
        };
        out.push((name.to_string(), column));
    }
    Ok(out)
}
