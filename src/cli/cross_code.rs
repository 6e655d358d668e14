//! `sim cross-code`: its arguments and the command (read the study file,
//! run the variants, write and print the report;
//! [`crate::studies::cross_code`]).

use std::path::PathBuf;

use anyhow::Result;

use crate::studies::cross_code::{StudyFile, cross_code};

/// Arguments of `sim cross-code`.
#[derive(Debug, clap::Args)]
pub struct CrossCodeArgs {
    /// Study file (TOML): the scene, the speeds, the variants (e.g. tables/studies/cooperrider_cross_code.toml).
    #[arg(value_name = "STUDY.toml")]
    pub study: PathBuf,
    /// Output directory (cross_code.md, .csv, .json, bifurcation.png, one directory of runs per variant).
    #[arg(long, value_name = "DIR", default_value = "cross_code")]
    pub out: PathBuf,
    /// Variants run in parallel [default: the number of cores].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// `sim cross-code`.
pub fn command(args: &CrossCodeArgs) -> Result<()> {
    let (study, dir) = StudyFile::load(&args.study)?;
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let stop = preproc::cli::stop_on_signal(false);
    let quiet = args.json;
    let mut report = cross_code(&study, &dir, &args.out, jobs, stop, &mut |m| {
        if !quiet {
            eprintln!("{m}");
        }
    })?;
    report.study = args.study.display().to_string();
    report.command = std::env::args().collect::<Vec<_>>().join(" ");
    report.write(&args.out)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_text());
    }
    Ok(())
}
