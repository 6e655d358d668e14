//! `sim run`: a scene from file (or the built-in single-wheelset case) to a
//! results file, plots and a summary (SPEC §8). The track tables (and, with
//! `method = "table"`, the contact lookup tables) are built on demand and
//! cached ([`crate::cache`]); the vehicle file becomes a
//! [`VehicleModel`]; the system is integrated with the scene's method while
//! outputs are sampled at the scene's interval. Ctrl-C (a stop flag) ends
//! the run at the next accepted step and the results so far are written,
//! as they are when the run fails (derailment, a contact that cannot be
//! solved): the error is then reported after writing.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use anyhow::{Context, Result, anyhow, ensure};
use nalgebra::{Matrix3, Vector3};
use preproc::contact_table::{ContactTableConfig, TableSupport, build_contact_table};
use preproc::{BuildConfig, BuildRequest, Inclination, NoProgress, run_build};
use runtime::body::RigidBody;
use runtime::contact::{ContactOptions, FlangeSearch, WheelsetContactModel};
use runtime::contact_force::ContactForceSettings;
use runtime::contact_table::ContactTable;
use runtime::creepage::CreepageOptions;
use runtime::dynamics::imported_contact::ImportedContactMethod;
use runtime::dynamics::system::EnergyLedger;
use runtime::dynamics::{
    BodySpec, ContactMethod, ElementSpec, End, InitialConditions, Recorder, ReferenceSpec,
    SystemSettings, VehicleModel, VehicleSystem, WheelsetSpec,
};
use runtime::hertz::Material;
use runtime::imported_contact::ImportedContactTable;
use runtime::integrator::{IntegrationStats, OutputGrid, integrate};
use runtime::normal::NormalForceModel;
use runtime::profile::{RailPlacement, RailProfileOptions, WheelProfileOptions};
use runtime::profile_import::{ImportOptions, load_rail, load_wheel};
use runtime::schema::results::RunResults;
use runtime::track::{InputFile, Provenance, TrackTables};
use serde::Serialize;

use crate::cache::{Fnv64, cache_dir};
use crate::scene::LoadedScene;
use crate::vehicle_file::{GROUND, VehicleFile};

/// Progress of a run, for the CLI's bar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunProgress {
    /// Simulated time reached and to reach (s).
    pub simulated_s: f64,
    pub total_s: f64,
    /// Wall time of the integration so far (s).
    pub wall_s: f64,
}

/// Where the track tables came from.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct TrackSource {
    pub path: String,
    /// Built by this run (false: read from the cache or the scene's file).
    pub built: bool,
    pub build_time_s: f64,
}

/// Per-wheelset figures of a run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct WheelsetSummary {
    pub name: String,
    /// Largest |lateral displacement| from the centreline (mm).
    pub peak_lateral_mm: f64,
    /// Lateral displacement at the end (mm).
    pub final_lateral_mm: f64,
    /// Distance travelled by the left and right wheels along their rails (m).
    pub travelled_left_m: f64,
    pub travelled_right_m: f64,
    /// Time with flange contact (s), left and right (from the samples).
    pub flange_contact_left_s: f64,
    pub flange_contact_right_s: f64,
    /// Number of separate flange contacts (onsets in the samples).
    pub flange_contact_events: u64,
    /// Nadal's criterion per wheel, left then right ([`crate::diagnostics`]).
    pub nadal: Vec<crate::diagnostics::WheelNadal>,
}

/// The energy bookkeeping of a run (J;
/// `runtime::dynamics::system::EnergyLedger`): E − E0 = axle torque work +
/// reference work + element turning work − creep, contact damping and
/// damper dissipation, up to `residual_j`.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct EnergySummary {
    /// Mechanical energy (kinetic, gravity, springs, Hertz) at the start and
    /// the end (J).
    pub initial_j: f64,
    pub final_j: f64,
    pub axle_torque_work_j: f64,
    pub reference_work_j: f64,
    pub creep_dissipation_j: f64,
    pub contact_damping_dissipation_j: f64,
    pub damper_dissipation_j: f64,
    /// Work of the spring–dampers beyond their potential: their directions
    /// turn with their first body (J).
    pub element_turning_work_j: f64,
    /// What the balance leaves unexplained (J).
    pub residual_j: f64,
}

impl From<&EnergyLedger> for EnergySummary {
    fn from(l: &EnergyLedger) -> Self {
        EnergySummary {
            initial_j: l.initial_energy_j,
            final_j: l.energy_j,
            axle_torque_work_j: l.axle_torque_work_j,
            reference_work_j: l.reference_work_j,
            creep_dissipation_j: l.creep_dissipation_j,
            contact_damping_dissipation_j: l.contact_damping_dissipation_j,
            damper_dissipation_j: l.damper_dissipation_j,
            element_turning_work_j: l.element_turning_work_j,
            residual_j: l.residual_j(),
        }
    }
}

/// The `--json` summary of a run.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct RunSummary {
    pub scene: String,
    pub title: String,
    pub output: String,
    pub plots: Vec<String>,
    pub creep_law: String,
    pub contact_method: String,
    pub integrator: String,
    pub speed_m_s: f64,
    /// Simulated time (s), the wall time of the integration (s) and their
    /// ratio (> 1: faster than real time).
    pub simulated_time_s: f64,
    pub wall_time_s: f64,
    pub real_time_factor: f64,
    /// Wall time before the integration: tables, vehicle, settling (s).
    pub setup_time_s: f64,
    pub steps: u64,
    pub rejected_steps: u64,
    pub rhs_evaluations: u64,
    pub output_samples: usize,
    pub contact_solves: u64,
    pub mean_newton_iterations: f64,
    pub cold_starts: u64,
    /// Flange pieces not searched (auto rule or off) and clear pieces not
    /// searched again.
    pub flange_searches_skipped: u64,
    /// Accepted states with a flange in contact, summed over the wheels.
    pub flange_contact_states: u64,
    pub wheelsets: Vec<WheelsetSummary>,
    /// Fallbacks the run went through ([`crate::diagnostics`]).
    pub fallbacks: crate::diagnostics::FallbackCounts,
    /// Energy bookkeeping between the first and the last accepted state.
    pub energy: Option<EnergySummary>,
    /// Why the run ended before its end time: "interrupted" (Ctrl-C),
    /// "end of track"; `None` when it completed.
    pub stopped: Option<String>,
    /// The error that ended the run, if any (the results so far are written).
    pub error: Option<String>,
    pub track: TrackSource,
    /// What the planner decided ([`crate::planner`]).
    pub plan: crate::planner::Plan,
}

/// What to run and where to write.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRequest {
    pub scene: LoadedScene,
    pub output: PathBuf,
    /// Directory for the PNG plots; `None`: no plots.
    pub plots: Option<PathBuf>,
}

/// Runs a scene (module docs). `progress` is called every few hundred
/// accepted steps; `stop` ends the run cleanly when set.
pub fn run_scene(
    req: &RunRequest,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
) -> Result<RunSummary> {
    let plan = crate::planner::plan(&req.scene).context("planning the run")?;
    run_scene_with_plan(req, plan, progress, stop)
}

/// Runs a scene with the decisions of [`crate::planner::plan`]; a run
/// whose flange guard trips is repeated with the flange searched (`auto`).
pub fn run_scene_with_plan(
    req: &RunRequest,
    mut plan: crate::planner::Plan,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
) -> Result<RunSummary> {
    loop {
        match run_planned(req, &plan, progress, stop.clone())? {
            Attempt::Done(summary) => return Ok(*summary),
            Attempt::Revise(why) => plan.revise_flange(&why),
        }
    }
}

/// One run of a plan.
enum Attempt {
    Done(Box<RunSummary>),
    /// The flange guard tripped (where, and the time lost).
    Revise(String),
}

fn run_planned(
    req: &RunRequest,
    plan: &crate::planner::Plan,
    progress: &mut dyn FnMut(RunProgress),
    stop: Option<Arc<AtomicBool>>,
) -> Result<Attempt> {
    let setup_start = Instant::now();
    let planned = plan.apply(&req.scene);
    let ls = &planned;
    let scene = &ls.scene;
    let (track, source) = load_track(ls).context("track tables")?;
    let vehicle_path = ls.path(&scene.vehicle.file);
    let vfile = VehicleFile::load(&vehicle_path)?;
    let rail_path = ls.path(&scene.track.rail_profile);
    let mut vehicle = vehicle_model(&vfile, &track, &rail_path)?;
    crate::load::add_loads(&mut vehicle, &scene.load)?;
    let settings = system_settings(ls, &vfile, &track)?;
    let integrator = scene.method()?;
    let (mut system, mut y0) = VehicleSystem::assemble(
        &track,
        &vehicle,
        settings,
        InitialConditions {
            lateral_m: scene.initial.lateral_m,
            yaw_rad: scene.initial.yaw_rad,
        },
    )
    .context("assembling the vehicle on the track")?;
    crate::load::perturb(
        &mut y0,
        &vehicle,
        &track,
        scene.initial.s_m,
        &scene.perturbation,
    )?;
    // With a flange guard the system stops on its own flag, set by the
    // guard or by the caller's (checked at every accepted step).
    let guard = plan.flange_guard;
    let guard_flag = Arc::new(AtomicBool::new(false));
    match (stop.clone(), guard) {
        (Some(flag), None) => system.set_stop_flag(flag),
        (None, None) => {}
        (_, Some(_)) => system.set_stop_flag(guard_flag.clone()),
    }
    system.enable_energy_ledger();
    let total_s = scene.duration_s();
    let setup_time_s = setup_start.elapsed().as_secs_f64();
    let start = Instant::now();
    let mut accepted = 0u64;
    {
        let progress_ref = &mut *progress;
        let (user_stop, guard_flag) =
            (stop.clone().filter(|_| guard.is_some()), guard_flag.clone());
        system.set_progress(Box::new(move |t| {
            accepted += 1;
            if let Some(u) = &user_stop
                && u.load(std::sync::atomic::Ordering::Relaxed)
            {
                guard_flag.store(true, std::sync::atomic::Ordering::Relaxed);
            }
            if accepted % 256 == 0 {
                progress_ref(RunProgress {
                    simulated_s: t,
                    total_s,
                    wall_s: start.elapsed().as_secs_f64(),
                });
            }
        }));
    }
    let mut recorder = Recorder::new(&system);
    let mut tripped: Option<String> = None;
    // Remembers the state of each evaluation for the diagnostic of a failure.
    let mut watched = crate::diagnostics::Watched::new(&mut system);
    let outcome = integrate(
        &integrator,
        &mut watched,
        0.0,
        &y0,
        total_s,
        &OutputGrid {
            interval_s: scene.run.output_interval_s,
        },
        &mut |sys, t, y| {
            sys.note(t, y);
            recorder.record(sys, t, y)?;
            if let Some(g) = guard
                && tripped.is_none()
            {
                tripped = crate::planner::guard_check(&g, &recorder.results, t);
                if tripped.is_some() {
                    guard_flag.store(true, std::sync::atomic::Ordering::Relaxed);
                }
            }
            Ok(())
        },
    );
    let wall_time_s = start.elapsed().as_secs_f64();
    let diagnostic = outcome.as_ref().err().map(|e| watched.diagnose(e));
    let hertz_floor_evaluations = watched.hertz_floor_evaluations();
    if let Some(why) = tripped {
        return Ok(Attempt::Revise(format!(
            "{why}; the first attempt took {wall_time_s:.2} s of integration"
        )));
    }
    let counters = system.counters();
    let stats_solvers =
        system
            .solvers()
            .iter()
            .fold(runtime::contact::SolverStats::default(), |mut a, s| {
                a.solves += s.stats.solves;
                a.iterations += s.stats.iterations;
                a.cold_starts += s.stats.cold_starts;
                a.flange_skipped += s.stats.flange_skipped;
                a.clear_skipped += s.stats.clear_skipped;
                a.minimisations += s.stats.minimisations;
                a
            });
    let track_end_reached = system.track_end_reached();
    let energy = system.energy_ledger().map(EnergySummary::from);
    drop(system);
    let (stats, error) = match outcome {
        Ok(s) => (Some(s), None),
        Err(e) => (None, Some(anyhow!(e))),
    };
    let simulated_time_s = recorder.results.time_s.last().copied().unwrap_or(0.0);
    let stopped = match &stats {
        Some(IntegrationStats { stopped: true, .. }) => {
            if stop
                .as_ref()
                .is_some_and(|f| f.load(std::sync::atomic::Ordering::Relaxed))
            {
                Some("interrupted".to_string())
            } else if track_end_reached {
                Some("end of track".to_string())
            } else {
                Some("stopped".to_string())
            }
        }
        _ => None,
    };
    let mut results = recorder.results;
    results.scene_toml = ls.text.clone();
    results.attributes = vec![
        ("title".into(), scene.title.clone()),
        ("scene".into(), ls.origin.clone()),
        ("vehicle".into(), vfile.name.clone()),
        ("creep_law".into(), scene.contact.creep_law.clone()),
        ("contact_method".into(), scene.contact.method.clone()),
        ("flange_search".into(), scene.contact.flange.clone()),
        ("integrator".into(), scene.run.integrator.clone()),
        ("speed_m_s".into(), format!("{}", scene.initial.speed_m_s)),
        ("track".into(), source.path.clone()),
        ("plan".into(), plan.to_text()),
        (
            "plan_json".into(),
            serde_json::to_string(plan).context("the plan as JSON")?,
        ),
        (
            "status".into(),
            match (&error, &stopped) {
                (Some(e), _) => format!("failed: {e}"),
                (None, Some(s)) => format!("stopped: {s}"),
                (None, None) => "completed".into(),
            },
        ),
    ];
    let fallbacks = crate::diagnostics::FallbackCounts::count(
        stats_solvers.minimisations,
        hertz_floor_evaluations,
        &results,
    );
    results
        .attributes
        .extend(crate::diagnostics::run_attributes(
            stats.as_ref(),
            counters.accepted,
            counters.evaluations,
            stats_solvers.solves,
            &fallbacks,
            diagnostic.as_ref(),
        ));
    runtime::schema::results::write_results(&req.output, &results)
        .with_context(|| format!("writing the results {}", req.output.display()))?;
    let plots = match &req.plots {
        Some(dir) if !results.is_empty() => {
            crate::run_plots::write_run_plots(&results, dir, &scene.title)?
                .into_iter()
                .map(|p| p.display().to_string())
                .collect()
        }
        _ => Vec::new(),
    };
    let summary = RunSummary {
        scene: ls.origin.clone(),
        title: scene.title.clone(),
        output: req.output.display().to_string(),
        plots,
        creep_law: scene.contact.creep_law.clone(),
        contact_method: scene.contact.method.clone(),
        integrator: scene.run.integrator.clone(),
        speed_m_s: scene.initial.speed_m_s,
        simulated_time_s,
        wall_time_s,
        real_time_factor: if wall_time_s > 0.0 {
            simulated_time_s / wall_time_s
        } else {
            f64::INFINITY
        },
        setup_time_s,
        steps: stats.map_or(counters.accepted, |s| s.steps),
        rejected_steps: stats.map_or(0, |s| s.rejected),
        rhs_evaluations: counters.evaluations,
        output_samples: results.len(),
        contact_solves: stats_solvers.solves,
        mean_newton_iterations: if stats_solvers.solves > 0 {
            stats_solvers.iterations as f64 / stats_solvers.solves as f64
        } else {
            0.0
        },
        cold_starts: stats_solvers.cold_starts,
        flange_searches_skipped: stats_solvers.flange_skipped + stats_solvers.clear_skipped,
        flange_contact_states: counters.flange_contact_states,
        wheelsets: wheelset_summaries(&results),
        fallbacks,
        energy,
        stopped,
        error: error.as_ref().map(crate::error_text::chain_text),
        track: source,
        plan: plan.clone(),
    };
    match error {
        Some(e) => Err(e.context(format!(
            "the run failed at t = {:.4} s{}; the results so far are in {}",
            simulated_time_s,
            diagnostic
                .as_ref()
                .map_or(String::new(), |d| format!(" ({})", d.headline())),
            req.output.display()
        ))),
        None => Ok(Attempt::Done(Box::new(summary))),
    }
}

/// The system settings of a scene (force models, contact method — building
/// or reading the contact tables when `method = "table"` — speed, start).
pub fn system_settings(
    ls: &LoadedScene,
    vfile: &VehicleFile,
    track: &TrackTables,
) -> Result<SystemSettings> {
    let scene = &ls.scene;
    let rail_path = ls.path(&scene.track.rail_profile);
    let material = Material {
        young_pa: scene.contact.young_pa,
        poisson: scene.contact.poisson,
    };
    let creep_law = scene.creep_law()?;
    let method = match scene.contact.method.as_str() {
        "table" => ContactMethod::Table(contact_tables(vfile, track, &rail_path, material)?),
        "imported" => {
            let path = ls.path(
                scene
                    .contact
                    .imported_table
                    .as_ref()
                    .context("[contact] imported_table")?,
            );
            let table = Arc::new(imported_table(&path)?);
            ContactMethod::Imported(ImportedContactMethod {
                tables: vec![table; vfile.wheelsets.len()],
                shear_modulus_override_pa: scene.contact.shear_modulus_pa,
            })
        }
        _ => ContactMethod::Online,
    };
    let flange: FlangeSearch = scene.contact.flange.parse().map_err(anyhow::Error::msg)?;
    let settings = SystemSettings {
        forces: ContactForceSettings {
            material,
            friction_coefficient: scene.contact.friction,
            creep_law,
            normal: NormalForceModel {
                restitution: scene.contact.restitution,
                ..NormalForceModel::default()
            },
            creepage: CreepageOptions {
                min_rolling_speed_m_s: scene.contact.min_rolling_speed_m_s,
            },
            non_hertzian: scene
                .contact
                .non_hertzian
                .parse()
                .map_err(anyhow::Error::msg)
                .context("[contact] non_hertzian")?,
        },
        contact: ContactOptions {
            flange,
            ..ContactOptions::default()
        },
        method,
        speed_m_s: scene.initial.speed_m_s,
        deceleration_m_s2: scene.initial.deceleration_m_s2,
        acceleration_m_s2: scene.initial.acceleration_m_s2,
        final_speed_m_s: scene.initial.final_speed_m_s,
        axle_torque_nm: scene.run.axle_torque_nm,
        axle_brake_torque_nm: scene.run.axle_brake_torque_nm,
        s_start_m: scene.initial.s_m,
        ..SystemSettings::default()
    };
    Ok(settings)
}

fn wheelset_summaries(r: &RunResults) -> Vec<WheelsetSummary> {
    let dt = |i: usize| -> f64 {
        if i + 1 < r.time_s.len() {
            r.time_s[i + 1] - r.time_s[i]
        } else {
            0.0
        }
    };
    r.wheelsets
        .iter()
        .map(|w| {
            let peak =
                w.lateral_m.iter().fold(
                    0.0_f64,
                    |m, v| if v.is_finite() { m.max(v.abs()) } else { m },
                );
            let time_in = |flags: &[u8]| -> f64 {
                // 0.0 + …: an empty f64 sum is −0.0.
                0.0 + flags
                    .iter()
                    .enumerate()
                    .filter(|(_, f)| **f == 1)
                    .map(|(i, _)| dt(i))
                    .sum::<f64>()
            };
            let events = w
                .wheels
                .iter()
                .map(|wh| {
                    wh.flange_contact
                        .windows(2)
                        .filter(|p| p[0] == 0 && p[1] == 1)
                        .count() as u64
                        + u64::from(wh.flange_contact.first() == Some(&1))
                })
                .sum();
            WheelsetSummary {
                name: w.name.clone(),
                peak_lateral_mm: peak * 1e3,
                final_lateral_mm: w.lateral_m.last().copied().unwrap_or(f64::NAN) * 1e3,
                travelled_left_m: w.wheels[0].travelled_m.last().copied().unwrap_or(0.0),
                travelled_right_m: w.wheels[1].travelled_m.last().copied().unwrap_or(0.0),
                flange_contact_left_s: time_in(&w.wheels[0].flange_contact),
                flange_contact_right_s: time_in(&w.wheels[1].flange_contact),
                flange_contact_events: events,
                nadal: crate::diagnostics::nadal_summary(w, &r.time_s),
            }
        })
        .collect()
}

impl RunSummary {
    /// Human-readable summary.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "{}\n  {} → {}\n  creep law {}, contact {}, integrator {}, {} m/s\n  simulated {:.3} s in {:.3} s wall (real-time factor {:.2}; setup {:.2} s)\n  {} steps ({} rejected), {} evaluations, {} contact solves ({:.2} Newton iterations each, {} cold starts)\n",
            self.title,
            self.scene,
            self.output,
            self.creep_law,
            self.contact_method,
            self.integrator,
            self.speed_m_s,
            self.simulated_time_s,
            self.wall_time_s,
            self.real_time_factor,
            self.setup_time_s,
            self.steps,
            self.rejected_steps,
            self.rhs_evaluations,
            self.contact_solves,
            self.mean_newton_iterations,
            self.cold_starts
        );
        for w in &self.wheelsets {
            s += &format!(
                "  wheelset {}: peak lateral {:.2} mm (final {:+.2} mm); travelled left {:.3} m, right {:.3} m; flange contact {:.2} s / {:.2} s ({} events)\n",
                w.name,
                w.peak_lateral_mm,
                w.final_lateral_mm,
                w.travelled_left_m,
                w.travelled_right_m,
                w.flange_contact_left_s,
                w.flange_contact_right_s,
                w.flange_contact_events
            );
        }
        if let Some(e) = &self.energy {
            s += &format!(
                "  energy: {:.1} J → {:.1} J; axle torque work {:.1} J, reference work {:.1} J, element turning {:.3} J, creep dissipation {:.1} J, contact damping {:.1} J, dampers {:.1} J; residual {:.3} J\n",
                e.initial_j,
                e.final_j,
                e.axle_torque_work_j,
                e.reference_work_j,
                e.element_turning_work_j,
                e.creep_dissipation_j,
                e.contact_damping_dissipation_j,
                e.damper_dissipation_j,
                e.residual_j
            );
        }
        for w in &self.wheelsets {
            s += &crate::diagnostics::nadal_text(&w.name, &w.nadal);
        }
        s += &self.fallbacks.to_text();
        if let Some(st) = &self.stopped {
            s += &format!("  stopped early: {st}\n");
        }
        if let Some(r) = &self.plan.revised {
            s += &format!("  plan revised: {r}\n");
        }
        for p in &self.plots {
            s += &format!("  plot {p}\n");
        }
        s += &format!(
            "  track {} ({})\n",
            self.track.path,
            if self.track.built {
                format!("built in {:.2} s", self.track.build_time_s)
            } else {
                "cached".into()
            }
        );
        s
    }
}

/// The scene's track tables: its table file, or built from its CSV inputs
/// into the cache (module docs).
pub fn load_track(ls: &LoadedScene) -> Result<(TrackTables, TrackSource)> {
    let t = &ls.scene.track;
    if let Some(length_m) = t.straight_m {
        let inclination = t
            .rail_inclination
            .parse::<Inclination>()
            .map_err(anyhow::Error::msg)
            .context("[track] rail_inclination")?;
        let spacing = BuildConfig {
            gauge_m: t.gauge_m,
            ..BuildConfig::default()
        }
        .rail_spacing_m();
        let tables = runtime::track::straight_track(
            length_m,
            t.step_m,
            t.gauge_m,
            spacing,
            inclination.angle_rad,
        );
        return Ok((
            tables,
            TrackSource {
                path: format!("ideal straight, {length_m} m (in memory)"),
                built: true,
                build_time_s: 0.0,
            },
        ));
    }
    if let Some(p) = &t.tables {
        let path = ls.path(p);
        let tables = runtime::schema::read_track(&path)?;
        return Ok((
            tables,
            TrackSource {
                path: path.display().to_string(),
                built: false,
                build_time_s: 0.0,
            },
        ));
    }
    if let Some(range) = t.range_m {
        let start = Instant::now();
        let tables = crate::planner::build_track_range(ls, range)?;
        let (a, b) = tables.centerline.range_m();
        return Ok((
            tables,
            TrackSource {
                path: format!(
                    "{} s {a:.1} … {b:.1} m at {} m (in memory)",
                    ls.path(t.centerline.as_ref().context("no centerline")?)
                        .display(),
                    t.step_m
                ),
                built: true,
                build_time_s: start.elapsed().as_secs_f64(),
            },
        ));
    }
    let centerline = ls.path(t.centerline.as_ref().context("no centerline")?);
    let cant = t.cant.as_ref().map(|p| ls.path(p));
    let irregularities = t.irregularities.as_ref().map(|p| ls.path(p));
    let config = crate::planner::build_config(ls)?;
    let mut key = Fnv64::default();
    key.write_str(env!("CARGO_PKG_VERSION"))
        .write_str(&format!("{config:?}"));
    for p in [Some(&centerline), cant.as_ref(), irregularities.as_ref()]
        .into_iter()
        .flatten()
    {
        let text =
            std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
        key.write_str(&text);
    }
    let path = cache_dir()?.join(format!("track-{:016x}.h5", key.finish()));
    if path.exists()
        && let Ok(tables) = runtime::schema::read_track(&path)
    {
        return Ok((
            tables,
            TrackSource {
                path: path.display().to_string(),
                built: false,
                build_time_s: 0.0,
            },
        ));
    }
    let start = Instant::now();
    let req = BuildRequest {
        centerline,
        cant,
        irregularities,
        output: path.clone(),
        config,
        contact: None,
        command_line: format!("sim run {} (tables built on demand)", ls.origin),
    };
    run_build(&req, &NoProgress).context("building the track tables")?;
    let tables = runtime::schema::read_track(&path)?;
    Ok((
        tables,
        TrackSource {
            path: path.display().to_string(),
            built: true,
            build_time_s: start.elapsed().as_secs_f64(),
        },
    ))
}

fn diag(i: [f64; 3]) -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::from(i))
}

/// The vehicle file as a [`VehicleModel`] on `track` (its rail placement)
/// with the scene's rail profile.
pub fn vehicle_model(v: &VehicleFile, track: &TrackTables, rail: &Path) -> Result<VehicleModel> {
    let rail_profile = load_rail(
        rail,
        &ImportOptions::default(),
        RailProfileOptions::default(),
    )
    .with_context(|| format!("rail profile {}", rail.display()))?;
    let placement = RailPlacement {
        gauge_m: track.meta.gauge_m,
        rail_spacing_m: track.meta.rail_spacing_m,
        inclination_rad: track.meta.rail_inclination_rad,
    };
    let mut wheelsets = Vec::new();
    for w in &v.wheelsets {
        let path = v.profile_path(w);
        let wheel = load_wheel(
            &path,
            &ImportOptions::default(),
            WheelProfileOptions {
                nominal_radius_m: w.nominal_radius_m,
                ..Default::default()
            },
        )
        .with_context(|| format!("wheel profile {}", path.display()))?;
        let contact = WheelsetContactModel::new(
            wheel.clone(),
            wheel,
            w.back_to_back_m,
            &rail_profile,
            &rail_profile,
            placement,
        )
        .with_context(|| format!("wheelset '{}'", w.name))?;
        wheelsets.push(WheelsetSpec {
            name: w.name.clone(),
            body: RigidBody {
                mass_kg: w.mass_kg,
                inertia_kg_m2: diag(w.inertia_kg_m2),
            },
            contact,
            x_m: w.x_m,
            y_m: w.y_m,
            nominal_radius_m: w.nominal_radius_m,
            static_wheel_load_n: v.static_wheel_load_n(w),
        });
    }
    let bodies: Vec<BodySpec> = v
        .bodies
        .iter()
        .map(|b| BodySpec {
            name: b.name.clone(),
            body: RigidBody {
                mass_kg: b.mass_kg,
                inertia_kg_m2: diag(b.inertia_kg_m2),
            },
            cg_m: Vector3::from(b.cg_m),
        })
        .collect();
    let references: Vec<ReferenceSpec> = v
        .references
        .iter()
        .map(|r| ReferenceSpec {
            name: r.name.clone(),
            origin_m: Vector3::from(r.origin_m),
        })
        .collect();
    let end = |name: &str| -> Result<End> {
        if name == GROUND {
            return Ok(End::Ground);
        }
        if let Some(i) = v.wheelsets.iter().position(|w| w.name == name) {
            return Ok(End::Wheelset(i));
        }
        if let Some(i) = v.bodies.iter().position(|b| b.name == name) {
            return Ok(End::Body(i));
        }
        if let Some(i) = v.references.iter().position(|r| r.name == name) {
            return Ok(End::Reference(i));
        }
        Err(anyhow!("unknown body '{name}'"))
    };
    let mut elements = Vec::new();
    for e in &v.elements {
        let (pa, pb) = e.points()?;
        elements.push(ElementSpec {
            name: e.name.clone(),
            a: end(&e.body_a)?,
            b: end(&e.body_b)?,
            point_a_m: Vector3::from(pa),
            point_b_m: Vector3::from(pb),
            stiffness_n_m: e.stiffness_n_m,
            damping_n_s_m: e.damping_n_s_m,
            preload_n: Vector3::from(e.preload_n),
        });
    }
    ensure!(!wheelsets.is_empty(), "the vehicle has no wheelset");
    Ok(VehicleModel {
        name: v.name.clone(),
        wheelsets,
        bodies,
        references,
        elements,
    })
}

/// An imported contact table: a `.h5`/`.hdf5` file written by
/// `track-preproc import-contact-table`, or any other file read as a DYTSI
/// RSGEO text table (`preproc::rsgeo`).
pub fn imported_table(path: &Path) -> Result<ImportedContactTable> {
    let hdf5 = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("h5") || e.eq_ignore_ascii_case("hdf5"));
    if hdf5 {
        runtime::schema::read_imported_contact_table(path)
            .with_context(|| format!("imported contact table {}", path.display()))
    } else {
        preproc::rsgeo::read_rsgeo(path)
            .with_context(|| format!("imported contact table {} (RSGEO)", path.display()))
    }
}

/// Contact lookup tables of every wheelset (built on demand for the
/// wheel/rail pair, the track's rail placement and the wheelset's static
/// load, and cached): lateral shifts ±15 mm every 0.1 mm, zero yaw.
pub fn contact_tables(
    v: &VehicleFile,
    track: &TrackTables,
    rail: &Path,
    material: Material,
) -> Result<Vec<Arc<ContactTable>>> {
    let mut out: Vec<Arc<ContactTable>> = Vec::new();
    let mut built: Vec<(u64, Arc<ContactTable>)> = Vec::new();
    for w in &v.wheelsets {
        let config = ContactTableConfig {
            wheel_profile: v.profile_path(w),
            rail_profile: rail.to_path_buf(),
            wheel_radius_m: w.nominal_radius_m,
            back_to_back_m: w.back_to_back_m,
            gauge_m: track.meta.gauge_m,
            rail_spacing_m: track.meta.rail_spacing_m,
            rail_inclination_rad: track.meta.rail_inclination_rad,
            y_min_m: -0.015,
            y_max_m: 0.015,
            y_step_m: 1e-4,
            yaw_rad: vec![0.0],
            support: TableSupport::Elastic {
                wheel_load_n: v.static_wheel_load_n(w),
                material,
            },
            ..Default::default()
        };
        let mut key = Fnv64::default();
        key.write_str(env!("CARGO_PKG_VERSION"))
            .write_str(&format!("{config:?}"));
        for p in [&config.wheel_profile, &config.rail_profile] {
            key.write_str(
                &std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?,
            );
        }
        let key = key.finish();
        if let Some((_, t)) = built.iter().find(|(k, _)| *k == key) {
            out.push(t.clone());
            continue;
        }
        let path = cache_dir()?.join(format!("contact-{key:016x}.h5"));
        let cached = path
            .exists()
            .then(|| runtime::schema::read_contact_table(&path).ok().flatten())
            .flatten();
        let table = match cached {
            Some(t) => t,
            None => {
                let model = config.model()?;
                let table = build_contact_table(&model, &config, &NoProgress)
                    .with_context(|| format!("contact table of wheelset '{}'", w.name))?;
                let inputs = [
                    ("wheel_profile", &config.wheel_profile),
                    ("rail_profile", &config.rail_profile),
                ]
                .iter()
                .map(|(role, p)| {
                    Ok(InputFile {
                        role: (*role).into(),
                        path: p.display().to_string(),
                        text: std::fs::read_to_string(p)?,
                    })
                })
                .collect::<Result<Vec<_>>>()?;
                runtime::schema::write_contact_table_file(
                    &path,
                    &table,
                    &Provenance {
                        command_line: "sim run (contact table built on demand)".into(),
                        inputs,
                    },
                )?;
                table
            }
        };
        let t = Arc::new(table);
        built.push((key, t.clone()));
        out.push(t);
    }
    Ok(out)
}
