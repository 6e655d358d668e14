//! `--set` as users type it (docs/reference/10-scene-files.md,
//! "Overrides"): a relative path resolves against the current directory,
//! a number given to a string entry is that string, and an entry can be
//! removed to give way to another (a centreline replaced by a table file)
//! without copying the scene.

use crate::common::{run, scratch, shipped, sim, stderr, track_preproc};

#[test]
fn set_paths_resolve_against_the_current_directory_and_entries_can_be_replaced() {
    let dir = scratch("overrides_set");
    std::fs::copy(
        shipped("tracks/straight_300m/centerline.csv"),
        dir.join("mine.csv"),
    )
    .unwrap();
    let scene = shipped("scenes/wheelset_straight.toml");
    let short = ["--set", "run.distance_m=0.5"];

    // A centreline beside the user, named relative to where they are.
    let o = run(sim()
        .current_dir(&dir)
        .arg("run")
        .arg(&scene)
        .args(["--set", "track.centerline=mine.csv"])
        .args(short)
        .args(["-o", "a.h5"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("a.h5").exists());

    // A misspelt relative path names the file where the user is.
    let o = run(sim()
        .current_dir(&dir)
        .arg("run")
        .arg(&scene)
        .args(["--set", "track.centerline=nope.csv"])
        .args(short)
        .args(["-o", "b.h5"]));
    assert!(!o.status.success());
    let want = dir.join("nope.csv").display().to_string();
    assert!(stderr(&o).contains(&want), "{}", stderr(&o));

    // `0` for the rail inclination (a string entry) is the string "0".
    let o = run(sim()
        .current_dir(&dir)
        .arg("run")
        .arg(&scene)
        .args(["--set", "track.rail_inclination=0"])
        .args(short)
        .args(["-o", "c.h5"]));
    assert!(o.status.success(), "{}", stderr(&o));

    // Replace the centreline by a table file built here.
    let o = run(track_preproc().current_dir(&dir).args([
        "build",
        "--centerline",
        "mine.csv",
        "-o",
        "t.h5",
    ]));
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run(sim()
        .current_dir(&dir)
        .arg("run")
        .arg(&scene)
        .args(["--set", "track.centerline=", "--set", "track.tables=t.h5"])
        .args(short)
        .args(["-o", "d.h5"]));
    assert!(o.status.success(), "{}", stderr(&o));

    // Removing an entry that is not set names it.
    let o = run(sim()
        .current_dir(&dir)
        .arg("run")
        .arg(&scene)
        .args(["--set", "track.cant="])
        .args(short)
        .args(["-o", "e.h5"]));
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("'track.cant' is not set"),
        "{}",
        stderr(&o)
    );
}
