//! Column formats: plain two-column text and CSV with a header row, read
//! with the workspace's one table reader ([`crate::io::csv`]).
//!
//! * Plain (`.dat`, `.txt`, …): `y z` a line, separated by white space or
//!   by one comma; `#`, `!` and `%` start a comment (a whole line or the
//!   rest of one); blank lines are ignored. Millimetres (EN 15302 reference
//!   files, Miniprof exports), z up (z negative downward). Not CSV: a
//!   comment may start anywhere in a line and the separator is chosen per
//!   line (runs of white space, or commas), so this module finds the data
//!   part of each line itself and splits it with
//!   [`split_fields`](crate::io::csv::split_fields).
//! * CSV (`.csv`): a header row naming two columns, `y` or `y_mm` and `z` or
//!   `z_mm` (any order, case-insensitive, optionally quoted), then rows of
//!   two comma-separated numbers; lines starting with `#` and blank lines
//!   are ignored (docs/reference/02-inputs.md §2). Each column's unit is in its name; z up. The
//!   header is checked here (its rules are the format's), the table read by
//!   [`CsvTable::parse`].

use std::path::Path;

use super::{PLAIN_DEFAULT_UNIT_M, ProfileImportError as E, RawPoint, RawProfile, number};
use crate::io::csv::{CsvError, CsvTable, Separator, data_lines, split_fields};

/// Characters that start a comment in a plain file.
const PLAIN_COMMENT: [char; 3] = ['#', '!', '%'];

pub(super) fn parse_plain(path: &Path, text: &str) -> Result<RawProfile, E> {
    let mut points = Vec::new();
    let mut comment: Vec<&str> = Vec::new();
    let mut last_line = 0;
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let (data, note) = match raw.find(PLAIN_COMMENT) {
            Some(k) => (&raw[..k], Some(&raw[k + 1..])),
            None => (raw, None),
        };
        let data = data.trim();
        if data.is_empty() {
            // Comment lines before the first point describe the file.
            if points.is_empty()
                && let Some(note) = note
            {
                comment.push(note.trim_start_matches(PLAIN_COMMENT).trim());
            }
            continue;
        }
        let separator = if data.contains(',') {
            Separator::Comma
        } else {
            Separator::Whitespace
        };
        let fields = split_fields(data, separator);
        if fields.len() != 2 {
            return Err(E::FieldCount {
                path: path.to_path_buf(),
                line,
                expected: "2 values (y z)".into(),
                found: fields.len(),
            });
        }
        let y = number(path, line, Some(1), || "y".into(), &fields[0])?;
        let z = number(path, line, Some(2), || "z".into(), &fields[1])?;
        points.push(RawPoint {
            y,
            z,
            weight: 1.0,
            line,
        });
        last_line = line;
    }
    Ok(RawProfile {
        in_file: points.len(),
        end_line: if points.is_empty() {
            text.lines().count()
        } else {
            last_line
        },
        points,
        // 1 / 1e-3 is exactly 1000.0 in floating point.
        per_m: [1.0 / PLAIN_DEFAULT_UNIT_M; 2],
        z_down: false,
        kind: None,
        comment: join_comment(&comment),
        simpack: None,
    })
}

fn join_comment(lines: &[&str]) -> Option<String> {
    let text = lines.join("\n").trim().to_string();
    (!text.is_empty()).then_some(text)
}

/// A recognised CSV column: which coordinate, and its unit in file units
/// per metre.
fn csv_column(name: &str) -> Option<(usize, f64)> {
    match name {
        "y" => Some((0, 1.0)),
        "z" => Some((1, 1.0)),
        "y_mm" => Some((0, 1000.0)),
        "z_mm" => Some((1, 1000.0)),
        _ => None,
    }
}

pub(super) fn parse_csv(path: &Path, text: &str) -> Result<RawProfile, E> {
    let header_err = |line: usize, rule: String| E::CsvHeader {
        path: path.to_path_buf(),
        line,
        rule,
    };
    let Some((header_line, l)) = data_lines(text).next() else {
        return Err(header_err(
            text.lines().count().max(1),
            "no header row (expected y,z in m or y_mm,z_mm in mm)".into(),
        ));
    };
    let line = header_line;
    let names: Vec<String> = split_fields(l, Separator::Comma)
        .iter()
        .map(|f| {
            f.trim_matches('"')
                .trim_matches('\'')
                .trim()
                .to_ascii_lowercase()
        })
        .collect();
    if names.iter().all(|n| n.parse::<f64>().is_ok()) {
        return Err(header_err(
            line,
            format!(
                "expected a header row naming the columns (y,z in m or y_mm,z_mm in mm), found numbers '{l}'; a file without a header is read as plain text (millimetres) when its extension is not .csv"
            ),
        ));
    }
    let mut per_m = [1.0, 1.0];
    let mut cols = [None, None];
    for (k, n) in names.iter().enumerate() {
        let Some((coord, unit)) = csv_column(n) else {
            return Err(header_err(
                line,
                format!(
                    "unknown column '{n}' (column {}); expected y or y_mm, and z or z_mm",
                    k + 1
                ),
            ));
        };
        if cols[coord].is_some() {
            return Err(header_err(
                line,
                format!("a second {} column '{n}'", ["y", "z"][coord]),
            ));
        }
        cols[coord] = Some(k);
        per_m[coord] = unit;
    }
    let (Some(cy), Some(cz), 2) = (cols[0], cols[1], names.len()) else {
        return Err(header_err(
            line,
            format!("the header '{l}' must name exactly two columns: y or y_mm, and z or z_mm"),
        ));
    };

    // The header is valid: the table reader's own header rules hold, and
    // what it refuses is a row.
    let coordinate = |column: usize| if column == cy + 1 { "y" } else { "z" };
    let table = CsvTable::parse(path, text, Separator::Comma).map_err(|e| match e {
        CsvError::FieldCount { line, found, .. } => E::FieldCount {
            path: path.to_path_buf(),
            line,
            expected: "2 comma-separated values (as named by the header)".into(),
            found,
        },
        CsvError::NotANumber {
            line, column, text, ..
        } => E::NotANumber {
            path: path.to_path_buf(),
            line,
            column: Some(column),
            what: coordinate(column).into(),
            text,
        },
        CsvError::NonFinite {
            line, column, text, ..
        } => E::NonFinite {
            path: path.to_path_buf(),
            line,
            column: Some(column),
            what: coordinate(column).into(),
            text,
        },
        other => E::Syntax {
            path: path.to_path_buf(),
            line: other.line().unwrap_or(header_line),
            rule: other.rule(),
        },
    })?;
    let points: Vec<RawPoint> = table
        .rows
        .iter()
        .map(|(line, v)| RawPoint {
            y: v[cy],
            z: v[cz],
            weight: 1.0,
            line: *line,
        })
        .collect();
    let preamble: Vec<&str> = table.preamble.iter().map(String::as_str).collect();
    Ok(RawProfile {
        in_file: points.len(),
        end_line: points.last().map_or(header_line, |p| p.line),
        points,
        per_m,
        z_down: false,
        kind: None,
        comment: join_comment(&preamble),
        simpack: None,
    })
}

#[cfg(test)]
mod tests {
    use super::super::{ImportOptions, ProfileFile, ProfileFormat, parse_profile};
    use super::*;

    fn parse(name: &str, text: &str) -> Result<ProfileFile, E> {
        parse_profile(Path::new(name), text, &ImportOptions::default())
    }

    #[test]
    fn plain_reads_millimetres_with_z_up_and_keeps_order() {
        let text = "% EN 15302 wheel\n# second line\n\n  -70.0   -9.519\n-69.865\t-10.73762 ! tail\n-69.73,-11.82506\n  -69.595 , -12.79093 # tail\n\n";
        let f = parse("w.dat", text).unwrap();
        assert_eq!(f.format, ProfileFormat::Plain);
        assert_eq!(f.kind, None);
        assert!(!f.z_down);
        let want = [
            [-70e-3, -9.519e-3],
            [-69.865e-3, -10.73762e-3],
            [-69.73e-3, -11.82506e-3],
            [-69.595e-3, -12.79093e-3],
        ];
        assert_eq!(f.len(), want.len());
        for (p, q) in f.points_m.iter().zip(want) {
            // value / 1000: within one rounding of the decimal in metres.
            assert!(
                (p[0] - q[0]).abs() <= 1e-17 && (p[1] - q[1]).abs() <= 1e-17,
                "{p:?} vs {q:?}"
            );
        }
        assert_eq!(f.lines, vec![4, 5, 6, 7]);
        assert_eq!(f.weights, vec![1.0; 4]);
        assert_eq!(f.comment.as_deref(), Some("EN 15302 wheel\nsecond line"));
        assert!(f.simpack.is_none());
    }

    #[test]
    fn plain_length_unit_option_overrides_millimetres() {
        let o = ImportOptions {
            length_unit: Some(1.0),
            ..Default::default()
        };
        let f =
            parse_profile(Path::new("w.txt"), "0 0\n0.001 0.5\n0.002 1\n0.003 2\n", &o).unwrap();
        assert_eq!(f.points_m[3], [0.003, 2.0]);
    }

    #[test]
    fn plain_errors_name_line_and_rule() {
        type Check = fn(&E) -> bool;
        let cases: [(&str, usize, Check); 8] = [
            (
                "0 0\n1 1\n2 abc\n3 3\n",
                3,
                |e| matches!(e, E::NotANumber { what, text, column: Some(2), .. } if what == "z" && text == "abc"),
            ),
            (
                "0 0\nx 1\n",
                2,
                |e| matches!(e, E::NotANumber { what, column: Some(1), .. } if what == "y"),
            ),
            ("0 0\n1 nan\n", 2, |e| matches!(e, E::NonFinite { .. })),
            ("0 0\n1 inf\n", 2, |e| matches!(e, E::NonFinite { .. })),
            ("0 0\n1 1 1\n", 2, |e| {
                matches!(e, E::FieldCount { found: 3, .. })
            }),
            ("# c\n5\n", 2, |e| {
                matches!(e, E::FieldCount { found: 1, .. })
            }),
            ("0 0\n1,,2\n", 2, |e| {
                matches!(e, E::FieldCount { found: 3, .. })
            }),
            ("# only\n# comments\n", 2, |e| {
                matches!(e, E::TooFewPoints { found: 0, .. })
            }),
        ];
        for (text, line, check) in cases {
            let e = parse("w.dat", text).expect_err(text);
            assert!(check(&e), "{text:?} → {e:?}");
            assert_eq!(e.line(), Some(line), "{text:?} → {e}");
            let at = format!("'w.dat', line {line}");
            let msg = e.to_string();
            assert!(
                msg.starts_with(&format!("{at}: ")) || msg.starts_with(&format!("{at}, column ")),
                "{msg}"
            );
        }
        // A Miniprof header line is not silently skipped.
        let e = parse("r.ban", "Filename=MBench_UIC60.ban\n").unwrap_err();
        assert!(
            matches!(
                e,
                E::FieldCount { line: 1, .. } | E::NotANumber { line: 1, .. }
            ),
            "{e}"
        );
    }

    #[test]
    fn csv_in_metres_in_millimetres_and_in_either_order() {
        let f = parse(
            "p.csv",
            "# rail\ny,z\n-0.02,0.001\n-0.01,0\n0,0\n0.01,0.0005\n",
        )
        .unwrap();
        assert_eq!(f.format, ProfileFormat::Csv);
        assert!(!f.z_down);
        assert_eq!(f.points_m[0], [-0.02, 0.001]);
        assert_eq!(f.lines, vec![3, 4, 5, 6]);
        assert_eq!(f.comment.as_deref(), Some("rail"));
        let f = parse("p.csv", "Y_MM, \"Z_MM\"\n-20,1\n-10,0\n0,0\n10,0.5\n").unwrap();
        assert_eq!(f.points_m[0], [-0.02, 0.001]);
        assert_eq!(f.points_m[3], [0.01, 0.0005]);
        let f = parse("p.csv", "z_mm,y\n1,-0.02\n0,-0.01\n0,0\n0.5,0.01\n").unwrap();
        assert_eq!(f.points_m[0], [-0.02, 0.001]);
        assert_eq!(f.points_m[3], [0.01, 0.0005]);
        let o = ImportOptions {
            length_unit: Some(1e-3),
            ..Default::default()
        };
        let f = parse_profile(Path::new("p.csv"), "y,z\n-20,1\n-10,0\n0,0\n10,0.5\n", &o).unwrap();
        assert_eq!(f.points_m[0], [-0.02, 0.001]);
    }

    #[test]
    fn csv_errors_name_line_and_rule() {
        type Check = fn(&E) -> bool;
        let cases: [(&str, usize, Check); 11] = [
            ("1,2\n3,4\n", 1, |e| matches!(e, E::CsvHeader { .. })),
            (
                "# c\nx,z\n1,2\n",
                2,
                |e| matches!(e, E::CsvHeader { rule, .. } if rule.contains("'x'")),
            ),
            (
                "y,y_mm\n1,2\n",
                1,
                |e| matches!(e, E::CsvHeader { rule, .. } if rule.contains("second y")),
            ),
            ("y\n1\n", 1, |e| matches!(e, E::CsvHeader { .. })),
            ("y,z,w\n1,2,3\n", 1, |e| matches!(e, E::CsvHeader { .. })),
            ("# only comments\n", 1, |e| matches!(e, E::CsvHeader { .. })),
            ("", 1, |e| matches!(e, E::CsvHeader { .. })),
            ("y,z\n0,0\n1\n", 3, |e| {
                matches!(e, E::FieldCount { found: 1, .. })
            }),
            (
                "y,z\n0,0\n1,x\n",
                3,
                |e| matches!(e, E::NotANumber { what, column: Some(2), .. } if what == "z"),
            ),
            (
                "z,y\n0,0\n1,1e999\n",
                3,
                |e| matches!(e, E::NonFinite { what, column: Some(2), .. } if what == "y"),
            ),
            ("y,z\n0,0\n1,1\n2,2\n", 4, |e| {
                matches!(e, E::TooFewPoints { found: 3, .. })
            }),
        ];
        for (text, line, check) in cases {
            let e = parse("p.csv", text).expect_err(text);
            assert!(check(&e), "{text:?} → {e:?}");
            assert_eq!(e.line(), Some(line), "{text:?} → {e}");
            let at = format!("'p.csv', line {line}");
            let msg = e.to_string();
            assert!(
                msg.starts_with(&format!("{at}: ")) || msg.starts_with(&format!("{at}, column ")),
                "{msg}"
            );
        }
    }
}
