//! Errors of the pre-processor. Every input error names the file, the line
//! (1-based, as an editor shows it) where there is one, and the rule broken
//! (docs/reference/02-inputs.md §2).

use std::fmt;
use std::path::PathBuf;

use runtime::geometry::spline::SplineError;

/// Where in an input file a problem is.
#[derive(Debug, Clone, PartialEq)]
pub struct Location {
    /// The file as the user named it.
    pub file: PathBuf,
    /// 1-based line number in the file, when the problem is on one line.
    pub line: Option<usize>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}, line {line}", self.file.display()),
            None => write!(f, "{}", self.file.display()),
        }
    }
}

/// A rule broken by an input file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{location}: {rule}")]
pub struct InputError {
    pub location: Location,
    pub rule: String,
}

impl InputError {
    pub fn new(file: impl Into<PathBuf>, line: Option<usize>, rule: impl Into<String>) -> Self {
        Self {
            location: Location {
                file: file.into(),
                line,
            },
            rule: rule.into(),
        }
    }
}

/// A build that could not be completed.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    #[error(transparent)]
    Input(#[from] InputError),
    #[error("invalid build option: {0}")]
    Config(String),
    #[error("{what}: {source}")]
    Spline {
        what: String,
        #[source]
        source: SplineError,
    },
    #[error("{0}")]
    Geometry(String),
    /// The track is too long for its table step or for the spacing of its
    /// closest control points: the `what` (a table, the rail nodal points)
    /// would need more than `max` rows, more memory than a build should
    /// take (checked before allocating: an allocation that fails aborts).
    #[error(
        "the {what} would need {rows:.3e} rows ({length_m:.1} m every {spacing_m} m), more than the {max:.0e} a build accepts; {hint}"
    )]
    TooLarge {
        what: &'static str,
        length_m: f64,
        spacing_m: f64,
        rows: f64,
        max: f64,
        hint: &'static str,
    },
    #[error("cannot read '{path}': {source}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(transparent)]
    Write(#[from] runtime::io::schema::SchemaError),
    #[error(transparent)]
    ContactTable(#[from] crate::contact_table::ContactTableBuildError),
    #[error(transparent)]
    RailCant(#[from] runtime::geometry::profile::rail_cant::RailCantError),
}
