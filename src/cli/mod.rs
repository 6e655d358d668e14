//! Command-line interface of `sim` (thin: parse, check, call, print).

pub mod args;
pub mod cross_code;
pub mod probe;
pub mod sweep;
pub mod tradeoff;

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

/// The user interrupted the work (Ctrl-C): `main` exits with 130, the
/// shell's code for a process ended by SIGINT.
#[derive(Debug)]
pub struct Interrupted {
    /// What was interrupted, and what was kept.
    pub what: String,
}

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted (Ctrl-C): {}", self.what)
    }
}

impl std::error::Error for Interrupted {}

/// The exit status of an interrupted command (128 + SIGINT).
pub const INTERRUPTED_EXIT_CODE: u8 = 130;

pub use args::{Cli, Command, ContactArgs, CreepCurveArgs, CriticalSpeedArgs, RunArgs};

/// Warnings on standard error, one a line.
fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("{w}");
    }
}

/// The scene's rail profile checked before any work
/// ([`crate::session::track::check_rail`]): a refusal (double canting, a
/// rail inclination or profile other than the table file's) ends the
/// command; warnings go to standard error.
pub(crate) fn check_scene_rail(scene: &crate::config::scene::LoadedScene) -> Result<()> {
    let check = crate::session::track::check_rail(scene).context("[track] rail profile")?;
    print_warnings(&check.warnings);
    Ok(())
}

/// `sim contact`: one pose or a poses file; text, JSON or CSV; to standard
/// output or, all or nothing, to `--out`.
fn contact_command(args: &args::ContactArgs) -> Result<()> {
    use crate::studies::contact as study;
    use args::ContactFormat;
    let config = args.to_config()?;
    let rolling = args.to_rolling()?;
    let out = args.checked_out()?;
    // Warnings of the rail profile now; a refusal comes from the model,
    // after the wheel profile is read (its errors first).
    if let Ok(check) = config.check_rail() {
        print_warnings(&check.warnings);
    }
    let started = std::time::Instant::now();
    let cases = match &args.poses {
        Some(path) => {
            let poses = study::read_poses(path)?;
            study::contact_batch(&config, &poses, path, &rolling)?.1
        }
        None => vec![study::contact_case(&config, &args.pose(), &rolling)?],
    };
    let elapsed = started.elapsed();
    let text = match args.format() {
        ContactFormat::Json if args.poses.is_some() => serde_json::to_string_pretty(&cases)? + "\n",
        ContactFormat::Json => serde_json::to_string_pretty(&cases[0])? + "\n",
        ContactFormat::Csv => study::rows_csv(&study::patch_rows(&cases)),
        ContactFormat::Text if args.poses.is_some() => {
            let mut t: String = cases
                .iter()
                .flat_map(|c| c.warnings.iter())
                .map(|w| format!("warning: {w}\n"))
                .collect();
            t += &study::rows_table(&study::patch_rows(&cases));
            t += &format!(
                "{} poses in {:.0} ms ({} convention, creep law {})\n",
                cases.len(),
                elapsed.as_secs_f64() * 1e3,
                rolling.convention.name(),
                rolling.settings.creep_law.name()
            );
            t
        }
        ContactFormat::Text => cases[0].to_text(),
    };
    match out {
        Some(path) => {
            runtime::io::atomic::write_atomically(&path, |tmp| std::fs::write(tmp, &text))
                .with_context(|| format!("writing {}", path.display()))?;
            eprintln!("wrote {} ({} poses)", path.display(), cases.len());
        }
        None => {
            use std::io::Write;
            let mut stdout = std::io::stdout().lock();
            // A closed pipe (`| head`) ends the output quietly.
            if let Err(e) = stdout
                .write_all(text.as_bytes())
                .and_then(|_| stdout.flush())
                && e.kind() != std::io::ErrorKind::BrokenPipe
            {
                return Err(e.into());
            }
        }
    }
    Ok(())
}

/// Run the CLI.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Contact(args) => contact_command(&args),
        Command::CreepCurves(args) => {
            let config = args.to_config()?;
            let curves = crate::studies::creep_curves::creep_curves(&config)?;
            for path in curves.write(&args.out)? {
                println!("wrote {}", path.display());
            }
            Ok(())
        }
        Command::Run(args) => run_command(&args),
        Command::CriticalSpeed(args) => critical_speed_command(&args),
        Command::Tradeoff(args) => tradeoff::command(&args),
        Command::CrossCode(args) => cross_code::command(&args),
        Command::Sweep(args) => sweep::command(&args),
        Command::Bifurcation {
            scene,
            min,
            max,
            step,
            ramp_deceleration,
            continuation,
            speed_step,
            dwell_s,
            criterion,
            jobs,
            set,
            out,
            json,
        } => {
            let scene = crate::config::scene::LoadedScene::load(&scene, &set)?;
            check_scene_rail(&scene)?;
            let settings = crate::studies::bifurcation::BifurcationSettings {
                min_m_s: min,
                max_m_s: max,
                step_m_s: step,
                deceleration_m_s2: ramp_deceleration,
                jobs: jobs
                    .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
                out_dir: out,
                criterion,
                continuations: continuation,
                dwell_step_m_s: speed_step,
                dwell_s,
            };
            let stop = preproc::cli::stop_on_signal(false);
            let mut b = crate::studies::bifurcation::bifurcation(&scene, &settings, stop)?;
            b.write(&settings.out_dir)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&b)?);
            } else {
                print!("{}", b.to_text());
            }
            Ok(())
        }
        Command::Compare {
            runs,
            out,
            wheelset,
            title,
            by,
        } => compare_runs(&runs, &out, wheelset, &title, by),
        Command::CompareContactTables {
            ours,
            imported,
            out,
            json,
        } => {
            let c = crate::studies::compare_tables::compare_contact_tables(&ours, &imported, &out)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&c)?);
            } else {
                print!("{}", c.to_text());
            }
            Ok(())
        }
        Command::Probe { file, s, json } => {
            let p = crate::cli::probe::probe_file(&file, s)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&p)?);
            } else {
                print!("{}", p.to_text());
            }
            Ok(())
        }
    }
}

/// The vehicle's static preloads and residuals (docs/reference/08-multibody.md §8.3),
/// as `sim run` prints them before the run.
fn static_preload_text(scene: &crate::config::scene::LoadedScene) -> Result<String> {
    let v = scene.vehicle_file()?;
    Ok(v.statics.as_ref().map_or(String::new(), |s| s.table(&v)))
}

fn run_command(args: &RunArgs) -> Result<()> {
    let req = args.to_request()?;
    check_scene_rail(&req.scene)?;
    let plan = crate::session::plan::plan(&req.scene).context("planning the run")?;
    if args.plan_only {
        if args.json {
            println!("{}", serde_json::to_string_pretty(&plan)?);
        } else {
            print!("{}", plan.to_text());
        }
        return Ok(());
    }
    if !args.json {
        print!("{}", plan.to_text());
        print!("{}", static_preload_text(&req.scene)?);
    }
    let stop = preproc::cli::stop_on_signal(false);
    let bar = if args.quiet || args.json {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {msg}").expect("static template"),
        );
        b
    };
    let mut progress = |p: crate::run::RunProgress| {
        bar.set_position((1000.0 * p.simulated_s / p.total_s.max(1e-12)) as u64);
        let rtf = if p.wall_s > 0.0 {
            p.simulated_s / p.wall_s
        } else {
            0.0
        };
        bar.set_message(format!(
            "t = {:.3} / {:.3} s, real-time factor {:.2}",
            p.simulated_s, p.total_s, rtf
        ));
    };
    let result = crate::report::run_files::run_to_files(&req, plan, &mut progress, Some(stop));
    bar.finish_and_clear();
    let summary = result?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        print!("{}", summary.to_text());
    }
    if summary.stopped.as_deref() == Some(crate::run::INTERRUPTED) {
        // `sim run … && next-step` must not go on with a partial run.
        return Err(Interrupted {
            what: format!("the run; the results so far are in {}", summary.output),
        }
        .into());
    }
    Ok(())
}

fn critical_speed_command(args: &CriticalSpeedArgs) -> Result<()> {
    use crate::studies::critical_speed::study;

    let scene = crate::config::scene::LoadedScene::load(&args.scene, &args.set)?;
    check_scene_rail(&scene)?;
    let settings = args.settings(&scene);
    let stop = preproc::cli::stop_on_signal(false);
    let quiet = args.json;
    let mut report = study(&scene, &settings, stop, &mut |m| {
        if !quiet {
            eprintln!("{m}");
        }
    })?;
    report.write(&args.out)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.to_text());
    }
    Ok(())
}

/// `sim compare`: the chart, then each later run against the first, per
/// wheelset both have, at equal track position or time
/// ([`crate::studies::run_difference`]).
fn compare_runs(
    runs: &[PathBuf],
    out: &Path,
    wheelset: usize,
    title: &str,
    by: args::CompareBy,
) -> Result<()> {
    use crate::studies::run_difference::{Abscissa, lateral_difference_by};
    let abscissa = match by {
        args::CompareBy::Position => Abscissa::TrackPosition,
        args::CompareBy::Time => Abscissa::Time,
    };
    let mut loaded = Vec::new();
    for p in runs {
        let r = runtime::io::schema::read_results(p)
            .with_context(|| format!("reading {}", p.display()))?;
        let shown = |name: &str| r.attribute(name).map_or("?".into(), |v| v.to_string());
        let label = format!("{} m/s, {}", shown("speed_m_s"), shown("creep_law"));
        loaded.push((label, r));
    }
    if abscissa == Abscissa::TrackPosition {
        for (path, (_, r)) in runs.iter().zip(&loaded) {
            let without: Vec<String> = r
                .wheelsets
                .iter()
                .filter(|w| w.track_s_m.is_empty() || w.track_s_m.iter().any(|s| !s.is_finite()))
                .map(|w| format!("'{}'", w.name))
                .collect();
            if !without.is_empty() {
                eprintln!(
                    "warning: {} has no track position for wheelset(s) {} (a file written before track_s_m was stored): compared and plotted by the distance travelled since the start instead, which lines up only runs that started at the same track position",
                    path.display(),
                    without.join(", ")
                );
            }
        }
    }
    let refs: Vec<(String, &runtime::results::RunResults)> =
        loaded.iter().map(|(l, r)| (l.clone(), r)).collect();
    crate::report::run_plots::write_comparison_plot_by(&refs, wheelset, out, title, abscissa)?;
    println!("wrote {}", out.display());
    let (first_path, (_, first)) = (&runs[0], &loaded[0]);
    for (path, (_, r)) in runs.iter().zip(&loaded).skip(1) {
        for (i, w) in r.wheelsets.iter().enumerate().take(first.wheelsets.len()) {
            let d = lateral_difference_by(first, r, i, abscissa).with_context(|| {
                format!("comparing {} with {}", path.display(), first_path.display())
            })?;
            let over = match abscissa {
                Abscissa::Time => format!("{:.3} s (t {:.3} … {:.3} s)", d.span(), d.from, d.to),
                Abscissa::TrackPosition => {
                    let what = if d.fell_back.contains(&true) {
                        "distance travelled"
                    } else {
                        "track"
                    };
                    format!(
                        "{:.3} m of {what} ({:.3} … {:.3} m)",
                        d.span(),
                        d.from,
                        d.to
                    )
                }
            };
            println!(
                "{} against {}, wheelset {i} ({}): lateral difference max {:.4} µm, rms {:.4} µm over {over}",
                path.display(),
                first_path.display(),
                w.name,
                d.max_m * 1e6,
                d.rms_m * 1e6
            );
        }
    }
    Ok(())
}
