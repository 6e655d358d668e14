//! Command-line interface of `track-preproc` (thin: parse, check, call the
//! library, print).

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use runtime::spline::Scheme;

use crate::config::{BuildConfig, Inclination, RailSpacing};
use crate::pipeline::{BuildRequest, run_build};
use crate::progress::{Progress, ProgressSink};

/// Offline track pre-processor: CSV control points → per-rail HDF5 databases.
#[derive(Debug, Parser)]
#[command(name = "track-preproc", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Build the centreline and rail databases of a track.
    Build(BuildArgs),
}

/// Arguments of `track-preproc build`.
#[derive(Debug, Args)]
pub struct BuildArgs {
    /// Centreline control points: CSV with x, y, z [m] and optionally cant [rad] or cant_mm.
    #[arg(long, value_name = "FILE")]
    pub centerline: PathBuf,
    /// Cant table (overrides the centreline's cant): CSV with s and cant [rad] or cant_mm.
    #[arg(long, value_name = "FILE")]
    pub cant: Option<PathBuf>,
    /// Irregularities: CSV s, align_left, align_right, level_left, level_right [m]
    /// or s, alignment, gauge, level, cross_level; `_mm` suffix allowed.
    #[arg(long, value_name = "FILE")]
    pub irregularities: Option<PathBuf>,
    /// Spline scheme for centreline, cant and rails.
    #[arg(long, default_value = "cubic", value_parser = ["cubic", "cubic-natural", "akima", "pchip"])]
    pub scheme: String,
    /// Table step Δs [m].
    #[arg(long, default_value_t = crate::config::DEFAULT_STEP_M, value_name = "M")]
    pub step: f64,
    /// Track gauge [m].
    #[arg(long, default_value_t = crate::config::DEFAULT_GAUGE_M, value_name = "M")]
    pub gauge: f64,
    /// Distance between the rail profile origins [m] (default: gauge + 2 × gauge-face offset).
    #[arg(long, value_name = "M")]
    pub rail_spacing: Option<f64>,
    /// Lateral offset of the gauge face from the rail profile origin [m] (UIC60: 0.036).
    #[arg(long, default_value_t = crate::config::DEFAULT_GAUGE_FACE_OFFSET_M, value_name = "M")]
    pub gauge_face_offset: f64,
    /// Rail inclination towards the track centre: 1:40, 1:20, 0, …
    #[arg(long, default_value = "1:40", value_name = "R")]
    pub rail_inclination: String,
    /// Cant base e0 for cant heights, φ = asin(h/e0) [m] (default: gauge + 0.065).
    #[arg(long, value_name = "M")]
    pub cant_base: Option<f64>,
    /// Output table file (.h5), written atomically.
    #[arg(short, long, value_name = "OUT.h5")]
    pub output: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

impl BuildArgs {
    /// Second stage: parsed arguments → checked build request.
    pub fn to_request(&self, command_line: String) -> Result<BuildRequest> {
        let scheme: Scheme = self.scheme.parse()?;
        let inclination: Inclination = self
            .rail_inclination
            .parse()
            .map_err(anyhow::Error::msg)
            .context("--rail-inclination")?;
        let config = BuildConfig {
            scheme,
            step_m: self.step,
            gauge_m: self.gauge,
            rail_spacing: match self.rail_spacing {
                Some(spacing_m) => RailSpacing::Explicit { spacing_m },
                None => RailSpacing::FromGauge {
                    gauge_face_offset_m: self.gauge_face_offset,
                },
            },
            inclination,
            cant_base_m: self.cant_base,
        };
        config.validate()?;
        Ok(BuildRequest {
            centerline: self.centerline.clone(),
            cant: self.cant.clone(),
            irregularities: self.irregularities.clone(),
            output: self.output.clone(),
            config,
            command_line,
        })
    }
}

/// The process's command line, shell-quoted where needed.
pub fn command_line() -> String {
    std::env::args()
        .map(|a| {
            if !a.is_empty()
                && a.chars()
                    .all(|c| c.is_ascii_alphanumeric() || "-_./:=,+".contains(c))
            {
                a
            } else {
                format!("'{}'", a.replace('\'', r"'\''"))
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// An indicatif bar driven by build progress events; hidden when stderr is
/// not a terminal.
pub struct BarSink {
    bar: ProgressBar,
}

impl BarSink {
    pub fn new() -> Self {
        let bar = if std::io::stderr().is_terminal() {
            ProgressBar::new(0)
        } else {
            ProgressBar::hidden()
        };
        bar.set_style(
            ProgressStyle::with_template("{msg:>12} [{bar:40}] {pos}/{len} rows ({eta})")
                .expect("valid template")
                .progress_chars("=> "),
        );
        Self { bar }
    }
}

impl Default for BarSink {
    fn default() -> Self {
        Self::new()
    }
}

impl ProgressSink for BarSink {
    fn event(&self, e: Progress) {
        match e {
            Progress::Stage { name, rows } => {
                self.bar.set_message(name);
                self.bar.set_length(rows);
                self.bar.set_position(0);
            }
            Progress::Rows(n) => self.bar.inc(n),
            Progress::Done => self.bar.finish_and_clear(),
        }
    }
}

/// Run the CLI.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Build(args) => {
            let req = args.to_request(command_line())?;
            let sink = BarSink::new();
            let summary = run_build(&req, &sink)
                .with_context(|| format!("building {} failed", req.output.display()))?;
            sink.event(Progress::Done);
            if args.json {
                println!("{}", serde_json::to_string_pretty(&summary)?);
            } else {
                print!("{}", summary.to_text());
            }
            Ok(())
        }
    }
}
