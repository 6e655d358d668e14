//! `railsim.build_track` and `railsim.Track`: `track-preproc build` and
//! `sim probe` from Python.

use std::path::PathBuf;

use clap::Parser;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use runtime::geometry::track::{Side, TrackTables};

use crate::arrays::floats;
use crate::errors::{OrValueError, value_error};

/// The per-rail track tables of a table file, held in memory: probe them at
/// any centreline distance with `probe`.
#[pyclass(module = "railsim", frozen)]
pub struct Track {
    tables: TrackTables,
    path: PathBuf,
    summary: Option<serde_json::Value>,
}

#[pymethods]
impl Track {
    /// Load the track tables of a table file written by `track-preproc
    /// build` or `railsim.build_track`.
    #[staticmethod]
    fn open(py: Python<'_>, path: PathBuf) -> PyResult<Track> {
        let tables = py
            .detach(|| railsim::cli::probe::load_tables(&path))
            .or_value_error()?;
        Ok(Track {
            tables,
            path,
            summary: None,
        })
    }

    /// The table file (str).
    #[getter]
    fn path(&self) -> String {
        self.path.display().to_string()
    }

    /// Centreline length (m).
    #[getter]
    fn length_m(&self) -> f64 {
        self.tables.centerline.length_m()
    }

    /// Range of centreline distance s of the tables (m), (first, last).
    #[getter]
    fn s_range_m(&self) -> (f64, f64) {
        self.tables.centerline.range_m()
    }

    /// Table step Δs (m).
    #[getter]
    fn step_m(&self) -> f64 {
        self.tables.centerline.step_m()
    }

    /// The build's summary (dict, as `track-preproc build --json` prints it)
    /// when this track was built in this session, else None.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match &self.summary {
            Some(s) => crate::arrays::to_python(py, s),
            None => Ok(py.None().into_bound(py)),
        }
    }

    /// Both rails and the centreline at centreline distance(s) `s_m` (m), a
    /// float or an array, interpolated linearly in the tables as a
    /// simulation does (`sim probe`). Keys (n = number of distances):
    ///
    /// - `s_m` (n,): the distances probed (m);
    /// - `position_m` (n, 3): centreline point (m);
    /// - `t`, `n`, `b` (n, 3): track frame (forward, left, up; unit);
    /// - `cant_rad` (n,): cant, + left rail up (rad);
    /// - `curvature_1_m` (n,): Frenet curvature of the centreline (1/m);
    /// - `left_position_m`, `right_position_m` (n, 3): rail profile origins (m);
    /// - `left_t`, `left_n`, `left_b`, `right_…` (n, 3): rail frames;
    /// - `left_l_m`, `right_l_m` (n,): each rail's own arc length (m).
    ///
    /// A distance outside the tables raises ValueError naming it.
    fn probe<'py>(&self, py: Python<'py>, s_m: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        let s = floats(s_m, "s_m")?;
        let probed = py
            .detach(|| probe_all(&self.tables, &s))
            .map_err(value_error)?;
        let out = PyDict::new(py);
        out.set_item("s_m", PyArray1::from_vec(py, s))?;
        for (name, v) in probed.vectors {
            out.set_item(name, rows3(py, v)?)?;
        }
        for (name, v) in probed.scalars {
            out.set_item(name, v.into_pyarray(py))?;
        }
        Ok(out)
    }

    fn __repr__(&self) -> String {
        let (a, b) = self.tables.centerline.range_m();
        format!(
            "railsim.Track('{}', s = {a} … {b} m, step {} m)",
            self.path.display(),
            self.tables.centerline.step_m()
        )
    }
}

/// Probed values by key: (n, 3) vectors and (n,) scalars.
struct Probed {
    vectors: Vec<(&'static str, Vec<[f64; 3]>)>,
    scalars: Vec<(&'static str, Vec<f64>)>,
}

fn probe_all(tables: &TrackTables, s: &[f64]) -> anyhow::Result<Probed> {
    use anyhow::Context;
    const VECTORS: [&str; 12] = [
        "position_m",
        "t",
        "n",
        "b",
        "left_position_m",
        "left_t",
        "left_n",
        "left_b",
        "right_position_m",
        "right_t",
        "right_n",
        "right_b",
    ];
    const SCALARS: [&str; 4] = ["cant_rad", "curvature_1_m", "left_l_m", "right_l_m"];
    let mut vectors: Vec<Vec<[f64; 3]>> = vec![Vec::with_capacity(s.len()); VECTORS.len()];
    let mut scalars: Vec<Vec<f64>> = vec![Vec::with_capacity(s.len()); SCALARS.len()];
    for &s_m in s {
        let at = || format!("probing the track at s = {s_m} m");
        let c = tables.centerline.at(s_m).with_context(at)?;
        let mut v: Vec<[f64; 3]> = vec![
            c.position.into(),
            c.frame.t.into(),
            c.frame.n.into(),
            c.frame.b.into(),
        ];
        let mut l = Vec::with_capacity(2);
        for side in Side::BOTH {
            let p = tables.rail_at_s(side, s_m).with_context(at)?;
            v.extend::<[[f64; 3]; 4]>([
                p.position.into(),
                p.frame.t.into(),
                p.frame.n.into(),
                p.frame.b.into(),
            ]);
            l.push(p.l_m);
        }
        for (k, x) in v.into_iter().enumerate() {
            vectors[k].push(x);
        }
        for (k, x) in [c.cant_rad, c.curvature_1_m, l[0], l[1]]
            .into_iter()
            .enumerate()
        {
            scalars[k].push(x);
        }
    }
    Ok(Probed {
        vectors: VECTORS.into_iter().zip(vectors).collect(),
        scalars: SCALARS.into_iter().zip(scalars).collect(),
    })
}

fn rows3(py: Python<'_>, v: Vec<[f64; 3]>) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let n = v.len();
    let flat: Vec<f64> = v.into_iter().flatten().collect();
    let a = Array2::from_shape_vec((n, 3), flat)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// Build a track's per-rail tables into the HDF5 file `out` (written all or
/// nothing), as `track-preproc build` does, and return the track.
///
/// - `centerline`: CSV of control points x, y, z (m) and optionally cant
///   (rad) or cant_mm; or `design`: a TOML file of design elements
///   (straights, arcs, transitions, cant ramps, grades);
/// - `cant`: CSV s, cant (rad) or cant_mm (with `centerline` only);
/// - `irregularities`: CSV s, align_left, align_right, level_left,
///   level_right (m), or s, alignment, gauge, level, cross_level; `_mm`
///   suffix allowed;
/// - `scheme`: spline of the centreline and rails: cubic, cubic-natural,
///   akima, pchip;
/// - `step_m`: table step Δs (m);
/// - `gauge_m`: track gauge (m); `rail_inclination`: "1:40", "1:20", "0";
/// - `rail` (and `wheel`): profile files; with both, the contact lookup
///   table is built into the same file.
///
/// Errors (a missing file, a bad row, an output that would replace an
/// input) raise ValueError with the CLI's message.
#[pyfunction]
#[pyo3(signature = (*, centerline=None, design=None, cant=None, irregularities=None,
    scheme="cubic", step_m=0.1, out, gauge_m=None, rail_inclination=None, rail=None, wheel=None))]
#[allow(clippy::too_many_arguments)]
pub fn build_track(
    py: Python<'_>,
    centerline: Option<PathBuf>,
    design: Option<PathBuf>,
    cant: Option<PathBuf>,
    irregularities: Option<PathBuf>,
    scheme: &str,
    step_m: f64,
    out: PathBuf,
    gauge_m: Option<f64>,
    rail_inclination: Option<String>,
    rail: Option<PathBuf>,
    wheel: Option<PathBuf>,
) -> PyResult<Track> {
    let mut args: Vec<String> = vec!["track-preproc".into(), "build".into()];
    let mut path = |flag: &str, p: &Option<PathBuf>| {
        if let Some(p) = p {
            args.push(flag.into());
            args.push(p.display().to_string());
        }
    };
    path("--centerline", &centerline);
    path("--design", &design);
    path("--cant", &cant);
    path("--irregularities", &irregularities);
    path("--rail", &rail);
    path("--wheel", &wheel);
    args.extend(["--scheme".into(), scheme.into()]);
    args.extend(["--step".into(), step_m.to_string()]);
    if let Some(g) = gauge_m {
        args.extend(["--gauge".into(), g.to_string()]);
    }
    if let Some(r) = rail_inclination {
        args.extend(["--rail-inclination".into(), r]);
    }
    args.extend(["--output".into(), out.display().to_string()]);
    let cli = preproc::cli::Cli::try_parse_from(&args)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.render().to_string()))?;
    let preproc::cli::Command::Build(build) = cli.command else {
        unreachable!("the arguments start with `build`")
    };
    let command_line = format!("railsim.build_track: {}", args.join(" "));
    let warnings = std::sync::Mutex::new(Vec::<String>::new());
    let (tables, summary) = py
        .detach(|| -> anyhow::Result<(TrackTables, serde_json::Value)> {
            let summary =
                preproc::cli::build(&build, command_line, &preproc::progress::NoProgress, &|w| {
                    warnings.lock().map_or((), |mut v| v.extend_from_slice(w))
                })?;
            Ok((
                railsim::cli::probe::load_tables(&out)?,
                serde_json::to_value(&summary)?,
            ))
        })
        .or_value_error()?;
    crate::errors::warn_all(py, &warnings.into_inner().unwrap_or_default())?;
    Ok(Track {
        tables,
        path: out,
        summary: Some(summary),
    })
}
