//! A run's outputs on disk: the results file (HDF5,
//! `docs/reference/04-table-files.md`) and its plots, written from a
//! [`RunOutcome`] in memory.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use anyhow::{Context, Result};

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

/// Writes a run's results file and plots (the plots only when there are
/// samples); the summary then names them. A run that failed is written
/// first and its error returned after, naming the file.
pub fn write_run(
    mut outcome: RunOutcome,
    output: &Path,
    plots: Option<&Path>,
) -> Result<RunSummary> {
    runtime::io::schema::write_results(output, &outcome.results)
        .with_context(|| format!("writing the results {}", output.display()))?;
    outcome.summary.output = output.display().to_string();
    if let Some(dir) = plots.filter(|_| !outcome.results.is_empty()) {
        outcome.summary.plots =
            super::run_plots::write_run_plots(&outcome.results, dir, &outcome.summary.title)?
                .into_iter()
                .map(|p| p.display().to_string())
                .collect();
    }
    outcome.into_result(&output.display().to_string())
}

/// Plans, runs and writes a request ([`crate::run::run_scene_with_plan`],
/// then [`write_run`]).
pub fn run_to_files(
    req: &RunRequest,
    plan: Plan,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
) -> Result<RunSummary> {
    let outcome = crate::run::run_scene_with_plan(&req.scene, plan, progress, stop)?;
    write_run(outcome, &req.output, req.plots.as_deref())
}
