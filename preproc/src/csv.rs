//! The numeric CSV files of docs/reference/02-inputs.md §2 (centreline, cant, irregularities): a
//! header row, then rows of numbers separated by commas; blank lines and
//! lines starting with `#` are ignored; spaces around fields are allowed.
//! Read by the workspace's one table reader, [`runtime::io::csv`]; this
//! module adds the pre-processor's rules (row counts, increasing columns,
//! unit suffixes) and its error type. Every error names the file and the
//! line, and the column where it is about one value. A UTF-8 byte-order
//! mark is ignored; bytes that are not UTF-8 are an error at their line
//! and column ([`read_text`]).

use std::path::{Path, PathBuf};

use runtime::io::csv::{CsvError, Separator};

use crate::error::{BuildError, InputError};

/// A numeric table read from a CSV file.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvTable {
    /// The file as named by the user (for messages).
    pub path: PathBuf,
    /// Column names, trimmed and lower-cased, in file order.
    pub columns: Vec<String>,
    /// Data rows: (1-based line number, values in column order).
    pub rows: Vec<(usize, Vec<f64>)>,
}

impl From<CsvError> for InputError {
    fn from(e: CsvError) -> Self {
        match (e.line(), e.column()) {
            (Some(line), Some(column)) => InputError::at_value(e.path(), line, column, e.rule()),
            (line, _) => InputError::new(e.path(), line, e.rule()),
        }
    }
}

/// The text of the input file `path`: UTF-8, or an error at the line and
/// column of the first byte that is not (`runtime::io::csv::read_text`).
pub fn read_text(path: &Path) -> Result<String, BuildError> {
    runtime::io::csv::read_text(path).map_err(|e| match e {
        CsvError::Read { path, source } => BuildError::Read { path, source },
        other => BuildError::Input(other.into()),
    })
}

impl CsvTable {
    /// Parse `text` (the content of `path`).
    pub fn parse(path: &Path, text: &str) -> Result<Self, InputError> {
        let t = runtime::io::csv::CsvTable::parse(path, text, Separator::Comma)?;
        Ok(Self {
            path: t.path,
            columns: t.columns,
            rows: t.rows,
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

    /// An error located at data row `row` (0-based).
    pub fn error_at(&self, row: usize, rule: impl Into<String>) -> InputError {
        InputError::new(&self.path, Some(self.line(row)), rule)
    }

    /// An error about the value in column `idx` (0-based, as
    /// [`CsvTable::column`] returns it) of data row `row` (0-based).
    pub fn error_at_value(&self, row: usize, idx: usize, rule: impl Into<String>) -> InputError {
        InputError::at_value(&self.path, self.line(row), idx + 1, rule)
    }

    /// An error about the whole file.
    pub fn error(&self, rule: impl Into<String>) -> InputError {
        InputError::new(&self.path, None, rule)
    }

    /// Require at least `min` data rows.
    pub fn require_rows(&self, min: usize) -> Result<(), InputError> {
        if self.rows.len() < min {
            return Err(self.error(format!(
                "at least {min} data rows are needed, found {}",
                self.rows.len()
            )));
        }
        Ok(())
    }

    /// Require that column `idx` strictly increases; names the first row
    /// that does not.
    pub fn require_increasing(&self, idx: usize) -> Result<(), InputError> {
        for k in 1..self.rows.len() {
            let (a, b) = (self.rows[k - 1].1[idx], self.rows[k].1[idx]);
            if b <= a {
                return Err(self.error_at(
                    k,
                    format!(
                        "column '{}' must strictly increase: {b} follows {a} (line {})",
                        self.columns[idx],
                        self.line(k - 1)
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// A value column that may carry a unit suffix: `name` in metres/radians or
/// `name_mm` in millimetres. Returns the column index and the factor to SI.
pub fn find_length_column(
    table: &CsvTable,
    name: &str,
) -> Result<Option<(usize, f64)>, InputError> {
    let plain = table.column(name);
    let mm = table.column(&format!("{name}_mm"));
    match (plain, mm) {
        (Some(_), Some(_)) => Err(table.error(format!(
            "columns '{name}' and '{name}_mm' both given; keep one"
        ))),
        (Some(i), None) => Ok(Some((i, 1.0))),
        (None, Some(i)) => Ok(Some((i, 1e-3))),
        (None, None) => Ok(None),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<CsvTable, InputError> {
        CsvTable::parse(Path::new("t.csv"), text)
    }

    #[test]
    fn reads_header_rows_comments_and_blanks() {
        let t = parse("# a comment\nx, Y ,z\n\n1,2,3\n# mid\n 4 , 5 , 6 \n").unwrap();
        assert_eq!(t.columns, ["x", "y", "z"]);
        assert_eq!(
            t.rows,
            vec![(4, vec![1.0, 2.0, 3.0]), (6, vec![4.0, 5.0, 6.0])]
        );
    }

    #[test]
    fn errors_name_file_line_and_rule() {
        let e = parse("x,y,z\n1,2,3\n1,abc,3\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.csv, line 3, column 2: column 'y': 'abc' is not a number"
        );
        let e = parse("x,y,z\n1,2\n").unwrap_err();
        assert!(e.to_string().contains("line 2: expected 3 values"), "{e}");
        let e = parse("x,y,z\n1,NaN,2\n").unwrap_err();
        assert!(e.to_string().contains("non-finite"), "{e}");
        let e = parse("x,y,z\n1,2,inf\n").unwrap_err();
        assert!(
            e.to_string().contains("line 2, column 3") && e.to_string().contains("non-finite"),
            "{e}"
        );
        let e = parse("x,y,z\n1,1e999,2\n").unwrap_err();
        assert!(e.to_string().contains("line 2, column 2"), "{e}");
        let e = parse("# only a comment\n").unwrap_err();
        assert!(e.to_string().contains("empty"), "{e}");
        let e = parse("1,2,3\n4,5,6\n").unwrap_err();
        assert!(e.to_string().contains("header"), "{e}");
        let e = parse("x,x\n1,2\n").unwrap_err();
        assert!(e.to_string().contains("twice"), "{e}");
    }

    /// A byte-order mark (before the header or before a first comment)
    /// is not part of the first line; the columns read as without it.
    #[test]
    fn byte_order_mark() {
        for text in [
            "\u{feff}x,y\n1,2\n",
            "\u{feff}# made on Windows\nx,y\n1,2\n",
        ] {
            let t = parse(text).unwrap();
            assert_eq!(t.columns, ["x", "y"], "{text:?}");
        }
    }

    /// A file that is not UTF-8 is refused at the line and column of its
    /// first byte that is not.
    #[test]
    fn not_utf8_names_the_line_and_column() {
        let dir = std::env::temp_dir().join(format!("preproc-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("latin1.csv");
        std::fs::write(&f, b"x,y,z\n0,0,0\n1,0,0 \xb0\n").unwrap();
        let e = read_text(&f).unwrap_err().to_string();
        assert!(
            e.contains("latin1.csv, line 3, column 7") && e.contains("not UTF-8"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn increasing_and_row_count_rules() {
        let t = parse("s,v\n0,1\n1,1\n1,2\n").unwrap();
        let e = t.require_increasing(0).unwrap_err();
        assert!(e.to_string().contains("line 4"), "{e}");
        assert!(t.require_rows(4).is_err());
        assert!(t.require_rows(3).is_ok());
    }

    #[test]
    fn unit_suffix() {
        let t = parse("s,cant_mm\n0,1\n").unwrap();
        assert_eq!(find_length_column(&t, "cant").unwrap(), Some((1, 1e-3)));
        let t = parse("s,cant,cant_mm\n0,1,2\n").unwrap();
        assert!(find_length_column(&t, "cant").is_err());
    }
}
