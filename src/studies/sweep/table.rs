//! A study's table: one row per variant — its number, the values of the
//! varied keys, its status, its figures, a message (the error of a failed
//! variant, the note of a critical speed not found) and its kept results.
//! The CSV is the resumable log (one line appended per finished variant);
//! the HDF5 table holds the same columns (`runtime::io::schema::write_study_table`).
//! Numbers are written in the shortest form that reads back exactly, so the
//! same rows give the same bytes.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use runtime::io::schema::StudyColumn;

/// A variant's outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Ok,
    Failed,
}

impl Status {
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Ok => "ok",
            Status::Failed => "failed",
        }
    }
}

/// The columns of a study's table.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    /// The varied keys.
    pub keys: Vec<String>,
    /// The figures.
    pub figures: Vec<String>,
}

impl Layout {
    /// The header: variant, the keys, status, the figures, message, results.
    pub fn header(&self) -> Vec<String> {
        let mut h = vec!["variant".to_string()];
        h.extend(self.keys.iter().cloned());
        h.push("status".into());
        h.extend(self.figures.iter().cloned());
        h.push("message".into());
        h.push("results".into());
        h
    }
}

/// One row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub variant: usize,
    /// The varied keys' values as written in the table.
    pub params: Vec<String>,
    pub status: Status,
    pub figures: Vec<Option<f64>>,
    pub message: String,
    /// The kept results, relative to the study folder; empty if none.
    pub results: String,
}

/// A scene value as the table writes it: a number in its shortest exact
/// form, a string as is.
pub fn value_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => s.clone(),
        toml::Value::Float(f) => number_text(*f),
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Boolean(b) => b.to_string(),
        other => other.to_string(),
    }
}

/// `f` in the shortest form that reads back exactly (Rust's `{}`).
pub fn number_text(f: f64) -> String {
    format!("{f}")
}

impl Row {
    fn record(&self) -> Vec<String> {
        let mut r = vec![self.variant.to_string()];
        r.extend(self.params.iter().cloned());
        r.push(self.status.as_str().into());
        r.extend(
            self.figures
                .iter()
                .map(|f| f.map_or(String::new(), number_text)),
        );
        r.push(self.message.clone());
        r.push(self.results.clone());
        r
    }
}

fn csv_line(fields: &[String]) -> Result<Vec<u8>> {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    w.write_record(fields)?;
    w.flush()?;
    w.into_inner().context("CSV buffer")
}

/// The table's CSV text: the header, then `rows` in the given order.
pub fn csv_text(layout: &Layout, rows: &[Row]) -> Result<Vec<u8>> {
    let mut out = csv_line(&layout.header())?;
    for r in rows {
        out.extend(csv_line(&r.record())?);
    }
    Ok(out)
}

/// Writes a whole table as CSV, all or nothing.
pub fn write_csv(path: &Path, layout: &Layout, rows: &[Row]) -> Result<()> {
    let text = csv_text(layout, rows)?;
    runtime::io::atomic::write_atomically(path, |tmp| std::fs::write(tmp, &text))
        .with_context(|| format!("writing {}", path.display()))
}

/// Appends one row to a table's CSV (its header written first if the file
/// is new) and flushes it to the disk: a killed study keeps every finished
/// row.
pub fn append_row(path: &Path, layout: &Layout, row: &Row) -> Result<()> {
    let new = !path.exists();
    let mut f = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(path)
        .with_context(|| format!("opening {}", path.display()))?;
    let mut bytes = Vec::new();
    if new {
        bytes.extend(csv_line(&layout.header())?);
    }
    bytes.extend(csv_line(&row.record())?);
    f.write_all(&bytes)
        .and_then(|_| f.sync_data())
        .with_context(|| format!("appending to {}", path.display()))
}

/// Reads a table's CSV. A last line cut short (the study was killed while
/// writing it) is dropped, and said so in the returned count; any other
/// malformed line is an error naming it.
pub fn read_csv(path: &Path, layout: &Layout) -> Result<(Vec<Row>, usize)> {
    let text = match std::fs::read(path) {
        Ok(t) => t,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((Vec::new(), 0)),
        Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
    };
    let complete = text.ends_with(b"\n");
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .from_reader(text.as_slice());
    let header: Vec<String> = reader
        .headers()
        .with_context(|| format!("{}: header", path.display()))?
        .iter()
        .map(str::to_string)
        .collect();
    if header != layout.header() {
        bail!(
            "{}: its columns ({}) are not this study's ({}): the study file changed; use another --out",
            path.display(),
            header.join(","),
            layout.header().join(",")
        );
    }
    let records: Vec<csv::StringRecord> = reader
        .records()
        .collect::<Result<_, _>>()
        .with_context(|| format!("reading {}", path.display()))?;
    let mut rows = Vec::with_capacity(records.len());
    let mut torn = 0;
    let n = records.len();
    for (k, rec) in records.into_iter().enumerate() {
        let line = rec.position().map_or(0, |p| p.line());
        match parse_record(&rec, layout) {
            Ok(r) => rows.push(r),
            Err(_) if k + 1 == n && !complete => torn += 1,
            Err(e) => return Err(e.context(format!("{}:{line}", path.display()))),
        }
    }
    Ok((rows, torn))
}

fn parse_record(rec: &csv::StringRecord, layout: &Layout) -> Result<Row> {
    let want = layout.header().len();
    if rec.len() != want {
        bail!("{} fields, the header has {want}", rec.len());
    }
    let f: Vec<&str> = rec.iter().collect();
    let k = layout.keys.len();
    let variant: usize = f[0]
        .parse()
        .with_context(|| format!("variant '{}'", f[0]))?;
    let status = match f[1 + k] {
        "ok" => Status::Ok,
        "failed" => Status::Failed,
        other => bail!("status '{other}' is neither ok nor failed"),
    };
    let figures = f[2 + k..2 + k + layout.figures.len()]
        .iter()
        .map(|s| {
            if s.is_empty() {
                Ok(None)
            } else {
                s.parse::<f64>()
                    .map(Some)
                    .with_context(|| format!("figure '{s}'"))
            }
        })
        .collect::<Result<_>>()?;
    Ok(Row {
        variant,
        params: f[1..1 + k].iter().map(|s| s.to_string()).collect(),
        status,
        figures,
        message: f[want - 2].to_string(),
        results: f[want - 1].to_string(),
    })
}

/// Writes the table as HDF5 (all or nothing): `variant` and the figures as
/// numbers, a key as numbers when every value is one, else as text.
pub fn write_h5(
    path: &Path,
    title: &str,
    fingerprint: &str,
    layout: &Layout,
    rows: &[Row],
) -> Result<()> {
    let mut columns: Vec<(String, StudyColumn)> = vec![(
        "variant".into(),
        StudyColumn::Numbers(rows.iter().map(|r| r.variant as f64).collect()),
    )];
    for (k, key) in layout.keys.iter().enumerate() {
        let numbers: Option<Vec<f64>> = rows
            .iter()
            .map(|r| r.params[k].parse::<f64>().ok())
            .collect();
        let column = match numbers {
            Some(v) => StudyColumn::Numbers(v),
            None => StudyColumn::Text(rows.iter().map(|r| r.params[k].clone()).collect()),
        };
        columns.push((key.clone(), column));
    }
    columns.push((
        "status".into(),
        StudyColumn::Text(rows.iter().map(|r| r.status.as_str().to_string()).collect()),
    ));
    for (j, name) in layout.figures.iter().enumerate() {
        columns.push((
            name.clone(),
            StudyColumn::Numbers(
                rows.iter()
                    .map(|r| r.figures[j].unwrap_or(f64::NAN))
                    .collect(),
            ),
        ));
    }
    columns.push((
        "message".into(),
        StudyColumn::Text(rows.iter().map(|r| r.message.clone()).collect()),
    ));
    columns.push((
        "results".into(),
        StudyColumn::Text(rows.iter().map(|r| r.results.clone()).collect()),
    ));
    runtime::io::schema::write_study_table(
        path,
        &[("title", title), ("fingerprint", fingerprint)],
        &columns,
    )
    .with_context(|| format!("writing {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layout() -> Layout {
        Layout {
            keys: vec!["contact.friction".into(), "contact.creep_law".into()],
            figures: vec!["critical_speed_m_s".into()],
        }
    }

    fn row(k: usize) -> Row {
        Row {
            variant: k,
            params: vec![number_text(0.1 * k as f64), "polach".into()],
            status: if k % 2 == 0 {
                Status::Ok
            } else {
                Status::Failed
            },
            figures: vec![if k % 2 == 0 {
                Some(83.3 + k as f64 / 3.0)
            } else {
                None
            }],
            message: if k % 2 == 0 {
                String::new()
            } else {
                "derailed, \"flange\" climb".into()
            },
            results: String::new(),
        }
    }

    #[test]
    fn rows_round_trip_exactly_and_a_torn_last_line_is_dropped() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.csv");
        for k in 0..4 {
            append_row(&p, &layout(), &row(k)).unwrap();
        }
        let (rows, torn) = read_csv(&p, &layout()).unwrap();
        assert_eq!(torn, 0);
        assert_eq!(rows, (0..4).map(row).collect::<Vec<_>>());
        // Killed while writing a fifth line.
        let mut text = std::fs::read(&p).unwrap();
        text.extend_from_slice(b"4,0.4,pol");
        std::fs::write(&p, &text).unwrap();
        let (rows, torn) = read_csv(&p, &layout()).unwrap();
        assert_eq!((rows.len(), torn), (4, 1));
        // Another layout is refused, naming both.
        let other = Layout {
            keys: vec!["x".into()],
            figures: vec![],
        };
        let e = read_csv(&p, &other).unwrap_err();
        assert!(format!("{e:#}").contains("study file changed"), "{e:#}");
    }

    #[test]
    fn hdf5_table_holds_the_columns() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.h5");
        let rows: Vec<Row> = (0..3).map(row).collect();
        write_h5(&p, "t", "abc", &layout(), &rows).unwrap();
        let cols = runtime::io::schema::read_study_table(&p).unwrap();
        let names: Vec<&str> = cols.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, layout().header());
        assert_eq!(cols[1].1, StudyColumn::Numbers(vec![0.0, 0.1, 0.2]));
        assert_eq!(cols[2].1, StudyColumn::Text(vec!["polach".into(); 3]));
    }
}
