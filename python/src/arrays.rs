//! numpy in and out: a float or an array of floats as a `Vec<f64>`, and
//! rows of serialisable records as one numpy array per column.

use numpy::{IntoPyArray, PyReadonlyArrayDyn};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// A float, a sequence of floats or a numpy array of any shape, flattened
/// (in C order), as floats; `name` names it in the error.
pub fn floats(value: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    if let Ok(x) = value.extract::<f64>() {
        return Ok(vec![x]);
    }
    let np = value.py().import("numpy")?;
    let array = np
        .getattr("asarray")?
        .call1((value, "float64"))
        .map_err(|e| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "{name}: expected a float or an array of floats ({e})"
            ))
        })?;
    let array: PyReadonlyArrayDyn<'_, f64> = array.extract()?;
    Ok(array.as_array().iter().copied().collect())
}

/// `Some(floats)` unless `value` is `None`.
pub fn optional_floats(value: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<Vec<f64>>> {
    match value {
        Some(v) if !v.is_none() => floats(v, name).map(Some),
        _ => Ok(None),
    }
}

/// Broadcast per-pose inputs to a common length `n`: a length-1 input is
/// repeated; another length that is not `n` is refused naming the input.
pub fn broadcast(name: &str, values: Vec<f64>, n: usize) -> PyResult<Vec<f64>> {
    match values.len() {
        l if l == n => Ok(values),
        1 => Ok(vec![values[0]; n]),
        l => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "{name} has {l} values, the other per-pose inputs {n}: give one value or {n}"
        ))),
    }
}

/// The records as a dict of numpy arrays, one per name of `columns`, in that
/// order: numbers as float64 (a missing value, JSON null, as NaN), whole
/// numbers of integer columns as int64, strings as numpy str arrays.
pub fn columns_dict<'py, R: serde::Serialize>(
    py: Python<'py>,
    columns: &[&str],
    integer_columns: &[&str],
    rows: &[R],
) -> PyResult<Bound<'py, PyDict>> {
    let values: Vec<serde_json::Map<String, serde_json::Value>> = rows
        .iter()
        .map(|r| match serde_json::to_value(r) {
            Ok(serde_json::Value::Object(m)) => Ok(m),
            _ => Err(pyo3::exceptions::PyRuntimeError::new_err(
                "internal: a row is not a record",
            )),
        })
        .collect::<PyResult<_>>()?;
    let out = PyDict::new(py);
    let np = py.import("numpy")?;
    for &name in columns {
        let cells = values
            .iter()
            .map(|m| m.get(name).unwrap_or(&serde_json::Value::Null));
        if integer_columns.contains(&name) {
            let v: Vec<i64> = cells.map(|c| c.as_i64().unwrap_or(-1)).collect();
            out.set_item(name, v.into_pyarray(py))?;
        } else if values
            .first()
            .and_then(|m| m.get(name))
            .is_some_and(serde_json::Value::is_string)
        {
            let v: Vec<String> = cells
                .map(|c| c.as_str().unwrap_or_default().to_string())
                .collect();
            let list = PyList::new(py, v)?;
            out.set_item(name, np.getattr("array")?.call1((list, "U"))?)?;
        } else {
            let v: Vec<f64> = cells.map(|c| c.as_f64().unwrap_or(f64::NAN)).collect();
            out.set_item(name, v.into_pyarray(py))?;
        }
    }
    Ok(out)
}

/// A serialisable value as the Python object `json.loads` would give.
pub fn to_python<'py, T: serde::Serialize>(
    py: Python<'py>,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("internal: {e}")))?;
    py.import("json")?.getattr("loads")?.call1((text,))
}
