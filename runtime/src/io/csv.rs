//! The one reader of the workspace's numeric text tables (docs/reference/02-inputs.md §2): the
//! track pre-processor's CSV inputs (`preproc::csv`), the CSV and plain
//! two-column profile files ([`crate::io::profile_import`]) and DYTSI's RSGEO
//! contact tables (`preproc::rsgeo`).
//!
//! # What it reads
//!
//! * [`read_text`]: the bytes of a file as UTF-8 text; bytes that are not
//!   UTF-8 are an error naming the line and column where they are.
//! * [`data_lines`]: the lines that carry data, numbered from 1 as an
//!   editor shows them; blank lines and lines whose first non-blank
//!   character is `#` are comments. A UTF-8 byte-order mark (U+FEFF, which
//!   some editors write at the start of a file) is not part of the text
//!   ([`strip_bom`]).
//! * [`split_fields`]: the fields of one line, trimmed, for either
//!   [`Separator`]:
//!   - [`Separator::Comma`]: CSV (RFC 4180) through the `csv` crate, so a
//!     quoted field may hold a comma; an empty field is kept (and then
//!     reported);
//!   - [`Separator::Whitespace`]: runs of blanks and tabs. The `csv` crate
//!     does not read this: it splits at every occurrence of a one-byte
//!     delimiter, so the column-aligned files these are (RSGEO rows padded
//!     with several spaces, its header separated by tabs, plain profiles
//!     `y z` with any blanks between) would read as rows of empty fields.
//!     The split is `str::split_whitespace`.
//! * [`parse_number`]: one numeric token, finite, in Rust/C syntax or with
//!   a Fortran `D` exponent (`1.5D+03`, as Fortran codes write).
//! * [`CsvTable::parse`] (and [`CsvTable::read`] for a file): a header row
//!   naming the columns (trimmed, lower-cased, unique, not numbers), then
//!   rows of as many numbers; the comments above the header are kept.
//!
//! Formats with their own line grammar (SIMPACK's blocks, plain profiles'
//! comments after `!` or `%` anywhere in a line) split their lines
//! themselves and use [`split_fields`] and [`parse_number`] for the rest.
//!
//! Every error names the file, the 1-based line and the column where there
//! are ones ([`CsvError`]); callers turn it into their own error types and
//! keep its structured fields.

use std::path::{Path, PathBuf};

/// How the fields of a line are separated (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Separator {
    /// Commas, RFC 4180 quoting.
    Comma,
    /// Runs of white space.
    Whitespace,
}

/// Why a token is not a usable number.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NumberError {
    /// Not a number at all.
    NotANumber,
    /// A number, but infinite or NaN.
    NonFinite,
}

/// Parse one numeric token (trimmed by the caller). Accepts Rust/C float
/// syntax (`+1.5e+03`, `.5`) and Fortran `D` exponents (`1.5D+03`); the
/// value must be finite.
pub fn parse_number(token: &str) -> Result<f64, NumberError> {
    let v = match token.parse::<f64>() {
        Ok(v) => v,
        Err(_) => {
            let fortran = token.replace(['d', 'D'], "e");
            if fortran == token
                || !token
                    .bytes()
                    .next()
                    .is_some_and(|b| b.is_ascii_digit() || b"+-.".contains(&b))
            {
                return Err(NumberError::NotANumber);
            }
            fortran
                .parse::<f64>()
                .map_err(|_| NumberError::NotANumber)?
        }
    };
    if v.is_finite() {
        Ok(v)
    } else {
        Err(NumberError::NonFinite)
    }
}

/// The UTF-8 byte-order mark, U+FEFF.
const BOM: char = '\u{feff}';

/// `text` without a leading UTF-8 byte-order mark: editors on Windows
/// write one at the start of a file; it is not part of the first line's
/// content (the Unicode Standard, §23.8 "Byte Order Mark"), and left in
/// place it would glue an invisible character to the first header name or
/// hide a `#` comment.
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix(BOM).unwrap_or(text)
}

/// Read the file `path` as UTF-8 text. Bytes that are not UTF-8 (a file
/// saved as Latin-1 or Windows-1252, a binary file) are a
/// [`CsvError::Encoding`] naming the 1-based line and character column of
/// the first such byte.
pub fn read_text(path: &Path) -> Result<String, CsvError> {
    let bytes = std::fs::read(path).map_err(|source| CsvError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    decode_utf8(path, bytes)
}

/// `bytes` (the content of `path`) as UTF-8 text, or a
/// [`CsvError::Encoding`] naming where the first byte that is not UTF-8 is.
pub fn decode_utf8(path: &Path, bytes: Vec<u8>) -> Result<String, CsvError> {
    String::from_utf8(bytes).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let valid = &bytes[..at];
        let line_start = valid.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
        // The prefix is valid UTF-8 by construction.
        let column = std::str::from_utf8(&valid[line_start..]).map_or(1, |l| l.chars().count() + 1);
        CsvError::Encoding {
            path: path.to_path_buf(),
            line: valid.iter().filter(|&&b| b == b'\n').count() + 1,
            column,
            byte: bytes[at],
        }
    })
}

/// The lines of `text` that carry data: (1-based line number, trimmed
/// text); blank lines and lines starting with `#` (after blanks) are
/// skipped, and a leading byte-order mark is ignored ([`strip_bom`]).
pub fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    strip_bom(text)
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
}

/// The trimmed fields of one line (module docs). A comma-separated line
/// that the CSV grammar cannot read (it never happens for one line of
/// text, but the crate's reader is fallible) falls back to a plain split
/// at commas.
pub fn split_fields(line: &str, separator: Separator) -> Vec<String> {
    match separator {
        Separator::Whitespace => line.split_whitespace().map(str::to_string).collect(),
        Separator::Comma => {
            let mut reader = comma_reader(line.as_bytes());
            let mut record = csv::StringRecord::new();
            match reader.read_record(&mut record) {
                Ok(true) => record.iter().map(str::to_string).collect(),
                Ok(false) => vec![String::new()],
                Err(_) => line.split(',').map(|f| f.trim().to_string()).collect(),
            }
        }
    }
}

/// A `csv` reader of comma-separated records: no header handling (done
/// here), rows of any length (checked here, with a better message), fields
/// trimmed.
fn comma_reader<R: std::io::Read>(input: R) -> csv::Reader<R> {
    csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(input)
}

/// Why a table could not be read. Every variant names the file; those
/// about its content the 1-based line, and the column where there is one.
#[derive(Debug, thiserror::Error)]
pub enum CsvError {
    #[error("cannot read '{}': {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{}, line {line}, column {column}: {}", path.display(), self.rule())]
    Encoding {
        path: PathBuf,
        line: usize,
        /// 1-based character column of the first byte that is not UTF-8.
        column: usize,
        /// That byte.
        byte: u8,
    },
    #[error("{}: {}", path.display(), self.rule())]
    Empty { path: PathBuf },
    #[error("{}, line {line}: {}", path.display(), self.rule())]
    Syntax {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{}, line {line}: {}", path.display(), self.rule())]
    HeaderNumber {
        path: PathBuf,
        line: usize,
        /// The header field that reads as a number.
        text: String,
    },
    #[error("{}, line {line}: {}", path.display(), self.rule())]
    HeaderUnnamed {
        path: PathBuf,
        line: usize,
        /// 1-based column.
        column: usize,
    },
    #[error("{}, line {line}: {}", path.display(), self.rule())]
    HeaderDuplicate {
        path: PathBuf,
        line: usize,
        name: String,
    },
    #[error("{}, line {line}: {}", path.display(), self.rule())]
    FieldCount {
        path: PathBuf,
        line: usize,
        /// The header's column names.
        columns: Vec<String>,
        found: usize,
    },
    #[error("{}, line {line}: {}", path.display(), self.rule())]
    NotANumber {
        path: PathBuf,
        line: usize,
        /// 1-based column.
        column: usize,
        name: String,
        text: String,
    },
    #[error("{}, line {line}: {}", path.display(), self.rule())]
    NonFinite {
        path: PathBuf,
        line: usize,
        /// 1-based column.
        column: usize,
        name: String,
        text: String,
    },
}

impl CsvError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Read { path, .. }
            | Self::Encoding { path, .. }
            | Self::Empty { path }
            | Self::Syntax { path, .. }
            | Self::HeaderNumber { path, .. }
            | Self::HeaderUnnamed { path, .. }
            | Self::HeaderDuplicate { path, .. }
            | Self::FieldCount { path, .. }
            | Self::NotANumber { path, .. }
            | Self::NonFinite { path, .. } => path,
        }
    }

    /// The 1-based line, when the error is about one.
    pub fn line(&self) -> Option<usize> {
        match self {
            Self::Read { .. } | Self::Empty { .. } => None,
            Self::Encoding { line, .. }
            | Self::Syntax { line, .. }
            | Self::HeaderNumber { line, .. }
            | Self::HeaderUnnamed { line, .. }
            | Self::HeaderDuplicate { line, .. }
            | Self::FieldCount { line, .. }
            | Self::NotANumber { line, .. }
            | Self::NonFinite { line, .. } => Some(*line),
        }
    }

    /// The 1-based column, when the error is about one value (or one
    /// byte).
    pub fn column(&self) -> Option<usize> {
        match self {
            Self::Encoding { column, .. }
            | Self::HeaderUnnamed { column, .. }
            | Self::NotANumber { column, .. }
            | Self::NonFinite { column, .. } => Some(*column),
            _ => None,
        }
    }

    /// The rule broken, without the file and the line.
    pub fn rule(&self) -> String {
        match self {
            Self::Read { source, .. } => source.to_string(),
            Self::Encoding { byte, .. } => format!(
                "byte 0x{byte:02x} is not UTF-8 (the file is in another encoding, e.g. Latin-1); save it as UTF-8"
            ),
            Self::Empty { .. } => "the file is empty (expected a header row)".into(),
            Self::Syntax { message, .. } => message.clone(),
            Self::HeaderNumber { text, .. } => {
                format!("expected a header row naming the columns, found the number '{text}'")
            }
            Self::HeaderUnnamed { column, .. } => format!("header column {column} has no name"),
            Self::HeaderDuplicate { name, .. } => format!("column '{name}' appears twice"),
            Self::FieldCount { columns, found, .. } => format!(
                "expected {} values ({}), found {found}",
                columns.len(),
                columns.join(", ")
            ),
            Self::NotANumber { name, text, .. } => {
                format!("column '{name}': '{text}' is not a number")
            }
            Self::NonFinite { name, text, .. } => {
                format!("column '{name}': non-finite value '{text}'")
            }
        }
    }
}

/// A numeric table with a header row (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct CsvTable {
    /// The file as named by the user (for messages).
    pub path: PathBuf,
    /// The comment lines above the header, without their `#` and blanks.
    pub preamble: Vec<String>,
    /// 1-based line of the header row.
    pub header_line: usize,
    /// Column names, trimmed and lower-cased, in file order.
    pub columns: Vec<String>,
    /// Data rows: (1-based line number, values in column order).
    pub rows: Vec<(usize, Vec<f64>)>,
}

impl CsvTable {
    /// Read the file `path` (module docs).
    pub fn read(path: &Path, separator: Separator) -> Result<Self, CsvError> {
        Self::parse(path, &read_text(path)?, separator)
    }

    /// Parse `text`, the content of `path` (named in errors). Pure: does
    /// not touch the file system.
    pub fn parse(path: &Path, text: &str, separator: Separator) -> Result<Self, CsvError> {
        let p = || path.to_path_buf();
        let text = strip_bom(text);
        let preamble = text
            .lines()
            .map(str::trim)
            .take_while(|l| l.is_empty() || l.starts_with('#'))
            .filter_map(|l| l.strip_prefix('#'))
            .map(|c| c.trim_start_matches('#').trim().to_string())
            .collect();
        let mut records = records(text, separator);
        let (header_line, header) = match records.next() {
            None => return Err(CsvError::Empty { path: p() }),
            Some(r) => r.map_err(|(line, message)| CsvError::Syntax {
                path: p(),
                line,
                message,
            })?,
        };
        // A quoted name after a blank (`x, "y"`) is not a CSV quoted field:
        // its quotes are removed here.
        let columns: Vec<String> = header
            .iter()
            .map(|c| c.trim_matches('"').trim().to_ascii_lowercase())
            .collect();
        for (i, c) in columns.iter().enumerate() {
            if c.is_empty() {
                return Err(CsvError::HeaderUnnamed {
                    path: p(),
                    line: header_line,
                    column: i + 1,
                });
            }
            if parse_number(c) != Err(NumberError::NotANumber) {
                return Err(CsvError::HeaderNumber {
                    path: p(),
                    line: header_line,
                    text: c.clone(),
                });
            }
            if columns[..i].contains(c) {
                return Err(CsvError::HeaderDuplicate {
                    path: p(),
                    line: header_line,
                    name: c.clone(),
                });
            }
        }

        let mut rows = Vec::new();
        for record in records {
            let (line, fields) = record.map_err(|(line, message)| CsvError::Syntax {
                path: p(),
                line,
                message,
            })?;
            if fields.len() != columns.len() {
                return Err(CsvError::FieldCount {
                    path: p(),
                    line,
                    columns: columns.clone(),
                    found: fields.len(),
                });
            }
            let mut values = Vec::with_capacity(fields.len());
            for (k, (f, c)) in fields.iter().zip(&columns).enumerate() {
                let v = parse_number(f).map_err(|e| {
                    let (path, column, name, text) = (p(), k + 1, c.clone(), f.clone());
                    match e {
                        NumberError::NotANumber => CsvError::NotANumber {
                            path,
                            line,
                            column,
                            name,
                            text,
                        },
                        NumberError::NonFinite => CsvError::NonFinite {
                            path,
                            line,
                            column,
                            name,
                            text,
                        },
                    }
                })?;
                values.push(v);
            }
            rows.push((line, values));
        }
        Ok(Self {
            path: path.to_path_buf(),
            preamble,
            header_line,
            columns,
            rows,
        })
    }

    /// Index of column `name`, if present.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c == name)
    }

    /// Values of column `idx`.
    pub fn values(&self, idx: usize) -> Vec<f64> {
        self.rows.iter().map(|(_, v)| v[idx]).collect()
    }

    /// Line number of data row `row` (0-based).
    pub fn line(&self, row: usize) -> usize {
        self.rows[row].0
    }
}

/// The records of a table's data lines: (1-based line, trimmed fields),
/// or (line, message) for a record the `csv` crate refuses.
type Record = Result<(usize, Vec<String>), (usize, String)>;

/// The records of `text` (module docs), read lazily.
fn records<'a>(text: &'a str, separator: Separator) -> Box<dyn Iterator<Item = Record> + 'a> {
    match separator {
        Separator::Whitespace => Box::new(
            data_lines(text).map(|(line, l)| Ok((line, split_fields(l, Separator::Whitespace)))),
        ),
        Separator::Comma => {
            // Comments and blank lines are removed first (the `csv` crate's
            // comment character counts only at the very start of a line),
            // remembering where each kept line was.
            let (lines, kept): (Vec<usize>, Vec<&str>) = data_lines(text).unzip();
            let mut reader = comma_reader(std::io::Cursor::new(kept.join("\n").into_bytes()));
            let mut record = csv::StringRecord::new();
            Box::new(std::iter::from_fn(move || {
                let at = |position: Option<&csv::Position>| {
                    let k = position.map_or(1, csv::Position::line) as usize;
                    lines.get(k.saturating_sub(1)).copied().unwrap_or(0)
                };
                match reader.read_record(&mut record) {
                    Ok(false) => None,
                    Ok(true) => Some(Ok((
                        at(record.position()),
                        record.iter().map(str::to_string).collect(),
                    ))),
                    Err(e) => Some(Err((at(e.position()), e.to_string()))),
                }
            }))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<CsvTable, CsvError> {
        CsvTable::parse(Path::new("t.csv"), text, Separator::Comma)
    }

    #[test]
    fn reads_header_rows_comments_and_blanks() {
        let t = parse("# a comment\n## two\nx, Y ,\"z\"\n\n1,2,3\n  # mid\n 4 , 5 , 6 \n").unwrap();
        assert_eq!(t.columns, ["x", "y", "z"]);
        assert_eq!(t.header_line, 3);
        assert_eq!(t.preamble, ["a comment", "two"]);
        assert_eq!(
            t.rows,
            vec![(5, vec![1.0, 2.0, 3.0]), (7, vec![4.0, 5.0, 6.0])]
        );
        assert_eq!(t.values(1), [2.0, 5.0]);
        assert_eq!(t.column("z"), Some(2));
        assert_eq!(t.line(1), 7);
        // A quoted header name may hold the separator.
        let t = parse("\"a,b\", \"C\"\n1,2\n").unwrap();
        assert_eq!(t.columns, ["a,b", "c"]);
        // White space: runs of blanks and tabs; Fortran exponents.
        let t = CsvTable::parse(
            Path::new("w.dat"),
            "a\tb\n1   2.5D+01\n",
            Separator::Whitespace,
        )
        .unwrap();
        assert_eq!(t.rows, vec![(2, vec![1.0, 25.0])]);
    }

    #[test]
    fn errors_name_file_line_column_and_rule() {
        let e = parse("x,y,z\n1,2,3\n1,abc,3\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv, line 3: column 'y': 'abc' is not a number"
        );
        assert!(
            matches!(
                e,
                CsvError::NotANumber {
                    line: 3,
                    column: 2,
                    ..
                }
            ),
            "{e:?}"
        );
        let e = parse("x,y,z\n1,2\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv, line 2: expected 3 values (x, y, z), found 2"
        );
        let e = parse("x,y,z\n1,NaN,2\n").unwrap_err();
        assert!(matches!(e, CsvError::NonFinite { column: 2, .. }), "{e:?}");
        assert!(e.to_string().contains("non-finite"), "{e}");
        let e = parse("x,y,z\n1,inf,2\n").unwrap_err();
        assert!(e.to_string().contains("non-finite"), "{e}");
        let e = parse("# only a comment\n").unwrap_err();
        assert_eq!(
            (e.line(), e.to_string()),
            (
                None,
                "t.csv: the file is empty (expected a header row)".into()
            )
        );
        let e = parse("1,2,3\n4,5,6\n").unwrap_err();
        assert!(matches!(e, CsvError::HeaderNumber { line: 1, .. }), "{e:?}");
        assert!(e.to_string().contains("header"), "{e}");
        let e = parse("x,x\n1,2\n").unwrap_err();
        assert!(e.to_string().contains("twice"), "{e}");
        let e = parse("x,,z\n1,2,3\n").unwrap_err();
        assert!(
            matches!(e, CsvError::HeaderUnnamed { column: 2, .. }),
            "{e:?}"
        );
        assert_eq!(e.path(), Path::new("t.csv"));
        let e = CsvTable::read(Path::new("/no/such/file.csv"), Separator::Comma).unwrap_err();
        assert!(
            matches!(e, CsvError::Read { .. }) && e.line().is_none(),
            "{e:?}"
        );
    }

    /// A byte-order mark at the start is not part of the text: the first
    /// header name and a first `#` comment read as without it.
    #[test]
    fn a_byte_order_mark_is_ignored() {
        let t = parse("\u{feff}x,y\n1,2\n").unwrap();
        assert_eq!(t.columns, ["x", "y"]);
        let t = parse("\u{feff}# made on Windows\nx,y\n1,2\n").unwrap();
        assert_eq!(
            (t.header_line, t.columns.clone()),
            (2, vec!["x".into(), "y".into()])
        );
        assert_eq!(t.preamble, ["made on Windows"]);
        assert_eq!(
            data_lines("\u{feff}# c\n1 2\n").collect::<Vec<_>>(),
            [(2, "1 2")]
        );
        let t = CsvTable::parse(
            Path::new("w.dat"),
            "\u{feff}a b\n1 2\n",
            Separator::Whitespace,
        )
        .unwrap();
        assert_eq!(t.columns, ["a", "b"]);
    }

    /// Bytes that are not UTF-8 are reported at their line and column.
    #[test]
    fn bytes_that_are_not_utf8_are_located() {
        let bytes = b"x,y\n1,2\n3,4 \xb0\n".to_vec();
        let e = decode_utf8(Path::new("t.csv"), bytes).unwrap_err();
        assert!(
            matches!(
                e,
                CsvError::Encoding {
                    line: 3,
                    column: 5,
                    byte: 0xb0,
                    ..
                }
            ),
            "{e:?}"
        );
        assert_eq!((e.line(), e.column()), (Some(3), Some(5)));
        assert!(
            e.to_string()
                .starts_with("t.csv, line 3, column 5: byte 0xb0 is not UTF-8"),
            "{e}"
        );
        // Multi-byte characters before it count as one column each.
        let e = decode_utf8(
            Path::new("t.csv"),
            "é\u{fc}".bytes().chain([0xff]).collect(),
        )
        .unwrap_err();
        assert_eq!((e.line(), e.column()), (Some(1), Some(3)));
        assert_eq!(
            decode_utf8(Path::new("t.csv"), b"ok".to_vec()).unwrap(),
            "ok"
        );
        let dir = std::env::temp_dir().join(format!("csv-utf8-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("latin1.csv");
        std::fs::write(&f, b"x,y\n\xe9,2\n").unwrap();
        let e = CsvTable::read(&f, Separator::Comma).unwrap_err();
        assert_eq!((e.line(), e.column()), (Some(2), Some(1)));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn numbers_and_fields() {
        assert_eq!(parse_number("+1.5e+03"), Ok(1500.0));
        assert_eq!(parse_number(".5"), Ok(0.5));
        assert_eq!(parse_number("1.5D+03"), Ok(1500.0));
        assert_eq!(parse_number("-2d-1"), Ok(-0.2));
        assert_eq!(parse_number("D1"), Err(NumberError::NotANumber));
        assert_eq!(parse_number("0.0.1"), Err(NumberError::NotANumber));
        assert_eq!(parse_number("1e999"), Err(NumberError::NonFinite));
        assert_eq!(parse_number("nan"), Err(NumberError::NonFinite));
        assert_eq!(split_fields(" 1 ,, 2 ", Separator::Comma), ["1", "", "2"]);
        assert_eq!(split_fields("1 \t 2", Separator::Whitespace), ["1", "2"]);
        assert_eq!(
            data_lines("a\n\n # c\n b \n").collect::<Vec<_>>(),
            [(1, "a"), (4, "b")]
        );
    }
}
