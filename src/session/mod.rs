//! A runnable model assembled from a configuration: the track tables, the
//! vehicle model, the contact data and the system settings, with the
//! planner's decisions ([`plan`]). A [`Session`] is built once per run and
//! is everything the run needs; a study that varies a scene builds one per
//! variation.

pub mod cache;
pub mod contact;
pub mod flange_clearance;
pub mod load;
pub mod plan;
pub mod settings;
pub mod track;
pub mod vehicle;

use std::time::Instant;

use anyhow::{Context, Result};
use runtime::geometry::track::TrackTables;
use runtime::integrators::Method;
use runtime::multibody::{InitialConditions, SystemSettings, VehicleModel, VehicleSystem};

use crate::config::scene::LoadedScene;
use crate::config::vehicle::VehicleFile;
use plan::Plan;
use track::TrackSource;

/// A scene made runnable: every input read and checked, every table built
/// or taken from the cache, the models assembled.
pub struct Session {
    /// The scene as it runs: the plan's choices applied.
    pub scene: LoadedScene,
    /// The planner's decisions.
    pub plan: Plan,
    /// The vehicle file.
    pub vehicle_file: VehicleFile,
    /// The track tables and where they came from.
    pub track: TrackTables,
    pub track_source: TrackSource,
    /// The vehicle model on this track, with the `[load]` elements.
    pub vehicle: VehicleModel,
    /// Force models, contact method and data, speed, start.
    pub settings: SystemSettings,
    /// The integration method.
    pub method: Method,
    /// Wall time of the assembly (s).
    pub setup_time_s: f64,
    /// Warnings of the inputs for the run's summary: what was dropped from a
    /// profile cut to its longest usable stretch
    /// (`track.keep_longest_stretch`).
    pub warnings: Vec<String>,
}

impl Session {
    /// Plans `scene` ([`plan::plan`]) and assembles it.
    pub fn new(scene: &LoadedScene) -> Result<Session> {
        let plan = plan::plan(scene).context("planning the run")?;
        Session::assemble(scene, plan)
    }

    /// Assembles `scene` with the decisions of `plan`.
    pub fn assemble(scene: &LoadedScene, plan: Plan) -> Result<Session> {
        let start = Instant::now();
        let ls = plan.apply(scene);
        let s = &ls.scene;
        let (track, track_source) = track::load_track(&ls).context("track tables")?;
        let vehicle_file = ls.vehicle_file()?;
        let (mut vehicle, warnings) = vehicle::vehicle_model(
            &vehicle_file,
            &track,
            &ls.path(&s.track.rail_profile),
            s.track.keep_longest_stretch,
        )?;
        load::add_loads(&mut vehicle, &s.load)?;
        let mut settings = settings::system_settings(&ls, &vehicle_file, &track)?;
        if settings.contact.flange == runtime::contact::FlangeSearch::Auto {
            // Assembly's flangeway clearances, from the cache (the planner
            // has usually swept them already).
            let m = &track.meta;
            let inputs = flange_clearance::ClearanceInputs {
                vehicle_file: &vehicle_file,
                rail: &ls.path(&s.track.rail_profile),
                placement: runtime::geometry::profile::RailPlacement {
                    gauge_m: m.gauge_m,
                    rail_spacing_m: m.rail_spacing_m,
                    inclination_rad: m.rail_inclination_rad,
                },
                keep_longest_stretch: s.track.keep_longest_stretch,
            };
            settings.flange_clearances_m =
                Some(flange_clearance::flange_clearances(&inputs, || {
                    Ok(&vehicle)
                })?);
        }
        let method = s.method()?;
        Ok(Session {
            scene: ls,
            plan,
            vehicle_file,
            track,
            track_source,
            vehicle,
            settings,
            method,
            setup_time_s: start.elapsed().as_secs_f64(),
            warnings: warnings.iter().map(ToString::to_string).collect(),
        })
    }

    /// The vehicle on the track as a system y′ = f(t, y) and its initial
    /// state: settled at the scene's lateral shift and yaw, then perturbed
    /// (`[perturbation]`).
    pub fn system(&self) -> Result<(VehicleSystem<'_>, Vec<f64>)> {
        let s = &self.scene.scene;
        let (system, mut y0) = VehicleSystem::assemble(
            &self.track,
            &self.vehicle,
            self.settings.clone(),
            InitialConditions {
                lateral_m: s.initial.lateral_m,
                yaw_rad: s.initial.yaw_rad,
            },
        )
        .context("assembling the vehicle on the track")?;
        load::perturb(
            &mut y0,
            &self.vehicle,
            &self.track,
            s.initial.s_m,
            &s.perturbation,
        )?;
        Ok((system, y0))
    }
}
