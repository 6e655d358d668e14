//! End to end: `track-preproc build` on the shipped example tracks, the
//! table file's layout (h5dump, the run-time reader, provenance), and
//! `sim probe` reading it back.

mod common;

use common::*;
use runtime::geometry::track::Side;
use runtime::io::schema;

fn build(dir: &std::path::Path, name: &str, extra: &[&str]) -> std::path::PathBuf {
    let out = dir.join(format!("{name}.h5"));
    let o = run(track_preproc()
        .arg("build")
        .args(extra)
        .arg("-o")
        .arg(&out)
        .arg("--json"));
    assert!(o.status.success(), "build failed: {}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_str(&stdout(&o)).expect("JSON summary");
    assert_eq!(summary["output"], out.display().to_string());
    out
}

#[test]
fn builds_the_paper_track_and_probes_it() {
    let dir = scratch("paper_track");
    let centerline = shipped("tracks/straight_300m/centerline.csv");
    let out = build(
        &dir,
        "straight",
        &[
            "--centerline",
            centerline.to_str().unwrap(),
            "--rail-inclination",
            "0",
        ],
    );
    // Only the finished file is left in the directory.
    assert_eq!(files_in(&dir), vec!["straight.h5".to_string()]);

    let tables = schema::read_track(&out).expect("the run-time reader loads it");
    assert_eq!(tables.centerline.rows().len(), 3001);
    assert!((tables.centerline.length_m() - 300.0).abs() < 1e-9);
    assert_eq!(tables.meta.scheme, "cubic");
    assert_eq!(tables.meta.step_m, 0.1);

    let prov = schema::read_provenance(&out).unwrap();
    assert!(prov.command_line.contains("track-preproc"));
    let input = &prov.inputs[0];
    assert_eq!(input.role, "centerline");
    assert_eq!(input.text, std::fs::read_to_string(&centerline).unwrap());

    let o = run(sim()
        .arg("probe")
        .arg(&out)
        .args(["--s", "123.45", "--json"]));
    assert!(o.status.success(), "{}", stderr(&o));
    let p: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    let rails = p["rails"].as_array().unwrap();
    assert_eq!(rails.len(), 2);
    for (r, side) in rails.iter().zip(Side::BOTH) {
        assert_eq!(r["side"], side.name());
        let pos: Vec<f64> = serde_json::from_value(r["position_m"].clone()).unwrap();
        assert!((pos[0] - 123.45).abs() < 1e-9);
        assert!((pos[1] - 0.7535 * side.sign()).abs() < 1e-12);
        let n: Vec<f64> = serde_json::from_value(r["n"].clone()).unwrap();
        assert!((n[1] - 1.0).abs() < 1e-12, "no inclination: n = {n:?}");
    }

    // Text form names both rails.
    let o = run(sim().arg("probe").arg(&out).args(["--s", "10"]));
    assert!(o.status.success());
    let text = stdout(&o);
    assert!(
        text.contains("left") && text.contains("right rail"),
        "{text}"
    );
}

#[test]
fn builds_the_curve_with_cant_and_the_irregular_track() {
    let dir = scratch("examples");
    let out = build(
        &dir,
        "curve",
        &[
            "--centerline",
            shipped("tracks/curve_r300/centerline.csv")
                .to_str()
                .unwrap(),
            "--scheme",
            "pchip",
        ],
    );
    let t = schema::read_track(&out).unwrap();
    let max_cant = t
        .centerline
        .rows()
        .iter()
        .fold(0.0_f64, |m, r| m.max(r.cant_rad.abs()));
    // 100 mm over the 1.5 m cant base.
    assert!(
        (max_cant - (0.1_f64 / 1.5).asin()).abs() < 1e-6,
        "{max_cant}"
    );
    // Left-hand curve: the left rail is the inner, shorter one.
    assert!(t.left.range_m().1 < t.right.range_m().1);

    let out = build(
        &dir,
        "irregular",
        &[
            "--centerline",
            shipped("tracks/irregular_300m/centerline.csv")
                .to_str()
                .unwrap(),
            "--irregularities",
            shipped("tracks/irregular_300m/irregularities.csv")
                .to_str()
                .unwrap(),
        ],
    );
    let t = schema::read_track(&out).unwrap();
    let max_irr = t
        .centerline
        .rows()
        .iter()
        .fold(0.0_f64, |m, r| m.max(r.align_left_m.abs()));
    assert!(max_irr > 1e-3 && max_irr < 1e-2, "{max_irr}");
    assert_eq!(schema::read_provenance(&out).unwrap().inputs.len(), 2);
}

/// `h5dump -H` lists the datasets (skipped, with a message, only when h5dump
/// is not installed).
#[test]
fn h5dump_lists_the_datasets() {
    if std::process::Command::new("h5dump")
        .arg("--version")
        .output()
        .is_err()
    {
        eprintln!("SKIPPED: h5dump not installed (apt-get install hdf5-tools)");
        return;
    }
    let dir = scratch("h5dump");
    let out = build(
        &dir,
        "t",
        &[
            "--centerline",
            shipped("tracks/straight_300m/centerline.csv")
                .to_str()
                .unwrap(),
        ],
    );
    let o = run(std::process::Command::new("h5dump").arg("-H").arg(&out));
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "GROUP \"centerline\"",
        "GROUP \"left_rail\"",
        "GROUP \"right_rail\"",
        "DATASET \"database\"",
        "GROUP \"input\"",
        "ATTRIBUTE \"columns\"",
        "ATTRIBUTE \"schema_version\"",
        "( 3001, 13 )",
        "( 3001, 23 )",
    ] {
        assert!(text.contains(needle), "h5dump -H lacks {needle}:\n{text}");
    }
}
