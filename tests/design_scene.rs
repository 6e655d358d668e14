//! Tracks from design elements end to end (issue 14 §1): `track-preproc
//! build --design`, and scenes with `[track] design = "…"` built and cached
//! on the fly, the cache key following the design file's content.

mod common;

use std::path::Path;

use common::*;
use railsim::config::scene::LoadedScene;
use railsim::session::track::load_track;

#[test]
fn track_preproc_builds_a_design_file_and_refuses_mixed_inputs() {
    let dir = scratch("design_cli");
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
    assert!(
        stdout(&o).contains("min curve radius  600.0 m"),
        "{}",
        stdout(&o)
    );
    let tables = runtime::io::schema::read_track(&out).unwrap();
    assert!((tables.centerline.length_m() - 1120.0).abs() < 1e-9);
    assert_eq!(tables.meta.cant_scheme, "design");
    for mixed in ["--centerline", "--cant"] {
        let o = run(track_preproc().args([
            "build",
            "--design",
            design.to_str().unwrap(),
            mixed,
            shipped("tracks/straight_300m/centerline.csv")
                .to_str()
                .unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]));
        assert!(!o.status.success());
        assert!(stderr(&o).contains("cannot be used with"), "{}", stderr(&o));
    }
}

fn scene_text(design: &Path, extra: &str) -> String {
    format!(
        "title = \"design scene\"\n[track]\ndesign = \"{}\"\n{extra}rail_inclination = \"1:40\"\nrail_profile = \"{}\"\nrail_profile_cant = \"1:40\"\n[vehicle]\nfile = \"{}\"\n[initial]\nspeed_m_s = 20.0\n[run]\ndistance_m = 10.0\n",
        design.display(),
        shipped("profiles/MBench_UIC60_v3.prr").display(),
        shipped("vehicles/ml95_like_bogie.toml").display()
    )
}

/// A scene's design file is built on the fly and cached; editing the
/// design file gives another cache entry (its content is in the key).
#[test]
fn scenes_build_and_cache_design_tracks_by_content() {
    let dir = scratch("design_scene_cache");
    let design = dir.join("track.toml");
    let text = std::fs::read_to_string(shipped("tracks/r250_reverse.toml")).unwrap();
    std::fs::write(&design, &text).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, scene_text(&design, "")).unwrap();
    let ls = LoadedScene::load(&scene, &[]).expect("scene");
    let (tables, first) = load_track(&ls).expect("track");
    assert!((tables.centerline.length_m() - 740.0).abs() < 1e-9);
    assert_eq!(tables.meta.cant_scheme, "design");
    let (_, again) = load_track(&ls).expect("cached");
    assert_eq!(first.path, again.path);
    assert!(!again.built, "read from the cache");
    // One straight 10 m longer: another key, another track.
    std::fs::write(
        &design,
        text.replacen("length_m = 100.0", "length_m = 110.0", 1),
    )
    .unwrap();
    let (tables, edited) = load_track(&ls).expect("track");
    assert_ne!(first.path, edited.path);
    assert!((tables.centerline.length_m() - 750.0).abs() < 1e-9);
}

/// `design` excludes the other track sources and a cant CSV; the schemes
/// are checked when the scene loads.
#[test]
fn design_is_exclusive_in_scenes() {
    let dir = scratch("design_scene_rules");
    let design = shipped("tracks/r600_design.toml");
    for (extra, expect) in [
        ("straight_m = 100.0\n", "give one of tables"),
        (
            &*format!(
                "centerline = \"{}\"\n",
                shipped("tracks/straight_300m/centerline.csv").display()
            ),
            "give one of tables",
        ),
        ("cant = \"cant.csv\"\n", "remove cant"),
        ("cant_scheme = \"quintic\"\n", "cant_scheme"),
    ] {
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, scene_text(&design, extra)).unwrap();
        let e = format!("{:#}", LoadedScene::load(&scene, &[]).unwrap_err());
        assert!(e.contains(expect), "{extra}: {e}");
    }
}
