//! `sim tradeoff`: its arguments and the command (parse, run the study,
//! write and print its report).

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::config::scene::LoadedScene;
use crate::studies::tradeoff::{
    CriticalSpeedSpec, TradeoffSettings, Variant, quick_scene, run_tradeoff,
};

/// Arguments of `sim tradeoff`.
#[derive(Debug, clap::Args)]
pub struct TradeoffArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
    /// Output directory (tradeoff.csv, tradeoff.md, pareto.png, runs/).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Runs per variant; the wall time is their median [default: 3, 1 with --quick].
    #[arg(long, value_name = "N")]
    pub repeats: Option<usize>,
    /// Reduced study: the reference and four variants over 50 m (tests, CI).
    #[arg(long)]
    pub quick: bool,
    /// Set a scene entry for every variant, before the reference's overrides (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Add a variant: NAME:KEY=VALUE;KEY=VALUE… applied after the reference's overrides (repeatable).
    #[arg(long = "variant", value_name = "SPEC")]
    pub variant: Vec<String>,
    /// Also the time-domain critical speed of every variant: MIN:MAX:TOL or MIN:MAX:TOL:DISTANCE_M (m/s, m; expensive).
    #[arg(long, value_name = "SPEC")]
    pub critical_speed: Option<String>,
    /// Parallel runs of the critical-speed searches [default: the number of cores].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// Print the report as JSON (and write tradeoff.json).
    #[arg(long)]
    pub json: bool,
}

/// `sim tradeoff`.
pub fn command(args: &TradeoffArgs) -> Result<()> {
    let mut scene = LoadedScene::load(&args.scene, &args.set)?;
    super::check_scene_rail(&scene)?;
    if args.quick {
        let keep = args.set.iter().any(|s| {
            s.trim_start().starts_with("run.distance_m")
                || s.trim_start().starts_with("run.duration_s")
        });
        scene = quick_scene(&scene, keep)?;
    }
    let settings = TradeoffSettings {
        repeats: args.repeats.unwrap_or(if args.quick { 1 } else { 3 }),
        quick: args.quick,
        out_dir: args.out.clone(),
        extra: args
            .variant
            .iter()
            .map(|v| Variant::parse(v).with_context(|| format!("--variant {v}")))
            .collect::<Result<_>>()?,
        critical_speed: args
            .critical_speed
            .as_deref()
            .map(CriticalSpeedSpec::parse)
            .transpose()?,
        jobs: args
            .jobs
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
    };
    let stop = preproc::cli::stop_on_signal(false);
    let quiet = args.json;
    let mut progress = |line: &str| {
        if !quiet {
            eprintln!("{line}");
        }
    };
    let mut report = run_tradeoff(&scene, &settings, &mut progress, stop)?;
    report.write(&args.out, args.json)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_text());
    }
    Ok(())
}
