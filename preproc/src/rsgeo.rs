//! Reader of DYTSI's `RSGEO.dat` contact geometry tables (the open
//! simulator DYTSI, D. Bigoni, DTU 2011–2014, LGPL-3: `input/RSGEO/1o40/
//! RSGEO.dat`, read there by `RSGEOTableReader`) into a
//! [`runtime::contact::imported::ImportedContactTable`].
//!
//! # Format
//!
//! Lines starting with `#` are comments (the file's first line is `#`);
//! the first other line is the header of thirteen quoted, tab-separated
//! column names, exactly:
//!
//! | col | name | meaning | unit |
//! |---|---|---|---|
//! | 0 | `rh(51)` | wheelset lateral displacement y | m |
//! | 1 | `Normalforce` | quasi-static normal force N0 | N |
//! | 2 | `DATAN(TANDJA(1,1))` | contact angle δ | rad |
//! | 3 | `a(1,1)` | semi-axis, rolling direction | m |
//! | 4 | `b(1,1)` | semi-axis, lateral | m |
//! | 5 | `BJA(2,1,1)+0,75` | contact point on the wheel, lateral from the wheelset centre | m |
//! | 6 | `R0J(1,1)` | rolling radius | m |
//! | 7–9 | `c11` `c22` `c23` | Kalker's coefficients | – |
//! | 10 | `BJA(3,1,1)` | vertical coordinate of the contact point on the rail | m |
//! | 11 | `Penetration` | quasi-static penetration q0 | m |
//! | 12 | `BJA(2,1,1)+0.75+rh(51)` | lateral contact position on the rail (zeros in the shipped file) | m |
//!
//! then one row per lateral displacement, thirteen numbers separated by
//! white space. Column 12 is not read: it is zero throughout the shipped
//! file and DYTSI recomputes it from column 5, y and the roll
//! (`WheelSetComponent::find_rsgeodata`). The rows describe the left wheel
//! (see [`runtime::contact::imported`]). Every rule broken is reported with
//! the file, the line and the rule.
//!
//! Lines, fields and numbers are read by the workspace's one table reader
//! ([`runtime::io::csv`]: comment lines, white-space fields, numbers). The
//! file is not CSV: its columns are aligned with runs of spaces and its
//! header is separated by tabs, so fields are split at runs of white space
//! ([`Separator::Whitespace`]; the names hold no blanks), and this module
//! checks the fixed header and the thirteen values of a row itself, with
//! the messages of this format.

use std::path::Path;

use runtime::contact::imported::{ImportedContactTable, ImportedRow};
use runtime::io::csv::{NumberError, Separator, data_lines, parse_number, split_fields};

use crate::error::InputError;

/// The thirteen column names of the header, in order.
pub const RSGEO_COLUMNS: [&str; 13] = [
    "rh(51)",
    "Normalforce",
    "DATAN(TANDJA(1,1))",
    "a(1,1)",
    "b(1,1)",
    "BJA(2,1,1)+0,75",
    "R0J(1,1)",
    "c11",
    "c22",
    "c23",
    "BJA(3,1,1)",
    "Penetration",
    "BJA(2,1,1)+0.75+rh(51)",
];

/// Why an RSGEO file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RsgeoError {
    #[error("cannot read '{path}': {source}")]
    Read {
        path: std::path::PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(transparent)]
    Input(#[from] InputError),
}

/// Reads an RSGEO file (module docs).
pub fn read_rsgeo(path: &Path) -> Result<ImportedContactTable, RsgeoError> {
    let text = std::fs::read_to_string(path).map_err(|source| RsgeoError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    Ok(parse_rsgeo(&text, path)?)
}

/// Parses the text of an RSGEO file; `path` names it in errors and in the
/// table's `source`.
pub fn parse_rsgeo(text: &str, path: &Path) -> Result<ImportedContactTable, InputError> {
    let err = |line: Option<usize>, rule: String| InputError::new(path, line, rule);
    let mut lines = data_lines(text);
    let (header_line, header) = lines
        .next()
        .ok_or_else(|| err(None, "no header line: the file is empty".into()))?;
    let names: Vec<String> = split_fields(header, Separator::Whitespace)
        .iter()
        .map(|n| n.trim_matches('"').to_string())
        .filter(|n| !n.is_empty())
        .collect();
    if names != RSGEO_COLUMNS {
        return Err(err(
            Some(header_line),
            format!(
                "the header must name the 13 RSGEO columns {:?}, found {} names {:?}",
                RSGEO_COLUMNS,
                names.len(),
                names
            ),
        ));
    }
    let mut y_m = Vec::new();
    let mut rows = Vec::new();
    let mut lines_of_rows = Vec::new();
    for (line, l) in lines {
        // Borrowed fields in a fixed array, split at ASCII whitespace (the
        // format's separators): no String per value and no vector per row,
        // and no Unicode decoding of 4 000 lines of numbers (the split was
        // more than half of reading the Cooperrider table; callgrind).
        let mut fields = [""; RSGEO_COLUMNS.len()];
        let mut count = 0;
        for f in l.split_ascii_whitespace() {
            if let Some(slot) = fields.get_mut(count) {
                *slot = f;
            }
            count += 1;
        }
        if count != RSGEO_COLUMNS.len() {
            return Err(err(
                Some(line),
                format!(
                    "{} values, expected {} (one per header column)",
                    count,
                    RSGEO_COLUMNS.len()
                ),
            ));
        }
        let mut v = [0.0; 13];
        for (k, (f, out)) in fields.iter().zip(v.iter_mut()).enumerate() {
            *out = parse_number(f).map_err(|e| {
                let name = RSGEO_COLUMNS[k];
                let rule = match e {
                    NumberError::NotANumber => {
                        format!("column {k} ({name}) = '{f}' is not a number")
                    }
                    NumberError::NonFinite => format!("column {k} ({name}) = {f} is not finite"),
                };
                err(Some(line), rule)
            })?;
        }
        y_m.push(v[0]);
        let mut r = [0.0; 11];
        r.copy_from_slice(&v[1..12]);
        rows.push(ImportedRow::from_values(&r));
        lines_of_rows.push(line);
    }
    if rows.len() < 2 {
        return Err(err(
            None,
            format!("{} data rows; at least 2 are needed", rows.len()),
        ));
    }
    if let Some(i) = (1..y_m.len()).find(|&i| y_m[i] <= y_m[i - 1]) {
        return Err(err(
            Some(lines_of_rows[i]),
            format!(
                "y = {} m does not increase (previous row {} m)",
                y_m[i],
                y_m[i - 1]
            ),
        ));
    }
    let table = ImportedContactTable {
        source: format!(
            "{} (DYTSI RSGEO contact geometry table; rows describe the left wheel)",
            path.display()
        ),
        format: "rsgeo".into(),
        y_m,
        rows,
    };
    table.validate().map_err(|e| match e {
        runtime::contact::imported::ImportedTableError::Invalid { row: Some(i), rule } => {
            err(Some(lines_of_rows[i]), rule)
        }
        other => err(None, other.to_string()),
    })?;
    Ok(table)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header() -> String {
        let quoted: Vec<String> = RSGEO_COLUMNS.iter().map(|c| format!("\"{c}\"")).collect();
        format!("#\n{}\n", quoted.join("\t"))
    }

    const ROW0: &str = "-1.0e-05 6.6661e+04 1.4e-02 5.95e-03 6.65e-03 7.5632e-01 4.2488e-01 4.12 3.56 1.37 -5.9e-05 7.01e-05 0.0";
    const ROW1: &str = "0.0 6.6661e+04 1.4e-02 5.95e-03 6.65e-03 7.5630e-01 4.2488e-01 4.12 3.56 1.37 -5.9e-05 7.01e-05 0.0";

    #[test]
    fn a_small_file_parses() {
        let text = format!("{}{ROW0}\n{ROW1}\n", header());
        let t = parse_rsgeo(&text, Path::new("x.dat")).unwrap();
        assert_eq!(t.rows.len(), 2);
        assert_eq!(t.y_m, vec![-1e-5, 0.0]);
        assert_eq!(t.rows[1].wheel_lateral_m, 0.7563);
        assert_eq!(t.format, "rsgeo");
        // Tabs and runs of blanks separate values as single spaces do.
        let tabbed = format!("{}{}\n{ROW1}\n", header(), ROW0.replace(' ', "\t  "));
        let u = parse_rsgeo(&tabbed, Path::new("x.dat")).unwrap();
        assert_eq!((u.y_m, u.rows), (t.y_m, t.rows));
    }

    #[test]
    fn errors_name_the_line_and_the_rule() {
        let cases = [
            (
                format!("{}{ROW0}\n{}\n", header(), ROW1.replace("4.12", "x")),
                "line 4",
                "not a number",
            ),
            (
                format!("{}{ROW0}\n{}\n", header(), ROW1.replace(" 0.0", "")),
                "line 4",
                "12 values",
            ),
            (
                // More values than columns: counted past the thirteenth.
                format!("{}{ROW0}\n{ROW1} 1.0 2.0\n", header()),
                "line 4",
                "15 values",
            ),
            (
                format!("{}{ROW1}\n{ROW0}\n", header()),
                "line 4",
                "does not increase",
            ),
            (
                format!("#\n\"rh(51)\"\n{ROW0}\n"),
                "line 2",
                "13 RSGEO columns",
            ),
            (
                format!(
                    "{}{ROW0}\n{}\n",
                    header(),
                    ROW1.replace("7.01e-05", "-7.01e-05")
                ),
                "line 4",
                "penetration",
            ),
            (format!("{}{ROW0}\n", header()), "x.dat", "at least 2"),
            (String::new(), "x.dat", "empty"),
        ];
        for (text, place, rule) in cases {
            let e = parse_rsgeo(&text, Path::new("x.dat"))
                .unwrap_err()
                .to_string();
            assert!(e.contains(place) && e.contains(rule), "{e}");
        }
    }
}
