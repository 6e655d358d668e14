//! What the planner knows before it decides: the track over the run's
//! range ([`TrackFacts`]), the distance travelled and the stretch of track
//! the run covers ([`travel_m`], [`required_range_m`]), and the vehicle's
//! flange ([`FlangeFacts`]), measured on an ideal straight whose vehicle
//! model the stability check shares (`CheckModel`: built at most once).

use std::path::PathBuf;

use anyhow::{Context, Result};
use preproc::BuildConfig;
use runtime::geometry::track::{Side, TrackTables};
use runtime::multibody::VehicleModel;
use serde::Serialize;

use super::measured::TrackKind;
use super::range::{build_config, track_model};
use crate::config::scene::LoadedScene;
use crate::config::vehicle::VehicleFile;

/// Curvature (1/m) below which a rail counts as straight (R > 10⁹ m: the
/// round-off of a spline fitted to collinear points).
pub const STRAIGHT_CURVATURE_1_M: f64 = 1e-9;

/// Margin of the track range before the vehicle's rearmost and after its
/// foremost point (m).
pub const RANGE_MARGIN_M: f64 = 5.0;

/// Table kept ahead of the leading wheelset by the dynamics (m;
/// `runtime::multibody::system`: the run stops 2 m before the table's end).
pub const DYNAMICS_LOOKAHEAD_M: f64 = 2.0;

/// What the track looks like over the run's range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackFacts {
    /// `centerline`, `table file` or `ideal straight`.
    pub kind: String,
    /// Length of the whole track (m).
    pub length_m: f64,
    /// Largest curvature of the rails and the centreline over the range (1/m).
    pub max_curvature_1_m: f64,
    /// Largest |cant| over the range (rad).
    pub max_cant_rad: f64,
    /// Whether the scene gives irregularities, and their largest |deviation|
    /// over the range (m).
    pub irregularities: bool,
    pub max_irregularity_m: f64,
    /// Table step of a table file (m).
    pub file_step_m: Option<f64>,
}

impl TrackFacts {
    /// An ideal straight over the range: no curvature, cant or irregularity.
    pub fn straight(&self) -> bool {
        self.max_curvature_1_m <= STRAIGHT_CURVATURE_1_M
            && self.max_cant_rad == 0.0
            && self.max_irregularity_m == 0.0
    }

    /// The kind of track of the measured constants
    /// (`tables/planner/measured.toml`).
    pub fn track_kind(&self) -> TrackKind {
        if self.max_irregularity_m > 0.0 {
            TrackKind::Irregular
        } else if self.straight() {
            TrackKind::Straight
        } else {
            TrackKind::Curve
        }
    }

    /// `straight`, `curve` or `irregular` ([`Self::track_kind`]).
    pub fn kind_name(&self) -> &'static str {
        self.track_kind().as_str()
    }
}

/// The flange facts of the vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlangeFacts {
    /// Smallest flangeway clearance over the wheelsets and sides (m).
    pub clearance_m: f64,
    /// Largest √(2 R0 h_flange) (m).
    pub reach_per_rad_m: f64,
    /// The initial approach |y₀| + |ψ₀|·reach (m).
    pub initial_approach_m: f64,
}

impl FlangeFacts {
    /// Not measured (the flange search cannot be off).
    pub(super) const UNKNOWN: FlangeFacts = FlangeFacts {
        clearance_m: f64::NAN,
        reach_per_rad_m: f64::NAN,
        initial_approach_m: f64::NAN,
    };
}

/// Simulated distance of the vehicle reference point (m): the distance, or
/// the distance the references cover in the duration (ramp or schedule).
pub fn travel_m(ls: &LoadedScene) -> f64 {
    let s = &ls.scene;
    if let Some(d) = s.run.distance_m {
        return d;
    }
    // The integral of the references' speed (ramp or schedule).
    s.speed_profile().distance_m(s.duration_s())
}

/// Longitudinal extent of the vehicle relative to its reference point (m):
/// wheelsets, bodies' centres of gravity, references' origins.
pub(super) fn vehicle_extent_m(v: &VehicleFile) -> (f64, f64) {
    let xs = v
        .wheelsets
        .iter()
        .map(|w| w.x_m)
        .chain(v.bodies.iter().map(|b| b.cg_m[0]))
        .chain(v.references.iter().map(|r| r.origin_m[0]));
    xs.fold((0.0_f64, 0.0_f64), |(lo, hi), x| (lo.min(x), hi.max(x)))
}

/// The stretch of track the run covers (m), before clipping to the track.
pub fn required_range_m(ls: &LoadedScene, v: &VehicleFile) -> [f64; 2] {
    let (back, front) = vehicle_extent_m(v);
    let s0 = ls.scene.initial.s_m;
    [
        s0 + back - RANGE_MARGIN_M,
        s0 + travel_m(ls) + front + DYNAMICS_LOOKAHEAD_M + RANGE_MARGIN_M,
    ]
}

/// Facts of the track over `[a, b]` (m; clipped to the track).
pub(super) fn track_facts(ls: &LoadedScene, range: [f64; 2]) -> Result<TrackFacts> {
    let t = &ls.scene.track;
    if let Some(l) = t.straight_m {
        return Ok(TrackFacts {
            kind: "ideal straight".into(),
            length_m: l,
            max_curvature_1_m: 0.0,
            max_cant_rad: 0.0,
            irregularities: false,
            max_irregularity_m: 0.0,
            file_step_m: None,
        });
    }
    if let Some(p) = &t.tables {
        let tables = runtime::io::schema::read_track(&ls.path(p))?;
        let rows = tables.centerline.rows();
        let inside = rows
            .iter()
            .filter(|r| r.s_m >= range[0] && r.s_m <= range[1]);
        let mut f = TrackFacts {
            kind: "table file".into(),
            length_m: tables.centerline.length_m(),
            max_curvature_1_m: 0.0,
            max_cant_rad: 0.0,
            irregularities: false,
            max_irregularity_m: 0.0,
            file_step_m: Some(tables.meta.step_m),
        };
        for r in inside {
            f.max_curvature_1_m = f.max_curvature_1_m.max(r.curvature_1_m.abs());
            f.max_cant_rad = f.max_cant_rad.max(r.cant_rad.abs());
            let d = [
                r.align_left_m,
                r.align_right_m,
                r.level_left_m,
                r.level_right_m,
            ]
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
            f.max_irregularity_m = f.max_irregularity_m.max(d);
        }
        f.irregularities = f.max_irregularity_m > 0.0;
        return Ok(f);
    }
    let config = build_config(ls)?;
    super::facts_cache::cached(ls, &config, range, || probe_facts(ls, &config, range))
}

/// The facts of a track built from CSV or design inputs, probed on the
/// fitted centreline and rails every 5 cm over `range` (m).
pub(super) fn probe_facts(
    ls: &LoadedScene,
    config: &BuildConfig,
    range: [f64; 2],
) -> Result<TrackFacts> {
    let model = track_model(ls, config)?;
    let length = model.centerline.length_m();
    let (a, b) = (range[0].max(0.0), range[1].min(length));
    // Probe every 5 cm (at most 200 000 points per curve): finer than the
    // rail nodes (≤ 1 m) and the irregularity samples.
    let probe = 0.05_f64.max((b - a) / 2e5);
    let n = ((b - a) / probe).ceil().max(1.0) as usize;
    let s: Vec<f64> = (0..=n).map(|k| a + (b - a) * k as f64 / n as f64).collect();
    let mut f = TrackFacts {
        kind: super::facts_cache::KIND.into(),
        length_m: length,
        max_curvature_1_m: 0.0,
        max_cant_rad: 0.0,
        irregularities: model.irregularities.is_some(),
        max_irregularity_m: 0.0,
        file_step_m: None,
    };
    for c in model.centerline.sample(&s)? {
        f.max_curvature_1_m = f.max_curvature_1_m.max(c.point.curvature());
        f.max_cant_rad = f.max_cant_rad.max(c.cant_rad.abs());
    }
    for side in Side::BOTH {
        let rail = model.rail(side);
        let (la, lb) = (rail.l_at_s(a).max(0.0), rail.l_at_s(b).min(rail.length_m()));
        let l: Vec<f64> = (0..=n)
            .map(|k| la + (lb - la) * k as f64 / n as f64)
            .collect();
        for r in rail.sample(&l, &model.centerline)? {
            f.max_curvature_1_m = f.max_curvature_1_m.max(r.point.curvature());
        }
    }
    if let Some(irr) = &model.irregularities {
        for &si in &s {
            let d = irr.at(si);
            let m = [
                d.align_left_m,
                d.align_right_m,
                d.level_left_m,
                d.level_right_m,
            ]
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
            f.max_irregularity_m = f.max_irregularity_m.max(m);
        }
    }
    Ok(f)
}

/// An ideal straight in memory with the scene's rail placement (the file's
/// with a table file), long enough for the vehicle, and the vehicle model
/// on it: for the flange facts and the linear stability check. The model
/// is built on first use and shared ([`Self::model`]).
pub(super) struct CheckModel<'a> {
    vehicle_file: &'a VehicleFile,
    rail: PathBuf,
    /// The scene's `track.keep_longest_stretch`.
    keep_longest_stretch: bool,
    /// The ideal straight.
    pub track: TrackTables,
    /// Where the vehicle's reference point starts on it (m).
    pub s_start_m: f64,
    vehicle: Option<VehicleModel>,
    /// How many times the vehicle model was built (tests: at most once).
    #[cfg(test)]
    builds: usize,
}

impl<'a> CheckModel<'a> {
    /// The ideal straight of `ls` for `v` (no vehicle model yet).
    pub fn new(ls: &LoadedScene, v: &'a VehicleFile) -> Result<CheckModel<'a>> {
        let t = &ls.scene.track;
        let (gauge, spacing, incl) = match &t.tables {
            Some(p) => {
                let m = runtime::io::schema::read_track(&ls.path(p))?.meta;
                (m.gauge_m, m.rail_spacing_m, m.rail_inclination_rad)
            }
            None => {
                let c = build_config(ls)?;
                (c.gauge_m, c.rail_spacing_m(), c.inclination.angle_rad)
            }
        };
        let (back, front) = vehicle_extent_m(v);
        let s_start = RANGE_MARGIN_M - back;
        let length = s_start + front + DYNAMICS_LOOKAHEAD_M + 2.0 * RANGE_MARGIN_M;
        Ok(CheckModel {
            vehicle_file: v,
            rail: ls.path(&t.rail_profile),
            keep_longest_stretch: t.keep_longest_stretch,
            track: runtime::geometry::track::straight_track(length, 1.0, gauge, spacing, incl),
            s_start_m: s_start,
            vehicle: None,
            #[cfg(test)]
            builds: 0,
        })
    }

    /// The rail profile's path.
    pub fn rail(&self) -> &std::path::Path {
        &self.rail
    }

    /// The vehicle file.
    pub fn vehicle_file(&self) -> &'a VehicleFile {
        self.vehicle_file
    }

    /// The straight and the vehicle model on it (built on the first call).
    pub fn model(&mut self) -> Result<(&TrackTables, &VehicleModel)> {
        let model = match self.vehicle.take() {
            Some(m) => m,
            None => {
                #[cfg(test)]
                {
                    self.builds += 1;
                }
                // The warnings of the profiles are the session's to show
                // (it loads the same files with the same option).
                crate::session::vehicle::vehicle_model(
                    self.vehicle_file,
                    &self.track,
                    &self.rail,
                    self.keep_longest_stretch,
                )?
                .0
            }
        };
        Ok((&self.track, self.vehicle.insert(model)))
    }

    /// How many times the vehicle model was built (at most once).
    #[cfg(test)]
    pub fn builds(&self) -> usize {
        self.builds
    }
}

/// Flangeway clearance and yawed-flange reach of the vehicle's wheelsets;
/// the clearance (a quasi-static sweep, about 0.1 s per contact model,
/// shared with assembly through [`crate::session::flange_clearance`]) is cached
/// ([`crate::session::cache`]) under a key of the profiles' texts, the wheelsets'
/// radius and back-to-back, the rail placement and the tool version.
pub(super) fn flange_facts(ls: &LoadedScene, check: &mut CheckModel) -> Result<FlangeFacts> {
    let v = check.vehicle_file();
    let rail = check.rail();
    let mut key = crate::session::cache::Fnv64::default();
    key.write_str(env!("CARGO_PKG_VERSION"))
        .write_str(&format!("{:?}", check.track.meta))
        .write_str(
            &std::fs::read_to_string(rail)
                .with_context(|| format!("reading {}", rail.display()))?,
        );
    for w in &v.wheelsets {
        let p = v.profile_path(w);
        key.write_str(
            &std::fs::read_to_string(&p).with_context(|| format!("reading {}", p.display()))?,
        )
        .write_str(&format!("{} {}", w.nominal_radius_m, w.back_to_back_m));
    }
    let path =
        crate::session::cache::cache_dir()?.join(format!("flange-{:016x}.txt", key.finish()));
    let i = &ls.scene.initial;
    let facts = |clearance_m: f64, reach: f64| FlangeFacts {
        clearance_m,
        reach_per_rad_m: reach,
        initial_approach_m: i.lateral_m.abs() + i.yaw_rad.abs() * reach,
    };
    if let Some((c, r)) = std::fs::read_to_string(&path).ok().and_then(|t| {
        let mut it = t.split_whitespace().map(str::parse::<f64>);
        Some((it.next()?.ok()?, it.next()?.ok()?))
    }) {
        return Ok(facts(c, r));
    }
    let rail = check.rail().to_path_buf();
    let m = &check.track.meta;
    let inputs = crate::session::flange_clearance::ClearanceInputs {
        vehicle_file: v,
        rail: &rail,
        placement: runtime::geometry::profile::RailPlacement {
            gauge_m: m.gauge_m,
            rail_spacing_m: m.rail_spacing_m,
            inclination_rad: m.rail_inclination_rad,
        },
        keep_longest_stretch: check.keep_longest_stretch,
    };
    let (_, vehicle) = check.model()?;
    // The sweep shared with assembly (`crate::session::flange_clearance`).
    let per_wheelset =
        crate::session::flange_clearance::flange_clearances(&inputs, || Ok(vehicle))?;
    let clearance = per_wheelset
        .iter()
        .flatten()
        .flatten()
        .fold(f64::INFINITY, |a, &c| a.min(c));
    let mut reach = 0.0_f64;
    for w in &vehicle.wheelsets {
        for side in Side::BOTH {
            let wheel = w.contact.wheel(side);
            reach = reach.max((2.0 * wheel.nominal_radius_m() * wheel.flange_depth_m()).sqrt());
        }
    }
    // Written atomically (the workspace's one atomic writer); a failure to
    // cache is not an error: the next plan measures again.
    let _ = runtime::io::write_atomically(&path, |tmp| {
        std::fs::write(tmp, format!("{clearance:e} {reach:e}\n"))
    });
    Ok(facts(clearance, reach))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn travel_follows_distance_duration_and_deceleration() {
        let base = LoadedScene::default_scene(&[]).expect("default scene");
        assert_eq!(travel_m(&base), 280.0);
        let t = LoadedScene::default_scene(&["run.distance_m=".into(), "run.duration_s=2".into()])
            .expect("duration");
        assert!((travel_m(&t) - 20.0).abs() < 1e-12);
        // 10 m/s braking at 2 m/s² for 10 s stops after 5 s and 25 m.
        let d = LoadedScene::default_scene(&[
            "run.distance_m=".into(),
            "run.duration_s=10".into(),
            "initial.deceleration_m_s2=2".into(),
        ])
        .expect("deceleration");
        assert!((travel_m(&d) - 25.0).abs() < 1e-9, "{}", travel_m(&d));
    }
}
