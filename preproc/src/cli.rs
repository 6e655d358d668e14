//! Command-line interface of `track-preproc` (thin: parse, check, call the
//! library, print).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use runtime::geometry::spline::Scheme;
use runtime::io::{Output, OutputKind, check_outputs};

use runtime::forces::hertz::Material;

use crate::config::{BuildConfig, Inclination, RailSpacing};
use crate::contact_table::{ContactTableConfig, TableSupport};
use crate::pipeline::{
    BuildRequest, ContactTableRequest, GeometryFiles, run_build, run_contact_table,
};
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
    /// Build the centreline and rail databases of a track (and, with --wheel
    /// and --rail, the contact lookup table).
    Build(BuildArgs),
    /// Build only the contact lookup table of a wheel/rail profile pair.
    ContactTable(ContactTableArgs),
    /// Import a contact geometry table computed by another code (DYTSI's RSGEO.dat) into HDF5.
    ImportContactTable(ImportContactTableArgs),
}

/// Arguments of `track-preproc import-contact-table`.
#[derive(Debug, Args)]
pub struct ImportContactTableArgs {
    /// Format of the input file (only DYTSI's RSGEO tables for now).
    #[arg(long, value_parser = ["rsgeo"], value_name = "FORMAT")]
    pub format: String,
    /// The table to import.
    #[arg(value_name = "FILE")]
    pub input: PathBuf,
    /// Output file (.h5), written atomically.
    #[arg(short, long, value_name = "OUT.h5")]
    pub output: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Profile pair and settings of a contact lookup table.
#[derive(Debug, Args, Clone)]
pub struct ContactArgs {
    /// Wheel profile (SIMPACK .prw, two columns y z (mm), or CSV y_mm,z_mm).
    #[arg(long, value_name = "FILE")]
    pub wheel: Option<PathBuf>,
    /// Rail profile (SIMPACK .prr, two columns, or CSV). A file already
    /// canted (detected from its head's symmetry) is refused with a non-zero
    /// --rail-inclination: double canting.
    #[arg(long, value_name = "FILE")]
    pub rail: Option<PathBuf>,
    /// The cant the rail profile file already carries as drawn: 1:40, 0, …
    /// (overrides its detection; declared, the rail inclination is added
    /// to it on purpose).
    #[arg(long, value_name = "R")]
    pub rail_profile_cant: Option<String>,
    /// Distance between the flange backs (m).
    #[arg(long, default_value_t = 1.360, value_name = "M")]
    pub back_to_back: f64,
    /// Nominal rolling radius at the taping line (m).
    #[arg(long, default_value_t = 0.46, value_name = "M")]
    pub wheel_radius: f64,
    /// Vertical load per wheel for the elastic (Hertzian) table (N).
    #[arg(long, value_name = "N", default_value_t = crate::contact_table::DEFAULT_WHEEL_LOAD_N)]
    pub wheel_load_n: f64,
    /// Rigid contact instead of elastic (both wheels just touching).
    #[arg(long)]
    pub rigid: bool,
    /// Young's modulus of wheel and rail (Pa).
    #[arg(long, default_value_t = 210e9, value_name = "PA")]
    pub young_pa: f64,
    /// Poisson's ratio of wheel and rail.
    #[arg(long, default_value_t = 0.3, value_name = "NU")]
    pub poisson: f64,
    /// Lateral shifts from −A to +A (mm).
    #[arg(long, default_value_t = 15.0, value_name = "A")]
    pub y_range_mm: f64,
    /// Step of the lateral shifts (mm).
    #[arg(long, default_value_t = 0.1, value_name = "S")]
    pub y_step_mm: f64,
    /// Yaw angles of the table (mrad), comma-separated (default: 0 only).
    #[arg(
        long,
        value_name = "LIST",
        value_delimiter = ',',
        allow_negative_numbers = true
    )]
    pub yaw_mrad: Vec<f64>,
    /// Spline scheme of the profile functions.
    #[arg(long, default_value = "cubic", value_parser = ["cubic", "cubic-natural", "akima", "pchip"])]
    pub profile_scheme: String,
    /// Write plots (Δr(y), contact points on the profiles) into this directory.
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
    /// A profile that folds back, repeats its lateral coordinate or breaks
    /// inside is refused; with this flag its longest usable stretch is kept
    /// instead, and a warning names every dropped line.
    #[arg(long)]
    pub keep_longest_stretch: bool,
}

/// The declared cant of `--rail-profile-cant`, parsed.
fn declared_cant(text: Option<&str>) -> Result<Option<Inclination>> {
    text.map(|t| {
        t.parse::<Inclination>()
            .map_err(anyhow::Error::msg)
            .context("--rail-profile-cant")
    })
    .transpose()
}

/// `--rail-inclination`, parsed.
fn inclination(text: &str) -> Result<Inclination> {
    text.parse()
        .map_err(anyhow::Error::msg)
        .context("--rail-inclination")
}

/// Prints the warnings of a rail profile check on standard error.
fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("{w}");
    }
}

impl ContactArgs {
    /// The contact-table settings, when both profiles are given.
    pub fn to_config(&self) -> Result<Option<ContactTableConfig>> {
        let (wheel, rail) = match (&self.wheel, &self.rail) {
            (None, None) => return Ok(None),
            (Some(w), Some(r)) => (w.clone(), r.clone()),
            _ => anyhow::bail!("--wheel and --rail go together: give both profiles or neither"),
        };
        let mut yaw: Vec<f64> = self.yaw_mrad.iter().map(|m| m * 1e-3).collect();
        if yaw.is_empty() {
            yaw.push(0.0);
        }
        yaw.sort_by(f64::total_cmp);
        let config = ContactTableConfig {
            wheel_profile: wheel,
            rail_profile: rail,
            profile_scheme: self.profile_scheme.parse()?,
            wheel_radius_m: self.wheel_radius,
            back_to_back_m: self.back_to_back,
            y_min_m: -self.y_range_mm * 1e-3,
            y_max_m: self.y_range_mm * 1e-3,
            y_step_m: self.y_step_mm * 1e-3,
            yaw_rad: yaw,
            rail_profile_cant_rad: declared_cant(self.rail_profile_cant.as_deref())?
                .map(|c| c.angle_rad),
            support: if self.rigid {
                TableSupport::Rigid
            } else {
                TableSupport::Elastic {
                    wheel_load_n: self.wheel_load_n,
                    material: Material {
                        young_pa: self.young_pa,
                        poisson: self.poisson,
                    },
                }
            },
            keep_longest_stretch: self.keep_longest_stretch,
            ..Default::default()
        };
        config.validate()?;
        Ok(Some(config))
    }
}

/// Arguments of `track-preproc contact-table`.
#[derive(Debug, Args)]
pub struct ContactTableArgs {
    #[command(flatten)]
    pub contact: ContactArgs,
    /// Track gauge (m).
    #[arg(long, default_value_t = crate::config::DEFAULT_GAUGE_M, value_name = "M")]
    pub gauge: f64,
    /// Distance between the rail profile origins (m) (default: gauge + 2 × gauge-face offset).
    #[arg(long, value_name = "M")]
    pub rail_spacing: Option<f64>,
    /// Lateral offset of the gauge face from the rail profile origin (m).
    #[arg(long, default_value_t = crate::config::DEFAULT_GAUGE_FACE_OFFSET_M, value_name = "M")]
    pub gauge_face_offset: f64,
    /// Rail inclination towards the track centre, turning the rail profile
    /// as drawn: 1:40, 1:20, 0, … (0 for profiles that already carry it,
    /// like MBench_UIC60_v3.prr).
    #[arg(long, default_value = crate::config::DEFAULT_RAIL_INCLINATION, value_name = "R")]
    pub rail_inclination: String,
    /// Output file (.h5), written atomically.
    #[arg(short, long, value_name = "OUT.h5")]
    pub output: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `track-preproc build`.
#[derive(Debug, Args)]
pub struct BuildArgs {
    /// Centreline control points: CSV with x, y, z (m) and optionally cant (rad) or cant_mm.
    #[arg(long, value_name = "FILE", required_unless_present = "design")]
    pub centerline: Option<PathBuf>,
    /// Cant table (overrides the centreline's cant): CSV with s and cant (rad) or cant_mm.
    #[arg(long, value_name = "FILE", conflicts_with = "design")]
    pub cant: Option<PathBuf>,
    /// Track from design elements (TOML: straights, arcs, transitions,
    /// cant ramps, grades; docs/reference/02-inputs.md §2.9), instead of
    /// --centerline/--cant.
    #[arg(long, value_name = "FILE", conflicts_with = "centerline")]
    pub design: Option<PathBuf>,
    /// Irregularities: CSV s, align_left, align_right, level_left, level_right (m)
    /// or s, alignment, gauge, level, cross_level; `_mm` suffix allowed.
    #[arg(long, value_name = "FILE")]
    pub irregularities: Option<PathBuf>,
    /// Spline scheme for the centreline and the rails.
    #[arg(long, default_value = "cubic", value_parser = ["cubic", "cubic-natural", "akima", "pchip"])]
    pub scheme: String,
    /// Spline scheme for the cant of control-point inputs (pchip: shape-preserving,
    /// no overshoot of a cant ramp).
    #[arg(long, default_value = "pchip", value_parser = ["cubic", "cubic-natural", "akima", "pchip"])]
    pub cant_scheme: String,
    /// Table step Δs (m).
    #[arg(long, default_value_t = crate::config::DEFAULT_STEP_M, value_name = "M")]
    pub step: f64,
    /// Track gauge (m).
    #[arg(long, default_value_t = crate::config::DEFAULT_GAUGE_M, value_name = "M")]
    pub gauge: f64,
    /// Distance between the rail profile origins (m) (default: gauge + 2 × gauge-face offset).
    #[arg(long, value_name = "M")]
    pub rail_spacing: Option<f64>,
    /// Lateral offset of the gauge face from the rail profile origin (m) (UIC60: 0.036).
    #[arg(long, default_value_t = crate::config::DEFAULT_GAUGE_FACE_OFFSET_M, value_name = "M")]
    pub gauge_face_offset: f64,
    /// Rail inclination towards the track centre, turning the rail profile
    /// as drawn: 1:40, 1:20, 0, … (0 for profiles that already carry it,
    /// like MBench_UIC60_v3.prr).
    #[arg(long, default_value = crate::config::DEFAULT_RAIL_INCLINATION, value_name = "R")]
    pub rail_inclination: String,
    /// Cant base e0 for cant heights, φ = asin(h/e0) (m) (default: gauge + 0.065).
    #[arg(long, value_name = "M")]
    pub cant_base: Option<f64>,
    /// Output table file (.h5), written atomically.
    #[arg(short, long, value_name = "OUT.h5")]
    pub output: PathBuf,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub contact: ContactArgs,
}

impl BuildArgs {
    /// Second stage: parsed arguments → checked build request.
    pub fn to_request(&self, command_line: String) -> Result<BuildRequest> {
        let scheme: Scheme = self.scheme.parse()?;
        let inclination = inclination(&self.rail_inclination)?;
        if self.contact.rail.is_none() && self.contact.rail_profile_cant.is_some() {
            anyhow::bail!(
                "--rail-profile-cant declares the cant of the --rail profile: give --rail too (nothing to declare it of)"
            );
        }
        let config = BuildConfig {
            scheme,
            cant_scheme: self.cant_scheme.parse()?,
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
            // The rail alone (no wheel) is checked and recorded, without a
            // contact table.
            rail_profile: self.contact.rail.clone(),
            rail_profile_cant: declared_cant(self.contact.rail_profile_cant.as_deref())?,
        };
        config.validate()?;
        let contact = match (&self.contact.wheel, &self.contact.rail) {
            (None, Some(_)) => None,
            _ => self.contact.to_config()?,
        };
        Ok(BuildRequest {
            contact,
            geometry: match (&self.design, &self.centerline) {
                (Some(d), None) => GeometryFiles::Design(d.clone()),
                (None, Some(c)) => GeometryFiles::ControlPoints {
                    centerline: c.clone(),
                    cant: self.cant.clone(),
                },
                _ => anyhow::bail!("give either --centerline (with --cant) or --design"),
            },
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

/// `track-preproc build` without its printing (also the Python package's
/// `build_track`): the request checked, the outputs checked before the
/// work (no output replaces an input, every location can be written,
/// `runtime::io::outputs`), the rail profile's warnings given to `warn`,
/// the build, then the contact plots when asked for.
pub fn build(
    args: &BuildArgs,
    command_line: String,
    sink: &dyn ProgressSink,
    warn: &dyn Fn(&[String]),
) -> Result<crate::summary::BuildSummary> {
    let req = args.to_request(command_line)?;
    let mut inputs: Vec<PathBuf> = req
        .geometry
        .paths()
        .into_iter()
        .chain(req.irregularities.iter().map(PathBuf::as_path))
        .map(Path::to_path_buf)
        .collect();
    if let Some(c) = &req.contact {
        inputs.extend(
            crate::contact_table::profile_paths(c)
                .into_iter()
                .map(|(_, p)| p.to_path_buf()),
        );
    }
    check_outputs(
        &inputs,
        &outputs(&req.output, args.contact.plots.as_deref()),
    )?;
    warn(
        &crate::pipeline::check_build_rail(&req.config)?
            .map(|c| c.warnings)
            .unwrap_or_default(),
    );
    let mut summary = run_build(&req, sink)
        .with_context(|| format!("building {} failed", req.output.display()))?;
    if let (Some(dir), Some(_)) = (&args.contact.plots, &req.contact) {
        let table = runtime::io::schema::read_contact_table(&req.output)?
            .context("the contact table just written is missing")?;
        crate::contact_plots::write_contact_plots(dir, &table)
            .with_context(|| format!("writing plots into {}", dir.display()))?;
    }
    summary.peak_memory_mb = crate::summary::peak_memory_mb();
    Ok(summary)
}

/// Run the CLI.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Build(args) => {
            let sink = BarSink::new();
            let summary = build(&args, command_line(), &sink, &|w| print_warnings(w))?;
            sink.event(Progress::Done);
            if args.json {
                println!("{}", serde_json::to_string_pretty(&summary)?);
            } else {
                print!("{}", summary.to_text());
            }
            Ok(())
        }
        Command::ImportContactTable(args) => import_contact_table(&args),
        Command::ContactTable(args) => {
            let inclination = inclination(&args.rail_inclination)?;
            let spacing = args
                .rail_spacing
                .unwrap_or(args.gauge + 2.0 * args.gauge_face_offset);
            let config = args
                .contact
                .to_config()?
                .context("contact-table needs --wheel and --rail")?;
            let config = ContactTableConfig {
                gauge_m: args.gauge,
                rail_spacing_m: spacing,
                rail_inclination_rad: inclination.angle_rad,
                ..config
            };
            let inputs: Vec<PathBuf> = crate::contact_table::profile_paths(&config)
                .into_iter()
                .map(|(_, p)| p.to_path_buf())
                .collect();
            check_outputs(
                &inputs,
                &outputs(&args.output, args.contact.plots.as_deref()),
            )?;
            // Warnings of the rail profile now; a refusal comes from the
            // build, after the wheel profile is read (its errors first).
            if let Ok(check) = config.check_rail() {
                print_warnings(&check.warnings);
            }
            let req = ContactTableRequest {
                config,
                output: args.output.clone(),
                command_line: command_line(),
            };
            let sink = BarSink::new();
            let (table, report) = run_contact_table(&req, &sink)
                .with_context(|| format!("building {} failed", req.output.display()))?;
            sink.event(Progress::Done);
            if let Some(dir) = &args.contact.plots {
                crate::contact_plots::write_contact_plots(dir, &table)
                    .with_context(|| format!("writing plots into {}", dir.display()))?;
            }
            if args.json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!(
                    "wrote {}\n{}  time              {:.3} s\n",
                    report.output,
                    report.contact_table.to_text(),
                    report.elapsed_s
                );
            }
            Ok(())
        }
    }
}

/// Summary of `track-preproc import-contact-table`.
#[derive(Debug, serde::Serialize)]
pub struct ImportSummary {
    pub input: String,
    pub output: String,
    pub format: String,
    pub rows: usize,
    pub y_min_m: f64,
    pub y_max_m: f64,
    pub y_step_m: f64,
    /// The left wheel's contact at y = 0 (N0 N, δ rad, a b m, lateral m, r m, q0 m).
    pub normal_force_at_0_n: f64,
    pub contact_angle_at_0_rad: f64,
    pub a_at_0_m: f64,
    pub b_at_0_m: f64,
    pub wheel_lateral_at_0_m: f64,
    pub rolling_radius_at_0_m: f64,
    pub penetration_at_0_m: f64,
}

/// The table file and, when asked for, the plots folder of a command.
fn outputs(table: &Path, plots: Option<&Path>) -> Vec<Output> {
    let mut out = vec![Output {
        path: table.to_path_buf(),
        kind: OutputKind::File,
        role: "the table file",
    }];
    out.extend(plots.map(|p| Output {
        path: p.to_path_buf(),
        kind: OutputKind::Directory,
        role: "the plots folder",
    }));
    out
}

fn import_contact_table(args: &ImportContactTableArgs) -> Result<()> {
    use runtime::geometry::track::{InputFile, Provenance};
    check_outputs(
        std::slice::from_ref(&args.input),
        &outputs(&args.output, None),
    )?;
    let table = match args.format.as_str() {
        "rsgeo" => crate::rsgeo::read_rsgeo(&args.input)?,
        other => anyhow::bail!("--format {other}: only rsgeo is supported"),
    };
    let text = std::fs::read_to_string(&args.input)
        .with_context(|| format!("reading {}", args.input.display()))?;
    let provenance = Provenance {
        command_line: command_line(),
        inputs: vec![InputFile {
            role: args.format.clone(),
            path: args.input.display().to_string(),
            text,
        }],
    };
    runtime::io::schema::write_imported_contact_table_file(&args.output, &table, &provenance)
        .with_context(|| format!("writing {}", args.output.display()))?;
    let at0 = table
        .row_at(0.0)
        .context("the table does not cover y = 0")?;
    let (lo, hi) = table.range_m();
    let summary = ImportSummary {
        input: args.input.display().to_string(),
        output: args.output.display().to_string(),
        format: table.format.clone(),
        rows: table.rows.len(),
        y_min_m: lo,
        y_max_m: hi,
        y_step_m: table.step_m(),
        normal_force_at_0_n: at0.normal_force_n,
        contact_angle_at_0_rad: at0.contact_angle_rad,
        a_at_0_m: at0.a_m,
        b_at_0_m: at0.b_m,
        wheel_lateral_at_0_m: at0.wheel_lateral_m,
        rolling_radius_at_0_m: at0.rolling_radius_m,
        penetration_at_0_m: at0.penetration_m,
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!(
            "wrote {}\n  {} rows ({}), y from {:+.3} to {:+.3} mm every {:.4} mm (rows: the left wheel)\n  at y = 0: N0 = {:.0} N, δ = {:.5} rad, a = {:.3} mm, b = {:.3} mm, r = {:.6} m, contact point {:.6} m from the centre, q0 = {:.2} µm",
            summary.output,
            summary.rows,
            summary.format,
            lo * 1e3,
            hi * 1e3,
            summary.y_step_m * 1e3,
            at0.normal_force_n,
            at0.contact_angle_rad,
            at0.a_m * 1e3,
            at0.b_m * 1e3,
            at0.rolling_radius_m,
            at0.wheel_lateral_m,
            at0.penetration_m * 1e6
        );
    }
    Ok(())
}

/// Makes a closed standard output (`track-preproc … | head`, `sim probe … |
/// head`) end the process quietly, as it ends Unix tools: Rust programs
/// ignore SIGPIPE, so `println!` to a closed pipe would panic ("failed
/// printing to stdout: Broken pipe"). Call first thing in `main`, before
/// any thread starts.
pub fn exit_quietly_on_closed_pipe() {
    #[cfg(unix)]
    // SAFETY: sets the disposition of one signal to its default; called at
    // the start of `main`, before any other thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

/// Installs the SIGINT/SIGTERM handler of a binary (Ctrl-C, `kill`): the
/// first signal sets the returned flag, so that long work stops cleanly at
/// its next step and writes what it has; a second signal (or the first,
/// for work that cannot stop cleanly: `stop_at_once`) removes the output
/// temporaries being written (`runtime::io::remove_temporaries_in_flight`)
/// and exits with 130 — no incomplete file is left behind.
pub fn stop_on_signal(stop_at_once: bool) -> std::sync::Arc<std::sync::atomic::AtomicBool> {
    use std::sync::atomic::Ordering;
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = stop.clone();
    // Installing fails only in a host that owns the signals; the default
    // action then applies, and the next write removes the stale temporary.
    let _ = ctrlc::set_handler(move || {
        if stop_at_once || flag.swap(true, Ordering::Relaxed) {
            let n = runtime::io::remove_temporaries_in_flight();
            eprintln!("interrupted: {n} incomplete output file(s) removed");
            std::process::exit(130);
        }
    });
    stop
}
