//! A run's outputs on disk: the results file (HDF5,
//! `docs/reference/04-table-files.md`) and its plots, written from a
//! [`RunOutcome`] in memory.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result};
use runtime::io::schema::ResultsWriter;

use crate::config::scene::LoadedScene;
use crate::run::{RunOutcome, RunProgress, RunSummary};
use crate::session::plan::Plan;

/// What to run and where to write.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRequest {
    pub scene: LoadedScene,
    pub output: PathBuf,
    /// Directory for the PNG plots; `None`: no plots.
    pub plots: Option<PathBuf>,
}

/// Writes a run held in memory: its results file and plots (the plots
/// only when there are samples); the summary then names them. A run that
/// failed is written first and its error returned after, naming the file.
pub fn write_run(outcome: RunOutcome, output: &Path, plots: Option<&Path>) -> Result<RunSummary> {
    let mut writer = create_results(output)?;
    writer
        .append_chunk(&outcome.results)
        .with_context(|| format!("writing the results {}", output.display()))?;
    finish_run(outcome, writer, plots)
}

/// The results file of `output`, created under its temporary name (which
/// probes the location before the work).
fn create_results(output: &Path) -> Result<ResultsWriter> {
    ResultsWriter::create(output)
        .with_context(|| format!("creating the results {}", output.display()))
}

/// Finish the results file whose samples the run appended (its metadata,
/// then the rename into place), then the plots from the outcome's view.
fn finish_run(
    mut outcome: RunOutcome,
    writer: ResultsWriter,
    plots: Option<&Path>,
) -> Result<RunSummary> {
    let output = writer.path().to_path_buf();
    writer
        .finish(&outcome.results)
        .with_context(|| format!("writing the results {}", output.display()))?;
    outcome.summary.output = output.display().to_string();
    if let Some(dir) = plots.filter(|_| !outcome.results.is_empty()) {
        outcome.summary.plots =
            super::run_plots::write_run_plots(&outcome.results, dir, &outcome.summary.title)?
                .into_iter()
                .map(|p| p.display().to_string())
                .collect();
        let curving = super::curving_plot::write_curving_plot(
            &outcome.results,
            &outcome.summary.curving.track_elements,
            outcome.summary.curving.track_elements_source,
            dir,
            &outcome.summary.title,
        )?;
        outcome.summary.plots.push(curving.display().to_string());
    }
    outcome.summary.peak_memory_mib = super::memory::peak_resident_mib();
    outcome.summary.cpu_time_s = super::memory::process_cpu_time_s();
    outcome.into_result(&output.display().to_string())
}

/// Plans, runs and writes a request: the outputs are locked (the results
/// file's lock, and the plots folder's: a second `sim run` writing either
/// at the same time is refused at once, so that the results and the plots
/// are of one run, [`runtime::io::OutputLock`]), the results file is
/// created (probing the location), the run appends its samples to it as it goes
/// ([`crate::run::run_scene_with_plan`] with a sink), then it is finished
/// and the plots drawn.
pub fn run_to_files(
    req: &RunRequest,
    plan: Plan,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
) -> Result<RunSummary> {
    let _locks = [Some(req.output.as_path()), req.plots.as_deref()]
        .into_iter()
        .flatten()
        .map(runtime::io::OutputLock::acquire)
        .collect::<Result<Vec<_>, _>>()?;
    let mut writer = create_results(&req.output)?;
    let outcome =
        crate::run::run_scene_with_plan(&req.scene, plan, progress, stop, Some(&mut writer))?;
    finish_run(outcome, writer, req.plots.as_deref())
}
