//! The command line of `sim`: its subcommands and arguments (clap), each
//! turned into a checked request by a second stage.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use runtime::forces::creep::CreepLaw;
use runtime::multibody::loaded_wheelset::{LoadConvention, PatchLocation};

/// Railway vehicle dynamics on pre-processed track tables.
#[derive(Debug, Parser)]
#[command(name = "sim", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Contact of a wheelset at a prescribed pose on a straight track.
    Contact(ContactArgs),
    /// Creep curves (force / μN against creepage) of every creep law for one contact ellipse.
    CreepCurves(CreepCurveArgs),
    /// Run a scene: a wheelset or bogie on the track; results (HDF5), plots, summary.
    Run(RunArgs),
    /// Critical speed per creep law: time-domain growth rates, a speed ramp, eigenvalues.
    CriticalSpeed(CriticalSpeedArgs),
    /// Speed against accuracy: the scene over the numerical knobs against a fine reference run.
    Tradeoff(super::tradeoff::TradeoffArgs),
    /// Parameter studies over any scene key: a study file's variants run on the local cores, sharded, resumable; `merge` joins shards; `slurm` writes a Slurm job array.
    Sweep(super::sweep::SweepArgs),
    /// One vehicle in several formulations side by side (a published one, ours, each difference alone): linear and nonlinear critical speeds, cycle amplitudes, bifurcation plot.
    CrossCode(super::cross_code::CrossCodeArgs),
    /// Bifurcation diagram: every wheelset's hunting amplitude against speed (up-scan, ramp-down and/or step-and-dwell continuation).
    Bifurcation {
        /// Scene file (TOML).
        #[arg(value_name = "SCENE.toml")]
        scene: PathBuf,
        /// Lowest speed (m/s).
        #[arg(long, value_name = "V")]
        min: f64,
        /// Highest speed (start of the ramp-down) (m/s).
        #[arg(long, value_name = "V")]
        max: f64,
        /// Speed step of the up-scan (m/s).
        #[arg(long, default_value_t = 2.0, value_name = "V")]
        step: f64,
        /// Deceleration of the ramp-down, and of the step-dwell's steps (m/s²).
        #[arg(long, default_value_t = 0.5, value_name = "A")]
        ramp_deceleration: f64,
        /// How the hunting branch is followed down: ramp (one decelerating run) or step-dwell (each speed held --dwell-s, --speed-step apart); repeatable for both.
        #[arg(long = "continuation", value_name = "C", default_value = "ramp")]
        continuation: Vec<crate::studies::bifurcation::Continuation>,
        /// Speed step of the step-dwell continuation (m/s).
        #[arg(long, default_value_t = 0.5, value_name = "V")]
        speed_step: f64,
        /// Time each step-dwell speed is held (s); its amplitude is taken over the second half.
        #[arg(long, default_value_t = 10.0, value_name = "S")]
        dwell_s: f64,
        /// The nonlinear critical speed where every wheelset's cycle has died (all) or the leading wheelset's (leading).
        #[arg(long, default_value = "all", value_name = "C")]
        criterion: crate::studies::cycle_death::HuntingCriterion,
        /// Runs in parallel [default: the number of cores].
        #[arg(long, value_name = "N")]
        jobs: Option<usize>,
        /// Set a scene entry for every run (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Output directory.
        #[arg(long, value_name = "DIR", default_value = "bifurcation")]
        out: PathBuf,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
    /// Lateral displacement of one wheelset from several results files in one chart against track position; prints each later run's lateral difference from the first at equal track position (or time: --by time), per wheelset, and the span compared.
    Compare {
        /// Results files written by `sim run`.
        #[arg(value_name = "RESULTS.h5", required = true)]
        runs: Vec<PathBuf>,
        /// Output PNG.
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
        /// Wheelset index (0 = the first in the vehicle file).
        #[arg(long, default_value_t = 0)]
        wheelset: usize,
        /// Chart title.
        #[arg(long, default_value = "Lateral displacement")]
        title: String,
        /// Compare (and plot) at equal track position of each wheelset (its track_s_m; files without it: the distance travelled, with a warning) or at equal time since the start.
        #[arg(long, value_enum, default_value_t = CompareBy::Position)]
        by: CompareBy,
    },
    /// Our contact table of a wheel/rail pair against an imported one (rolling radius, contact angle, semi-axes, Δr): PNGs, CSV, summary.
    CompareContactTables {
        /// Our contact lookup table (from track-preproc contact-table).
        #[arg(long, value_name = "OURS.h5")]
        ours: PathBuf,
        /// The imported table: a .h5 from track-preproc import-contact-table, or an RSGEO .dat.
        #[arg(long, value_name = "IMPORTED.h5")]
        imported: PathBuf,
        /// Output directory (PNGs and comparison.csv).
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Print the summary as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Print both rails' interpolated position and frame at a centreline distance.
    Probe {
        /// Track table file written by `track-preproc build`.
        #[arg(value_name = "TABLES.h5")]
        file: PathBuf,
        /// Centreline distance s (m).
        #[arg(long, value_name = "S", allow_negative_numbers = true)]
        s: f64,
        /// Print JSON.
        #[arg(long)]
        json: bool,
    },
}

/// Arguments of `sim contact`.
#[derive(Debug, clap::Args)]
pub struct ContactArgs {
    /// Wheel profile (SIMPACK .prw, two columns y z (mm), or CSV y_mm,z_mm).
    #[arg(long, value_name = "FILE")]
    pub wheel: PathBuf,
    /// Rail profile (SIMPACK .prr, two columns, or CSV). A file already
    /// canted (detected from its head's symmetry) is refused with a non-zero
    /// --rail-inclination: double canting.
    #[arg(long, value_name = "FILE")]
    pub rail: PathBuf,
    /// The cant the rail profile file already carries as drawn: 1:40, 0, …
    /// (overrides its detection; declared, the rail inclination is added
    /// to it on purpose).
    #[arg(long, value_name = "R")]
    pub rail_profile_cant: Option<String>,
    /// Track gauge (m) (between the gauge points, 14 mm below the top).
    #[arg(long, default_value_t = 1.435, value_name = "M")]
    pub gauge: f64,
    /// Distance between the flange backs (m).
    #[arg(long, default_value_t = 1.360, value_name = "M")]
    pub back_to_back: f64,
    /// Nominal rolling radius at the taping line (m).
    #[arg(long, default_value_t = 0.46, value_name = "M")]
    pub wheel_radius: f64,
    /// Rail inclination towards the track centre, turning the rail profile
    /// as drawn: 1:40, 1:20, 0, … (0 for profiles that already carry it,
    /// like MBench_UIC60_v3.prr).
    #[arg(long, default_value = preproc::config::DEFAULT_RAIL_INCLINATION, value_name = "R")]
    pub rail_inclination: String,
    /// Lateral shift of the wheelset, positive to the left (mm).
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "Y",
        allow_negative_numbers = true
    )]
    pub y_mm: f64,
    /// Yaw of the wheelset, positive turning its nose left (mrad).
    #[arg(
        long,
        default_value_t = 0.0,
        value_name = "PSI",
        allow_negative_numbers = true
    )]
    pub yaw_mrad: f64,
    /// Roll of the wheelset, positive raising the left wheel (rad); each
    /// wheel is then solved at its own height. Default: solved so that both
    /// wheels carry their load.
    #[arg(long, value_name = "RAD", allow_negative_numbers = true)]
    pub roll_rad: Option<f64>,
    /// Angular velocity of the axle, positive rolling forward (rad/s); the
    /// creepages are relative to it. Default: V/r₀.
    #[arg(long, value_name = "W", allow_negative_numbers = true)]
    pub axle_rate_rad_s: Option<f64>,
    /// Poses file (CSV: y_mm, yaw_mrad and optional roll_rad,
    /// axle_rate_rad_s, speed_m_s, vertical_force_per_wheel_n, case): every
    /// pose in one run, one output row per contact patch. Replaces --y-mm,
    /// --yaw-mrad, --roll-rad and --axle-rate-rad-s.
    #[arg(long, value_name = "POSES.csv", conflicts_with_all = ["y_mm", "yaw_mrad", "roll_rad", "axle_rate_rad_s"])]
    pub poses: Option<PathBuf>,
    /// Vertical load per wheel (N) (Hertzian contact).
    #[arg(long, default_value_t = 10_000.0, value_name = "N")]
    pub wheel_load_n: f64,
    /// What the vertical load balances: `vertical` (the vertical components
    /// of the normal and the creep forces of all the wheel's patches, solved
    /// together: the Manchester benchmark's definition) or `normal` (the
    /// normal forces' vertical components alone).
    #[arg(long, value_enum, default_value_t = LoadConventionArg::Vertical)]
    pub load_convention: LoadConventionArg,
    /// Where each patch is located, its creepages evaluated and its forces
    /// directed: `centre` (the centroid of the undeformed interpenetration
    /// volume, as CONTACT reports it) or `deepest` (the point of maximum
    /// penetration of the contact equations).
    #[arg(long, value_enum, default_value_t = PatchLocationArg::Centre)]
    pub patch_location: PatchLocationArg,
    /// Rigid contact instead (both wheels just touching).
    #[arg(long)]
    pub rigid: bool,
    /// Young's modulus (Pa).
    #[arg(long, default_value_t = 210e9, value_name = "E")]
    pub young_pa: f64,
    /// Poisson's ratio.
    #[arg(long, default_value_t = 0.3, value_name = "NU")]
    pub poisson: f64,
    /// Spline scheme of the profile functions.
    #[arg(long, default_value = "cubic", value_parser = ["cubic", "cubic-natural", "akima", "pchip"])]
    pub profile_scheme: String,
    /// Forward speed of the wheelset (m/s); it spins at V/r₀ about its axle.
    #[arg(long, default_value_t = 30.0, value_name = "V")]
    pub speed_m_s: f64,
    /// Creep law.
    #[arg(long, default_value = "polach", value_parser = CreepLaw::NAMES)]
    pub creep: String,
    /// Coefficient of friction.
    #[arg(long, default_value_t = 0.3, value_name = "MU")]
    pub mu: f64,
    /// A profile that folds back, repeats its lateral coordinate or breaks
    /// inside is refused; with this flag its longest usable stretch is kept
    /// instead, and a warning names every dropped line.
    #[arg(long)]
    pub keep_longest_stretch: bool,
    /// Print JSON (the same as --format json).
    #[arg(long, conflicts_with = "format")]
    pub json: bool,
    /// Output format: `text` (default), `json` (one object per pose) or
    /// `csv` (one row per contact patch, in mm, rad, N, N·mm).
    #[arg(long, value_enum)]
    pub format: Option<ContactFormat>,
    /// Write the output to this file (all or nothing) instead of standard
    /// output.
    #[arg(short = 'o', long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Load convention of `sim contact` (see `--load-convention`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LoadConventionArg {
    Vertical,
    Normal,
}

/// Patch location of `sim contact` (see `--patch-location`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PatchLocationArg {
    Centre,
    Deepest,
}

/// Output format of `sim contact`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ContactFormat {
    Text,
    Json,
    Csv,
}

/// Arguments of `sim critical-speed`.
#[derive(Debug, clap::Args)]
pub struct CriticalSpeedArgs {
    /// Scene file (TOML).
    #[arg(value_name = "SCENE.toml")]
    pub scene: PathBuf,
    /// Creep law (repeatable) [default: the scene's].
    #[arg(long = "creep", value_name = "LAW")]
    pub creep: Vec<crate::config::scene::CreepLawName>,
    /// Lowest speed of the search (m/s).
    #[arg(long, default_value_t = 10.0, value_name = "V")]
    pub min: f64,
    /// Highest speed of the search (and start of the ramp) (m/s).
    #[arg(long, default_value_t = 120.0, value_name = "V")]
    pub max: f64,
    /// Width of the final bracket (m/s).
    #[arg(long, default_value_t = 0.1, value_name = "V")]
    pub tol: f64,
    /// Runs in parallel [default: the number of cores].
    #[arg(long, value_name = "N")]
    pub jobs: Option<usize>,
    /// time (growth rates of runs), ramp (nonlinear, speed ramped down), linear (eigenvalues); repeatable.
    #[arg(long = "method", value_name = "M", default_value = "time")]
    pub method: Vec<crate::studies::critical_speed::CriticalSpeedMethod>,
    /// Start transient skipped by the growth-rate fit (s).
    #[arg(long, default_value_t = 1.0, value_name = "S")]
    pub skip_s: f64,
    /// Deceleration of the ramp (m/s²).
    #[arg(long, default_value_t = 0.5, value_name = "A")]
    pub ramp_deceleration: f64,
    /// Ramp: the nonlinear critical speed where every wheelset's cycle has died (all) or the leading wheelset's (leading).
    #[arg(long, default_value = "all", value_name = "C")]
    pub criterion: crate::studies::cycle_death::HuntingCriterion,
    /// Set a scene entry for every run (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output directory (rates.csv, rates.png, ramp_wheelsets.csv, runs/).
    #[arg(long, value_name = "DIR", default_value = "critical_speed")]
    pub out: PathBuf,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

impl CriticalSpeedArgs {
    /// The study's settings for `scene`: its creep law when none is given,
    /// every core when `--jobs` is not.
    pub fn settings(
        &self,
        scene: &crate::config::scene::LoadedScene,
    ) -> crate::studies::critical_speed::CriticalSpeedSettings {
        crate::studies::critical_speed::CriticalSpeedSettings {
            laws: if self.creep.is_empty() {
                vec![scene.scene.contact.creep_law]
            } else {
                self.creep.clone()
            },
            min_m_s: self.min,
            max_m_s: self.max,
            tol_m_s: self.tol,
            jobs: self
                .jobs
                .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
            methods: self.method.clone(),
            out_dir: self.out.clone(),
            skip_s: self.skip_s,
            ramp_deceleration_m_s2: self.ramp_deceleration,
            criterion: self.criterion,
        }
    }
}

/// Arguments of `sim run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Scene file (TOML); without it, the paper's single-wheelset case on the shipped data.
    #[arg(value_name = "SCENE.toml")]
    pub scene: Option<PathBuf>,
    /// Results file (HDF5) [default: SCENE.h5 in the current directory, SCENE the scene file's name].
    #[arg(short, long, value_name = "OUT.h5")]
    pub output: Option<PathBuf>,
    /// Override a scene entry, e.g. --set initial.speed_m_s=20 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Directory for the PNG plots [default: OUT without .h5, then _plots].
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
    /// Do not draw plots.
    #[arg(long, conflicts_with = "plots")]
    pub no_plots: bool,
    /// Print the summary as JSON.
    #[arg(long)]
    pub json: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Model only what the scene requires: the planner chooses the flange
    /// search, contact method, table step, track range and integrator wherever the
    /// scene leaves them out (= --set plan.mode=required; docs/guide/speed-accuracy-tradeoff.md "Only what
    /// the scene requires").
    #[arg(long, conflicts_with = "model_everything")]
    pub plan: bool,
    /// Model everything: flange always searched, online contact, the finest
    /// table step, the whole track, RK4 at 0.1 ms (= --set plan.mode=everything).
    #[arg(long)]
    pub model_everything: bool,
    /// Print the plan (what the run would model, and why) and exit.
    #[arg(long)]
    pub plan_only: bool,
}

impl RunArgs {
    /// Second stage: the checked request.
    pub fn to_request(&self) -> Result<crate::report::run_files::RunRequest> {
        use crate::config::scene::LoadedScene;
        let mut set = self.set.clone();
        if self.plan {
            set.push("plan.mode=\"required\"".into());
        }
        if self.model_everything {
            set.push("plan.mode=\"everything\"".into());
        }
        let (scene, stem) = match &self.scene {
            Some(p) => (
                LoadedScene::load(p, &set)?,
                p.file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| "run".into()),
            ),
            None => (
                LoadedScene::default_scene(&set)?,
                "wheelset_straight".to_string(),
            ),
        };
        let output = self
            .output
            .clone()
            .unwrap_or_else(|| PathBuf::from(format!("{stem}.h5")));
        let plots = if self.no_plots {
            None
        } else {
            Some(self.plots.clone().unwrap_or_else(|| {
                let mut p = output.with_extension("").into_os_string();
                p.push("_plots");
                PathBuf::from(p)
            }))
        };
        // Refused before the run, not after it when the results are
        // written: an output that is an input, a directory for a file, a
        // missing or read-only directory.
        use runtime::io::{Output, OutputKind, check_outputs};
        let inputs = scene.input_paths();
        let mut outputs = vec![Output {
            path: output.clone(),
            kind: OutputKind::File,
            role: "the results file",
        }];
        outputs.extend(plots.iter().map(|p| Output {
            path: p.clone(),
            kind: OutputKind::Directory,
            role: "the plots folder",
        }));
        check_outputs(&inputs, &outputs)?;
        Ok(crate::report::run_files::RunRequest {
            scene,
            output,
            plots,
        })
    }
}

/// Arguments of `sim creep-curves`.
#[derive(Debug, clap::Args)]
pub struct CreepCurveArgs {
    /// Output directory (creep_curves.png, creep_curves.csv).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Normal force (N).
    #[arg(long, default_value_t = 80_000.0, value_name = "N")]
    pub normal_n: f64,
    /// Semi-axis of the contact ellipse in the rolling direction (mm) (with --b-mm; default: Hertz from the radii).
    #[arg(long, value_name = "MM", requires = "b_mm")]
    pub a_mm: Option<f64>,
    /// Lateral semi-axis (mm) (with --a-mm).
    #[arg(long, value_name = "MM", requires = "a_mm")]
    pub b_mm: Option<f64>,
    /// Wheel rolling radius for the Hertz ellipse (m).
    #[arg(long, default_value_t = 0.46, value_name = "M")]
    pub wheel_radius: f64,
    /// Rail head transverse radius for the Hertz ellipse (m).
    #[arg(long, default_value_t = 0.3, value_name = "M")]
    pub rail_head_radius: f64,
    /// Coefficient of friction.
    #[arg(long, default_value_t = 0.3, value_name = "MU")]
    pub mu: f64,
    /// Rolling speed (m/s) (slip-velocity dependent friction).
    #[arg(long, default_value_t = 30.0, value_name = "V")]
    pub speed_m_s: f64,
    /// Young's modulus (Pa).
    #[arg(long, default_value_t = 210e9, value_name = "E")]
    pub young_pa: f64,
    /// Poisson's ratio.
    #[arg(long, default_value_t = 0.3, value_name = "NU")]
    pub poisson: f64,
    /// Largest creepage of the ξ and η sweeps (default: twice the heuristic law's saturation creepage).
    #[arg(long, value_name = "S")]
    pub max_creepage: Option<f64>,
    /// Points per curve.
    #[arg(long, default_value_t = 201, value_name = "K")]
    pub points: usize,
    /// FASTSIM strips across the ellipse.
    #[arg(long, value_name = "K")]
    pub fastsim_strips: Option<usize>,
    /// FASTSIM elements per strip.
    #[arg(long, value_name = "K")]
    pub fastsim_elements: Option<usize>,
}

impl CreepCurveArgs {
    /// Second stage: checked settings.
    pub fn to_config(&self) -> Result<crate::studies::creep_curves::CreepCurveConfig> {
        use crate::studies::creep_curves::CreepCurveConfig;
        let material = crate::studies::contact::material(self.young_pa, self.poisson);
        material.validate().context("--young-pa / --poisson")?;
        let (a_m, b_m) = match (self.a_mm, self.b_mm) {
            (Some(a), Some(b)) => (a * 1e-3, b * 1e-3),
            _ => CreepCurveConfig::from_radii(
                self.normal_n,
                self.wheel_radius,
                self.rail_head_radius,
                material,
            )?,
        };
        let mut fastsim = runtime::forces::creep::FastsimParams::default();
        if let Some(k) = self.fastsim_strips {
            fastsim.strips = k;
        }
        if let Some(k) = self.fastsim_elements {
            fastsim.elements_per_strip = k;
        }
        let config = CreepCurveConfig {
            normal_force_n: self.normal_n,
            a_m,
            b_m,
            friction_coefficient: self.mu,
            speed_m_s: self.speed_m_s,
            material,
            max_creepage: self.max_creepage,
            points: self.points,
            fastsim,
        };
        config.validate()?;
        Ok(config)
    }
}

impl ContactArgs {
    /// Second stage: the wheelset's motion and the force models.
    pub fn to_rolling(&self) -> Result<crate::studies::contact::Rolling> {
        let creep_law = CreepLaw::from_name(&self.creep)
            .with_context(|| format!("--creep {}: unknown creep law", self.creep))?;
        let settings = runtime::multibody::contact_force::ContactForceSettings {
            material: crate::studies::contact::material(self.young_pa, self.poisson),
            friction_coefficient: self.mu,
            creep_law,
            ..Default::default()
        };
        settings.validate().context("force model settings")?;
        if !(self.speed_m_s.is_finite() && self.speed_m_s >= 0.0) {
            anyhow::bail!(
                "--speed-m-s must be finite and >= 0, got {}",
                self.speed_m_s
            );
        }
        Ok(crate::studies::contact::Rolling {
            speed_m_s: self.speed_m_s,
            settings,
            convention: match self.load_convention {
                LoadConventionArg::Vertical => LoadConvention::Vertical,
                LoadConventionArg::Normal => LoadConvention::Normal,
            },
            location: match self.patch_location {
                PatchLocationArg::Centre => PatchLocation::Centre,
                PatchLocationArg::Deepest => PatchLocation::DeepestPoint,
            },
        })
    }

    /// The output format asked for.
    pub fn format(&self) -> ContactFormat {
        match (self.format, self.json) {
            (Some(f), _) => f,
            (None, true) => ContactFormat::Json,
            (None, false) => ContactFormat::Text,
        }
    }

    /// The single pose of the command line.
    pub fn pose(&self) -> crate::studies::contact::PoseRequest {
        crate::studies::contact::PoseRequest {
            case: 1,
            y_m: self.y_mm * 1e-3,
            yaw_rad: self.yaw_mrad * 1e-3,
            roll_rad: self.roll_rad,
            axle_rate_rad_s: self.axle_rate_rad_s,
            speed_m_s: None,
            load_n: None,
        }
    }

    /// The output file, checked before the work: not one of the inputs,
    /// its folder writable.
    pub fn checked_out(&self) -> Result<Option<PathBuf>> {
        let Some(out) = &self.out else {
            return Ok(None);
        };
        use runtime::io::{Output, OutputKind, check_outputs};
        let mut inputs = vec![self.wheel.clone(), self.rail.clone()];
        inputs.extend(self.poses.iter().cloned());
        check_outputs(
            &inputs,
            &[Output {
                path: out.clone(),
                kind: OutputKind::File,
                role: "the contact output",
            }],
        )?;
        Ok(Some(out.clone()))
    }

    /// Second stage: checked settings.
    pub fn to_config(&self) -> Result<preproc::contact_table::ContactTableConfig> {
        use preproc::contact_table::{ContactTableConfig, TableSupport};
        let inclination: preproc::Inclination = self
            .rail_inclination
            .parse()
            .map_err(anyhow::Error::msg)
            .context("--rail-inclination")?;
        let config = ContactTableConfig {
            wheel_profile: self.wheel.clone(),
            rail_profile: self.rail.clone(),
            profile_scheme: self.profile_scheme.parse()?,
            wheel_radius_m: self.wheel_radius,
            back_to_back_m: self.back_to_back,
            gauge_m: self.gauge,
            rail_spacing_m: self.gauge + 2.0 * preproc::config::DEFAULT_GAUGE_FACE_OFFSET_M,
            rail_inclination_rad: inclination.angle_rad,
            rail_profile_cant_rad: self
                .rail_profile_cant
                .as_deref()
                .map(|t| {
                    t.parse::<preproc::Inclination>()
                        .map_err(anyhow::Error::msg)
                        .context("--rail-profile-cant")
                })
                .transpose()?
                .map(|c| c.angle_rad),
            support: if self.rigid {
                TableSupport::Rigid
            } else {
                TableSupport::Elastic {
                    wheel_load_n: self.wheel_load_n,
                    material: crate::studies::contact::material(self.young_pa, self.poisson),
                }
            },
            keep_longest_stretch: self.keep_longest_stretch,
            ..Default::default()
        };
        config.validate()?;
        Ok(config)
    }
}

/// What `sim compare` lines the runs up by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CompareBy {
    /// Equal track position s of the wheelset (m).
    Position,
    /// Equal time since the start (s).
    Time,
}
