//! Files in, table file out: read and check the inputs, build, tabulate and
//! write atomically. Used by `track-preproc build` and by `sim` when a scene
//! names CSV inputs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use runtime::schema;
use runtime::track::{InputFile, Provenance, TrackTables};

use crate::config::BuildConfig;
use crate::error::BuildError;
use crate::inputs::{CantInput, CenterlineInput, IrregularityInput};
use crate::model::{TrackInputs, TrackModel};
use crate::progress::{Progress, ProgressSink};
use crate::summary::BuildSummary;

/// Everything a build needs.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildRequest {
    pub centerline: PathBuf,
    pub cant: Option<PathBuf>,
    pub irregularities: Option<PathBuf>,
    pub output: PathBuf,
    pub config: BuildConfig,
    /// Recorded under `/input/command_line`.
    pub command_line: String,
}

fn read(path: &Path) -> Result<String, BuildError> {
    std::fs::read_to_string(path).map_err(|source| BuildError::Read {
        path: path.to_path_buf(),
        source,
    })
}

/// Read and parse the input files of a request (with their text, for
/// provenance).
pub fn read_inputs(req: &BuildRequest) -> Result<(TrackInputs, Vec<InputFile>), BuildError> {
    let mut files = Vec::new();
    let mut keep = |role: &str, path: &Path, text: &str| {
        files.push(InputFile {
            role: role.into(),
            path: path.display().to_string(),
            text: text.into(),
        })
    };
    let text = read(&req.centerline)?;
    let centerline = CenterlineInput::parse(&req.centerline, &text)?;
    keep("centerline", &req.centerline, &text);
    let cant = match &req.cant {
        Some(p) => {
            let text = read(p)?;
            let c = CantInput::parse(p, &text)?;
            keep("cant", p, &text);
            Some(c)
        }
        None => None,
    };
    let irregularities = match &req.irregularities {
        Some(p) => {
            let text = read(p)?;
            let i = IrregularityInput::parse(p, &text)?;
            keep("irregularities", p, &text);
            Some(i)
        }
        None => None,
    };
    Ok((
        TrackInputs {
            centerline,
            cant,
            irregularities,
        },
        files,
    ))
}

/// Build the tables of a request in memory (no file written).
pub fn build_tables(
    req: &BuildRequest,
    progress: &dyn ProgressSink,
) -> Result<(TrackTables, Provenance), BuildError> {
    req.config.validate()?;
    let (inputs, files) = read_inputs(req)?;
    let model = TrackModel::build(&inputs, &req.config)?;
    let tables = model.tabulate(progress)?;
    Ok((
        tables,
        Provenance {
            command_line: req.command_line.clone(),
            inputs: files,
        },
    ))
}

/// Build and write the table file of a request; returns the summary.
pub fn run_build(
    req: &BuildRequest,
    progress: &dyn ProgressSink,
) -> Result<BuildSummary, BuildError> {
    let start = Instant::now();
    let (tables, provenance) = build_tables(req, progress)?;
    progress.event(Progress::Stage {
        name: "writing",
        rows: 0,
    });
    schema::write_track_file(&req.output, &tables, &provenance)?;
    progress.event(Progress::Done);
    Ok(BuildSummary::new(
        &tables,
        &req.output.display().to_string(),
        start.elapsed().as_secs_f64(),
    ))
}
