//! The plan elements of a design file recorded with its track tables
//! (`/design`, docs/reference/04-table-files.md §4.1) and used by `sim
//! run`'s curving outputs (docs/guide/curving-and-safety.md, "Finding the
//! arcs"): `track-preproc build --design` records them exactly, a stretch
//! built in memory clips them, and a short run on the R 600 m design scene
//! reports the design's arc 280–580 m (found from the curvature it would
//! be 276.1–584.1 m).

mod common;

use common::*;
use railsim::config::scene::LoadedScene;
use railsim::session::track::load_track;
use runtime::geometry::track::PlanElementKind;

#[test]
fn a_design_build_records_its_elements_and_a_stretch_clips_them() {
    let dir = scratch("design_elements_build");
    let out = dir.join("r600.h5");
    let design = shipped("tracks/r600_design.toml");
    let o = run(track_preproc().args([
        "build",
        "--design",
        design.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let tables = runtime::io::schema::read_track(&out).unwrap();
    // What the curvature rule finds instead: 276.1–584.1 m, R −600.4 m
    // (measured), which the design's elements replace.
    let rows = tables.centerline.rows();
    let s: Vec<f64> = rows.iter().map(|r| r.s_m).collect();
    let k: Vec<f64> = rows.iter().map(|r| r.horizontal_curvature_1_m).collect();
    let found = railsim::run::curving::elements::find_elements(&s, &k);
    let arc = found
        .iter()
        .find(|e| e.kind == railsim::run::curving::ElementKind::Arc)
        .unwrap();
    assert!(arc.start_s_m < 279.0 && arc.end_s_m > 581.0, "{arc:?}");
    let e = tables.design_elements;
    let joints: Vec<f64> = e.iter().map(|e| e.s_start_m).collect();
    assert_eq!(
        joints,
        [0.0, 200.0, 280.0, 580.0, 660.0, 740.0, 940.0, 1020.0]
    );
    assert_eq!(e[7].s_end_m, 1120.0);
    use PlanElementKind::*;
    let kinds: Vec<_> = e.iter().map(|e| e.kind).collect();
    assert_eq!(
        kinds,
        [
            Straight, Transition, Arc, Transition, Transition, Arc, Transition, Straight
        ]
    );
    assert_eq!(e[1].shape, "clothoid");
    assert_eq!(
        (e[1].radius_start_m, e[1].radius_end_m),
        (f64::INFINITY, -600.0)
    );
    assert_eq!((e[2].radius_start_m, e[5].radius_end_m), (-600.0, 600.0));
    // 120 mm over the cant base e0 = gauge + 65 mm (φ = asin(h/e0)).
    let cant = (0.120_f64 / (1.435 + 0.065)).asin();
    assert!((e[2].cant_start_rad - cant).abs() < 1e-12, "{:?}", e[2]);
    assert_eq!(e[1].cant_start_rad, 0.0);

    // The scene's stretch [250, 300] m in memory: the transition from
    // 250 m (5/8 of the clothoid: R −960 m) and the arc to 300 m.
    let scene = dir.join("scene.toml");
    let text = std::fs::read_to_string(shipped("scenes/bogie_r600.toml"))
        .unwrap()
        .replace(
            "design = \"../tracks/r600_design.toml\"",
            &format!(
                "design = \"{}\"\nrange_m = [250.0, 300.0]",
                design.display()
            ),
        )
        .replace("../", &format!("{}/", shipped("").display()));
    std::fs::write(&scene, text).unwrap();
    let ls = LoadedScene::load(&scene, &[]).expect("scene");
    let (tables, _) = load_track(&ls).expect("track stretch");
    let e = &tables.design_elements;
    assert_eq!(e.len(), 2, "{e:#?}");
    let (a, b) = tables.centerline.range_m();
    assert_eq!((e[0].s_start_m, e[1].s_end_m), (a, b));
    assert_eq!((e[0].s_end_m, e[1].s_start_m), (280.0, 280.0));
    let r = e[0].radius_start_m;
    assert!(
        (r - (-600.0 * 80.0 / (a - 200.0))).abs() < 1e-6,
        "{r} at {a} m"
    );
}

/// `sim run` on the design scene, from 262 m over 30 m (the clothoid into
/// the arc): the elements and the arc are the design's, named as such.
#[test]
fn a_design_scene_reports_the_design_arc() {
    let dir = scratch("design_elements_run");
    let scene = shipped("scenes/bogie_r600.toml");
    let args = |json: bool| {
        let mut c = sim();
        c.env("RAILSIM_CACHE_DIR", dir.join("cache"))
            .args(["run", "-q", "--no-plots", scene.to_str().unwrap(), "-o"])
            .arg(dir.join(if json { "j.h5" } else { "t.h5" }))
            .args(["--set", "initial.s_m=262", "--set", "run.distance_m=30"]);
        if json {
            c.arg("--json");
        }
        c
    };
    let o = run(&mut args(true));
    assert!(o.status.success(), "{}", stderr(&o));
    let j: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON summary");
    let c = &j["curving"];
    assert_eq!(c["track_elements_source"], "design_file");
    let arc = &c["arcs"][0];
    assert_eq!(arc["start_s_m"], 280.0);
    assert_eq!(arc["end_s_m"], 580.0);
    assert_eq!(arc["radius_m"], -600.0);
    let t = &c["track_elements"][1];
    assert_eq!(
        (&t["kind"], &t["start_s_m"], &t["end_s_m"]),
        (&"transition".into(), &200.0.into(), &280.0.into())
    );
    let covered = arc["wheelsets"][0]["covered_m"].as_f64().unwrap();
    assert!(covered > 5.0, "{arc}");

    let o = run(&mut args(false));
    let text = stdout(&o);
    for needle in [
        "track elements (design file): straight 0.0–200.0 m; transition 200.0–280.0 m; arc 280.0–580.0 m (R -600 m);",
        "arc 280.0–580.0 m (R -600 m, cant 120 mm, cant deficiency ",
    ] {
        assert!(text.contains(needle), "{needle} missing:\n{text}");
    }
}
