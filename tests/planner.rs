//! The planner ([`railsim::session::plan`], docs/guide/speed-accuracy-tradeoff.md "Only what the scene
//! requires"): its decisions for constructed scenes (straight, curve,
//! irregular; small and large offsets; a stable bogie and an unstable
//! wheelset; with and without a tolerance), forced values kept, the
//! block printed by `sim run`, the planned run equal to the fully modelled
//! one on the straight, the track range equal to the whole-track table, and
//! the flange guard's revision.

mod common;

use std::path::Path;

use common::*;
use railsim::config::scene::{ContactMethodKind, FlangeMode, LoadedScene, PlanMode};
use railsim::report::run_files::{RunRequest, run_to_files};
use railsim::session::plan::{
    By, FlangeGuard, IntegratorPlan, Plan, TrackFacts, build_track_range,
};
use runtime::io::schema::read_results;
use serde_json::Value;

/// The bogie scene with its track and run length replaced.
fn bogie_scene(dir: &Path, name: &str, track: &str, extra: &str) -> std::path::PathBuf {
    let scenes = shipped("scenes");
    let text = format!(
        r#"title = "planner test {name}"
[track]
{track}
rail_profile = "{scenes}/../profiles/MBench_UIC60_v3.prr"
rail_profile_cant = "1:40"
[vehicle]
file = "{scenes}/../vehicles/ml95_like_bogie.toml"
[initial]
speed_m_s = 30.0
s_m = 5.0
lateral_m = -0.002
[run]
distance_m = 40.0
step_s = 5e-4
{extra}
"#,
        scenes = scenes.display()
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("write scene");
    path
}

fn straight(step: &str) -> String {
    format!(
        "centerline = \"{}\"\n{step}",
        shipped("tracks/straight_300m/centerline.csv").display()
    )
}

fn curve() -> String {
    format!(
        "centerline = \"{}\"",
        shipped("tracks/curve_r300/centerline.csv").display()
    )
}

fn irregular() -> String {
    format!(
        "centerline = \"{}\"\nirregularities = \"{}\"",
        shipped("tracks/irregular_300m/centerline.csv").display(),
        shipped("tracks/irregular_300m/irregularities.csv").display()
    )
}

/// `sim run SCENE --plan-only --json` with extra arguments: the plan.
fn plan_of(dir: &Path, scene: &Path, args: &[&str]) -> Value {
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .arg("run")
        .arg(scene)
        .args(["--plan-only", "--json"])
        .args(args));
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_str(&stdout(&o)).expect("JSON plan")
}

fn decision<'a>(plan: &'a Value, item: &str) -> &'a Value {
    plan["decisions"]
        .as_array()
        .expect("decisions")
        .iter()
        .find(|d| d["item"] == item)
        .unwrap_or_else(|| panic!("no {item} in {plan}"))
}

const ALL: [&str; 3] = ["--plan", "--set", "plan.choose=[\"all\"]"];

#[test]
fn straight_small_offset_stable_bogie_needs_no_flange_search_and_a_coarse_table() {
    let dir = scratch("planner_straight");
    let scene = bogie_scene(&dir, "straight", &straight("step_m = 0.1"), "");
    let p = plan_of(&dir, &scene, &ALL);
    assert_eq!(p["flange"], "off", "{p:#}");
    let guard = &p["flange_guard"];
    // Guard: the ML95-like flangeway clearance (6.8 mm) less 3 + 1 mm.
    let g = guard["threshold_m"].as_f64().expect("guard");
    assert!((0.0025..0.0031).contains(&g), "{guard}");
    assert!(
        decision(&p, "flange_search")["reason"]
            .as_str()
            .unwrap()
            .contains("hunting mode damped"),
        "{p:#}"
    );
    assert_eq!(p["step_m"], 1.0);
    assert_eq!(p["method"], "online", "no tolerance: online");
    // 5 m + 40 m + 1.05 m + 2 m + 5 m; the rear end clips at 0.
    let r = p["range_m"].as_array().expect("a range");
    assert_eq!(r[0], 0.0);
    assert!((r[1].as_f64().unwrap() - 53.05).abs() < 1e-9, "{r:?}");
    assert_eq!(decision(&p, "irregularities")["value"], "none");
    assert_eq!(decision(&p, "table_step")["by"], "planner");
    // With a tolerance above the measured 4.9 µm: the contact table, and
    // the settling at assembly needs no flange search.
    let p = plan_of(
        &dir,
        &scene,
        &[&ALL[..], &["--set", "run.lateral_tolerance_m=1e-5"]].concat(),
    );
    assert_eq!(p["method"], "table", "{p:#}");
    assert_eq!(p["flange"], "off");
    // Below it: online.
    let p = plan_of(
        &dir,
        &scene,
        &[&ALL[..], &["--set", "run.lateral_tolerance_m=1e-6"]].concat(),
    );
    assert_eq!(p["method"], "online", "{p:#}");
}

#[test]
fn a_large_offset_or_an_unstable_vehicle_keeps_the_flange_search() {
    let dir = scratch("planner_offset");
    let scene = bogie_scene(&dir, "offset", &straight(""), "");
    let p = plan_of(
        &dir,
        &scene,
        &[&ALL[..], &["--set", "initial.lateral_m=-0.004"]].concat(),
    );
    assert_eq!(p["flange"], "auto", "{p:#}");
    assert!(p["flange_guard"].is_null());
    assert!(
        decision(&p, "flange_search")["reason"]
            .as_str()
            .unwrap()
            .contains("initial approach 4.00 mm >"),
        "{p:#}"
    );
    // The unsuspended wheelset hunts with growing amplitude at 10 m/s
    // (paper Fig. 15): its hunting mode is not damped.
    let p = plan_of(&dir, &shipped("scenes/wheelset_straight.toml"), &ALL);
    assert_eq!(p["flange"], "auto", "{p:#}");
    assert!(
        decision(&p, "flange_search")["reason"]
            .as_str()
            .unwrap()
            .contains("may grow to the flange"),
        "{p:#}"
    );
    // A yaw adds its flange's reach: 10 mrad × √(2 R0 h) ≈ 1.6 mm.
    let p = plan_of(
        &dir,
        &scene,
        &[&ALL[..], &["--set", "initial.yaw_rad=0.01"]].concat(),
    );
    assert_eq!(p["flange"], "auto", "{p:#}");
    // An external load or an initial push can reach the flange on any track.
    for push in [
        "load.lateral_force_n=5000",
        "perturbation.lateral_velocity_m_s=0.2",
    ] {
        let p = plan_of(&dir, &scene, &[&ALL[..], &["--set", push]].concat());
        assert_eq!(p["flange"], "auto", "{push}: {p:#}");
        assert!(
            decision(&p, "flange_search")["reason"]
                .as_str()
                .unwrap()
                .contains("[load] or a [perturbation]"),
            "{p:#}"
        );
    }
}

#[test]
fn curves_and_irregularities_keep_the_flange_search_and_refine_the_table() {
    let dir = scratch("planner_curve");
    let scene = bogie_scene(&dir, "curve", &curve(), "lateral_tolerance_m = 1e-5");
    // The first 40 m are the straight before the clothoid: only the
    // clothoid's start is in the range.
    let p = plan_of(&dir, &scene, &["--plan"]);
    assert!(
        p["track"]["max_curvature_1_m"].as_f64().unwrap() < 1e-3,
        "{p:#}"
    );
    let p = plan_of(&dir, &scene, &["--plan", "--set", "run.distance_m=280"]);
    assert_eq!(p["flange"], "auto", "{p:#}");
    assert_eq!(p["method"], "online", "the table fails in the curve: {p:#}");
    // Chord error h²κ/8 within half the tolerance (5 µm) on R ≈ 292 m:
    // h ≤ 0.107 m → 0.1 m.
    assert_eq!(p["step_m"], 0.1, "{p:#}");
    let k = p["track"]["max_curvature_1_m"].as_f64().unwrap();
    assert!((3.2e-3..3.6e-3).contains(&k), "{k}");
    // Without a tolerance: 1 µm → 0.04 m.
    let p = plan_of(
        &dir,
        &scene,
        &[
            "--plan",
            "--set",
            "run.distance_m=280",
            "--set",
            "run.lateral_tolerance_m=",
        ],
    );
    let h = p["step_m"].as_f64().unwrap();
    assert!(h * h * k / 8.0 <= 1e-6 && h >= 0.02, "{h}");

    let scene = bogie_scene(&dir, "irregular", &irregular(), "");
    let p = plan_of(&dir, &scene, &["--plan"]);
    assert_eq!(p["flange"], "auto");
    assert_eq!(decision(&p, "irregularities")["value"], "built");
    let h = p["step_m"].as_f64().unwrap();
    let k = p["track"]["max_curvature_1_m"].as_f64().unwrap();
    assert!(h < 1.0 && h * h * k / 8.0 <= 1e-6, "{h} {k}");
    let p = plan_of(
        &dir,
        &scene,
        &["--plan", "--set", "run.lateral_tolerance_m=1e-3"],
    );
    assert_eq!(
        p["method"], "online",
        "6.3 mm measured on the irregular track: {p:#}"
    );
}

#[test]
fn forced_values_are_kept_and_modes_scene_and_everything_do_what_they_say() {
    let dir = scratch("planner_forced");
    // The scene sets the flange search and the step: the planner keeps them
    // in mode "required" and chooses the rest.
    let scene = bogie_scene(
        &dir,
        "forced",
        &straight("step_m = 0.1"),
        "[contact]\nflange = \"on\"\n[plan]\nmode = \"required\"",
    );
    let p = plan_of(&dir, &scene, &[]);
    assert_eq!(p["flange"], "on");
    assert_eq!(decision(&p, "flange_search")["by"], "scene");
    assert_eq!(p["step_m"], 0.1);
    assert_eq!(decision(&p, "table_step")["by"], "scene");
    assert!(
        decision(&p, "table_step")["reason"]
            .as_str()
            .unwrap()
            .contains("would choose 1 m")
    );
    assert_eq!(decision(&p, "track_range")["by"], "planner");
    // `choose` hands a set item to the planner.
    let p = plan_of(&dir, &scene, &["--set", "plan.choose=[\"flange\"]"]);
    assert_eq!(p["flange"], "off", "{p:#}");
    assert_eq!(p["step_m"], 0.1);
    // An explicit range is kept.
    let p = plan_of(&dir, &scene, &["--set", "track.range_m=[0.0, 120.0]"]);
    assert_eq!(p["range_m"], serde_json::json!([0.0, 120.0]));
    // Mode "scene" (the default of every shipped scene): nothing changes.
    let p = plan_of(&dir, &shipped("scenes/bogie_straight.toml"), &[]);
    assert_eq!(p["mode"], "scene");
    assert_eq!(p["flange"], "auto");
    assert_eq!(p["step_m"], 0.1);
    assert!(p["range_m"].is_null());
    assert!(
        p["decisions"]
            .as_array()
            .unwrap()
            .iter()
            .all(|d| d["by"] == "scene")
    );
    // Everything: the reference of the measurements.
    let p = plan_of(
        &dir,
        &shipped("scenes/bogie_straight.toml"),
        &["--model-everything"],
    );
    assert_eq!(p["flange"], "on");
    assert_eq!(p["method"], "online");
    assert_eq!(p["step_m"], 0.01);
    assert!(p["range_m"].is_null());
    // The imported contact of the Cooperrider car stays.
    let p = plan_of(
        &dir,
        &shipped("scenes/cooperrider_straight.toml"),
        &["--model-everything"],
    );
    assert_eq!(p["method"], "imported");
    // Bad [plan] entries name the rule.
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", dir.join("cache"))
        .arg("run")
        .arg(&scene)
        .args(["--plan-only", "--set", "plan.choose=[\"creep_law\"]"]));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("choose"), "{}", stderr(&o));
}

#[test]
fn sim_run_prints_the_block_and_the_planned_run_equals_the_full_model() {
    let dir = scratch("planner_run");
    let scene = bogie_scene(&dir, "run", &straight("step_m = 0.1"), "");
    let cache = dir.join("cache");
    let planned = dir.join("planned.h5");
    // Every item but the integrator, which is the reference's (RK4 at
    // 0.1 ms): the planned flange, table and range change nothing.
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", &cache)
        .arg("run")
        .arg(&scene)
        .args(["--no-plots", "-q", "-o"])
        .arg(&planned)
        .args([
            "--plan",
            "--set",
            "plan.choose=[\"flange\", \"method\", \"step\", \"range\"]",
            "--set",
            "run.integrator=\"rk4\"",
            "--set",
            "run.step_s=1e-4",
        ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    // The block: its header and the indented lines under it, before the
    // summary's title.
    let block: Vec<&str> = text
        .lines()
        .enumerate()
        .take_while(|(i, l)| *i == 0 || l.starts_with("  "))
        .map(|(_, l)| l)
        .collect();
    let block = block.join("\n");
    assert!(text.starts_with("plan (mode required"), "{text}");
    for item in [
        "irregularities",
        "track range",
        "table step",
        "contact method",
        "flange search",
        "integrator",
        "creep law",
    ] {
        assert!(
            block.lines().any(|l| l.starts_with(&format!("  {item} "))),
            "{item} missing: {text}"
        );
    }
    assert!(block.contains("[planner]"), "{text}");
    assert!(
        text.len() > block.len() + 100,
        "the summary follows: {text}"
    );
    let full = dir.join("full.h5");
    let o = run(sim()
        .env("RAILSIM_CACHE_DIR", &cache)
        .arg("run")
        .arg(&scene)
        .args(["--no-plots", "--json", "--model-everything", "-o"])
        .arg(&full));
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: Value = serde_json::from_str(&stdout(&o)).expect("JSON");
    assert_eq!(summary["plan"]["mode"], "everything");
    assert_eq!(summary["plan"]["flange"], "on");
    let (a, b) = (
        read_results(&planned).unwrap(),
        read_results(&full).unwrap(),
    );
    let attr = |r: &runtime::results::RunResults, k: &str| {
        r.attributes
            .iter()
            .find(|(n, _)| n == k)
            .map(|(_, v)| v.to_string())
            .unwrap_or_default()
    };
    assert!(attr(&a, "plan").starts_with("plan (mode required"));
    assert_eq!(attr(&a, "flange_search"), "off");
    assert_eq!(attr(&b, "flange_search"), "on");
    assert_eq!(a.time_s.len(), b.time_s.len());
    // Flange off (never near), 1 m table, the range only: the same run.
    for (wa, wb) in a.wheelsets.iter().zip(&b.wheelsets) {
        let d = wa
            .lateral_m
            .iter()
            .zip(&wb.lateral_m)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(d <= 1e-9, "wheelset {}: {d} m", wa.name);
        assert!(wa.lateral_m.iter().any(|y| y.abs() > 1e-3));
    }
}

#[test]
fn the_range_table_has_the_whole_track_rows() {
    let dir = scratch("planner_range");
    let scene = bogie_scene(&dir, "range", &irregular(), "");
    let ls = LoadedScene::load(&scene, &["track.step_m=0.25".into()]).expect("scene");
    let part = build_track_range(&ls, [52.3, 131.9]).expect("range");
    let whole = preproc::build_tables(
        &preproc::BuildRequest {
            geometry: preproc::GeometryFiles::centerline(shipped(
                "tracks/irregular_300m/centerline.csv",
            )),
            irregularities: Some(shipped("tracks/irregular_300m/irregularities.csv")),
            output: dir.join("unused.h5"),
            config: railsim::session::plan::build_config(&ls).expect("config"),
            contact: None,
            command_line: String::new(),
        },
        &preproc::NoProgress,
    )
    .expect("whole")
    .0;
    let (a, b) = part.centerline.range_m();
    assert!((52.3 - 0.25..=52.3).contains(&a) && (131.9..131.9 + 0.25).contains(&b));
    let rows = whole.centerline.rows();
    let k0 = rows.iter().position(|r| r.s_m == a).expect("same grid");
    assert_eq!(
        &rows[k0..k0 + part.centerline.rows().len()],
        part.centerline.rows()
    );
    for (p, w) in [(&part.left, &whole.left), (&part.right, &whole.right)] {
        let k0 = w
            .rows()
            .iter()
            .position(|r| r.l_m == p.rows()[0].l_m)
            .expect("same grid");
        assert_eq!(&w.rows()[k0..k0 + p.rows().len()], p.rows());
        // The rails cover the centreline's range.
        let (lo, hi) = p.range_m();
        let l = |s: f64| part.centerline.rail_l(p.side(), s).unwrap();
        assert!(lo <= l(a) && hi >= l(b));
    }
    // A range beyond the track clips to it; one narrower than a step fails.
    let clipped = build_track_range(&ls, [250.0, 1000.0]).expect("clipped");
    assert_eq!(clipped.centerline.range_m().1, whole.centerline.range_m().1);
    let e = build_track_range(&ls, [10.0, 10.1]).unwrap_err();
    assert!(format!("{e:#}").contains("range_m"), "{e:#}");
}

#[test]
fn a_tripped_flange_guard_repeats_the_run_with_the_flange_searched() {
    let dir = scratch("planner_guard");
    let scenes = shipped("scenes");
    let text = format!(
        r#"[track]
straight_m = 60.0
rail_profile = "{s}/../profiles/MBench_UIC60_v3.prr"
rail_profile_cant = "1:40"
[vehicle]
file = "{s}/../vehicles/ml95_like_bogie.toml"
[initial]
speed_m_s = 30.0
lateral_m = -0.002
[run]
distance_m = 15.0
step_s = 5e-4
"#,
        s = scenes.display()
    );
    let ls = LoadedScene::from_text(&text, dir.clone(), &[], "guard test".into()).expect("scene");
    // A plan with the flange search off and a guard the 2 mm start trips.
    let plan = Plan {
        mode: PlanMode::Required,
        decisions: vec![railsim::session::plan::Decision {
            item: "flange_search".into(),
            value: "off".into(),
            by: By::Planner,
            reason: "test".into(),
        }],
        flange: FlangeMode::Off,
        method: ContactMethodKind::Online,
        step_m: Some(1.0),
        range_m: None,
        straight_m: Some(60.0),
        integrator: IntegratorPlan::default(),
        flange_guard: Some(FlangeGuard {
            threshold_m: 0.0015,
            reach_per_rad_m: 0.15,
        }),
        revised: None,
        track: TrackFacts {
            kind: "ideal straight".into(),
            length_m: 60.0,
            max_curvature_1_m: 0.0,
            max_cant_rad: 0.0,
            irregularities: false,
            max_irregularity_m: 0.0,
            file_step_m: None,
        },
        flange_facts: None,
        planning_time_s: 0.0,
    };
    let req = RunRequest {
        scene: ls,
        output: dir.join("guard.h5"),
        plots: None,
    };
    let s = run_to_files(&req, plan, &mut |_| {}, None).expect("run");
    let why = s.plan.revised.as_deref().expect("revised");
    assert!(
        why.starts_with("flange search off → auto") && why.contains("wheelset 'front'"),
        "{why}"
    );
    assert_eq!(s.plan.flange, FlangeMode::Auto);
    assert!(s.plan.flange_guard.is_none());
    assert!(s.to_text().contains("plan revised"));
    assert!(s.stopped.is_none() && s.error.is_none(), "{s:?}");
    assert!(
        (s.simulated_time_s - 0.5).abs() < 1e-9,
        "ran to the end: {}",
        s.simulated_time_s
    );
}

#[test]
fn the_planner_chooses_rosenbrock_for_the_bogie_and_the_run_uses_it() {
    let dir = scratch("planner_integrator");
    // No run.integrator in the scene: mode "required" chooses it.
    let scene = bogie_scene(
        &dir,
        "integrator",
        &straight("step_m = 0.1"),
        "[plan]\nmode = \"required\"",
    );
    let text = scene_text_with_distance(&scene, 10.0);
    std::fs::write(&scene, text).expect("write scene");
    let cache = dir.join("cache");
    let sim_json = |out: &Path, args: &[&str]| -> Value {
        let o = run(sim()
            .env("RAILSIM_CACHE_DIR", &cache)
            .arg("run")
            .arg(&scene)
            .args(["--no-plots", "--json", "-o"])
            .arg(out)
            .args(args));
        assert!(o.status.success(), "{}", stderr(&o));
        serde_json::from_str(&stdout(&o)).expect("JSON")
    };
    let planned = dir.join("planned.h5");
    let s = sim_json(&planned, &[]);
    let d = decision(&s["plan"], "integrator");
    assert_eq!(d["by"], "planner", "{d}");
    // Every wheelset of the bogie is suspended: the default atol.
    assert_eq!(d["value"], "rosenbrock atol 5.0e-6", "{d}");
    assert_eq!(s["integrator"], "rosenbrock", "the run used it: {s:#}");
    assert_eq!(s["plan"]["integrator"]["choice"]["atol"], 5e-6);
    let a = read_results(&planned).unwrap();
    let attr = |r: &runtime::results::RunResults, k: &str| {
        r.attributes
            .iter()
            .find(|(n, _)| n == k)
            .map(|(_, v)| v.to_string())
            .unwrap_or_default()
    };
    assert_eq!(attr(&a, "integrator"), "rosenbrock");
    assert!(attr(&a, "plan").contains("rosenbrock atol 5.0e-6 [planner]"));
    // The bogie's W factorised by blocks every time (reference 8.5, "Block
    // elimination"): the fallback count is written, and zero.
    assert_eq!(attr(&a, "dense_lu_fallbacks"), "0");
    assert_eq!(s["fallbacks"]["dense_lu_factorisations"], 0, "{s:#}");
    // The reference: RK4 at 0.1 ms; the planned run within the issue's
    // 10 µm of it (docs/guide/speed-accuracy-tradeoff.md, "The integrator").
    let full = dir.join("full.h5");
    let s = sim_json(&full, &["--set", "plan.mode=\"everything\""]);
    assert_eq!(s["integrator"], "rk4");
    assert_eq!(decision(&s["plan"], "integrator")["value"], "rk4 0.100 ms");
    let b = read_results(&full).unwrap();
    assert_eq!(a.time_s.len(), b.time_s.len());
    for (wa, wb) in a.wheelsets.iter().zip(&b.wheelsets) {
        let d = wa
            .lateral_m
            .iter()
            .zip(&wb.lateral_m)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(d <= 1e-5, "wheelset {}: {d} m", wa.name);
        assert!(wa.lateral_m.iter().any(|y| y.abs() > 1e-3));
    }
}

/// The scene file's text with `run.distance_m` replaced.
fn scene_text_with_distance(scene: &Path, distance_m: f64) -> String {
    std::fs::read_to_string(scene).expect("scene").replace(
        "distance_m = 40.0",
        &format!("distance_m = {distance_m:.1}"),
    )
}
