//! Errors of the pre-processor. Every input error names the file, the line
//! (1-based, as an editor shows it) and the column (1-based) where there
//! are ones, and the rule broken (docs/reference/02-inputs.md §2).

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
    /// 1-based column (field of a CSV row, or character of the line), when
    /// the problem is one value.
    pub column: Option<usize>,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ", line {line}")?;
            if let Some(column) = self.column {
                write!(f, ", column {column}")?;
            }
        }
        Ok(())
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
                column: None,
            },
            rule: rule.into(),
        }
    }

    /// An error about the value at `line`, `column` (both 1-based).
    pub fn at_value(
        file: impl Into<PathBuf>,
        line: usize,
        column: usize,
        rule: impl Into<String>,
    ) -> Self {
        Self {
            location: Location {
                file: file.into(),
                line: Some(line),
                column: Some(column),
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
    /// A built table's cant beyond [`crate::bounds::MAX_CANT_RAD`] though
    /// the input is within it: the spline's overshoot (`input` says so,
    /// with the input's peak and the remedy).
    #[error(
        "the built cant reaches {cant_rad:+.4} rad ({cant_mm:+.1} mm) at s = {s_m:.3} m, beyond the ±{bound_rad:.4} rad (200 mm on the standard cant base) of any track: {input}"
    )]
    BuiltCant {
        s_m: f64,
        cant_rad: f64,
        cant_mm: f64,
        bound_rad: f64,
        input: String,
    },
    /// A built table's irregularity beyond
    /// [`crate::bounds::MAX_IRREGULARITY_M`] though every value of the
    /// file is within it: the not-a-knot spline's overshoot.
    #[error(
        "the built {component} reaches {:.1} mm at s = {s_m:.3} m, beyond the ±{:.0} mm of any track, though the file's values are within it: the cubic spline overshoots between the samples; sample the file more densely there",
        value_m * 1e3,
        bound_m * 1e3
    )]
    BuiltIrregularity {
        component: &'static str,
        s_m: f64,
        value_m: f64,
        bound_m: f64,
    },
    /// The centreline or a rail is longer or shorter than its table rows
    /// resolve (docs/reference/03-track-preproc.md §3g).
    #[error(
        "the {what} is {built_m:.3} m long but its table rows resolve {resolved_m:.3} m (centreline {centreline_m:.3} m; difference {:.3} m, more than the {tolerance_m:.3} m allowed): the geometry varies between the rows of the {step_m} m step (irregularities, cant or control points closer than the step, with content shorter than 2 × step) and the tables cannot show it; use a finer --step or smooth the input",
        (built_m - resolved_m).abs()
    )]
    Length {
        what: &'static str,
        built_m: f64,
        resolved_m: f64,
        centreline_m: f64,
        tolerance_m: f64,
        step_m: f64,
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
