//! `railsim.Results`: a run's time series by their results-file paths, in
//! memory (from `railsim.run`) or read from any results file `sim run`
//! wrote.

use std::path::PathBuf;

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use runtime::results::{RunResults, SeriesValues};

use crate::errors::{OrValueError, value_error};

/// The time series of a run: `results["wheelset_0/lateral_m"]` is a numpy
/// array, one value per sample, named as in the results file (`keys()`
/// lists them; docs/reference/04-table-files.md). Units are in the names
/// (m, rad, N, …); signs: track frame forward, left, up; forces on the
/// wheel; a zone's values are NaN where it is not in contact.
#[pyclass(module = "railsim", frozen)]
pub struct Results {
    pub(crate) results: RunResults,
    /// The run summary (`sim run --json`), for a run of this session.
    pub(crate) summary: Option<serde_json::Value>,
    /// The inputs of the run, which `save` may not replace.
    pub(crate) inputs: Vec<PathBuf>,
}

impl Results {
    fn series(&self, name: &str) -> Option<SeriesValues<'_>> {
        let name = name.trim_start_matches('/');
        self.results
            .named_series()
            .into_iter()
            .find(|s| s.path == name)
            .map(|s| s.values)
    }
}

#[pymethods]
impl Results {
    /// Read a results file written by `sim run`, a study, or `Results.save`.
    #[staticmethod]
    fn open(py: Python<'_>, path: PathBuf) -> PyResult<Results> {
        let results = py
            .detach(|| {
                use anyhow::Context;
                runtime::io::schema::read_results(&path)
                    .with_context(|| format!("reading {}", path.display()))
            })
            .or_value_error()?;
        Ok(Results {
            results,
            summary: None,
            inputs: Vec::new(),
        })
    }

    /// The series `name` (e.g. "wheelset_0/lateral_m",
    /// "wheelset_0/left/flange/normal_n", "bodies/frame/yaw_rad") as a new
    /// numpy array: float64, or uint8 for flags.
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        match self.series(name) {
            Some(SeriesValues::F64(v)) => Ok(v.to_vec().into_pyarray(py).into_any()),
            Some(SeriesValues::Flags(v)) => Ok(v.to_vec().into_pyarray(py).into_any()),
            None => Err(pyo3::exceptions::PyKeyError::new_err(format!(
                "'{name}' is not a series of these results (keys() lists them, e.g. 'wheelset_0/lateral_m')"
            ))),
        }
    }

    fn __contains__(&self, name: &str) -> bool {
        self.series(name).is_some()
    }

    /// The paths of every series, in file order.
    fn keys(&self) -> Vec<String> {
        self.results
            .named_series()
            .into_iter()
            .map(|s| s.path)
            .collect()
    }

    /// The unit of series `name` ("m", "rad", "N", "-", …).
    fn units(&self, name: &str) -> PyResult<&'static str> {
        let name = name.trim_start_matches('/');
        self.results
            .named_series()
            .into_iter()
            .find(|s| s.path == name)
            .map(|s| s.dataset.units)
            .ok_or_else(|| pyo3::exceptions::PyKeyError::new_err(name.to_string()))
    }

    /// Number of samples.
    fn __len__(&self) -> usize {
        self.results.time_s.len()
    }

    /// Time of every sample since the start of the run (s).
    #[getter]
    fn time_s<'py>(&self, py: Python<'py>) -> Bound<'py, numpy::PyArray1<f64>> {
        self.results.time_s.clone().into_pyarray(py)
    }

    /// The wheelsets' names, in vehicle order (wheelset_0 first).
    #[getter]
    fn wheelsets(&self) -> Vec<String> {
        self.results
            .wheelsets
            .iter()
            .map(|w| w.name.clone())
            .collect()
    }

    /// The figures `sim run` prints (dict, as `sim run --json`), for a run
    /// of this session; None for a file opened with `Results.open`.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match &self.summary {
            Some(s) => crate::arrays::to_python(py, s),
            None => Ok(py.None().into_bound(py)),
        }
    }

    /// The run's attributes (dict): speed_m_s, creep_law, status, …
    #[getter]
    fn attributes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in &self.results.attributes {
            use runtime::results::AttrValue;
            match v {
                AttrValue::Text(t) => d.set_item(k, t)?,
                AttrValue::Float(x) => d.set_item(k, x)?,
                AttrValue::Int(i) => d.set_item(k, i)?,
                AttrValue::Bool(b) => d.set_item(k, b)?,
            }
        }
        Ok(d)
    }

    /// The scene as run (TOML text, overrides applied).
    #[getter]
    fn scene_toml(&self) -> &str {
        &self.results.scene_toml
    }

    /// Write the results file (HDF5, the same layout as `sim
    /// run` writes), all or nothing; a path that is one of the run's
    /// inputs is refused.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| -> anyhow::Result<()> {
            use anyhow::Context;
            runtime::io::check_outputs(
                &self.inputs,
                &[runtime::io::Output {
                    path: path.clone(),
                    kind: runtime::io::OutputKind::File,
                    role: "the results file",
                }],
            )?;
            runtime::io::schema::write_results(&path, &self.results)
                .with_context(|| format!("writing the results {}", path.display()))
        })
        .map_err(value_error)
    }

    /// An xarray.Dataset with every series as a variable on the
    /// `time_s` coordinate (its unit in the variable's `units` attribute);
    /// needs xarray installed.
    fn to_xarray<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let xr = py.import("xarray").map_err(|_| {
            pyo3::exceptions::PyImportError::new_err("to_xarray needs xarray: pip install xarray")
        })?;
        let vars = PyDict::new(py);
        for s in self.results.named_series().into_iter().skip(1) {
            let values: Bound<'py, PyAny> = match s.values {
                SeriesValues::F64(v) => v.to_vec().into_pyarray(py).into_any(),
                SeriesValues::Flags(v) => v.to_vec().into_pyarray(py).into_any(),
            };
            let attrs = PyDict::new(py);
            attrs.set_item("units", s.dataset.units)?;
            attrs.set_item("description", s.dataset.description)?;
            let dims = PyList::new(py, ["time_s"])?;
            vars.set_item(s.path, (dims, values, attrs))?;
        }
        let coords = PyDict::new(py);
        coords.set_item("time_s", self.results.time_s.clone().into_pyarray(py))?;
        let attrs = self.attributes(py)?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("coords", coords)?;
        kwargs.set_item("attrs", attrs)?;
        xr.getattr("Dataset")?.call((vars,), Some(&kwargs))
    }

    fn __repr__(&self) -> String {
        let t = self.results.time_s.last().copied().unwrap_or(0.0);
        format!(
            "railsim.Results({} samples, t = 0 … {t:.3} s, wheelsets {:?})",
            self.results.time_s.len(),
            self.wheelsets()
        )
    }
}
