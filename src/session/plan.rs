//! Model only what a scene requires (issue 7, SPEC §0: "a run models only
//! what its scene requires"). Before a run, [`plan`] looks at the scene —
//! the track's geometry over the stretch the run covers, the vehicle, the
//! speed and the initial offset, the stated tolerance — and decides:
//!
//! | item | the planner's rule |
//! |---|---|
//! | flange search | `off` on an ideal straight (no curvature, cant or irregularity over the run's range) when the initial approach of every wheel, \|y₀\| + \|ψ₀\|·√(2 R0 h_flange), is at most [`START_FRACTION`] of the guard's threshold (below) **and** the linearised centred run is stable with margin at the scene's speed (hunting mode damping ratio ≥ [`MIN_HUNTING_DAMPING`]); `auto` otherwise. An `off` run is watched ([`FlangeGuard`]): should a wheelset come within [`GUARD_MARGIN_M`] of the `auto` threshold, the run is repeated with `auto`. Until then the `auto` rule would not have searched either, so the results are those of `auto`. |
//! | irregularities | the build's irregularity stage runs only when the scene gives an irregularity table (stated with its largest deviation over the run's range). |
//! | track range | only the stretch the run covers: from the rearmost point of the vehicle (wheelsets, bodies, references) at the start, minus [`RANGE_MARGIN_M`], to the foremost point at the end (distance, or duration × speed, less with a deceleration), plus the 2 m the dynamics keeps ahead and [`RANGE_MARGIN_M`]. Built in memory ([`build_track_range`]); the rows are those of the whole-track table (same grid). |
//! | table step | exact at any step on an ideal straight (linear interpolation of straight lines; `sim tradeoff` on the bogie measured zero error up to 1 m): [`MAX_STEP_M`]. Otherwise the coarsest of [`NICE_STEPS_M`] whose chord error h²κ/8 stays within [`GEOMETRY_TOLERANCE_M`] (κ the largest curvature of the rails over the range, irregularities included). The paper's rule h ≤ V·Δt (§2) is reported for comparison. |
//! | contact method | the contact lookup table where its error measured by `sim tradeoff` ([`TABLE_CONTACT_ERRORS`]) is within the scene's `run.lateral_tolerance_m`; online otherwise (and always without a stated tolerance). |
//! | creep law | never chosen (it is physics, not numerics); its cost relative to Polach, measured by `sim tradeoff`, is stated ([`CREEP_LAW_COST`]). |
//!
//! The `[plan]` section of the scene says who decides:
//!
//! - `mode = "scene"` (the default, every shipped scene): the scene runs as
//!   written; the block reports the scene's values and what the planner
//!   would choose (the cheap checks only: no linearisation).
//! - `mode = "required"`: the planner chooses every item the scene leaves
//!   out — an entry present in the scene (`contact.flange`,
//!   `contact.method`, `track.step_m`, `track.range_m`) forces that choice —
//!   and the items listed in `choose` (`flange`, `method`, `step`, `range`,
//!   or `all`) even when the scene sets them.
//! - `mode = "everything"`: the reference to measure against — flange
//!   always searched, online contact (an imported contact stays), the finest
//!   table step [`FINEST_STEP_M`] (the `sim tradeoff` reference's), the
//!   whole track.
//!
//! The decisions are one block of the output ([`Plan::to_text`]), the
//! `plan` object of `sim run --json` and the `plan` attribute of the
//! results file.

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use preproc::{BuildConfig, BuildRequest, Inclination, RailSpacing, TrackModel};
use runtime::contact::quasi_static::flange_clearance_m;
use runtime::dynamics::linear::linearise;
use runtime::dynamics::{InitialConditions, VehicleSystem};
use runtime::track::{Side, TrackTables};
use serde::Serialize;

use crate::config::scene::{ContactMethodKind, FlangeMode, LoadedScene, PlanItem, PlanMode};
use crate::config::vehicle::VehicleFile;

/// The items the planner may choose (`[plan] choose`).
pub const ITEMS: [&str; 4] = ["flange", "method", "step", "range"];

/// Largest table step the planner uses (m): the largest step `sim tradeoff`
/// measured on the straight (zero error against 0.01 m).
pub const MAX_STEP_M: f64 = 1.0;

/// The finest table step (m): the `sim tradeoff` reference's
/// (the reference run of `sim tradeoff`).
pub const FINEST_STEP_M: f64 = 0.01;

/// The steps the planner picks from (m), coarsest first (each divides 1 m).
pub const NICE_STEPS_M: [f64; 10] = [1.0, 0.5, 0.25, 0.2, 0.1, 0.05, 0.04, 0.025, 0.02, 0.01];

/// Largest chord error of the rail tables' linear interpolation the planner
/// accepts without a stated tolerance (m): h²κ/8 ≤ this (the sagitta of a
/// chord h on a curve of curvature κ; README "Linear interpolation of the
/// tables"). With `run.lateral_tolerance_m` the bound is half the tolerance.
/// The bound is what `sim tradeoff` measures (bogie, 30 m/s, against a
/// 0.01 m table; largest error of the lateral displacement): on
/// `curve_r300` (κ = 3.43e-3 1/m) 3.0 / 106 / 415 µm at 0.1 / 0.5 / 1 m
/// against bounds of 4.3 / 107 / 429 µm; on `irregular_300m`
/// (κ = 1.90e-3 1/m) 0.5 / 15 / 54 µm against 2.4 / 59 / 238 µm.
pub const GEOMETRY_TOLERANCE_M: f64 = 1e-6;

/// Curvature (1/m) below which a rail counts as straight (R > 10⁹ m: the
/// round-off of a spline fitted to collinear points).
pub const STRAIGHT_CURVATURE_1_M: f64 = 1e-9;

/// Margin of the track range before the vehicle's rearmost and after its
/// foremost point (m).
pub const RANGE_MARGIN_M: f64 = 5.0;

/// Table kept ahead of the leading wheelset by the dynamics (m;
/// `runtime::dynamics::system`: the run stops 2 m before the table's end).
pub const DYNAMICS_LOOKAHEAD_M: f64 = 2.0;

/// Safety margin of the `auto` flange rule (m; `ContactOptions::auto_margin_m`).
pub const AUTO_MARGIN_M: f64 = 0.003;

/// Extra margin of the flange guard before the `auto` threshold (m): covers
/// the lateral motion between two output samples.
pub const GUARD_MARGIN_M: f64 = 0.001;

/// Largest initial approach for `flange = off`, as a fraction of the
/// guard's threshold: a motion that decays from its start reaches the guard
/// only if it overshoots its start by a third.
pub const START_FRACTION: f64 = 0.75;

/// Least damping ratio of the linearised hunting mode for `flange = off`:
/// the envelope of a 5 % damped mode falls e-fold within about three
/// cycles; nearer the linear critical speed the subcritical hunting cycle
/// (README "Critical speed": 5–10 m/s below it) may be reached.
pub const MIN_HUNTING_DAMPING: f64 = 0.05;

/// The contact lookup table's largest error of the leading wheelset's
/// lateral displacement against online contact, measured by `sim tradeoff`
/// (variant "contact table" against its reference, RK4 0.1 ms, table step
/// 0.01 m, flange always searched).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeasuredTableError {
    /// Track kind: `straight`, `curve` or `irregular`.
    pub track: &'static str,
    /// Largest error of the lateral displacement (m).
    pub max_lateral_error_m: f64,
    /// Initial lateral offset of the measurement (m).
    pub initial_offset_m: f64,
    /// The study.
    pub source: &'static str,
}

/// The measurements the method decision uses (README "Only what the scene
/// requires"). The error is scaled by |y₀| / initial_offset_m when the
/// scene's offset is larger.
pub const TABLE_CONTACT_ERRORS: [MeasuredTableError; 3] = [
    MeasuredTableError {
        track: "straight",
        max_lateral_error_m: 4.863e-6,
        initial_offset_m: 0.002,
        source: "sim tradeoff tables/scenes/bogie_straight.toml (bogie, 30 m/s, 280 m)",
    },
    MeasuredTableError {
        track: "irregular",
        max_lateral_error_m: 6.340e-3,
        initial_offset_m: 0.002,
        source: "sim tradeoff of the bogie scene on tracks/irregular_300m (30 m/s, 280 m)",
    },
    // The run with the table failed: in the curve the leading wheelset's
    // lateral shift left the table's ±15 mm.
    MeasuredTableError {
        track: "curve",
        max_lateral_error_m: f64::INFINITY,
        initial_offset_m: 0.002,
        source: "sim tradeoff of the bogie scene on tracks/curve_r300 (30 m/s): the table run fails, the lateral shift leaves the table's ±15 mm",
    },
];

/// Wall time of each creep law relative to Polach's, measured by
/// `sim tradeoff tables/scenes/bogie_straight.toml` (bogie, 30 m/s, RK4
/// 0.1 ms, medians of 3: Polach 2.54 s, Kalker 2.89 s, Heuristic 2.80 s,
/// FASTSIM 16×64 10.73 s).
pub const CREEP_LAW_COST: [(&str, f64); 4] = [
    ("polach", 1.0),
    ("kalker", 1.13),
    ("heuristic", 1.10),
    ("fastsim", 4.22),
];

/// Who set a value.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum By {
    /// The scene's own entry (or its default in `mode = "scene"`).
    Scene,
    /// The planner.
    Planner,
    /// `mode = "everything"`.
    Everything,
}

impl By {
    fn name(self) -> &'static str {
        match self {
            By::Scene => "scene",
            By::Planner => "planner",
            By::Everything => "everything",
        }
    }
}

/// One line of the block.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Decision {
    /// `flange_search`, `irregularities`, `track_range`, `table_step`,
    /// `contact_method`, `creep_law`.
    pub item: String,
    pub value: String,
    pub by: By,
    pub reason: String,
}

/// Stop an `off` run whose wheelset approaches its flange: trips when
/// |y| + |ψ|·`reach_per_rad_m` ≥ `threshold_m` for any wheelset at an
/// output sample (y lateral displacement, ψ yaw relative to the track).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FlangeGuard {
    /// Flangeway clearance − `auto` margin − [`GUARD_MARGIN_M`] (m).
    pub threshold_m: f64,
    /// √(2 R0 h_flange) (m per rad of yaw).
    pub reach_per_rad_m: f64,
}

impl FlangeGuard {
    /// Whether a wheelset at lateral displacement `lateral_m` and yaw
    /// `yaw_rad` trips the guard.
    pub fn trips(&self, lateral_m: f64, yaw_rad: f64) -> bool {
        lateral_m.abs() + yaw_rad.abs() * self.reach_per_rad_m >= self.threshold_m
    }
}

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

    /// `straight`, `curve` or `irregular` (the kinds of
    /// [`TABLE_CONTACT_ERRORS`]).
    pub fn kind_name(&self) -> &'static str {
        if self.max_irregularity_m > 0.0 {
            "irregular"
        } else if self.straight() {
            "straight"
        } else {
            "curve"
        }
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

/// The decisions for one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// Who decided (`[plan] mode`).
    pub mode: PlanMode,
    /// The block, in order.
    pub decisions: Vec<Decision>,
    /// The values to run with.
    pub flange: FlangeMode,
    pub method: ContactMethodKind,
    /// Table step (m); `None` with a table file.
    pub step_m: Option<f64>,
    /// Track range (m); `None`: the whole track.
    pub range_m: Option<[f64; 2]>,
    /// Length of an ideal straight (m), shortened to the range.
    pub straight_m: Option<f64>,
    /// Watch an `off` run (see [`FlangeGuard`]).
    pub flange_guard: Option<FlangeGuard>,
    /// Set when a run was repeated: why.
    pub revised: Option<String>,
    pub track: TrackFacts,
    pub flange_facts: Option<FlangeFacts>,
    /// Wall time of the planning (s).
    pub planning_time_s: f64,
}

/// Entries written in the scene (after the overrides): those force a choice.
fn explicit_entries(ls: &LoadedScene) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let Ok(table) = ls.text.parse::<toml::Table>() else {
        return out;
    };
    for (section, key) in [
        ("contact", "flange"),
        ("contact", "method"),
        ("track", "step_m"),
        ("track", "range_m"),
    ] {
        if table
            .get(section)
            .and_then(toml::Value::as_table)
            .is_some_and(|t| t.contains_key(key))
        {
            out.insert(format!("{section}.{key}"));
        }
    }
    out
}

/// Simulated distance of the vehicle reference point (m): the distance, or
/// the duration at the speed (with a deceleration, until the stop).
pub fn travel_m(ls: &LoadedScene) -> f64 {
    let s = &ls.scene;
    if let Some(d) = s.run.distance_m {
        return d;
    }
    let (v0, a) = (s.initial.speed_m_s, s.initial.deceleration_m_s2);
    let t = s.duration_s();
    if a > 0.0 {
        let t_stop = v0 / a;
        let t = t.min(t_stop);
        v0 * t - 0.5 * a * t * t
    } else {
        v0 * t
    }
}

/// Longitudinal extent of the vehicle relative to its reference point (m):
/// wheelsets, bodies' centres of gravity, references' origins.
fn vehicle_extent_m(v: &VehicleFile) -> (f64, f64) {
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

/// The preproc build configuration of the scene's `[track]`.
pub fn build_config(ls: &LoadedScene) -> Result<BuildConfig> {
    let t = &ls.scene.track;
    Ok(BuildConfig {
        scheme: t.scheme.parse().context("[track] scheme")?,
        step_m: t.step_m,
        gauge_m: t.gauge_m,
        rail_spacing: RailSpacing::default(),
        inclination: t
            .rail_inclination
            .parse::<Inclination>()
            .map_err(anyhow::Error::msg)
            .context("[track] rail_inclination")?,
        cant_base_m: None,
    })
}

/// The scene's CSV inputs fitted (every curve of the track, no tables).
fn track_model(ls: &LoadedScene, config: &BuildConfig) -> Result<TrackModel> {
    let t = &ls.scene.track;
    let req = BuildRequest {
        centerline: ls.path(t.centerline.as_ref().context("no centerline")?),
        cant: t.cant.as_ref().map(|p| ls.path(p)),
        irregularities: t.irregularities.as_ref().map(|p| ls.path(p)),
        output: PathBuf::new(),
        config: config.clone(),
        contact: None,
        command_line: String::new(),
    };
    let (inputs, _) = preproc::pipeline::read_inputs(&req).context("reading the track inputs")?;
    TrackModel::build(&inputs, config).context("fitting the track")
}

/// Facts of the track over `[a, b]` (m; clipped to the track).
fn track_facts(ls: &LoadedScene, range: [f64; 2]) -> Result<TrackFacts> {
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
        let tables = runtime::schema::read_track(&ls.path(p))?;
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
    let model = track_model(ls, &config)?;
    let length = model.centerline.length_m();
    let (a, b) = (range[0].max(0.0), range[1].min(length));
    // Probe every 5 cm (at most 200 000 points per curve): finer than the
    // rail nodes (≤ 1 m) and the irregularity samples.
    let probe = 0.05_f64.max((b - a) / 2e5);
    let n = ((b - a) / probe).ceil().max(1.0) as usize;
    let s: Vec<f64> = (0..=n).map(|k| a + (b - a) * k as f64 / n as f64).collect();
    let mut f = TrackFacts {
        kind: "centerline".into(),
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
/// with a table file), long enough for the vehicle: for the flange facts
/// and the linear stability check.
fn check_track(ls: &LoadedScene, v: &VehicleFile) -> Result<(TrackTables, f64)> {
    let t = &ls.scene.track;
    let (gauge, spacing, incl) = match &t.tables {
        Some(p) => {
            let m = runtime::schema::read_track(&ls.path(p))?.meta;
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
    Ok((
        runtime::track::straight_track(length, 1.0, gauge, spacing, incl),
        s_start,
    ))
}

/// Flangeway clearance and yawed-flange reach of the vehicle's wheelsets;
/// the clearance (a quasi-static sweep, about 0.2 s) is cached
/// ([`crate::session::cache`]) under a key of the profiles' texts, the wheelsets'
/// radius and back-to-back, the rail placement and the tool version.
fn flange_facts(ls: &LoadedScene, v: &VehicleFile, track: &TrackTables) -> Result<FlangeFacts> {
    let rail = ls.path(&ls.scene.track.rail_profile);
    let mut key = crate::session::cache::Fnv64::default();
    key.write_str(env!("CARGO_PKG_VERSION"))
        .write_str(&format!("{:?}", track.meta))
        .write_str(
            &std::fs::read_to_string(&rail)
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
    let vehicle = crate::session::vehicle::vehicle_model(v, track, &rail)?;
    let mut clearance = f64::INFINITY;
    let mut reach = 0.0_f64;
    let mut done: Vec<&runtime::contact::WheelsetContactModel> = Vec::new();
    for w in &vehicle.wheelsets {
        if done.contains(&&w.contact) {
            continue;
        }
        for side in Side::BOTH {
            let c = flange_clearance_m(&w.contact, side)
                .with_context(|| format!("flangeway clearance of wheelset '{}'", w.name))?;
            clearance = clearance.min(c.unwrap_or(f64::INFINITY));
            let wheel = w.contact.wheel(side);
            reach = reach.max((2.0 * wheel.nominal_radius_m() * wheel.flange_depth_m()).sqrt());
        }
        done.push(&w.contact);
    }
    // Written atomically; a failure to cache is not an error.
    static WRITES: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = path.with_extension(format!("tmp{}-{n}", std::process::id()));
    if std::fs::write(&tmp, format!("{clearance:e} {reach:e}\n")).is_ok() {
        let _ = std::fs::rename(&tmp, &path);
    }
    Ok(facts(clearance, reach))
}

/// Damping ratio and frequency (Hz) of the hunting mode of the centred run
/// at the scene's speed, creep law and friction, online contact, on an
/// ideal straight (`runtime::dynamics::linear`); `None` when there is no
/// oscillatory lateral mode.
fn hunting(
    ls: &LoadedScene,
    v: &VehicleFile,
    track: &TrackTables,
    s_start: f64,
) -> Result<Option<(f64, f64)>> {
    let mut check = ls.clone();
    check.scene.contact.method = ContactMethodKind::Online;
    // Off: the centred run has no flange contact, and the assembly then
    // skips the flangeway clearance sweep.
    check.scene.contact.flange = FlangeMode::Off;
    let vehicle =
        crate::session::vehicle::vehicle_model(v, track, &ls.path(&ls.scene.track.rail_profile))?;
    let mut settings = crate::session::settings::system_settings(&check, v, track)?;
    settings.s_start_m = s_start;
    settings.deceleration_m_s2 = 0.0;
    let (mut system, y0) =
        VehicleSystem::assemble(track, &vehicle, settings, InitialConditions::default())
            .context("assembling the vehicle for the stability check")?;
    let lin = linearise(&mut system, &y0).context("linearising the centred run")?;
    Ok(lin.hunting().map(|m| (m.damping_ratio, m.frequency_hz)))
}

fn mm(x_m: f64) -> String {
    format!("{:.2} mm", x_m * 1e3)
}

/// The largest of [`NICE_STEPS_M`] within `h_m` (the finest if none).
fn nice_step_m(h_m: f64) -> f64 {
    NICE_STEPS_M
        .iter()
        .copied()
        .find(|&s| s <= h_m)
        .unwrap_or(FINEST_STEP_M)
}

/// Decide what the scene requires (module docs).
pub fn plan(ls: &LoadedScene) -> Result<Plan> {
    let start = Instant::now();
    let scene = &ls.scene;
    let mode = scene.plan.mode;
    let explicit = explicit_entries(ls);
    let planner_chooses = |item: PlanItem, entry: &str| -> bool {
        mode == PlanMode::Required && (scene.plan.chooses(item) || !explicit.contains(entry))
    };
    let vfile = VehicleFile::load(&ls.path(&scene.vehicle.file))?;
    let wanted = required_range_m(ls, &vfile);
    let facts = track_facts(ls, wanted)?;
    let mut decisions = Vec::new();

    // Irregularities: the build's stage runs only with a table.
    decisions.push(Decision {
        item: "irregularities".into(),
        value: if facts.irregularities {
            "built"
        } else {
            "none"
        }
        .into(),
        by: By::Scene,
        reason: if facts.irregularities {
            format!(
                "the scene gives an irregularity table: largest deviation {} over the run's range",
                mm(facts.max_irregularity_m)
            )
        } else {
            "the scene has none: the irregularity stage is skipped".into()
        },
    });

    // Track range.
    let t = &scene.track;
    let clipped = [wanted[0].max(0.0), wanted[1].min(facts.length_m)];
    let range_reason = format!(
        "s {:.1} m + {:.1} m travelled, vehicle {:.2} … {:+.2} m, {} m lookahead, {} m margins: {:.1} … {:.1} m of {:.1} m",
        scene.initial.s_m,
        travel_m(ls),
        vehicle_extent_m(&vfile).0,
        vehicle_extent_m(&vfile).1,
        DYNAMICS_LOOKAHEAD_M,
        RANGE_MARGIN_M,
        clipped[0],
        clipped[1],
        facts.length_m
    );
    let (mut range_m, mut straight_m) = (t.range_m, t.straight_m);
    let range_by;
    let range_value;
    if t.tables.is_some() {
        range_by = By::Scene;
        range_value = format!("0 … {:.1} m", facts.length_m);
        decisions.push(Decision {
            item: "track_range".into(),
            value: range_value,
            by: range_by,
            reason: "a table file is used as it is".into(),
        });
    } else if mode == PlanMode::Everything {
        range_m = None;
        decisions.push(Decision {
            item: "track_range".into(),
            value: format!("0 … {:.1} m", facts.length_m),
            by: By::Everything,
            reason: "the whole track".into(),
        });
    } else if planner_chooses(PlanItem::Range, "track.range_m") {
        let whole = clipped[0] <= 0.0 && clipped[1] >= facts.length_m;
        if t.straight_m.is_some() {
            straight_m = Some(clipped[1].max(10.5).min(facts.length_m));
            range_m = None;
            range_value = format!("0 … {:.1} m", straight_m.unwrap_or(facts.length_m));
        } else if whole {
            range_m = None;
            range_value = format!("0 … {:.1} m", facts.length_m);
        } else {
            range_m = Some(clipped);
            range_value = format!("{:.1} … {:.1} m", clipped[0], clipped[1]);
        }
        decisions.push(Decision {
            item: "track_range".into(),
            value: range_value,
            by: By::Planner,
            reason: range_reason,
        });
    } else {
        let value = match t.range_m {
            Some([a, b]) => format!("{a:.1} … {b:.1} m"),
            None => format!("0 … {:.1} m", facts.length_m),
        };
        decisions.push(Decision {
            item: "track_range".into(),
            value,
            by: By::Scene,
            reason: format!(
                "the planner would tabulate {:.1} … {:.1} m",
                clipped[0], clipped[1]
            ),
        });
    }

    // Table step.
    let v = scene.initial.speed_m_s;
    let dt = match scene.run.integrator.as_str() {
        "rk4" => Some(scene.run.step_s),
        _ => None,
    };
    let paper = match dt {
        Some(dt) => format!("paper §2's rule h ≤ V·Δt = {:.4} m", v * dt),
        None => "paper §2's rule h ≤ V·Δt (Δt adaptive)".into(),
    };
    let (planned_step, step_reason) = if facts.straight() {
        (
            MAX_STEP_M,
            format!(
                "ideal straight over the range: linear interpolation is exact at any step (sim tradeoff: zero error up to 1 m); {paper} not needed"
            ),
        )
    } else {
        let k = facts.max_curvature_1_m;
        let (eps, eps_why) = match scene.run.lateral_tolerance_m {
            Some(tol) => (0.5 * tol, "half the tolerance"),
            None => (GEOMETRY_TOLERANCE_M, "no tolerance stated"),
        };
        let h = (8.0 * eps / k).sqrt();
        let step = nice_step_m(h).min(MAX_STEP_M);
        (
            step,
            format!(
                "largest curvature {k:.3e} 1/m (R {:.0} m): chord error h²κ/8 = {:.2} µm ≤ {:.2} µm ({eps_why}; sim tradeoff measured the lateral error below this bound); {paper}",
                1.0 / k,
                step * step * k / 8.0 * 1e6,
                eps * 1e6
            ),
        )
    };
    let step_m;
    if let Some(fs) = facts.file_step_m {
        step_m = None;
        decisions.push(Decision {
            item: "table_step".into(),
            value: format!("{fs} m"),
            by: By::Scene,
            reason: "a table file is used as it is".into(),
        });
    } else if mode == PlanMode::Everything {
        step_m = Some(FINEST_STEP_M);
        decisions.push(Decision {
            item: "table_step".into(),
            value: format!("{FINEST_STEP_M} m"),
            by: By::Everything,
            reason: "the finest step (sim tradeoff's reference)".into(),
        });
    } else if planner_chooses(PlanItem::Step, "track.step_m") {
        step_m = Some(planned_step);
        decisions.push(Decision {
            item: "table_step".into(),
            value: format!("{planned_step} m"),
            by: By::Planner,
            reason: step_reason,
        });
    } else {
        step_m = Some(t.step_m);
        decisions.push(Decision {
            item: "table_step".into(),
            value: format!("{} m", t.step_m),
            by: By::Scene,
            reason: format!("the planner would choose {planned_step} m: {step_reason}"),
        });
    }

    // Flange search (decided before the method: the table needs no flange
    // contact to be expected).
    let c = &scene.contact;
    let method_chosen = planner_chooses(PlanItem::Method, "contact.method")
        && c.method != ContactMethodKind::Imported;
    let flange_chosen = planner_chooses(PlanItem::Flange, "contact.flange");
    // The flange facts matter only where the flange search may be off: an
    // ideal straight with a contact that searches (not imported).
    let straight = facts.straight() && c.method != ContactMethodKind::Imported;
    let (track, s_start) = check_track(ls, &vfile)?;
    let ffacts = if straight {
        flange_facts(ls, &vfile, &track)?
    } else {
        FlangeFacts {
            clearance_m: f64::NAN,
            reach_per_rad_m: f64::NAN,
            initial_approach_m: f64::NAN,
        }
    };
    let threshold = ffacts.clearance_m - AUTO_MARGIN_M;
    let guard_threshold = threshold - GUARD_MARGIN_M;
    let start_limit = START_FRACTION * guard_threshold;
    // External loads and initial pushes can drive a wheelset to its flange
    // whatever the track: the flange is then searched.
    let disturbed = scene.load != crate::config::load::LoadSection::default()
        || scene.perturbation != crate::config::load::PerturbationSection::default();
    let geometric_ok = straight && !disturbed && ffacts.initial_approach_m <= start_limit;
    let geometric_reason = if disturbed {
        "the scene applies a [load] or a [perturbation]".to_string()
    } else if !facts.straight() {
        format!(
            "the track is not an ideal straight over the range ({})",
            facts.kind_name()
        )
    } else if !straight {
        "an imported contact".to_string()
    } else if !geometric_ok {
        format!(
            "initial approach {} > {} (3/4 of the guard {}: the auto threshold {} clearance − {} = {}, less 1 mm)",
            mm(ffacts.initial_approach_m),
            mm(start_limit),
            mm(guard_threshold),
            mm(ffacts.clearance_m),
            mm(AUTO_MARGIN_M),
            mm(threshold)
        )
    } else {
        format!(
            "ideal straight, initial approach {} ≤ {} (3/4 of the guard {})",
            mm(ffacts.initial_approach_m),
            mm(start_limit),
            mm(guard_threshold)
        )
    };
    // The linear check costs an assembly and a linearisation: only when the
    // planner decides and it can matter.
    let run_linear = geometric_ok && mode != PlanMode::Scene && (flange_chosen || method_chosen);
    // A check that cannot be made is no reason to fail the run: the flange
    // is then searched.
    let stability = if run_linear {
        Some(hunting(ls, &vfile, &track, s_start).map_err(|e| format!("{e:#}")))
    } else {
        None
    };
    let checked = stability.is_some();
    let (no_flange_expected, flange_reason) = match (geometric_ok, stability) {
        (false, _) => (false, geometric_reason.clone()),
        (true, Some(Err(e))) => (
            false,
            format!("{geometric_reason}, but the stability check failed: {e}"),
        ),
        (true, None) => (
            false,
            format!(
                "{geometric_reason}; the hunting mode's damping is checked only when the planner decides"
            ),
        ),
        (true, Some(Ok(None))) => (
            false,
            format!(
                "{geometric_reason}, but no hunting mode found at {v} m/s to check its damping"
            ),
        ),
        (true, Some(Ok(Some((zeta, f))))) if zeta >= MIN_HUNTING_DAMPING => (
            true,
            format!(
                "{geometric_reason}; hunting mode damped at {v} m/s (ζ = {zeta:.3} ≥ {MIN_HUNTING_DAMPING}, {f:.2} Hz)"
            ),
        ),
        (true, Some(Ok(Some((zeta, f))))) => (
            false,
            format!(
                "{geometric_reason}, but the hunting mode at {v} m/s has ζ = {zeta:.3} < {MIN_HUNTING_DAMPING} ({f:.2} Hz): the motion may grow to the flange"
            ),
        ),
    };

    // Contact method.
    let kind = facts.kind_name();
    let measured = TABLE_CONTACT_ERRORS.iter().find(|m| m.track == kind);
    let tol = scene.run.lateral_tolerance_m;
    let (planned_method, method_reason) = match (tol, measured) {
        (None, _) => (
            ContactMethodKind::Online,
            "no run.lateral_tolerance_m: the exact (online) contact".to_string(),
        ),
        (Some(tol), None) => (
            ContactMethodKind::Online,
            format!(
                "the contact table's error is not measured on a {kind} track; tolerance {tol:.1e} m"
            ),
        ),
        (Some(tol), Some(m)) if !m.max_lateral_error_m.is_finite() => (
            ContactMethodKind::Online,
            format!(
                "the contact table is unusable on a {kind} track: {}; tolerance {tol:.1e} m",
                m.source
            ),
        ),
        (Some(tol), Some(m)) => {
            let scale = (scene.initial.lateral_m.abs() / m.initial_offset_m).max(1.0);
            let est = m.max_lateral_error_m * scale;
            if kind == "straight" && !no_flange_expected {
                (
                    ContactMethodKind::Online,
                    "flange contact cannot be ruled out, and the table's zero-yaw rows do not model a yawed flange's lead (measured without flange contact)".to_string(),
                )
            } else if est <= tol {
                (
                    ContactMethodKind::Table,
                    format!(
                        "measured error {:.2} µm{} ≤ tolerance {:.2} µm ({}); the table is built once per wheel/rail pair and cached",
                        est * 1e6,
                        if scale > 1.0 {
                            format!(" (scaled ×{scale:.1} for the offset)")
                        } else {
                            String::new()
                        },
                        tol * 1e6,
                        m.source
                    ),
                )
            } else {
                (
                    ContactMethodKind::Online,
                    format!(
                        "measured table error {:.2} µm > tolerance {:.2} µm ({})",
                        est * 1e6,
                        tol * 1e6,
                        m.source
                    ),
                )
            }
        }
    };
    let method;
    if c.method == ContactMethodKind::Imported {
        method = c.method;
        decisions.push(Decision {
            item: "contact_method".into(),
            value: method.to_string(),
            by: By::Scene,
            reason: "an imported contact table (the scene's model of the contact)".into(),
        });
    } else if mode == PlanMode::Everything {
        method = ContactMethodKind::Online;
        decisions.push(Decision {
            item: "contact_method".into(),
            value: method.to_string(),
            by: By::Everything,
            reason: "Newton at every evaluation".into(),
        });
    } else if method_chosen {
        method = planned_method;
        decisions.push(Decision {
            item: "contact_method".into(),
            value: method.to_string(),
            by: By::Planner,
            reason: method_reason,
        });
    } else {
        method = c.method;
        decisions.push(Decision {
            item: "contact_method".into(),
            value: method.to_string(),
            by: By::Scene,
            reason: if mode == PlanMode::Scene {
                "the planner decides with [plan] mode = \"required\" and run.lateral_tolerance_m"
                    .into()
            } else {
                format!("the planner would choose {planned_method}: {method_reason}")
            },
        });
    }

    let mut flange_guard = None;
    let flange;
    if method == ContactMethodKind::Table && method_chosen && flange_chosen {
        // Chosen only when no flange contact is expected: the assembly's
        // settling then needs no flange search (nor its clearance sweep).
        flange = FlangeMode::Off;
        decisions.push(Decision {
            item: "flange_search".into(),
            value: "off".into(),
            by: By::Planner,
            reason: format!(
                "the table contact takes its flange contact from its table; off for the settling at assembly: {flange_reason}"
            ),
        });
    } else if method != ContactMethodKind::Online {
        flange = c.flange;
        decisions.push(Decision {
            item: "flange_search".into(),
            value: if method == ContactMethodKind::Imported {
                "not used".into()
            } else {
                format!("{} (settling only)", c.flange)
            },
            by: By::Scene,
            reason: if method == ContactMethodKind::Imported {
                "the imported contact takes its one contact per wheel from its table".into()
            } else {
                format!(
                    "the {method} contact takes its flange contact from its table; the flange search only settles the wheelsets at assembly"
                )
            },
        });
    } else if mode == PlanMode::Everything {
        flange = FlangeMode::On;
        decisions.push(Decision {
            item: "flange_search".into(),
            value: flange.to_string(),
            by: By::Everything,
            reason: "searched at every solve".into(),
        });
    } else if flange_chosen {
        let off = no_flange_expected;
        flange = if off {
            FlangeMode::Off
        } else {
            FlangeMode::Auto
        };
        if off {
            flange_guard = Some(FlangeGuard {
                threshold_m: guard_threshold,
                reach_per_rad_m: ffacts.reach_per_rad_m,
            });
        }
        decisions.push(Decision {
            item: "flange_search".into(),
            value: flange.to_string(),
            by: By::Planner,
            reason: if off {
                format!(
                    "{flange_reason}; guarded: the run is repeated with auto if a wheelset reaches {}",
                    mm(guard_threshold)
                )
            } else {
                format!("{flange_reason} (auto: searched within 3 mm of the flange)")
            },
        });
    } else {
        flange = c.flange;
        decisions.push(Decision {
            item: "flange_search".into(),
            value: flange.to_string(),
            by: By::Scene,
            reason: format!(
                "the planner {}: {flange_reason}",
                if geometric_ok && !checked {
                    "might choose off"
                } else if no_flange_expected {
                    "would choose off"
                } else {
                    "would choose auto"
                }
            ),
        });
    }

    // Creep law: stated, never chosen.
    let cost = CREEP_LAW_COST
        .iter()
        .find(|(n, _)| *n == c.creep_law.as_str())
        .map(|(_, f)| *f);
    let fastsim = CREEP_LAW_COST[3].1;
    decisions.push(Decision {
        item: "creep_law".into(),
        value: c.creep_law.to_string(),
        by: By::Scene,
        reason: match cost {
            Some(f) => format!(
                "wall time ×{f:.2} of Polach's (FASTSIM ×{fastsim:.2}, Kalker ×{:.2}, Heuristic ×{:.2}; sim tradeoff, bogie at 30 m/s)",
                CREEP_LAW_COST[1].1,
                CREEP_LAW_COST[2].1
            ),
            None => "cost not measured".into(),
        },
    });

    Ok(Plan {
        mode: scene.plan.mode,
        decisions,
        flange,
        method,
        step_m,
        range_m,
        straight_m,
        flange_guard,
        revised: None,
        track: facts,
        flange_facts: straight.then_some(ffacts),
        planning_time_s: start.elapsed().as_secs_f64(),
    })
}

impl Plan {
    /// The scene to run: `ls` with the plan's choices.
    pub fn apply(&self, ls: &LoadedScene) -> LoadedScene {
        let mut out = ls.clone();
        let s = &mut out.scene;
        s.contact.flange = self.flange;
        s.contact.method = self.method;
        if let Some(h) = self.step_m {
            s.track.step_m = h;
        }
        s.track.range_m = self.range_m;
        if s.track.straight_m.is_some() {
            s.track.straight_m = self.straight_m;
        }
        out
    }

    /// The `off` flange search did not hold: search with `auto` (`why`
    /// says where the guard tripped).
    pub fn revise_flange(&mut self, why: &str) {
        self.flange = FlangeMode::Auto;
        self.flange_guard = None;
        self.revised = Some(format!("flange search off → auto: {why}"));
        if let Some(d) = self
            .decisions
            .iter_mut()
            .find(|d| d.item == "flange_search")
        {
            d.value = "auto".into();
            d.reason = format!("revised during the run ({why}); planned off: {}", d.reason);
        }
    }

    /// The block printed before the summary.
    pub fn to_text(&self) -> String {
        let mut s = format!(
            "plan (mode {}; planned in {:.3} s):\n",
            self.mode, self.planning_time_s
        );
        for d in &self.decisions {
            s += &format!(
                "  {:<15} {:<16} [{}] {}\n",
                d.item.replace('_', " "),
                d.value,
                d.by.name(),
                d.reason
            );
        }
        if let Some(r) = &self.revised {
            s += &format!("  revised: {r}\n");
        }
        s
    }
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

/// The flange guard at an output sample: where it trips (wheelset, time,
/// distance, lateral and yaw), or `None`.
pub fn guard_check(
    guard: &FlangeGuard,
    results: &runtime::results::RunResults,
    t_s: f64,
) -> Option<String> {
    results.wheelsets.iter().find_map(|w| {
        let (y, psi) = (*w.lateral_m.last()?, *w.yaw_rad.last()?);
        guard.trips(y, psi).then(|| {
            format!(
                "wheelset '{}' reached {} (yaw {:.2} mrad) at t = {t_s:.3} s, s = {:.1} m, guard {}",
                w.name,
                mm(y),
                psi * 1e3,
                w.distance_m.last().copied().unwrap_or(f64::NAN),
                mm(guard.threshold_m)
            )
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_round_down_to_the_nice_ones() {
        assert_eq!(nice_step_m(2.0), 1.0);
        assert_eq!(nice_step_m(0.107), 0.1);
        assert_eq!(nice_step_m(0.0483), 0.04);
        assert_eq!(nice_step_m(0.001), FINEST_STEP_M);
        // Every nice step divides 1 m (the rows of a range lie on the
        // whole-track grid of any of them).
        for h in NICE_STEPS_M {
            let n = 1.0 / h;
            assert!((n - n.round()).abs() < 1e-9, "{h}");
        }
    }

    #[test]
    fn the_guard_adds_the_yawed_flange_reach() {
        let g = FlangeGuard {
            threshold_m: 0.0028,
            reach_per_rad_m: 0.155,
        };
        assert!(!g.trips(-0.002, 0.0));
        assert!(g.trips(-0.0028, 0.0));
        assert!(g.trips(0.002, -0.006), "2 mm + 6 mrad × 0.155 m = 2.93 mm");
        assert!(!g.trips(0.002, 0.005), "2 mm + 0.78 mm");
    }

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

    #[test]
    fn plan_sections_are_checked() {
        let ok = LoadedScene::default_scene(&[
            "plan.mode=required".into(),
            "plan.choose=[\"flange\", \"all\"]".into(),
        ])
        .expect("a valid [plan]");
        assert!(ok.scene.plan.chooses(PlanItem::Step));
        for (mode, choose, what) in [
            ("sometimes", "[]", "sometimes"),
            ("required", "[\"integrator\"]", "integrator"),
            ("scene", "[\"flange\"]", "choose"),
        ] {
            let e = LoadedScene::default_scene(&[
                format!("plan.mode={mode}"),
                format!("plan.choose={choose}"),
            ])
            .unwrap_err();
            assert!(format!("{e:#}").contains(what), "{e:#}");
        }
    }
}
