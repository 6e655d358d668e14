//! `railsim.run` and `railsim.critical_speed`: the work runs on a worker
//! thread with the GIL released while the calling thread watches for
//! Ctrl-C (Python's signal handlers run only there) and draws the progress.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use clap::Parser;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use railsim::config::scene::LoadedScene;

use crate::errors::{OrValueError, RunFailed, message, value_error};
use crate::results::Results;

/// How often the calling thread looks for Ctrl-C and redraws progress.
const WATCH_PERIOD: Duration = Duration::from_millis(100);

/// Runs `work` on a worker thread with the GIL released; every
/// [`WATCH_PERIOD`] the calling thread runs Python's signal handlers (a
/// Ctrl-C sets `stop`, which the work polls, and its KeyboardInterrupt is
/// returned beside the result) and calls `tick`.
fn watched<R: Send>(
    py: Python<'_>,
    stop: &Arc<AtomicBool>,
    work: impl FnOnce() -> R + Send,
    tick: &mut dyn FnMut(Python<'_>) -> PyResult<()>,
) -> PyResult<(R, Option<PyErr>)> {
    let mut interrupt = None;
    let mut tick_error = None;
    // The calling thread waits for the worker's result with the GIL
    // released, waking every WATCH_PERIOD; the worker never touches Python.
    let result = std::thread::scope(|s| {
        let (done, finished) = std::sync::mpsc::sync_channel(1);
        // A Mutex makes the receiver shareable with the GIL-free closure.
        let finished = Mutex::new(finished);
        let worker = s.spawn(move || {
            // The receiver lives until the worker is joined below.
            let _ = done.send(work());
        });
        loop {
            let waited = py.detach(|| match finished.lock() {
                Ok(f) => f.recv_timeout(WATCH_PERIOD),
                Err(_) => Err(std::sync::mpsc::RecvTimeoutError::Disconnected),
            });
            match waited {
                Ok(r) => {
                    let _ = worker.join();
                    return Some(r);
                }
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => {
                    // The worker ended without a result: it panicked.
                    let _ = worker.join();
                    return None;
                }
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
            }
            if interrupt.is_none()
                && let Err(e) = py.check_signals()
            {
                stop.store(true, Ordering::Relaxed);
                interrupt = Some(e);
            }
            if tick_error.is_none()
                && let Err(e) = tick(py)
            {
                tick_error = Some(e);
            }
        }
    });
    if let Some(e) = tick_error {
        return Err(e);
    }
    match result {
        Some(r) => Ok((r, interrupt)),
        None => Err(pyo3::exceptions::PyRuntimeError::new_err(
            "internal error: the worker thread panicked",
        )),
    }
}

/// A Python value as a TOML value (through JSON: numbers, strings, bools,
/// lists, dicts).
fn toml_value(value: &Bound<'_, PyAny>, what: &str) -> PyResult<toml::Value> {
    let json: String = value
        .py()
        .import("json")?
        .getattr("dumps")?
        .call1((value,))
        .and_then(|t| t.extract())
        .map_err(|e| {
            pyo3::exceptions::PyValueError::new_err(format!(
                "{what}: not a number, string, bool, list or dict ({e})"
            ))
        })?;
    let v: serde_json::Value = serde_json::from_str(&json)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("{what}: {e}")))?;
    serde_json::from_value::<toml::Value>(v).map_err(|e| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "{what}: cannot be written in TOML ({e}; None is allowed only as a `set` value)"
        ))
    })
}

/// The `set` dict as the CLI's `--set key=value` overrides; None removes
/// an entry (`key=`).
fn overrides(set: Option<&Bound<'_, PyDict>>) -> PyResult<Vec<String>> {
    let Some(set) = set else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (k, v) in set.iter() {
        let key: String = k.extract().map_err(|_| {
            pyo3::exceptions::PyValueError::new_err(
                "set: keys are scene keys such as 'initial.speed_m_s'",
            )
        })?;
        if v.is_none() {
            out.push(format!("{key}="));
        } else {
            let value = toml_value(&v, &format!("set['{key}']"))?;
            out.push(format!("{key}={value}"));
        }
    }
    Ok(out)
}

/// The scene of `scene` (a path, a dict of the scene file's tables, or
/// None for the built-in single-wheelset scene) with `set` applied, and
/// every file it reads, the scene file included (which no output may
/// replace).
fn load_scene(
    scene: Option<&Bound<'_, PyAny>>,
    set: Option<&Bound<'_, PyDict>>,
) -> PyResult<(LoadedScene, Vec<PathBuf>)> {
    let loaded = scene_of(scene, set)?;
    let inputs = loaded.input_paths();
    Ok((loaded, inputs))
}

fn scene_of(
    scene: Option<&Bound<'_, PyAny>>,
    set: Option<&Bound<'_, PyDict>>,
) -> PyResult<LoadedScene> {
    let overrides = overrides(set)?;
    match scene {
        None => LoadedScene::default_scene(&overrides).or_value_error(),
        Some(s) if s.is_instance_of::<PyDict>() => {
            let table = toml_value(s, "scene")?;
            let text = toml::to_string(&table)
                .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("scene: {e}")))?;
            let dir = std::env::current_dir().unwrap_or_default();
            LoadedScene::from_text(&text, dir, &overrides, "scene dict".into())
                .map_err(|e| value_error(e.context("in the scene dict")))
        }
        Some(s) => {
            let path: PathBuf = s.extract().map_err(|_| {
                pyo3::exceptions::PyTypeError::new_err(
                    "scene: a path (str or os.PathLike), a dict, or None for the built-in scene",
                )
            })?;
            LoadedScene::load(&path, &overrides).or_value_error()
        }
    }
}

/// What a progress bar shows.
#[derive(Clone, Copy, Default)]
struct Shown {
    simulated_s: f64,
    total_s: f64,
    wall_s: f64,
}

/// Run a scene as `sim run` does and keep its results in memory.
///
/// - `scene`: a scene file (TOML), a dict with the scene file's tables
///   (relative paths from the current directory), or None for the built-in
///   single-wheelset scene;
/// - `set`: overrides by scene key, e.g. `{"initial.speed_m_s": 20,
///   "contact.creep_law": "kalker"}` (`--set key=value`; None removes an
///   entry);
/// - `progress`: True (or None, the default) draws a one-line progress on
///   sys.stderr; a callable
///   is called with (simulated_s, total_s, wall_s) about ten times a
///   second; False shows nothing.
///
/// Returns `railsim.Results`; `results.summary` holds the figures `sim run`
/// prints. `results.save(path)` writes the results file.
///
/// Ctrl-C stops the run cleanly: KeyboardInterrupt is raised with the
/// partial results as `args[1]`. A run that fails part-way (derailment)
/// raises `railsim.RunFailed` with the results so far as `args[1]`. A
/// refused scene raises ValueError with the CLI's message.
#[pyfunction]
#[pyo3(signature = (scene=None, set=None, progress=None))]
pub fn run(
    py: Python<'_>,
    scene: Option<&Bound<'_, PyAny>>,
    set: Option<&Bound<'_, PyDict>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<Results> {
    let (scene, inputs) = load_scene(scene, set)?;
    railsim::session::track::check_rail(&scene)
        .map(|c| c.warnings)
        .map_err(|e| value_error(e.context("[track] rail profile")))
        .and_then(|w| crate::errors::warn_all(py, &w))?;
    let stop = Arc::new(AtomicBool::new(false));
    let shown = Mutex::new(None::<Shown>);
    // None (the default) draws, as True does.
    let show = progress.is_none_or(|p| p.is_none() || p.is_truthy().unwrap_or(false));
    let callback = progress.filter(|p| p.is_callable());
    let mut drawn = false;
    let mut tick = |py: Python<'_>| -> PyResult<()> {
        if !show {
            return Ok(());
        }
        let Some(s) = *shown.lock().map_err(|_| poisoned())? else {
            return Ok(());
        };
        if let Some(p) = callback {
            p.call1((s.simulated_s, s.total_s, s.wall_s))?;
        } else {
            let rtf = if s.wall_s > 0.0 {
                s.simulated_s / s.wall_s
            } else {
                0.0
            };
            let text = format!(
                "\rrailsim.run: t = {:.3} / {:.3} s, real-time factor {:.1}   ",
                s.simulated_s, s.total_s, rtf
            );
            let err = py.import("sys")?.getattr("stderr")?;
            err.call_method1("write", (PyString::new(py, &text),))?;
            err.call_method0("flush")?;
            drawn = true;
        }
        Ok(())
    };
    let (outcome, interrupt) = watched(
        py,
        &stop,
        || {
            railsim::run::run_scene(
                &scene,
                &mut |p: railsim::run::RunProgress| {
                    if let Ok(mut s) = shown.lock() {
                        *s = Some(Shown {
                            simulated_s: p.simulated_s,
                            total_s: p.total_s,
                            wall_s: p.wall_s,
                        });
                    }
                },
                Some(stop.clone()),
            )
        },
        &mut tick,
    )?;
    if drawn {
        py.import("sys")?
            .getattr("stderr")?
            .call_method1("write", ("\n",))?;
    }
    let outcome = match outcome {
        Ok(o) => o,
        Err(e) => return Err(interrupt.unwrap_or_else(|| value_error(e))),
    };
    let interrupted = outcome.summary.stopped.as_deref() == Some(railsim::run::INTERRUPTED);
    let (results, summary) = outcome.into_parts("the exception's results (args[1])");
    match summary {
        Ok(mut summary) => {
            summary.output = String::new();
            summary.peak_memory_mib = railsim::report::memory::peak_resident_mib();
            summary.cpu_time_s = railsim::report::memory::process_cpu_time_s();
            let summary = serde_json::to_value(&summary)
                .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
            let r = Results {
                results,
                summary: Some(summary),
                inputs,
            };
            if interrupted {
                let partial = Py::new(py, r)?;
                return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err((
                    "railsim.run interrupted (Ctrl-C); the results so far are args[1]",
                    partial,
                )));
            }
            Ok(r)
        }
        Err(e) => {
            let partial = Py::new(
                py,
                Results {
                    results,
                    summary: None,
                    inputs,
                },
            )?;
            Err(RunFailed::new_err((message(&e), partial)))
        }
    }
}

fn poisoned() -> PyErr {
    pyo3::exceptions::PyRuntimeError::new_err("internal error: a lock was poisoned")
}

/// The critical speed of a scene's vehicle as `sim critical-speed --json`
/// finds it: one dict per creep law and method, in that order (its
/// `results` list).
///
/// - `scene`: a scene file, or a dict as for `run`; `set`: overrides;
/// - `creep`: creep law names (default: the scene's);
/// - `method`: "time" (bisection on the growth rate of runs), "ramp" (a
///   decelerating run from the hunting cycle), "linear" (eigenvalues);
///   default ["time"];
/// - `min_m_s`, `max_m_s`: speed range (m/s); `tol_m_s`: bracket width (m/s);
/// - `jobs`: runs in parallel (default: the number of cores);
/// - `out`: a folder for the per-run results files, the plots and the
///   report (as the CLI's `--out`); None: a temporary folder, removed.
///
/// Ctrl-C stops the study (KeyboardInterrupt).
#[pyfunction]
#[pyo3(signature = (scene, creep=None, method=None, min_m_s=10.0, max_m_s=120.0, tol_m_s=0.1,
    jobs=None, set=None, out=None, skip_s=1.0, ramp_deceleration_m_s2=0.5, criterion="all"))]
#[allow(clippy::too_many_arguments)]
pub fn critical_speed<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    creep: Option<Vec<String>>,
    method: Option<Vec<String>>,
    min_m_s: f64,
    max_m_s: f64,
    tol_m_s: f64,
    jobs: Option<usize>,
    set: Option<&Bound<'py, PyDict>>,
    out: Option<PathBuf>,
    skip_s: f64,
    ramp_deceleration_m_s2: f64,
    criterion: &str,
) -> PyResult<Bound<'py, PyAny>> {
    let (loaded, _) = load_scene(Some(scene), set)?;
    // The CLI's parser gives the typed laws, methods and criterion (its
    // names and messages); the scene argument is a placeholder.
    let mut args: Vec<String> = vec!["sim".into(), "critical-speed".into(), "SCENE".into()];
    for c in creep.iter().flatten() {
        args.push(format!("--creep={c}"));
    }
    for m in method.iter().flatten() {
        args.push(format!("--method={m}"));
    }
    if let Some(j) = jobs {
        args.push(format!("--jobs={j}"));
    }
    args.extend([
        format!("--min={min_m_s}"),
        format!("--max={max_m_s}"),
        format!("--tol={tol_m_s}"),
        format!("--skip-s={skip_s}"),
        format!("--ramp-deceleration={ramp_deceleration_m_s2}"),
        format!("--criterion={criterion}"),
    ]);
    let cli = railsim::cli::Cli::try_parse_from(&args)
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.render().to_string()))?;
    let railsim::cli::Command::CriticalSpeed(a) = cli.command else {
        unreachable!("the arguments start with `critical-speed`")
    };
    let scratch;
    let out_dir = match &out {
        Some(d) => d.clone(),
        None => {
            scratch = tempfile::tempdir().map_err(|e| {
                pyo3::exceptions::PyOSError::new_err(format!("creating a temporary folder: {e}"))
            })?;
            scratch.path().to_path_buf()
        }
    };
    let settings = railsim::studies::critical_speed::CriticalSpeedSettings {
        out_dir: out_dir.clone(),
        ..a.settings(&loaded)
    };
    let stop = Arc::new(AtomicBool::new(false));
    let write = out.is_some();
    let (report, interrupt) = watched(
        py,
        &stop,
        || -> anyhow::Result<_> {
            railsim::session::track::check_rail(&loaded)?;
            let mut report = railsim::studies::critical_speed::study(
                &loaded,
                &settings,
                stop.clone(),
                &mut |_| {},
            )?;
            if write {
                report.write(&out_dir)?;
            }
            Ok(report)
        },
        &mut |_| Ok(()),
    )?;
    if let Some(e) = interrupt {
        return Err(e);
    }
    let report = report.map_err(value_error)?;
    crate::arrays::to_python(py, &report.results)
}
