//! `sim sweep`: a parameter study on the local cores (`sim sweep STUDY
//! --out DIR [--shard I/N]`), the join of its shards (`sim sweep merge
//! DIR`) and its Slurm job array (`sim sweep slurm STUDY --shards N --out
//! DIR [--submit]`). docs/guide/sweeps.md.

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;

use anyhow::{Context, Result};

use crate::studies::sweep::merge::merge;
use crate::studies::sweep::runner::{Progress, run_shard};
use crate::studies::sweep::slurm::{SlurmOptions, submit, write_scripts};
use crate::studies::sweep::{Dir, Shard, Study};

/// Arguments of `sim sweep`.
#[derive(Debug, clap::Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct SweepArgs {
    #[command(subcommand)]
    pub action: Option<SweepAction>,
    /// Study file (TOML; docs/guide/sweeps.md, examples in tables/sweeps/).
    #[arg(value_name = "SWEEP.toml", required = true)]
    pub study: Option<PathBuf>,
    /// Study folder: the tables, the kept results, the plots. A re-run
    /// into the same folder skips the variants already done.
    #[arg(long, value_name = "DIR", required = true)]
    pub out: Option<PathBuf>,
    /// Run shard I of N only (the variants whose number modulo N is I);
    /// join the shards with `sim sweep merge DIR`.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<Shard>,
    /// Variants in parallel [default: the number of cores].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The subcommands of `sim sweep`.
#[derive(Debug, clap::Subcommand)]
pub enum SweepAction {
    /// Join the shard tables of a study folder into table.csv and table.h5
    /// (every variant exactly once), and draw the study's plots.
    Merge {
        /// Study folder.
        #[arg(value_name = "DIR")]
        dir: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Write the Slurm job array of a study (task I runs shard I of N) and
    /// its merge job (after every task, --dependency=afterok); print the
    /// sbatch command, or submit with --submit.
    Slurm {
        /// Study file (TOML).
        #[arg(value_name = "SWEEP.toml")]
        study: PathBuf,
        /// Array tasks (shards).
        #[arg(long, value_name = "N")]
        shards: usize,
        /// Study folder (on a file system every node sees).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Slurm partition.
        #[arg(long, value_name = "P")]
        partition: Option<String>,
        /// Wall-time limit of each task (Slurm syntax, e.g. 2:00:00).
        #[arg(long, value_name = "T")]
        time: Option<String>,
        /// Cores per task (the shard's threads).
        #[arg(long, value_name = "C", default_value_t = 1)]
        cpus_per_task: usize,
        /// Submit the jobs with sbatch and print their ids.
        #[arg(long)]
        submit: bool,
    },
}

/// Run `sim sweep`.
pub fn command(args: &SweepArgs) -> Result<()> {
    match &args.action {
        Some(SweepAction::Merge { dir, json }) => merge_command(dir, *json),
        Some(SweepAction::Slurm {
            study,
            shards,
            out,
            partition,
            time,
            cpus_per_task,
            submit: and_submit,
        }) => {
            let study = Study::load(study)?;
            let dir = Dir { root: out.clone() };
            let options = SlurmOptions {
                shards: *shards,
                partition: partition.clone(),
                time: time.clone(),
                cpus_per_task: *cpus_per_task,
                sim: std::env::current_exe().context("the path of this sim")?,
            };
            let scripts = write_scripts(&study, &dir, &options)?;
            println!(
                "'{}': {} variants in {shards} array tasks",
                study.file.sweep.title,
                study.variants.len()
            );
            println!("wrote {}", scripts.array.display());
            println!("wrote {}", scripts.merge.display());
            if *and_submit {
                let ids = submit(&scripts)?;
                println!(
                    "submitted: array job {} (tasks 0-{}), merge job {} (afterok:{})",
                    ids.array_job,
                    shards - 1,
                    ids.merge_job,
                    ids.array_job
                );
            } else {
                println!("submit with:\n  {}", scripts.command);
            }
            Ok(())
        }
        None => {
            let (Some(path), Some(out)) = (&args.study, &args.out) else {
                anyhow::bail!("give a study file and --out DIR (or a subcommand: merge, slurm)");
            };
            run_command(path, out, args)
        }
    }
}

fn run_command(path: &Path, out: &Path, args: &SweepArgs) -> Result<()> {
    let study = Study::load(path)?;
    let dir = Dir {
        root: out.to_path_buf(),
    };
    let shard = args.shard.unwrap_or(Shard::ALL);
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let stop = preproc::cli::stop_on_signal(false);
    let bar = if args.quiet || args.json {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(0);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{bar:40} {pos}/{len} variants, {msg} elapsed {elapsed}, ETA {eta}",
            )
            .expect("static template"),
        );
        b
    };
    let progress = |p: Progress| {
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        bar.set_message(format!("{} failed,", p.failed));
    };
    let report = run_shard(&study, &dir, shard, jobs, stop.clone(), &progress);
    bar.finish_and_clear();
    let report = report?;
    let text = format!(
        "'{}' shard {}: {} variants, {} done before, {} computed ({} failed) in {:.1} s{}\n",
        study.file.sweep.title,
        report.shard,
        report.variants,
        report.already_done,
        report.computed,
        report.failed,
        report.wall_s,
        if report.retried > 0 {
            format!(
                ", {} failed rows of an earlier run computed again",
                report.retried
            )
        } else {
            String::new()
        }
    );
    if report.interrupted || stop.load(Ordering::Relaxed) {
        eprint!("{text}");
        return Err(crate::cli::Interrupted {
            what: format!(
                "the study; its finished rows are in {}: the same command completes it",
                dir.shards().display()
            ),
        }
        .into());
    }
    if shard != Shard::ALL {
        if args.json {
            println!("{}", serde_json::to_string_pretty(&report)?);
        } else {
            print!("{text}");
            println!(
                "when every shard is done: sim sweep merge {}",
                dir.root.display()
            );
        }
        return Ok(());
    }
    if !args.json {
        print!("{text}");
    }
    merged(&dir, Some(&study), args.json)
}

fn merge_command(dir: &Path, json: bool) -> Result<()> {
    let dir = Dir {
        root: dir.to_path_buf(),
    };
    let manifest = dir.read_manifest()?.with_context(|| {
        format!(
            "{} is not a study folder (no study.json)",
            dir.root.display()
        )
    })?;
    // The study file names missing variants' parameters and holds the
    // plots' settings; a folder copied without it, or whose study file
    // has changed since, still merges (without plots, and said so).
    let study = match Study::load(Path::new(&manifest.study_file)) {
        Ok(s) if s.fingerprint == manifest.fingerprint => Some(s),
        Ok(_) => {
            eprintln!(
                "warning: {} has changed since the study ran: merged without its plots",
                manifest.study_file
            );
            None
        }
        Err(e) => {
            eprintln!(
                "warning: the study file {} cannot be read ({}): merged without its plots",
                manifest.study_file,
                crate::error_text::chain_text(&e)
            );
            None
        }
    };
    merged(&dir, study.as_ref(), json)
}

fn merged(dir: &Dir, study: Option<&Study>, json: bool) -> Result<()> {
    let (report, rows) = merge(dir, study)?;
    let mut plots = Vec::new();
    if let Some(s) = study
        && let Some(spec) = &s.file.sweep.plot
    {
        plots = crate::report::sweep::write_sweep_plots(
            &dir.plots(),
            &s.file.sweep.title,
            spec,
            &s.layout(),
            &rows,
        )?;
    }
    if json {
        let mut v = serde_json::to_value(&report)?;
        v["plots"] = serde_json::json!(
            plots
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
        );
        println!("{}", serde_json::to_string_pretty(&v)?);
    } else {
        println!(
            "merged {} rows ({} failed) of {} shard table(s): {}, {}",
            report.rows,
            report.failed,
            report.shard_tables.len(),
            report.table_csv,
            report.table_h5
        );
        for p in plots {
            println!("wrote {}", p.display());
        }
    }
    Ok(())
}
