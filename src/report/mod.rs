//! Reports: what runs and studies leave for the user — results files,
//! plots, CSV, markdown and text. Studies return data; these write it.

pub mod bifurcation;
pub mod critical_speed;
pub mod cross_code;
pub mod curving_plot;
pub mod memory;
pub mod run_files;
pub mod run_plots;
pub mod run_text;
pub mod sweep;
pub mod tradeoff;

use std::path::Path;

use anyhow::{Context, Result};

/// A text file (CSV, markdown, JSON) written all-or-nothing
/// (`runtime::io::atomic`): nothing appears at `path` unless all of it was
/// written.
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    runtime::io::write_atomically(path, |tmp| std::fs::write(tmp, text))
        .with_context(|| format!("writing {}", path.display()))
}
