//! The track range decision: only the stretch the run covers (module docs
//! of [`super`]), built in memory ([`build_track_range`]) on the
//! whole-track grid.

use std::path::PathBuf;

use anyhow::{Context, Result};
use preproc::{BuildConfig, BuildRequest, GeometryFiles, RailSpacing, TrackModel};
use runtime::geometry::track::TrackTables;

use super::facts::{DYNAMICS_LOOKAHEAD_M, RANGE_MARGIN_M, TrackFacts, travel_m, vehicle_extent_m};
use super::{By, Decision};
use crate::config::scene::{LoadedScene, PlanMode};
use crate::config::vehicle::VehicleFile;
use crate::session::cache::Fnv64;

/// The track range to run with.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct RangeChoice {
    pub decision: Decision,
    /// `track.range_m`; `None`: the whole track.
    pub range_m: Option<[f64; 2]>,
    /// `track.straight_m` (an ideal straight shortened to the range).
    pub straight_m: Option<f64>,
}

/// Decide the track range: `wanted` is [`super::required_range_m`],
/// `chosen` whether the planner chooses it.
pub(super) fn decide(
    ls: &LoadedScene,
    v: &VehicleFile,
    facts: &TrackFacts,
    wanted: [f64; 2],
    mode: PlanMode,
    chosen: bool,
) -> RangeChoice {
    let scene = &ls.scene;
    let t = &scene.track;
    let clipped = [wanted[0].max(0.0), wanted[1].min(facts.length_m)];
    let (back, front) = vehicle_extent_m(v);
    let range_reason = format!(
        "s {:.1} m + {:.1} m travelled, vehicle {:.2} … {:+.2} m, {} m lookahead, {} m margins: {:.1} … {:.1} m of {:.1} m",
        scene.initial.s_m,
        travel_m(ls),
        back,
        front,
        DYNAMICS_LOOKAHEAD_M,
        RANGE_MARGIN_M,
        clipped[0],
        clipped[1],
        facts.length_m
    );
    let (mut range_m, mut straight_m) = (t.range_m, t.straight_m);
    let decision = if t.tables.is_some() {
        Decision {
            item: "track_range".into(),
            value: format!("0 … {:.1} m", facts.length_m),
            by: By::Scene,
            reason: "a table file is used as it is".into(),
        }
    } else if mode == PlanMode::Everything {
        range_m = None;
        Decision {
            item: "track_range".into(),
            value: format!("0 … {:.1} m", facts.length_m),
            by: By::Everything,
            reason: "the whole track".into(),
        }
    } else if chosen {
        let whole = clipped[0] <= 0.0 && clipped[1] >= facts.length_m;
        let value;
        if t.straight_m.is_some() {
            straight_m = Some(clipped[1].max(10.5).min(facts.length_m));
            range_m = None;
            value = format!("0 … {:.1} m", straight_m.unwrap_or(facts.length_m));
        } else if whole {
            range_m = None;
            value = format!("0 … {:.1} m", facts.length_m);
        } else {
            range_m = Some(clipped);
            value = format!("{:.1} … {:.1} m", clipped[0], clipped[1]);
        }
        Decision {
            item: "track_range".into(),
            value,
            by: By::Planner,
            reason: range_reason,
        }
    } else {
        Decision {
            item: "track_range".into(),
            value: match t.range_m {
                Some([a, b]) => format!("{a:.1} … {b:.1} m"),
                None => format!("0 … {:.1} m", facts.length_m),
            },
            by: By::Scene,
            reason: format!(
                "the planner would tabulate {:.1} … {:.1} m",
                clipped[0], clipped[1]
            ),
        }
    };
    RangeChoice {
        decision,
        range_m,
        straight_m,
    }
}

/// The preproc build configuration of the scene's `[track]`.
pub fn build_config(ls: &LoadedScene) -> Result<BuildConfig> {
    let t = &ls.scene.track;
    Ok(BuildConfig {
        scheme: t.scheme.scheme(),
        cant_scheme: t.cant_scheme.scheme(),
        step_m: t.step_m,
        gauge_m: t.gauge_m,
        rail_spacing: RailSpacing::default(),
        inclination: t.inclination()?,
        cant_base_m: None,
        rail_profile: Some(ls.path(&t.rail_profile)),
        rail_profile_cant: t.declared_rail_cant()?,
    })
}

/// The files of the scene's track geometry: its design file, or its
/// centreline and cant CSVs.
pub fn geometry_files(ls: &LoadedScene) -> Result<GeometryFiles> {
    let t = &ls.scene.track;
    Ok(match (&t.design, &t.centerline) {
        (Some(d), _) => GeometryFiles::Design(ls.path(d)),
        (None, Some(c)) => GeometryFiles::ControlPoints {
            centerline: ls.path(c),
            cant: t.cant.as_ref().map(|p| ls.path(p)),
        },
        (None, None) => anyhow::bail!("[track] has neither centerline nor design inputs"),
    })
}

/// A cache key ([`crate::session::cache`]) holding everything the scene's
/// track is built from: the tool version, the build configuration, the
/// kind of geometry (a design file's text is not a centreline's) and the
/// content of every input file (geometry, irregularities, rail profile;
/// `config` holds only their paths). Each cache adds what its entry is.
pub fn track_inputs_key(ls: &LoadedScene, config: &BuildConfig) -> Result<Fnv64> {
    let geometry = geometry_files(ls)?;
    let irregularities = ls.scene.track.irregularities.as_ref().map(|p| ls.path(p));
    let mut key = Fnv64::default();
    key.write_str(env!("CARGO_PKG_VERSION"))
        .write_str(&format!("{config:?}"))
        .write_str(match geometry {
            GeometryFiles::Design(_) => "design",
            GeometryFiles::ControlPoints { .. } => "control points",
        });
    for p in geometry
        .paths()
        .into_iter()
        .chain(irregularities.as_deref())
        .chain(config.rail_profile.as_deref())
    {
        let text =
            std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?;
        key.write_str(&text);
    }
    Ok(key)
}

/// The scene's CSV inputs fitted (every curve of the track, no tables).
pub(super) fn track_model(ls: &LoadedScene, config: &BuildConfig) -> Result<TrackModel> {
    let t = &ls.scene.track;
    let req = BuildRequest {
        geometry: geometry_files(ls)?,
        irregularities: t.irregularities.as_ref().map(|p| ls.path(p)),
        output: PathBuf::new(),
        config: config.clone(),
        contact: None,
        command_line: String::new(),
    };
    let (inputs, _) = preproc::pipeline::read_inputs(&req).context("reading the track inputs")?;
    TrackModel::from_inputs(&inputs, config).context("fitting the track")
}

/// The scene's track tables over `[from, to]` (m) only, built in memory
/// from its CSV inputs: the curves are fitted over the whole track (as
/// `track-preproc build` does), then only the rows inside the range are
/// tabulated, on the whole-track grid (rows k·h of s and of each rail's L),
/// so they equal the whole-track table's rows. The centreline rows are
/// built by `preproc::model::TrackModel::tabulate_range`.
pub fn build_track_range(ls: &LoadedScene, range: [f64; 2]) -> Result<TrackTables> {
    let config = build_config(ls)?;
    let model = track_model(ls, &config)?;
    model
        .tabulate_range(range[0], range[1], "sim run (track range in memory)")
        .with_context(|| format!("[track] range_m = [{}, {}]", range[0], range[1]))
}
