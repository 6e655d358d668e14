//! Files in, table file out: read and check the inputs, build, tabulate and
//! write atomically. Used by `track-preproc build` and by `sim` when a scene
//! names CSV inputs.

use std::path::{Path, PathBuf};
use std::time::Instant;

use runtime::geometry::profile::rail_cant::{RailCantCheck, Spelling, check_rail_file};
use runtime::geometry::track::{InputFile, Provenance, TrackTables};
use runtime::io::schema;

use crate::config::BuildConfig;
use crate::contact_table::{ContactTableConfig, build_contact_table, conicity_of};
use crate::csv::read_text;
use crate::design::DesignInput;
use crate::error::BuildError;
use crate::inputs::{CantInput, CenterlineInput, IrregularityInput};
use crate::model::{DesignInputs, Inputs, TrackInputs, TrackModel};
use crate::progress::{Progress, ProgressSink};
use crate::summary::{BuildSummary, ContactTableSummary};

/// The files that give a track's geometry.
#[derive(Debug, Clone, PartialEq)]
pub enum GeometryFiles {
    /// Centreline control points (CSV), with an optional cant table (CSV).
    ControlPoints {
        centerline: PathBuf,
        cant: Option<PathBuf>,
    },
    /// A design file (TOML; docs/reference/02-inputs.md §2.9).
    Design(PathBuf),
}

impl GeometryFiles {
    /// Control points without a cant table.
    pub fn centerline(path: impl Into<PathBuf>) -> Self {
        GeometryFiles::ControlPoints {
            centerline: path.into(),
            cant: None,
        }
    }

    /// Every file, in the order read.
    pub fn paths(&self) -> Vec<&Path> {
        match self {
            GeometryFiles::ControlPoints { centerline, cant } => std::iter::once(centerline)
                .chain(cant.iter())
                .map(PathBuf::as_path)
                .collect(),
            GeometryFiles::Design(p) => vec![p.as_path()],
        }
    }
}

/// Everything a build needs.
#[derive(Debug, Clone, PartialEq)]
pub struct BuildRequest {
    pub geometry: GeometryFiles,
    pub irregularities: Option<PathBuf>,
    pub output: PathBuf,
    pub config: BuildConfig,
    /// Build a contact lookup table too (docs/reference/04-table-files.md §4) with these settings; its
    /// gauge, rail spacing and inclination are the track's.
    pub contact: Option<ContactTableConfig>,
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
/// provenance). The CSV files must be UTF-8 (a byte-order mark is
/// ignored); a byte that is not is an error at its line and column.
pub fn read_inputs(req: &BuildRequest) -> Result<(Inputs, Vec<InputFile>), BuildError> {
    let mut files = Vec::new();
    let mut keep = |role: &str, path: &Path, text: &str| {
        files.push(InputFile {
            role: role.into(),
            path: path.display().to_string(),
            text: text.into(),
        })
    };
    enum Geometry {
        ControlPoints(Box<(CenterlineInput, Option<CantInput>)>),
        Design(DesignInput),
    }
    let geometry = match &req.geometry {
        GeometryFiles::ControlPoints { centerline, cant } => {
            let text = read_text(centerline)?;
            let parsed = CenterlineInput::parse(centerline, &text)?;
            keep("centerline", centerline, &text);
            let cant = match cant {
                Some(p) => {
                    let text = read_text(p)?;
                    let c = CantInput::parse(p, &text)?;
                    keep("cant", p, &text);
                    Some(c)
                }
                None => None,
            };
            Geometry::ControlPoints(Box::new((parsed, cant)))
        }
        GeometryFiles::Design(p) => {
            let text = read_text(p)?;
            let d = DesignInput::parse(p, &text, req.config.cant_base_m())?;
            keep("design", p, &text);
            Geometry::Design(d)
        }
    };
    let irregularities = match &req.irregularities {
        Some(p) => {
            let text = read_text(p)?;
            let i = IrregularityInput::parse(p, &text)?;
            keep("irregularities", p, &text);
            Some(i)
        }
        None => None,
    };
    let inputs = match geometry {
        Geometry::ControlPoints(b) => {
            let (centerline, cant) = *b;
            Inputs::ControlPoints(Box::new(TrackInputs {
                centerline,
                cant,
                irregularities,
            }))
        }
        Geometry::Design(design) => Inputs::Design(Box::new(DesignInputs {
            design,
            irregularities,
        })),
    };
    Ok((inputs, files))
}

/// The rail profile of a build checked against its inclination (double
/// canting refused; messages name the command-line options), when the
/// build names one.
pub fn check_build_rail(config: &BuildConfig) -> Result<Option<RailCantCheck>, BuildError> {
    Ok(match &config.rail_profile {
        Some(path) => Some(check_rail_file(
            path,
            config.rail_profile_cant.as_ref().map(|c| c.angle_rad),
            config.inclination.angle_rad,
            Spelling::CommandLine,
        )?),
        None => None,
    })
}

/// Build the tables of a request in memory (no file written); the rail
/// profile, when the request names one, is checked before the work
/// ([`check_build_rail`]) and recorded in the tables' metadata.
pub fn build_tables(
    req: &BuildRequest,
    progress: &dyn ProgressSink,
) -> Result<(TrackTables, Provenance), BuildError> {
    req.config.validate()?;
    let rail = check_build_rail(&req.config)?;
    let (inputs, files) = read_inputs(req)?;
    let model = TrackModel::from_inputs(&inputs, &req.config)?;
    let mut tables = model.tabulate(progress)?;
    let mut files = files;
    if let (Some(r), Some(path)) = (rail, &req.config.rail_profile) {
        files.push(InputFile {
            role: "rail_profile".into(),
            path: path.display().to_string(),
            text: read(path)?,
        });
        tables.meta.rail_profile = Some(r.record);
    }
    Ok((
        tables,
        Provenance {
            command_line: req.command_line.clone(),
            inputs: files,
        },
    ))
}

/// Read the profile files of a contact table, for provenance.
fn profile_inputs(c: &ContactTableConfig) -> Result<Vec<InputFile>, BuildError> {
    crate::contact_table::profile_paths(c)
        .into_iter()
        .map(|(role, path)| {
            Ok(InputFile {
                role: role.into(),
                path: path.display().to_string(),
                text: read(path)?,
            })
        })
        .collect()
}

/// Build and write the table file of a request; returns the summary.
pub fn run_build(
    req: &BuildRequest,
    progress: &dyn ProgressSink,
) -> Result<BuildSummary, BuildError> {
    let start = Instant::now();
    // The contact table's rail is the track's: recorded with it.
    let mut req = req.clone();
    if let (None, Some(c)) = (&req.config.rail_profile, &req.contact) {
        req.config.rail_profile = Some(c.rail_profile.clone());
    }
    let req = &req;
    let (tables, mut provenance) = build_tables(req, progress)?;
    let contact = match &req.contact {
        Some(c) => {
            let c = ContactTableConfig {
                gauge_m: req.config.gauge_m,
                rail_spacing_m: req.config.rail_spacing_m(),
                rail_inclination_rad: req.config.inclination.angle_rad,
                rail_profile_cant_rad: req.config.rail_profile_cant.as_ref().map(|i| i.angle_rad),
                ..c.clone()
            };
            for input in profile_inputs(&c)? {
                if !provenance.inputs.iter().any(|i| i.role == input.role) {
                    provenance.inputs.push(input);
                }
            }
            let (model, warnings) = c.model()?;
            Some((build_contact_table(&model, &c, progress)?, warnings))
        }
        None => None,
    };
    progress.event(Progress::Stage {
        name: "writing",
        rows: 0,
    });
    let w = schema::TableFileWriter::create(&req.output)?;
    w.write_track(&tables)?;
    if let Some((t, _)) = &contact {
        w.write_contact_table(t)?;
    }
    w.write_provenance(&provenance)?;
    w.finish()?;
    progress.event(Progress::Done);
    let mut summary = BuildSummary::new(
        &tables,
        &req.output.display().to_string(),
        start.elapsed().as_secs_f64(),
    );
    summary.contact_table = contact.as_ref().map(|(t, warnings)| ContactTableSummary {
        warnings: warnings.iter().map(ToString::to_string).collect(),
        ..ContactTableSummary::new(t, conicity_of(t))
    });
    Ok(summary)
}

/// A contact table on its own (`track-preproc contact-table`).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactTableRequest {
    pub config: ContactTableConfig,
    pub output: PathBuf,
    pub command_line: String,
}

/// What `track-preproc contact-table` produced.
#[derive(Debug, Clone, serde::Serialize, PartialEq)]
pub struct ContactTableReport {
    pub output: String,
    pub contact_table: ContactTableSummary,
    pub elapsed_s: f64,
}

/// Build a contact table and write it to a file of its own.
pub fn run_contact_table(
    req: &ContactTableRequest,
    progress: &dyn ProgressSink,
) -> Result<(runtime::contact::table::ContactTable, ContactTableReport), BuildError> {
    let start = Instant::now();
    let (model, warnings) = req.config.model()?;
    let table = build_contact_table(&model, &req.config, progress)?;
    let provenance = Provenance {
        command_line: req.command_line.clone(),
        inputs: profile_inputs(&req.config)?,
    };
    schema::write_contact_table_file(&req.output, &table, &provenance)?;
    progress.event(Progress::Done);
    let report = ContactTableReport {
        output: req.output.display().to_string(),
        contact_table: ContactTableSummary {
            warnings: warnings.iter().map(ToString::to_string).collect(),
            ..ContactTableSummary::new(&table, conicity_of(&table))
        },
        elapsed_s: start.elapsed().as_secs_f64(),
    };
    Ok((table, report))
}
