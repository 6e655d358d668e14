//! A study's plots: each figure against the varied key `[plot] x`, one
//! line per value of `[plot] lines` (e.g. one per creep law), from the
//! merged table; a variant without the figure (failed, or none found) is
//! left out of its line.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use preproc::plot::{LineChart, Series, write_line_chart};

use crate::config::sweep::PlotSpec;
use crate::studies::sweep::table::{Layout, Row};

/// Writes one PNG per plotted figure into `dir`; returns their paths.
pub fn write_sweep_plots(
    dir: &Path,
    title: &str,
    spec: &PlotSpec,
    layout: &Layout,
    rows: &[Row],
) -> Result<Vec<PathBuf>> {
    // The x of a row: a varied key's value, or a figure.
    type Abscissa = Box<dyn Fn(&Row) -> Option<f64>>;
    let x_of: Abscissa = if let Some(c) = layout.keys.iter().position(|k| *k == spec.x) {
        Box::new(move |r: &Row| r.params[c].parse::<f64>().ok())
    } else {
        let j = layout
            .figures
            .iter()
            .position(|f| *f == spec.x)
            .with_context(|| format!("[plot] x = '{}' is not a column of the table", spec.x))?;
        Box::new(move |r: &Row| r.figures[j])
    };
    let line_col =
        match &spec.lines {
            Some(l) => {
                Some(layout.keys.iter().position(|k| k == l).with_context(|| {
                    format!("[plot] lines = '{l}' is not a column of the table")
                })?)
            }
            None => None,
        };
    let figures: Vec<&String> = if spec.figures.is_empty() {
        layout.figures.iter().filter(|f| **f != spec.x).collect()
    } else {
        spec.figures.iter().collect()
    };
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut written = Vec::new();
    for f in figures {
        let j = layout
            .figures
            .iter()
            .position(|g| g == f)
            .with_context(|| format!("[plot] figure '{f}' is not a column"))?;
        let mut lines: BTreeMap<String, Vec<(f64, f64)>> = BTreeMap::new();
        for r in rows {
            let (Some(x), Some(y)) = (x_of(r), r.figures[j]) else {
                continue;
            };
            let label = line_col.map_or_else(
                || f.clone(),
                |c| format!("{} = {}", layout.keys[c], r.params[c]),
            );
            lines.entry(label).or_default().push((x, y));
        }
        let mut chart = LineChart::new(
            title,
            spec.x_label.clone().unwrap_or_else(|| spec.x.clone()),
            spec.labels.get(f).cloned().unwrap_or_else(|| f.clone()),
        );
        for (label, mut points) in lines {
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            chart = chart.with_series(Series::line(label, points));
        }
        let name: String = f
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || c == '_' {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        let path = dir.join(format!("{name}.png"));
        write_line_chart(&path, &chart, (900, 600))
            .with_context(|| format!("drawing {}", path.display()))?;
        written.push(path);
    }
    Ok(written)
}
