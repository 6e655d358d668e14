//! Reading wheel and rail profile files (docs/reference/02-inputs.md §2, "Profiles") into plain
//! data: the points of the file **in the file's own coordinate convention**,
//! converted to metres, with the metadata needed to convert them into the
//! toolkit's wheel/rail conventions (done elsewhere, not here).
//!
//! The module is behind the `io` feature (on by default): its plain and
//! CSV formats are read by the workspace's one table reader
//! ([`crate::io::csv`], which also parses every number here). Parsing text
//! ([`parse_profile`], [`parse_profile_as`]) does not touch the file
//! system; [`read_profile`], [`load_wheel`] and [`load_rail`] read files.
//!
//! # Formats
//!
//! | format | recognised by | units | z | lateral convention |
//! |---|---|---|---|---|
//! | [`ProfileFormat::Simpack`] | extension `.prw` (wheel) / `.prr` (rail), or a file whose first statement is `header.begin` / `spline.begin` | `units.len.f` (l\[file\] / l\[m\]; 1000 = mm; default 1 = m) | **down** (`z_down = true`) | as in the file after its own `mirror.y`; for the Manchester benchmark files the flange / gauge face is at negative y |
//! | [`ProfileFormat::Plain`] | any other extension (`.dat`, `.txt`, …) | **millimetres** (EN 15302 and Miniprof practice) | **up** (`z_down = false`) | flange at negative y (EN 15302 reference files) |
//! | [`ProfileFormat::Csv`] | extension `.csv` | per column: `y`, `z` in metres, `y_mm`, `z_mm` in millimetres | **up** (`z_down = false`) | as in the file |
//!
//! * SIMPACK: `!` starts a comment (outside quoted strings); blocks
//!   `header.begin … header.end` (keys `version` = 1, `type` = 0 rail / 1
//!   wheel) and `spline.begin … spline.end` with the processing keys and one
//!   `point.begin … point.end` block of rows `y z [weight]`. The processing
//!   the file asks for is applied; see [`SimpackSettings`] for the order and
//!   its source.
//! * Plain: one point `y z` a line, separated by white space or by one comma;
//!   `#`, `!` and `%` start a comment (whole line or the rest of a line);
//!   blank lines are ignored.
//! * CSV: a header row naming exactly two columns (`y`/`y_mm` and
//!   `z`/`z_mm`, any order), then one row of numbers a line; lines starting
//!   with `#` and blank lines are ignored (docs/reference/02-inputs.md §2).
//!
//! # Import options
//!
//! [`ImportOptions`] are applied **after** the format's own processing:
//! `length_unit` replaces the unit the format implies (SIMPACK
//! `1 / units.len.f`, plain millimetres, CSV column suffix), and `mirror_y`
//! / `mirror_z` negate y / z for files that use the other convention. The
//! result is then in the format's documented convention above: `z_down`
//! describes the points returned, whatever the options.
//!
//! # What is checked
//!
//! Every error names the file, the 1-based line and the rule broken
//! ([`ProfileImportError`]): a value that is not a number or not finite
//! (and its column), a
//! row with the wrong number of values, fewer than [`MIN_POINTS`] points
//! (after the file's processing), two consecutive equal points, a SIMPACK
//! file without a point block, with an unknown key, a duplicated key, badly
//! nested blocks, a transform value this reader does not support (e.g.
//! `mirror.y = 2`) or a header `type` that contradicts the `.prw` / `.prr`
//! extension; a CSV header that does not name the columns.
//!
//! Not read: Miniprof `.ban` / `.whl` files with their `Key=Value` header
//! (refused at line 1 as a plain file); strip the header to read the data
//! as plain millimetre columns.
//!
//! Points are **never sorted or reordered** (except by a SIMPACK
//! `inversion = 1`, which the file asks for). Whether y is strictly
//! monotone is reported in [`ProfileFile::y_order`]: profiles with vertical
//! faces can repeat or reverse y. Each point keeps the line it came from
//! ([`ProfileFile::lines`]), so later checks can name it too
//! ([`ProfileFile::error_at`]): building a wheel or rail profile
//! ([`load_wheel`], [`load_rail`]) passes the lines on, and the one rule of
//! the usable stretch (the same for every format,
//! docs/reference/05-surfaces.md §5.3) refuses a profile that folds back or
//! repeats y inside it at the line of the first offending point.
//!
//! A UTF-8 byte order mark at the start of the text is skipped in every
//! format. A value that is not a number names the file, the line and, in a
//! row of numbers, the column (the 1-based field).

mod columns;
mod load;
mod simpack;

pub use load::{Loaded, ProfileLoadError, load_rail, load_wheel};

pub use simpack::SimpackSettings;

use std::path::{Path, PathBuf};

use crate::io::csv::{NumberError, parse_number};

/// Fewest points a profile may have (a cubic spline needs four).
pub const MIN_POINTS: usize = 4;

/// Millimetres in metres: the default unit of plain two-column files
/// (m per file unit).
pub const PLAIN_DEFAULT_UNIT_M: f64 = 1e-3;

/// The file format a profile was read as.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProfileFormat {
    /// SIMPACK `.prw` / `.prr`.
    Simpack,
    /// Two numbers a line, millimetres by default.
    Plain,
    /// CSV with a header row `y,z` (m) or `y_mm,z_mm` (mm).
    Csv,
}

/// Wheel or rail, when the file says so (SIMPACK header `type`, or the
/// extension `.prw` / `.prr`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProfileKind {
    Wheel,
    Rail,
}

/// Options applied after the format's own processing.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ImportOptions {
    /// Overrides the length unit the format implies (m per file unit)
    /// (e.g. `Some(1e-3)` for millimetres, `Some(1.0)` for metres). For
    /// SIMPACK it replaces `1 / units.len.f`, for CSV the unit implied by
    /// the column names. Must be finite and positive.
    pub length_unit: Option<f64>,
    /// Negate y after the format's processing (a file using the other
    /// lateral convention).
    pub mirror_y: bool,
    /// Negate z after the format's processing (a file whose z points the
    /// other way than its format's convention).
    pub mirror_z: bool,
}

/// How y runs along the points, in file order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum YOrder {
    /// Strictly increasing.
    Increasing,
    /// Strictly decreasing.
    Decreasing,
    /// Neither: y repeats or turns back first at point `index` (0-based; the
    /// step from `index - 1` to `index` breaks the direction of the first
    /// step), which came from file line `line`.
    NotMonotone { index: usize, line: usize },
}

/// A profile as read from a file: points in the file's convention, metres.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileFile {
    /// The file as named by the caller.
    pub path: PathBuf,
    pub format: ProfileFormat,
    /// Wheel or rail when the file says so (SIMPACK header `type`, else the
    /// extension `.prw` / `.prr`); `None` for plain and CSV files.
    pub kind: Option<ProfileKind>,
    /// Points (y, z) (m) in the file's coordinate convention (see
    /// `z_down`), in file order after the file's own processing and the
    /// import options.
    pub points_m: Vec<[f64; 2]>,
    /// 1-based line of the file each point came from (same length as
    /// `points_m`).
    pub lines: Vec<usize>,
    /// Spline weight of each point (SIMPACK third column, default 1; 1 for
    /// the other formats) (-).
    pub weights: Vec<f64>,
    /// `true` when z points down (SIMPACK), `false` when up (plain, CSV).
    pub z_down: bool,
    /// Whether y is strictly monotone along the points.
    pub y_order: YOrder,
    /// SIMPACK `comment`; for plain and CSV files the comment lines before
    /// the first data (or header) line, joined by newlines.
    pub comment: Option<String>,
    /// The SIMPACK settings that were applied (SIMPACK files only).
    pub simpack: Option<SimpackSettings>,
}

impl ProfileFile {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points_m.len()
    }

    /// Never true for a profile that was read successfully.
    pub fn is_empty(&self) -> bool {
        self.points_m.is_empty()
    }

    /// `true` if y is strictly increasing or strictly decreasing.
    pub fn y_monotone(&self) -> bool {
        !matches!(self.y_order, YOrder::NotMonotone { .. })
    }

    /// Smallest and largest y (m).
    pub fn y_range_m(&self) -> (f64, f64) {
        range(self.points_m.iter().map(|p| p[0]))
    }

    /// Smallest and largest z (m) (file convention: see `z_down`).
    pub fn z_range_m(&self) -> (f64, f64) {
        range(self.points_m.iter().map(|p| p[1]))
    }

    /// An error about point `index` (0-based), naming its file and line, for
    /// checks made after import (e.g. a wheel region that is not convex).
    /// An index past the end names the last point.
    pub fn error_at(&self, index: usize, rule: impl Into<String>) -> ProfileImportError {
        let line = self
            .lines
            .get(index)
            .or(self.lines.last())
            .copied()
            .unwrap_or(1);
        ProfileImportError::Invalid {
            path: self.path.clone(),
            line,
            rule: rule.into(),
        }
    }
}

fn range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// Why a profile file could not be imported. Every variant names the file;
/// every variant about the file's content names the 1-based line and the
/// rule broken.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileImportError {
    #[error("cannot read profile file '{path}': {message}")]
    Io { path: PathBuf, message: String },
    #[error("'{path}': invalid import option: {rule}")]
    InvalidOption { path: PathBuf, rule: String },
    #[error("'{path}', line {line}{}: {what}: '{text}' is not a number", column_note(*column))]
    NotANumber {
        path: PathBuf,
        line: usize,
        /// 1-based column (field) of the value in its row; `None` for a
        /// value that is not in a row of numbers (a SIMPACK key's value).
        column: Option<usize>,
        /// Which value (e.g. "z", "value of 'shift.y'").
        what: String,
        text: String,
    },
    #[error(
        "'{path}', line {line}{}: {what}: '{text}' is not finite (every value must be a finite number)",
        column_note(*column)
    )]
    NonFinite {
        path: PathBuf,
        line: usize,
        /// As for `NotANumber`.
        column: Option<usize>,
        what: String,
        text: String,
    },
    #[error("'{path}', line {line}: expected {expected}, found {found} value(s)")]
    FieldCount {
        path: PathBuf,
        line: usize,
        /// What a row must hold, e.g. "2 values (y z)".
        expected: String,
        found: usize,
    },
    #[error(
        "'{path}', line {line}: {found} profile point(s) ({in_file} in the file{}), at least {min} are needed",
        removed_note(*found, *in_file)
    )]
    TooFewPoints {
        path: PathBuf,
        /// The end of the point data.
        line: usize,
        /// Points left after processing.
        found: usize,
        /// Points in the file.
        in_file: usize,
        min: usize,
    },
    #[error(
        "'{path}', line {line}: no 'point.begin … point.end' block inside 'spline.begin … spline.end' (a SIMPACK profile needs one)"
    )]
    MissingPointBlock { path: PathBuf, line: usize },
    #[error("'{path}', line {line}: '{key} = {value}' is not supported: {allowed}")]
    UnsupportedValue {
        path: PathBuf,
        line: usize,
        key: String,
        value: String,
        /// The rule: what is allowed.
        allowed: String,
    },
    #[error(
        "'{path}', line {line}: unknown key '{key}' in the {block} block (known keys: {known})"
    )]
    UnknownKey {
        path: PathBuf,
        line: usize,
        block: String,
        key: String,
        known: String,
    },
    #[error("'{path}', line {line}: key '{key}' is given twice (first on line {first_line})")]
    DuplicateKey {
        path: PathBuf,
        line: usize,
        key: String,
        first_line: usize,
    },
    #[error("'{path}', line {line}: {rule}")]
    Syntax {
        path: PathBuf,
        line: usize,
        rule: String,
    },
    #[error(
        "'{path}', line {line}: header type = {header_type} ({header_kind:?}) contradicts the file extension ({extension_kind:?})"
    )]
    KindConflict {
        path: PathBuf,
        line: usize,
        header_type: i64,
        header_kind: ProfileKind,
        extension_kind: ProfileKind,
    },
    #[error("'{path}', line {line}: CSV header: {rule}")]
    CsvHeader {
        path: PathBuf,
        line: usize,
        rule: String,
    },
    #[error(
        "'{path}', line {line}: point (y = {y_m} m, z = {z_m} m) equals the point before it (line {previous_line}); consecutive points must differ"
    )]
    DuplicatePoint {
        path: PathBuf,
        line: usize,
        previous_line: usize,
        y_m: f64,
        z_m: f64,
    },
    /// A rule broken by an imported profile, found by a later check
    /// ([`ProfileFile::error_at`]).
    #[error("'{path}', line {line}: {rule}")]
    Invalid {
        path: PathBuf,
        line: usize,
        rule: String,
    },
}

/// ", column N" when there is a column.
fn column_note(column: Option<usize>) -> String {
    column.map_or(String::new(), |c| format!(", column {c}"))
}

/// Part of the "too few points" message.
fn removed_note(found: usize, in_file: usize) -> &'static str {
    if found == in_file {
        ""
    } else {
        ", the rest removed by the file's processing"
    }
}

impl ProfileImportError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Io { path, .. }
            | Self::InvalidOption { path, .. }
            | Self::NotANumber { path, .. }
            | Self::NonFinite { path, .. }
            | Self::FieldCount { path, .. }
            | Self::TooFewPoints { path, .. }
            | Self::MissingPointBlock { path, .. }
            | Self::UnsupportedValue { path, .. }
            | Self::UnknownKey { path, .. }
            | Self::DuplicateKey { path, .. }
            | Self::Syntax { path, .. }
            | Self::KindConflict { path, .. }
            | Self::CsvHeader { path, .. }
            | Self::DuplicatePoint { path, .. }
            | Self::Invalid { path, .. } => path,
        }
    }

    /// The 1-based line the error is about (`None` for I/O and option
    /// errors, which are not about a line).
    pub fn line(&self) -> Option<usize> {
        match self {
            Self::Io { .. } | Self::InvalidOption { .. } => None,
            Self::NotANumber { line, .. }
            | Self::NonFinite { line, .. }
            | Self::FieldCount { line, .. }
            | Self::TooFewPoints { line, .. }
            | Self::MissingPointBlock { line, .. }
            | Self::UnsupportedValue { line, .. }
            | Self::UnknownKey { line, .. }
            | Self::DuplicateKey { line, .. }
            | Self::Syntax { line, .. }
            | Self::KindConflict { line, .. }
            | Self::CsvHeader { line, .. }
            | Self::DuplicatePoint { line, .. }
            | Self::Invalid { line, .. } => Some(*line),
        }
    }
}

/// Read the profile file `path` (format from its extension or content, see
/// the module docs); the parsing alone is [`parse_profile`].
pub fn read_profile(
    path: &Path,
    options: &ImportOptions,
) -> Result<ProfileFile, ProfileImportError> {
    let bytes = std::fs::read(path).map_err(|e| ProfileImportError::Io {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    // Comments of old files may be Latin-1; numbers and keys are ASCII.
    let text = String::from_utf8_lossy(&bytes);
    parse_profile(path, &text, options)
}

/// Parse `text`, the content of `path_for_messages` (whose extension picks
/// the format together with the content, see [`detect_format`]). Pure: does
/// not touch the file system.
pub fn parse_profile(
    path_for_messages: &Path,
    text: &str,
    options: &ImportOptions,
) -> Result<ProfileFile, ProfileImportError> {
    let format = detect_format(path_for_messages, text);
    parse_profile_as(path_for_messages, text, format, options)
}

/// Parse `text` as `format`, whatever the file's extension.
pub fn parse_profile_as(
    path_for_messages: &Path,
    text: &str,
    format: ProfileFormat,
    options: &ImportOptions,
) -> Result<ProfileFile, ProfileImportError> {
    let path = path_for_messages;
    if let Some(u) = options.length_unit
        && !(u.is_finite() && u > 0.0)
    {
        return Err(ProfileImportError::InvalidOption {
            path: path.to_path_buf(),
            rule: format!(
                "length_unit must be a finite positive number of metres per file unit, got {u}"
            ),
        });
    }
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let ext_kind = extension_kind(path);
    let raw = match format {
        ProfileFormat::Simpack => simpack::parse(path, text, ext_kind)?,
        ProfileFormat::Plain => columns::parse_plain(path, text)?,
        ProfileFormat::Csv => columns::parse_csv(path, text)?,
    };
    finish(path, format, raw, ext_kind, options)
}

/// The format `parse_profile` reads `text` (the content of `path`) as:
/// `.prw`/`.prr` → SIMPACK, `.csv` → CSV (extensions case-insensitive);
/// otherwise SIMPACK if the first statement (after `!` comments and blank
/// lines) is `header.begin` or `spline.begin`, else plain.
pub fn detect_format(path: &Path, text: &str) -> ProfileFormat {
    match extension(path).as_deref() {
        Some("prw" | "prr") => return ProfileFormat::Simpack,
        Some("csv") => return ProfileFormat::Csv,
        _ => {}
    }
    let first = text
        .lines()
        .map(|l| l.split('!').next().unwrap_or("").trim())
        .find(|l| !l.is_empty())
        .map(|l| l.trim_start_matches('\u{feff}').to_ascii_lowercase());
    match first.as_deref() {
        Some("header.begin" | "spline.begin") => ProfileFormat::Simpack,
        _ => ProfileFormat::Plain,
    }
}

fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

fn extension_kind(path: &Path) -> Option<ProfileKind> {
    match extension(path).as_deref() {
        Some("prw") => Some(ProfileKind::Wheel),
        Some("prr") => Some(ProfileKind::Rail),
        _ => None,
    }
}

/// One point as read, in file units, with its source line.
#[derive(Debug, Clone, Copy, PartialEq)]
struct RawPoint {
    y: f64,
    z: f64,
    weight: f64,
    line: usize,
}

/// What a format parser hands to [`finish`]: points in file units after the
/// format's own processing (except the unit conversion).
#[derive(Debug, Clone)]
struct RawProfile {
    points: Vec<RawPoint>,
    /// Points in the file before processing.
    in_file: usize,
    /// Line where the point data end (for "too few points").
    end_line: usize,
    /// File units per metre of the y and the z values (1000 for mm):
    /// metres = value / per_m, which keeps decimal millimetres exact to
    /// rounding.
    per_m: [f64; 2],
    z_down: bool,
    kind: Option<ProfileKind>,
    comment: Option<String>,
    simpack: Option<SimpackSettings>,
}

/// Units, options, and the checks common to all formats.
fn finish(
    path: &Path,
    format: ProfileFormat,
    raw: RawProfile,
    ext_kind: Option<ProfileKind>,
    options: &ImportOptions,
) -> Result<ProfileFile, ProfileImportError> {
    let per_m = options
        .length_unit
        .map_or(raw.per_m, |u| [1.0 / u, 1.0 / u]);
    let sy = if options.mirror_y { -1.0 } else { 1.0 };
    let sz = if options.mirror_z { -1.0 } else { 1.0 };

    let n = raw.points.len();
    let mut points_m = Vec::with_capacity(n);
    let mut lines = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    for p in &raw.points {
        let y = sy * p.y / per_m[0];
        let z = sz * p.z / per_m[1];
        for (v, what) in [(y, "y"), (z, "z")] {
            if !v.is_finite() {
                return Err(ProfileImportError::NonFinite {
                    path: path.to_path_buf(),
                    line: p.line,
                    column: None,
                    what: format!("{what} after processing and unit conversion"),
                    text: v.to_string(),
                });
            }
        }
        points_m.push([y, z]);
        lines.push(p.line);
        weights.push(p.weight);
    }

    if n < MIN_POINTS {
        return Err(ProfileImportError::TooFewPoints {
            path: path.to_path_buf(),
            line: raw.end_line.max(1),
            found: n,
            in_file: raw.in_file,
            min: MIN_POINTS,
        });
    }
    for i in 1..n {
        if points_m[i] == points_m[i - 1] {
            return Err(ProfileImportError::DuplicatePoint {
                path: path.to_path_buf(),
                line: lines[i],
                previous_line: lines[i - 1],
                y_m: points_m[i][0],
                z_m: points_m[i][1],
            });
        }
    }
    let y_order = y_order(&points_m, &lines);

    Ok(ProfileFile {
        path: path.to_path_buf(),
        format,
        kind: raw.kind.or(ext_kind),
        points_m,
        lines,
        weights,
        z_down: raw.z_down,
        y_order,
        comment: raw.comment,
        simpack: raw.simpack,
    })
}

/// Direction of y along the points (at least two points).
fn y_order(points: &[[f64; 2]], lines: &[usize]) -> YOrder {
    let first = points[1][0] - points[0][0];
    if first == 0.0 {
        return YOrder::NotMonotone {
            index: 1,
            line: lines[1],
        };
    }
    let increasing = first > 0.0;
    for i in 2..points.len() {
        let d = points[i][0] - points[i - 1][0];
        if (increasing && d <= 0.0) || (!increasing && d >= 0.0) {
            return YOrder::NotMonotone {
                index: i,
                line: lines[i],
            };
        }
    }
    if increasing {
        YOrder::Increasing
    } else {
        YOrder::Decreasing
    }
}

/// [`parse_number`] (the workspace's one number reader) with the error
/// located at `line` and `column` (1-based field of a row, if any) and
/// described by `what`.
fn number(
    path: &Path,
    line: usize,
    column: Option<usize>,
    what: impl Fn() -> String,
    token: &str,
) -> Result<f64, ProfileImportError> {
    parse_number(token).map_err(|e| match e {
        NumberError::NotANumber => ProfileImportError::NotANumber {
            path: path.to_path_buf(),
            line,
            column,
            what: what(),
            text: token.to_string(),
        },
        NumberError::NonFinite => ProfileImportError::NonFinite {
            path: path.to_path_buf(),
            line,
            column,
            what: what(),
            text: token.to_string(),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plain(text: &str) -> Result<ProfileFile, ProfileImportError> {
        parse_profile(Path::new("p.dat"), text, &ImportOptions::default())
    }

    const SQUARE: &str = "0 0\n1 1\n2 4\n3 9\n";

    #[test]
    fn numbers_accept_common_spellings_and_refuse_the_rest() {
        for (t, v) in [
            ("1", 1.0),
            ("+1.5e+03", 1500.0),
            ("-.5", -0.5),
            ("6.9612628E+01", 69.612628),
            ("1.5D+03", 1500.0),
            ("2d-1", 0.2),
        ] {
            assert_eq!(parse_number(t).ok(), Some(v), "{t}");
        }
        for t in ["abc", "1,5", "d3", "", "1e", "--1"] {
            assert!(
                matches!(parse_number(t), Err(NumberError::NotANumber)),
                "{t}"
            );
        }
        for t in ["inf", "-inf", "NaN", "1e999", "1d999"] {
            assert!(
                matches!(parse_number(t), Err(NumberError::NonFinite)),
                "{t}"
            );
        }
    }

    #[test]
    fn format_detection_by_extension_then_content() {
        let p = |s: &str| Path::new(s).to_path_buf();
        assert_eq!(detect_format(&p("a.PRW"), "1 2"), ProfileFormat::Simpack);
        assert_eq!(detect_format(&p("a.prr"), ""), ProfileFormat::Simpack);
        assert_eq!(
            detect_format(&p("a.Csv"), "header.begin"),
            ProfileFormat::Csv
        );
        assert_eq!(
            detect_format(&p("a.txt"), "! c\n\n  Header.Begin\n"),
            ProfileFormat::Simpack
        );
        assert_eq!(
            detect_format(&p("a.txt"), "spline.begin ! x"),
            ProfileFormat::Simpack
        );
        assert_eq!(
            detect_format(&p("a.txt"), "# c\n1 2\n"),
            ProfileFormat::Plain
        );
        assert_eq!(detect_format(&p("noext"), ""), ProfileFormat::Plain);
    }

    #[test]
    fn length_unit_override_and_mirrors_apply_after_the_format() {
        let f = plain(SQUARE).unwrap();
        assert_eq!(f.points_m[3], [3e-3, 9e-3]);
        let o = ImportOptions {
            length_unit: Some(1.0),
            mirror_y: true,
            mirror_z: false,
        };
        let f = parse_profile(Path::new("p.dat"), SQUARE, &o).unwrap();
        assert_eq!(f.points_m[3], [-3.0, 9.0]);
        assert_eq!(f.y_order, YOrder::Decreasing);
        assert!(!f.z_down, "options do not change the documented convention");
        let o = ImportOptions {
            mirror_z: true,
            ..Default::default()
        };
        let f = parse_profile(Path::new("p.dat"), SQUARE, &o).unwrap();
        assert_eq!(f.points_m[2], [2e-3, -4e-3]);
    }

    #[test]
    fn invalid_length_unit_is_refused() {
        for u in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let o = ImportOptions {
                length_unit: Some(u),
                ..Default::default()
            };
            let e = parse_profile(Path::new("p.dat"), SQUARE, &o).unwrap_err();
            assert!(
                matches!(e, ProfileImportError::InvalidOption { .. }),
                "{u}: {e}"
            );
            assert_eq!(e.line(), None);
            assert_eq!(e.path(), Path::new("p.dat"));
        }
    }

    #[test]
    fn y_order_is_reported_not_repaired() {
        assert_eq!(plain(SQUARE).unwrap().y_order, YOrder::Increasing);
        assert!(plain(SQUARE).unwrap().y_monotone());
        assert_eq!(
            plain("3 0\n2 1\n1 2\n0 3\n").unwrap().y_order,
            YOrder::Decreasing
        );
        // A vertical face: y repeats at the third point (line 3).
        let f = plain("0 0\n1 0\n1 1\n2 1\n").unwrap();
        assert_eq!(f.y_order, YOrder::NotMonotone { index: 2, line: 3 });
        assert!(!f.y_monotone());
        assert_eq!(f.points_m[2], [1e-3, 1e-3], "not reordered");
        // Repeated y on the first step.
        let f = plain("0 0\n0 1\n1 1\n2 1\n").unwrap();
        assert_eq!(f.y_order, YOrder::NotMonotone { index: 1, line: 2 });
        // Turning back (an overhang), line numbers count comments.
        let f = plain("# c\n0 0\n1 0\n2 1\n1.5 2\n").unwrap();
        assert_eq!(f.y_order, YOrder::NotMonotone { index: 3, line: 5 });
    }

    #[test]
    fn too_few_points_and_duplicates() {
        let e = plain("0 0\n1 1\n2 2\n").unwrap_err();
        assert!(
            matches!(
                e,
                ProfileImportError::TooFewPoints {
                    found: 3,
                    in_file: 3,
                    min: 4,
                    line: 3,
                    ..
                }
            ),
            "{e}"
        );
        let e = plain("0 0\n1 1\n1 1\n2 2\n3 3\n").unwrap_err();
        assert!(
            matches!(
                e,
                ProfileImportError::DuplicatePoint {
                    line: 3,
                    previous_line: 2,
                    ..
                }
            ),
            "{e}"
        );
        // Equal but not consecutive is fine (a closed outline, say).
        assert!(plain("0 0\n1 1\n2 0\n0 0\n").is_ok());
    }

    #[test]
    fn error_at_names_the_points_line() {
        let f = plain("# header\n0 0\n\n1 1\n2 4\n3 9\n").unwrap();
        assert_eq!(f.lines, vec![2, 4, 5, 6]);
        let e = f.error_at(1, "not convex");
        assert_eq!(e.line(), Some(4));
        assert_eq!(e.to_string(), "'p.dat', line 4: not convex");
        assert_eq!(f.error_at(99, "x").line(), Some(6));
        assert_eq!(f.y_range_m(), (0.0, 3e-3));
        assert_eq!(f.z_range_m(), (0.0, 9e-3));
        assert_eq!(f.len(), 4);
        assert!(!f.is_empty());
    }

    /// Every format, by extension and by content, and read from a file:
    /// a UTF-8 byte order mark (Windows editors write one) is not data.
    #[test]
    fn a_byte_order_mark_is_ignored_in_every_format() {
        let simpack = |t: i64| {
            format!(
                "header.begin\nversion = 1\ntype = {t}\nheader.end\nspline.begin\npoint.begin\n0 0\n1 1\n2 4\n3 9\npoint.end\nspline.end\n"
            )
        };
        let bare = "spline.begin\npoint.begin\n0 0\n1 1\n2 4\n3 9\npoint.end\nspline.end\n";
        let cases = [
            ("w.prw", simpack(1), ProfileFormat::Simpack),
            ("r.prr", simpack(0), ProfileFormat::Simpack),
            ("p.txt", bare.to_string(), ProfileFormat::Simpack),
            ("p.dat", SQUARE.to_string(), ProfileFormat::Plain),
            (
                "p.csv",
                format!("y_mm,z_mm\n{}", SQUARE.replace(' ', ",")),
                ProfileFormat::Csv,
            ),
            (
                "q.csv",
                format!("# c\ny,z\n{}", SQUARE.replace(' ', ",")),
                ProfileFormat::Csv,
            ),
        ];
        let dir = std::env::temp_dir().join(format!("profile_bom_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (name, text, format) in cases {
            let plain = parse_profile(Path::new(name), &text, &ImportOptions::default())
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let with_bom = format!("\u{feff}{text}");
            let f = parse_profile(Path::new(name), &with_bom, &ImportOptions::default())
                .unwrap_or_else(|e| panic!("{name} with a BOM: {e}"));
            assert_eq!(f.format, format, "{name}");
            assert_eq!(f.points_m, plain.points_m, "{name}");
            assert_eq!(f.lines, plain.lines, "{name}");
            let path = dir.join(name);
            std::fs::write(&path, with_bom.as_bytes()).unwrap();
            let f = read_profile(&path, &ImportOptions::default())
                .unwrap_or_else(|e| panic!("{name} read with a BOM: {e}"));
            assert_eq!(f.points_m, plain.points_m, "{name}");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    /// A number that does not parse names the file, the line and the
    /// column (field) in every format.
    #[test]
    fn a_bad_number_names_file_line_and_column() {
        let cases = [
            ("p.dat", "0 0\n1 1\n2 x4\n3 9\n", 3, 2),
            ("p.dat", "0 0\n1,1\nq,4\n3 9\n", 3, 1),
            ("p.csv", "z_mm,y_mm\n0,0\n1,1\n2,4\n9,3o\n", 5, 2),
            (
                "r.prr",
                "spline.begin\npoint.begin\n0 0\n1 1\n2 4 1e\n3 9\npoint.end\nspline.end\n",
                5,
                3,
            ),
        ];
        for (name, text, line, column) in cases {
            let e = parse_profile(Path::new(name), text, &ImportOptions::default()).unwrap_err();
            assert!(
                matches!(e, ProfileImportError::NotANumber { column: Some(c), .. } if c == column),
                "{name}: {e:?}"
            );
            assert!(
                e.to_string()
                    .starts_with(&format!("'{name}', line {line}, column {column}: ")),
                "{e}"
            );
        }
    }
}
