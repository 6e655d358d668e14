//! Command-line interface of `sim` (thin: parse, check, call, print).

use std::path::PathBuf;

use anyhow::Result;
use clap::{Parser, Subcommand};

/// Railway vehicle dynamics on pre-processed track tables.
#[derive(Debug, Parser)]
#[command(name = "sim", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Print both rails' interpolated position and frame at a centreline distance.
    Probe {
        /// Track table file written by `track-preproc build`.
        #[arg(value_name = "TABLES.h5")]
        file: PathBuf,
        /// Centreline distance s [m].
        #[arg(long, value_name = "S", allow_negative_numbers = true)]
        s: f64,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

/// Run the CLI.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Probe { file, s, json } => {
            let p = crate::probe::probe_file(&file, s)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&p)?);
            } else {
                print!("{}", p.to_text());
            }
            Ok(())
        }
    }
}
